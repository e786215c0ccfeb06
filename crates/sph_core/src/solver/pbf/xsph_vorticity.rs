//! The velocity passes that close a PBF step (Macklin & Müller 2013, sec. 5): XSPH viscosity
//! (Schechter & Bridson 2012), with the densities at the final positions in the same pass, and
//! vorticity confinement (Fedkiw et al. 2001, as Macklin & Müller 2013 apply it).

use crate::boundary::samples::{BodyForceSum, Boundary};
use crate::kernel::CubicSpline;
use crate::neighbor::lists::IndexLists;
use crate::neighbor::pair_lanes::{lane_sum, wide_lanes, Lanes, LANES};
use crate::solver::pbf::macklin2013::{boundary_volume_sum, Constraint, PbfContext};
use glam::Vec3;

/// XSPH viscosity, v_i + c Σ_j (m/ρ_j) (v_j - v_i) W_ij into `velocity_out` (ρ_j from the last λ
/// pass, in `constraint`), with the no-slip bodies' share of it ([`wall_friction`]), and the
/// densities at the final `positions` (fluid and boundary, as
/// [`compute_densities`](crate::solver::pbf::macklin2013::compute_densities)) into `density`:
/// one pass, as all weigh the same W. Returns the friction's force on each boundary body over
/// the step of `dt` (indexed like [`Boundary::friction`]; all zero on free-slip bodies).
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
    dt: f32,
) -> Vec<BodyForceSum> {
    let k = &ctx.kernel;
    let self_weight = k.value(0.0);
    let wide = wide_lanes();
    let bodies = boundary.map_or(0, Boundary::body_count);
    let reaction = -ctx.mass / dt;
    lists.update_fold(
        velocity_out,
        density,
        || vec![BodyForceSum::default(); bodies],
        |mut sums, i, pairs, v, rho| {
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
            if let Some(b) = boundary {
                let friction = wall_friction(ctx, b, x_i, v_i, pairs.boundary);
                if let Some(WallFriction { change, weight }) = friction {
                    *v += change;
                    // The body takes the momentum the particle loses, -m Δv / dt, shared by
                    // the samples in proportion to their weights.
                    for &s in pairs.boundary {
                        let s = s as usize;
                        let share = sample_friction_weight(k, b, x_i, s) / weight;
                        if share > 0.0 {
                            let body = b.body[s] as usize;
                            let force = change * (reaction * share);
                            sums[body].add(force, b.position[s], b.origin[body]);
                        }
                    }
                }
            }
            let solid = boundary_volume_sum(k, x_i, boundary, pairs.boundary);
            *rho = ctx.mass * (self_weight + w_sum) + ctx.rest_density * solid;
            sums
        },
        |mut a, b| {
            a.iter_mut().zip(&b).for_each(|(a, b)| a.merge(b));
            a
        },
    )
}

/// What the no-slip samples do to one particle's velocity in [`wall_friction`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WallFriction {
    /// The change of the particle's velocity [m/s].
    pub change: Vec3,
    /// Σ_b f_b V_b W_ib over the particle's samples (> 0).
    pub weight: f32,
}

/// The no-slip walls in XSPH's form (Akinci 2012's boundary viscosity with PBF's viscosity):
/// a sample of a body with friction factor f_b counts as water moving with the body, its XSPH
/// weight f_b V_b W_ib, so the particle's velocity moves towards the samples' weighted mean v̄_b
/// by c Σ_b f_b V_b W_ib (XSPH's c), at most all the way:
/// Δv_i = min(c Σ_b f_b V_b W_ib, 1) (v̄_b - v_i). The cap keeps a large f from reversing the
/// particle's slide. `None` when no sample of `samples` has friction.
pub fn wall_friction(
    ctx: &PbfContext,
    boundary: &Boundary,
    x_i: Vec3,
    v_i: Vec3,
    samples: &[u32],
) -> Option<WallFriction> {
    let (mut weight, mut moving) = (0.0f32, Vec3::ZERO);
    for &s in samples {
        let s = s as usize;
        let w = sample_friction_weight(&ctx.kernel, boundary, x_i, s);
        if w > 0.0 {
            weight += w;
            moving += boundary.velocity[s] * w;
        }
    }
    (weight > 0.0).then(|| WallFriction {
        change: (moving / weight - v_i) * (ctx.xsph_c * weight).min(1.0),
        weight,
    })
}

/// f_b V_b W_ib of sample `s` for the particle at `x_i` (0 on a free-slip body).
#[inline]
fn sample_friction_weight(k: &CubicSpline, boundary: &Boundary, x_i: Vec3, s: usize) -> f32 {
    let friction = boundary.friction[boundary.body[s] as usize];
    if friction <= 0.0 {
        return 0.0;
    }
    let w = k
        .value_and_gradient_factor((x_i - boundary.position[s]).length_squared())
        .0;
    friction * boundary.volume[s] * w
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::boundary::collider::Slip;
    use crate::container::BoxContainer;
    use crate::neighbor::Neighbors;
    use crate::params::SphParams;

    /// One particle sliding at 1 m/s just above the floor of a tank whose walls have `slip`:
    /// its velocity after the XSPH pass and the walls' force (body 0) over a step of `dt`.
    fn slide_over_the_floor(slip: Slip, dt: f32) -> (Vec3, Vec3, f32) {
        let params = SphParams::water();
        let ctx = PbfContext::of(&params);
        let container = BoxContainer::from_min_max(Vec3::ZERO, Vec3::splat(0.3));
        let mut boundary = Boundary::new(&container, &params, slip).unwrap();
        boundary.sort();
        let x = vec![Vec3::new(0.15, 0.5 * params.spacing(), 0.15)];
        let v = vec![Vec3::new(1.0, 0.0, 0.0)];
        let h = params.smoothing_radius;
        let mut neighbors = Neighbors::new(params.neighbor_search, &container, h, 1).unwrap();
        neighbors.sort(&x);
        let mut lists = IndexLists::default();
        lists.rebuild_indices(&neighbors, &x, Some(&boundary));
        let constraint = vec![Constraint {
            lambda: 0.0,
            density: params.rest_density,
        }];
        let (mut v_out, mut rho) = (vec![Vec3::ZERO], vec![0.0]);
        let b = Some(&boundary);
        let forces = xsph_and_densities(
            &ctx,
            &lists,
            &x,
            b,
            &constraint,
            &v,
            &mut v_out,
            &mut rho,
            dt,
        );
        (v_out[0], forces[0].force.as_vec3(), ctx.mass)
    }

    /// A no-slip floor slows a particle sliding over it, never past the floor's own velocity,
    /// and takes the momentum it loses (the walls feel -m Δv / dt); a free-slip floor does
    /// nothing.
    #[test]
    fn a_no_slip_floor_slows_a_sliding_particle_and_takes_its_momentum() {
        let dt = 1.0 / 120.0;
        let (v, force, _) = slide_over_the_floor(Slip::Free, dt);
        assert_eq!(v, Vec3::new(1.0, 0.0, 0.0));
        assert_eq!(force, Vec3::ZERO);
        let mut slowed = Vec::new();
        for friction in [1.0, 30.0, 100.0] {
            let (v, force, mass) = slide_over_the_floor(Slip::NoSlip { friction }, dt);
            let change = v - Vec3::new(1.0, 0.0, 0.0);
            assert!(v.x < 1.0 && v.x >= 0.0, "friction {friction}: {v}");
            assert!(
                v.y.abs() < 1e-6 && v.z.abs() < 1e-6,
                "friction {friction}: {v}"
            );
            let expected = -change * mass / dt;
            assert!(
                (force - expected).length() <= 1e-4 * expected.length(),
                "friction {friction}: the walls feel {force}, the particle lost {expected}"
            );
            slowed.push(1.0 - v.x);
        }
        eprintln!("the slide lost in a step at f = 1, 30, 100: {slowed:?}");
        // More friction slows more: the weight grows with f until the cap holds it at the
        // floor's velocity.
        assert!(
            slowed[0] < slowed[1] && slowed[1] <= slowed[2],
            "{slowed:?}"
        );
    }
}
