//! The render world: the frame plan is extracted, the GPU buffers are prepared, and the stage
//! systems of [`SphGraphSystems`] run once per force evaluation inside the [`SphStep`] schedule,
//! which the `sph_simulate` system of Bevy's `RenderGraph` schedule runs for every evaluation of
//! every step of the frame (substeps and the design's two-evaluation leapfrog repeat stages in
//! an interleaved order that a once-per-frame chain could not express).

pub mod buffers;
pub mod pipelines;
pub mod stages;

use crate::api::SphBackend;
use crate::api::SphGpuBuffers;
use crate::simulation::{SphFrame, SphSimulation};
use bevy::asset::RenderAssetUsages;
use bevy::core_pipeline::schedule::camera_driver;
use bevy::ecs::schedule::ScheduleLabel;
use bevy::prelude::*;
use bevy::render::render_resource::{BindGroup, CachedPipelineState, PipelineCache};
use bevy::render::renderer::{RenderGraph, RenderGraphSystems};
use bevy::render::storage::ShaderBuffer;
use bevy::render::{Extract, ExtractSchedule, Render, RenderApp, RenderStartup, RenderSystems};
use bevy::shader::load_shader_library;
use buffers::SphGpuState;
use pipelines::{SphPipelines, StagePipelines, VariantKey};
use sph_core::Integrator;
use std::sync::{Arc, Mutex};

/// The stage passes, as named in GPU timings (`render/<name>/elapsed_gpu`).
pub const STAGE_NAMES: [&str; 10] = [
    "sph_time_step",
    "sph_count_cells",
    "sph_prefix_sum",
    "sph_bitonic_sort",
    "sph_hash_offsets",
    "sph_scatter",
    "sph_density",
    "sph_normals",
    "sph_forces",
    "sph_integrate",
];

/// The public, chained set of stage systems in the [`SphStep`] schedule: time step (before a
/// drifting count pass), count cells, prefix sum (grid) or bitonic sort + hash offsets (hash),
/// scatter, density, normals (surface tension only), forces, time step and integrate (symplectic
/// Euler only).
#[derive(SystemSet, Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct SphGraphSystems;

/// One force evaluation: the stage systems, run by `sph_simulate` as often as the integrator and
/// the substeps need.
#[derive(ScheduleLabel, Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct SphStep;

/// The integrator phase fused into the count pass, before the neighbour sort.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum PrePhase {
    /// Nothing: forces at the current state.
    #[default]
    None,
    /// Kick-drift-kick: half kick, drift, collide, predicted velocity.
    KickDrift,
    /// The design's leapfrog: drift with a0, predicted velocity.
    LeapfrogDrift,
}

/// What the forces pass does besides computing accelerations.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum ForcesRole {
    /// Accelerations from the current velocities, nothing else.
    #[default]
    Plain,
    /// Kick-drift-kick closing kick (viscosity sees predicted velocities).
    KickClose,
    /// The design's leapfrog, first evaluation: keep a0.
    LeapfrogFirst,
    /// The design's leapfrog, second evaluation: v += (a0 + a1) dt/2.
    LeapfrogSecond,
}

/// One force evaluation's plan.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct EvaluationPlan {
    /// Phase fused into the count pass.
    pub pre: PrePhase,
    /// Role of the forces pass.
    pub forces: ForcesRole,
    /// Run the symplectic-Euler integrate pass after the forces.
    pub euler: bool,
    /// Where the time-step pass runs in this evaluation: right before the step's first
    /// integration phase.
    pub time_step: TimeStepPoint,
}

/// Where an evaluation runs the time-step pass.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum TimeStepPoint {
    /// Not in this evaluation.
    #[default]
    None,
    /// Before the count pass (its pre-phase drifts: kick-drift-kick, the leapfrog's second
    /// evaluation).
    Start,
    /// Between the forces and the integrate pass (symplectic Euler).
    BeforeIntegrate,
}

/// The evaluations of one step (kick-drift-kick with stale forces evaluates them first).
pub fn evaluation_plans(integrator: Integrator, forces_stale: bool) -> Vec<EvaluationPlan> {
    let plain = EvaluationPlan::default();
    match integrator {
        Integrator::SymplecticEuler => vec![EvaluationPlan {
            euler: true,
            time_step: TimeStepPoint::BeforeIntegrate,
            ..plain
        }],
        Integrator::KickDriftKick => {
            let step = EvaluationPlan {
                pre: PrePhase::KickDrift,
                forces: ForcesRole::KickClose,
                time_step: TimeStepPoint::Start,
                ..plain
            };
            if forces_stale {
                vec![plain, step]
            } else {
                vec![step]
            }
        }
        Integrator::Leapfrog => vec![
            EvaluationPlan {
                forces: ForcesRole::LeapfrogFirst,
                ..plain
            },
            EvaluationPlan {
                pre: PrePhase::LeapfrogDrift,
                forces: ForcesRole::LeapfrogSecond,
                time_step: TimeStepPoint::Start,
                ..plain
            },
        ],
    }
}

/// Everything the stage systems need for the evaluation being encoded.
#[derive(Resource, Clone)]
pub struct SphRun {
    /// Group 0.
    pub bind_group: BindGroup,
    /// Group 1 of the bitonic sort and each step's dynamic offset (hash mode).
    pub bitonic: Option<(BindGroup, Vec<u32>)>,
    /// Pipelines of the current variant.
    pub pipelines: StagePipelines,
    /// The buffers, for clears and copies.
    pub buffers: buffers::GpuBuffers,
    /// Live particles.
    pub particle_count: u32,
    /// The evaluation being encoded.
    pub plan: EvaluationPlan,
    /// Record GPU timestamps for this evaluation.
    pub timed: bool,
    /// Dispatches encoded so far this frame.
    pub dispatches: u32,
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
}

/// Shared between the worlds (render writes, main reads).
#[derive(Resource, Clone, Default)]
pub struct SphRenderFeedback(Arc<Mutex<RenderFeedback>>);

impl SphRenderFeedback {
    /// A copy of the current feedback.
    pub fn get(&self) -> RenderFeedback {
        self.0.lock().map(|f| f.clone()).unwrap_or_default()
    }

    fn update(&self, f: impl FnOnce(&mut RenderFeedback)) {
        if let Ok(mut guard) = self.0.lock() {
            f(&mut guard);
        }
    }
}

/// The main world's frame plan, in the render world.
#[derive(Resource, Clone, Default, Deref)]
pub struct ExtractedSphFrame(pub SphFrame);

pub(crate) fn build(app: &mut App) {
    load_shader_library!(app, "shaders/types.wgsl");
    load_shader_library!(app, "shaders/bindings.wgsl");
    load_shader_library!(app, "shaders/kernels.wgsl");
    load_shader_library!(app, "shaders/neighbors.wgsl");
    load_shader_library!(app, "shaders/clock.wgsl");
    stages::embed_shaders(app);
    let feedback = SphRenderFeedback::default();
    app.insert_resource(feedback.clone());
    let Some(render_app) = app.get_sub_app_mut(RenderApp) else {
        return;
    };
    let mut step = bevy::ecs::schedule::Schedule::new(SphStep);
    step.configure_sets(SphGraphSystems);
    render_app
        .insert_resource(feedback)
        .init_resource::<SphGpuState>()
        .init_resource::<ExtractedSphFrame>()
        .add_schedule(step)
        .add_systems(SphStep, stages::stage_systems().in_set(SphGraphSystems))
        .add_systems(ExtractSchedule, extract_sph_frame)
        .add_systems(RenderStartup, pipelines::init_sph_pipelines)
        .add_systems(
            Render,
            (
                (pipelines::queue_sph_pipelines, buffers::prepare_sph_buffers)
                    .in_set(RenderSystems::PrepareResources),
                buffers::prepare_sph_bind_groups.in_set(RenderSystems::PrepareBindGroups),
            ),
        )
        .add_systems(
            RenderGraph,
            sph_simulate
                .in_set(RenderGraphSystems::Render)
                .before(camera_driver),
        );
}

/// Creates the readable state buffers once the backend is known to be the GPU.
pub(crate) fn finish(app: &mut App) {
    let world = app.world_mut();
    let (backend, capacity) = {
        let sim = world.resource::<SphSimulation>();
        (sim.backend, sim.capacity)
    };
    if backend != SphBackend::Gpu {
        return;
    }
    let Some(mut assets) = world.get_resource_mut::<Assets<ShaderBuffer>>() else {
        return;
    };
    let buffers = SphGpuBuffers::new(&mut assets, capacity);
    world.insert_resource(buffers.clone());
    world.resource_mut::<SphSimulation>().frame.buffers = Some(buffers);
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
            neighbor_count: make(4 * n),
            clock: make(std::mem::size_of::<sph_core::gpu_layout::GpuClock>()),
        }
    }
}

fn extract_sph_frame(mut commands: Commands, sim: Extract<Res<SphSimulation>>) {
    commands.insert_resource(ExtractedSphFrame(sim.frame.clone()));
}

/// Why a set of pipelines cannot run yet, or `None` when all are ready.
fn pipelines_not_ready(cache: &PipelineCache, stage: &StagePipelines) -> Option<String> {
    for id in stage.all() {
        match cache.get_compute_pipeline_state(id) {
            CachedPipelineState::Ok(_) => {}
            CachedPipelineState::Err(e) => return Some(format!("gpu: shader error: {e}")),
            _ => return Some("gpu: compiling shaders".to_string()),
        }
    }
    None
}

/// Runs this frame's steps: for every step, the [`SphStep`] schedule once per force evaluation.
pub fn sph_simulate(world: &mut World) {
    let frame = world.resource::<ExtractedSphFrame>();
    if !frame.active || frame.steps == 0 {
        return;
    }
    let (steps, params) = (frame.steps, frame.params);
    let feedback = world.resource::<SphRenderFeedback>().clone();
    let state = world.resource::<SphGpuState>();
    let (Some(bind_group), Some(gpu_buffers)) = (state.bind_group.clone(), state.buffers.clone())
    else {
        feedback.update(|f| {
            f.status = state
                .status
                .clone()
                .or(Some("gpu: preparing buffers".into()))
        });
        return;
    };
    let particle_count = state.particle_count;
    let mut forces_stale = state.forces_stale;
    let bitonic = state.bitonic_bind_group.clone();
    let key = VariantKey::of(&params, frame.neighbor_counts);
    let Some(stage) = world.resource::<SphPipelines>().variants.get(&key).cloned() else {
        feedback.update(|f| f.status = Some("gpu: compiling shaders".into()));
        return;
    };
    if let Some(why) = pipelines_not_ready(world.resource::<PipelineCache>(), &stage) {
        feedback.update(|f| f.status = Some(why));
        return;
    }
    world.insert_resource(SphRun {
        bind_group,
        bitonic,
        pipelines: stage,
        buffers: gpu_buffers,
        particle_count,
        plan: EvaluationPlan::default(),
        timed: false,
        dispatches: 0,
    });
    let mut last_step_dispatches = 0;
    for step in 0..steps {
        let before = world.resource::<SphRun>().dispatches;
        for (k, plan) in evaluation_plans(params.integrator, forces_stale)
            .into_iter()
            .enumerate()
        {
            {
                let mut run = world.resource_mut::<SphRun>();
                run.plan = plan;
                run.timed = step == 0 && k == 0;
            }
            world.run_schedule(SphStep);
        }
        forces_stale = false;
        last_step_dispatches = world.resource::<SphRun>().dispatches - before;
    }
    world.resource_mut::<SphGpuState>().forces_stale = false;
    feedback.update(|f| {
        f.step_count += steps as u64;
        f.dispatches_per_step = last_step_dispatches;
        f.status = None;
    });
}
