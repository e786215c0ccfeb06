//! The design's cell offsets: where each hash bucket starts and ends in the sorted keys
//! (`hash_offsets.wgsl`; CPU twin: the offset loop of `sph_core::neighbor::hash::SpatialHash::sort`).

use super::{encode_pass, workgroups};
use crate::render::buffers::slot;
use crate::render::SphRun;
use bevy::asset::{embedded_asset, load_embedded_asset};
use bevy::prelude::*;
use bevy::render::render_resource::PipelineCache;
use bevy::render::renderer::RenderContext;

pub(crate) fn embed(app: &mut App) {
    embedded_asset!(app, "hash_offsets.wgsl");
}

pub(crate) fn load(asset_server: &AssetServer) -> Handle<Shader> {
    load_embedded_asset!(asset_server, "hash_offsets.wgsl")
}

/// Clears the bucket starts and records each bucket's range (hash mode only).
pub fn sph_hash_offsets(
    mut ctx: RenderContext,
    mut run: ResMut<SphRun>,
    cache: Res<PipelineCache>,
) {
    let Some(pipeline) = run.pipelines.hash_offsets else {
        return;
    };
    ctx.command_encoder()
        .clear_buffer(run.buffers.at(slot::BUCKET_START), 0, None);
    encode_pass(
        &mut ctx,
        &mut run,
        &cache,
        "sph_hash_offsets",
        pipeline,
        |pass, run| {
            pass.dispatch_workgroups(workgroups(run.particle_count), 1, 1);
            1
        },
    );
}
