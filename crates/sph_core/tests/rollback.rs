//! Rollback of unstable steps on the CPU solver: a dam break at three times the largest stable
//! time step (kick-drift-kick, docs/trade.md) recovers by rolling back and halving dt.

use sph_core::scenario::dam_break_with_particles;
use sph_core::{CpuSolver, Rollback};
use glam::Vec3;

/// The kick-drift-kick integrator's largest stable dt at 2,000 particles (docs/trade.md).
const LARGEST_STABLE_DT: f32 = 9.405e-4;

fn dam_break_at_three_times_the_stable_dt(rollback: Rollback) -> CpuSolver {
    let mut scene = dam_break_with_particles(2000);
    scene.params.time_step = 3.0 * LARGEST_STABLE_DT;
    let mut solver = CpuSolver::new(scene.params, scene.container, 4096).unwrap();
    solver.set_rollback(rollback).unwrap();
    solver.spawn(&scene.positions(), Vec3::ZERO);
    solver
}

#[test]
fn an_unstable_dam_break_rolls_back_and_goes_on() {
    let mut solver = dam_break_at_three_times_the_stable_dt(Rollback::default());
    let count = solver.len();
    for _ in 0..300 {
        solver.step();
    }
    let d = solver.diagnostics();
    assert!(solver.rollbacks() >= 1, "no rollback happened");
    assert_eq!(solver.unstable_step(), None, "health must stay ok");
    assert_eq!(d.non_finite_count, 0);
    assert_eq!(d.outside_count, 0);
    assert_eq!(solver.len(), count);
    assert!(solver.last_time_step() < 3.0 * LARGEST_STABLE_DT);
    let mut ids = solver.particles().id.clone();
    ids.sort_unstable();
    assert!(ids.iter().enumerate().all(|(k, &id)| id == k as u32), "ids lost or duplicated");
}

#[test]
fn without_rollback_the_same_run_freezes() {
    let mut solver = dam_break_at_three_times_the_stable_dt(Rollback::off());
    for _ in 0..300 {
        solver.step();
    }
    assert!(solver.unstable_step().is_some());
    assert_eq!(solver.rollbacks(), 0);
    assert_eq!(solver.diagnostics().non_finite_count, 0, "the last good state is kept");
}

#[test]
fn bad_rollback_settings_are_refused_and_the_previous_ones_stay() {
    let mut solver = dam_break_at_three_times_the_stable_dt(Rollback::off());
    let bad = Rollback {
        max_retries: 0,
        ..Rollback::default()
    };
    let e = solver.set_rollback(bad).unwrap_err();
    assert_eq!(e.field, "rollback.max_retries");
    assert_eq!(solver.rollback(), Rollback::off());
}
