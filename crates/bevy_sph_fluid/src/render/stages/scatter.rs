//! Pass 3 of the sort: every particle's state moves to its sorted slot, then the sorted copies
//! become the state (`scatter.wgsl`; CPU twin `sph_core::neighbor::grid::DenseGrid::scatter` and
//! the reorder in `sph_core::solver`).

use super::{encode_pass, workgroups};
use crate::render::buffers::slot;
use crate::render::SphRun;
use bevy::asset::{embedded_asset, load_embedded_asset};
use bevy::prelude::*;
use bevy::render::render_resource::PipelineCache;
use bevy::render::renderer::RenderContext;

pub(crate) fn embed(app: &mut App) {
    embedded_asset!(app, "scatter.wgsl");
}

pub(crate) fn load(asset_server: &AssetServer) -> Handle<Shader> {
    load_embedded_asset!(asset_server, "scatter.wgsl")
}

/// Scatters the five state arrays into sorted order and copies them back (copies are not
/// dispatches).
pub fn sph_scatter(mut ctx: RenderContext, mut run: ResMut<SphRun>, cache: Res<PipelineCache>) {
    let pipeline = run.pipelines.scatter;
    encode_pass(
        &mut ctx,
        &mut run,
        &cache,
        "sph_scatter",
        pipeline,
        |pass, run| {
            pass.dispatch_workgroups(workgroups(run.particle_count), 1, 1);
            1
        },
    );
    let bytes = 16 * run.particle_count as u64;
    if bytes == 0 {
        return;
    }
    let encoder = ctx.command_encoder();
    for k in 0..5 {
        encoder.copy_buffer_to_buffer(
            run.buffers.at(slot::SORTED_POSITION + k),
            0,
            run.buffers.at(slot::POSITION + k),
            0,
            Some(bytes),
        );
    }
}
