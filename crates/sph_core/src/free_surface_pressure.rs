//! The pressure a free-surface particle carries (WCSPH): where the clamped equation of state
//! gives a particle no pressure, it takes the SPH interpolant of the equation of state's
//! pressures at its position, p_i = Σ_j (m/ρ_j) p_j W_poly6(x_i − x_j) (Müller 2003 eq. 1,
//! i included), at most [`StageContext::max_surface_pressure`] (ρ0 |g| Δx/2,
//! [`crate::stage::max_surface_pressure`]).
//!
//! Why: a particle of the top row misses the neighbours above it, so its density reads low and
//! the clamped equation of state gives it no pressure, where the water at its depth (half a
//! spacing under the surface) holds ρ0 g Δx/2. The row under it then carries the top row's
//! weight alone and reads too high, and the row under that, anchored through the top row
//! (rows Δx apart interact only with the rows next to them at h = 2 Δx), too low. The
//! interpolant sees the water below through the kernel and fades where the support empties.
//! Measured on the 8,000-particle tank (`sph-bench run --scenario hydrostatic`,
//! docs/boundary.md): layers 1 and 2 read +17.0 % and −9.8 % against ρ0 g depth with the
//! clamped pressure, about −6 % and −7 % with this one.
//!
//! Tried: the Shepard average Σ_j V_j p_j W_ij / Σ_j V_j W_ij (−3.5 % and −6.0 %) handed whole
//! interior pressures to spray, and `obstacles` had 2 guard corrections against 0. The
//! interpolant without a bound still hands a splash part of an impact's pressure: dambreak32k
//! at its fixed dt of 1 ms (three times the speed of sound's step, rolled back to 0.5 ms) had
//! 12,973 guard corrections against 14. Bounded at ρ0 |g| Δx, 26 there and 1 in `obstacles` (a
//! jet's leading particle driven into the floor); at ρ0 |g| Δx/2, 15 and 0.

use crate::neighbor::Neighbors;
use crate::stage::StageContext;
use glam::Vec3;
use rayon::prelude::*;

/// The SPH interpolant of `eos_pressure` at `positions[i]`: Σ_j (m/ρ_j) p_j W_poly6 over the
/// neighbours within h, i included.
pub fn interpolated_pressure(
    ctx: &StageContext,
    neighbors: &Neighbors,
    positions: &[Vec3],
    density: &[f32],
    eos_pressure: &[f32],
    i: usize,
) -> f32 {
    let mut sum = 0.0;
    neighbors.for_each_neighbor(positions, positions[i], |j, _, r2| {
        sum += ctx.kernels.poly6(r2) * eos_pressure[j] / density[j];
    });
    sum * ctx.mass
}

/// Fills `pressure` for every (sorted) particle: its own equation-of-state pressure, or where
/// that is exactly 0 (the clamp's zero) the interpolant of the pressures around it
/// ([`interpolated_pressure`]), at most [`StageContext::max_surface_pressure`]. With the clamp
/// off (`SphParams::clamp_negative_pressure`), a negative pressure is the particle's own and is
/// kept.
pub fn extrapolate_free_surface_pressure(
    ctx: &StageContext,
    neighbors: &Neighbors,
    positions: &[Vec3],
    density: &[f32],
    eos_pressure: &[f32],
    pressure: &mut [f32],
) {
    pressure.par_iter_mut().enumerate().for_each(|(i, p)| {
        let own = eos_pressure[i];
        *p = if own != 0.0 {
            own
        } else {
            interpolated_pressure(ctx, neighbors, positions, density, eos_pressure, i)
                .min(ctx.max_surface_pressure)
        };
    });
}
