//! The free surface's pressure pass (`free_surface_pressure.wgsl`; CPU twin
//! `sph_core::free_surface_pressure`).

use crate::render::buffers::Buf;
use crate::render::stage::{Dispatch, GpuStage};
use bevy::asset::{embedded_asset, load_embedded_asset};
use sph_core::gpu_layout::WORKGROUP_SIZE;
use sph_core::{CpuStage, WcsphStage};

/// WCSPH: p_i = the equation of state's p_i where not 0 (the clamp's zero), else the SPH
/// interpolant of the equation of state's pressures around i, Σ_j (m/ρ_j) p_j W_ij, at most
/// ρ0 |g| Δx/2 (at the free surface), for every particle. Reads `PressureEos`, writes
/// `Pressure`, so no particle reads a pressure another thread is writing.
pub const STAGE: GpuStage = GpuStage {
    name: "sph_free_surface_pressure",
    cpu_twin: CpuStage::Wcsph(WcsphStage::FreeSurfacePressure),
    embed: |app| embedded_asset!(app, "free_surface_pressure.wgsl"),
    shader: |server| load_embedded_asset!(server, "free_surface_pressure.wgsl"),
    bindings: &[
        Buf::Position,
        Buf::Density,
        Buf::Pressure,
        Buf::PressureEos,
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
