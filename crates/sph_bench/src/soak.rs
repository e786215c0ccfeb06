//! `sph-bench soak`: a long run of the dam break (100,000 CPU steps or 10,000 GPU steps of 4,096
//! particles by default) that reports health, the drift of the density error and any particle
//! loss, sampled a hundred times along the way. Not part of the test suite.

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
}

/// Runs the soak.
pub fn run(args: &SoakArgs, bars: &Bars) -> Result<SoakReport, String> {
    let setup = Setup {
        rollback: rollback(args.rollback),
        ..setup(Scenario::DamBreak, args.particles, 0.146)
    };
    let mut sim = simulation(&setup, args.backend, args.substeps, bars)?;
    let started = std::time::Instant::now();
    let chunk = (args.steps / 100).max(1);
    let mut progress = bars.run("soak", args.steps);
    let mut report = SoakReport {
        backend: args.backend.name().into(),
        integrator: names(
            setup.scene.params.integrator,
            setup.scene.params.neighbor_search,
        )
        .0
        .into(),
        particles: setup.scene.particle_count(),
        dt: setup.scene.params.time_step,
        ..Default::default()
    };
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
    let state = sim.state()?;
    let d = diagnostics(&setup, &state);
    let tenth = (report.samples.len() / 10).max(1);
    let mean = |s: &[[f64; 5]]| s.iter().map(|x| x[2]).sum::<f64>() / s.len().max(1) as f64;
    report.density_error_early_pct = mean(&report.samples[..tenth.min(report.samples.len())]);
    report.density_error_late_pct =
        mean(&report.samples[report.samples.len().saturating_sub(tenth)..]);
    report.steps = sim.steps();
    report.sim_time = sim.time();
    report.wall_seconds = started.elapsed().as_secs_f64();
    report.unstable_step = sim.unstable_step();
    report.rollback = setup.rollback.enabled;
    report.rollbacks = sim.rollbacks();
    report.dt_last = sim.last_dt();
    report.nan_count = d.non_finite_count;
    report.escaped_count = d.outside_count;
    report.particles_lost = report.particles as i64 - d.particle_count as i64;
    report.health =
        if report.unstable_step.is_none() && d.non_finite_count == 0 && d.outside_count == 0 {
            "ok"
        } else {
            "unstable"
        }
        .into();
    Ok(report)
}
