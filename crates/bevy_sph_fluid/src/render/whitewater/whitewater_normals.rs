//! Whitewater's surface normals (`whitewater_normals.wgsl`; CPU twin
//! `sph_core::whitewater::ihmsen2012::FluidView`). Zeroes the class counters too.

use crate::render::buffers::Buf;
use crate::render::stage::{Dispatch, GpuStage};
use bevy::asset::{embedded_asset, load_embedded_asset};
use sph_core::gpu_layout::WORKGROUP_SIZE;
use sph_core::CpuStage;

/// n̂_i from Σ_j x_ij W̃_ij for every fluid particle.
pub const STAGE: GpuStage = GpuStage {
    name: "sph_whitewater_normals",
    cpu_twin: CpuStage::Whitewater,
    embed: |app| embedded_asset!(app, "whitewater_normals.wgsl"),
    shader: |server| load_embedded_asset!(server, "whitewater_normals.wgsl"),
    bindings: &[
        Buf::Position,
        Buf::CellStart,
        Buf::BucketStart,
        Buf::BucketEnd,
        Buf::WhitewaterFluid,
        Buf::DiffuseCounts,
    ],
    workgroup_size: WORKGROUP_SIZE,
    roles: &[&[]],
    role: GpuStage::after_the_steps_first_sort,
    // Thread 0 runs without particles too: it zeroes the class counters.
    dispatch: Dispatch::Threads(|run| run.particle_count.max(1)),
    before: None,
    after: None,
};
