//! Density and pressure pass: ρ_i = Σ_j m W_poly6(x_i - x_j, h) (Müller 2003 eq. 3, self
//! included) plus the boundary samples' ρ0 Σ_b V_b W_poly6(x_i - x_b) (Akinci 2012), then
//! p_i from the equation of state.

use crate::boundary::samples::Boundary;
use crate::neighbor::Neighbors;
use crate::stage::StageContext;
use glam::Vec3;
use rayon::prelude::*;

/// The boundary's share of the density at `x_i`: ρ0 Σ_b V_b W_poly6(x_i - x_b) (Akinci 2012,
/// the pseudo-mass Ψ_b = ρ0 V_b).
#[inline]
pub fn boundary_density_at(ctx: &StageContext, boundary: &Boundary, x_i: Vec3) -> f32 {
    ctx.rest_density
        * boundary.grid.weighted_sum_over_candidates(
            &boundary.position,
            &boundary.volume,
            x_i,
            |r2| ctx.kernels.poly6_unchecked(r2),
        )
}

/// Density ρ_i of the particle at `x_i`, fluid and boundary.
#[inline]
pub fn density_at(
    ctx: &StageContext,
    neighbors: &Neighbors,
    positions: &[Vec3],
    boundary: Option<&Boundary>,
    x_i: Vec3,
) -> f32 {
    let fluid = ctx.mass
        * neighbors.sum_over_neighbors(positions, x_i, |r2| ctx.kernels.poly6_unchecked(r2));
    fluid + boundary.map_or(0.0, |b| boundary_density_at(ctx, b, x_i))
}

/// Fills `density` and `pressure` for every (sorted) particle.
pub fn compute_density_pressure(
    ctx: &StageContext,
    neighbors: &Neighbors,
    positions: &[Vec3],
    boundary: Option<&Boundary>,
    density: &mut [f32],
    pressure: &mut [f32],
) {
    density
        .par_iter_mut()
        .zip(pressure.par_iter_mut())
        .zip(positions.par_iter())
        .for_each(|((rho, p), &x_i)| {
            *rho = density_at(ctx, neighbors, positions, boundary, x_i);
            *p = ctx.eos.pressure(*rho);
        });
}
