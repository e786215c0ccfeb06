//! Whitewater's counting sort, pass 1 (`whitewater_bin.wgsl`): each live diffuse particle's cell
//! and rank in it. An ordering only: its CPU twin is the whitewater step it speeds up
//! (`sph_core::whitewater::ihmsen2012`), whose results it leaves unchanged.

use crate::render::buffers::Buf;
use crate::render::stage::{Dispatch, GpuStage, StageRun};
use bevy::asset::{embedded_asset, load_embedded_asset};
use bevy::render::render_resource::CommandEncoder;
use sph_core::gpu_layout::WORKGROUP_SIZE;
use sph_core::CpuStage;

/// Counts the live diffuse particles per cell.
pub const STAGE: GpuStage = GpuStage {
    name: "sph_whitewater_bin",
    cpu_twin: CpuStage::Whitewater,
    embed: |app| embedded_asset!(app, "whitewater_bin.wgsl"),
    shader: |server| load_embedded_asset!(server, "whitewater_bin.wgsl"),
    bindings: &[Buf::DiffuseState, Buf::DiffuseBins, Buf::DiffuseOrder],
    workgroup_size: WORKGROUP_SIZE,
    roles: &[&[]],
    role: GpuStage::after_the_steps_first_sort,
    dispatch: Dispatch::Threads(|run| run.buffers.diffuse_capacity),
    before: Some(clear_bins),
    after: None,
};

/// The counts start from zero every step.
fn clear_bins(encoder: &mut CommandEncoder, run: &StageRun) {
    run.buffers.clear(encoder, Buf::DiffuseBins);
}
