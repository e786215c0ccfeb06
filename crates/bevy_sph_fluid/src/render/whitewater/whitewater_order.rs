//! Whitewater's counting sort, pass 3 (`whitewater_order.wgsl`): the live slots in cell order.
//! An ordering only (CPU twin: the whitewater step it speeds up).

use crate::render::buffers::Buf;
use crate::render::stage::{Dispatch, GpuStage};
use bevy::asset::{embedded_asset, load_embedded_asset};
use sph_core::gpu_layout::WORKGROUP_SIZE;
use sph_core::CpuStage;

/// Lists the live slots in cell order.
pub const STAGE: GpuStage = GpuStage {
    name: "sph_whitewater_order",
    cpu_twin: CpuStage::Whitewater,
    embed: |app| embedded_asset!(app, "whitewater_order.wgsl"),
    shader: |server| load_embedded_asset!(server, "whitewater_order.wgsl"),
    bindings: &[Buf::DiffuseState, Buf::DiffuseBins, Buf::DiffuseOrder],
    workgroup_size: WORKGROUP_SIZE,
    roles: &[&[]],
    role: GpuStage::after_the_steps_first_sort,
    dispatch: Dispatch::Threads(|run| run.buffers.diffuse_capacity),
    before: None,
    after: None,
};
