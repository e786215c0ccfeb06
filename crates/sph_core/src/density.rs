//! Density and pressure pass: ρ_i = Σ_j m W_poly6(x_i - x_j, h) (Müller 2003 eq. 3, self included),
//! then p_i from the equation of state.

use crate::neighbor::Neighbors;
use crate::stage::StageContext;
use glam::Vec3;
use rayon::prelude::*;

/// Density ρ_i of the particle at `x_i`.
#[inline]
pub fn density_at(ctx: &StageContext, neighbors: &Neighbors, positions: &[Vec3], x_i: Vec3) -> f32 {
    ctx.mass * neighbors.sum_over_neighbors(positions, x_i, |r2| ctx.kernels.poly6_unchecked(r2))
}

/// Fills `density` and `pressure` for every (sorted) particle.
pub fn compute_density_pressure(
    ctx: &StageContext,
    neighbors: &Neighbors,
    positions: &[Vec3],
    density: &mut [f32],
    pressure: &mut [f32],
) {
    density
        .par_iter_mut()
        .zip(pressure.par_iter_mut())
        .zip(positions.par_iter())
        .for_each(|((rho, p), &x_i)| {
            *rho = density_at(ctx, neighbors, positions, x_i);
            *p = ctx.eos.pressure(*rho);
        });
}
