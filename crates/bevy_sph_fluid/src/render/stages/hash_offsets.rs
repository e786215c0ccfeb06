//! The design's cell offsets: where each hash bucket starts and ends in the sorted keys
//! (`hash_offsets.wgsl`; CPU twin: the offset loop of `sph_core::neighbor::hash::SpatialHash::sort`).

use crate::render::buffers::Buf;
use crate::render::stage::{Dispatch, GpuStage, StageRun};
use bevy::asset::{embedded_asset, load_embedded_asset};
use bevy::render::render_resource::CommandEncoder;
use sph_core::gpu_layout::WORKGROUP_SIZE;
use sph_core::CpuStage;

/// Clears the bucket starts and records each bucket's range (hash mode only).
pub const STAGE: GpuStage = GpuStage {
    name: "sph_hash_offsets",
    cpu_twin: CpuStage::Sort,
    embed: |app| embedded_asset!(app, "hash_offsets.wgsl"),
    shader: |server| load_embedded_asset!(server, "hash_offsets.wgsl"),
    bindings: &[Buf::SortKeys, Buf::BucketStart, Buf::BucketEnd, Buf::Clock],
    workgroup_size: WORKGROUP_SIZE,
    roles: &[&[]],
    role: GpuStage::every_evaluation,
    dispatch: Dispatch::Threads(GpuStage::per_particle),
    before: Some(clear_bucket_starts),
    after: None,
};

fn clear_bucket_starts(encoder: &mut CommandEncoder, run: &StageRun) {
    run.buffers.clear(encoder, Buf::BucketStart);
}
