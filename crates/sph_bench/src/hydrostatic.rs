//! The hydrostatic tank: pressure against ρ0 g depth, layer by layer, averaged over the last 40 %
//! of the run (the column's acoustic oscillation averages out), for every particle (the walls
//! are Akinci 2012 boundary samples, so the particles next to them count too).
//!
//! The depth is the weight depth: the weight of the water above a particle per unit floor area,
//! over ρ0 g. A column at rest carries that (p(y) = g ∫ ρ dy, and mass is conserved), however
//! much it has settled. Each particle counts as a slab one spacing thick: a particle a spacing or
//! more above counts whole, the particle itself half, so the lattice's jitter does not split a
//! row. Layers are binned by weight depth too. The derived particle mass is ρ0 Δx³ / 1.0098
//! (`SphParams::from_spacing`), so a spacing of water weighs 1 % under ρ0 g Δx.
//!
//! Measured from the initial surface with the particle's current height instead (the first
//! reference, kept as `error_vs_initial_surface_pct`), the top rows read deeper than they are:
//! in `validate`'s 0.2 m tank the second row stands 1.6 mm under its initial place (10 % of its
//! depth) and the top row 2.0 mm (the wall rows sit closer to the side walls than Δx/2, so the
//! column is wider and lower), and binning by that depth put some of the top row's particles
//! with the row under it. The weight depth is exact for a tank with nothing in
//! it; with a body in the water (the buoyancy scenario) the layers below the body's top read
//! shallow by the body's volume over the floor area.

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
    /// A particle's volume over the floor area [m]: the weight depth of one particle.
    depth_per_particle: f64,
    /// Per layer: Σ weight depth, Σ pressure, count, Σ depth below the initial surface.
    sums: Vec<LayerSums>,
    density_error_sum: f64,
    density_samples: u64,
    /// Σ of each sample's mean speed.
    speed_mean_sum: f64,
    /// Σ of each sample's largest speed, and the samples above [`TANK_MAX_SPEED`].
    speed_max_sum: f64,
    speed_max_over: u64,
}

impl HydrostaticSampler {
    /// A sampler for the tank of `setup` in a run that ends at `end` [s] (`setup.duration`, or
    /// the command line's `--time`): the window is the run's last 40 %.
    pub fn new(setup: &Setup, end: f64) -> Self {
        let p = &setup.scene.params;
        Self {
            start: 0.6 * end,
            spacing: p.spacing(),
            surface: setup.scene.container.min().y + setup.water_depth.unwrap_or(0.0),
            depth_per_particle: {
                let (lo, hi) = (setup.scene.container.min(), setup.scene.container.max());
                let floor_area = ((hi.x - lo.x) * (hi.z - lo.z)) as f64;
                (p.particle_mass / p.rest_density) as f64 / floor_area
            },
            sums: Vec::new(),
            density_error_sum: 0.0,
            density_samples: 0,
            speed_mean_sum: 0.0,
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
        let heights = SortedHeights::new(&state.positions);
        let mut error = 0.0;
        for (k, (x, &rho)) in state.positions.iter().zip(&state.densities).enumerate() {
            error += ((rho / params.rest_density - 1.0).max(0.0) * 100.0) as f64;
            let depth = heights.particles_above(x.y, self.spacing) * self.depth_per_particle;
            let layer = (depth / self.spacing as f64).floor().max(0.0) as usize;
            if self.sums.len() <= layer {
                self.sums.resize(layer + 1, LayerSums::default());
            }
            let s = &mut self.sums[layer];
            s.depth += depth;
            s.pressure += state.pressures[k] as f64;
            s.count += 1;
            s.depth_below_initial_surface += (self.surface - x.y) as f64;
        }
        self.density_error_sum += error / state.positions.len() as f64;
        self.density_samples += 1;
        let speed_max = state
            .velocities
            .iter()
            .map(|v| v.length() as f64)
            .fold(0.0, f64::max);
        let speed_sum: f64 = state.velocities.iter().map(|v| v.length() as f64).sum();
        self.speed_mean_sum += speed_sum / state.velocities.len() as f64;
        self.speed_max_sum += speed_max;
        self.speed_max_over += (speed_max > TANK_MAX_SPEED) as u64;
    }

    /// The figures.
    pub fn finish(self, params: &SphParams) -> HydrostaticFigures {
        let rho_g = params.rest_density as f64 * params.gravity.length() as f64;
        let layers: Vec<Layer> = self
            .sums
            .iter()
            .filter(|s| s.count > 0)
            .map(|s| {
                let n = s.count as f64;
                let (depth, pressure) = (s.depth / n, s.pressure / n);
                let depth_below_initial_surface = s.depth_below_initial_surface / n;
                let expected = rho_g * depth;
                let at_initial_surface = rho_g * depth_below_initial_surface;
                Layer {
                    depth,
                    pressure,
                    expected,
                    error_pct: (pressure - expected) / expected * 100.0,
                    depth_below_initial_surface,
                    error_vs_initial_surface_pct: (pressure - at_initial_surface)
                        / at_initial_surface
                        * 100.0,
                }
            })
            .collect();
        let below: Vec<f64> = layers.iter().skip(1).map(|l| l.error_pct.abs()).collect();
        let below_initial_surface = layers
            .iter()
            .skip(1)
            .map(|l| l.error_vs_initial_surface_pct.abs());
        let samples = self.density_samples.max(1) as f64;
        HydrostaticFigures {
            speed_mean_window_mean: self.speed_mean_sum / samples,
            speed_max_window_mean: self.speed_max_sum / samples,
            speed_max_window_over_pct: self.speed_max_over as f64 / samples * 100.0,
            max_error_below_top_pct: below.iter().copied().fold(0.0, f64::max),
            mean_error_below_top_pct: below.iter().sum::<f64>() / below.len().max(1) as f64,
            max_error_vs_initial_surface_pct: below_initial_surface.fold(0.0, f64::max),
            density_error_mean_pct: self.density_error_sum / samples,
            layers,
            // The run fills these in from the walls' force.
            walls_force_n: None,
            walls_weight_error_pct: None,
        }
    }
}

/// One layer's running sums.
#[derive(Clone, Copy, Default)]
struct LayerSums {
    depth: f64,
    pressure: f64,
    count: u64,
    depth_below_initial_surface: f64,
}

/// The particles' heights, sorted, with their running sums: how much of the water lies above a
/// height, in O(log n).
struct SortedHeights {
    heights: Vec<f64>,
    /// `prefix[k]` = Σ of the first k heights.
    prefix: Vec<f64>,
}

impl SortedHeights {
    fn new(positions: &[sph_core::glam::Vec3]) -> Self {
        let mut heights: Vec<f64> = positions.iter().map(|x| x.y as f64).collect();
        heights.sort_by(f64::total_cmp);
        let mut prefix = Vec::with_capacity(heights.len() + 1);
        prefix.push(0.0);
        for &y in &heights {
            prefix.push(prefix.last().copied().unwrap_or(0.0) + y);
        }
        Self { heights, prefix }
    }

    /// Σ_j clamp((y_j − y) / s + 1/2, 0, 1): every particle a slab of thickness `s`, counted by
    /// the share of it above `y` (a particle at `y` counts half).
    fn particles_above(&self, y: f32, s: f32) -> f64 {
        let (y, s) = (y as f64, s as f64);
        let lo = self.heights.partition_point(|&h| h <= y - 0.5 * s);
        let hi = self.heights.partition_point(|&h| h < y + 0.5 * s);
        let whole = (self.heights.len() - hi) as f64;
        let k = (hi - lo) as f64;
        let partial = (self.prefix[hi] - self.prefix[lo] - k * y) / s + 0.5 * k;
        whole + partial
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
            ids: (0..n as u32).collect(),
        }
    }

    /// The tank's lattice at rest, the row k (from the top) `settle(k)` below its place, each
    /// particle at its row's exact hydrostatic pressure (the weight above it).
    fn lattice(setup: &Setup, settle: impl Fn(usize) -> f32) -> State {
        let mut state = state(setup, 0.0);
        let p = &setup.scene.params;
        let (spacing, top) = (p.spacing(), setup.water_depth.unwrap_or(0.0));
        for (x, pressure) in state.positions.iter_mut().zip(&mut state.pressures) {
            let row = ((top - x.y) / spacing).floor() as usize;
            *pressure = p.rest_density * p.gravity.length() * weight_depth(setup, row) as f32;
            x.y -= settle(row);
        }
        state
    }

    /// The weight depth of the lattice's row k: k + 1/2 rows of particles of mass m on the
    /// spacing² each, over ρ0 (m = ρ0 Δx³ / 1.0098, so a spacing of water weighs 1 % under
    /// ρ0 g Δx).
    fn weight_depth(setup: &Setup, row: usize) -> f64 {
        let p = &setup.scene.params;
        let area = p.spacing() as f64 * p.spacing() as f64;
        (row as f64 + 0.5) * (p.particle_mass / p.rest_density) as f64 / area
    }

    #[test]
    fn a_settled_column_reads_its_weight_not_its_height() {
        let setup = setup(Scenario::Hydrostatic, 1000, 0.0);
        let spacing = setup.scene.params.spacing();
        // At rest on the lattice both depths agree and every layer is exact.
        let mut sampler = HydrostaticSampler::new(&setup, setup.duration);
        sampler.record(&setup, setup.duration, &lattice(&setup, |_| 0.0));
        let exact = sampler.finish(&setup.scene.params);
        assert_eq!(exact.layers.len(), 10);
        for (k, layer) in exact.layers.iter().enumerate() {
            let due = weight_depth(&setup, k);
            assert!(
                (layer.depth - due).abs() < 1e-6,
                "layer {k}: {}",
                layer.depth
            );
            assert!(
                layer.error_pct.abs() < 1e-3,
                "layer {k}: {}",
                layer.error_pct
            );
            let at_height = (k as f64 + 0.5) * spacing as f64;
            assert!((layer.depth_below_initial_surface - at_height).abs() < 1e-6);
        }
        // Settled by 1 % of its height (more at the top, none at the floor), with its top row
        // sagging a further tenth of a spacing: the weight above each particle is unchanged,
        // its height below the initial surface is not.
        let rows = exact.layers.len();
        let settle = |k: usize| {
            let column = 0.01 * (rows - k) as f32 * spacing * (rows - k) as f32 / rows as f32;
            column + if k == 0 { 0.1 * spacing } else { 0.0 }
        };
        let mut sampler = HydrostaticSampler::new(&setup, setup.duration);
        sampler.record(&setup, setup.duration, &lattice(&setup, settle));
        let settled = sampler.finish(&setup.scene.params);
        assert_eq!(settled.layers.len(), rows);
        assert!(settled.max_error_below_top_pct < 0.5, "{settled:?}");
        assert!(
            settled.layers[1].error_vs_initial_surface_pct < -3.0,
            "{:?}",
            settled.layers[1]
        );
    }

    #[test]
    fn the_window_reports_the_mean_and_largest_speed_of_every_sample() {
        let setup = setup(Scenario::Hydrostatic, 1000, 0.0);
        let mut sampler = HydrostaticSampler::new(&setup, setup.duration);
        let late = setup.duration;
        // Before the window: ignored.
        sampler.record(&setup, 0.0, &state(&setup, 1.0));
        sampler.record(&setup, late, &state(&setup, 0.1));
        sampler.record(&setup, late, &state(&setup, 0.02));
        let figures = sampler.finish(&setup.scene.params);
        assert!((figures.speed_max_window_mean - 0.06).abs() < 1e-6);
        let n = setup.scene.positions().len() as f64;
        let mean = (0.1 + 0.02) / n / 2.0;
        assert!((figures.speed_mean_window_mean - mean).abs() < 1e-9 * mean.max(1.0));
        assert_eq!(figures.speed_max_window_over_pct, 50.0);
    }
}
