//! The frame's steps: `sph_simulate` (Bevy's `RenderGraph` schedule, before the camera driver)
//! runs the [`SphStep`] schedule once per force evaluation (PBF: once per phase) of every
//! step, and
//! `sph_encode_stages`, the one system of that schedule, encodes the scene's stage list;
//! `sph_publish_state` then copies the state where the main world reads it.

use super::buffers::SphGpuState;
use super::extract::ExtractedSphFrame;
use super::pipelines::{pipelines_not_ready, SphPipelines};
use super::plan::{EvaluationPlan, VariantKey};
use super::solvers::dfsph::phase::DfsphPhase;
use super::solvers::frame_step_plans;
use super::solvers::pbf::phase::PbfPhase;
use super::stage::{encode_stage, StageRun};
use crate::api::{STATUS_COMPILING_SHADERS, STATUS_PREPARING_BUFFERS};
use crate::sets::SphStep;
use crate::shared::SphRenderFeedback;
use bevy::prelude::*;
use bevy::render::render_resource::PipelineCache;
use bevy::render::renderer::RenderContext;

/// Encodes every stage of the list, in order, for the evaluation in [`StageRun::plan`].
pub fn sph_encode_stages(
    mut ctx: RenderContext,
    mut run: ResMut<StageRun>,
    cache: Res<PipelineCache>,
) {
    let stages = std::mem::take(&mut run.stages);
    for queued in &stages {
        encode_stage(&mut ctx, &mut run, &cache, queued);
    }
    run.stages = stages;
}

/// Copies the state to the main world's buffers every frame the simulation is active (after
/// the steps, spawns or a reset), so snapshots, the surface and the every-frame readbacks see it.
pub fn sph_publish_state(
    mut ctx: RenderContext,
    frame: Res<ExtractedSphFrame>,
    state: Res<SphGpuState>,
) {
    if !frame.active {
        return;
    }
    if let Some(buffers) = &state.buffers {
        buffers.publish(ctx.command_encoder(), state.particle_count);
        if let Some(target) = state.body_target.as_ref().filter(|_| buffers.key.bodies) {
            let (arena, at) = buffers.at(super::buffers::Buf::BodyWords);
            let from = at + sph_core::gpu_layout::GPU_BODY_STATES_OFFSET as u64;
            let bytes = (std::mem::size_of::<sph_core::gpu_layout::GpuBodyStates>() as u64)
                .min(target.size());
            ctx.command_encoder()
                .copy_buffer_to_buffer(arena, from, target, 0, Some(bytes));
        }
        if let Some(targets) = &state.whitewater_targets {
            super::whitewater::publish(
                buffers,
                ctx.command_encoder(),
                targets,
                state.particle_count,
            );
        }
    }
}

/// Runs this frame's steps: for every step, the [`SphStep`] schedule once per force evaluation.
pub fn sph_simulate(world: &mut World) {
    let frame = world.resource::<ExtractedSphFrame>();
    if !frame.active || frame.steps == 0 {
        return;
    }
    let (steps, params, dfsph_iterations) = (frame.steps, frame.params, frame.dfsph_iterations);
    let key = VariantKey::of_frame(frame);
    let feedback = world.resource::<SphRenderFeedback>().clone();
    let state = world.resource::<SphGpuState>();
    let Some(gpu_buffers) = state
        .buffers
        .clone()
        .filter(|_| !state.bind_groups.is_empty())
    else {
        feedback.update(|f| {
            f.status = state
                .status
                .clone()
                .or(Some(STATUS_PREPARING_BUFFERS.into()))
        });
        return;
    };
    // Whitewater's stages run only on buffers that hold its regions (a frame whose buffers
    // could not be reallocated yet runs without).
    let key = VariantKey {
        whitewater: key.whitewater && gpu_buffers.key.whitewater,
        ..key
    };
    let particle_count = state.particle_count;
    let boundary_samples = state.boundary_samples;
    let mut forces_stale = state.forces_stale;
    let bitonic = state.bitonic_bind_group.clone();
    let bind_groups = state.bind_groups.clone();
    let Some(list) = world.resource::<SphPipelines>().variants.get(&key).cloned() else {
        feedback.update(|f| f.status = Some(STATUS_COMPILING_SHADERS.into()));
        return;
    };
    if let Some(why) = pipelines_not_ready(world.resource::<PipelineCache>(), &list) {
        feedback.update(|f| f.status = Some(why));
        return;
    }
    let stage_names = list.iter().map(|q| q.stage.name).collect::<Vec<_>>();
    world.insert_resource(StageRun {
        stages: list,
        bind_groups,
        bitonic,
        buffers: gpu_buffers,
        particle_count,
        boundary_samples,
        plan: EvaluationPlan::default(),
        timed: false,
        dispatches: 0,
    });
    let mut last_step_dispatches = 0;
    for step in 0..steps {
        let before = world.resource::<StageRun>().dispatches;
        let plans = frame_step_plans(&params, forces_stale, dfsph_iterations, step + 1 == steps);
        for (k, plan) in plans.into_iter().enumerate() {
            {
                let mut run = world.resource_mut::<StageRun>();
                run.plan = plan;
                // The first step's first evaluation, or every phase of a PBF or DFSPH step (each
                // of its stages runs in some phases; the iterations' passes are timed in the
                // last).
                run.timed = step == 0
                    && (k == 0 || plan.pbf != PbfPhase::None || plan.dfsph != DfsphPhase::None);
            }
            world.run_schedule(SphStep);
        }
        forces_stale = false;
        last_step_dispatches = world.resource::<StageRun>().dispatches - before;
    }
    world.resource_mut::<SphGpuState>().forces_stale = false;
    feedback.update(|f| {
        f.step_count += steps as u64;
        f.dispatches_per_step = last_step_dispatches;
        f.status = None;
        // The time step has two places in the list; each name once.
        let mut names: Vec<&'static str> = Vec::new();
        for name in stage_names {
            if !names.contains(&name) {
                names.push(name);
            }
        }
        f.stage_names = names;
    });
}
