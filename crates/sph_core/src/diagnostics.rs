//! Per-step diagnostics: counts, density error, speeds, CFL number, energies, NaN and escapes.

use crate::container::BoxContainer;
use crate::params::SphParams;
use glam::Vec3;

/// Tolerance [m] for "outside the container" (positions are clamped exactly onto the walls).
pub const OUTSIDE_TOLERANCE: f32 = 1.0e-4;

/// A summary of the particle state after a step.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Diagnostics {
    /// Live particles.
    pub particle_count: usize,
    /// Mean compression error max(0, ρ/ρ0 - 1) in percent. Free-surface particles always have a
    /// density deficit, so compression is what measures incompressibility (as in PCISPH/DFSPH).
    pub density_error_mean_pct: f32,
    /// Largest compression error in percent.
    pub density_error_max_pct: f32,
    /// Mean density ρ / ρ0 (signed: below 1 near free surfaces).
    pub density_ratio_mean: f32,
    /// Largest speed |v| [m/s].
    pub max_speed: f32,
    /// dt (c0 + v_max) / h.
    pub cfl: f32,
    /// Σ m |v|² / 2 [J].
    pub kinetic_energy: f64,
    /// Σ m (-g · (x - floor centre)) [J].
    pub potential_energy: f64,
    /// Particles with a NaN or infinite position, velocity or density.
    pub non_finite_count: usize,
    /// Particles outside the container (beyond [`OUTSIDE_TOLERANCE`]).
    pub outside_count: usize,
}

/// The state arrays diagnostics read.
pub struct DiagnosticsInput<'a> {
    /// Positions.
    pub position: &'a [Vec3],
    /// Velocities.
    pub velocity: &'a [Vec3],
    /// Densities.
    pub density: &'a [f32],
}

impl Diagnostics {
    /// Diagnostics of the given state.
    pub fn measure(params: &SphParams, container: &BoxContainer, state: &DiagnosticsInput) -> Self {
        let n = state.position.len();
        let mut d = Diagnostics {
            particle_count: n,
            ..Default::default()
        };
        let m = params.particle_mass as f64;
        let mut error_sum = 0.0f64;
        let mut ratio_sum = 0.0f64;
        let mut max_speed2 = 0.0f32;
        for i in 0..n {
            let (x, v, rho) = (state.position[i], state.velocity[i], state.density[i]);
            if !(x.is_finite() && v.is_finite() && rho.is_finite()) {
                d.non_finite_count += 1;
                continue;
            }
            if !container.contains(x, OUTSIDE_TOLERANCE) {
                d.outside_count += 1;
            }
            let ratio = rho / params.rest_density;
            let error = (ratio - 1.0).max(0.0) * 100.0;
            error_sum += error as f64;
            ratio_sum += ratio as f64;
            d.density_error_max_pct = d.density_error_max_pct.max(error);
            let v2 = v.length_squared();
            max_speed2 = max_speed2.max(v2);
            d.kinetic_energy += 0.5 * m * v2 as f64;
            d.potential_energy -= m * params.gravity.dot(x - container.floor_center) as f64;
        }
        let finite = (n - d.non_finite_count).max(1) as f64;
        d.density_error_mean_pct = (error_sum / finite) as f32;
        d.density_ratio_mean = (ratio_sum / finite) as f32;
        d.max_speed = max_speed2.sqrt();
        d.cfl = params.cfl_number(d.max_speed);
        d
    }
}
