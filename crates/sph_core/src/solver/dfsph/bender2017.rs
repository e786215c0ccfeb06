//! Divergence-free SPH (Bender & Koschier 2015, "Divergence-free smoothed particle
//! hydrodynamics"; 2017, IEEE TVCG): the stages of the two pressure solves, written over
//! [`NeighborLists`] so that one step's dozen passes over the same pairs read lists instead of
//! walking cells. The step that strings them together is `CpuSolver`'s (`solver/dfsph/mod.rs`).
//!
//! DFSPH measures density with its own kernel, the cubic spline ([`crate::kernel::CubicSpline`],
//! normalised on the rest lattice), and every gradient below is of that same kernel, so that the
//! solve predicts the density it will measure after the move. Not poly6, the WCSPH density
//! kernel: its gradient peaks at 0.45 h, so close to the rest spacing h/2 that compressed pairs
//! stop repelling, and a tank at rest sinks into its floor (docs/dfsph.md).
//!
//! Notation:
//! - g_ij = m ∇W(x_i - x_j) for fluid neighbours, g_ib = Ψ_b ∇W(x_i - x_b) with Ψ_b = ρ0 V_b for
//!   boundary samples (Akinci 2012); the fluid pairs' g_ij rounded to 3e-5 of their largest as
//!   the GPU packs them ([`crate::gpu_dfsph_pairs`]), so both backends solve with the same g_ij;
//! - the stiffness κ_i [m⁵/(kg s²)] is a pressure over density squared, p_i/ρ_i², so it does not
//!   depend on dt and warm-starts across steps whose dt differ;
//! - the pressure acceleration is a_i = -Σ_j (κ_i + κ_j) g_ij - 2 κ_i Σ_b g_ib: the symmetric
//!   form with the particle's stiffness mirrored onto the samples (κ_b = κ_i, as WCSPH's walls
//!   mirror p_i, `crate::forces`). With κ_b = 0 instead (the boundary answering with κ_i once),
//!   a wall row needs twice its pressure to hold: the tank's bottom layer reads +85 % and the
//!   rows next to the side walls too (mean 10.1 %);
//! - the samples hold the hydrostatic rise between particle and sample besides (as WCSPH's
//!   walls do, Adami et al. 2012's g term): [`BoundaryRise`], a step's constant, applied with
//!   the non-pressure accelerations. Mirroring alone (κ_b = κ_i) under-states a floor's pressure
//!   and over-states a ceiling's, so a box held under water read +28 % (docs/dfsph.md);
//! - the rate of density change is Dρ_i/Dt = Σ_j (v_i - v_j)·g_ij + Σ_b (v_i - v_b)·g_ib;
//! - the samples mirror κ_i and hold the rise only while every dynamic collider can give way
//!   ([`Boundary::mirrors`]); otherwise, and for a particle pinched between samples (D with the
//!   mirror below half of D without), they answer with κ_i once.
//!
//! With the neighbours' stiffness held (a Jacobi step), κ_i alone changes Dρ_i/Dt by exactly
//! -dt κ_i D_i, through i's own velocity and its neighbours', with
//! D_i = (Σ_j g_ij + 2 Σ_b g_ib)·(Σ_j g_ij + Σ_b g_ib) + Σ_j |g_ij|² (the DFSPH factor is
//! α_i = ρ_i / D_i in the paper's κ; ours is 1 / D_i). Hence the stiffness that removes a
//! predicted density excess s_i = ρ*_i - ρ0 in one step is κ_i = s_i / (dt² D_i), and the one
//! that removes a compression rate d_i = Dρ_i/Dt is κ_i = d_i / (dt D_i).

use crate::boundary::samples::{BodyForceSum, Boundary};
use crate::kernel::CubicSpline;
use crate::neighbor::lists::{NeighborLists, PairsOf};
use crate::params::SphParams;
use crate::stability::viscous_limit;
use glam::Vec3;
use rayon::prelude::*;

/// A particle with fewer neighbours (fluid and boundary) than this lies at a free surface, and
/// the divergence-free solve leaves it alone: the missing neighbours make any motion look like
/// expansion or compression, and correcting it makes the surface sticky.
pub const INTERIOR_NEIGHBORS: usize = 20;

/// The quantities of particle i that stay constant through a step's solves.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ParticleFactor {
    /// 1 / D_i (0 when D_i is too small: an isolated particle is not corrected).
    pub inverse_factor: f32,
    /// Σ_b g_ib, the boundary's share of the pressure acceleration per unit κ_i.
    pub boundary_grad: Vec3,
    /// Whether the samples mirror κ_i, so that they answer with 2 κ_i: they all do
    /// ([`Boundary::mirrors`]) and the particle is not pinched.
    pub mirrors: bool,
    /// Σ_b v_b·g_ib, the moving boundary's share of Dρ_i/Dt.
    pub boundary_flux: f32,
    /// max(p_i, 0) of the pressure p_i = (κ_i^ρ + κ_i^v) ρ0² that the solves' totals held when
    /// the factors were found, the floor of [`BoundaryRise`] [Pa].
    pub rise_floor: f32,
    /// Fluid and boundary neighbours.
    pub neighbor_count: u32,
}

/// D_i below this fraction of the rest lattice's D gets no correction.
pub const FACTOR_EPSILON: f32 = 1.0e-6;

/// The fraction of the previous step's stiffness the constant-density solve starts from, where
/// the fluid is compressed before it (Bender & Koschier 2017 warm-start from the previous
/// stiffness; SPlisHSPlasH does it only where the predicted density exceeds ρ0, and so do we).
/// Half of it: with the whole, the tank's rows next to the mirrored walls keep the stiffness of
/// the steps before and the tank never comes to rest (0.011 m/s against 0.0012 m/s with half;
/// docs/dfsph.md, "The boundary in the solves").
pub const DENSITY_WARM_START: f32 = 0.5;

/// The free surface's stiffness in the constant-density solve, at most ρ0 |g| Δx/2 over ρ0²
/// (WCSPH's free-surface pressure, [`crate::forces`], moved into the solve): a top-row particle
/// (under-dense, no source) is otherwise pushed by the row beneath and by nothing above, and
/// stands half a spacing higher than WCSPH's, its row beneath over-pressed (+8 % in the tank).
#[derive(Clone, Copy, Debug)]
pub struct TopRowStiffness<'a> {
    /// The solve's sources s_i of the iteration.
    pub source: &'a [f32],
    /// ρ_i.
    pub density: &'a [f32],
    /// ρ0 [kg/m³].
    pub rest_density: f32,
    /// The cap, |g| Δx / (2 ρ0) [m⁵/(kg s²)].
    pub cap: f32,
}

/// Below this fraction of ρ0 a particle without a source is on the free surface.
pub const TOP_ROW_DENSITY: f32 = 0.95;

impl TopRowStiffness<'_> {
    /// The stiffness sum each top-row particle reaches this iteration (NaN elsewhere): the
    /// |g_ij|-weighted mean of its neighbours' positive sums `total` (before the iteration's
    /// Jacobi stiffness joins them), at most the cap.
    pub fn targets(&self, lists: &NeighborLists, total: &[f32], targets: &mut Vec<f32>) {
        targets.resize(total.len(), f32::NAN);
        lists.update(targets, |i, pairs, t| {
            *t = f32::NAN;
            if self.source[i] > 0.0 || self.density[i] >= TOP_ROW_DENSITY * self.rest_density {
                return;
            }
            let (mut sum, mut weights) = (0.0, 0.0);
            for p in pairs.fluid {
                let k = total[p.index as usize];
                if k > 0.0 {
                    let w = p.grad.length();
                    sum += w * k;
                    weights += w;
                }
            }
            if weights > 0.0 {
                *t = (sum / weights).min(self.cap);
            }
        });
    }
}

/// The same for the divergence-free solve, where the fluid is being compressed. Half of it: with
/// the whole, a tank at rest keeps moving (mean speed 0.029 m/s against 0.005) because the
/// divergence stiffness corrects transients rather than carrying a lasting pressure.
pub const DIVERGENCE_WARM_START: f32 = 0.5;

/// D_i of a particle in the rest lattice: Σ_j |m ∇W|² over the lattice neighbours (the sum of
/// the gradients vanishes there), for DFSPH's kernel (the cubic spline normalised on the
/// lattice); the scale of [`compute_factors`]'s cut-off.
pub fn rest_lattice_factor(params: &SphParams) -> f32 {
    let dx = params.spacing();
    let kernel = CubicSpline::new(params.smoothing_radius, dx);
    let mut sum = 0.0;
    for i in -2i32..=2 {
        for j in -2i32..=2 {
            for k in -2i32..=2 {
                let r = Vec3::new(i as f32, j as f32, k as f32) * dx;
                sum += kernel.gradient(r, r.length()).length_squared();
            }
        }
    }
    sum * params.particle_mass * params.particle_mass
}

/// The pressure the boundary samples hold beyond the mirrored p_i: the hydrostatic rise between
/// the particle and each sample (Adami et al. 2012's g term, as WCSPH's walls,
/// `crate::forces::boundary_acceleration_at`), p_b^rise = max(ρ0 g·(x_b - x_i), -p̂_i), p̂_i the
/// particle's [`ParticleFactor::rise_floor`] (a sample above a free-surface particle does not
/// pull on it). It does not depend on the stiffness, so it acts once a step, with the
/// non-pressure accelerations (v* = v + dt (a_np + a_rise)), and its reactions join the bodies'
/// forces once.
#[derive(Clone, Copy, Debug)]
pub struct BoundaryRise<'a> {
    /// Particle positions (the factors').
    pub positions: &'a [Vec3],
    /// The factors, for the floors.
    pub factors: &'a [ParticleFactor],
    /// g [m/s²].
    pub gravity: Vec3,
    /// ρ0 [kg/m³].
    pub rest_density: f32,
}

impl BoundaryRise<'_> {
    /// p_b^rise / ρ0² of particle i and a sample at `x_b`.
    #[inline]
    fn over_rho0_squared(&self, i: usize, x_b: Vec3) -> f32 {
        let rho0 = self.rest_density;
        let rise =
            (rho0 * self.gravity.dot(x_b - self.positions[i])).max(-self.factors[i].rise_floor);
        rise / (rho0 * rho0)
    }

    /// The rise's acceleration of particle i, a_i^rise = -Σ_b (p_b^rise/ρ0²) g_ib (the caller
    /// checks that the samples mirror).
    fn acceleration(&self, i: usize, pairs: PairsOf, boundary: &Boundary) -> Vec3 {
        pairs.boundary.iter().fold(Vec3::ZERO, |a, pair| {
            a - pair.grad * self.over_rho0_squared(i, boundary.position[pair.index as usize])
        })
    }

    /// v_i += dt (a_i + a_i^rise): the predicted velocities of the non-pressure accelerations
    /// `acceleration` and the rise (none unless the samples mirror, [`Boundary::mirrors`]).
    pub fn predict(
        &self,
        lists: &NeighborLists,
        boundary: &Boundary,
        acceleration: &[Vec3],
        dt: f32,
        v: &mut [Vec3],
    ) {
        if !boundary.mirrors() {
            lists.update(v, |i, _, v_i| *v_i += acceleration[i] * dt);
            return;
        }
        lists.update(v, |i, pairs, v_i| {
            *v_i += (acceleration[i] + self.acceleration(i, pairs, boundary)) * dt;
        });
    }

    /// The fluid's force on each boundary body from the rise: m (p_b^rise/ρ0²) g_ib per pair,
    /// at the sample, with its torque (indexed like [`Boundary::friction`]; zero unless the
    /// samples mirror).
    pub fn reactions(
        &self,
        lists: &NeighborLists,
        boundary: &Boundary,
        mass: f32,
    ) -> Vec<BodyForceSum> {
        let bodies = boundary.body_count();
        if !boundary.mirrors() {
            return vec![BodyForceSum::default(); bodies];
        }
        lists.fold(
            || vec![BodyForceSum::default(); bodies],
            |mut sums, i, pairs| {
                for p in pairs.boundary {
                    let b = p.index as usize;
                    let body = boundary.body[b] as usize;
                    let x_b = boundary.position[b];
                    let force = p.grad * (mass * self.over_rho0_squared(i, x_b));
                    sums[body].add(force, x_b, boundary.origin[body]);
                }
                sums
            },
            |mut a, b| {
                a.iter_mut().zip(&b).for_each(|(a, b)| a.merge(b));
                a
            },
        )
    }
}

/// Fills `factors` from the lists: 1/D_i, Σ_b g_ib, Σ_b v_b·g_ib, neighbour counts, and the
/// rise's floor from `totals`, the solves' summed stiffness (κ^ρ, κ^v) of each particle (none:
/// 0). `reference` is a typical D (the rest lattice's) that scales the cut-off for isolated
/// particles.
pub fn compute_factors(
    lists: &NeighborLists,
    boundary: Option<&Boundary>,
    totals: Option<(&[f32], &[f32])>,
    rest_density: f32,
    reference: f32,
    factors: &mut [ParticleFactor],
) {
    let mirrored = boundary.is_some_and(Boundary::mirrors);
    lists.update(factors, |i, pairs, out| {
        let mut sum = Vec3::ZERO;
        let mut squares = 0.0;
        for pair in pairs.fluid {
            sum += pair.grad;
            squares += pair.grad.length_squared();
        }
        let mut boundary_grad = Vec3::ZERO;
        let mut boundary_flux = 0.0;
        if let Some(b) = boundary {
            for pair in pairs.boundary {
                boundary_grad += pair.grad;
                boundary_flux += b.velocity[pair.index as usize].dot(pair.grad);
            }
        }
        let rise_floor = totals.map_or(0.0, |(density, divergence)| {
            ((density[i] + divergence[i]) * rest_density * rest_density).max(0.0)
        });
        // The boundary mirrors κ_i (see the module), unless the particle is pinched.
        let once = (sum + boundary_grad).length_squared() + squares;
        let with_mirror = once + boundary_grad.dot(sum + boundary_grad);
        let mirrors = mirrored && with_mirror >= 0.5 * once;
        let d = if mirrors { with_mirror } else { once };
        *out = ParticleFactor {
            inverse_factor: if d > FACTOR_EPSILON * reference {
                1.0 / d
            } else {
                0.0
            },
            boundary_grad,
            mirrors,
            boundary_flux,
            rise_floor,
            neighbor_count: (pairs.fluid.len() + pairs.boundary.len()) as u32,
        };
    });
}

/// Dρ_i/Dt at the velocities `v`.
#[inline]
pub fn density_rate(i: usize, pairs: PairsOf, v: &[Vec3], factor: &ParticleFactor) -> f32 {
    let v_i = v[i];
    let fluid: f32 = pairs
        .fluid
        .iter()
        .map(|p| (v_i - v[p.index as usize]).dot(p.grad))
        .sum();
    fluid + v_i.dot(factor.boundary_grad) - factor.boundary_flux
}

/// The most compression the constant-density solve removes in one step, as a fraction of ρ0.
/// The water scenes stay well below it (the most compressed particle at the end of a run is at
/// 0.1 to 1.3 %, docs/dfsph.md); a spawn that squeezes 64
/// particles into one cell (8 ρ0) would otherwise be pushed apart in a single step by more than
/// a support radius, which the stability check rejects at any dt (the solve's displacement does
/// not shrink with dt). Capped, it spreads over a few dozen steps.
pub const MAX_CORRECTION: f32 = 0.05;

/// The constant-density solve's source: the predicted density's excess
/// s_i = min(max(ρ_i + dt Dρ_i/Dt - ρ0, 0), [`MAX_CORRECTION`] ρ0) [kg/m³] (a deficit is the
/// missing air of a free surface, not a tension). Returns Σ_i s_i.
pub fn density_source(
    lists: &NeighborLists,
    v: &[Vec3],
    density: &[f32],
    factors: &[ParticleFactor],
    rest_density: f32,
    dt: f32,
    source: &mut [f32],
) -> f64 {
    lists.update(source, |i, pairs, s| {
        let predicted = density[i] + dt * density_rate(i, pairs, v, &factors[i]);
        *s = (predicted - rest_density).clamp(0.0, MAX_CORRECTION * rest_density);
    });
    source.par_iter().map(|&s| s as f64).sum()
}

/// The divergence-free solve's source: the compression rate d_i = max(Dρ_i/Dt, 0)
/// [kg/(m³ s)], zero for particles with fewer than [`INTERIOR_NEIGHBORS`]. Returns Σ_i d_i.
pub fn divergence_source(
    lists: &NeighborLists,
    v: &[Vec3],
    factors: &[ParticleFactor],
    source: &mut [f32],
) -> f64 {
    lists.update(source, |i, pairs, d| {
        let factor = &factors[i];
        *d = if factor.neighbor_count as usize >= INTERIOR_NEIGHBORS {
            density_rate(i, pairs, v, factor).max(0.0)
        } else {
            0.0
        };
    });
    source.par_iter().map(|&d| d as f64).sum()
}

/// The over-relaxation of a solve's iterations after its first
/// ([`crate::DfsphSettings::divergence_over_relaxation`],
/// [`crate::DfsphSettings::density_over_relaxation`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OverRelaxation {
    /// ω.
    pub omega: f32,
    /// A particle whose source is at most this (the solve's tolerance times ρ0, [kg/(m³ s)])
    /// has converged and takes a plain Jacobi step.
    pub converged_source: f32,
}

/// One Jacobi update of the stiffness: κ_i = scale · source_i / D_i (scale 1/dt² for the
/// density solve, 1/dt for the divergence solve), added to the step's running `total`. With
/// `over_relaxation` (the iterations after a solve's first), the stiffness applied is
/// ω κ_i + (ω - 1) κ'_i, κ'_i being the one `stiffness` holds from the iteration before, but
/// only where the source is above `converged_source`: the momentum (ω - 1) κ'_i would push on a
/// particle whose compression is already gone, and the expansion it leaves is taken back by no
/// solve (the sources are clamped at 0). With the momentum everywhere, a box held under water
/// read +60.6 % over ρ0 g V instead of −5.1 % (docs/dfsph.md). The threshold is the solve's own
/// tolerance rather than 0, so that the rule does not flip on rounding: a source that converges
/// to 0 sits at 0 within rounding, where the CPU and the GPU would disagree.
/// `top_row`: [`TopRowStiffness::targets`] of the iteration, the sums the top row's particles
/// rise to (the constant-density solve's iterations).
pub fn stiffness_from_source(
    source: &[f32],
    factors: &[ParticleFactor],
    scale: f32,
    over_relaxation: Option<OverRelaxation>,
    top_row: Option<&[f32]>,
    stiffness: &mut [f32],
    total: &mut [f32],
) {
    stiffness
        .par_iter_mut()
        .zip(total.par_iter_mut())
        .enumerate()
        .for_each(|(i, (k, sum))| {
            let jacobi = scale * source[i] * factors[i].inverse_factor;
            *k = match over_relaxation {
                Some(r) if source[i] > r.converged_source => {
                    r.omega * jacobi + (r.omega - 1.0) * *k
                }
                _ => jacobi,
            };
            *sum += *k;
            // A top-row particle's sum rises to its target (NaN: none).
            let target = top_row.map_or(f32::NAN, |t| t[i]);
            if target > *sum {
                *k += target - *sum;
                *sum = target;
            }
        });
}

/// v_i += dt a_i with the pressure acceleration a_i = -Σ_j (κ_i + κ_j) g_ij - 2 κ_i Σ_b g_ib.
pub fn apply_stiffness(
    lists: &NeighborLists,
    stiffness: &[f32],
    factors: &[ParticleFactor],
    dt: f32,
    v: &mut [Vec3],
) {
    lists.update(v, |i, pairs, v_i| {
        let k_i = stiffness[i];
        let f = &factors[i];
        let boundary_k = if f.mirrors { 2.0 * k_i } else { k_i };
        let mut a = -boundary_k * f.boundary_grad;
        for p in pairs.fluid {
            a -= (k_i + stiffness[p.index as usize]) * p.grad;
        }
        *v_i += a * dt;
    });
}

/// The fluid's force on each boundary body from the stiffness `total` of a solve: the reaction
/// -m a_ib = 2 m κ_i g_ib of every pair (the boundary mirrors κ_i), at the sample, with its torque about the body's origin
/// (Akinci 2012's two-way coupling). Indexed like [`Boundary::friction`].
pub fn boundary_reactions(
    lists: &NeighborLists,
    boundary: &Boundary,
    factors: &[ParticleFactor],
    total: &[f32],
    mass: f32,
) -> Vec<BodyForceSum> {
    let bodies = boundary.body_count();
    lists.fold(
        || vec![BodyForceSum::default(); bodies],
        |mut sums, i, pairs| {
            let k = total[i] * mass;
            if k != 0.0 {
                for p in pairs.boundary {
                    let b = p.index as usize;
                    let body = boundary.body[b] as usize;
                    let k = if !factors[i].mirrors { k } else { 2.0 * k };
                    sums[body].add(p.grad * k, boundary.position[b], boundary.origin[body]);
                }
            }
            sums
        },
        |mut a, b| {
            a.iter_mut().zip(&b).for_each(|(a, b)| a.merge(b));
            a
        },
    )
}

/// DFSPH's time step: `params.time_step` when fixed; with `params.adaptive_time_step`,
/// min(time_step, λ Δx / v_max, 0.125 h² / ν): the CFL rule of the flow speed (Bender & Koschier
/// 2017, λ = `cfl_factor`, Δx the particle spacing), with no speed of sound.
pub fn dfsph_time_step(params: &SphParams, max_speed: f32) -> f32 {
    if !params.adaptive_time_step {
        return params.time_step;
    }
    let cfl = if max_speed > 0.0 {
        params.cfl_factor * params.spacing() / max_speed
    } else {
        f32::INFINITY
    };
    let dt = params.time_step.min(cfl).min(viscous_limit(params));
    if dt.is_finite() && dt > 0.0 {
        dt
    } else {
        params.time_step
    }
}
