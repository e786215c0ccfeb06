//! A U-tube of square section on a Δx = 0.01 m lattice: two legs [`LEG`] wide joined under a
//! divider [`DIVIDER`] thick by a channel [`CHANNEL`] high, all [`DEPTH`] deep. The water
//! starts [`AMPLITUDE`] above its rest level [`REST_LEVEL`] in the left leg and as much below it
//! in the right, and oscillates. Without friction the column of length L along the tube's centre
//! line, L = 2 (h0 - w/2) + a + d (legs from the surface to the channel's middle, then across),
//! swings with the period T = 2π √(L / 2g) (any fluid-mechanics text: the U-tube manometer);
//! here L = 0.7 m and T = 1.187 s at g = 9.81.
//!
//! Each leg's level is read from the water it holds above the channel, N Δx³ / (a D) (so a
//! splash does not move it), and the period from the zero crossings of their difference.

use serde::Serialize;
use sph_core::glam::Vec3;

/// The lattice spacing Δx [m].
pub const SPACING: f32 = 0.01;
/// Width of each leg a [m].
pub const LEG: f32 = 0.1;
/// Thickness of the divider between the legs d [m].
pub const DIVIDER: f32 = 0.1;
/// Height of the channel under the divider w [m].
pub const CHANNEL: f32 = 0.1;
/// Depth of the tube (z) D [m].
pub const DEPTH: f32 = 0.1;
/// The level at rest h0 [m].
pub const REST_LEVEL: f32 = 0.3;
/// The left leg starts this much above the rest level, the right one as much below [m].
pub const AMPLITUDE: f32 = 0.05;
/// Height of the container [m].
pub const HEIGHT: f32 = 0.5;
/// Simulated time of a run [s]: about two and a half periods.
pub const DURATION: f64 = 3.0;

/// The length of the water column along the tube's centre line, L = 2 (h0 - w/2) + a + d [m].
pub fn column_length() -> f64 {
    (2.0 * (REST_LEVEL - 0.5 * CHANNEL) + LEG + DIVIDER) as f64
}

/// The frictionless period T = 2π √(L / 2g) [s] under gravity `g` [m/s²].
pub fn textbook_period(g: f64) -> f64 {
    std::f64::consts::TAU * (column_length() / (2.0 * g)).sqrt()
}

/// The tube's inner width along x, 2a + d [m].
pub fn width() -> f32 {
    2.0 * LEG + DIVIDER
}

/// Each leg's level above the floor [m]: the channel's height plus the volume of the particles
/// above the channel in that leg over the leg's section.
pub fn leg_levels(positions: &[Vec3]) -> (f64, f64) {
    let volume = (SPACING as f64).powi(3);
    let section = (LEG * DEPTH) as f64;
    let (mut left, mut right) = (0usize, 0usize);
    for x in positions.iter().filter(|x| x.y > CHANNEL) {
        if x.x < LEG {
            left += 1;
        } else if x.x > LEG + DIVIDER {
            right += 1;
        }
    }
    let level = |n: usize| CHANNEL as f64 + n as f64 * volume / section;
    (level(left), level(right))
}

/// The level difference (left - right) over time, sampled while the run goes.
#[derive(Clone, Debug, Default)]
pub struct UTubeSampler {
    series: Vec<[f64; 2]>,
}

impl UTubeSampler {
    /// Records the legs' level difference at `time`.
    pub fn record(&mut self, time: f64, positions: &[Vec3]) {
        let (left, right) = leg_levels(positions);
        self.series.push([time, left - right]);
    }

    /// The figures of the run under gravity `g`.
    pub fn finish(self, g: f64) -> UTubeFigures {
        let textbook = textbook_period(g);
        let swing = oscillation(&self.series, 0.2 * 2.0 * AMPLITUDE as f64);
        let period = swing.as_ref().map(|s| s.period);
        UTubeFigures {
            column_length_m: column_length(),
            textbook_period_s: textbook,
            period_s: period,
            period_error_pct: period.map(|p| 100.0 * (p / textbook - 1.0)),
            zero_crossings: swing.as_ref().map_or(0, |s| s.crossings),
            first_swing_m: swing.as_ref().map(|s| s.first_swing),
            last_swing_m: swing.as_ref().map(|s| s.last_swing),
            level_difference: self.series,
        }
    }
}

/// What the U-tube measured.
#[derive(Clone, Debug, Default, Serialize)]
pub struct UTubeFigures {
    /// The column's length L along the centre line [m].
    pub column_length_m: f64,
    /// The frictionless period 2π √(L / 2g) [s].
    pub textbook_period_s: f64,
    /// The measured period [s]: twice the mean time between zero crossings of the level
    /// difference (none with fewer than two crossings: the oscillation died out).
    pub period_s: Option<f64>,
    /// (measured / textbook - 1) [%].
    pub period_error_pct: Option<f64>,
    /// Zero crossings of the level difference in the run.
    pub zero_crossings: usize,
    /// The largest |level difference| between the first two crossings [m].
    pub first_swing_m: Option<f64>,
    /// The largest |level difference| between the last two crossings [m].
    pub last_swing_m: Option<f64>,
    /// (t [s], left level - right level [m]) every sample.
    pub level_difference: Vec<[f64; 2]>,
}

/// An oscillation read from its zero crossings.
#[derive(Clone, Debug, PartialEq)]
pub struct Oscillation {
    /// Twice the mean time between crossings [s].
    pub period: f64,
    /// Crossings counted.
    pub crossings: usize,
    /// The largest |value| between the first two crossings.
    pub first_swing: f64,
    /// The largest |value| between the last two crossings.
    pub last_swing: f64,
}

/// The period of the signal `series` (t, value) about zero, from the times (interpolated) where
/// it changes sign. A crossing counts only once the signal has been at least `hysteresis` away
/// from zero on the other side, so that noise near zero does not add crossings. `None` with
/// fewer than two crossings.
pub fn oscillation(series: &[[f64; 2]], hysteresis: f64) -> Option<Oscillation> {
    let mut crossings: Vec<(f64, usize)> = Vec::new();
    let mut side = 0.0f64;
    for (k, w) in series.windows(2).enumerate() {
        let ([t0, v0], [t1, v1]) = (w[0], w[1]);
        if side == 0.0 {
            if v0.abs() >= hysteresis {
                side = v0.signum();
            }
            continue;
        }
        if v1.signum() == -side && v0.signum() != v1.signum() {
            let t = if v1 != v0 {
                t0 + (t1 - t0) * v0 / (v0 - v1)
            } else {
                t0
            };
            crossings.push((t, k + 1));
            side = 0.0;
        }
    }
    if crossings.len() < 2 {
        return None;
    }
    let swing = |a: usize, b: usize| series[a..b].iter().map(|p| p[1].abs()).fold(0.0, f64::max);
    let n = crossings.len();
    Some(Oscillation {
        period: 2.0 * (crossings[n - 1].0 - crossings[0].0) / (n - 1) as f64,
        crossings: n,
        first_swing: swing(crossings[0].1, crossings[1].1),
        last_swing: swing(crossings[n - 2].1, crossings[n - 1].1),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn damped(period: f64, decay: f64, noise: f64) -> Vec<[f64; 2]> {
        (0..300)
            .map(|k| {
                let t = 0.01 * k as f64;
                let jitter = noise * if k % 2 == 0 { 1.0 } else { -1.0 };
                let v = 0.1 * (-decay * t).exp() * (std::f64::consts::TAU * t / period).cos();
                [t, v + jitter]
            })
            .collect()
    }

    #[test]
    fn a_damped_cosine_gives_its_period_and_its_decay() {
        let o = oscillation(&damped(1.2, 0.3, 0.0), 0.02).unwrap();
        assert!((o.period - 1.2).abs() < 0.005, "{o:?}");
        assert_eq!(o.crossings, 5);
        assert!(o.last_swing < 0.6 * o.first_swing, "{o:?}");
    }

    #[test]
    fn noise_near_zero_adds_no_crossing_and_a_dead_signal_has_no_period() {
        let o = oscillation(&damped(1.2, 0.0, 0.004), 0.02).unwrap();
        assert_eq!(o.crossings, 5, "{o:?}");
        assert!((o.period - 1.2).abs() < 0.01, "{o:?}");
        // Decays to nothing before it crosses twice.
        assert_eq!(oscillation(&damped(1.2, 20.0, 0.0), 0.02), None);
    }

    #[test]
    fn the_legs_read_the_water_above_the_channel() {
        // A full lattice to 0.35 m in the left leg, 0.25 m in the right.
        let mut positions = Vec::new();
        for (x0, top) in [(0.0f32, 0.35f32), (LEG + DIVIDER, 0.25)] {
            for i in 0..10 {
                for j in 0..((top / SPACING).round() as usize) {
                    for k in 0..10 {
                        let at = |n: usize| (n as f32 + 0.5) * SPACING;
                        positions.push(Vec3::new(x0 + at(i), at(j), at(k)));
                    }
                }
            }
        }
        let (left, right) = leg_levels(&positions);
        assert!((left - 0.35).abs() < 1e-6 && (right - 0.25).abs() < 1e-6);
        assert!((textbook_period(9.81) - 1.187).abs() < 0.001);
    }
}
