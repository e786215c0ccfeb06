//! The ranges of the sandbox's parameter sliders, shared with the stability tests
//! (`tests/stability_extremes.rs` checks every parameter at both ends of its range).

use std::ops::RangeInclusive;

/// Artificial viscosity α (dimensionless) of ν = α h c0 / 10, set with
/// `SphParams::set_artificial_viscosity_alpha`. The water preset has α = 0.15 (0.25 with DFSPH,
/// which scales the viscosity by 5/3); the end covers the design preset's μ = 0.02 Pa s at ρ0 = 1
/// (α ≈ 1.7 at the default budget, 3.3 at the largest; with DFSPH 2.8 and 5.5, the slider then
/// shows 4 but keeps the value until moved).
pub const VISCOSITY_ALPHA: RangeInclusive<f32> = 0.0..=4.0;
/// Pressure stiffness k (Tait's B [Pa]).
pub const STIFFNESS: RangeInclusive<f32> = 1e-2..=1e7;
/// Rest density ρ0 [kg/m³] (set with [`set_rest_density`]).
pub const REST_DENSITY: RangeInclusive<f32> = 0.5..=2000.0;
/// Surface tension γ.
pub const SURFACE_TENSION: RangeInclusive<f32> = 0.0..=2.0;
/// Fraction of the normal velocity kept after a wall bounce.
pub const WALL_DAMPING: RangeInclusive<f32> = 0.0..=1.0;
/// Gravity along y [m/s²].
pub const GRAVITY_Y: RangeInclusive<f32> = -20.0..=0.0;
/// Time step dt, or the largest adaptive dt [s].
pub const TIME_STEP: RangeInclusive<f32> = 1e-5..=0.01;
/// CFL factor λ of the adaptive time step.
pub const CFL_FACTOR: RangeInclusive<f32> = 0.05..=1.0;

/// Sets the rest density of the fluid: the particle mass follows (m = ρ0 Δx³), so a denser fluid
/// is heavier rather than squeezed (with the old mass, ρ/ρ0 = 2000 overflows Tait's (ρ/ρ0)⁷ in f32).
pub fn set_rest_density(p: &mut sph_core::SphParams, rest_density: f32) {
    p.particle_mass *= rest_density / p.rest_density;
    p.rest_density = rest_density;
}
