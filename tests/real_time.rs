//! Real-time mode ([`SphControl::real_time`]): each frame advances the water by the frame's own
//! time, clamped, in as many steps as the solver needs, on both backends; bad limits are refused
//! with the field and the previous state kept.

mod common;

use bevy::prelude::*;
use bevy::time::TimeUpdateStrategy;
use bevy_sph_fluid::prelude::*;
use common::*;
use sph_core::{BlockSpawn, BoxContainer, Solver};
use std::time::Duration;

const FRAME: f32 = 1.0 / 60.0;

/// A small tank whose frames last exactly `frame` seconds, running in real-time mode.
fn real_time_app(backend: SphBackend, solver: Solver, frame: f32) -> App {
    let mut app = headless_app(4_000, backend);
    let mut params = sph_core::SphParams::water();
    params.use_solver(solver);
    let dx = params.spacing();
    app.insert_resource(SphParams(params));
    app.insert_resource(TimeUpdateStrategy::ManualDuration(Duration::from_secs_f32(
        frame,
    )));
    app.world_mut()
        .spawn(SphContainer(BoxContainer::from_min_max(
            Vec3::ZERO,
            Vec3::new(0.3, 0.3, 0.12),
        )));
    let block = BlockSpawn::new(Vec3::splat(0.5 * dx), Vec3::new(0.14, 0.12, 0.11), dx);
    app.world_mut().spawn(SphBlockSpawn {
        block,
        velocity: Vec3::ZERO,
    });
    app.insert_resource(SphControl {
        running: true,
        real_time: Some(SphRealTime::default()),
        ..default()
    });
    app
}

/// Simulated time gained over `frames` frames [s], as the stats report it.
fn gain(app: &mut App, frames: u32) -> f64 {
    let start = app.world().resource::<SphStats>().sim_time;
    for _ in 0..frames {
        app.update();
    }
    app.world().resource::<SphStats>().sim_time - start
}

#[test]
fn cpu_frames_advance_by_their_own_time_for_every_solver() {
    for solver in [Solver::Wcsph, Solver::Dfsph, Solver::Pbf] {
        let mut app = real_time_app(SphBackend::Cpu, solver, FRAME);
        gain(&mut app, 2);
        let count = app.world().resource::<SphStats>().particle_count;
        let gained = gain(&mut app, 12);
        let expected = 12.0 * FRAME as f64;
        assert!(
            (gained - expected).abs() < 1e-5,
            "{solver:?}: {gained} s in 12 frames of {FRAME} s"
        );
        let stats = app.world().resource::<SphStats>();
        assert!(stats.frame_steps >= 1, "{solver:?}");
        if solver == Solver::Pbf {
            assert_eq!(stats.frame_steps, 2, "PBF's largest dt is 1/120 s");
        }
        assert_eq!(stats.particle_count, count);
        assert_eq!(stats.health, SphHealth::Ok, "{solver:?}");
        assert!(stats.density_error_mean_pct.is_finite());
    }
}

#[test]
fn a_hitch_is_clamped_to_the_largest_frame_time() {
    let mut app = real_time_app(SphBackend::Cpu, Solver::Pbf, 0.5);
    gain(&mut app, 2);
    let gained = gain(&mut app, 4);
    let expected = 4.0 * SphRealTime::default().max_frame_time as f64;
    assert!(
        (gained - expected).abs() < 1e-5,
        "{gained} against {expected}"
    );
}

#[test]
fn bad_limits_are_refused_and_nothing_moves() {
    let mut app = real_time_app(SphBackend::Cpu, Solver::Pbf, FRAME);
    gain(&mut app, 3);
    for (bad, field) in [
        (
            SphRealTime {
                max_frame_time: 0.0,
                ..default()
            },
            "max_frame_time",
        ),
        (
            SphRealTime {
                max_frame_time: f32::NAN,
                ..default()
            },
            "max_frame_time",
        ),
        (
            SphRealTime {
                max_steps: 0,
                ..default()
            },
            "max_steps",
        ),
        (
            SphRealTime {
                max_steps: 65,
                ..default()
            },
            "max_steps",
        ),
    ] {
        app.world_mut().resource_mut::<SphControl>().real_time = Some(bad);
        let gained = gain(&mut app, 2);
        assert_eq!(gained, 0.0, "{bad:?}");
        let error = app.world().resource::<SphStats>().error.clone();
        let error = error.expect("an error naming the field");
        assert!(
            error.contains(&format!("SphControl::real_time.{field}")),
            "{error}"
        );
    }
    app.world_mut().resource_mut::<SphControl>().real_time = Some(SphRealTime::default());
    let gained = gain(&mut app, 3);
    assert!((gained - 3.0 * FRAME as f64).abs() < 1e-5, "{gained}");
    assert_eq!(app.world().resource::<SphStats>().error, None);
}

/// `SphControl::max_body_frame_time` outside (0, 1] s is refused by name and nothing moves;
/// `None` (no limit) and a valid time run on.
#[test]
fn a_bad_body_frame_time_is_refused_and_nothing_moves() {
    let mut app = real_time_app(SphBackend::Cpu, Solver::Pbf, FRAME);
    gain(&mut app, 3);
    for bad in [0.0, -0.01, f32::NAN, 2.0] {
        app.world_mut()
            .resource_mut::<SphControl>()
            .max_body_frame_time = Some(bad);
        assert_eq!(gain(&mut app, 2), 0.0, "{bad}");
        let error = app.world().resource::<SphStats>().error.clone();
        let error = error.expect("an error naming the field");
        assert!(error.contains("SphControl::max_body_frame_time"), "{error}");
    }
    for good in [None, Some(0.01)] {
        app.world_mut()
            .resource_mut::<SphControl>()
            .max_body_frame_time = good;
        let gained = gain(&mut app, 3);
        assert!(
            (gained - 3.0 * FRAME as f64).abs() < 1e-5,
            "{good:?}: {gained}"
        );
        assert_eq!(app.world().resource::<SphStats>().error, None);
    }
}

#[test]
fn gpu_frames_advance_by_their_own_time_without_waiting() {
    let _gpu = GPU.lock().unwrap_or_else(|e| e.into_inner());
    for solver in [Solver::Wcsph, Solver::Pbf] {
        let mut app = real_time_app(SphBackend::Gpu, solver, FRAME);
        warm_up(&mut app);
        // Once the rule's dt is read back, every frame plans its steps from it and the device
        // splits the frame among them; the clock is read back a frame or two late, so compare
        // long runs.
        let frames = 30;
        let gained = gain(&mut app, frames);
        let expected = frames as f64 * FRAME as f64;
        assert!(
            (gained - expected).abs() < 0.05 * expected,
            "{solver:?}: {gained} s in {frames} frames of {FRAME} s"
        );
        let stats = app.world().resource::<SphStats>();
        match solver {
            Solver::Pbf => assert_eq!(stats.frame_steps, 2, "PBF's largest dt is 1/120 s"),
            _ => assert!(stats.frame_steps > 1, "WCSPH needs many steps per 1/60 s"),
        }
        // No step was longer than the rule allowed: the device's dt is at most the budget's
        // share.
        assert!(stats.time_step <= FRAME / stats.frame_steps as f32 * 1.05);
        assert_eq!(stats.health, SphHealth::Ok, "{solver:?}");
        assert_eq!(stats.error, None, "{solver:?}");
    }
}

/// Runs until the pipelines are compiled and the clock's first readbacks arrived.
fn warm_up(app: &mut App) {
    for _ in 0..400 {
        app.update();
        if app.world().resource::<SphStats>().sim_time > 0.1 {
            break;
        }
    }
    let stats = app.world().resource::<SphStats>().clone();
    assert!(stats.sim_time > 0.1, "{:?}", stats.error);
}

/// PBF on the GPU: frames of 0.5 s gain `max_frame_time` each, and the water stays healthy.
#[test]
fn a_gpu_hitch_is_clamped_to_the_largest_frame_time() {
    let _gpu = GPU.lock().unwrap_or_else(|e| e.into_inner());
    let mut app = real_time_app(SphBackend::Gpu, Solver::Pbf, 0.5);
    warm_up(&mut app);
    let count = app.world().resource::<SphStats>().particle_count;
    let frames = 20;
    let gained = gain(&mut app, frames);
    let expected = frames as f64 * SphRealTime::default().max_frame_time as f64;
    assert!(
        (gained - expected).abs() < 0.05 * expected,
        "{gained} against {expected}"
    );
    let stats = app.world().resource::<SphStats>();
    assert_eq!(stats.health, SphHealth::Ok);
    assert_eq!(stats.particle_count, count);
    let s = snapshot(&mut app);
    assert_eq!(s.positions.len(), count as usize);
    assert!(s.positions.iter().all(|x| x.is_finite()));
}
