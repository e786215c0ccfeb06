//! Particle conservation checked against what the solver holds, not only against the main
//! world's counters: every shipped scene runs 2 s with avian on both backends, and every simulated
//! second the particles are read back (from the device on the GPU) and must be exactly the
//! spawned ones less the drained: as many as initial + emitted − drained, each id once, each
//! below the number of particles ever spawned. The scenes together must both emit and drain, so
//! the check sees particles added and removed.
//!
//! `particle_balance()` alone compares counters that are updated by matching additions and
//! subtractions, and a GPU snapshot always has `particle_count` entries: neither sees a
//! particle lost or duplicated on the device. Duplicated or lost slots show here as repeated or
//! out-of-range ids, and a solver that lost particles as a short snapshot.

mod common;

use avian3d::prelude::PhysicsPlugins;
use bevy::prelude::*;
use bevy_sph_fluid::prelude::*;
use std::time::{Duration, Instant};

/// Simulated time each scene runs [s]: long enough for aquaplay's tap to emit and its drain to
/// take water. `sph-bench soak --scene F --bodies avian [--backend gpu] --time S` runs the same
/// check for as long as asked.
const SECONDS: f64 = 2.0;
/// Steps per frame.
const SUBSTEPS: u32 = 4;
/// Wall-clock bound of one scene on one backend: a run that stalls fails instead of hanging.
const WALL_BOUND: Duration = Duration::from_secs(600);

const SCENES: [&str; 7] = [
    "aquaplay.ron",
    "basin_jet.ron",
    "dam_break.ron",
    "gate.ron",
    "lock.ron",
    "pipe_fill.ron",
    "ramp.ron",
];

/// The snapshot's particles against the counters: the count, each id once, every id spawned.
fn check_against_the_solver(app: &mut App, case: &str) {
    let stats = app.world().resource::<SphStats>().clone();
    let snapshot = common::snapshot(app);
    let expected = stats.particles_initial + stats.particles_emitted - stats.particles_drained;
    assert_eq!(
        snapshot.ids.len() as u64,
        expected,
        "{case}: the solver holds {} particles; initial {} + emitted {} - drained {}",
        snapshot.ids.len(),
        stats.particles_initial,
        stats.particles_emitted,
        stats.particles_drained
    );
    let spawned = stats.particles_initial + stats.particles_emitted;
    let mut ids = snapshot.ids.clone();
    ids.sort_unstable();
    if let Some(&top) = ids.last() {
        assert!(
            (top as u64) < spawned,
            "{case}: id {top} was never spawned ({spawned} spawned)"
        );
    }
    let before = ids.len();
    ids.dedup();
    assert_eq!(
        ids.len(),
        before,
        "{case}: {} ids repeated",
        before - ids.len()
    );
}

/// Runs one scene, checking the balance every frame and the solver's particles every second;
/// returns the particles emitted and drained.
fn run_scene(scene: &str, backend: SphBackend) -> (u64, u64) {
    let case = format!("{scene} on {backend:?}");
    let mut app = common::shipped_scene_app(&format!("scenes/{scene}"), backend, |app| {
        app.add_plugins(PhysicsPlugins::new(SphWaterTime));
    });
    app.insert_resource(SphControl {
        running: true,
        substeps: SUBSTEPS,
        ..default()
    });
    let start = Instant::now();
    let mut next_check = 1.0;
    loop {
        app.update();
        let stats = app.world().resource::<SphStats>();
        assert!(!stats.health.is_unstable(), "{case}: {:?}", stats.health);
        assert_eq!(stats.particle_balance(), 0, "{case}: {stats:?}");
        assert!(
            start.elapsed() < WALL_BOUND,
            "{case}: {:.2} s simulated in {WALL_BOUND:?}",
            stats.sim_time
        );
        let t = stats.sim_time;
        if t >= next_check {
            // Paused while the snapshot is taken, and until the GPU drains' count has caught up
            // with the last sort's tail: the snapshot is of the state the counters describe.
            app.world_mut().resource_mut::<SphControl>().running = false;
            for _ in 0..6 {
                app.update();
            }
            check_against_the_solver(&mut app, &format!("{case} at {t:.2} s"));
            app.world_mut().resource_mut::<SphControl>().running = true;
            next_check += 1.0;
        }
        if t >= SECONDS {
            break;
        }
    }
    let stats = app.world().resource::<SphStats>();
    println!(
        "{case}: {SECONDS} s in {:.0} s of wall time; {} particles (initial {}, emitted {}, \
         drained {})",
        start.elapsed().as_secs_f64(),
        stats.particle_count,
        stats.particles_initial,
        stats.particles_emitted,
        stats.particles_drained
    );
    (stats.particles_emitted, stats.particles_drained)
}

/// Every shipped scene on one backend; the scenes together must have emitted and drained.
fn run_every_scene(backend: SphBackend) {
    let (mut emitted, mut drained) = (0, 0);
    for scene in SCENES {
        let (e, d) = run_scene(scene, backend);
        emitted += e;
        drained += d;
    }
    assert!(
        emitted > 0 && drained > 0,
        "{backend:?}: the scenes emitted {emitted} and drained {drained} particles; the check \
         needs both"
    );
}

#[test]
fn every_shipped_scene_keeps_its_particles_on_the_cpu() {
    run_every_scene(SphBackend::Cpu);
}

#[test]
fn every_shipped_scene_keeps_its_particles_on_the_gpu() {
    let _gpu = common::GPU.lock().unwrap_or_else(|e| e.into_inner());
    run_every_scene(SphBackend::Gpu);
}
