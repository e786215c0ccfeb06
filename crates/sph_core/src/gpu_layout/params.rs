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
use glam::UVec3;

/// The uniform block every pass reads (WGSL `SphUniforms`, the same names in the same order).
/// Every field is a 4-byte scalar, a 3-vector that starts a 16-byte row and is followed by a
/// scalar, or (last) an array of 16-byte rows, so WGSL's uniform layout and this `repr(C)`
/// layout agree; the shader tests compare every field's offset.
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
    /// Grid cells along x, y, z.
    pub grid_dims: [u32; 3],
    /// The padded sort length (hash mode, a power of two).
    pub sort_length: u32,
    /// Grid origin (the box minimum) [m].
    pub grid_origin: [f32; 3],
    /// Grid cell size, h [m].
    pub cell_size: f32,
    /// Box minimum [m].
    pub box_min: [f32; 3],
    /// Wall damping.
    pub wall_damping: f32,
    /// Box maximum [m].
    pub box_max: [f32; 3],
    /// The fixed time step dt [s] (`SphParams::time_step`).
    pub fixed_dt: f32,
    /// Gravity [m/s²].
    pub gravity: [f32; 3],
    /// Particle mass m [kg].
    pub particle_mass: f32,
    /// Smoothing radius h [m].
    pub h: f32,
    /// h² [m²].
    pub h_squared: f32,
    /// poly6's constant, 315/(64π h⁹).
    pub poly6_scale: f32,
    /// ∇poly6's constant, -945/(32π h⁹).
    pub poly6_grad: f32,
    /// ∇spiky's constant, -45/(π h⁶), times the pressure-gradient correction of
    /// [`crate::stage::StageContext`].
    pub spiky_grad: f32,
    /// ∇²viscosity's constant, 45/(π h⁶).
    pub viscosity_laplacian: f32,
    /// Akinci's cohesion constant, 32/(π h⁹).
    pub cohesion: f32,
    /// The cohesion kernel's offset, h⁶/64.
    pub cohesion_offset: f32,
    /// Rest density ρ0 [kg/m³].
    pub rest_density: f32,
    /// Stiffness k.
    pub stiffness: f32,
    /// Dynamic viscosity μ.
    pub viscosity: f32,
    /// Surface tension γ.
    pub surface_tension: f32,
    /// Equation of state: 1 Tait, 0 linear.
    pub tait: u32,
    /// Clamp negative pressure (0/1).
    pub clamp_negative_pressure: u32,
    /// Adaptive time step (0/1).
    pub adaptive_time_step: u32,
    /// Colliders in the guard's list ([`Self::with_boundary`]).
    pub guard_colliders: u32,
    /// The time-step rule's largest dt [s].
    pub max_dt: f32,
    /// CFL factor λ.
    pub cfl_factor: f32,
    /// The viscous limit 0.125 h² ρ0/μ [s] (f32::MAX without viscosity).
    pub viscous_limit: f32,
    /// Speed of sound c0 [m/s].
    pub speed_of_sound: f32,
    /// Rollback ([`crate::rollback`]) on (1) or off (0); all four rollback fields are zero until
    /// [`Self::with_rollback`].
    pub rollback_enabled: u32,
    /// Steps between checkpoints.
    pub checkpoint_interval: u32,
    /// Retries before a step is given up.
    pub max_retries: u32,
    /// Steps at a reduced dt after a rollback.
    pub recovery_steps: u32,
    /// Real-time mode ([`crate::frame_budget`]): the frame's time [s] as f32 bits; the budget
    /// fields are zero (off) until [`Self::with_frame_budget`].
    pub budget_time_bits: u32,
    /// The steps planned for the frame (0: no budget).
    pub budget_steps: u32,
    /// The frame's number (a new number starts a new budget).
    pub budget_frame: u32,
    /// The water's reactions on the boundary bodies are summed (1) or not (0): some collider is
    /// in the guard's list ([`Self::with_boundary`]), or the app reads the walls' force
    /// ([`Self::with_wall_force`]). Without a reader the passes skip the sums.
    pub sum_reactions: u32,
    /// PBF ([`crate::solver::pbf::macklin2013::PbfContext`]): the cubic spline's value constant k.
    pub pbf_cubic_k: f32,
    /// PBF: the cubic spline's gradient constant l.
    pub pbf_cubic_l: f32,
    /// PBF: the relaxation ε [1/m²].
    pub pbf_relaxation: f32,
    /// PBF: s_corr's k in λ's units.
    pub pbf_s_corr_k: f32,
    /// PBF: 1 / W(Δq).
    pub pbf_inverse_w_dq: f32,
    /// PBF: XSPH's c.
    pub pbf_xsph_c: f32,
    /// PBF: vorticity confinement's ε [m/s].
    pub pbf_vorticity_epsilon: f32,
    /// PBF: the correction cap before the step's gravity term
    /// ([`crate::solver::pbf::macklin2013::MAX_CORRECTION`] h) [m].
    pub pbf_max_correction: f32,
    /// PBF: s_corr's n.
    pub pbf_s_corr_n: u32,
    /// PBF: Jacobi iterations per step.
    pub pbf_iterations: u32,
    /// PBF: the neighbour lists' length, [`PBF_MAX_NEIGHBORS`].
    pub pbf_max_neighbors: u32,
    /// PBF: the over-relaxation ω as f32 bits.
    pub pbf_over_relaxation_bits: u32,
    /// DFSPH ([`crate::solver::dfsph::bender2017`]): the largest mean density error (a fraction of
    /// ρ0).
    pub dfsph_max_density_error: f32,
    /// DFSPH: the largest mean divergence error [1/s].
    pub dfsph_max_divergence_error: f32,
    /// DFSPH: the cut-off of an isolated particle's factor (a fraction of the rest lattice's D).
    pub dfsph_factor_epsilon: f32,
    /// DFSPH: warm start (1) or not (0).
    pub dfsph_warm_start: f32,
    /// DFSPH: the constant-density solve's least iterations.
    pub dfsph_min_density_iterations: u32,
    /// DFSPH: the constant-density solve's most iterations.
    pub dfsph_max_density_iterations: u32,
    /// DFSPH: the divergence-free solve's least iterations.
    pub dfsph_min_divergence_iterations: u32,
    /// DFSPH: the divergence-free solve's most iterations.
    pub dfsph_max_divergence_iterations: u32,
    /// The spacing Δx [m] (DFSPH's CFL rule's length).
    pub spacing: f32,
    /// DFSPH: the constant-density solve's warm start fraction
    /// ([`crate::solver::dfsph::bender2017::DENSITY_WARM_START`]).
    pub dfsph_density_warm_start: f32,
    /// DFSPH: the divergence-free solve's warm start fraction
    /// ([`crate::solver::dfsph::bender2017::DIVERGENCE_WARM_START`]).
    pub dfsph_divergence_warm_start: f32,
    /// DFSPH: the largest correction per step
    /// ([`crate::solver::dfsph::bender2017::MAX_CORRECTION`]).
    pub dfsph_max_correction: f32,
    /// Drains: the main world's frame number, recorded with each sort's tail
    /// ([`Self::with_drains`]).
    pub drain_frame: u32,
    /// Drains: the open drains in [`GpuPumps`](crate::gpu_layout::GpuPumps) (0 = none).
    pub open_drains: u32,
    /// PBF: the weight of each Jacobi iteration's λ ([`crate::PbfSettings::jacobi_weight`]).
    pub pbf_jacobi_weight: f32,
    /// Unused (keeps the block in 16-byte rows).
    pub drains_unused_w: u32,
    /// DFSPH: the divergence-free solve's over-relaxation ω
    /// ([`crate::DfsphSettings::divergence_over_relaxation`]).
    pub dfsph_divergence_over_relaxation: f32,
    /// DFSPH: the constant-density solve's over-relaxation ω
    /// ([`crate::DfsphSettings::density_over_relaxation`]).
    pub dfsph_density_over_relaxation: f32,
    /// 1 when some boundary sample has friction, else 0 ([`Self::with_boundary`]: without one
    /// DFSPH's forces pass skips the samples and the reactions' workgroup sums, which only
    /// friction feeds there).
    pub boundary_friction: f32,
    /// 1 while the boundary samples do not mirror DFSPH's stiffness, else 0
    /// ([`GpuBoundarySamples::mirrors`](crate::gpu_layout::GpuBoundarySamples::mirrors), from
    /// [`Self::with_boundary`]).
    pub unmirrored_samples: f32,
    /// The boundary samples' contact ([`crate::stage::BoundaryContact`]): its range Δx [m].
    pub contact_radius: f32,
    /// The contact's pressure at r = 0, 2 ρ0 c0² [Pa].
    pub contact_modulus: f32,
    /// The free surface's largest pressure ρ0 |g| Δx/2 [Pa]
    /// ([`crate::stage::max_surface_pressure`]).
    pub max_surface_pressure: f32,
    /// The speculative contact's margin from the solids' surfaces [m]
    /// ([`crate::boundary::speculative_contact::SURFACE_MARGIN`] Δx).
    pub surface_margin: f32,
    /// Whitewater (Ihmsen et al. 2012, [`crate::whitewater`]): the trapped-air potential's
    /// limits τ_min, τ_max [m/s] ([`Self::with_whitewater`]; zero while whitewater is off).
    pub whitewater_trapped_air_min: f32,
    /// τ_max of the trapped-air potential [m/s].
    pub whitewater_trapped_air_max: f32,
    /// τ_min of the wave-crest potential.
    pub whitewater_wave_crest_min: f32,
    /// τ_max of the wave-crest potential.
    pub whitewater_wave_crest_max: f32,
    /// τ_min of the kinetic-energy potential [J/kg].
    pub whitewater_kinetic_min: f32,
    /// τ_max of the kinetic-energy potential [J/kg].
    pub whitewater_kinetic_max: f32,
    /// k_ta [1/s].
    pub whitewater_trapped_air_rate: f32,
    /// k_wc [1/s].
    pub whitewater_wave_crest_rate: f32,
    /// A diffuse particle with fewer fluid neighbours is spray.
    pub whitewater_spray_below: u32,
    /// A diffuse particle with more fluid neighbours is a bubble.
    pub whitewater_bubble_above: u32,
    /// The shortest foam lifetime drawn at birth [s].
    pub whitewater_lifetime_min: f32,
    /// The longest foam lifetime drawn at birth [s].
    pub whitewater_lifetime_max: f32,
    /// Bubbles' buoyancy k_b.
    pub whitewater_buoyancy: f32,
    /// Bubbles' drag k_d.
    pub whitewater_drag: f32,
    /// The diffuse pool's slots (0: whitewater off).
    pub whitewater_capacity: u32,
    /// The seed of the shedding's random numbers.
    pub whitewater_seed: u32,
    /// The steps of the frame the whitewater stages cover: they run once a frame, in its last
    /// step, for this many steps' dt ([`Self::with_whitewater`]).
    pub whitewater_steps: u32,
    /// The boundary samples uploaded (the bodies' placement moves those of moved bodies;
    /// `bevy_sph_fluid::render::bodies`).
    pub boundary_sample_count: u32,
    /// Unused.
    pub whitewater_unused_z: u32,
    /// Unused.
    pub whitewater_unused_w: u32,
    /// Where each packed storage buffer starts in its arena, in elements, at index `Buf as
    /// usize` (`bevy_sph_fluid::render::arenas`): four to a 16-byte row, so the uniform layout
    /// has no padding. WGSL reads it through `sph::bindings`'s `*_at` functions.
    pub buffer_at: [[u32; 4]; BUFFER_AT_ROWS],
}

/// The rows of [`GpuSphParams::buffer_at`]: room for 48 storage buffers.
pub const BUFFER_AT_ROWS: usize = 12;

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
        let contact = crate::stage::BoundaryContact::of(params);
        Self {
            particle_count,
            capacity,
            cell_count: dims.x * dims.y * dims.z,
            table_size: hash_table_size(capacity as usize) as u32,
            grid_dims: dims.to_array(),
            sort_length: sort_length(capacity),
            grid_origin: lo.to_array(),
            cell_size: params.smoothing_radius,
            box_min: lo.to_array(),
            wall_damping: params.wall_damping,
            box_max: hi.to_array(),
            fixed_dt: params.time_step,
            gravity: params.gravity.to_array(),
            particle_mass: params.particle_mass,
            h: k.h,
            h_squared: k.h2,
            poly6_scale: k.poly6,
            poly6_grad: k.poly6_grad,
            // The pressure force's gradient constant, with the rest-lattice correction.
            spiky_grad: k.spiky_grad * crate::stage::pressure_gradient_scale(params, &k),
            viscosity_laplacian: k.viscosity_laplacian,
            cohesion: k.cohesion,
            cohesion_offset: k.cohesion_offset,
            rest_density: params.rest_density,
            stiffness: params.stiffness,
            viscosity: params.viscosity,
            surface_tension: params.surface_tension,
            tait: (params.equation_of_state == EquationOfState::Tait) as u32,
            clamp_negative_pressure: params.clamp_negative_pressure as u32,
            adaptive_time_step: params.adaptive_time_step as u32,
            guard_colliders: 0,
            max_dt: params.time_step,
            cfl_factor: params.cfl_factor,
            viscous_limit: crate::stability::viscous_limit(params).min(f32::MAX),
            speed_of_sound: params.speed_of_sound(),
            rollback_enabled: 0,
            checkpoint_interval: 0,
            max_retries: 0,
            recovery_steps: 0,
            budget_time_bits: 0,
            budget_steps: 0,
            budget_frame: 0,
            sum_reactions: 0,
            pbf_cubic_k: pbf.kernel.k,
            pbf_cubic_l: pbf.kernel.l,
            pbf_relaxation: pbf.epsilon,
            pbf_s_corr_k: pbf.s_corr_k,
            pbf_inverse_w_dq: pbf.inverse_w_dq,
            pbf_xsph_c: pbf.xsph_c,
            pbf_vorticity_epsilon: pbf.vorticity_epsilon,
            pbf_max_correction: pbf.max_correction,
            pbf_s_corr_n: pbf.s_corr_n.max(0) as u32,
            pbf_iterations: params.pbf.iterations,
            pbf_max_neighbors: PBF_MAX_NEIGHBORS,
            pbf_over_relaxation_bits: pbf.over_relaxation.to_bits(),
            dfsph_max_density_error: d.max_density_error,
            dfsph_max_divergence_error: d.max_divergence_error,
            dfsph_factor_epsilon: crate::solver::dfsph::bender2017::FACTOR_EPSILON
                * rest_lattice_factor(params),
            dfsph_warm_start: d.warm_start as u32 as f32,
            dfsph_min_density_iterations: d.min_density_iterations,
            dfsph_max_density_iterations: d.max_density_iterations,
            dfsph_min_divergence_iterations: d.min_divergence_iterations,
            dfsph_max_divergence_iterations: d.max_divergence_iterations,
            spacing: params.spacing(),
            dfsph_density_warm_start: crate::solver::dfsph::bender2017::DENSITY_WARM_START,
            dfsph_divergence_warm_start: crate::solver::dfsph::bender2017::DIVERGENCE_WARM_START,
            dfsph_max_correction: crate::solver::dfsph::bender2017::MAX_CORRECTION,
            drain_frame: 0,
            open_drains: 0,
            pbf_jacobi_weight: pbf.jacobi_weight,
            drains_unused_w: 0,
            dfsph_divergence_over_relaxation: d.divergence_over_relaxation,
            dfsph_density_over_relaxation: d.density_over_relaxation,
            boundary_friction: 0.0,
            unmirrored_samples: 0.0,
            contact_radius: contact.radius,
            contact_modulus: contact.modulus,
            max_surface_pressure: crate::stage::max_surface_pressure(params),
            surface_margin: crate::boundary::speculative_contact::SURFACE_MARGIN * contact.radius,
            whitewater_trapped_air_min: 0.0,
            whitewater_trapped_air_max: 0.0,
            whitewater_wave_crest_min: 0.0,
            whitewater_wave_crest_max: 0.0,
            whitewater_kinetic_min: 0.0,
            whitewater_kinetic_max: 0.0,
            whitewater_trapped_air_rate: 0.0,
            whitewater_wave_crest_rate: 0.0,
            whitewater_spray_below: 0,
            whitewater_bubble_above: 0,
            whitewater_lifetime_min: 0.0,
            whitewater_lifetime_max: 0.0,
            whitewater_buoyancy: 0.0,
            whitewater_drag: 0.0,
            whitewater_capacity: 0,
            whitewater_seed: 0,
            whitewater_steps: 0,
            boundary_sample_count: 0,
            whitewater_unused_z: 0,
            whitewater_unused_w: 0,
            // Set by the plugin from its arenas' layout.
            buffer_at: [[0; 4]; BUFFER_AT_ROWS],
        }
    }

    /// The same block with whitewater on: `settings`, a pool of `capacity` diffuse particles,
    /// the shedding's `seed`, and the frame's `steps` (the stages run once, for all of them).
    pub fn with_whitewater(
        mut self,
        settings: &crate::whitewater::settings::WhitewaterSettings,
        capacity: u32,
        seed: u32,
        steps: u32,
    ) -> Self {
        let s = settings;
        self.whitewater_trapped_air_min = s.trapped_air.min;
        self.whitewater_trapped_air_max = s.trapped_air.max;
        self.whitewater_wave_crest_min = s.wave_crest.min;
        self.whitewater_wave_crest_max = s.wave_crest.max;
        self.whitewater_kinetic_min = s.kinetic_energy.min;
        self.whitewater_kinetic_max = s.kinetic_energy.max;
        self.whitewater_trapped_air_rate = s.trapped_air_rate;
        self.whitewater_wave_crest_rate = s.wave_crest_rate;
        self.whitewater_spray_below = s.spray_below;
        self.whitewater_bubble_above = s.bubble_above;
        self.whitewater_lifetime_min = s.lifetime.0;
        self.whitewater_lifetime_max = s.lifetime.1;
        self.whitewater_buoyancy = s.buoyancy;
        self.whitewater_drag = s.drag;
        self.whitewater_capacity = capacity;
        self.whitewater_seed = seed;
        self.whitewater_steps = steps.max(1);
        self
    }

    /// The same block with a frame budget: `duration` seconds split among `steps` steps on the
    /// device, for the frame numbered `frame`.
    pub fn with_frame_budget(mut self, duration: f32, steps: u32, frame: u32) -> Self {
        self.budget_time_bits = duration.to_bits();
        self.budget_steps = steps;
        self.budget_frame = frame;
        self
    }

    /// The same block with what the boundary upload knows: the colliders in the guard's list,
    /// whether some boundary sample has friction and whether the samples do not mirror DFSPH's
    /// stiffness (1 or 0).
    pub fn with_boundary(mut self, colliders: u32, friction: bool, unmirrored: bool) -> Self {
        self.guard_colliders = colliders;
        self.sum_reactions |= (colliders > 0) as u32;
        self.boundary_friction = if friction { 1.0 } else { 0.0 };
        self.unmirrored_samples = if unmirrored { 1.0 } else { 0.0 };
        self
    }

    /// The same block with the walls' force summed when `read` (the app reads it), besides the
    /// colliders' ([`Self::sum_reactions`]).
    pub fn with_wall_force(mut self, read: bool) -> Self {
        self.sum_reactions |= read as u32;
        self
    }

    /// The same block with the drains' frame: the main world's frame `number` and the open
    /// drains in [`GpuPumps`](crate::gpu_layout::GpuPumps) (0 = none).
    pub fn with_drains(mut self, number: u32, open: u32) -> Self {
        self.drain_frame = number;
        self.open_drains = open;
        self
    }

    /// The same block with the rollback settings of `rollback`.
    pub fn with_rollback(mut self, rollback: &crate::rollback::Rollback) -> Self {
        self.rollback_enabled = rollback.enabled as u32;
        self.checkpoint_interval = rollback.checkpoint_interval;
        self.max_retries = rollback.max_retries;
        self.recovery_steps = crate::rollback::RECOVERY_STEPS;
        self
    }
}
