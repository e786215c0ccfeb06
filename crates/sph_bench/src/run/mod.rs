//! Runs one scenario on either backend: steps in chunks, samples the state every 0.01 s where the
//! scenario measures something over time, shows a progress bar, and fills the report.
//!
//! The run loop is here; `setup` turns the command line into a scenario's setup, `samples`
//! measures the particle state, and `bodies` the forces on colliders and the motion of bodies.

mod bodies;
mod samples;
mod setup;
#[cfg(test)]
mod tests;

pub use samples::diagnostics;
pub use setup::{configured_setup, names, rollback};

use crate::args::{Backend, Duration, RunArgs};
use crate::martin_moyce::{experiment, rms_error_and_best_shift};
use crate::progress::Bars;
use crate::report::Report;
use crate::scenarios::Setup;
use crate::sim::app::AppSimulation;
use crate::sim::cpu::CpuSimulation;
use crate::sim::Simulation;
use bodies::{body_motion, buoyancy, BodyTrack, ForceWindow};
use samples::{level_difference, Samples, SAMPLE_INTERVAL};

fn median(mut v: Vec<f64>) -> f64 {
    if v.is_empty() {
        return 0.0;
    }
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// The backend's simulation of `setup` (the GPU's first step taken, so shaders are compiled).
pub fn simulation(
    setup: &Setup,
    backend: Backend,
    substeps: u32,
    bars: &Bars,
) -> Result<Box<dyn Simulation>, String> {
    let avian = setup
        .extras
        .as_ref()
        .is_some_and(|e| e.bodies == crate::scenarios::Bodies::Avian);
    Ok(match backend {
        // avian runs in a Bevy app: the plugin's CPU backend there.
        Backend::Cpu if avian => Box::new(AppSimulation::new(
            setup,
            bevy_sph_fluid::SphBackend::Cpu,
            substeps,
        )?),
        Backend::Cpu => Box::new(CpuSimulation::new(setup)?),
        Backend::Gpu => {
            let mut gpu = AppSimulation::new(setup, bevy_sph_fluid::SphBackend::Gpu, substeps)?;
            bars.note("  compiling shaders and taking the first step");
            gpu.advance(1)?;
            Box::new(gpu)
        }
    })
}

/// Progress in the bar's units: steps, or simulated milliseconds.
fn progress_units(duration: Duration, steps: u64, time: f64) -> (u64, u64) {
    match duration {
        Duration::Steps(n) => (steps.min(n), n),
        Duration::Time(t) => {
            let len = (t * 1e3).ceil() as u64;
            (((time * 1e3).round() as u64).min(len), len)
        }
    }
}

/// Runs `setup` on `backend` for `duration` and reports; a progress bar in `bars` shows how far.
pub fn run_setup(
    setup: &Setup,
    backend: Backend,
    substeps: u32,
    duration: Duration,
    bars: &Bars,
) -> Result<Report, String> {
    run_setup_sampled(setup, backend, substeps, duration, None, bars)
}

/// [`run_setup`] with the state and the bodies sampled every `samples_every` seconds of
/// simulated time (`None`: every [`SAMPLE_INTERVAL`] and [`bodies::BODY_SAMPLE_INTERVAL`]).
/// In the plugin's app (the GPU backend, avian bodies on either) a sample pauses the app until
/// its clock is read back, which the GPU's readback-lagged coupling of moving bodies notices
/// (docs/scenes.md): fewer samples run more frames unpaused, as a game runs.
pub fn run_setup_sampled(
    setup: &Setup,
    backend: Backend,
    substeps: u32,
    duration: Duration,
    samples_every: Option<f64>,
    bars: &Bars,
) -> Result<Report, String> {
    let mut sim = simulation(setup, backend, substeps, bars)?;
    let params = setup.scene.params;
    let end = match duration {
        Duration::Time(t) => t,
        Duration::Steps(n) => n as f64 * params.time_step as f64,
    };
    let mut samples = Samples::for_setup(setup, backend, end);
    let mut times = Vec::new();
    let mut next_sample = 0.0;
    let mut progress = bars.run(setup.scenario.name(), progress_units(duration, 0, 0.0).1);
    let mut forces = ForceWindow::new(0.6 * end, setup.colliders.len());
    let state_interval = samples_every.unwrap_or(SAMPLE_INTERVAL);
    let mut track = BodyTrack::new(setup, samples_every.unwrap_or(bodies::BODY_SAMPLE_INTERVAL));
    let finished = |sim: &dyn Simulation| match duration {
        Duration::Steps(n) => sim.steps() >= n,
        Duration::Time(t) => sim.time() >= t - 1e-9,
    };
    loop {
        track.record(setup, sim.as_ref(), &forces.last, false);
        if samples.wanted() && sim.time() + 1e-9 >= next_sample {
            let state = sim.state()?;
            samples.record(setup, sim.time(), &state, sim.whitewater_counts())?;
            next_sample += state_interval;
        }
        if finished(sim.as_ref()) || sim.unstable_step().is_some() {
            break;
        }
        // Chunks are planned with the rule's largest dt, so a chunk never runs past the end or
        // the next sample: with the last dt read back (a frame or two late on the GPU, and
        // small while PBF's water was fast), a GPU run of the pipe scene ended 0.12 s past 2 s.
        let dt = params.time_step as f64;
        let mut chunk = match duration {
            Duration::Steps(n) => n.saturating_sub(sim.steps()),
            Duration::Time(t) => ((t - sim.time()) / dt).ceil().max(1.0) as u64,
        };
        if samples.wanted() {
            chunk = chunk.min(((next_sample - sim.time()) / dt).ceil().max(1.0) as u64);
        }
        if !track.bodies.is_empty() {
            chunk = chunk.min(((track.next - sim.time()) / dt).ceil().max(1.0) as u64);
        }
        let chunk = chunk.clamp(1, 500) as u32;
        let (taken, ms) = sim.advance(chunk)?;
        if taken > 0 {
            times.push(ms / taken as f64);
        }
        forces.record(sim.as_mut());
        let (done, _) = progress_units(duration, sim.steps(), sim.time());
        progress.set(
            done,
            format!("t = {:.3} s, step {}", sim.time(), sim.steps()),
        );
    }
    progress.finish();
    track.record(setup, sim.as_ref(), &forces.last, true);
    let state = sim.state()?;
    let d = diagnostics(setup, &state);
    let (integrator, search) = names(params.integrator, params.neighbor_search);
    let steps = sim.steps();
    let ms = median(times);
    let sim_time = sim.time();
    let dt_mean = if steps > 0 {
        sim_time / steps as f64
    } else {
        params.time_step as f64
    };
    let left_out = sim.spawns_inside_colliders();
    // A pipe-fill's particles are its capacity; a scene file's are its blocks' (the emitters'
    // are counted as emitted).
    let particles = match setup.extras {
        Some(_) => setup.scene.particle_count(),
        None => setup.scene.particle_count().max(setup.capacity),
    } - left_out as usize;
    let speeds: Vec<f32> = state.velocities.iter().map(|v| v.length()).collect();
    let colliders_now = sim.colliders_now(&setup.colliders);
    // Deeper than the guard's tolerance (a particle resting on an edge rounds a few ulps in).
    let depth = sph_core::boundary::guard::tolerance(setup.scene.params.spacing());
    let inside_collider_count = state
        .positions
        .iter()
        .filter(|&&x| colliders_now.iter().any(|c| c.signed_distance(x) < -depth))
        .count();
    let unstable_step = sim.unstable_step();
    let mut report = Report {
        scenario: setup.scenario.name().into(),
        backend: backend.name().into(),
        adapter: sim.adapter(),
        particles,
        integrator: integrator.into(),
        search: search.into(),
        solver: params.solver.name().into(),
        pressure_iterations_mean: sim.iterations().means().0,
        pressure_iterations_max: sim.iterations().means().1,
        divergence_iterations_mean: sim.iterations().means().2,
        solves_cut_short: sim.iterations().cut_short,
        density_error_mean_run_pct: samples.density_error_run(d.density_error_mean_pct),
        surface_tension: params.has_surface_tension(),
        adaptive_time_step: params.adaptive_time_step,
        cfl_factor: params.cfl_factor,
        dt: params.time_step,
        dt_mean,
        steps,
        sim_time,
        ms_per_step_median: ms,
        cost_per_sim_second_s: ms / 1e3 / dt_mean,
        ns_per_particle_step: ms * 1e6 / particles.max(1) as f64,
        dispatches_per_step: sim.dispatches_per_step(),
        stage_ms: sim.stage_ms().into_iter().collect(),
        density_error_mean_pct: d.density_error_mean_pct,
        density_error_max_pct: d.density_error_max_pct,
        density_error_mean_max_pct: samples.density_error_peak.max(d.density_error_mean_pct),
        nan_count: d.non_finite_count,
        escaped_count: d.outside_count,
        particles_final: d.particle_count,
        gpu_bytes_per_particle: sim.gpu_bytes_per_particle(),
        gpu_mib_per_million: sim.gpu_bytes_per_particle() as f64 * 1e6 / (1024.0 * 1024.0),
        rollback: setup.rollback.enabled,
        rollbacks: sim.rollbacks(),
        dt_last: sim.last_dt(),
        health: if unstable_step.is_some() || d.non_finite_count > 0 || d.outside_count > 0 {
            "unstable"
        } else {
            "ok"
        }
        .into(),
        unstable_step,
        speed_mean_end: speeds.iter().sum::<f32>() / speeds.len().max(1) as f32,
        speed_max_end: speeds.iter().copied().fold(0.0, f32::max),
        boundary_corrections: sim.boundary_corrections().0,
        wall_corrections: sim.boundary_corrections().1,
        inside_collider_count,
        spawns_inside_colliders: left_out,
        level_difference_end: setup
            .gate_x
            .map(|x| level_difference(&state, x, setup.scene.params.spacing())),
        collider_forces: forces.report(&setup.colliders),
        particles_emitted: sim.flow_counts().0,
        particles_drained: sim.flow_counts().1,
        scene_file: setup.extras.as_ref().map(|e| e.file.clone()),
        solver_replaced: setup
            .extras
            .as_ref()
            .and_then(|e| e.solver_replaced)
            .map(|s| s.name().to_owned()),
        probes: setup
            .extras
            .as_ref()
            .map(|e| sim.probe_log().report(&e.probes, sim_time))
            .unwrap_or_default(),
        bodies: setup.extras.as_ref().map(|e| e.bodies.name().into()),
        body_motion: body_motion(setup, &colliders_now, track),
        ..Default::default()
    };
    report.particle_balance = report.particles as i64 + report.particles_emitted as i64
        - report.particles_drained as i64
        - report.particles_final as i64;
    if setup.scenario == crate::scenarios::Scenario::Buoyancy {
        report.buoyancy = buoyancy(setup, &report.collider_forces);
    }
    if let Some(mut figures) = samples.dam_break {
        // Only a run that reached T = 2.5 is compared (NaN, written as null, otherwise).
        let reached = figures.front_nd.last().is_some_and(|p| p[0] >= 2.5);
        let (raw, shifted, shift) = if reached {
            rms_error_and_best_shift(&figures.front_nd, &experiment())
        } else {
            (f64::NAN, f64::NAN, f64::NAN)
        };
        figures.rms_z_raw = raw;
        figures.rms_z_shifted = shifted;
        figures.best_shift = shift;
        report.dam_break = Some(figures);
    }
    report.hydrostatic = samples.hydrostatic.map(|h| h.finish(&params));
    let g = params.gravity.length() as f64;
    if let (Some(h), Some(walls)) = (report.hydrostatic.as_mut(), forces.walls()) {
        let weight = report.particles_final as f64 * params.particle_mass as f64 * g;
        let down = params.gravity.normalize_or_zero().as_dvec3();
        h.walls_force_n = Some(walls.dot(down));
        h.walls_weight_error_pct = Some((walls.dot(down) - weight) / weight * 100.0);
    }
    report.u_tube = samples.u_tube.map(|u| u.finish(g));
    report.orifice = samples.orifice.map(|o| o.finish(g));
    report.thin_wall = samples.thin_wall.map(|w| w.finish());
    let stage_ms = sim.stage_ms();
    report.whitewater = samples
        .whitewater
        .map(|w| w.finish(&stage_ms, substeps, report.steps));
    Ok(report)
}

/// `sph-bench run`.
pub fn run(args: &RunArgs, bars: &Bars) -> Result<Report, String> {
    let setup = match &args.scene {
        // The file decides the parameters and the solver; the run's length, backend and
        // rollback come from the command line.
        Some(path) => {
            let mut setup = crate::scene_run::setup_from_file(path)?;
            // --solver replaces the file's solver (with its own time-step rule); the report
            // says which ran and where it came from.
            if let (Some(solver), Some(extras)) = (args.solver, setup.extras.as_mut()) {
                extras.solver_replaced = Some(setup.scene.params.solver);
                setup.scene.params.use_solver(solver);
                setup
                    .scene
                    .params
                    .validate()
                    .map_err(|e| format!("--solver {}: {e}", solver.name()))?;
            }
            setup.rollback = rollback(args.rollback);
            // The file's whitewater, or the defaults with --whitewater on.
            if args.whitewater && setup.whitewater.is_none() {
                setup.whitewater = Some(Default::default());
            }
            if let Some(extras) = &mut setup.extras {
                extras.bodies = args.bodies;
            }
            setup
        }
        None => configured_setup(args),
    };
    let duration = args.duration().unwrap_or(Duration::Time(setup.duration));
    run_setup_sampled(
        &setup,
        args.backend,
        args.substeps,
        duration,
        args.samples_every.map(f64::from),
        bars,
    )
}
