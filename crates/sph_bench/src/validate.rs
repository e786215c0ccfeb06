//! `sph-bench validate`: the Martin & Moyce (1952) dam break against experiment, on the CPU
//! solver. Reports the RMS of the front error Z for T <= 2.5, raw and with the best time shift
//! in [0, 0.3] (the experiments lag because the gate takes time to remove).

use serde::Serialize;
use sph_core::front::surge_front;
use sph_core::glam::Vec3;
use sph_core::scenario::dam_break;
use sph_core::{CpuSolver, Diagnostics};

/// Martin & Moyce's surge front, n² = 2 (copied from the shared validation data, with its source).
const MARTIN_MOYCE: &str = include_str!("../data/martin_moyce_1952_n2.csv");

/// Gravity used for T = t sqrt(2g/a).
const G: f64 = 9.81;

/// Options of `sph-bench validate`.
#[derive(Clone, Debug, PartialEq)]
pub struct ValidateArgs {
    /// Particles in the column (about).
    pub particles: usize,
    /// Column width a [m].
    pub a: f32,
    /// Where the JSON goes.
    pub json: Option<String>,
}

/// The validation report.
#[derive(Clone, Debug, Default, Serialize)]
pub struct ValidateReport {
    /// "dam-break".
    pub scenario: String,
    /// Column width a [m].
    pub column_width_a: f32,
    /// Particles.
    pub particles: usize,
    /// Time step [s].
    pub dt: f32,
    /// [[t, x]]: front position [m] from the wall, every 0.01 s.
    pub front: Vec<[f64; 2]>,
    /// [[T, Z]] with T = t sqrt(2g/a), Z = x/a.
    pub front_nd: Vec<[f64; 2]>,
    /// RMS of Z_sim(T) - Z_exp(T) over the experimental points with T <= 2.5.
    pub rms_z_raw: f64,
    /// The same with the simulation delayed by the best shift in [0, 0.3].
    pub rms_z_shifted: f64,
    /// That shift in T.
    pub best_shift: f64,
    /// "ok" or "unstable".
    pub health: String,
}

/// Parses the experiment: (T, Z) rows after the comment lines and the header.
pub fn experiment() -> Vec<(f64, f64)> {
    MARTIN_MOYCE
        .lines()
        .filter(|l| !l.starts_with('#') && !l.starts_with('T'))
        .filter_map(|l| {
            let (t, z) = l.split_once(',')?;
            Some((t.trim().parse().ok()?, z.trim().parse().ok()?))
        })
        .collect()
}

/// Z of the simulated series at T (linear interpolation; clamped at the ends).
fn interpolate(series: &[[f64; 2]], t: f64) -> f64 {
    match series.iter().position(|p| p[0] >= t) {
        None => series.last().map_or(0.0, |p| p[1]),
        Some(0) => series[0][1],
        Some(k) => {
            let (a, b) = (series[k - 1], series[k]);
            a[1] + (b[1] - a[1]) * (t - a[0]) / (b[0] - a[0])
        }
    }
}

/// RMS of Z_sim(T - shift) - Z_exp(T) over the experimental points with T <= 2.5.
pub fn rms_error(series: &[[f64; 2]], experiment: &[(f64, f64)], shift: f64) -> f64 {
    let errors: Vec<f64> = experiment
        .iter()
        .filter(|(t, _)| *t <= 2.5 + 1e-9)
        .map(|&(t, z)| interpolate(series, (t - shift).max(0.0)) - z)
        .collect();
    (errors.iter().map(|e| e * e).sum::<f64>() / errors.len().max(1) as f64).sqrt()
}

/// Runs the dam break and compares it with the experiment.
pub fn run(args: &ValidateArgs) -> Result<ValidateReport, String> {
    let spacing = args.a / (args.particles.max(1) as f32).cbrt();
    let cells = |length: f32| (length / spacing).round().max(1.0) * spacing;
    let (a, depth) = (cells(args.a), cells(0.5 * args.a));
    let scene = dam_break(a, depth, spacing);
    let n = scene.particle_count();
    let mut solver =
        CpuSolver::new(scene.params, scene.container, n.max(1)).map_err(|e| e.to_string())?;
    solver.spawn(&scene.positions(), Vec3::ZERO);
    let time_scale = (2.0 * G / a as f64).sqrt();
    let t_end = 2.8 / time_scale;
    let link = scene.params.smoothing_radius;
    let mut report = ValidateReport {
        scenario: "dam-break".into(),
        column_width_a: a,
        particles: n,
        dt: scene.params.time_step,
        health: "ok".into(),
        ..Default::default()
    };
    let mut next_sample = 0.0;
    let mut last_progress = 0;
    loop {
        if solver.time() + 1e-9 >= next_sample {
            let positions = &solver.particles().position;
            let x = surge_front(positions, &scene.container, link).unwrap_or(0.0) as f64;
            report.front.push([solver.time(), x]);
            report
                .front_nd
                .push([solver.time() * time_scale, x / a as f64]);
            next_sample += 0.01;
        }
        if solver.time() >= t_end {
            break;
        }
        solver.step();
        let percent = (solver.time() / t_end * 100.0) as u32;
        if percent >= last_progress + 10 {
            last_progress = percent;
            eprintln!("  {percent:3}% (t = {:.3} s)", solver.time());
        }
    }
    let d: Diagnostics = solver.diagnostics();
    if d.non_finite_count > 0 || d.outside_count > 0 {
        report.health = "unstable".into();
    }
    let experiment = experiment();
    report.rms_z_raw = rms_error(&report.front_nd, &experiment, 0.0);
    let (shift, rms) = (0..=30)
        .map(|k| k as f64 * 0.01)
        .map(|s| (s, rms_error(&report.front_nd, &experiment, s)))
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .unwrap_or((0.0, report.rms_z_raw));
    report.best_shift = shift;
    report.rms_z_shifted = rms;
    Ok(report)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn experiment_is_parsed_with_its_first_and_last_points() {
        let e = experiment();
        assert!(e.len() >= 14);
        assert_eq!(e[0], (0.0, 1.0));
        assert!(e.windows(2).all(|w| w[1].0 > w[0].0 && w[1].1 >= w[0].1));
    }

    #[test]
    fn rms_is_zero_for_the_experiment_itself_and_finds_a_known_shift() {
        let e = experiment();
        let series: Vec<[f64; 2]> = e.iter().map(|&(t, z)| [t, z]).collect();
        assert!(rms_error(&series, &e, 0.0) < 1e-12);
        // A series that leads the experiment by 0.2 in T is best matched by a 0.2 shift.
        let leading: Vec<[f64; 2]> = e.iter().map(|&(t, z)| [t - 0.2, z]).collect();
        let best = (0..=30)
            .map(|k| k as f64 * 0.01)
            .min_by(|a, b| rms_error(&leading, &e, *a).total_cmp(&rms_error(&leading, &e, *b)))
            .unwrap();
        assert!((best - 0.2).abs() < 0.011, "best shift {best}");
    }
}
