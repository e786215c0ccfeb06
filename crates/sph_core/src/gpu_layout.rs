//! Plain-old-data mirrors of the GPU buffers (`Gpu*`), shared by the Bevy plugin and the tests,
//! so the CPU and GPU agree on every byte. WGSL twin: `bevy_sph_fluid/src/shaders/types.wgsl`.

use crate::container::BoxContainer;
use crate::dfsph_bender2017::rest_lattice_factor;
use crate::kernel::Kernels;
use crate::neighbor::grid::DenseGrid;
use crate::neighbor::hash::hash_table_size;
use crate::params::{EquationOfState, ParamError, SphParams};
use crate::pbf_macklin2013::PbfContext;
use bytemuck::{Pod, Zeroable};
use glam::{UVec3, Vec3};

/// Workgroup size of every per-particle pass.
pub const WORKGROUP_SIZE: u32 = 64;

/// The most neighbours a particle keeps in the GPU's PBF neighbour lists (pairs within h at the
/// predicted positions). A particle has about 33 at rest density (h = 2 Δx); one with more
/// than this many (about twice the rest density) loses the rest for the step, and the clock
/// counts them ([`GpuClock::neighbor_list_overflows`]).
pub const PBF_MAX_NEIGHBORS: u32 = 64;

/// The GPU's neighbour lists (PBF's and DFSPH's) keep entry k of particle i in tiles of this
/// many particles, row by row: at `((i / LIST_TILE) * PBF_MAX_NEIGHBORS + k) * LIST_TILE +
/// i % LIST_TILE` (`list_slot` in the plugin's `shaders/neighbors.wgsl`), so that a pass over the
/// lists streams through memory on a SIMD machine such as lavapipe.
pub const LIST_TILE: u32 = 8;

/// Entries of a GPU neighbour list for `capacity` particles: whole tiles of [`LIST_TILE`]
/// particles, [`PBF_MAX_NEIGHBORS`] entries each.
pub fn list_entries(capacity: u32) -> u64 {
    capacity.next_multiple_of(LIST_TILE) as u64 * PBF_MAX_NEIGHBORS as u64
}

/// Threads of the single-workgroup prefix sum.
pub const PREFIX_SUM_THREADS: u32 = 256;

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
    /// (0/1), colliders in the guard's list (set by the plugin from the boundary upload).
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
    /// PBF ([`crate::pbf_macklin2013::PbfContext`]): the cubic spline's value and gradient
    /// constants k and l, the relaxation ε [1/m²], s_corr's k in λ's units.
    pub pbf_kernel: [f32; 4],
    /// PBF: 1 / W(Δq), XSPH c, vorticity ε [m/s], the correction cap before the step's
    /// gravity term ([`crate::pbf_macklin2013::MAX_CORRECTION`] h) [m].
    pub pbf: [f32; 4],
    /// PBF: s_corr's n, the Jacobi iterations per step, [`PBF_MAX_NEIGHBORS`], the
    /// over-relaxation ω as f32 bits.
    pub pbf_counts: [u32; 4],
    /// DFSPH ([`crate::dfsph_bender2017`]): the largest mean density error (fraction of ρ0),
    /// the largest mean divergence error [1/s], the cut-off of an isolated particle's factor
    /// (a fraction of the rest lattice's D), warm start (1) or not (0).
    pub dfsph: [f32; 4],
    /// DFSPH: min and max constant-density iterations, min and max divergence-free iterations.
    pub dfsph_counts: [u32; 4],
    /// DFSPH: the spacing Δx [m] (the CFL rule's length), the warm starts' fractions
    /// ([`crate::dfsph_bender2017::DENSITY_WARM_START`], [`crate::dfsph_bender2017::DIVERGENCE_WARM_START`]),
    /// [`crate::dfsph_bender2017::MAX_CORRECTION`].
    pub dfsph_b: [f32; 4],
    /// Drains: the main world's frame number (recorded with each sort's tail), the open drains
    /// in [`GpuPumps`] (0 = none), 0, 0.
    pub drains: [u32; 4],
    /// DFSPH: the over-relaxation ω of the divergence-free solve
    /// ([`crate::DfsphSettings::divergence_over_relaxation`]) and of the constant-density solve
    /// ([`crate::DfsphSettings::density_over_relaxation`]); 1 when some boundary sample has
    /// friction, else 0 (set by the plugin from the boundary upload: without one DFSPH's forces
    /// pass skips the samples and the reactions' workgroup sums, which only friction feeds
    /// there); 1 while the boundary samples do not mirror the stiffness, else 0
    /// ([`GpuBoundarySamples::mirrors`], also from the upload).
    pub dfsph_c: [f32; 4],
    /// The boundary samples' contact ([`crate::stage::BoundaryContact`]): its range Δx [m],
    /// its pressure at r = 0, 2 ρ0 c0² [Pa]; the free surface's largest pressure ρ0 |g| Δx/2 [Pa]
    /// ([`crate::stage::max_surface_pressure`]); the speculative contact's margin from the
    /// solids' surfaces [m] ([`crate::boundary::speculative_contact::SURFACE_MARGIN`] Δx).
    pub boundary_contact: [f32; 4],
}

/// The simulation clock (WGSL `SphClock`), a storage buffer written only by the GPU: the
/// `sph_time_step` pass chooses each step's dt from the extremes the last pass of the previous
/// step recorded, advances time and freezes the simulation when a step went unstable.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
pub struct GpuClock {
    /// dt of the step in progress or last taken [s], as f32 bits.
    pub dt_bits: u32,
    /// Steps taken since the reset.
    pub step: u32,
    /// Simulated time [ns], low and high words (exact integer sum of the steps' dt).
    pub time_ns: [u32; 2],
    /// Largest |v| of the last step, f32 bits (non-finite values compare above every finite one).
    pub max_speed_bits: u32,
    /// Largest |a| of the last step, f32 bits.
    pub max_acceleration_bits: u32,
    /// 0 while healthy; otherwise the step (1-based) detected as unstable. Frozen until reset.
    pub unstable_step: u32,
    /// What the pass after the time-step pass does with the checkpoint: 0 nothing, 1 save,
    /// 2 restore.
    pub checkpoint_action: u32,
    /// Rollbacks since the reset.
    pub rollbacks: u32,
    /// Rollbacks since the last checkpoint.
    pub retries: u32,
    /// Halvings of the rule's dt (dt scale 2^-halvings).
    pub halvings: u32,
    /// Stable steps since the last rollback or recovery.
    pub stable_steps: u32,
    /// 1 when a checkpoint exists.
    pub has_checkpoint: u32,
    /// The step count at the checkpoint.
    pub checkpoint_step: u32,
    /// Simulated time at the checkpoint [ns], low and high words.
    pub checkpoint_time_ns: [u32; 2],
    /// Particles the checkpoint holds.
    pub checkpoint_count: u32,
    /// Particles the checkpoint held before the last restore.
    pub restore_count: u32,
    /// Set by the CPU when particles were uploaded: checkpoint at the next stable step.
    pub save_requested: u32,
    /// The rule's dt before the rollback scale [s], f32 bits.
    pub rule_dt_bits: u32,
    /// The rule's dt at the checkpoint [s], f32 bits (a retry takes half of it).
    pub checkpoint_rule_dt_bits: u32,
    /// Particles the guard moved out of a collider or back into the box since the reset (see
    /// [`crate::boundary::guard`]).
    pub boundary_corrections: u32,
    /// Of those, the particles clamped back into the box.
    pub wall_corrections: u32,
    /// Real-time mode: the number of the frame whose budget is being spent.
    pub budget_frame: u32,
    /// What is left of that frame's time [s], f32 bits.
    pub budget_remaining_bits: u32,
    /// Steps left in that frame's plan.
    pub budget_steps_left: u32,
    /// PBF: particles that had more than [`PBF_MAX_NEIGHBORS`] neighbours in a step's lists
    /// (and lost the rest for that step), summed over the steps since the reset.
    pub neighbor_list_overflows: u32,
    /// DFSPH: the workgroup count of the solve's next pass, then 1, 1: the indirect dispatch
    /// arguments of the solves' passes, 0 once the solve converged (copied to the indirect
    /// buffer after each of them).
    pub dfsph_args: [u32; 3],
    /// DFSPH: 1 once the solve in progress converged.
    pub dfsph_done: u32,
    /// DFSPH: the iterations the solve in progress applied.
    pub dfsph_applied: u32,
    /// DFSPH: the mean-error sums of the solve's sources, two 64-bit fixed-point accumulators
    /// (low, high words; units of [`DFSPH_ERROR_UNIT`] ρ0 or ρ0/s) that the iterations
    /// ping-pong.
    pub dfsph_error: [u32; 4],
    /// DFSPH: constant-density iterations summed over the steps since the reset.
    pub density_iterations: u32,
    /// DFSPH: the most constant-density iterations of one step since the reset.
    pub density_iterations_max: u32,
    /// DFSPH: divergence-free iterations summed over the steps since the reset.
    pub divergence_iterations: u32,
    /// DFSPH: the last constant-density solve's mean error (fraction of ρ0), f32 bits.
    pub density_error_bits: u32,
    /// DFSPH: the last divergence-free solve's mean error [1/s], f32 bits.
    pub divergence_error_bits: u32,
    /// Drains: particles marked as drained counted by the sort under way (the sort's pass 1
    /// adds, pass 2 takes the sum and zeroes it).
    pub marked: u32,
    /// Drains: how many marked particles the last sort moved to the tail of the live range.
    pub tail_size: u32,
    /// Drains: the main world's frame number of that sort (`GpuSphParams::drains[0]`).
    pub tail_frame: u32,
    /// PBF: the Jacobi iteration under way (from 0; set by each iteration's λ pass).
    pub pbf_iteration: u32,
    /// DFSPH: the most iterations one step's constant-density and divergence-free solves took
    /// since the CPU last zeroed them (at the start of every frame with steps, so a reading
    /// holds that frame's most).
    pub dfsph_frame_max: [u32; 2],
    /// DFSPH: the constant-density and divergence-free solves that ran out of the passes the
    /// CPU encoded for them before they converged or reached their most iterations, since the
    /// reset (see `bevy_sph_fluid`'s iteration budget).
    pub dfsph_cut_short: [u32; 2],
    /// Steps the device has begun since the reset, rolled back or not: unlike `step`, it never
    /// goes back, so a readback whose `steps_run` equals the steps dispatched is current.
    pub steps_run: u32,
}

/// The unit of DFSPH's error sums on the device ([`GpuClock::dfsph_error`]): 1e-9 of ρ0 (or
/// ρ0 per second) per particle.
pub const DFSPH_ERROR_UNIT: f64 = 1.0e-9;

impl GpuClock {
    /// dt [s].
    pub fn dt(&self) -> f32 {
        f32::from_bits(self.dt_bits)
    }

    /// Simulated time [s].
    pub fn time(&self) -> f64 {
        ((self.time_ns[1] as u64) << 32 | self.time_ns[0] as u64) as f64 * 1e-9
    }

    /// Byte offset of the `save_requested` flag (written by the CPU after an upload).
    pub const SAVE_REQUESTED_OFFSET: u64 = std::mem::offset_of!(GpuClock, save_requested) as u64;

    /// Byte offset of `dfsph_args` (copied to the indirect buffer after each solve pass).
    pub const DFSPH_ARGS_OFFSET: u64 = std::mem::offset_of!(GpuClock, dfsph_args) as u64;

    /// Byte offset of `dfsph_frame_max` (zeroed by the CPU at the start of every frame).
    pub const DFSPH_FRAME_MAX_OFFSET: u64 = std::mem::offset_of!(GpuClock, dfsph_frame_max) as u64;

    /// Byte offset of `has_checkpoint` (cleared by the CPU when the buffers are reallocated).
    pub const HAS_CHECKPOINT_OFFSET: u64 = std::mem::offset_of!(GpuClock, has_checkpoint) as u64;

    /// DFSPH: solves of both kinds cut short by the encoded iterations since the reset.
    pub fn solves_cut_short(&self) -> u64 {
        self.dfsph_cut_short.iter().map(|&n| n as u64).sum()
    }

    /// The extremes the last step recorded.
    pub fn extremes(&self) -> crate::stability::StepExtremes {
        crate::stability::StepExtremes {
            max_speed: f32::from_bits(self.max_speed_bits),
            max_acceleration: f32::from_bits(self.max_acceleration_bits),
        }
    }
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
                crate::dfsph_bender2017::FACTOR_EPSILON * rest_lattice_factor(params),
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
                crate::dfsph_bender2017::DENSITY_WARM_START,
                crate::dfsph_bender2017::DIVERGENCE_WARM_START,
                crate::dfsph_bender2017::MAX_CORRECTION,
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

/// Length of the bitonic sort: the next power of two >= capacity.
pub fn sort_length(capacity: u32) -> u32 {
    capacity.max(1).next_power_of_two()
}

/// One bitonic merge step (WGSL `BitonicStep`), bound at a dynamic offset per dispatch.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuBitonicStep {
    /// Size of the bitonic sequences being merged.
    pub k: u32,
    /// Compare distance.
    pub j: u32,
    /// Padding.
    pub pad: [u32; 2],
}

/// The (k, j) steps of a bitonic sort of `n` (a power of two) keys: log2(n)(log2(n)+1)/2 steps.
pub fn bitonic_steps(n: u32) -> Vec<GpuBitonicStep> {
    let mut steps = Vec::new();
    let mut k = 2;
    while k <= n {
        let mut j = k / 2;
        while j > 0 {
            steps.push(GpuBitonicStep { k, j, pad: [0; 2] });
            j /= 2;
        }
        k *= 2;
    }
    steps
}

/// The 4-byte word stored in a position's w component: the particle id, bit-cast to f32.
pub fn id_to_w(id: u32) -> f32 {
    f32::from_bits(id)
}

/// The bit of a position's w that marks a particle a drain took (the GPU backend's drains: it
/// stays in the live range, sorted to its tail, until the main world lowers its count).
pub const DRAINED_BIT: u32 = 1 << 31;

/// The particle id stored in a position's w component (without the drained mark).
pub fn w_to_id(w: f32) -> u32 {
    w.to_bits() & !DRAINED_BIT
}

/// A collider as the GPU guard reads it (WGSL `GpuCollider`): where it is, its shape and its
/// velocity. Rust twin: [`crate::boundary::collider::Collider`].
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuCollider {
    /// Translation [m]; w = shape kind (0 cuboid, 1 sphere, 2 capsule, 3 cylinder, 4 mesh).
    pub translation: [f32; 4],
    /// Rotation quaternion (x, y, z, w).
    pub rotation: [f32; 4],
    /// Cuboid: half extents; sphere: (radius, 0, 0); capsule and cylinder: (radius,
    /// half_length, 0); mesh: (first node word, first triangle word, both bit-cast u32, half
    /// thickness or -1 when closed); w = bounding radius.
    pub size: [f32; 4],
    /// Linear velocity [m/s] (zero for static colliders); w = the collider's body index in
    /// the reactions (slot + 1, [`crate::boundary::samples::WALLS_BODY`] being 0), as u32 bits.
    pub linear_velocity: [f32; 4],
    /// Angular velocity [rad/s].
    pub angular_velocity: [f32; 4],
}

impl GpuCollider {
    /// The GPU form of `c`, body `body` in the reactions; a mesh's words start at `mesh_offset`
    /// in [`GpuBoundarySamples::meshes`].
    pub fn of(c: &crate::boundary::collider::Collider, mesh_offset: u32, body: u32) -> Self {
        use crate::boundary::collider::{ColliderMotion, ColliderShape};
        let (kind, size) = match c.shape {
            ColliderShape::Cuboid { half_extents } => (0.0, half_extents),
            ColliderShape::Sphere { radius } => (1.0, Vec3::new(radius, 0.0, 0.0)),
            ColliderShape::Capsule {
                radius,
                half_length,
            } => (2.0, Vec3::new(radius, half_length, 0.0)),
            ColliderShape::Cylinder {
                radius,
                half_length,
            } => (3.0, Vec3::new(radius, half_length, 0.0)),
            // Nodes from the offset, triangles after them, the shell's half thickness (-1:
            // closed).
            ColliderShape::TriMesh(ref mesh) => (
                4.0,
                Vec3::new(
                    f32::from_bits(mesh_offset),
                    f32::from_bits(mesh_offset + 2 * mesh.nodes().len() as u32),
                    mesh.thickness().map_or(-1.0, |t| 0.5 * t),
                ),
            ),
        };
        let moving = c.motion != ColliderMotion::Static;
        let v = |x: Vec3| {
            let x = if moving { x } else { Vec3::ZERO };
            [x.x, x.y, x.z, 0.0]
        };
        let t = c.pose.translation;
        let q = c.pose.rotation;
        Self {
            translation: [t.x, t.y, t.z, kind],
            rotation: [q.x, q.y, q.z, q.w],
            size: [size.x, size.y, size.z, c.bounding_radius()],
            linear_velocity: {
                let [x, y, z, _] = v(c.linear_velocity);
                [x, y, z, f32::from_bits(body)]
            },
            angular_velocity: v(c.angular_velocity),
        }
    }
}

/// The boundary samples as the GPU reads them, in the order of the grid sort
/// ([`crate::Boundary`]): `position` (xyz, w = volume V_b), `velocity` (xyz, w = the body's
/// friction factor, 0 = free slip) and `cell_start` (cells + 1 exclusive offsets over the
/// container's dense grid, the same grid the fluid uses in grid mode).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct GpuBoundarySamples {
    /// Positions [m], w = V_b [m³].
    pub position: Vec<[f32; 4]>,
    /// Velocities [m/s], w = friction factor.
    pub velocity: Vec<[f32; 4]>,
    /// Exclusive cell offsets, cells + 1 entries.
    pub cell_start: Vec<u32>,
    /// The colliders, for the guard.
    pub colliders: Vec<GpuCollider>,
    /// Each sample's body: 0 the walls, k + 1 the collider slot k ([`crate::ColliderId`]).
    pub body: Vec<u32>,
    /// Whether the samples mirror DFSPH's stiffness and hold the hydrostatic rise
    /// (`crate::dfsph_bender2017`): unless a dynamic collider is in the boundary. The GPU does not
    /// let a body give way in the solves ([`crate::boundary::free_bodies`]), so it follows
    /// [`crate::Boundary::mirrors`] as if no mass were known. The plugin passes it on in
    /// [`GpuSphParams::dfsph_c`]'s w.
    pub mirrors: bool,
    /// The mesh colliders' hierarchies and triangles ([`crate::TriMesh::gpu_words`]), one after
    /// the other.
    pub meshes: Vec<[f32; 4]>,
    /// [`crate::Boundary::membership`]: a change means a collider joined or left.
    pub membership: u64,
}

impl GpuBoundarySamples {
    /// The sorted samples of `boundary` (sort it first).
    pub fn of(boundary: &crate::Boundary) -> Self {
        let position = boundary
            .position
            .iter()
            .zip(&boundary.volume)
            .map(|(p, &v)| [p.x, p.y, p.z, v])
            .collect();
        let velocity = boundary
            .velocity
            .iter()
            .zip(&boundary.body)
            .map(|(u, &b)| [u.x, u.y, u.z, boundary.friction[b as usize]])
            .collect();
        let mut meshes = Vec::new();
        let colliders = boundary
            .colliders()
            .map(|(id, c)| {
                let offset = meshes.len() as u32;
                if let crate::boundary::collider::ColliderShape::TriMesh(mesh) = &c.shape {
                    meshes.extend(mesh.gpu_words());
                }
                GpuCollider::of(c, offset, id.0 + 1)
            })
            .collect();
        Self {
            position,
            velocity,
            cell_start: boundary.grid.cell_start.clone(),
            colliders,
            body: boundary.body.clone(),
            mirrors: !boundary.dynamic.contains(&true),
            meshes,
            membership: boundary.membership(),
        }
    }
}

/// Bodies whose force the GPU sums: the walls and the first 31 collider slots. A body beyond
/// is left out of the sums (its [`GpuBodyForces::sum`] is `None`). While no collider is in the
/// boundary nothing is summed (no reader asks for the walls' force; `body_reactions.wgsl`).
pub const GPU_BODY_SLOTS: usize = 32;

/// Components summed per body: the force and Σ x_b × f (the moment about the world origin).
pub const GPU_BODY_COMPONENTS: usize = 6;

/// The fluid's force on each body summed on the device over one frame's force evaluations
/// (WGSL `SphBodyForces`): per body and component a 64-bit two's-complement fixed-point sum in
/// units of [`body_force_unit`] (the force) and [`body_moment_unit`] (the moment), as (low,
/// high) words, then the evaluations. Workgroups sum
/// their particles in 32-bit fixed point first; each adds its total with two 32-bit atomics and
/// the carry, so the sum is exact whatever the order.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, Pod, Zeroable)]
pub struct GpuBodyForces {
    /// (low, high) words of each body's six sums, body-major: sum k at `2k`, `2k + 1`.
    pub sums: [u32; 2 * GPU_BODY_SLOTS * GPU_BODY_COMPONENTS],
    /// Force evaluations summed (forces passes since the buffer was cleared).
    pub evaluations: u32,
    /// The number of the frame that wrote the buffer last (the plugin's frame counter, written
    /// by the CPU every frame, with steps or not): how old a reading is.
    pub frame: u32,
    /// Padding.
    pub pad: [u32; 2],
}

impl Default for GpuBodyForces {
    fn default() -> Self {
        Self::zeroed()
    }
}

/// The fixed-point unit of the body forces [N]: a thousandth of the weight of one particle of
/// mass `mass` under standard gravity, so a workgroup's 32-bit sum holds two million particle
/// weights and a body's rounding error stays a thousandth of a particle's weight per workgroup.
pub fn body_force_unit(mass: f32) -> f32 {
    (mass * 9.81e-3).max(f32::MIN_POSITIVE)
}

/// The fixed-point unit of the body moments Σ x_b × f [N m]: [`body_force_unit`] / 16. Each
/// thread's moment about the world origin is rounded to it before the sums, and the torque about
/// a body's origin is the small difference of two such moments: with the force's unit, a few
/// hundred particles next to a body left the GPU's torque 3e-4 to 6e-4 N m from the CPU's in
/// `tests/colliders.rs` (a tenth of a particle's weight times 1 m is 8e-4 N m there), as large as
/// the torques compared. A workgroup's 32-bit sum still holds over 100,000 particle weights times 1 m.
pub fn body_moment_unit(mass: f32) -> f32 {
    body_force_unit(mass) / 16.0
}

impl GpuBodyForces {
    /// Byte offset of [`Self::frame`].
    pub const FRAME_OFFSET: u64 = std::mem::offset_of!(GpuBodyForces, frame) as u64;

    /// The value of one sum in units.
    fn value(&self, body: usize, component: usize) -> i64 {
        let k = 2 * (body * GPU_BODY_COMPONENTS + component);
        ((self.sums[k + 1] as u64) << 32 | self.sums[k] as u64) as i64
    }

    /// Body `body`'s force [N] and torque about `origin` [N m], each the mean over the summed
    /// evaluations, for particles of mass `mass`; `None` beyond [`GPU_BODY_SLOTS`] or without
    /// evaluations.
    pub fn mean(&self, body: usize, mass: f32, origin: Vec3) -> Option<crate::BodyForce> {
        if body >= GPU_BODY_SLOTS || self.evaluations == 0 {
            return None;
        }
        let per_evaluation = 1.0 / self.evaluations as f64;
        let v = |k: usize, unit: f32| {
            glam::DVec3::new(
                self.value(body, k) as f64,
                self.value(body, k + 1) as f64,
                self.value(body, k + 2) as f64,
            ) * (unit as f64 * per_evaluation)
        };
        let (force, moment) = (v(0, body_force_unit(mass)), v(3, body_moment_unit(mass)));
        // Σ (x_b - o) × f = Σ x_b × f - o × Σ f.
        let torque = moment - origin.as_dvec3().cross(force);
        Some(crate::BodyForce {
            force: force.as_vec3(),
            torque: torque.as_vec3(),
        })
    }
}

#[cfg(test)]
mod body_force_tests {
    use super::*;

    /// Adds `units` to one sum the way the WGSL does: the low word with its carry, then the
    /// sign-extended high word.
    fn add(sums: &mut GpuBodyForces, at: usize, units: i32) {
        let (low, carry) = sums.sums[2 * at].overflowing_add(units as u32);
        sums.sums[2 * at] = low;
        sums.sums[2 * at + 1] = sums.sums[2 * at + 1]
            .wrapping_add(if units < 0 { u32::MAX } else { 0 })
            .wrapping_add(carry as u32);
    }

    #[test]
    fn fixed_point_sums_are_exact_and_give_the_torque_about_the_origin() {
        let mut sums = GpuBodyForces::default();
        // Body 1: 3 evaluations of a force (0, -2000, 0) units at x = (1, 0, 0) [m], added in
        // pieces of both signs that cross the 32-bit range of the low word many times.
        let moment_units = (body_force_unit(1.0) / body_moment_unit(1.0)).round() as usize;
        assert_eq!(moment_units, 16);
        for _ in 0..3 {
            for piece in [-1_000_000_000, 999_998_000, -1_000, -1_000] {
                add(&mut sums, GPU_BODY_COMPONENTS + 1, piece);
                // Σ x × f with x = (1, 0, 0): z component = x f_y, in 16 times finer units.
                for _ in 0..moment_units {
                    add(&mut sums, GPU_BODY_COMPONENTS + 5, piece);
                }
            }
        }
        sums.evaluations = 3;
        let mass = 0.008;
        let unit = body_force_unit(mass) as f64;
        let f = sums.mean(1, mass, Vec3::ZERO).unwrap();
        let expected = (-1_000_000_000.0 + 999_998_000.0 - 2_000.0) * unit;
        assert!((f.force.y as f64 - expected).abs() < 1e-6 * expected.abs());
        assert!((f.torque.z as f64 - expected).abs() < 1e-6 * expected.abs());
        // About the point of application the torque vanishes.
        let at_point = sums.mean(1, mass, Vec3::X).unwrap();
        assert!(at_point.torque.length() < 1e-6 * expected.abs() as f32);
        assert_eq!(sums.mean(0, mass, Vec3::ZERO).unwrap().force, Vec3::ZERO);
        assert!(sums.mean(GPU_BODY_SLOTS, mass, Vec3::ZERO).is_none());
        sums.evaluations = 0;
        assert!(sums.mean(1, mass, Vec3::ZERO).is_none());
    }
}

/// Most pumps the GPU applies (the rest are left out and reported).
pub const MAX_GPU_PUMPS: usize = 16;

/// A pump as the GPU reads it (WGSL `GpuPump`). Rust twin: [`crate::flow::pump::Pump`].
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuPump {
    /// The box's centre [m]; w = the target speed [m/s].
    pub center_speed: [f32; 4],
    /// The inverse of the box's rotation (world to box frame), quaternion (x, y, z, w).
    pub to_local: [f32; 4],
    /// The box's half extents [m]; w = the strength [1/s].
    pub half_extents_strength: [f32; 4],
    /// The unit direction it pushes in (world).
    pub direction: [f32; 4],
}

/// The pumps of a frame (WGSL `SphPumps`): how many, then up to [`MAX_GPU_PUMPS`].
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuPumps {
    /// Pumps in use.
    pub count: u32,
    /// Open drains, in the slots after the pumps (as boxes: centre, rotation, half extents).
    pub sink_count: u32,
    /// Padding to 16 bytes.
    pub pad: [u32; 2],
    /// The pumps, then the drains; slots past `count + sink_count` are ignored.
    pub pumps: [GpuPump; MAX_GPU_PUMPS],
}

impl GpuPumps {
    /// The GPU form of the first [`MAX_GPU_PUMPS`] of `pumps` (validated ones: a zero direction
    /// stays zero and pushes nothing).
    pub fn of(pumps: &[crate::flow::pump::Pump]) -> Self {
        let mut out = Self::default();
        for (slot, p) in out.pumps.iter_mut().zip(pumps) {
            let c = p.region.pose.translation;
            let q = p.region.pose.rotation.inverse();
            let h = p.region.half_extents;
            let d = p.direction.normalize_or_zero();
            *slot = GpuPump {
                center_speed: [c.x, c.y, c.z, p.speed],
                to_local: [q.x, q.y, q.z, q.w],
                half_extents_strength: [h.x, h.y, h.z, p.strength],
                direction: [d.x, d.y, d.z, 0.0],
            };
        }
        out.count = pumps.len().min(MAX_GPU_PUMPS) as u32;
        out
    }

    /// [`Self::of`] `pumps`, then the open ones of `sinks` in the slots left (a pump's box with
    /// no strength); returns the drains that found no slot.
    pub fn with_sinks(pumps: &[crate::flow::pump::Pump], sinks: &[crate::flow::sink::Sink]) -> (Self, usize) {
        let mut out = Self::of(pumps);
        let open: Vec<&crate::flow::sink::Sink> = sinks.iter().filter(|s| s.open).collect();
        let first = out.count as usize;
        for (slot, sink) in out.pumps[first..].iter_mut().zip(&open) {
            let c = sink.region.pose.translation;
            let q = sink.region.pose.rotation.inverse();
            let h = sink.region.half_extents;
            *slot = GpuPump {
                center_speed: [c.x, c.y, c.z, 0.0],
                to_local: [q.x, q.y, q.z, q.w],
                half_extents_strength: [h.x, h.y, h.z, 0.0],
                direction: [0.0; 4],
            };
        }
        out.sink_count = open.len().min(MAX_GPU_PUMPS - first) as u32;
        (out, open.len() - out.sink_count as usize)
    }
}

/// Most probes the GPU measures (the rest are left out and reported).
pub const MAX_GPU_PROBES: usize = 16;

/// The flux sums' fixed-point unit [m/s]: Σ v·n is summed as i32 multiples of it.
pub const PROBE_SPEED_UNIT: f32 = 1e-4;

/// A probe as the GPU reads it (WGSL `GpuProbe`). Rust twin: [`crate::flow::probe::ProbeKind`].
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuProbe {
    /// Level: (x, 0, z); flux: the rectangle's centre; count: the box's centre [m]. w = the
    /// kind: 0 level, 1 flux, 2 count.
    pub center_kind: [f32; 4],
    /// World to probe frame, quaternion (x, y, z, w) (identity for a level).
    pub to_local: [f32; 4],
    /// Level: (radius, 0, 0); flux: (half width, half height, half slab thickness); count: the
    /// half extents [m].
    pub half: [f32; 4],
    /// Flux: the unit normal (world). Level: the column's bins
    /// ([`crate::flow::probe::LevelColumn`]): (floor, bin height, 0, 0) [m].
    pub normal: [f32; 4],
}

/// The frame's probes and their sums (WGSL `SphProbes`), written whole by the CPU with zeroed
/// sums every frame that steps, summed by every closing kick, read back every frame.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct GpuProbes {
    /// Probes in use.
    pub count: u32,
    /// The main world's frame number, so a readback is matched with its probes.
    pub frame: u32,
    /// Steps summed (each closing kick of particle 0 adds one).
    pub samples: u32,
    /// The last step summed (the clock's step count at its closing kick).
    pub step: u32,
    /// The simulated time at the end of that step [ns], low and high words.
    pub time_ns: [u32; 2],
    /// Padding.
    pub pad: [u32; 2],
    /// The probes.
    pub probes: [GpuProbe; MAX_GPU_PROBES],
    /// Per probe: [unused, particles, Σ v·n in [`PROBE_SPEED_UNIT`] (i32 bits), unused],
    /// summed over the frame's steps.
    pub sums: [[u32; 4]; MAX_GPU_PROBES],
    /// Per Level probe and bin: the [`float_key`] of the bin's highest particle centre over
    /// the frame's steps (0: empty).
    pub level_tops: [[u32; crate::flow::probe::LEVEL_BINS]; MAX_GPU_PROBES],
}

impl Default for GpuProbes {
    fn default() -> Self {
        Self::zeroed()
    }
}

/// A key that orders f32 as u32 (atomicMax on positions): negative values flipped, positive
/// ones with the sign bit set. 0 is below every finite value's key.
pub fn float_key(x: f32) -> u32 {
    let b = x.to_bits();
    if b & 0x8000_0000 != 0 {
        !b
    } else {
        b | 0x8000_0000
    }
}

/// The value of a [`float_key`] (`None` for the 0 key of no particle).
pub fn key_float(key: u32) -> Option<f32> {
    if key == 0 {
        return None;
    }
    let b = if key & 0x8000_0000 != 0 {
        key & 0x7fff_ffff
    } else {
        !key
    };
    Some(f32::from_bits(b))
}

impl GpuProbes {
    /// The simulated time at the end of the last step summed [s].
    pub fn time(&self) -> f64 {
        ((self.time_ns[1] as u64) << 32 | self.time_ns[0] as u64) as f64 * 1e-9
    }

    /// The GPU form of the first [`MAX_GPU_PROBES`] of `kinds` in `container` for particles
    /// of spacing `spacing`, for frame `frame`, with zero sums.
    pub fn of(
        kinds: &[crate::flow::probe::ProbeKind],
        container: &crate::container::BoxContainer,
        spacing: f32,
        frame: u32,
    ) -> Self {
        use crate::flow::probe::{flux_slab_thickness, LevelColumn, ProbeKind};
        let column = LevelColumn::of(container, spacing);
        let mut out = Self {
            count: kinds.len().min(MAX_GPU_PROBES) as u32,
            frame,
            ..Self::default()
        };
        for (slot, kind) in out.probes.iter_mut().zip(kinds) {
            let q = |r: glam::Quat| {
                let r = r.inverse();
                [r.x, r.y, r.z, r.w]
            };
            *slot = match *kind {
                ProbeKind::Level { x, z, radius } => GpuProbe {
                    center_kind: [x, 0.0, z, 0.0],
                    to_local: [0.0, 0.0, 0.0, 1.0],
                    half: [radius, 0.0, 0.0, 0.0],
                    normal: [column.floor, column.bin, 0.0, 0.0],
                },
                ProbeKind::Flux { pose, half_size } => {
                    let c = pose.translation;
                    let n = pose.rotation * Vec3::Z;
                    GpuProbe {
                        center_kind: [c.x, c.y, c.z, 1.0],
                        to_local: q(pose.rotation),
                        half: [
                            half_size[0],
                            half_size[1],
                            0.5 * flux_slab_thickness(spacing),
                            0.0,
                        ],
                        normal: [n.x, n.y, n.z, 0.0],
                    }
                }
                ProbeKind::Count { region } => {
                    let c = region.pose.translation;
                    let h = region.half_extents;
                    GpuProbe {
                        center_kind: [c.x, c.y, c.z, 2.0],
                        to_local: q(region.pose.rotation),
                        half: [h.x, h.y, h.z, 0.0],
                        normal: [0.0; 4],
                    }
                }
            };
        }
        out
    }

    /// Probe `k`'s reading, averaged over the summed steps (level: the column of all of them
    /// together), for particles of `params`; `None` before a step was summed.
    pub fn reading(&self, k: usize, params: &SphParams) -> Option<crate::flow::probe::ProbeReading> {
        use crate::flow::probe::flux_slab_thickness;
        if self.samples == 0 || k >= self.count as usize {
            return None;
        }
        let samples = self.samples as f64;
        let [_, particles, flux, _] = self.sums[k];
        let mean_particles = particles as f64 / samples;
        let count = mean_particles.round() as u32;
        let spacing = params.spacing();
        Some(match self.probes[k].center_kind[3] as u32 {
            0 => crate::flow::probe::ProbeReading {
                value: crate::flow::probe::column_surface(&self.level_tops[k].map(key_float))
                    .map(|y| y + 0.5 * spacing),
                particles: count,
                mean_speed: None,
            },
            1 => {
                let sum = flux as i32 as f64 * PROBE_SPEED_UNIT as f64;
                let volume = (params.particle_mass / params.rest_density) as f64;
                crate::flow::probe::ProbeReading {
                    value: Some(
                        (sum / samples * volume / flux_slab_thickness(spacing) as f64) as f32,
                    ),
                    particles: count,
                    mean_speed: (particles > 0).then(|| (sum / particles as f64) as f32),
                }
            }
            _ => crate::flow::probe::ProbeReading {
                value: Some(mean_particles as f32),
                particles: count,
                mean_speed: None,
            },
        })
    }
}

#[cfg(test)]
mod probe_layout_tests {
    use super::*;

    #[test]
    fn float_keys_keep_the_order_of_floats() {
        let xs = [-3.5f32, -0.01, -0.0, 0.0, 1e-6, 0.25, 7.0];
        let keys: Vec<u32> = xs.iter().map(|&x| float_key(x)).collect();
        assert!(keys.windows(2).all(|w| w[0] <= w[1]), "{keys:?}");
        for &x in &xs {
            assert_eq!(key_float(float_key(x)), Some(x));
        }
        assert_eq!(key_float(0), None);
    }
}
