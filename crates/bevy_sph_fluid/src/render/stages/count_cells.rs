//! Pass 1 of the neighbour sort fused with the integrator's pre-evaluation phase
//! (`count_cells.wgsl`; CPU twins `sph_core::neighbor::grid::DenseGrid::count_cells`,
//! `sph_core::neighbor::hash::SpatialHash::sort` keys, `sph_core::integrate::{kick_drift,
//! leapfrog_drift}`).

use super::{encode_pass, workgroups};
use crate::render::buffers::slot;
use crate::render::SphRun;
use bevy::asset::{embedded_asset, load_embedded_asset};
use bevy::prelude::*;
use bevy::render::render_resource::PipelineCache;
use bevy::render::renderer::RenderContext;

pub(crate) fn embed(app: &mut App) {
    embedded_asset!(app, "count_cells.wgsl");
}

pub(crate) fn load(asset_server: &AssetServer) -> Handle<Shader> {
    load_embedded_asset!(asset_server, "count_cells.wgsl")
}

/// Clears the cell counts (grid) and counts every particle into its cell, or writes every
/// slot's hash key (hash, padded to the sort length).
pub fn sph_count_cells(mut ctx: RenderContext, mut run: ResMut<SphRun>, cache: Res<PipelineCache>) {
    let grid = run.pipelines.prefix_sum.is_some();
    if grid {
        ctx.command_encoder()
            .clear_buffer(run.buffers.at(slot::CELL_COUNTS), 0, None);
    }
    let pipeline = run.pipelines.count_for(run.plan.pre);
    encode_pass(
        &mut ctx,
        &mut run,
        &cache,
        "sph_count_cells",
        pipeline,
        |pass, run| {
            let threads = if grid {
                run.particle_count
            } else {
                run.buffers.sort_length
            };
            pass.dispatch_workgroups(workgroups(threads), 1, 1);
            1
        },
    );
}
