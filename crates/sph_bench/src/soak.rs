//! `sph-bench soak`: a long run of the dam break (100,000 CPU steps or 10,000 GPU steps of 4,096
//! particles by default) that reports health, the drift of the density error and any particle
//! loss, sampled a hundred times along the way; or, with `--scene FILE`, a scene file for
//! `--time` of simulated time (10 minutes by default) with resident memory and the particles
//! read back from the solver checked every simulated minute. Not part of the test suite.

use crate::args::SoakArgs;
use crate::progress::Bars;
use crate::run::{diagnostics, names, rollback, simulation};
use crate::scenarios::{setup, Scenario, Setup};
use serde::Serialize;

/// The soak report.
#[derive(Clone, Debug, Default, Serialize)]
pub struct SoakReport {
    /// "cpu" or "gpu".
    pub backend: String,
    /// Integrator.
    pub integrator: String,
    /// Particles spawned.
    pub particles: usize,
    /// Steps taken.
    pub steps: u64,
    /// dt [s].
    pub dt: f32,
    /// Simulated time [s].
    pub sim_time: f64,
    /// Wall-clock time [s].
    pub wall_seconds: f64,
    /// "ok" or "unstable".
    pub health: String,
    /// The step detected as unstable (and not rolled back).
    pub unstable_step: Option<u64>,
    /// Unstable steps were rolled back and retried at half the dt (`--rollback on`).
    pub rollback: bool,
    /// Unstable steps rolled back (0 with rollback off).
    pub rollbacks: u64,
    /// The time step in use at the end [s] (after any halving by rollbacks).
    pub dt_last: f32,
    /// Particles spawned minus particles at the end (0: nothing lost).
    pub particles_lost: i64,
    /// NaN particles at the end.
    pub nan_count: usize,
    /// Particles outside the box at the end.
    pub escaped_count: usize,
    /// Mean compression error over the first and the last tenth of the samples [%].
    pub density_error_early_pct: f64,
    /// See `density_error_early_pct`.
    pub density_error_late_pct: f64,
    /// Largest mean compression error sampled [%].
    pub density_error_peak_pct: f32,
    /// [[step, t, mean density error %, max speed, particles]] every steps/100.
    pub samples: Vec<[f64; 5]>,
    /// A scene soak (`--scene`): the file.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub scene_file: Option<String>,
    /// A scene soak: what moved its bodies ("held" or "avian").
    #[serde(skip_serializing_if = "Option::is_none")]
    pub bodies: Option<String>,
    /// A scene soak: [[t, resident memory MiB]] every simulated minute (and at the start).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub resident_mib: Vec<[f64; 2]>,
    /// A scene soak: the growth of resident memory from the first simulated minute to the end
    /// [%].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub resident_growth_after_first_minute_pct: Option<f64>,
    /// A scene soak: the particles read back from the solver (the device on the GPU) every
    /// simulated minute, against initial + emitted − drained, with unique ids: how many checks
    /// ran, and what each failing one found.
    pub balance_checks: u64,
    /// See `balance_checks`.
    pub balance_failures: Vec<String>,
}

impl SoakReport {
    /// An empty report of a soak of `setup` with `particles` at the start.
    fn of(args: &SoakArgs, setup: &Setup, particles: usize) -> Self {
        let p = &setup.scene.params;
        Self {
            backend: args.backend.name().into(),
            integrator: names(p.integrator, p.neighbor_search).0.into(),
            particles,
            dt: p.time_step,
            ..Self::default()
        }
    }
}

/// Resident memory of this process [MiB] (Linux: /proc/self/statm), or `None` elsewhere.
fn resident_mib() -> Option<f64> {
    let statm = std::fs::read_to_string("/proc/self/statm").ok()?;
    let pages: f64 = statm.split_whitespace().nth(1)?.parse().ok()?;
    Some(pages * 4096.0 / (1024.0 * 1024.0))
}

/// The particles read back against what the counters say: `None` when they agree.
fn balance_failure(
    state: &crate::sim::State,
    initial: u64,
    emitted: u64,
    drained: u64,
    t: f64,
) -> Option<String> {
    let expected = initial + emitted - drained;
    let mut ids = state.ids.clone();
    ids.sort_unstable();
    let held = ids.len();
    ids.dedup();
    let spawned = initial + emitted;
    let out_of_range = ids.last().is_some_and(|&top| top as u64 >= spawned);
    (held as u64 != expected || ids.len() != held || out_of_range).then(|| {
        format!(
            "t = {t:.1} s: {held} particles held ({} distinct ids), initial {initial} + emitted              {emitted} - drained {drained} = {expected}{}",
            ids.len(),
            if out_of_range { ", an id never spawned" } else { "" }
        )
    })
}

/// `sph-bench soak --scene FILE`: the scene for `--time` of simulated time, with resident memory
/// and the particles read back every simulated minute.
fn run_scene(args: &SoakArgs, path: &std::path::Path, bars: &Bars) -> Result<SoakReport, String> {
    let mut setup = crate::scene_run::setup_from_file(path)?;
    setup.rollback = rollback(args.rollback);
    if let Some(extras) = &mut setup.extras {
        extras.bodies = args.bodies;
    }
    let mut sim = simulation(&setup, args.backend, args.substeps, bars)?;
    let started = std::time::Instant::now();
    let end = args.time as f64;
    let initial =
        (setup.scene.particle_count() as u64).saturating_sub(sim.spawns_inside_colliders());
    let mut report = SoakReport {
        scene_file: Some(path.display().to_string()),
        bodies: Some(args.bodies.name().into()),
        ..SoakReport::of(args, &setup, initial as usize)
    };
    report.resident_mib.extend(resident_mib().map(|m| [0.0, m]));
    let mut progress = bars.run("soak", (end * 10.0).ceil() as u64);
    let dt = setup.scene.params.time_step as f64;
    let mut next_check = 60.0f64.min(end);
    while sim.time() < end - 1e-9 && sim.unstable_step().is_none() {
        // A simulated second a chunk at most, ending at the next check.
        let until = (sim.time() + 1.0).min(next_check);
        let k = ((until - sim.time()) / dt).ceil().clamp(1.0, 100_000.0) as u32;
        sim.advance(k)?;
        let t = sim.time();
        if t + 1e-9 >= next_check {
            let state = sim.state()?;
            let d = diagnostics(&setup, &state);
            report.samples.push([
                sim.steps() as f64,
                t,
                d.density_error_mean_pct as f64,
                d.max_speed as f64,
                d.particle_count as f64,
            ]);
            report.density_error_peak_pct =
                report.density_error_peak_pct.max(d.density_error_mean_pct);
            let (emitted, drained) = sim.flow_counts();
            report.balance_checks += 1;
            report
                .balance_failures
                .extend(balance_failure(&state, initial, emitted, drained, t));
            report.resident_mib.extend(resident_mib().map(|m| [t, m]));
            next_check = (next_check + 60.0).min(end);
        }
        progress.set(
            (t * 10.0) as u64,
            format!("t = {t:.1} s, {} checks", report.balance_checks),
        );
    }
    progress.finish();
    let (early, late) = density_error_tenths(&report.samples);
    (
        report.density_error_early_pct,
        report.density_error_late_pct,
    ) = (early, late);
    let (emitted, drained) = sim.flow_counts();
    let d = finish(&mut report, sim.as_mut(), &setup, started)?;
    report.particles_lost = (initial + emitted) as i64 - drained as i64 - d.particle_count as i64;
    // From the sample at the first minute (the second) to the last, when there is a later one.
    if let [_, first, .., last] = report.resident_mib[..] {
        report.resident_growth_after_first_minute_pct = Some((last[1] / first[1] - 1.0) * 100.0);
    }
    Ok(report)
}

/// Runs the soak.
pub fn run(args: &SoakArgs, bars: &Bars) -> Result<SoakReport, String> {
    if let Some(path) = &args.scene {
        return run_scene(args, path, bars);
    }
    let setup = Setup {
        rollback: rollback(args.rollback),
        ..setup(Scenario::DamBreak, args.particles, 0.146)
    };
    let mut sim = simulation(&setup, args.backend, args.substeps, bars)?;
    let started = std::time::Instant::now();
    let chunk = (args.steps / 100).max(1);
    let mut progress = bars.run("soak", args.steps);
    let mut report = SoakReport::of(args, &setup, setup.scene.particle_count());
    while sim.steps() < args.steps && sim.unstable_step().is_none() {
        let k = chunk.min(args.steps - sim.steps()) as u32;
        sim.advance(k)?;
        let state = sim.state()?;
        let d = diagnostics(&setup, &state);
        report.samples.push([
            sim.steps() as f64,
            sim.time(),
            d.density_error_mean_pct as f64,
            d.max_speed as f64,
            d.particle_count as f64,
        ]);
        report.density_error_peak_pct = report.density_error_peak_pct.max(d.density_error_mean_pct);
        progress.set(
            sim.steps(),
            format!(
                "step {}, t = {:.2} s, density error {:.3} %",
                sim.steps(),
                sim.time(),
                d.density_error_mean_pct
            ),
        );
    }
    progress.finish();
    let (early, late) = density_error_tenths(&report.samples);
    (
        report.density_error_early_pct,
        report.density_error_late_pct,
    ) = (early, late);
    let d = finish(&mut report, sim.as_mut(), &setup, started)?;
    report.particles_lost = report.particles as i64 - d.particle_count as i64;
    Ok(report)
}

/// The mean density error [%] of the first and the last tenth of the samples.
fn density_error_tenths(samples: &[[f64; 5]]) -> (f64, f64) {
    let tenth = (samples.len() / 10).max(1);
    let mean = |s: &[[f64; 5]]| s.iter().map(|x| x[2]).sum::<f64>() / s.len().max(1) as f64;
    (
        mean(&samples[..tenth.min(samples.len())]),
        mean(&samples[samples.len().saturating_sub(tenth)..]),
    )
}

/// The figures every soak ends with: steps, times, health, rollbacks and the final state's
/// diagnostics (returned for the particle count).
fn finish(
    report: &mut SoakReport,
    sim: &mut dyn crate::sim::Simulation,
    setup: &Setup,
    started: std::time::Instant,
) -> Result<sph_core::Diagnostics, String> {
    let state = sim.state()?;
    let d = diagnostics(setup, &state);
    report.steps = sim.steps();
    report.sim_time = sim.time();
    report.wall_seconds = started.elapsed().as_secs_f64();
    report.unstable_step = sim.unstable_step();
    report.rollback = setup.rollback.enabled;
    report.rollbacks = sim.rollbacks();
    report.dt_last = sim.last_dt();
    report.nan_count = d.non_finite_count;
    report.escaped_count = d.outside_count;
    report.health =
        if report.unstable_step.is_none() && d.non_finite_count == 0 && d.outside_count == 0 {
            "ok"
        } else {
            "unstable"
        }
        .into();
    Ok(d)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenarios::Bodies;

    /// A short scene soak with an emitter and a drain: the particles read back agree with the
    /// counters at every check, and memory is sampled.
    #[test]
    fn a_scene_soak_checks_the_particles_it_reads_back() {
        let scene = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../assets/scenes/aquaplay.ron");
        let args = SoakArgs {
            backend: crate::args::Backend::Cpu,
            steps: 1,
            particles: 1,
            rollback: true,
            substeps: 4,
            scene: Some(scene),
            bodies: Bodies::Held,
            time: 0.3,
            json: None,
        };
        let report = run(&args, &Bars::new(true)).unwrap();
        assert_eq!(report.health, "ok");
        assert!(report.sim_time >= 0.3 - 1e-6, "{}", report.sim_time);
        assert_eq!(report.balance_checks, 1);
        assert_eq!(report.balance_failures, Vec::<String>::new());
        assert_eq!(report.particles_lost, 0);
        assert_eq!(report.resident_mib.len(), 2, "{:?}", report.resident_mib);
        assert_eq!(report.resident_growth_after_first_minute_pct, None);
        // A lost particle is seen.
        let mut state = crate::sim::State {
            ids: (0..10).collect(),
            ..Default::default()
        };
        assert_eq!(balance_failure(&state, 10, 0, 0, 1.0), None);
        state.ids[3] = 4;
        assert!(balance_failure(&state, 10, 0, 0, 1.0).is_some());
        state.ids.pop();
        assert!(balance_failure(&state, 10, 0, 0, 1.0).is_some());
    }
}
