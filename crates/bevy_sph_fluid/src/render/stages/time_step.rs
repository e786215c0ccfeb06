//! The time step, right before each step's first integration phase (`time_step.wgsl`; CPU twin `sph_core::stability` and
//! `CpuSolver::step`): checks the previous step's recorded extremes for instability (freezing
//! the clock), chooses dt (fixed, or the adaptive CFL rule) and advances the simulated time, all on
//! the GPU, so the CPU never waits for the maximum speed.

use super::encode_pass;
use crate::render::{SphRun, TimeStepPoint};
use bevy::asset::{embedded_asset, load_embedded_asset};
use bevy::prelude::*;
use bevy::render::render_resource::PipelineCache;
use bevy::render::renderer::RenderContext;

pub(crate) fn embed(app: &mut App) {
    embedded_asset!(app, "time_step.wgsl");
}

pub(crate) fn load(asset_server: &AssetServer) -> Handle<Shader> {
    load_embedded_asset!(asset_server, "time_step.wgsl")
}

/// One thread before a drifting count pass (kick-drift-kick, the leapfrog's second evaluation).
pub fn sph_time_step(ctx: RenderContext, run: ResMut<SphRun>, cache: Res<PipelineCache>) {
    if run.plan.time_step == TimeStepPoint::Start {
        encode(ctx, run, cache);
    }
}

/// One thread between the forces and the integrate pass (symplectic Euler).
pub fn sph_time_step_before_integrate(
    ctx: RenderContext,
    run: ResMut<SphRun>,
    cache: Res<PipelineCache>,
) {
    if run.plan.time_step == TimeStepPoint::BeforeIntegrate {
        encode(ctx, run, cache);
    }
}

fn encode(mut ctx: RenderContext, mut run: ResMut<SphRun>, cache: Res<PipelineCache>) {
    let pipeline = run.pipelines.time_step;
    encode_pass(
        &mut ctx,
        &mut run,
        &cache,
        "sph_time_step",
        pipeline,
        |pass, _| {
            pass.dispatch_workgroups(1, 1, 1);
            1
        },
    );
}
