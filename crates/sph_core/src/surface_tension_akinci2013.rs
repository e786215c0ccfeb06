//! Akinci, Akinci & Teschner 2013, "Versatile surface tension and adhesion for SPH fluids":
//! per-particle normals (eq. 16), cohesion (eqs. 13-14), curvature (eq. 15) and the symmetric
//! correction factor K_ij = 2 ρ0 / (ρ_i + ρ_j) (eq. 17).

use crate::neighbor::Neighbors;
use crate::stage::StageContext;
use glam::Vec3;
use rayon::prelude::*;

/// Fills `normal` with n_i = h Σ_j (m / ρ_j) ∇W_poly6(x_i - x_j) (Akinci 2013 eq. 16).
pub fn compute_normals(
    ctx: &StageContext,
    neighbors: &Neighbors,
    positions: &[Vec3],
    density: &[f32],
    normal: &mut [Vec3],
) {
    normal
        .par_iter_mut()
        .zip(positions.par_iter())
        .for_each(|(n, &x_i)| {
            let mut sum = Vec3::ZERO;
            neighbors.for_each_neighbor(positions, x_i, |j, r, r2| {
                sum += ctx.kernels.poly6_grad(r, r2) / density[j];
            });
            *n = ctx.kernels.h * ctx.mass * sum;
        });
}

/// Surface-tension acceleration on i from j, F_ij / m_i with
/// F_ij = K_ij (F_cohesion + F_curvature), F_cohesion = -γ m_i m_j C(r) r/|r| (eq. 13),
/// F_curvature = -γ m_i (n_i - n_j) (eq. 15), K_ij = 2 ρ0 / (ρ_i + ρ_j) (eq. 17).
/// `r = x_i - x_j`; coincident particles get no cohesion direction (never NaN).
#[inline]
pub fn surface_tension_pair(
    ctx: &StageContext,
    r: Vec3,
    r_len: f32,
    rho_i: f32,
    rho_j: f32,
    n_i: Vec3,
    n_j: Vec3,
) -> Vec3 {
    let correction = 2.0 * ctx.rest_density / (rho_i + rho_j);
    let cohesion = if r_len > 0.0 {
        r * (ctx.mass * ctx.kernels.cohesion(r_len) / r_len)
    } else {
        Vec3::ZERO
    };
    -ctx.surface_tension * correction * (cohesion + (n_i - n_j))
}
