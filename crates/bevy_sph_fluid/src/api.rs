//! The main-world API: resources users edit and read, components that describe the scene, and
//! the readback messages.

use bevy::asset::RenderAssetUsages;
use bevy::prelude::*;
use bevy::render::storage::ShaderBuffer;
use sph_core::{BlockSpawn, BoxContainer, Diagnostics, PipeEmitter};

/// Most steps per frame ([`SphControl::substeps`], [`SphRealTime::max_steps`]).
pub const MAX_SUBSTEPS: u32 = 64;

/// Which solver runs the simulation.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Reflect)]
pub enum SphBackend {
    /// GPU compute passes in the render graph (falls back to the CPU without compute shaders).
    #[default]
    Gpu,
    /// The `sph_core` CPU reference solver, stepped in the main world.
    Cpu,
}

/// The simulation parameters ([`sph_core::SphParams`]); edits take effect on the next step.
/// Invalid values are not applied: the step is skipped and [`SphStats::error`] names the field.
#[derive(Resource, Clone, Copy, Debug, PartialEq, Reflect, Deref, DerefMut)]
#[reflect(Resource)]
pub struct SphParams(pub sph_core::SphParams);

impl Default for SphParams {
    fn default() -> Self {
        Self(sph_core::SphParams::water())
    }
}

/// Particle slots of every buffer. Starts at the plugin's capacity; changing it reallocates the
/// buffers and resets the simulation (block spawners fire again).
#[derive(Resource, Clone, Copy, Debug, PartialEq, Eq, Reflect)]
#[reflect(Resource)]
pub struct SphCapacity(pub u32);

/// Run, pause, single-step, reset, and how far each frame steps: a fixed number of steps
/// ([`Self::substeps`]) or, with [`Self::real_time`], the frame's own time.
#[derive(Resource, Clone, Copy, Debug, PartialEq, Reflect)]
#[reflect(Resource)]
pub struct SphControl {
    /// Step every frame while true.
    pub running: bool,
    /// Take exactly one step on the next frame (cleared when taken), also while paused.
    pub single_step: bool,
    /// Remove every particle on the next frame and respawn the block spawners (cleared when done).
    pub reset: bool,
    /// Simulation steps per rendered frame while running (1 ..= 64), unless [`Self::real_time`].
    pub substeps: u32,
    /// Real-time mode: each frame advances the water by the frame's own time ([`Time`]'s delta
    /// in the plugin's schedule, clamped to [`SphRealTime::max_frame_time`]) in as many steps as
    /// the solver's time-step rule needs. `None` (the default) takes [`Self::substeps`] steps.
    pub real_time: Option<SphRealTime>,
    /// The density pass also records each particle's neighbour count (debug views; GPU only).
    pub record_neighbor_counts: bool,
    /// How unstable steps are handled: rolled back to the last checkpoint and retried at half
    /// the dt (the default), or frozen at once ([`sph_core::Rollback::off`]). Invalid settings are
    /// refused and named in [`SphStats::error`].
    pub rollback: sph_core::Rollback,
    /// GPU backend, while a dynamic [`SphCollider`] the device does not move is in the water
    /// (one without an [`SphRigidBody`]: with avian on the water's clock every dynamic body has
    /// one, and this never applies): the most simulated time one frame covers [s] (`None`: no
    /// limit); a frame takes at least one step, shortened to this time when the time-step
    /// rule's is longer. Such a body's force is read back about three frames late, and a late
    /// force does work on a body that bobs: with 8.3 ms of water a frame a boat of 400 kg/m³
    /// sometimes, and with 16 ms always, bobbed higher each time until it left the water
    /// (docs/scenes.md). Default [`DEFAULT_MAX_BODY_FRAME_TIME`]; allowed (0, 1] s.
    pub max_body_frame_time: Option<f32>,
}

/// The default of [`SphControl::max_body_frame_time`] [s]: two DFSPH steps of 2.7 ms a frame, or
/// one PBF step shortened from 1/120 s to 6 ms, both measured to keep floating bodies stable on
/// the GPU, with a boat still afloat when its forces came two frames later than usual; four
/// DFSPH steps (10.8 ms) and two PBF steps (16.7 ms) were not, and PBF's full step of 8.3 ms
/// threw a boat out in one CI run.
pub const DEFAULT_MAX_BODY_FRAME_TIME: f32 = 0.006;

impl SphControl {
    /// Refuses a [`Self::max_body_frame_time`] outside (0, 1] s, by name.
    pub fn validate_body_frame_time(&self) -> Result<(), sph_core::ParamError> {
        match self.max_body_frame_time {
            Some(t) if !(t > 0.0 && t <= 1.0) => Err(sph_core::ParamError {
                field: "SphControl::max_body_frame_time",
                value: t.to_string(),
                allowed: "(0, 1] s, or None",
            }),
            _ => Ok(()),
        }
    }
}

impl Default for SphControl {
    fn default() -> Self {
        Self {
            running: true,
            single_step: false,
            reset: false,
            substeps: 1,
            real_time: None,
            record_neighbor_counts: false,
            rollback: sph_core::Rollback::default(),
            max_body_frame_time: Some(DEFAULT_MAX_BODY_FRAME_TIME),
        }
    }
}

/// The limits of real-time mode ([`SphControl::real_time`]).
///
/// A frame longer than `max_frame_time` (a hitch, a breakpoint) advances the water by
/// `max_frame_time` only, and no frame takes more than `max_steps` steps: when the solver needs
/// more, the water runs slower than real time and [`SphStats::real_time_factor`] says by how much.
/// On the GPU the frame's steps are planned from the time-step rule's dt as last read back, and
/// the time-step pass splits the frame among them on the device (see
/// [`sph_core::frame_budget`]): the CPU never waits for the GPU.
#[derive(Clone, Copy, Debug, PartialEq, Reflect)]
pub struct SphRealTime {
    /// The most simulated time one frame advances [s], in (0, 1]. Default 1/20 s.
    pub max_frame_time: f32,
    /// The most steps one frame takes, 1 ..= 64. Default 64.
    pub max_steps: u32,
}

impl Default for SphRealTime {
    fn default() -> Self {
        Self {
            max_frame_time: 1.0 / 20.0,
            max_steps: MAX_SUBSTEPS,
        }
    }
}

impl SphRealTime {
    /// Checks both limits; the error names the field, the value and the allowed range.
    pub fn validate(&self) -> Result<(), sph_core::ParamError> {
        if !(self.max_frame_time > 0.0 && self.max_frame_time <= 1.0) {
            return Err(sph_core::ParamError {
                field: "SphControl::real_time.max_frame_time",
                value: self.max_frame_time.to_string(),
                allowed: "(0, 1] s",
            });
        }
        if !(1..=MAX_SUBSTEPS).contains(&self.max_steps) {
            return Err(sph_core::ParamError {
                field: "SphControl::real_time.max_steps",
                value: self.max_steps.to_string(),
                allowed: "1 ..= 64",
            });
        }
        Ok(())
    }

    /// The simulated time a frame of `delta` seconds advances: `delta` clamped to
    /// [`Self::max_frame_time`] (0 for a non-finite or negative delta).
    pub fn frame_time(&self, delta: f32) -> f32 {
        if delta.is_finite() && delta > 0.0 {
            delta.min(self.max_frame_time)
        } else {
            0.0
        }
    }
}

/// Health of the simulation as last measured.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Reflect)]
pub enum SphHealth {
    /// Not measured yet (the GPU backend measures on readback).
    #[default]
    Unknown,
    /// No NaN, nothing outside the container.
    Ok,
    /// A step went unstable (see `sph_core::stability`: a non-finite speed or acceleration, a
    /// particle crossing more than h in one step) and could not be rolled back (rollback off, or
    /// out of retries), or NaN or escaped particles were seen. The simulation is frozen until
    /// reset.
    Unstable {
        /// The step (1-based, since the last reset) at which the instability was detected.
        step: u64,
    },
}

impl SphHealth {
    /// Ok without NaN and escapes, Unstable (at `step`) otherwise.
    pub fn of(d: &Diagnostics, step: u64) -> Self {
        if d.non_finite_count == 0 && d.outside_count == 0 {
            Self::Ok
        } else {
            Self::Unstable { step }
        }
    }

    /// Whether an instability was detected.
    pub fn is_unstable(&self) -> bool {
        matches!(self, Self::Unstable { .. })
    }
}

/// The diffuse particles by class, and what the pool did since whitewater was turned on.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Reflect)]
pub struct SphWhitewaterCounts {
    /// Spray now (few fluid neighbours: ballistic).
    pub spray: u32,
    /// Foam now (on the surface: carried by the water, ageing).
    pub foam: u32,
    /// Bubbles now (under the surface: buoyant, dragged).
    pub bubbles: u32,
    /// Shed so far.
    pub born: u64,
    /// Refused so far by a full pool.
    pub dropped: u64,
    /// Died so far (foam at the end of its lifetime, any that left the container).
    pub expired: u64,
}

/// Statistics of the simulation, updated every frame.
#[derive(Resource, Clone, Debug, Default, Reflect)]
#[reflect(Resource)]
pub struct SphStats {
    /// The backend actually running (the GPU request may have fallen back to the CPU).
    pub backend: SphBackend,
    /// Adapter name ("cpu" for the CPU backend).
    pub adapter: String,
    /// Why a GPU request runs on the CPU: no render device, no compute shaders, or a device
    /// limit the pipelines need (named, with what is needed and what the device has). `None`
    /// when the backend is the one asked for.
    pub fallback_reason: Option<String>,
    /// Steps taken since the last reset.
    pub step_count: u64,
    /// Simulated time since the last reset [s] (GPU: read back from the GPU clock).
    pub sim_time: f64,
    /// The time step of the last step [s] (the adaptive rule's choice when it is on).
    pub time_step: f32,
    /// Steps the simulation clock has counted: the solver's steps (CPU), or the GPU clock as last
    /// read back, a frame or two behind `step_count`, and no longer counting once frozen.
    pub clock_steps: u64,
    /// Steps the clock has begun, rolled back or not: the solver's steps (CPU), or the GPU
    /// clock's count as last read back. Unlike `clock_steps` it never goes back, so the readback
    /// is current once it equals `step_count` (what a benchmark waits for; the game never does).
    pub clock_steps_run: u64,
    /// Live particles.
    pub particle_count: u32,
    /// Particle slots.
    pub capacity: u32,
    /// Particles refused because the capacity was full, since the last reset.
    pub refused_spawns: u64,
    /// Particles left out of spawns because they lay inside a collider, since the last reset.
    pub spawns_inside_colliders: u64,
    /// Unstable steps rolled back since the last reset (see [`SphControl::rollback`]).
    pub rollbacks: u64,
    /// Particles the last-resort guard moved out of a solid or back into the box since the last
    /// reset (GPU: read back with the clock). 0 while the boundary model holds.
    pub boundary_corrections: u64,
    /// Of those, the particles clamped back into the container's box.
    pub wall_corrections: u64,
    /// GPU PBF: particles that had more neighbours than the step's lists hold
    /// (`sph_core::gpu_layout::PBF_MAX_NEIGHBORS`, about twice the rest density) and boundary
    /// samples with more particles in reach than theirs hold
    /// (`sph_core::gpu_layout::PBF_MAX_WALL_NEIGHBORS`), each losing the rest for that step,
    /// summed over the steps since the last reset. 0 on the CPU backend, whose lists have no
    /// limit.
    pub neighbor_list_overflows: u64,
    /// Boundary samples (Akinci 2012) of the container's walls and the colliders.
    pub boundary_samples: u32,
    /// Colliders refused this frame (the simulation goes on without them).
    pub collider_errors: Vec<SphColliderError>,
    /// The diffuse particles by class, while whitewater runs (`crate::whitewater`).
    pub whitewater: Option<SphWhitewaterCounts>,
    /// Why the `SphWhitewater` asked for does not run: a setting refused by name (the
    /// whitewater before it runs on).
    pub whitewater_error: Option<String>,
    /// Compute dispatches in the last step (GPU backend).
    pub dispatches_per_step: u32,
    /// DFSPH: constant-density iterations per step, mean over the last frame's steps (GPU: over
    /// the steps between the last two clock readings, which arrive a frame or two late); PBF:
    /// its constraint iterations, a fixed count per step on both backends (0 with WCSPH).
    pub pressure_iterations_mean: f32,
    /// Simulated seconds per wall-clock second over the last half second or more of real time
    /// (1 = real time; GPU: from the clock as read back).
    pub real_time_factor: f32,
    /// Steps the last frame took (planned on the GPU).
    pub frame_steps: u32,
    /// The solver's mean compression, mean over particles of max(ρ/ρ0 − 1, 0) [%]: from the
    /// last step on the CPU backend, from the last snapshot on the GPU backend.
    pub density_error_mean_pct: f32,
    /// DFSPH: the most constant-density iterations of one step in the last frame (GPU: since the
    /// last reset).
    pub pressure_iterations_max: u32,
    /// DFSPH: divergence-free iterations per step, mean over the last frame's steps (GPU: as
    /// `pressure_iterations_mean`).
    pub divergence_iterations_mean: f32,
    /// DFSPH on the GPU: solves (constant-density and divergence-free) since the reset that ran
    /// out of the iterations the frame encoded before they converged or reached their most
    /// (`bevy_sph_fluid::dfsph_budget`); 0 on the CPU, which always iterates to the end.
    pub dfsph_solves_cut_short: u64,
    /// GPU backend with a dynamic collider in the water: frames since the start that took no
    /// steps because the newest body forces read back were more than
    /// [`crate::shared::MAX_BODY_FORCE_LAG`] frames old (a slow or loaded GPU); 0 on the CPU.
    pub frames_held_for_body_forces: u64,
    /// [`SphReadbackRequest`]s that got no snapshot because the GPU was still copying the
    /// previous one (one copy is in flight at a time; ask again after the snapshot arrives).
    /// Requests in the same frame share one snapshot and are not counted. 0 on the CPU.
    pub snapshot_requests_dropped: u64,
    /// Per-stage time of the last frame in milliseconds: GPU timestamps when the adapter supports
    /// them and `RenderDiagnosticsPlugin` is added (GPU backend), wall clock (CPU backend).
    pub stage_ms: Vec<(String, f64)>,
    /// GPU time of the water surface's passes in the last measured frame [ms] (depth,
    /// thickness, the filter's passes summed, normals, composite): GPU timestamps when the
    /// adapter supports them and `RenderDiagnosticsPlugin` is added. The passes are named, not
    /// numbered per camera: with several surface cameras, the last one drawn.
    pub surface_ms: Vec<(String, f64)>,
    /// GPU memory of the particle buffers per particle slot [bytes].
    pub gpu_bytes_per_particle: u32,
    /// Health as last measured.
    pub health: SphHealth,
    /// Diagnostics of the last readback (GPU) or step (CPU).
    #[reflect(ignore)]
    pub diagnostics: Option<Diagnostics>,
    /// Why the simulation is not stepping (invalid parameter, no container, shaders compiling...).
    pub error: Option<String>,
    /// Particles the block spawners added since the last reset.
    pub particles_initial: u64,
    /// Particles the emitters added since the last reset.
    pub particles_emitted: u64,
    /// Particles the drains ([`crate::flow::SphSink`]) removed since the last reset.
    pub particles_drained: u64,
    /// The last drain, pump or probe refused (by entity, field and value) or not run on this
    /// backend; the simulation goes on without it.
    pub flow_error: Option<String>,
    /// The last scene file that failed to load or validate, by file, line and field (the
    /// running scene stays); cleared when a scene loads.
    pub scene_error: Option<String>,
}

/// [`SphStats::error`] while the GPU backend compiles its compute shaders: the water does not
/// step yet (on lavapipe a DFSPH scene takes seconds). See [`SphStats::gpu_warming_up`].
pub const STATUS_COMPILING_SHADERS: &str = "gpu: compiling shaders";

/// [`SphStats::error`] while the GPU backend creates the scene's buffers and bind groups: the
/// water does not step yet. See [`SphStats::gpu_warming_up`].
pub const STATUS_PREPARING_BUFFERS: &str = "gpu: preparing buffers";

impl SphStats {
    /// Whether the GPU backend is still starting up ([`STATUS_COMPILING_SHADERS`],
    /// [`STATUS_PREPARING_BUFFERS`]): not an error, but no step has been taken with the current
    /// scene yet. Screenshots and timings should wait for it to end.
    pub fn gpu_warming_up(&self) -> bool {
        matches!(
            self.error.as_deref(),
            Some(STATUS_COMPILING_SHADERS | STATUS_PREPARING_BUFFERS)
        )
    }

    /// initial + emitted − drained − live: 0 while no particle is lost or duplicated.
    pub fn particle_balance(&self) -> i64 {
        self.particles_initial as i64 + self.particles_emitted as i64
            - self.particles_drained as i64
            - self.particle_count as i64
    }
}

/// The container: a box standing on a floor plate. Exactly one entity should carry it.
#[derive(Component, Clone, Copy, Debug, PartialEq, Reflect, Deref, DerefMut)]
#[reflect(Component)]
pub struct SphContainer(pub BoxContainer);

/// The water's force and torque on the container's walls and floor (torque about the world
/// origin), averaged like [`SphColliderForce`]. Add it to the [`SphContainer`]'s entity to have
/// it written: the CPU backend writes it every frame, the GPU backend when the device's sums are
/// read back (it sums the walls' reactions only while some entity carries this, or a collider is
/// in the water). Water at rest presses on them with its weight, so `force` reads N m g then.
#[derive(Component, Clone, Copy, Debug, Default, PartialEq, Reflect)]
#[reflect(Component)]
pub struct SphWallForce {
    /// Force [N].
    pub force: Vec3,
    /// Torque about the world origin [N m].
    pub torque: Vec3,
}

/// A solid the water meets, placed by the entity's [`GlobalTransform`]: an Akinci 2012 boundary
/// of samples in the shape, on both backends. The shape is sampled when the component is added
/// or changed; moving the transform only moves the samples. A transform's scale scales the
/// shape (uniformly for spheres, capsules and cylinders). Invalid shapes, poses or scales are
/// refused: [`SphStats::collider_errors`] names the entity, the field and the value, and the
/// simulation goes on without that collider.
#[derive(Component, Clone, Debug, PartialEq, Reflect)]
#[reflect(Component)]
#[require(Transform, SphColliderForce)]
pub struct SphCollider {
    /// The shape in the entity's frame (y is the axis of capsules and cylinders).
    pub shape: sph_core::ColliderShape,
    /// Static (never moves), kinematic (the game moves it; the water sees its velocity) or
    /// dynamic (the game or a physics engine moves it and applies [`SphColliderForce`]).
    pub motion: sph_core::ColliderMotion,
    /// Free slip (pressure only) or no slip (the water's viscosity against the surface).
    pub slip: sph_core::Slip,
}

impl SphCollider {
    /// A static, free-slip collider of `shape`.
    pub fn new(shape: sph_core::ColliderShape) -> Self {
        Self {
            shape,
            motion: sph_core::ColliderMotion::Static,
            slip: sph_core::Slip::Free,
        }
    }

    /// The same collider with motion kind `motion`.
    pub fn with_motion(mut self, motion: sph_core::ColliderMotion) -> Self {
        self.motion = motion;
        self
    }

    /// The same collider with slip `slip`.
    pub fn with_slip(mut self, slip: sph_core::Slip) -> Self {
        self.slip = slip;
        self
    }
}

/// The water's force and torque on a collider (about the entity's origin), averaged over the
/// force evaluations of the last frame that stepped: for game code or a physics engine to apply
/// to a dynamic body. The CPU backend writes it every frame; the GPU backend sums it on the
/// device and writes it when the readback arrives, a frame or two later (the first 31 collider
/// slots are summed).
#[derive(Component, Clone, Copy, Debug, Default, PartialEq, Reflect)]
#[reflect(Component)]
pub struct SphColliderForce {
    /// Force [N].
    pub force: Vec3,
    /// Torque about the entity's origin [N m].
    pub torque: Vec3,
}

/// The mass [kg] of the body behind a dynamic [`SphCollider`]. With it, DFSPH's solves on the
/// CPU backend let the body give way to the water's pressure within a frame
/// (`sph_core::boundary::free_bodies`): a body that the game or a physics engine moves once a frame would
/// otherwise be an unstoppable solid to the water's several steps in that frame, and a heavy body
/// resting on water rattles (measured: a 1,500 kg/m³ box at ±0.1 m/s without its mass, 0.02 m/s
/// with it). The avian integration keeps it equal to avian's mass for free dynamic bodies; a game
/// that moves dynamic bodies itself adds it. Refused unless finite and positive (the field
/// `mass`, in [`SphStats::collider_errors`]). Ignored by WCSPH, PBF and the GPU backend, and on
/// static and kinematic colliders. Leave it off a body held by a joint: the water would expect
/// the body to give way where the joint holds it.
#[derive(Component, Clone, Copy, Debug, PartialEq, Reflect)]
#[reflect(Component)]
pub struct SphColliderMass(pub f32);

/// A dynamic [`SphCollider`]'s rigid body as the physics engine that moves it sees it, written by
/// the engine's integration every frame (the `avian` feature writes it for avian bodies run on
/// the water's clock). On the GPU backend the device then moves the body with the water at every
/// step (`sph_core::bodies`; docs/scenes.md, "Bodies on the GPU"): the water's force acts on it
/// at once, not three frames late, and the engine's state (its contacts, joints and a game's
/// pushes) joins the device's once a frame. The pose is the entity's [`Transform`]. Ignored by
/// the CPU backend, by static and kinematic colliders, and beyond the first
/// [`sph_core::gpu_layout::GPU_MOVED_BODIES`] collider slots.
#[derive(Component, Clone, Copy, Debug, PartialEq, Reflect)]
#[reflect(Component)]
pub struct SphRigidBody {
    /// Mass M [kg] (> 0 and finite, or the body is not moved).
    pub mass: f32,
    /// The centre of mass in the entity's frame [m].
    pub center_of_mass: Vec3,
    /// The inverse inertia tensor about the centre of mass, in the entity's frame
    /// [1/(kg m²)] (zero about a locked rotation).
    pub inverse_inertia: Mat3,
    /// 1 on each world axis the body may move along, 0 where it is locked.
    pub free_translation: Vec3,
    /// 1 on each world axis the body may turn about, 0 where it is locked.
    pub free_rotation: Vec3,
    /// A hinge: the world axis the body turns about, through its origin (a wheel on its axle).
    pub hinge_axis: Option<Vec3>,
    /// Gravity on the body [m/s²].
    pub gravity: Vec3,
    /// Linear damping [1/s] (v / (1 + dt c) a step, as avian's `LinearDamping`).
    pub linear_damping: f32,
    /// Angular damping [1/s].
    pub angular_damping: f32,
    /// The centre of mass's velocity [m/s].
    pub linear_velocity: Vec3,
    /// The angular velocity [rad/s].
    pub angular_velocity: Vec3,
}

/// A collider the simulation refused, with why.
#[derive(Clone, Debug, PartialEq, Reflect)]
pub struct SphColliderError {
    /// The entity carrying the [`SphCollider`].
    pub entity: Entity,
    /// The field, e.g. `shape.radius` or `transform.scale`.
    pub field: String,
    /// The offending value.
    pub value: String,
    /// What is allowed.
    pub allowed: String,
}

impl std::fmt::Display for SphColliderError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "collider {}: `{}` = {}: allowed {}",
            self.entity, self.field, self.value, self.allowed
        )
    }
}

/// How the water slides along the container's walls, on the container's entity: free slip
/// (the default without this component: pressure only) or no slip with a friction factor on the
/// water's viscosity (PBF's: XSPH's c). A glass tank at rest is calmest with no slip; with WCSPH
/// and DFSPH a dam break's front is closest to experiment with free slip, with PBF with no slip
/// at a friction factor of about 30 (docs/pbf.md).
#[derive(Component, Clone, Copy, Debug, PartialEq, Reflect)]
#[reflect(Component)]
pub struct SphWallSlip(pub sph_core::Slip);

/// A block of particles spawned once when the component is added, and again on every reset.
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct SphBlockSpawn {
    /// The lattice.
    pub block: BlockSpawn,
    /// Initial velocity of every particle [m/s].
    pub velocity: Vec3,
}

/// A pipe emitter: spawns whole discs of particles every frame (the design's water jet).
#[derive(Component, Clone, Debug, PartialEq)]
pub struct SphEmitter(pub PipeEmitter);

/// Ask for a snapshot of the particle state; answered by a [`SphSnapshot`] a few frames later.
/// Nothing is read back unless asked.
#[derive(Message, Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SphReadbackRequest;

/// The particle state at one step: positions, velocities, accelerations, densities and stable
/// ids, in the
/// solver's current (cell-sorted) order.
#[derive(Message, Clone, Debug, Default, PartialEq)]
pub struct SphSnapshot {
    /// The step the snapshot was taken after.
    pub step: u64,
    /// Particle ids (spawn order since the last reset).
    pub ids: Vec<u32>,
    /// Positions [m].
    pub positions: Vec<Vec3>,
    /// Velocities [m/s].
    pub velocities: Vec<Vec3>,
    /// Accelerations of the last force evaluation [m/s²].
    pub accelerations: Vec<Vec3>,
    /// Densities [kg/m³].
    pub densities: Vec<f32>,
    /// Pressures [Pa] (WCSPH: the equation of state's; DFSPH: (κ^ρ + κ^v) ρ² of the solves, the
    /// pressure its accelerations carry; PBF: -ρ0 Λ / dt², the pressure its step's weighted λ sum
    /// Λ stands for, `sph_core::solver::pbf::macklin2013::equivalent_pressure`).
    pub pressures: Vec<f32>,
    /// Neighbours within h (GPU backend, while [`SphControl::record_neighbor_counts`]).
    pub neighbor_counts: Option<Vec<u32>>,
}

impl SphSnapshot {
    /// Diagnostics (density error, NaN, escapes, speeds...) of this state.
    pub fn diagnostics(
        &self,
        params: &sph_core::SphParams,
        container: &BoxContainer,
    ) -> Diagnostics {
        Diagnostics::measure(
            params,
            container,
            &sph_core::diagnostics::DiagnosticsInput {
                position: &self.positions,
                velocity: &self.velocities,
                density: &self.densities,
            },
        )
    }
}

/// Handles of the GPU state buffers: read back by [`SphReadbackRequest`] (GPU backend), and
/// bindable by a material to draw particles straight from the GPU. On the GPU backend the render
/// world writes them; on the CPU backend the plugin copies the solver's positions, velocities,
/// densities and pressures into them every frame. Never modify these assets yourself. Replaced when
/// [`SphCapacity`] changes.
#[derive(Resource, Clone, Debug, PartialEq, Eq)]
pub struct SphGpuBuffers {
    /// `array<vec4<f32>>`: xyz position [m], w = particle id (bit-cast u32).
    pub position: Handle<ShaderBuffer>,
    /// `array<vec4<f32>>`: xyz velocity [m/s].
    pub velocity: Handle<ShaderBuffer>,
    /// `array<vec4<f32>>`: xyz acceleration of the last force evaluation [m/s²].
    pub acceleration: Handle<ShaderBuffer>,
    /// `array<f32>`: density [kg/m³].
    pub density: Handle<ShaderBuffer>,
    /// `array<f32>`: pressure [Pa] after each step (WCSPH: the equation of state's; DFSPH:
    /// (κ^ρ + κ^v) ρ² of the solves; PBF: 0).
    pub pressure: Handle<ShaderBuffer>,
    /// `array<u32>`: neighbours within h, written while [`SphControl::record_neighbor_counts`].
    pub neighbor_count: Handle<ShaderBuffer>,
    /// `SphClock` ([`sph_core::gpu_layout::GpuClock`]): dt, steps, simulated time, the last
    /// step's extremes and the instability freeze. Read back every frame into [`SphStats`].
    pub clock: Handle<ShaderBuffer>,
    /// `SphBodyForces` ([`sph_core::gpu_layout::GpuBodyForces`]): the fluid's force on each
    /// body summed over a frame's steps on the device. Read back every frame into
    /// [`SphColliderForce`].
    pub body_forces: Handle<ShaderBuffer>,
    /// `SphProbes` ([`sph_core::gpu_layout::GpuProbes`]): the frame's probes and their sums.
    /// Read back every frame into `SphProbeReading` messages.
    pub probes: Handle<ShaderBuffer>,
}

impl SphGpuBuffers {
    /// Render-world-only buffers for `capacity` particles (read back, drawn, never written by
    /// the main world).
    pub fn new(assets: &mut Assets<ShaderBuffer>, capacity: u32) -> Self {
        let n = capacity as usize;
        let mut make = |bytes: usize| {
            assets.add(ShaderBuffer::with_size(
                bytes.max(16),
                RenderAssetUsages::RENDER_WORLD,
            ))
        };
        Self {
            position: make(16 * n),
            velocity: make(16 * n),
            acceleration: make(16 * n),
            density: make(4 * n),
            pressure: make(4 * n),
            neighbor_count: make(4 * n),
            clock: make(std::mem::size_of::<sph_core::gpu_layout::GpuClock>()),
            body_forces: make(std::mem::size_of::<sph_core::gpu_layout::GpuBodyForces>()),
            probes: make(std::mem::size_of::<sph_core::gpu_layout::GpuProbes>()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_gpu_warms_up_only_while_it_compiles_or_prepares() {
        let mut stats = SphStats::default();
        assert!(!stats.gpu_warming_up());
        for status in [STATUS_COMPILING_SHADERS, STATUS_PREPARING_BUFFERS] {
            stats.error = Some(status.to_string());
            assert!(stats.gpu_warming_up(), "{status}");
        }
        stats.error = Some("gpu: shader error: bad".to_string());
        assert!(!stats.gpu_warming_up());
    }
}
