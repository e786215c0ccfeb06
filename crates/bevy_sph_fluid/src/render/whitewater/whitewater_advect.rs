//! Whitewater's advection and deaths (`whitewater_advect.wgsl`; CPU twin
//! `sph_core::whitewater::ihmsen2012::Whitewater::step`), one thread per live slot, in cell order.

use crate::render::buffers::Buf;
use crate::render::stage::{Dispatch, GpuStage};
use bevy::asset::{embedded_asset, load_embedded_asset};
use sph_core::gpu_layout::WORKGROUP_SIZE;
use sph_core::CpuStage;

/// Classifies and moves every live diffuse particle; empties the slots of those that die.
pub const STAGE: GpuStage = GpuStage {
    name: "sph_whitewater_advect",
    cpu_twin: CpuStage::Whitewater,
    embed: |app| embedded_asset!(app, "whitewater_advect.wgsl"),
    shader: |server| load_embedded_asset!(server, "whitewater_advect.wgsl"),
    bindings: &[
        Buf::Position,
        Buf::Velocity,
        Buf::CellStart,
        Buf::BucketStart,
        Buf::BucketEnd,
        Buf::DiffuseState,
        Buf::DiffuseFree,
        Buf::DiffuseCounts,
        Buf::DiffuseBins,
        Buf::DiffuseOrder,
        Buf::Clock,
    ],
    workgroup_size: WORKGROUP_SIZE,
    roles: &[&[]],
    role: GpuStage::after_the_steps_first_sort,
    dispatch: Dispatch::Threads(|run| run.buffers.diffuse_capacity),
    before: None,
    after: None,
};
