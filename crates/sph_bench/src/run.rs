//! Runs one scenario on the CPU solver or on the plugin's GPU passes.

use crate::args::{Backend, Duration, RunArgs, TimeStep};
use crate::report::Report;
use bevy::prelude::*;
use bevy_sph_fluid::headless;
use bevy_sph_fluid::prelude::*;
use sph_core::diagnostics::DiagnosticsInput;
use sph_core::scenario::{dam_break_with_particles, Scene};
use sph_core::{CpuSolver, Diagnostics, NeighborSearch};
use std::time::Instant;

/// The scene of the arguments.
pub fn scene(args: &RunArgs) -> Scene {
    let mut scene = dam_break_with_particles(args.particles);
    let p = &mut scene.params;
    p.integrator = args.integrator;
    p.neighbor_search = args.search;
    if args.surface_tension {
        p.surface_tension = sph_core::params::WATER_SURFACE_TENSION;
    }
    match args.time_step {
        TimeStep::Default => {}
        TimeStep::Fixed(dt) => p.time_step = dt,
        TimeStep::Cfl(lambda) => {
            // Same rule as the derivation: dt = λ h / (c0 + v_peak), v_peak = c0 / 10.
            let c0 = p.speed_of_sound();
            p.time_step = lambda * p.smoothing_radius / (1.1 * c0);
        }
    }
    scene
}

fn steps_of(args: &RunArgs, dt: f32) -> u64 {
    match args.duration {
        Duration::Steps(n) => n,
        Duration::Time(t) => (t / dt as f64).ceil() as u64,
    }
}

fn median(mut v: Vec<f64>) -> f64 {
    if v.is_empty() {
        return 0.0;
    }
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn progress(done: u64, total: u64, last: &mut u64) {
    let percent = done * 100 / total.max(1);
    if percent >= *last + 10 || done == total {
        *last = percent;
        eprintln!("  {percent:3}% ({done}/{total} steps)");
    }
}

fn names(args: &RunArgs) -> (String, String) {
    let integrator = match args.integrator {
        sph_core::Integrator::SymplecticEuler => "euler",
        sph_core::Integrator::Leapfrog => "leapfrog",
        sph_core::Integrator::KickDriftKick => "kdk",
    };
    let search = match args.search {
        NeighborSearch::Grid => "grid",
        NeighborSearch::Hash => "hash",
    };
    (integrator.into(), search.into())
}

fn base_report(args: &RunArgs, scene: &Scene, steps: u64, times: Vec<f64>) -> Report {
    let (integrator, search) = names(args);
    let ms = median(times);
    let dt = scene.params.time_step;
    Report {
        scenario: args.scenario.clone(),
        backend: if args.backend == Backend::Gpu {
            "gpu"
        } else {
            "cpu"
        }
        .into(),
        particles: scene.particle_count(),
        integrator,
        search,
        surface_tension: args.surface_tension,
        dt,
        steps,
        sim_time: steps as f64 * dt as f64,
        ms_per_step_median: ms,
        cost_per_sim_second_s: ms / 1e3 / dt as f64,
        ns_per_particle_step: ms * 1e6 / scene.particle_count().max(1) as f64,
        ..Default::default()
    }
}

fn finish(report: &mut Report, d: &Diagnostics) {
    report.density_error_mean_pct = d.density_error_mean_pct;
    report.density_error_max_pct = d.density_error_max_pct;
    report.nan_count = d.non_finite_count;
    report.escaped_count = d.outside_count;
    report.particles_final = d.particle_count;
}

/// Runs on the CPU solver.
pub fn run_cpu(args: &RunArgs) -> Result<Report, String> {
    let scene = scene(args);
    let n = scene.particle_count();
    let mut solver =
        CpuSolver::new(scene.params, scene.container, n.max(1)).map_err(|e| e.to_string())?;
    solver.spawn(&scene.positions(), Vec3::ZERO);
    let steps = steps_of(args, scene.params.time_step);
    let mut times = Vec::with_capacity(steps as usize);
    let mut last = 0;
    for k in 0..steps {
        let t = Instant::now();
        solver.step();
        times.push(t.elapsed().as_secs_f64() * 1e3);
        progress(k + 1, steps, &mut last);
    }
    let mut report = base_report(args, &scene, steps, times);
    report.adapter = "cpu".into();
    report.stage_ms = solver
        .timings()
        .stages()
        .iter()
        .map(|(name, t)| {
            (
                name.to_string(),
                t.as_secs_f64() * 1e3 / steps.max(1) as f64,
            )
        })
        .collect();
    finish(&mut report, &solver.diagnostics());
    Ok(report)
}

/// Runs on the GPU passes of `SphFluidPlugin` in a headless app.
pub fn run_gpu(args: &RunArgs) -> Result<Report, String> {
    let adapter = headless::vulkan_adapter()?;
    let scene = scene(args);
    let n = scene.particle_count();
    let mut app = headless::headless_app(
        DefaultPlugins.build().disable::<bevy::winit::WinitPlugin>(),
        n.max(1) as u32,
        SphBackend::Gpu,
        true,
    );
    app.insert_resource(SphParams(scene.params));
    app.world_mut().spawn(SphContainer(scene.container));
    for block in &scene.blocks {
        app.world_mut().spawn(SphBlockSpawn {
            block: *block,
            velocity: Vec3::ZERO,
        });
    }
    app.update();
    let steps = steps_of(args, scene.params.time_step);
    eprintln!("  compiling shaders and taking the first step on {adapter}");
    headless::step_to(&mut app, 1)?;
    let mut times = Vec::new();
    let mut last = 0;
    let mut done = 1;
    while done < steps {
        let k = (args.substeps as u64).min(steps - done) as u32;
        app.insert_resource(SphControl {
            running: true,
            substeps: k,
            ..default()
        });
        let t = Instant::now();
        app.update();
        headless::wait_for_gpu(&app);
        let taken = headless::steps_taken(&app) - done;
        if taken == 0 {
            let error = app.world().resource::<SphStats>().error.clone();
            return Err(format!("the GPU stopped stepping: {error:?}"));
        }
        times.push(t.elapsed().as_secs_f64() * 1e3 / taken as f64);
        done += taken;
        progress(done, steps, &mut last);
    }
    app.insert_resource(SphControl {
        running: false,
        ..default()
    });
    let snapshot = headless::snapshot(&mut app)?;
    // Read after the snapshot's extra frames: the main world sees the render world's feedback
    // one frame late.
    let stats = app.world().resource::<SphStats>().clone();
    let mut report = base_report(args, &scene, done, times);
    report.adapter = adapter;
    report.dispatches_per_step = stats.dispatches_per_step;
    report.gpu_bytes_per_particle = stats.gpu_bytes_per_particle;
    report.gpu_mib_per_million = stats.gpu_bytes_per_particle as f64 * 1e6 / (1024.0 * 1024.0);
    report.stage_ms = stats.stage_ms.into_iter().collect();
    let d = Diagnostics::measure(
        &scene.params,
        &scene.container,
        &DiagnosticsInput {
            position: &snapshot.positions,
            velocity: &snapshot.velocities,
            density: &snapshot.densities,
        },
    );
    finish(&mut report, &d);
    Ok(report)
}
