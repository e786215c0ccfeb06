//! Akinci 2013 normals pass (`normals.wgsl`; CPU twin
//! `sph_core::surface_tension_akinci2013::compute_normals`). Listed only with surface tension.

use crate::render::buffers::Buf;
use crate::render::stage::{Dispatch, GpuStage};
use bevy::asset::{embedded_asset, load_embedded_asset};
use sph_core::gpu_layout::WORKGROUP_SIZE;
use sph_core::CpuStage;

/// n_i = h Σ (m/ρ_j) ∇W for every particle.
pub const STAGE: GpuStage = GpuStage {
    name: "sph_normals",
    cpu_twin: CpuStage::Normals,
    embed: |app| embedded_asset!(app, "normals.wgsl"),
    shader: |server| load_embedded_asset!(server, "normals.wgsl"),
    bindings: &[
        Buf::Position,
        Buf::Density,
        Buf::Normal,
        Buf::CellStart,
        Buf::BucketStart,
        Buf::BucketEnd,
    ],
    workgroup_size: WORKGROUP_SIZE,
    roles: &[&[]],
    role: GpuStage::every_evaluation,
    dispatch: Dispatch::Threads(GpuStage::per_particle),
    before: None,
    after: None,
};
