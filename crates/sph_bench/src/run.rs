//! Runs one scenario on either backend: steps in chunks, samples the state every 0.01 s where the
//! scenario measures something over time, shows a progress bar, and fills the report.

use crate::args::{integrator_name, search_name, Backend, Duration, RunArgs};
use crate::hydrostatic::HydrostaticSampler;
use crate::martin_moyce::{experiment, rms_error_and_best_shift};
use crate::progress::Bars;
use crate::report::{
    BodyMotion, BodySample, BuoyancyFigures, ColliderForceReport, DamBreakFigures, Report,
};
use crate::scenarios::{setup, Setup, G};
use crate::sim::{AppSimulation, CpuSimulation, Simulation, State};
use sph_core::diagnostics::DiagnosticsInput;
use sph_core::front::surge_front;
use sph_core::glam::Vec3;
use sph_core::{Diagnostics, Integrator, NeighborSearch, Rollback, Solver};

/// Interval between samples of the state [s].
pub const SAMPLE_INTERVAL: f64 = 0.01;

/// The setup of the arguments: the scenario with the integrator, search, surface tension,
/// time-step and rollback overrides applied.
pub fn configured_setup(args: &RunArgs) -> Setup {
    let mut s = setup(args.scenario, args.particles, args.a);
    let p = &mut s.scene.params;
    p.integrator = args.integrator;
    p.neighbor_search = args.search;
    if args.surface_tension {
        p.surface_tension = sph_core::params::WATER_SURFACE_TENSION;
    }
    let solver = args.solver.unwrap_or(Solver::Wcsph);
    match solver {
        Solver::Wcsph => {
            if let Some(dt) = args.dt {
                p.time_step = dt;
            }
            p.adaptive_time_step = args.adaptive;
            if let Some(lambda) = args.cfl {
                p.cfl_factor = lambda;
                if !args.adaptive && args.dt.is_none() {
                    // A fixed step from the CFL factor: dt = λ h / (c0 + v_peak), v_peak = c0 / 10.
                    p.time_step = lambda * p.smoothing_radius / (1.1 * p.speed_of_sound());
                }
            }
        }
        Solver::Dfsph | Solver::Pbf => {
            // The solver's own rule, unless a dt is given (then fixed, or the largest with
            // --adaptive on), with --cfl's λ in place of the solver's.
            p.use_solver(solver);
            if let Some(lambda) = args.cfl {
                p.cfl_factor = lambda;
            }
            if let Some(dt) = args.dt {
                p.time_step = dt;
                p.adaptive_time_step = args.adaptive;
            }
            if let Some(pct) = args.density_error {
                p.dfsph.max_density_error = pct / 100.0;
            }
            if let Some(pct) = args.divergence_error {
                p.dfsph.max_divergence_error = pct / 100.0;
            }
            p.dfsph.warm_start = args.warm_start;
            if let Some(n) = args.max_iterations {
                p.dfsph.max_density_iterations = n;
                p.dfsph.max_divergence_iterations = n;
            }
            if let Some(omega) = args.divergence_over_relaxation {
                p.dfsph.divergence_over_relaxation = omega;
            }
            if let Some(omega) = args.density_over_relaxation {
                p.dfsph.density_over_relaxation = omega;
            }
            if let Some(n) = args.pbf_iterations {
                p.pbf.iterations = n;
            }
            if let Some(epsilon) = args.pbf_vorticity {
                p.pbf.vorticity_epsilon = epsilon;
            }
            if let Some(omega) = args.pbf_over_relaxation {
                p.pbf.over_relaxation = omega;
            }
        }
    }
    if let Some(alpha) = args.viscosity_alpha {
        // ν = α h c0 / 10, as in the derivation; after use_solver, which sets DFSPH's own α.
        p.set_artificial_viscosity_alpha(alpha);
    }
    s.rollback = rollback(args.rollback);
    s.walls = args.walls;
    if let Some(f) = args.wall_friction {
        s.wall_friction = (f > 0.0).then_some(f);
    }
    s
}

/// The rollback settings of `--rollback on|off`.
pub fn rollback(on: bool) -> Rollback {
    if on {
        Rollback::default()
    } else {
        Rollback::off()
    }
}

/// Names of the integrator and search, as on the command line.
pub fn names(integrator: Integrator, search: NeighborSearch) -> (&'static str, &'static str) {
    (integrator_name(integrator), search_name(search))
}

fn median(mut v: Vec<f64>) -> f64 {
    if v.is_empty() {
        return 0.0;
    }
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// What a scenario records while it runs.
#[derive(Default)]
struct Samples {
    dam_break: Option<DamBreakFigures>,
    hydrostatic: Option<HydrostaticSampler>,
    /// The largest mean compression error seen [%].
    density_error_peak: f32,
    /// Σ and count of the sampled mean compression errors [%].
    density_error_sum: f64,
    density_error_samples: u64,
    /// Sample the density even without a dam break or a tank (cheap on the CPU).
    track_density: bool,
}

impl Samples {
    /// The samplers of `setup` for a run that ends at `end` [s].
    fn for_setup(setup: &Setup, backend: Backend, end: f64) -> Self {
        Self {
            track_density: backend == Backend::Cpu,
            density_error_sum: 0.0,
            density_error_samples: 0,
            dam_break: setup.column_width_a.map(|a| DamBreakFigures {
                column_width_a: a,
                ..Default::default()
            }),
            hydrostatic: setup
                .water_depth
                .map(|_| HydrostaticSampler::new(setup, end)),
            density_error_peak: 0.0,
        }
    }

    fn wanted(&self) -> bool {
        self.track_density || self.dam_break.is_some() || self.hydrostatic.is_some()
    }

    /// The mean of the sampled mean compression errors, or `end` without samples.
    fn density_error_run(&self, end: f32) -> f32 {
        if self.density_error_samples == 0 {
            end
        } else {
            (self.density_error_sum / self.density_error_samples as f64) as f32
        }
    }

    fn record(&mut self, setup: &Setup, time: f64, state: &State) {
        let d = diagnostics(setup, state);
        self.density_error_peak = self.density_error_peak.max(d.density_error_mean_pct);
        self.density_error_sum += d.density_error_mean_pct as f64;
        self.density_error_samples += 1;
        if let Some(d) = &mut self.dam_break {
            let a = d.column_width_a as f64;
            let link = setup.scene.params.smoothing_radius;
            let x = surge_front(&state.positions, &setup.scene.container, link).unwrap_or(0.0);
            d.front.push([time, x as f64]);
            d.front_nd.push([time * (2.0 * G / a).sqrt(), x as f64 / a]);
        }
        if let Some(h) = &mut self.hydrostatic {
            h.record(setup, time, state);
        }
    }
}

/// Diagnostics of `state` in the scenario.
pub fn diagnostics(setup: &Setup, state: &State) -> Diagnostics {
    Diagnostics::measure(
        &setup.scene.params,
        &setup.scene.container,
        &DiagnosticsInput {
            position: &state.positions,
            velocity: &state.velocities,
            density: &state.densities,
        },
    )
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
    let mut track = BodyTrack::new(setup);
    let finished = |sim: &dyn Simulation| match duration {
        Duration::Steps(n) => sim.steps() >= n,
        Duration::Time(t) => sim.time() >= t - 1e-9,
    };
    loop {
        track.record(setup, sim.as_ref(), &forces.last, false);
        if samples.wanted() && sim.time() + 1e-9 >= next_sample {
            let state = sim.state()?;
            samples.record(setup, sim.time(), &state);
            next_sample += SAMPLE_INTERVAL;
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
    Ok(report)
}

/// The water level of each basin (the 98th percentile of the heights of the particles more than
/// 4 spacings from the gate and the side walls) and their difference [m].
pub fn level_difference(state: &State, gate_x: f32, spacing: f32) -> f32 {
    let level = |left: bool| {
        let mut y: Vec<f32> = state
            .positions
            .iter()
            .filter(|x| {
                let away = (x.x - gate_x).abs() > 4.0 * spacing;
                away && (x.x < gate_x) == left
            })
            .map(|x| x.y)
            .collect();
        if y.is_empty() {
            return 0.0;
        }
        y.sort_by(f32::total_cmp);
        y[((y.len() - 1) as f32 * 0.98) as usize]
    };
    (level(true) - level(false)).abs()
}

/// Averages the water's force on each collider over the window from `start` on.
struct ForceWindow {
    start: f64,
    sums: Vec<(sph_core::glam::DVec3, sph_core::glam::DVec3)>,
    evaluations: u64,
    /// The force on each collider as last taken, in or before the window [N].
    last: Vec<Vec3>,
}

impl ForceWindow {
    fn new(start: f64, colliders: usize) -> Self {
        Self {
            start,
            sums: vec![Default::default(); colliders],
            evaluations: 0,
            last: vec![Vec3::ZERO; colliders],
        }
    }

    fn record(&mut self, sim: &mut dyn Simulation) {
        let in_window = sim.time() >= self.start;
        let Some((forces, n)) = sim.take_collider_forces() else {
            return;
        };
        if n > 0 {
            for (last, f) in self.last.iter_mut().zip(&forces) {
                *last = f.force;
            }
        }
        if !in_window || n == 0 {
            return;
        }
        for (sum, f) in self.sums.iter_mut().zip(&forces) {
            sum.0 += f.force.as_dvec3() * n as f64;
            sum.1 += f.torque.as_dvec3() * n as f64;
        }
        self.evaluations += n;
    }

    fn report(&self, colliders: &[crate::scenarios::ScenarioCollider]) -> Vec<ColliderForceReport> {
        if self.evaluations == 0 {
            return Vec::new();
        }
        let n = self.evaluations as f64;
        colliders
            .iter()
            .zip(&self.sums)
            .map(|(c, (f, t))| ColliderForceReport {
                name: c.name.clone(),
                force: (*f / n).as_vec3().to_array(),
                torque: (*t / n).as_vec3().to_array(),
                evaluations: self.evaluations,
            })
            .collect()
    }
}

/// How often a scene file's dynamic and hinged colliders are sampled [s of simulated time].
pub const BODY_SAMPLE_INTERVAL: f64 = 0.05;
/// A body slower than this [m/s] over the last quarter of a run has settled.
pub const SETTLED_SPEED: f32 = 0.02;
/// A body turning slower than this [rad/s] over the last quarter of a run has settled.
pub const SETTLED_TURN_RATE: f32 = 0.05;

/// The poses of a scene file's dynamic and hinged colliders every [`BODY_SAMPLE_INTERVAL`].
struct BodyTrack {
    /// The tracked colliders' indices in `Setup::colliders`.
    bodies: Vec<usize>,
    series: Vec<Vec<BodySample>>,
    next: f64,
}

impl BodyTrack {
    fn new(setup: &Setup) -> Self {
        let bodies: Vec<usize> = setup.extras.as_ref().map_or(Vec::new(), |extras| {
            extras
                .colliders
                .iter()
                .enumerate()
                .filter(|(_, written)| written.body.is_some() || written.hinge.is_some())
                .map(|(k, _)| k)
                .collect()
        });
        Self {
            series: vec![Vec::new(); bodies.len()],
            bodies,
            next: 0.0,
        }
    }

    /// Samples the bodies when the next sample is due, or at the end of the run (`last`) when
    /// the latest sample is older.
    fn record(&mut self, setup: &Setup, sim: &dyn Simulation, forces: &[Vec3], last: bool) {
        let t = sim.time();
        let newest = self.series.first().and_then(|s| s.last()).map(|s| s.t);
        let due = t + 1e-9 >= self.next || (last && newest.is_some_and(|n| n < t));
        if self.bodies.is_empty() || !due {
            return;
        }
        self.next = t + BODY_SAMPLE_INTERVAL;
        let now = sim.colliders_now(&setup.colliders);
        for (series, &k) in self.series.iter_mut().zip(&self.bodies) {
            let pose = now[k].pose;
            let (velocity, turn_rate) = match series.last() {
                Some(last) if t > last.t => {
                    let dt = (t - last.t) as f32;
                    let before = sph_core::glam::Quat::from_array(last.rotation);
                    (
                        (pose.translation - Vec3::from(last.position)) / dt,
                        before.angle_between(pose.rotation) / dt,
                    )
                }
                _ => (Vec3::ZERO, 0.0),
            };
            series.push(BodySample {
                t,
                position: pose.translation.to_array(),
                rotation: pose.rotation.to_array(),
                velocity: velocity.to_array(),
                turn_rate,
                force: forces.get(k).copied().unwrap_or_default().to_array(),
            });
        }
    }
}

/// Where each of a scene file's dynamic and hinged colliders started and where it is now, with
/// its samples and whether it settled.
fn body_motion(setup: &Setup, now: &[sph_core::Collider], track: BodyTrack) -> Vec<BodyMotion> {
    track
        .bodies
        .iter()
        .zip(track.series)
        .map(|(&k, series)| {
            let c = &setup.colliders[k];
            let start = c.at(0.0).pose;
            let end = series.last().map_or(0.0, |s| s.t);
            let last_quarter: Vec<&BodySample> =
                series.iter().filter(|s| s.t >= 0.75 * end).collect();
            let settled = last_quarter.len() >= 2
                && last_quarter.iter().all(|s| {
                    Vec3::from(s.velocity).length() < SETTLED_SPEED
                        && s.turn_rate < SETTLED_TURN_RATE
                });
            BodyMotion {
                name: c.name.clone(),
                start: start.translation.to_array(),
                end: now[k].pose.translation.to_array(),
                turned_rad: start.rotation.angle_between(now[k].pose.rotation),
                settled,
                series,
            }
        })
        .collect()
}

/// The held box's upward force against ρ0 |g| V.
fn buoyancy(setup: &Setup, forces: &[ColliderForceReport]) -> Option<BuoyancyFigures> {
    let c = setup.colliders.first()?;
    let f = forces.first()?;
    let sph_core::boundary::collider::ColliderShape::Cuboid { half_extents } = c.collider.shape
    else {
        return None;
    };
    let p = &setup.scene.params;
    let volume = 8.0 * (half_extents.x * half_extents.y * half_extents.z) as f64;
    let expected = p.rest_density as f64 * p.gravity.length() as f64 * volume;
    let measured = f.force[1] as f64;
    Some(BuoyancyFigures {
        expected_n: expected,
        measured_n: measured,
        error_pct: (measured - expected) / expected * 100.0,
    })
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
            if let Some(extras) = &mut setup.extras {
                extras.bodies = args.bodies;
            }
            setup
        }
        None => configured_setup(args),
    };
    let duration = args.duration().unwrap_or(Duration::Time(setup.duration));
    run_setup(&setup, args.backend, args.substeps, duration, bars)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenarios::{Bodies, Scenario};
    use sph_core::glam::Vec3;

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
                    let report =
                        run_setup(&setup, backend, 10, Duration::Steps(30), &Bars::new(true));
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
        let scene = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../assets/scenes/dam_break.ron");
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
        let scene = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../assets/scenes/aquaplay.ron");
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
            report.particles + report.particles_emitted as usize
                - report.particles_drained as usize,
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
        let scene =
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/scenes/lock.ron");
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
}
