//! Whitewater's potentials and shedding (`whitewater_shed.wgsl`; CPU twin
//! `sph_core::whitewater::ihmsen2012`: `FluidView::potentials`, `shed_count`), one thread per
//! fluid particle.

use crate::render::buffers::Buf;
use crate::render::stage::{Dispatch, GpuStage};
use bevy::asset::{embedded_asset, load_embedded_asset};
use sph_core::gpu_layout::WORKGROUP_SIZE;
use sph_core::CpuStage;

/// The water's potentials at every fluid particle, and the diffuse particles they shed.
pub const STAGE: GpuStage = GpuStage {
    name: "sph_whitewater_shed",
    cpu_twin: CpuStage::Whitewater,
    embed: |app| embedded_asset!(app, "whitewater_shed.wgsl"),
    shader: |server| load_embedded_asset!(server, "whitewater_shed.wgsl"),
    bindings: &[
        Buf::Position,
        Buf::Velocity,
        Buf::CellStart,
        Buf::BucketStart,
        Buf::BucketEnd,
        Buf::WhitewaterFluid,
        Buf::DiffuseState,
        Buf::DiffuseFree,
        Buf::DiffuseCounts,
        Buf::Clock,
    ],
    workgroup_size: WORKGROUP_SIZE,
    roles: &[&[]],
    role: GpuStage::after_the_steps_first_sort,
    dispatch: Dispatch::Threads(GpuStage::per_particle),
    before: None,
    after: None,
};
