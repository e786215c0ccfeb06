//! Forces pass with the integrator's closing phase (`forces.wgsl`; CPU twins
//! `sph_core::forces` and `sph_core::integrate::{kick, leapfrog_kick}`).

use super::{encode_pass, workgroups};
use crate::render::SphRun;
use bevy::asset::{embedded_asset, load_embedded_asset};
use bevy::prelude::*;
use bevy::render::render_resource::PipelineCache;
use bevy::render::renderer::RenderContext;

pub(crate) fn embed(app: &mut App) {
    embedded_asset!(app, "forces.wgsl");
}

pub(crate) fn load(asset_server: &AssetServer) -> Handle<Shader> {
    load_embedded_asset!(asset_server, "forces.wgsl")
}

/// Pressure, viscosity, surface tension and gravity for every particle, in the evaluation's role.
pub fn sph_forces(mut ctx: RenderContext, mut run: ResMut<SphRun>, cache: Res<PipelineCache>) {
    let pipeline = run.pipelines.forces_for(run.plan.forces);
    encode_pass(
        &mut ctx,
        &mut run,
        &cache,
        "sph_forces",
        pipeline,
        |pass, run| {
            pass.dispatch_workgroups(workgroups(run.particle_count), 1, 1);
            1
        },
    );
}
