//! Density and pressure pass (`density.wgsl`; CPU twin `sph_core::density`).

use crate::render::buffers::Buf;
use crate::render::stage::{Dispatch, GpuStage};
use bevy::asset::{embedded_asset, load_embedded_asset};
use sph_core::gpu_layout::WORKGROUP_SIZE;
use sph_core::{CpuStage, WcsphStage};

/// ρ_i = m Σ W_poly6 + ρ0 Σ_b V_b W_poly6 (the boundary samples), p_i = EOS(ρ_i) into the equation of state's pressures (the free-surface pass writes the pressures from them) for every particle (with `NEIGHBOR_COUNT`, the variant
/// shader def of the debug views, also the neighbours within h).
pub const STAGE: GpuStage = GpuStage {
    name: "sph_density",
    cpu_twin: CpuStage::Wcsph(WcsphStage::Density),
    embed: |app| embedded_asset!(app, "density.wgsl"),
    shader: |server| load_embedded_asset!(server, "density.wgsl"),
    bindings: &[
        Buf::Position,
        Buf::Density,
        Buf::PressureEos,
        Buf::NeighborCount,
        Buf::CellStart,
        Buf::BucketStart,
        Buf::BucketEnd,
        Buf::BoundaryPosition,
        Buf::BoundaryCellStart,
    ],
    workgroup_size: WORKGROUP_SIZE,
    roles: &[&[]],
    role: GpuStage::every_evaluation,
    dispatch: Dispatch::Threads(GpuStage::per_particle),
    before: None,
    after: None,
};
