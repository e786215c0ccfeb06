//! A tank empties through a slot under a sluice, on a Δx = 0.01 m lattice: water [`HEAD`] deep
//! stands on a table [`TABLE_HEIGHT`] high and [`TANK_LENGTH`] long, [`DEPTH`] deep (z), behind
//! a divider [`DIVIDER`] thick whose lower edge leaves a slot [`SLOT`] high over the table. The
//! jet falls into the basin below the table, so the outflow is free. The textbook discharge
//! through a sharp-edged opening is Q = Cd b W √(2 g H), Cd = [`TEXTBOOK_CD`] (the contraction
//! of the jet), H the depth upstream.
//!
//! The tank's volume is read from the particles above the table behind the divider, N Δx³; the
//! measured Cd is the volume that left over the window [`WINDOW`] against ∫ b W √(2 g H) dt
//! over the same samples, H = volume / (tank length × depth).

use serde::Serialize;
use sph_core::glam::Vec3;

/// The lattice spacing Δx [m].
pub const SPACING: f32 = 0.01;
/// The water's depth on the table at the start, H0 [m].
pub const HEAD: f32 = 0.3;
/// Height of the table the tank stands on [m].
pub const TABLE_HEIGHT: f32 = 0.3;
/// Length of the tank behind the divider [m].
pub const TANK_LENGTH: f32 = 0.49;
/// Thickness of the divider [m] (it ends where the table ends).
pub const DIVIDER: f32 = 0.03;
/// Height of the slot between the table and the divider's lower edge, b [m].
pub const SLOT: f32 = 0.04;
/// Depth of the tank (z), the slot's width W [m].
pub const DEPTH: f32 = 0.05;
/// Length of the container (x) [m]: the basin below takes the jet.
pub const LENGTH: f32 = 1.0;
/// Height of the container [m].
pub const HEIGHT: f32 = 0.7;
/// Simulated time of a run [s].
pub const DURATION: f64 = 1.0;
/// The measurement's window [s]: after the jet has formed, while H ≫ b.
pub const WINDOW: (f64, f64) = (0.2, 0.8);
/// The discharge coefficient of a sharp-edged opening with free outflow.
pub const TEXTBOOK_CD: f64 = 0.61;

/// The volume in the tank [m³]: the particles above the table behind the divider.
pub fn tank_volume(positions: &[Vec3]) -> f64 {
    let n = positions
        .iter()
        .filter(|x| x.x < TANK_LENGTH && x.y > TABLE_HEIGHT)
        .count();
    n as f64 * (SPACING as f64).powi(3)
}

/// The tank's volume over time, sampled while the run goes.
#[derive(Clone, Debug, Default)]
pub struct OrificeSampler {
    series: Vec<[f64; 2]>,
}

impl OrificeSampler {
    /// Records the tank's volume at `time`.
    pub fn record(&mut self, time: f64, positions: &[Vec3]) {
        self.series.push([time, tank_volume(positions)]);
    }

    /// The figures of the run under gravity `g`.
    pub fn finish(self, g: f64) -> OrificeFigures {
        let cd = discharge_coefficient(&self.series, g, WINDOW);
        OrificeFigures {
            textbook_cd: TEXTBOOK_CD,
            discharge_coefficient: cd,
            discharge_error_pct: cd.map(|cd| 100.0 * (cd / TEXTBOOK_CD - 1.0)),
            window_s: [WINDOW.0, WINDOW.1],
            tank_volume: self.series,
        }
    }
}

/// What the sluice measured.
#[derive(Clone, Debug, Default, Serialize)]
pub struct OrificeFigures {
    /// Cd of a sharp-edged opening with free outflow.
    pub textbook_cd: f64,
    /// The measured Cd: the volume that left over the window against ∫ b W √(2 g H) dt (none
    /// when the run did not cover the window).
    pub discharge_coefficient: Option<f64>,
    /// (measured / textbook - 1) [%].
    pub discharge_error_pct: Option<f64>,
    /// The window [s].
    pub window_s: [f64; 2],
    /// (t [s], the tank's volume [m³]) every sample.
    pub tank_volume: Vec<[f64; 2]>,
}

/// Cd from the samples (t, volume) within `window`: (V(start) - V(end)) over the trapezoidal
/// ∫ b W √(2 g H) dt, H = V / (tank length × depth). `None` without two samples in the window
/// or without an outflow to compare with.
pub fn discharge_coefficient(series: &[[f64; 2]], g: f64, window: (f64, f64)) -> Option<f64> {
    let inside: Vec<[f64; 2]> = series
        .iter()
        .copied()
        .filter(|p| p[0] >= window.0 - 1e-9 && p[0] <= window.1 + 1e-9)
        .collect();
    let (first, last) = (inside.first()?, inside.last()?);
    if inside.len() < 2 {
        return None;
    }
    let area = (TANK_LENGTH * DEPTH) as f64;
    let slot = (SLOT * DEPTH) as f64;
    let ideal = |v: f64| slot * (2.0 * g * (v / area).max(0.0)).sqrt();
    let integral: f64 = inside
        .windows(2)
        .map(|w| 0.5 * (ideal(w[0][1]) + ideal(w[1][1])) * (w[1][0] - w[0][0]))
        .sum();
    (integral > 0.0).then(|| (first[1] - last[1]) / integral)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Torricelli's draining tank: dV/dt = -Cd b W √(2 g V / A) has √V falling linearly.
    #[test]
    fn a_tank_draining_by_torricelli_gives_its_coefficient_back() {
        let (g, cd) = (9.81, 0.55);
        let area = (TANK_LENGTH * DEPTH) as f64;
        let k = cd * (SLOT * DEPTH) as f64 * (2.0 * g / area).sqrt();
        let v0 = area * HEAD as f64;
        let series: Vec<[f64; 2]> = (0..=100)
            .map(|i| {
                let t = 0.01 * i as f64;
                let root = v0.sqrt() - 0.5 * k * t;
                [t, root * root]
            })
            .collect();
        let measured = discharge_coefficient(&series, g, WINDOW).unwrap();
        assert!((measured - cd).abs() < 1e-3, "{measured}");
        // Nothing flows out: no coefficient to speak of.
        let still: Vec<[f64; 2]> = series.iter().map(|p| [p[0], v0]).collect();
        assert_eq!(discharge_coefficient(&still, g, WINDOW), Some(0.0));
        assert_eq!(discharge_coefficient(&series[..10], g, WINDOW), None);
    }

    #[test]
    fn the_tank_counts_the_water_above_the_table_behind_the_divider() {
        let volume = (SPACING as f64).powi(3);
        let positions = [
            Vec3::new(0.1, TABLE_HEIGHT + 0.005, 0.02),
            Vec3::new(0.3, TABLE_HEIGHT + 0.2, 0.02),
            // Under the divider, in the jet, in the basin below.
            Vec3::new(TANK_LENGTH + 0.01, TABLE_HEIGHT + 0.01, 0.02),
            Vec3::new(0.7, 0.4, 0.02),
            Vec3::new(0.2, 0.1, 0.02),
        ];
        assert!((tank_volume(&positions) - 2.0 * volume).abs() < 1e-12);
    }
}
