//! The constants every stage reads, gathered once per step from [`SphParams`].

use crate::eos::Eos;
use crate::kernel::Kernels;
use crate::params::SphParams;
use glam::Vec3;

use crate::solver::dfsph::stages::DfsphStage;
use crate::solver::pbf::stages::PbfStage;
use crate::solver::wcsph::stages::WcsphStage;

/// Per-step constants shared by the density, normals and forces stages.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StageContext {
    /// Kernel constants for h.
    pub kernels: Kernels,
    /// Equation of state.
    pub eos: Eos,
    /// Particle mass m.
    pub mass: f32,
    /// Rest density ρ0.
    pub rest_density: f32,
    /// Dynamic viscosity μ.
    pub viscosity: f32,
    /// Akinci γ.
    pub surface_tension: f32,
    /// Gravity g.
    pub gravity: Vec3,
    /// The rest-lattice correction of the pressure gradient, 1 / G
    /// ([`Kernels::lattice_gradient_moment`] times m / (ρ0 Δx³)).
    pub pressure_gradient_scale: f32,
    /// The boundary samples' contact (WCSPH's forces).
    pub contact: BoundaryContact,
    /// The most pressure a free-surface particle takes from the water around it, ρ0 |g| Δx/2 [Pa]
    /// ([`crate::free_surface_pressure`]).
    pub max_surface_pressure: f32,
}

impl StageContext {
    /// The constants of `params`.
    pub fn new(params: &SphParams) -> Self {
        let kernels = Kernels::new(params.smoothing_radius);
        Self {
            kernels,
            pressure_gradient_scale: pressure_gradient_scale(params, &kernels),
            eos: Eos::from_params(params),
            mass: params.particle_mass,
            rest_density: params.rest_density,
            viscosity: params.viscosity,
            surface_tension: params.surface_tension,
            gravity: params.gravity,
            contact: BoundaryContact::of(params),
            max_surface_pressure: max_surface_pressure(params),
        }
    }

    /// The same constants for an evaluation whose next drift starts from v + a dt/2
    /// ([`BoundaryContact::drift_kick`]).
    pub fn with_half_kick_drift(mut self) -> Self {
        self.contact.drift_kick = 0.5;
        self
    }

    /// The same constants with the contact's stopping time step `dt`
    /// ([`BoundaryContact::time_step`]; non-positive or non-finite values keep dt_max).
    pub fn with_step_dt(mut self, dt: f32) -> Self {
        if dt.is_finite() && dt > 0.0 {
            self.contact.time_step = dt;
        }
        self
    }
}

/// The most pressure a free-surface particle takes from the water around it
/// ([`crate::free_surface_pressure`]): ρ0 |g| Δx/2 [Pa], what the top row holds at rest (half a
/// spacing of water above its centre). Without gravity it is 0 and the surface keeps its clamped
/// pressure.
pub fn max_surface_pressure(params: &SphParams) -> f32 {
    0.5 * params.rest_density * params.gravity.length() * params.spacing()
}

/// The boundary samples' contact: a sample closer to a particle than the particle spacing Δx
/// (where the rest lattice puts the nearest one) pushes it away with the pressure
/// p_c = 2 ρ0 c0² s² (1 + (8 s)⁴), s = 1 - r/Δx,
/// in the mirrored pressure force's form ([`Self::push`]). The pushes of a particle's samples are
/// summed, and the sum is scaled so that it stops the particle's approach within the step and
/// never throws it back ([`Self::stopping_scale`], a perfectly inelastic contact; pushing both
/// ways shook the hydrostatic tank's top rows). ρ0 c0² is the equation of state's bulk modulus
/// at rest; the square leaves a lattice pressed a few percent closer almost alone (the
/// hydrostatic tank, the time step) and grows where a particle reaches the surface, r ≈ Δx/2 on
/// a face and 0.7 Δx at an edge. The factor 1 + (8 s)⁴ is 2 at r = 7/8 Δx and 257 at Δx/2: with
/// s² alone a splash driven at a wall met too weak a push to stop it in time, and 3 particles of
/// `obstacles` ended up to 0.3 mm inside the walls (the same profile ×16 throughout stops them
/// but shakes the tank's wall rows). The mirrored pressure alone vanishes where a splashing
/// particle's own pressure is clamped to zero: a thin sheet then slid into the walls and over a
/// box's convex edges (7,329 guard corrections in `sph-bench run --scenario obstacles`). It acts
/// in WCSPH's forces only: in DFSPH's non-pressure forces it took that run's corrections from
/// 11,086 to 312, but a body heavier than water then settled onto a trapped layer of water
/// (docs/boundary.md). A short-range repulsion in
/// the spirit of Monaghan 1994's boundary force; the factor 2, the square and the stopping were
/// chosen from measurements (docs/boundary.md, "The samples' contact").
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BoundaryContact {
    /// The range Δx [m].
    pub radius: f32,
    /// The pressure at r = 0, 2 ρ0 c0² [Pa].
    pub modulus: f32,
    /// The time step the contact stops approaches within [s] ([`Self::stopping_scale`]): dt_max
    /// in an evaluation that comes before the step's dt is chosen, the step's dt in the closing
    /// evaluation of kick-drift-kick and the leapfrog ([`StageContext::with_step_dt`]). Never the
    /// previous step's: the state alone decides the step.
    pub time_step: f32,
    /// The share of this evaluation's acceleration that the velocity of the next drift takes
    /// (the solids' speculative contact, [`crate::boundary::speculative_contact`]): 1 where the drift
    /// starts from v + a dt (kick-drift-kick's closing evaluation, symplectic Euler), 1/2 where
    /// it starts from v + a dt/2 (the leapfrog's first evaluation, kick-drift-kick's first when
    /// its forces were stale; [`StageContext::with_half_kick_drift`]).
    pub drift_kick: f32,
}

impl BoundaryContact {
    /// The contact of `params`: its spacing and ρ0 c0² ([`SphParams::speed_of_sound`]).
    pub fn of(params: &SphParams) -> Self {
        Self {
            radius: params.spacing(),
            modulus: 2.0 * params.rest_density * params.speed_of_sound().powi(2),
            time_step: params.time_step,
            drift_kick: 1.0,
        }
    }

    /// The factor in [0, 1] that scales a particle's summed contact acceleration `push` so that
    /// the contact stops the approach and never reverses it (a perfectly inelastic contact):
    /// with `v_rel` the particle's velocity relative to the samples and `a_other` every other
    /// acceleration on it, the contact's velocity change over dt ([`Self::time_step`]) along
    /// n = push/|push| is at most the approach speed the step would otherwise end with,
    /// -(v_rel + a_other dt)·n.
    #[inline]
    pub fn stopping_scale(&self, push: Vec3, v_rel: Vec3, a_other: Vec3) -> f32 {
        let magnitude = push.length();
        if !magnitude.is_finite() || magnitude <= 0.0 {
            return 0.0;
        }
        let approach = -(v_rel + a_other * self.time_step).dot(push) / magnitude;
        (approach / (magnitude * self.time_step)).clamp(0.0, 1.0)
    }

    /// Sample b's contact acceleration on particle i before [`Self::stopping_scale`]:
    /// -ρ0 V_b (p_c/ρ0²) ∇W_spiky(r) / G, the mirrored pressure force's form with p_c alone
    /// (r = x_i - x_b; zero beyond Δx).
    #[inline]
    pub fn push(&self, ctx: &StageContext, r: Vec3, r_len: f32, volume: f32) -> Vec3 {
        let p_c = self.pressure(r_len);
        if p_c <= 0.0 {
            return Vec3::ZERO;
        }
        ctx.kernels.spiky_grad(r, r_len)
            * (-volume * p_c * ctx.pressure_gradient_scale / ctx.rest_density)
    }

    /// p_c at distance `r` from a sample [Pa]: 2 ρ0 c0² s² (1 + (8 s)⁴) with s = 1 - r/Δx within
    /// Δx, else 0.
    #[inline]
    pub fn pressure(&self, r: f32) -> f32 {
        let s = (1.0 - r / self.radius).max(0.0);
        let s2 = s * s;
        let steep = 64.0 * s2;
        self.modulus * s2 * (1.0 + steep * steep)
    }
}

/// 1 / G, the rest-lattice correction of the pressure gradient for `params` (see
/// [`Kernels::lattice_gradient_moment`]).
pub fn pressure_gradient_scale(params: &SphParams, kernels: &Kernels) -> f32 {
    let spacing = params.spacing();
    let volume_scale = params.particle_mass / (params.rest_density * spacing.powi(3));
    let moment = kernels.lattice_gradient_moment(spacing) * volume_scale;
    if moment.is_finite() && moment > 0.0 {
        1.0 / moment
    } else {
        1.0
    }
}

/// The stages of the CPU solver, in pipeline order. The GPU stage registry
/// (`bevy_sph_fluid::render::stages`) names one of these as the CPU twin of each of its passes;
/// several GPU passes may share a twin (count cells, prefix sum and scatter are the CPU's sort).
/// The stages every solver may run are variants here; each solver's own stages are its enum, in
/// its folder, and each solver lists its step's stages there (`step_stages`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum CpuStage {
    /// The time-step rule, the stability check and rollback ([`crate::stability`],
    /// [`crate::rollback`]).
    TimeStep,
    /// Neighbour sort: cell counts, offsets and the reorder ([`crate::neighbor`]).
    Sort,
    /// The step's neighbour lists (PBF and DFSPH: the pairs within h,
    /// [`crate::neighbor::lists::NeighborLists::rebuild`]).
    NeighborLists,
    /// Akinci 2013 normals ([`crate::surface_tension_akinci2013`]).
    Normals,
    /// Accelerations ([`crate::forces`]).
    Forces,
    /// Integration phases ([`crate::integrate`]).
    Integrate,
    /// Whitewater's diffuse particles after a step ([`crate::whitewater::ihmsen2012`]).
    Whitewater,
    /// The bodies the water carries, advanced with it ([`crate::bodies`]).
    Bodies,
    /// WCSPH's own stages.
    Wcsph(WcsphStage),
    /// DFSPH's own stages.
    Dfsph(DfsphStage),
    /// PBF's own stages.
    Pbf(PbfStage),
}
