//! Rollback of unstable steps through the plugin, on both backends: a dam break at three times
//! the kick-drift-kick integrator's largest stable time step (docs/trade.md, 2,000 particles)
//! for 300 steps rolls back at least once and ends healthy, with no NaN, nothing outside the
//! box and every particle kept (ids neither lost nor duplicated). With rollback off, the same
//! run is reported unstable. DFSPH at a fixed step far beyond its CFL rule recovers the same
//! way on both backends.

mod common;

use bevy::prelude::*;
use bevy_sph_fluid::prelude::*;
use common::*;
use sph_core::scenario::{dam_break_with_particles, Scene};
use sph_core::Rollback;

/// The kick-drift-kick integrator's largest stable dt at 2,000 particles (docs/trade.md).
const LARGEST_STABLE_DT: f32 = 9.405e-4;

fn scene() -> Scene {
    let mut scene = dam_break_with_particles(2000);
    scene.params.time_step = 3.0 * LARGEST_STABLE_DT;
    scene
}

/// The same dam break with DFSPH at a fixed step of 20 ms, far beyond what its CFL rule allows
/// once the column falls (its own rule takes 2–3 ms).
fn dfsph_scene() -> Scene {
    let mut scene = dam_break_with_particles(2000);
    scene.params.use_solver(sph_core::Solver::Dfsph);
    scene.params.adaptive_time_step = false;
    scene.params.time_step = 0.02;
    scene
}

/// Runs 300 steps of the scene on `backend` with `rollback`; returns the stats and the state.
fn run(backend: SphBackend, rollback: Rollback) -> (SphStats, SphSnapshot, Scene) {
    run_scene(scene(), backend, rollback)
}

fn run_scene(
    scene: Scene,
    backend: SphBackend,
    rollback: Rollback,
) -> (SphStats, SphSnapshot, Scene) {
    let mut app = headless_app(scene.particle_count() as u32, backend);
    bevy_sph_fluid::headless::spawn_scene(&mut app, &scene);
    app.world_mut().resource_mut::<SphControl>().rollback = rollback;
    app.world_mut().resource_mut::<SphControl>().substeps = 10;
    app.world_mut().resource_mut::<SphControl>().running = true;
    // 300 step attempts: the CPU backend steps every frame (its step count goes back on a
    // rollback and stops when frozen); the GPU's count is the steps encoded.
    let mut frames = 0;
    while frames < 2000 && (steps_taken(&app) < 300 && (backend == SphBackend::Gpu || frames < 30))
    {
        app.update();
        frames += 1;
    }
    app.world_mut().resource_mut::<SphControl>().running = false;
    let snapshot = snapshot(&mut app);
    let stats = app.world().resource::<SphStats>().clone();
    (stats, snapshot, scene)
}

fn assert_recovered(backend: SphBackend) {
    assert_recovered_in(scene(), backend);
}

fn assert_recovered_in(scene: Scene, backend: SphBackend) {
    let solver = scene.params.solver;
    let (stats, s, scene) = run_scene(scene, backend, Rollback::default());
    let what = format!("{backend:?}, {solver:?}");
    eprintln!(
        "{what}: {} rollbacks, {:.3} s simulated, health {:?}",
        stats.rollbacks, stats.sim_time, stats.health
    );
    assert!(stats.rollbacks >= 1, "{what}: no rollback ({stats:?})");
    assert_eq!(stats.health, SphHealth::Ok, "{what}");
    let d = s.diagnostics(&scene.params, &scene.container);
    assert_eq!(d.non_finite_count, 0, "{what}: NaN");
    assert_eq!(d.outside_count, 0, "{what}: escaped");
    assert_eq!(d.particle_count, scene.particle_count(), "{what}: count");
    let mut ids = s.ids.clone();
    ids.sort_unstable();
    assert!(
        ids.iter().enumerate().all(|(k, &id)| id == k as u32),
        "{what}: ids lost or duplicated"
    );
    let full_steps = 300.0 * scene.params.time_step as f64;
    assert!(
        stats.sim_time > 0.0 && stats.sim_time < full_steps,
        "{what}: rolled-back and halved steps simulate less than 300 full steps: {} s",
        stats.sim_time
    );
}

#[test]
fn cpu_backend_rolls_back_and_goes_on() {
    assert_recovered(SphBackend::Cpu);
}

#[test]
fn gpu_backend_rolls_back_and_goes_on() {
    let _gpu = GPU.lock().unwrap_or_else(|e| e.into_inner());
    assert_recovered(SphBackend::Gpu);
}

/// DFSPH's step on the GPU restores the checkpoint in its prediction pass and leaves the rest
/// of the step alone (the move's sort rebuilds the neighbourhood of the restored state).
#[test]
fn dfsph_rolls_back_and_goes_on_on_both_backends() {
    let _gpu = GPU.lock().unwrap_or_else(|e| e.into_inner());
    for backend in [SphBackend::Cpu, SphBackend::Gpu] {
        assert_recovered_in(dfsph_scene(), backend);
    }
}

#[test]
fn without_rollback_both_backends_report_the_instability() {
    let _gpu = GPU.lock().unwrap_or_else(|e| e.into_inner());
    for backend in [SphBackend::Cpu, SphBackend::Gpu] {
        let (stats, _, _) = run(backend, Rollback::off());
        assert!(
            stats.health.is_unstable(),
            "{backend:?}: {:?}",
            stats.health
        );
        assert_eq!(stats.rollbacks, 0, "{backend:?}");
    }
}

#[test]
fn bad_rollback_settings_are_refused_and_named() {
    let scene = scene();
    let mut app = headless_app(scene.particle_count() as u32, SphBackend::Cpu);
    bevy_sph_fluid::headless::spawn_scene(&mut app, &scene);
    app.world_mut()
        .resource_mut::<SphControl>()
        .rollback
        .max_retries = 0;
    app.world_mut().resource_mut::<SphControl>().single_step = true;
    app.update();
    let stats = app.world().resource::<SphStats>().clone();
    let error = stats.error.unwrap_or_default();
    assert!(
        error.contains("rollback.max_retries") && error.contains("1 ..= 16"),
        "{error}"
    );
    assert_eq!(stats.step_count, 0, "no step with invalid settings");
}
