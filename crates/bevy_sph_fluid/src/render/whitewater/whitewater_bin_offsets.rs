//! Whitewater's counting sort, pass 2 (`whitewater_bin_offsets.wgsl`): each cell's first rank,
//! in one workgroup. An ordering only (CPU twin: the whitewater step it speeds up).

use crate::render::buffers::Buf;
use crate::render::stage::{Dispatch, GpuStage};
use bevy::asset::{embedded_asset, load_embedded_asset};
use sph_core::gpu_layout::WORKGROUP_SIZE;
use sph_core::CpuStage;

/// The exclusive prefix sum of the per-cell counts, in place.
pub const STAGE: GpuStage = GpuStage {
    name: "sph_whitewater_bin_offsets",
    cpu_twin: CpuStage::Whitewater,
    embed: |app| embedded_asset!(app, "whitewater_bin_offsets.wgsl"),
    shader: |server| load_embedded_asset!(server, "whitewater_bin_offsets.wgsl"),
    bindings: &[Buf::DiffuseBins],
    workgroup_size: WORKGROUP_SIZE,
    roles: &[&[]],
    role: GpuStage::after_the_steps_first_sort,
    dispatch: Dispatch::Threads(|_| WORKGROUP_SIZE),
    before: None,
    after: None,
};
