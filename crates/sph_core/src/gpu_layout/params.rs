//! The uniform block every pass reads (WGSL `SphUniforms`), built from the parameters.

use crate::container::BoxContainer;
use crate::gpu_layout::particles::*;
use crate::gpu_layout::sizes::*;
use crate::kernel::Kernels;
use crate::neighbor::grid::DenseGrid;
use crate::neighbor::hash::hash_table_size;
use crate::params::{EquationOfState, ParamError, SphParams};
use crate::solver::dfsph::bender2017::rest_lattice_factor;
use crate::solver::pbf::macklin2013::PbfContext;
use bytemuck::{Pod, Zeroable};
use glam::{UVec3, Vec3};

/// The uniform block every pass reads (WGSL `SphUniforms`). All fields are 4-byte scalars or
/// 16-byte vectors in groups of four, so std140 and the Rust layout agree.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuSphParams {
    /// Live particles.
    pub particle_count: u32,
    /// Particle slots in every buffer.
    pub capacity: u32,
    /// Dense-grid cells (grid mode).
    pub cell_count: u32,
    /// Spatial-hash buckets (hash mode).
    pub table_size: u32,
    /// Grid cells along x, y, z; w = padded sort length (hash mode, a power of two).
    pub grid_dims: [u32; 4],
    /// Grid origin (box minimum); w = cell size h.
    pub grid_origin: [f32; 4],
    /// Box minimum; w = wall damping.
    pub box_min: [f32; 4],
    /// Box maximum; w = time step dt.
    pub box_max: [f32; 4],
    /// Gravity; w = particle mass.
    pub gravity: [f32; 4],
    /// h, h², poly6 and ∇poly6 constants.
    pub kernel_a: [f32; 4],
    /// ∇spiky (times the pressure-gradient correction of [`crate::stage::StageContext`]),
    /// ∇²viscosity, cohesion and cohesion offset constants.
    pub kernel_b: [f32; 4],
    /// ρ0, stiffness k, viscosity μ, surface tension γ.
    pub material: [f32; 4],
    /// Equation of state (0 linear, 1 Tait), clamp negative pressure (0/1), adaptive time step
    /// (0/1), colliders in the guard's list ([`Self::with_boundary`]).
    pub flags: [u32; 4],
    /// The time-step rule: largest dt, CFL factor λ, viscous limit 0.125 h² ρ0/μ (f32::MAX
    /// without viscosity), speed of sound c0.
    pub time_step: [f32; 4],
    /// Rollback ([`crate::rollback`]): enabled (0/1), checkpoint interval, max retries, recovery
    /// steps. All zero (off) until [`Self::with_rollback`].
    pub rollback: [u32; 4],
    /// Real-time mode ([`crate::frame_budget`]): the frame's time [s] as f32 bits, the steps
    /// planned for it, the frame's number (a new number starts a new budget), 0. All zero (off)
    /// until [`Self::with_frame_budget`].
    pub frame_budget: [u32; 4],
    /// PBF ([`crate::solver::pbf::macklin2013::PbfContext`]): the cubic spline's value and gradient
    /// constants k and l, the relaxation ε [1/m²], s_corr's k in λ's units.
    pub pbf_kernel: [f32; 4],
    /// PBF: 1 / W(Δq), XSPH c, vorticity ε [m/s], the correction cap before the step's
    /// gravity term ([`crate::solver::pbf::macklin2013::MAX_CORRECTION`] h) [m].
    pub pbf: [f32; 4],
    /// PBF: s_corr's n, the Jacobi iterations per step, [`PBF_MAX_NEIGHBORS`], the
    /// over-relaxation ω as f32 bits.
    pub pbf_counts: [u32; 4],
    /// DFSPH ([`crate::solver::dfsph::bender2017`]): the largest mean density error (fraction of ρ0),
    /// the largest mean divergence error [1/s], the cut-off of an isolated particle's factor
    /// (a fraction of the rest lattice's D), warm start (1) or not (0).
    pub dfsph: [f32; 4],
    /// DFSPH: min and max constant-density iterations, min and max divergence-free iterations.
    pub dfsph_counts: [u32; 4],
    /// DFSPH: the spacing Δx [m] (the CFL rule's length), the warm starts' fractions
    /// ([`crate::solver::dfsph::bender2017::DENSITY_WARM_START`], [`crate::solver::dfsph::bender2017::DIVERGENCE_WARM_START`]),
    /// [`crate::solver::dfsph::bender2017::MAX_CORRECTION`].
    pub dfsph_b: [f32; 4],
    /// Drains: the main world's frame number (recorded with each sort's tail), the open drains
    /// in [`GpuPumps`] (0 = none), 0, 0.
    pub drains: [u32; 4],
    /// DFSPH: the over-relaxation ω of the divergence-free solve
    /// ([`crate::DfsphSettings::divergence_over_relaxation`]) and of the constant-density solve
    /// ([`crate::DfsphSettings::density_over_relaxation`]); 1 when some boundary sample has
    /// friction, else 0 ([`Self::with_boundary`]: without one DFSPH's forces pass skips the
    /// samples and the reactions' workgroup sums, which only friction feeds there);
    /// 1 while the boundary samples do not mirror the stiffness, else 0
    /// ([`GpuBoundarySamples::mirrors`](crate::gpu_layout::GpuBoundarySamples::mirrors), also from
    /// the upload).
    pub dfsph_c: [f32; 4],
    /// The boundary samples' contact ([`crate::stage::BoundaryContact`]): its range Δx [m],
    /// its pressure at r = 0, 2 ρ0 c0² [Pa]; the free surface's largest pressure ρ0 |g| Δx/2 [Pa]
    /// ([`crate::stage::max_surface_pressure`]); the speculative contact's margin from the
    /// solids' surfaces [m] ([`crate::boundary::speculative_contact::SURFACE_MARGIN`] Δx).
    pub boundary_contact: [f32; 4],
}

impl GpuSphParams {
    /// The uniform block for `params` in `container`, `capacity` slots and `particle_count` live
    /// particles. Fails like [`DenseGrid::new`] when the grid would be too large.
    pub fn new(
        params: &SphParams,
        container: &BoxContainer,
        capacity: u32,
        particle_count: u32,
    ) -> Result<Self, ParamError> {
        let grid = DenseGrid::new(container, params.smoothing_radius)?;
        Ok(Self::with_grid(
            params,
            container,
            grid.dims,
            capacity,
            particle_count,
        ))
    }

    /// As [`Self::new`] with precomputed grid dimensions.
    pub fn with_grid(
        params: &SphParams,
        container: &BoxContainer,
        dims: UVec3,
        capacity: u32,
        particle_count: u32,
    ) -> Self {
        let k = Kernels::new(params.smoothing_radius);
        let pbf = PbfContext::of(params);
        let d = &params.dfsph;
        let (lo, hi) = (container.min(), container.max());
        let v4 = |v: Vec3, w: f32| [v.x, v.y, v.z, w];
        Self {
            particle_count,
            capacity,
            cell_count: dims.x * dims.y * dims.z,
            table_size: hash_table_size(capacity as usize) as u32,
            grid_dims: [dims.x, dims.y, dims.z, sort_length(capacity)],
            grid_origin: v4(lo, params.smoothing_radius),
            box_min: v4(lo, params.wall_damping),
            box_max: v4(hi, params.time_step),
            gravity: v4(params.gravity, params.particle_mass),
            kernel_a: [k.h, k.h2, k.poly6, k.poly6_grad],
            kernel_b: [
                // The pressure force's gradient constant, with the rest-lattice correction.
                k.spiky_grad * crate::stage::pressure_gradient_scale(params, &k),
                k.viscosity_laplacian,
                k.cohesion,
                k.cohesion_offset,
            ],
            material: [
                params.rest_density,
                params.stiffness,
                params.viscosity,
                params.surface_tension,
            ],
            flags: [
                (params.equation_of_state == EquationOfState::Tait) as u32,
                params.clamp_negative_pressure as u32,
                params.adaptive_time_step as u32,
                0,
            ],
            time_step: [
                params.time_step,
                params.cfl_factor,
                crate::stability::viscous_limit(params).min(f32::MAX),
                params.speed_of_sound(),
            ],
            rollback: [0; 4],
            frame_budget: [0; 4],
            pbf_kernel: [pbf.kernel.k, pbf.kernel.l, pbf.epsilon, pbf.s_corr_k],
            pbf: [
                pbf.inverse_w_dq,
                pbf.xsph_c,
                pbf.vorticity_epsilon,
                pbf.max_correction,
            ],
            pbf_counts: [
                pbf.s_corr_n.max(0) as u32,
                params.pbf.iterations,
                PBF_MAX_NEIGHBORS,
                pbf.over_relaxation.to_bits(),
            ],
            dfsph: [
                d.max_density_error,
                d.max_divergence_error,
                crate::solver::dfsph::bender2017::FACTOR_EPSILON * rest_lattice_factor(params),
                d.warm_start as u32 as f32,
            ],
            dfsph_counts: [
                d.min_density_iterations,
                d.max_density_iterations,
                d.min_divergence_iterations,
                d.max_divergence_iterations,
            ],
            dfsph_b: [
                params.spacing(),
                crate::solver::dfsph::bender2017::DENSITY_WARM_START,
                crate::solver::dfsph::bender2017::DIVERGENCE_WARM_START,
                crate::solver::dfsph::bender2017::MAX_CORRECTION,
            ],
            drains: [0; 4],
            dfsph_c: [
                params.dfsph.divergence_over_relaxation,
                params.dfsph.density_over_relaxation,
                0.0,
                0.0,
            ],
            boundary_contact: {
                let contact = crate::stage::BoundaryContact::of(params);
                [
                    contact.radius,
                    contact.modulus,
                    crate::stage::max_surface_pressure(params),
                    crate::boundary::speculative_contact::SURFACE_MARGIN * contact.radius,
                ]
            },
        }
    }

    /// The same block with a frame budget: `duration` seconds split among `steps` steps on the
    /// device, for the frame numbered `frame`.
    pub fn with_frame_budget(mut self, duration: f32, steps: u32, frame: u32) -> Self {
        self.frame_budget = [duration.to_bits(), steps, frame, 0];
        self
    }

    /// The same block with what the boundary upload knows: the colliders in the guard's list
    /// (`flags`' w), whether some boundary sample has friction and whether the samples do not
    /// mirror DFSPH's stiffness (`dfsph_c`'s z and w, 1 or 0).
    pub fn with_boundary(mut self, colliders: u32, friction: bool, unmirrored: bool) -> Self {
        self.flags[3] = colliders;
        self.dfsph_c[2] = if friction { 1.0 } else { 0.0 };
        self.dfsph_c[3] = if unmirrored { 1.0 } else { 0.0 };
        self
    }

    /// The same block with the drains' frame: the main world's frame `number` and the open
    /// drains in [`GpuPumps`](crate::gpu_layout::GpuPumps) (0 = none).
    pub fn with_drains(mut self, number: u32, open: u32) -> Self {
        self.drains = [number, open, 0, 0];
        self
    }

    /// The same block with the rollback settings of `rollback`.
    pub fn with_rollback(mut self, rollback: &crate::rollback::Rollback) -> Self {
        self.rollback = [
            rollback.enabled as u32,
            rollback.checkpoint_interval,
            rollback.max_retries,
            crate::rollback::RECOVERY_STEPS,
        ];
        self
    }
}
