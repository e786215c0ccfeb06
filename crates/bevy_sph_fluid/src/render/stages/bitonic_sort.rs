//! The design's bitonic sort of (hash key, particle) pairs: one dispatch per (k, j) step,
//! log2(n)(log2(n)+1)/2 of them (`bitonic_sort.wgsl`; CPU twin: the stable sort by key in
//! `sph_core::neighbor::hash::SpatialHash::sort`, which ties on the particle index the same way).

use super::{encode_pass, workgroups};
use crate::render::SphRun;
use bevy::asset::{embedded_asset, load_embedded_asset};
use bevy::prelude::*;
use bevy::render::render_resource::PipelineCache;
use bevy::render::renderer::RenderContext;

pub(crate) fn embed(app: &mut App) {
    embedded_asset!(app, "bitonic_sort.wgsl");
}

pub(crate) fn load(asset_server: &AssetServer) -> Handle<Shader> {
    load_embedded_asset!(asset_server, "bitonic_sort.wgsl")
}

/// Sorts the keys (hash mode only).
pub fn sph_bitonic_sort(
    mut ctx: RenderContext,
    mut run: ResMut<SphRun>,
    cache: Res<PipelineCache>,
) {
    let (Some(pipeline), Some((bind_group, offsets))) =
        (run.pipelines.bitonic_sort, run.bitonic.clone())
    else {
        return;
    };
    encode_pass(
        &mut ctx,
        &mut run,
        &cache,
        "sph_bitonic_sort",
        pipeline,
        |pass, run| {
            let groups = workgroups(run.buffers.sort_length);
            for &offset in &offsets {
                pass.set_bind_group(1, &bind_group, &[offset]);
                pass.dispatch_workgroups(groups, 1, 1);
            }
            offsets.len() as u32
        },
    );
}
