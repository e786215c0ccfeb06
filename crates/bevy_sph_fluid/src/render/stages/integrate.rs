//! Symplectic-Euler integration pass (`integrate.wgsl`; CPU twin `sph_core::integrate::euler`).
//! The leapfrogs fuse their phases into the count and forces passes instead.

use super::{encode_pass, workgroups};
use crate::render::SphRun;
use bevy::asset::{embedded_asset, load_embedded_asset};
use bevy::prelude::*;
use bevy::render::render_resource::PipelineCache;
use bevy::render::renderer::RenderContext;

pub(crate) fn embed(app: &mut App) {
    embedded_asset!(app, "integrate.wgsl");
}

pub(crate) fn load(asset_server: &AssetServer) -> Handle<Shader> {
    load_embedded_asset!(asset_server, "integrate.wgsl")
}

/// v += a dt; x += v dt; collide — only in a symplectic-Euler evaluation.
pub fn sph_integrate(mut ctx: RenderContext, mut run: ResMut<SphRun>, cache: Res<PipelineCache>) {
    if !run.plan.euler {
        return;
    }
    let pipeline = run.pipelines.integrate;
    encode_pass(
        &mut ctx,
        &mut run,
        &cache,
        "sph_integrate",
        pipeline,
        |pass, run| {
            pass.dispatch_workgroups(workgroups(run.particle_count), 1, 1);
            1
        },
    );
}
