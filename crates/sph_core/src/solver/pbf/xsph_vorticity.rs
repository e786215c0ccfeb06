//! The velocity passes that close a PBF step (Macklin & Müller 2013, sec. 5): XSPH viscosity
//! (Schechter & Bridson 2012), with the densities at the final positions in the same pass, and
//! vorticity confinement (Fedkiw et al. 2001, as Macklin & Müller 2013 apply it).

use crate::boundary::samples::Boundary;
use crate::neighbor::lists::IndexLists;
use crate::neighbor::pair_lanes::{lane_sum, wide_lanes, Lanes, LANES};
use crate::solver::pbf::macklin2013::{boundary_volume_sum, Constraint, PbfContext};
use glam::Vec3;

/// XSPH viscosity, v_i + c Σ_j (m/ρ_j) (v_j - v_i) W_ij into `velocity_out` (ρ_j from the last λ
/// pass, in `constraint`), and the densities at the final `positions` (fluid and boundary, as
/// [`compute_densities`](crate::solver::pbf::macklin2013::compute_densities)) into `density`: one pass, as both weigh the same W_ij.
#[allow(clippy::too_many_arguments)]
pub fn xsph_and_densities(
    ctx: &PbfContext,
    lists: &IndexLists,
    positions: &[Vec3],
    boundary: Option<&Boundary>,
    constraint: &[Constraint],
    velocity: &[Vec3],
    velocity_out: &mut [Vec3],
    density: &mut [f32],
) {
    let k = &ctx.kernel;
    let self_weight = k.value(0.0);
    let wide = wide_lanes();
    lists.update_pair(velocity_out, density, |i, pairs, v, rho| {
        let (x_i, v_i) = (positions[i], velocity[i]);
        let pass = FluidXsph {
            ctx,
            x_i,
            v_i,
            fluid: pairs.fluid,
            positions,
            velocity,
            constraint,
        };
        let (w_sum, smoothing) = pass.sums(wide);
        *v = v_i + smoothing * ctx.xsph_c;
        let solid = boundary_volume_sum(k, x_i, boundary, pairs.boundary);
        *rho = ctx.mass * (self_weight + w_sum) + ctx.rest_density * solid;
    });
}

/// One particle's fluid sums of [`xsph_and_densities`]: Σ_j W_ij and Σ_j (m/ρ_j)(v_j - v_i) W_ij.
pub(super) struct FluidXsph<'a> {
    pub ctx: &'a PbfContext,
    pub x_i: Vec3,
    pub v_i: Vec3,
    pub fluid: &'a [u32],
    pub positions: &'a [Vec3],
    pub velocity: &'a [Vec3],
    pub constraint: &'a [Constraint],
}

impl FluidXsph<'_> {
    /// The sums, in the AVX2 copy when `wide` ([`wide_lanes`]).
    #[inline]
    pub(super) fn sums(&self, wide: bool) -> (f32, Vec3) {
        #[cfg(target_arch = "x86_64")]
        if wide {
            #[target_feature(enable = "avx2,fma")]
            fn avx2(pass: &FluidXsph) -> (f32, Vec3) {
                pass.in_lanes::<true>()
            }
            // SAFETY: `wide` comes from `wide_lanes()`: this CPU has AVX2 and FMA.
            return unsafe { avx2(self) };
        }
        let _ = wide;
        self.in_lanes::<false>()
    }

    #[inline(always)]
    fn in_lanes<const WIDE: bool>(&self) -> (f32, Vec3) {
        let Self {
            ctx,
            x_i,
            v_i,
            fluid,
            positions,
            velocity,
            constraint,
        } = *self;
        let k = &ctx.kernel;
        let beyond = 2.0 * k.h;
        let [mut w_sum, mut sx, mut sy, mut sz] = [[0.0f32; LANES]; 4];
        for block in fluid.chunks(LANES) {
            let r = Lanes::gather::<WIDE>(x_i, positions, block, beyond);
            // v_i - v_j (the lanes past the list's end hold zeros).
            let dv = Lanes::gather::<WIDE>(v_i, velocity, block, 0.0);
            let mut volume = [0.0f32; LANES];
            for (l, &j) in block.iter().enumerate() {
                volume[l] = ctx.mass / constraint[j as usize].density;
            }
            for l in 0..LANES {
                let w = k.value_and_gradient_factor(r.r2::<WIDE>(l)).0;
                w_sum[l] += w;
                let weight = volume[l] * w;
                sx[l] -= dv.x[l] * weight;
                sy[l] -= dv.y[l] * weight;
                sz[l] -= dv.z[l] * weight;
            }
        }
        (
            lane_sum(&w_sum),
            Vec3::new(lane_sum(&sx), lane_sum(&sy), lane_sum(&sz)),
        )
    }
}

/// The vorticity ω_i = ∇ × v = Σ_j (m/ρ_j) (v_j - v_i) × ∇_j W_ij with ∇_j W_ij = -∇_i W_ij
/// (Macklin & Müller 2013, eq. 15, with the SPH volume m/ρ_j so that ω is in 1/s).
pub fn vorticity(
    ctx: &PbfContext,
    lists: &IndexLists,
    positions: &[Vec3],
    density: &[f32],
    velocity: &[Vec3],
    omega: &mut [Vec3],
) {
    let k = &ctx.kernel;
    lists.update(omega, |i, pairs, w| {
        let (x_i, v_i) = (positions[i], velocity[i]);
        let mut curl = Vec3::ZERO;
        for &j in pairs.fluid {
            let j = j as usize;
            let r = x_i - positions[j];
            let grad_j = -k.gradient(r, r.length());
            curl += (velocity[j] - v_i).cross(grad_j) * (ctx.mass / density[j]);
        }
        *w = curl;
    });
}

/// Vorticity confinement: v_i += dt ε (N_i × ω_i) with N = η/|η| and
/// η_i = ∇|ω|_i = Σ_j (m/ρ_j) (|ω_j| - |ω_i|) ∇_i W_ij (Macklin & Müller 2013, eq. 16, after
/// Fedkiw et al. 2001): the force turns the flow around the local peaks of |ω|.
#[allow(clippy::too_many_arguments)]
pub fn confine_vorticity(
    ctx: &PbfContext,
    lists: &IndexLists,
    positions: &[Vec3],
    density: &[f32],
    omega: &[Vec3],
    dt: f32,
    velocity_in: &[Vec3],
    velocity_out: &mut [Vec3],
) {
    let k = &ctx.kernel;
    lists.update(velocity_out, |i, pairs, v| {
        let (x_i, w_i) = (positions[i], omega[i].length());
        let mut eta = Vec3::ZERO;
        for &j in pairs.fluid {
            let j = j as usize;
            let r = x_i - positions[j];
            eta += k.gradient(r, r.length()) * ((omega[j].length() - w_i) * ctx.mass / density[j]);
        }
        let n = eta.normalize_or_zero();
        *v = velocity_in[i] + n.cross(omega[i]) * (ctx.vorticity_epsilon * dt);
    });
}
