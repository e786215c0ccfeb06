//! Pass 2 of the grid sort: exclusive prefix sum of the cell counts in one workgroup
//! (`prefix_sum.wgsl`; CPU twin `sph_core::neighbor::grid::DenseGrid::prefix_sum`).

use crate::render::buffers::Buf;
use crate::render::stage::{Dispatch, GpuStage};
use bevy::asset::{embedded_asset, load_embedded_asset};
use sph_core::gpu_layout::PREFIX_SUM_THREADS;
use sph_core::CpuStage;

/// cell_start = exclusive scan of the counts (grid mode only).
pub const STAGE: GpuStage = GpuStage {
    name: "sph_prefix_sum",
    cpu_twin: CpuStage::Sort,
    embed: |app| embedded_asset!(app, "prefix_sum.wgsl"),
    shader: |server| load_embedded_asset!(server, "prefix_sum.wgsl"),
    bindings: &[Buf::CellCounts, Buf::CellStart, Buf::Clock],
    workgroup_size: PREFIX_SUM_THREADS,
    roles: &[&[]],
    role: GpuStage::every_evaluation,
    dispatch: Dispatch::Threads(|_| PREFIX_SUM_THREADS),
    before: None,
    after: None,
};
