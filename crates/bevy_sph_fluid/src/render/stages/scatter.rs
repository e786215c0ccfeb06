//! Pass 3 of the sort: every particle's state moves to its sorted slot, then the sorted copies
//! become the state (`scatter.wgsl`; CPU twin `sph_core::neighbor::grid::DenseGrid::scatter` and
//! the reorder in `sph_core::solver`).

use crate::render::buffers::Buf;
use crate::render::stage::{Dispatch, GpuStage, StageRun};
use bevy::asset::{embedded_asset, load_embedded_asset};
use bevy::render::render_resource::CommandEncoder;
use sph_core::gpu_layout::WORKGROUP_SIZE;
use sph_core::CpuStage;

/// Scatters the five state arrays into sorted order and copies them back (copies are not
/// dispatches).
pub const STAGE: GpuStage = GpuStage {
    name: "sph_scatter",
    cpu_twin: CpuStage::Sort,
    embed: |app| embedded_asset!(app, "scatter.wgsl"),
    shader: |server| load_embedded_asset!(server, "scatter.wgsl"),
    bindings: &[
        Buf::Position,
        Buf::Velocity,
        Buf::VelocityPredicted,
        Buf::Acceleration,
        Buf::AccelerationStart,
        Buf::SortedPosition,
        Buf::SortedVelocity,
        Buf::SortedVelocityPredicted,
        Buf::SortedAcceleration,
        Buf::SortedAccelerationStart,
        Buf::CellOf,
        Buf::RankInCell,
        Buf::CellStart,
        Buf::SortValues,
    ],
    workgroup_size: WORKGROUP_SIZE,
    roles: &[&[]],
    role: GpuStage::every_evaluation,
    dispatch: Dispatch::Threads(GpuStage::per_particle),
    before: None,
    after: Some(copy_back),
};

/// The five sorted arrays, in state order, and where each is copied back.
const COPIES: [(Buf, Buf); 5] = [
    (Buf::SortedPosition, Buf::Position),
    (Buf::SortedVelocity, Buf::Velocity),
    (Buf::SortedVelocityPredicted, Buf::VelocityPredicted),
    (Buf::SortedAcceleration, Buf::Acceleration),
    (Buf::SortedAccelerationStart, Buf::AccelerationStart),
];

fn copy_back(encoder: &mut CommandEncoder, run: &StageRun) {
    let bytes = 16 * run.particle_count as u64;
    if bytes == 0 {
        return;
    }
    for (sorted, state) in COPIES {
        run.buffers.copy(encoder, sorted, state, bytes);
    }
}
