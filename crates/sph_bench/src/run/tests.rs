//! Runs of whole scenarios and scene files through `run` and `run_setup`: rollback, the tank's
//! window, oversized steps on both backends, `--solver` over a scene file's, drains and probes,
//! and held or avian-moved bodies.

use super::setup::configured_setup;
use super::{run, run_setup};
use crate::args::{Backend, Duration, RunArgs};
use crate::progress::Bars;
use crate::report::Report;
use crate::scenarios::{Bodies, Scenario};
use sph_core::glam::Vec3;
use sph_core::{Integrator, Solver};

/// A scene file shipped in assets/scenes.
fn shipped_scene(file: &str) -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../assets/scenes")
        .join(file)
}

/// A small dam break at several times its derived dt (0.003 s), for 0.2 s.
fn too_large_a_step(rollback: bool) -> Report {
    let args = RunArgs {
        particles: 500,
        dt: Some(0.003),
        rollback,
        ..Default::default()
    };
    let derived = configured_setup(&RunArgs {
        dt: None,
        ..args.clone()
    })
    .scene
    .params
    .time_step;
    assert!(0.003 > 4.0 * derived, "derived dt {derived}");
    let setup = configured_setup(&args);
    run_setup(
        &setup,
        Backend::Cpu,
        1,
        Duration::Time(0.2),
        &Bars::new(true),
    )
    .unwrap()
}

#[test]
fn the_tanks_window_is_the_last_forty_percent_of_the_run_the_command_line_asks_for() {
    // The tank's own length is several seconds; `--time` shortens the run, and the window
    // must shrink with it (it stayed at the scenario's length, and came out empty).
    let args = RunArgs {
        scenario: Scenario::Hydrostatic,
        particles: 1000,
        time: Some(0.05),
        ..Default::default()
    };
    assert!(configured_setup(&args).duration > 1.0);
    let report = run(&args, &Bars::new(true)).unwrap();
    let tank = report.hydrostatic.expect("the tank's figures");
    assert!(!tank.layers.is_empty(), "{tank:?}");
    assert!(tank.speed_mean_window_mean > 0.0, "{tank:?}");
}

/// A dam break at 3 and 10 times its derived dt, on both backends: each run ends (its 30
/// steps taken, with rollbacks, or reported unstable) within a wall-clock bound, so a run
/// that waits forever fails here instead of hanging CI.
#[test]
fn oversized_steps_finish_or_report_unstable_on_both_backends() {
    let base = RunArgs {
        particles: 2000,
        integrator: Integrator::KickDriftKick,
        ..Default::default()
    };
    let derived = configured_setup(&base).scene.params.time_step;
    for backend in [Backend::Cpu, Backend::Gpu] {
        for factor in [3.0, 10.0] {
            let setup = configured_setup(&RunArgs {
                dt: Some(factor * derived),
                ..base.clone()
            });
            let (send, receive) = std::sync::mpsc::channel();
            std::thread::spawn(move || {
                let report = run_setup(&setup, backend, 10, Duration::Steps(30), &Bars::new(true));
                let _ = send.send(report);
            });
            let case = format!("{backend:?} at {factor} x dt {derived}");
            let report = receive
                .recv_timeout(std::time::Duration::from_secs(120))
                .unwrap_or_else(|_| panic!("{case}: no end after 120 s"))
                .unwrap_or_else(|e| panic!("{case}: {e}"));
            let finished = report.steps >= 30 && report.health == "ok";
            assert!(
                finished || report.unstable_step.is_some(),
                "{case}: {} steps, health {}, unstable {:?}",
                report.steps,
                report.health,
                report.unstable_step
            );
        }
    }
}

#[test]
fn solver_on_the_command_line_replaces_the_scene_files_and_the_report_says_so() {
    let scene = shipped_scene("dam_break.ron");
    let args = |solver| RunArgs {
        scene: Some(scene.clone()),
        solver,
        steps: Some(2),
        ..Default::default()
    };
    let own = run(&args(None), &Bars::new(true)).unwrap();
    assert_eq!(own.solver_replaced, None);
    let other = if own.solver == "pbf" {
        Solver::Wcsph
    } else {
        Solver::Pbf
    };
    let replaced = run(&args(Some(other)), &Bars::new(true)).unwrap();
    assert_eq!(replaced.solver, other.name());
    assert_eq!(
        replaced.solver_replaced.as_deref(),
        Some(own.solver.as_str())
    );
}

#[test]
fn rollback_reaches_the_solver_and_the_report() {
    let on = too_large_a_step(true);
    assert!(
        on.rollback && on.rollbacks > 0,
        "{} rollbacks",
        on.rollbacks
    );
    assert_eq!((on.health.as_str(), on.unstable_step), ("ok", None));
    assert!(
        on.dt_last < 0.003 && on.dt_last > 0.0,
        "dt_last {}",
        on.dt_last
    );
    assert!(on.sim_time >= 0.2 - 1e-6);
    let off = too_large_a_step(false);
    assert!(!off.rollback);
    assert_eq!(off.rollbacks, 0);
    assert_eq!(off.health, "unstable");
    assert!(off.unstable_step.is_some());
    assert_eq!(off.dt_last, 0.003);
}

#[test]
fn a_scene_file_runs_with_its_drain_pump_and_probes_and_the_balance_holds() {
    let scene = shipped_scene("aquaplay.ron");
    let args = RunArgs {
        scene: Some(scene),
        time: Some(0.3),
        ..Default::default()
    };
    let report = run(&args, &Bars::new(true)).unwrap();
    assert_eq!(report.health, "ok");
    assert_eq!(report.particle_balance, 0, "{report:?}");
    assert!(report.particles_emitted > 0);
    assert_eq!(
        report.particles + report.particles_emitted as usize - report.particles_drained as usize,
        report.particles_final
    );
    assert_eq!(report.probes.len(), 4);
    assert!(report.probes.iter().all(|p| !p.readings.is_empty()));
    // The pump has set the front channel flowing along +x.
    let flow = &report.probes[0];
    assert_eq!(flow.kind, "flux");
    assert!(
        flow.readings.last().unwrap()[1] > 0.0,
        "{:?}",
        flow.readings.last()
    );
}

/// lock.ron with `--bodies held` and `--bodies avian` (CPU): held, the boat stays where the
/// file puts it and the report says so; with avian the water moves it and it floats in the
/// upper basin (water 0.24 m deep), and the particle balance holds.
#[test]
fn a_scene_files_boat_is_held_or_moved_by_avian() {
    let scene = shipped_scene("lock.ron");
    let report = |bodies| {
        let args = RunArgs {
            scene: Some(scene.clone()),
            bodies,
            time: Some(0.6),
            ..Default::default()
        };
        run(&args, &Bars::new(true)).unwrap()
    };
    let held = report(Bodies::Held);
    assert_eq!(held.bodies.as_deref(), Some("held"));
    assert_eq!(held.body_motion.len(), 1, "{:?}", held.body_motion);
    assert_eq!(held.body_motion[0].name, "boat");
    assert_eq!(held.body_motion[0].start, held.body_motion[0].end);
    // Sampled every 0.05 s over the 0.6 s, at rest when held.
    let series = &held.body_motion[0].series;
    assert!(
        (12..=14).contains(&series.len()),
        "{} samples",
        series.len()
    );
    assert!(held.body_motion[0].settled);
    assert!(series.iter().all(|s| s.velocity == [0.0; 3]));
    assert!(
        series.last().unwrap().force[1] > 0.0,
        "the water holds it up"
    );
    let moved = report(Bodies::Avian);
    assert_eq!(moved.health, "ok", "{moved:?}");
    assert_eq!(moved.particle_balance, 0);
    assert_eq!(moved.bodies.as_deref(), Some("avian"));
    let boat = &moved.body_motion[0];
    let (start, end) = (Vec3::from(boat.start), Vec3::from(boat.end));
    assert!(start.distance(end) > 0.005, "moved: {start} -> {end}");
    // Afloat: neither on the floor (0.03 m) nor above the water.
    assert!(end.y > 0.15 && end.y < 0.3, "the boat floats: {end}");
    // The samples follow it from where it started to where it ended.
    let first = Vec3::from(boat.series[0].position);
    let last = Vec3::from(boat.series.last().unwrap().position);
    assert_eq!(first, start);
    assert!(last.distance(end) < 0.05, "{last} vs {end}");
    assert!(boat.series.iter().any(|s| s.velocity != [0.0; 3]));
}

/// `--samples-every` spaces the bodies' samples as asked (0.2 s over 0.6 s: at 0, 0.2, 0.4 and
/// 0.6 s, where the default takes one every 0.05 s).
#[test]
fn samples_every_spaces_the_bodies_samples() {
    let scene = shipped_scene("lock.ron");
    let args = RunArgs {
        scene: Some(scene),
        time: Some(0.6),
        samples_every: Some(0.2),
        ..Default::default()
    };
    let report = run(&args, &Bars::new(true)).unwrap();
    let times: Vec<f64> = report.body_motion[0].series.iter().map(|s| s.t).collect();
    assert!((4..=5).contains(&times.len()), "{times:?}");
    for pair in times.windows(2).take(3) {
        let gap = pair[1] - pair[0];
        assert!((0.19..0.22).contains(&gap), "{times:?}");
    }
}

/// An emitter half covered by a solid: the particles it would place inside the solid are never
/// emitted, and the report counts none of them against the initial blocks (there are none), on
/// the solver's own loop and in the plugin's app (avian), where the plugin counts every
/// left-out: the balance holds in both.
#[test]
fn an_emitters_particles_left_inside_a_solid_keep_the_balance() {
    let scene = |lid: &str| {
        format!(
            "(\n  preset: Water,\n  spacing: 0.02,\n  solver: Pbf(iterations: 4),\n  \
             container: (min: (0.0, 0.0, 0.0), max: (0.4, 0.4, 0.3)),\n  emitters: [\n    \
             (position: (0.04, 0.3, 0.15), direction: (1.0, 0.0, 0.0), radius: 0.04, \
             speed: 1.5, total: 400),\n  ],\n  colliders: [{lid}],\n)"
        )
    };
    let lid = "(name: \"lid\", shape: Cuboid(half_extents: (0.03, 0.03, 0.06)), \
               position: (0.04, 0.27, 0.15), motion: Static)";
    let run_file = |text: String, bodies| {
        let file = std::env::temp_dir().join(format!(
            "sph_bench_covered_{}_{bodies:?}.ron",
            std::process::id()
        ));
        std::fs::write(&file, text).unwrap();
        let args = RunArgs {
            scene: Some(file.clone()),
            bodies,
            time: Some(0.1),
            ..Default::default()
        };
        let report = run(&args, &Bars::new(true)).unwrap();
        std::fs::remove_file(&file).ok();
        report
    };
    let open = run_file(scene(""), Bodies::Held);
    for bodies in [Bodies::Held, Bodies::Avian] {
        let report = run_file(scene(lid), bodies);
        assert_eq!(report.health, "ok", "{bodies:?}");
        // The lid covers part of the pipe's mouth: fewer particles come out.
        assert!(
            report.particles_emitted > 0 && report.particles_emitted < open.particles_emitted,
            "{bodies:?}: {} emitted, {} without the lid",
            report.particles_emitted,
            open.particles_emitted
        );
        assert_eq!(report.spawns_inside_colliders, 0, "{bodies:?}");
        assert_eq!(report.particle_balance, 0, "{bodies:?}: {report:?}");
    }
}
