//! Forces pass: symmetric pressure (design eq. 9), viscosity (design eq. 10, Müller 2003 eq. 14),
//! gravity, and Akinci 2013 surface tension when γ > 0. Writes accelerations a_i = f_i / ρ_i + g.

use crate::neighbor::Neighbors;
use crate::stage::StageContext;
use crate::surface_tension_akinci2013::surface_tension_pair;
use glam::Vec3;
use rayon::prelude::*;

/// The particle fields the forces pass reads (sorted order).
#[derive(Clone, Copy)]
pub struct ForceInputs<'a> {
    /// Positions.
    pub position: &'a [Vec3],
    /// Velocities seen by the viscosity term (current or predicted, per integrator).
    pub velocity: &'a [Vec3],
    /// Densities from the density pass.
    pub density: &'a [f32],
    /// Pressures from the density pass.
    pub pressure: &'a [f32],
    /// Akinci normals (read only when surface tension is on).
    pub normal: &'a [Vec3],
}

/// Acceleration of particle i:
/// a_i = -(1/ρ_i) Σ_j m (p_i + p_j) / (2 ρ_j) ∇W_spiky
///       + (μ/ρ_i) Σ_j m (v_j - v_i) / ρ_j ∇²W_visc + Σ_j F_ij^st / m + g.
/// The pairwise forces m_i a_ij are antisymmetric, so internal forces conserve momentum.
#[inline]
pub fn acceleration_at(
    ctx: &StageContext,
    neighbors: &Neighbors,
    input: &ForceInputs,
    i: usize,
) -> Vec3 {
    let x_i = input.position[i];
    let v_i = input.velocity[i];
    let rho_i = input.density[i];
    let p_i = input.pressure[i];
    let n_i = input.normal.get(i).copied().unwrap_or(Vec3::ZERO);
    let with_viscosity = ctx.viscosity > 0.0;
    let with_surface_tension = ctx.surface_tension > 0.0;
    let mut pressure_viscosity = Vec3::ZERO;
    let mut surface_tension = Vec3::ZERO;
    neighbors.for_each_neighbor(input.position, x_i, |j, r, r2| {
        if j == i {
            return;
        }
        let r_len = r2.sqrt();
        let rho_j = input.density[j];
        let p_j = input.pressure[j];
        // Design eq. 9: f_i^p = -Σ m (p_i + p_j) / (2 ρ_j) ∇W_spiky(r_ij).
        pressure_viscosity -= ctx.kernels.spiky_grad(r, r_len) * ((p_i + p_j) / (2.0 * rho_j));
        if with_viscosity {
            // Design eq. 10: f_i^v = μ Σ m (v_j - v_i) / ρ_j ∇²W_visc(r_ij).
            pressure_viscosity += (input.velocity[j] - v_i)
                * (ctx.viscosity * ctx.kernels.viscosity_laplacian(r_len) / rho_j);
        }
        if with_surface_tension {
            surface_tension +=
                surface_tension_pair(ctx, r, r_len, rho_i, rho_j, n_i, input.normal[j]);
        }
    });
    pressure_viscosity * (ctx.mass / rho_i) + surface_tension + ctx.gravity
}

/// Fills `acceleration` for every (sorted) particle.
pub fn compute_accelerations(
    ctx: &StageContext,
    neighbors: &Neighbors,
    input: &ForceInputs,
    acceleration: &mut [Vec3],
) {
    acceleration
        .par_iter_mut()
        .enumerate()
        .for_each(|(i, a)| *a = acceleration_at(ctx, neighbors, input, i));
}
