//! Whole-scene physics: a hydrostatic column at rest and a dam break.

use sph_core::glam::Vec3;
use sph_core::scenario::{dam_break_with_particles, hydrostatic};
use sph_core::CpuSolver;

#[test]
fn hydrostatic_column_settles_with_small_density_error() {
    let scene = hydrostatic(0.1, 0.2, 0.01);
    let n = scene.particle_count();
    let mut solver = CpuSolver::new(scene.params, scene.container, n).unwrap();
    solver.spawn(&scene.positions(), Vec3::ZERO);
    let steps = (1.0 / scene.params.time_step).ceil() as usize;
    for _ in 0..steps {
        solver.step();
    }
    let d = solver.diagnostics();
    assert_eq!(d.particle_count, n);
    assert_eq!(d.non_finite_count, 0);
    assert_eq!(d.outside_count, 0);
    assert!(
        d.density_error_mean_pct <= 1.0,
        "mean density error {} %",
        d.density_error_mean_pct
    );
    // Settled: far below the column's free-fall speed √(2 g H) = 2 m/s.
    assert!(d.max_speed < 0.2, "still moving at {} m/s", d.max_speed);
}

#[test]
fn dam_break_keeps_its_particles_finite_and_inside_for_one_second() {
    let scene = dam_break_with_particles(8_000);
    let n = scene.particle_count();
    assert!(n >= 8_000, "{n} particles");
    let mut solver = CpuSolver::new(scene.params, scene.container, n).unwrap();
    solver.spawn(&scene.positions(), Vec3::ZERO);
    let initial = solver.diagnostics();
    while solver.time() < 1.0 {
        solver.step();
        if solver.step_count().is_multiple_of(500) {
            let d = solver.diagnostics();
            assert_eq!(d.non_finite_count, 0, "NaN at t = {}", solver.time());
        }
    }
    let d = solver.diagnostics();
    assert_eq!(d.particle_count, n);
    assert_eq!(d.non_finite_count, 0);
    assert_eq!(d.outside_count, 0);
    // The column collapsed: its potential energy dropped.
    assert!(d.potential_energy < 0.8 * initial.potential_energy);
    let max_x = solver
        .particles()
        .position
        .iter()
        .map(|p| p.x)
        .fold(0.0, f32::max);
    assert!(max_x > 2.0 * 0.146, "front only reached {max_x} m");
}
