//! Pass 2 of the grid sort: exclusive prefix sum of the cell counts in one workgroup
//! (`prefix_sum.wgsl`; CPU twin `sph_core::neighbor::grid::DenseGrid::prefix_sum`).

use super::encode_pass;
use crate::render::SphRun;
use bevy::asset::{embedded_asset, load_embedded_asset};
use bevy::prelude::*;
use bevy::render::render_resource::PipelineCache;
use bevy::render::renderer::RenderContext;

pub(crate) fn embed(app: &mut App) {
    embedded_asset!(app, "prefix_sum.wgsl");
}

pub(crate) fn load(asset_server: &AssetServer) -> Handle<Shader> {
    load_embedded_asset!(asset_server, "prefix_sum.wgsl")
}

/// cell_start = exclusive scan of the counts (grid mode only).
pub fn sph_prefix_sum(mut ctx: RenderContext, mut run: ResMut<SphRun>, cache: Res<PipelineCache>) {
    let Some(pipeline) = run.pipelines.prefix_sum else {
        return;
    };
    encode_pass(
        &mut ctx,
        &mut run,
        &cache,
        "sph_prefix_sum",
        pipeline,
        |pass, _| {
            pass.dispatch_workgroups(1, 1, 1);
            1
        },
    );
}
