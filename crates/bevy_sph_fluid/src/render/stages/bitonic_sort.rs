//! The design's bitonic sort of (hash key, particle) pairs: one dispatch per (k, j) step,
//! log2(n)(log2(n)+1)/2 of them (`bitonic_sort.wgsl`; CPU twin: the stable sort by key in
//! `sph_core::neighbor::hash::SpatialHash::sort`, which ties on the particle index the same way).

use crate::render::buffers::Buf;
use crate::render::stage::{Dispatch, GpuStage};
use bevy::asset::{embedded_asset, load_embedded_asset};
use sph_core::gpu_layout::WORKGROUP_SIZE;
use sph_core::CpuStage;

/// Sorts the keys (hash mode only); group 1 holds each step's (k, j).
pub const STAGE: GpuStage = GpuStage {
    name: "sph_bitonic_sort",
    cpu_twin: CpuStage::Sort,
    embed: |app| embedded_asset!(app, "bitonic_sort.wgsl"),
    shader: |server| load_embedded_asset!(server, "bitonic_sort.wgsl"),
    bindings: &[Buf::SortKeys, Buf::SortValues],
    workgroup_size: WORKGROUP_SIZE,
    roles: &[&[]],
    role: GpuStage::every_evaluation,
    dispatch: Dispatch::BitonicSteps,
    before: None,
    after: None,
};
