//! Martin & Moyce (1952): the dam break's surge front in the experiment, and the RMS of a
//! simulated front against it (for T <= 2.5, raw and with the best time shift in [0, 0.3]: the
//! experiments lag because the gate takes time to remove).

/// Martin & Moyce's surge front, n² = 2 (copied from the shared validation data, with its source).
const MARTIN_MOYCE: &str = include_str!("../data/martin_moyce_1952_n2.csv");

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

/// (raw RMS, RMS at the best shift, best shift) with shifts 0, 0.01, ..., 0.3.
pub fn rms_error_and_best_shift(series: &[[f64; 2]], experiment: &[(f64, f64)]) -> (f64, f64, f64) {
    let raw = rms_error(series, experiment, 0.0);
    let (shift, shifted) = (0..=30)
        .map(|k| k as f64 * 0.01)
        .map(|s| (s, rms_error(series, experiment, s)))
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .unwrap_or((0.0, raw));
    (raw, shifted, shift)
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
        let (raw, shifted, best) = rms_error_and_best_shift(&leading, &e);
        assert!((best - 0.2).abs() < 0.011, "best shift {best}");
        assert!(shifted < 0.02 && raw > 0.05, "raw {raw}, shifted {shifted}");
    }
}
