//! The neighbour lists PBF and DFSPH share: PBF's after the sort of the predicted positions,
//! DFSPH's after each of its sorts (`neighbor_lists.wgsl`; CPU twin
//! `sph_core::neighbor::lists::NeighborLists::rebuild`).

use crate::render::buffers::Buf;
use crate::render::plan::EvaluationPlan;
use crate::render::solvers::dfsph::phase::DfsphPhase;
use crate::render::solvers::pbf::phase::PbfPhase;
use crate::render::stage::{Dispatch, GpuStage};
use bevy::asset::{embedded_asset, load_embedded_asset};
use sph_core::gpu_layout::WORKGROUP_SIZE;
use sph_core::CpuStage;

/// The pairs within h at x* of every particle, once per PBF step (in its prediction phase):
/// the iterations then visit about 33 neighbours each instead of the 27 cells' candidates.
/// DFSPH builds the same lists after each of its sorts, for its solves' dozens of passes.
pub const STAGE: GpuStage = GpuStage {
    name: "sph_neighbor_lists",
    cpu_twin: CpuStage::NeighborLists,
    embed: |app| embedded_asset!(app, "neighbor_lists.wgsl"),
    shader: |server| load_embedded_asset!(server, "neighbor_lists.wgsl"),
    bindings: &[
        Buf::Position,
        Buf::NeighborCount,
        Buf::NeighborLists,
        Buf::CellStart,
        Buf::BucketStart,
        Buf::BucketEnd,
        Buf::Clock,
    ],
    workgroup_size: WORKGROUP_SIZE,
    roles: &[&[]],
    role: |plan: &EvaluationPlan| {
        let dfsph = plan.dfsph != DfsphPhase::None && plan.sorts();
        (plan.pbf == PbfPhase::Predict || dfsph).then_some(0)
    },
    dispatch: Dispatch::Threads(GpuStage::per_particle),
    before: None,
    after: None,
};
