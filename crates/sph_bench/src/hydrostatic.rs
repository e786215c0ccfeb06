//! The hydrostatic tank: pressure against ρ0 g depth, layer by layer, averaged over the last 40 %
//! of the run (the column's acoustic oscillation averages out), for every particle (the walls
//! are Akinci 2012 boundary samples, so the particles next to them count too). Depth is measured from the
//! water's initial surface (weak compressibility changes the height by the density error, well
//! under 1 %), so a splashing particle cannot move the reference.

use crate::report::{HydrostaticFigures, Layer};
use crate::scenarios::Setup;
use crate::sim::State;
use sph_core::SphParams;

/// The hydrostatic issue's largest speed at the end of a tank at rest [m/s].
pub const TANK_MAX_SPEED: f64 = 0.05;

/// Accumulates layer pressures over the averaging window.
pub struct HydrostaticSampler {
    start: f64,
    spacing: f32,
    surface: f32,
    margin: f32,
    /// Per layer: Σ depth, Σ pressure, count.
    sums: Vec<(f64, f64, u64)>,
    density_error_sum: f64,
    density_samples: u64,
    /// Σ of each sample's largest speed, and the samples above [`TANK_MAX_SPEED`].
    speed_max_sum: f64,
    speed_max_over: u64,
}

impl HydrostaticSampler {
    /// A sampler for the tank of `setup`.
    pub fn new(setup: &Setup) -> Self {
        let p = &setup.scene.params;
        Self {
            start: 0.6 * setup.duration,
            spacing: p.spacing(),
            surface: setup.scene.container.min().y + setup.water_depth.unwrap_or(0.0),
            margin: 0.0,
            sums: Vec::new(),
            density_error_sum: 0.0,
            density_samples: 0,
            speed_max_sum: 0.0,
            speed_max_over: 0,
        }
    }

    /// Adds the state at `time` (ignored before the window).
    pub fn record(&mut self, setup: &Setup, time: f64, state: &State) {
        if time < self.start || state.positions.is_empty() {
            return;
        }
        let params = &setup.scene.params;
        let (lo, hi) = (setup.scene.container.min(), setup.scene.container.max());
        let surface = self.surface;
        let mut error = 0.0;
        for (k, (x, &rho)) in state.positions.iter().zip(&state.densities).enumerate() {
            error += ((rho / params.rest_density - 1.0).max(0.0) * 100.0) as f64;
            let interior = x.x - lo.x >= self.margin
                && hi.x - x.x >= self.margin
                && x.z - lo.z >= self.margin
                && hi.z - x.z >= self.margin;
            if !interior {
                continue;
            }
            let depth = surface - x.y;
            let layer = (depth / self.spacing).floor().max(0.0) as usize;
            if self.sums.len() <= layer {
                self.sums.resize(layer + 1, (0.0, 0.0, 0));
            }
            let s = &mut self.sums[layer];
            s.0 += depth as f64;
            s.1 += state.pressures[k] as f64;
            s.2 += 1;
        }
        self.density_error_sum += error / state.positions.len() as f64;
        self.density_samples += 1;
        let speed_max = state
            .velocities
            .iter()
            .map(|v| v.length() as f64)
            .fold(0.0, f64::max);
        self.speed_max_sum += speed_max;
        self.speed_max_over += (speed_max > TANK_MAX_SPEED) as u64;
    }

    /// The figures.
    pub fn finish(self, params: &SphParams) -> HydrostaticFigures {
        let layers: Vec<Layer> = self
            .sums
            .iter()
            .filter(|s| s.2 > 0)
            .map(|&(depth, pressure, n)| {
                let (depth, pressure) = (depth / n as f64, pressure / n as f64);
                let expected = params.rest_density as f64 * params.gravity.length() as f64 * depth;
                Layer {
                    depth,
                    pressure,
                    expected,
                    error_pct: (pressure - expected) / expected * 100.0,
                }
            })
            .collect();
        let below: Vec<f64> = layers.iter().skip(1).map(|l| l.error_pct.abs()).collect();
        let samples = self.density_samples.max(1) as f64;
        HydrostaticFigures {
            speed_max_window_mean: self.speed_max_sum / samples,
            speed_max_window_over_pct: self.speed_max_over as f64 / samples * 100.0,
            max_error_below_top_pct: below.iter().copied().fold(0.0, f64::max),
            mean_error_below_top_pct: below.iter().sum::<f64>() / below.len().max(1) as f64,
            density_error_mean_pct: self.density_error_sum / samples,
            layers,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenarios::{setup, Scenario};
    use sph_core::glam::Vec3;

    /// A tank state with every particle at rest but one moving at `speed`.
    fn state(setup: &Setup, speed: f32) -> State {
        let positions = setup.scene.positions();
        let n = positions.len();
        let mut velocities = vec![Vec3::ZERO; n];
        velocities[n / 2] = Vec3::new(0.0, 0.0, speed);
        State {
            positions,
            velocities,
            densities: vec![setup.scene.params.rest_density; n],
            pressures: vec![0.0; n],
        }
    }

    #[test]
    fn the_window_reports_the_largest_speed_of_every_sample() {
        let setup = setup(Scenario::Hydrostatic, 1000, 0.0);
        let mut sampler = HydrostaticSampler::new(&setup);
        let late = setup.duration;
        // Before the window: ignored.
        sampler.record(&setup, 0.0, &state(&setup, 1.0));
        sampler.record(&setup, late, &state(&setup, 0.1));
        sampler.record(&setup, late, &state(&setup, 0.02));
        let figures = sampler.finish(&setup.scene.params);
        assert!((figures.speed_max_window_mean - 0.06).abs() < 1e-6);
        assert_eq!(figures.speed_max_window_over_pct, 50.0);
    }
}
