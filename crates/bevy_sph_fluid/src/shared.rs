//! Types shared by the main-world systems, the render world and the readback, in the one
//! direction data flows: [`SphSimulation`] and its frame plan [`SphFrame`] (main world ->
//! extracted), [`SphRenderFeedback`] (render world -> main world), [`ClockReadback`] (the GPU
//! clock as read back). This module imports none of the modules that use it.

use crate::api::*;
use bevy::prelude::*;
use sph_core::gpu_layout::{id_to_w, GpuBoundarySamples, GpuClock};
use sph_core::{Boundary, BoxContainer, CpuSolver};
use std::sync::{Arc, Mutex};

/// How far a frame goes: the steps it plans and the simulated time they are expected to cover.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FramePlan {
    /// Steps to take (on the CPU backend in real-time mode: at most this many, as the rule needs).
    pub steps: u32,
    /// The simulated time the steps are expected to cover [s] (emitters emit for it; a moved
    /// collider's velocity is its displacement over it).
    pub duration: f32,
    /// Real-time mode: the frame's time to split among the steps [s].
    pub budget: Option<f32>,
}

impl FramePlan {
    /// The plan for `control` when the frame took `delta` seconds and a step is expected to take
    /// `dt` (the time-step rule's dt as last known).
    pub fn of(control: &SphControl, delta: f32, dt: f32) -> Self {
        let dt = if dt.is_finite() && dt > 0.0 { dt } else { 0.0 };
        if !control.running {
            let steps = control.single_step as u32;
            return Self {
                steps,
                duration: steps as f32 * dt,
                budget: None,
            };
        }
        match control.real_time {
            Some(real_time) => {
                let budget = real_time.frame_time(delta);
                if budget <= 0.0 {
                    return Self::default();
                }
                let steps = sph_core::frame_budget::steps_to_cover(budget, dt)
                    .min(real_time.max_steps.clamp(1, MAX_SUBSTEPS));
                // Short of the budget only when the step cap cuts the frame.
                let duration = if dt > 0.0 {
                    budget.min(steps as f32 * dt)
                } else {
                    budget
                };
                Self {
                    steps,
                    duration,
                    budget: Some(budget),
                }
            }
            None => {
                let steps = control.substeps.clamp(1, MAX_SUBSTEPS);
                Self {
                    steps,
                    duration: steps as f32 * dt,
                    budget: None,
                }
            }
        }
    }
}

impl FramePlan {
    /// The plan cut to cover at most `max_time` of simulated time when a step takes `dt`:
    /// as many whole steps as fit, and at least one; a single step longer than `max_time` is
    /// shortened to it through the frame's budget (the device's `budget_dt`), and real-time
    /// mode's budget is cut with the steps.
    pub fn capped(self, max_time: f32, dt: f32) -> Self {
        if !(dt > 0.0 && max_time > 0.0) {
            return self;
        }
        // A hair over, so that two steps of 0.003 s fit in 0.006 s despite rounding.
        let slack = max_time * (1.0 + 1e-4);
        if self.steps as f32 * dt <= slack {
            return self;
        }
        let most = ((slack / dt).floor() as u32).max(1);
        let steps = self.steps.min(most);
        let duration = (steps as f32 * dt).min(max_time);
        Self {
            steps,
            duration,
            budget: Some(self.budget.map_or(duration, |b| b.min(duration))),
        }
    }
}

/// The most frames the newest body forces read back may be older than the frame being planned
/// before the water waits for them (GPU backend, a dynamic collider in the water). The readback
/// of frame N normally arrives while frame N + 1 or N + 2 is planned.
pub const MAX_BODY_FORCE_LAG: u32 = 3;

/// The most frames in a row the water waits for the body forces: a readback that stops coming
/// slows the water down but cannot freeze it.
pub const MAX_FRAMES_HELD_FOR_FORCES: u32 = 8;

/// Whether frame `planned` holds the water (takes no steps) because the newest body forces read
/// back, stamped `newest` (`None` before the first), are more than [`MAX_BODY_FORCE_LAG`] frames
/// old, unless `held_in_a_row` frames were already held ([`MAX_FRAMES_HELD_FOR_FORCES`]). A force
/// that arrives late does work on a body that bobs; waiting keeps the lag bounded whatever the
/// GPU's load.
pub fn holds_for_body_forces(planned: u32, newest: Option<u32>, held_in_a_row: u32) -> bool {
    body_force_lag(planned, newest) > MAX_BODY_FORCE_LAG
        && held_in_a_row < MAX_FRAMES_HELD_FOR_FORCES
}

/// How many frames frame `frame` comes after the newest body forces read back, stamped `newest`
/// (`None` before the first reading counts as stamp 0); the frame counter wraps.
pub fn body_force_lag(frame: u32, newest: Option<u32>) -> u32 {
    frame.wrapping_sub(newest.unwrap_or(0))
}

/// The GPU backend's drains in the main world (see `flow::lower_gpu_count`): a tail read back
/// is used only if its sort came at or after both frames.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct GpuDrainSync {
    /// The last frame that uploaded spawns.
    pub last_spawn_frame: u32,
    /// The frame from which the last drop (or reset) holds.
    pub lowered_from: u32,
}

/// What the render world does this frame; extracted every frame.
#[derive(Resource, Clone, Debug, Default)]
pub struct SphFrame {
    /// Whether the GPU backend runs.
    pub active: bool,
    /// Parameters (validated).
    pub params: sph_core::SphParams,
    /// Container.
    pub container: BoxContainer,
    /// Particle slots.
    pub capacity: u32,
    /// Drop every particle before spawning.
    pub reset: bool,
    /// Live particles before this frame's spawns.
    pub spawn_offset: u32,
    /// New particles: xyz position, w = id.
    pub spawn_positions: Vec<[f32; 4]>,
    /// New particles' velocities.
    pub spawn_velocities: Vec<[f32; 4]>,
    /// Steps to take this frame.
    pub steps: u32,
    /// Real-time mode: the frame's time [s], split among `steps` on the device, and this frame's
    /// number (the time-step pass starts a new budget when it changes).
    pub budget: Option<(f32, u32)>,
    /// The density pass records neighbour counts.
    pub neighbor_counts: bool,
    /// Some container carries [`crate::SphWallForce`]: the walls' force is summed.
    pub wall_force: bool,
    /// How unstable steps are handled.
    pub rollback: sph_core::Rollback,
    /// The state buffers.
    pub buffers: Option<SphGpuBuffers>,
    /// The pumps (the first `sph_core::gpu_layout::MAX_GPU_PUMPS` are applied).
    pub pumps: Vec<sph_core::Pump>,
    /// The open drains (in the pumps' slots left; the GPU marks the particles inside).
    pub sinks: Vec<sph_core::Sink>,
    /// The probes (the first `sph_core::gpu_layout::MAX_GPU_PROBES` are measured).
    pub probes: Vec<sph_core::ProbeKind>,
    /// The main world's number of this frame (`SphSimulation::frame_number`).
    pub number: u32,
    /// The boundary samples (walls and colliders) with their generation: the render world
    /// uploads them when the generation changes.
    pub boundary: Option<(u64, Arc<GpuBoundarySamples>)>,
    /// DFSPH: the Jacobi iterations each step encodes for the constant-density and the
    /// divergence-free solve (`crate::dfsph_budget`); a solve that converges sooner leaves the
    /// rest as empty dispatches.
    pub dfsph_iterations: [u32; 2],
    /// Whitewater's stages run, with these settings and buffers (`crate::whitewater::gpu`).
    pub whitewater: Option<GpuWhitewaterFrame>,
    /// The bodies the device moves (`crate::moved_bodies`), while there are any.
    pub bodies: Option<GpuBodiesFrame>,
}

/// The bodies the device moves, as the render world runs them.
#[derive(Clone, Debug)]
pub struct GpuBodiesFrame {
    /// Every collider slot's input ([`sph_core::gpu_layout::GPU_MOVED_BODIES`] of them; a slot
    /// the device does not move has mass 0).
    pub inputs: Vec<sph_core::gpu_layout::GpuBodyInput>,
    /// The main world's copy of the bodies' states (`GpuBodyStates`), read back every frame.
    pub states: Handle<bevy::render::storage::ShaderBuffer>,
}

/// Whitewater on the GPU backend, as the render world runs it.
#[derive(Clone, Debug)]
pub struct GpuWhitewaterFrame {
    /// The settings (validated).
    pub settings: sph_core::whitewater::settings::WhitewaterSettings,
    /// The diffuse pool's slots.
    pub capacity: u32,
    /// The water's particle slots the potentials' buffer was made for.
    pub fluid_capacity: u32,
    /// Bumped when the pool starts again empty (new settings or capacity).
    pub generation: u64,
    /// The main world's copy of the slots' (position, class) for drawing, capacity long.
    pub draw: Handle<bevy::render::storage::ShaderBuffer>,
    /// The main world's copy of the counters (`GpuDiffuseCounts`), read back every frame.
    pub counts: Handle<bevy::render::storage::ShaderBuffer>,
    /// The main world's copy of each fluid particle's potentials, in the state's order (for
    /// checks: what the shedding saw at the last step).
    pub potentials: Handle<bevy::render::storage::ShaderBuffer>,
}

impl SphFrame {
    /// Live particles after this frame's spawns.
    pub fn particle_count(&self) -> u32 {
        self.spawn_offset + self.spawn_positions.len() as u32
    }
}

/// Main-world bookkeeping shared by both backends.
#[derive(Resource)]
pub struct SphSimulation {
    /// Particle slots.
    pub capacity: u32,
    /// The requested backend.
    pub requested: SphBackend,
    /// The backend in use (resolved in `finish`).
    pub backend: SphBackend,
    /// Adapter name.
    pub adapter: String,
    /// Why a GPU request runs on the CPU (`None` when it runs where it was asked to).
    pub fallback_reason: Option<String>,
    /// Live particles (the main world is the authority; the CPU backend's drains report here).
    pub particle_count: u32,
    /// Particles the block spawners added since the last reset.
    pub initial: u64,
    /// Particles the emitters added since the last reset.
    pub emitted: u64,
    /// Particles the drains removed since the last reset.
    pub drained: u64,
    /// Next particle id.
    pub next_id: u32,
    /// Refused particles since the last reset.
    pub refused: u64,
    /// Particles left out of spawns since the last reset because they lay inside a collider.
    pub inside_colliders: u64,
    /// The CPU solver (CPU backend).
    pub cpu: Option<CpuSolver>,
    /// This frame's plan for the render world.
    pub frame: SphFrame,
    /// Container the solver was built for.
    pub container: Option<BoxContainer>,
    /// The GPU backend's boundary (walls and colliders), sorted on the CPU and uploaded when it
    /// changes; the CPU backend's lives in its solver.
    pub gpu_boundary: Option<Boundary>,
    /// Bumped whenever the GPU boundary is re-sorted.
    pub boundary_generation: u64,
    /// Bumped when the boundary is replaced without its colliders (a rebuilt CPU solver), so
    /// the collider systems add them again.
    pub boundary_epoch: u64,
    /// The walls' slip in use.
    pub wall_slip: sph_core::Slip,
    /// The time-step rule's dt as last known [s] (the CPU solver's, or the GPU clock's as read
    /// back), rollback scale included: what a frame plans its steps with.
    pub rule_dt: Option<f32>,
    /// Frames planned since the start (numbers the GPU's frame budgets).
    pub frame_number: u32,
    /// Frames in a row that held the water for the body forces ([`holds_for_body_forces`]).
    pub frames_held_in_a_row: u32,
    /// The GPU backend's drains: when the live count may drop by a tail read back.
    pub gpu_drains: GpuDrainSync,
    /// DFSPH on the GPU: the clock's iteration sums at the last reading.
    pub gpu_iterations: Option<GpuIterations>,
    /// DFSPH on the GPU: how many iterations of each solve a step encodes.
    pub dfsph_budget: crate::dfsph_budget::DfsphIterationBudget,
    /// This frame's plan, made first thing in the `Prepare` set.
    pub plan: FramePlan,
    /// The GPU backend's emitters: the device's step count as last seen by them (`None` after
    /// a reset); they emit only in frames after it advanced.
    pub emission_steps_seen: Option<u64>,
}

/// DFSPH's iteration sums of one clock reading (`GpuClock`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct GpuIterations {
    /// The clock's step.
    pub step: u32,
    /// Constant-density iterations since the reset.
    pub density: u32,
    /// Divergence-free iterations since the reset.
    pub divergence: u32,
}

impl SphSimulation {
    pub(crate) fn new(capacity: u32, requested: SphBackend) -> Self {
        Self {
            capacity,
            requested,
            backend: requested,
            adapter: String::new(),
            fallback_reason: None,
            particle_count: 0,
            initial: 0,
            emitted: 0,
            drained: 0,
            next_id: 0,
            refused: 0,
            inside_colliders: 0,
            cpu: None,
            frame: SphFrame::default(),
            container: None,
            gpu_boundary: None,
            boundary_generation: 0,
            boundary_epoch: 0,
            wall_slip: sph_core::Slip::Free,
            rule_dt: None,
            emission_steps_seen: None,
            frame_number: 0,
            frames_held_in_a_row: 0,
            gpu_drains: GpuDrainSync::default(),
            gpu_iterations: None,
            dfsph_budget: Default::default(),
            plan: FramePlan::default(),
        }
    }

    /// Queues particles for spawning; leaves out (and counts) what lies inside a collider and
    /// refuses (and counts) what exceeds the capacity. Returns the particles added.
    pub(crate) fn spawn(
        &mut self,
        positions: impl IntoIterator<Item = Vec3>,
        velocity: Vec3,
    ) -> u64 {
        // One pass over the positions, keeping only what fits: a block larger than the free
        // slots is counted, not built whole.
        let free = (self.capacity - self.particle_count) as usize;
        let boundary = self.boundary().filter(|b| b.colliders().next().is_some());
        let (mut admitted, mut inside, mut refused) = (Vec::new(), 0u64, 0u64);
        for x in positions {
            if boundary.is_some_and(|b| !b.admits_spawn(x)) {
                inside += 1;
            } else if admitted.len() < free {
                admitted.push(x);
            } else {
                refused += 1;
            }
        }
        self.inside_colliders += inside;
        self.refused += refused;
        let take = admitted.len();
        match (&mut self.cpu, self.backend) {
            (Some(solver), SphBackend::Cpu) => {
                solver.spawn(&admitted, velocity);
            }
            _ => {
                for &p in &admitted {
                    self.frame
                        .spawn_positions
                        .push([p.x, p.y, p.z, id_to_w(self.next_id)]);
                    self.frame
                        .spawn_velocities
                        .push([velocity.x, velocity.y, velocity.z, 0.0]);
                    self.next_id += 1;
                }
            }
        }
        self.particle_count += take as u32;
        take as u64
    }
}

impl SphSimulation {
    /// The dt a step is expected to take [s]: the rule's as last known, else the last step's
    /// (with the adaptive rule) or `params.time_step`.
    pub fn expected_dt(&self, params: &sph_core::SphParams, stats: &SphStats) -> f32 {
        match self.rule_dt {
            Some(dt) if dt.is_finite() && dt > 0.0 => dt,
            _ if params.adaptive_time_step && stats.time_step > 0.0 => {
                stats.time_step.min(params.time_step)
            }
            _ => params.time_step,
        }
    }

    /// This frame's plan (see [`FramePlan::of`]).
    pub fn plan(
        &self,
        control: &SphControl,
        params: &sph_core::SphParams,
        stats: &SphStats,
        delta: f32,
    ) -> FramePlan {
        FramePlan::of(control, delta, self.expected_dt(params, stats))
    }

    /// The boundary of the backend in use: the CPU solver's or the GPU backend's.
    pub fn boundary(&self) -> Option<&Boundary> {
        match self.backend {
            SphBackend::Cpu => self.cpu.as_ref().map(CpuSolver::boundary),
            SphBackend::Gpu => self.gpu_boundary.as_ref(),
        }
    }

    /// The boundary of the backend in use, to add, move and remove colliders: the CPU solver's,
    /// or the GPU backend's (built for `container` and `params`, or rebuilt when either changed).
    /// `None` before the CPU solver exists or when `params` cannot build a grid.
    pub fn boundary_mut(
        &mut self,
        container: &BoxContainer,
        params: &sph_core::SphParams,
    ) -> Option<&mut Boundary> {
        match self.backend {
            SphBackend::Cpu => self.cpu.as_mut().map(CpuSolver::boundary_mut),
            SphBackend::Gpu => {
                self.ensure_gpu_boundary(container, params).ok()?;
                self.gpu_boundary.as_mut()
            }
        }
    }

    fn ensure_gpu_boundary(
        &mut self,
        container: &BoxContainer,
        params: &sph_core::SphParams,
    ) -> Result<(), sph_core::ParamError> {
        match &mut self.gpu_boundary {
            Some(b) if b.matches(container, params) => {}
            Some(b) => b.rebuild_for(container, params)?,
            None => self.gpu_boundary = Some(Boundary::new(container, params, self.wall_slip)?),
        }
        Ok(())
    }

    /// Builds the GPU boundary for `container` and `params` (or rebuilds it when either changed),
    /// re-sorts it when a collider moved, and puts the samples in this frame's plan when they
    /// changed.
    pub(crate) fn prepare_gpu_boundary(
        &mut self,
        container: &BoxContainer,
        params: &sph_core::SphParams,
    ) -> Result<(), sph_core::ParamError> {
        self.ensure_gpu_boundary(container, params)?;
        let Some(boundary) = &mut self.gpu_boundary else {
            return Ok(());
        };
        if boundary.sort() || self.frame.boundary.is_none() {
            self.boundary_generation += 1;
            self.frame.boundary = Some((
                self.boundary_generation,
                Arc::new(GpuBoundarySamples::of(boundary)),
            ));
        }
        Ok(())
    }
}

/// What the render world reports back to the main world.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RenderFeedback {
    /// Steps taken since the last reset.
    pub step_count: u64,
    /// Dispatches of the last step.
    pub dispatches_per_step: u32,
    /// GPU bytes allocated per particle slot (all buffers / capacity).
    pub gpu_bytes_per_particle: u32,
    /// Why the GPU is not stepping, prefixed `gpu:`.
    pub status: Option<String>,
    /// The passes of the scene's stage list, as named in GPU timings
    /// (`render/<name>/elapsed_gpu`).
    pub stage_names: Vec<&'static str>,
}

/// Shared between the worlds (render writes, main reads).
#[derive(Resource, Clone, Default)]
pub struct SphRenderFeedback(Arc<Mutex<RenderFeedback>>);

impl SphRenderFeedback {
    /// A copy of the current feedback.
    pub fn get(&self) -> RenderFeedback {
        self.0.lock().map(|f| f.clone()).unwrap_or_default()
    }

    /// Applies `f` to the feedback.
    pub fn update(&self, f: impl FnOnce(&mut RenderFeedback)) {
        if let Ok(mut guard) = self.0.lock() {
            f(&mut guard);
        }
    }
}

/// The fluid's force on each body as last read back (GPU backend, every frame, asynchronously):
/// the sums of one frame's force evaluations.
#[derive(Resource, Default)]
pub struct BodyForceReadback {
    /// The buffer being read and the entity reading it.
    pub(crate) source: Option<(Handle<bevy::render::storage::ShaderBuffer>, Entity)>,
    /// The latest sums that arrived and were not yet written to the colliders.
    pub latest: Option<sph_core::gpu_layout::GpuBodyForces>,
    /// The newest frame stamp read back (`GpuBodyForces::frame`), steps or not: the forces the
    /// bodies have are at most this old.
    pub newest_frame: Option<u32>,
}

/// The probes' sums as last read back (GPU backend, every frame, asynchronously).
#[derive(Resource, Default)]
pub struct ProbeReadback {
    /// The buffer being read and the entity reading it.
    pub(crate) source: Option<(Handle<bevy::render::storage::ShaderBuffer>, Entity)>,
    /// The latest sums that arrived with at least one step summed, not yet turned into
    /// readings.
    pub latest: Option<sph_core::gpu_layout::GpuProbes>,
}

/// The GPU clock as last read back (every frame, asynchronously, 32 bytes).
#[derive(Resource, Default)]
pub struct ClockReadback {
    /// The clock buffer being read and the entity reading it.
    pub(crate) source: Option<(Handle<bevy::render::storage::ShaderBuffer>, Entity)>,
    /// The latest clock that arrived.
    pub latest: Option<GpuClock>,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_water_waits_for_body_forces_older_than_the_lag_and_not_forever() {
        // Forces of frame 7 while frame 10 is planned: 3 frames old, go on; 4 old, wait.
        assert!(!holds_for_body_forces(10, Some(7), 0));
        assert!(holds_for_body_forces(11, Some(7), 0));
        // Before the first reading the stamp counts as 0.
        assert!(!holds_for_body_forces(2, None, 0));
        assert!(holds_for_body_forces(5, None, 0));
        // Never more than MAX_FRAMES_HELD_FOR_FORCES in a row.
        assert!(holds_for_body_forces(
            50,
            Some(7),
            MAX_FRAMES_HELD_FOR_FORCES - 1
        ));
        assert!(!holds_for_body_forces(
            50,
            Some(7),
            MAX_FRAMES_HELD_FOR_FORCES
        ));
        // The frame counter wraps.
        assert!(!holds_for_body_forces(1, Some(u32::MAX - 1), 0));
        assert!(holds_for_body_forces(3, Some(u32::MAX - 1), 0));
    }

    #[test]
    fn a_capped_plan_covers_at_most_the_time_and_takes_at_least_one_step() {
        let plan = FramePlan {
            steps: 10,
            duration: 0.03,
            budget: None,
        };
        // Two steps of 3 ms fit in 6 ms, rounding aside; the device spends them as a budget.
        let two = plan.capped(0.006, 0.003);
        assert_eq!(two.steps, 2);
        assert!((two.duration - 0.006).abs() < 1e-7);
        assert_eq!(two.budget, Some(two.duration));
        // A step longer than the limit still goes, one a frame, shortened to the limit.
        let one = plan.capped(0.006, 1.0 / 120.0);
        assert_eq!(
            (one.steps, one.duration, one.budget),
            (1, 0.006, Some(0.006))
        );
        let single = FramePlan {
            steps: 1,
            duration: 1.0 / 120.0,
            budget: None,
        };
        assert_eq!(single.capped(0.006, 1.0 / 120.0), one);
        // A plan within the limit, or without a known dt, is left alone.
        assert_eq!(plan.capped(1.0, 0.003), plan);
        assert_eq!(plan.capped(0.006, 0.0), plan);
        // Real-time mode's budget is cut with the steps.
        let real_time = FramePlan {
            steps: 6,
            duration: 1.0 / 60.0,
            budget: Some(1.0 / 60.0),
        };
        let cut = real_time.capped(0.006, 0.0028);
        assert_eq!(cut.steps, 2);
        assert_eq!(cut.budget, Some(cut.duration));
    }
}
