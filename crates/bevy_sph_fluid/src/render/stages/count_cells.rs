//! Pass 1 of the neighbour sort fused with the integrator's pre-evaluation phase and the
//! rollback checkpoint (`count_cells.wgsl`; CPU twins `sph_core::neighbor::grid::DenseGrid::
//! count_cells`, `sph_core::neighbor::hash::SpatialHash::sort` keys, `sph_core::integrate::
//! {kick_drift, leapfrog_drift}`, step 1 of the PBF step (`sph_core::solver::pbf`), the
//! checkpoint of `CpuSolver::step`).

use crate::render::buffers::Buf;
use crate::render::plan::{EvaluationPlan, PrePhase};
use crate::render::stage::{Dispatch, GpuStage, StageRun};
use bevy::asset::{embedded_asset, load_embedded_asset};
use bevy::render::render_resource::CommandEncoder;
use sph_core::gpu_layout::WORKGROUP_SIZE;
use sph_core::CpuStage;

/// Clears the cell counts (grid) and counts every particle into its cell, or writes every
/// slot's hash key (hash, padded to the sort length). Roles: no pre-phase, kick-drift,
/// leapfrog drift, PBF's prediction, DFSPH's move (the first three drifting roles run right after the time-step pass, so
/// they apply the checkpoint).
pub const STAGE: GpuStage = GpuStage {
    name: "sph_count_cells",
    cpu_twin: CpuStage::Sort,
    embed: |app| embedded_asset!(app, "count_cells.wgsl"),
    shader: |server| load_embedded_asset!(server, "count_cells.wgsl"),
    bindings: &[
        Buf::Position,
        Buf::Velocity,
        Buf::VelocityPredicted,
        Buf::Acceleration,
        Buf::AccelerationStart,
        Buf::CellOf,
        Buf::RankInCell,
        Buf::CellCounts,
        Buf::SortKeys,
        Buf::SortValues,
        Buf::Clock,
        Buf::Checkpoint,
        Buf::BodyForces,
        Buf::Colliders,
        Buf::Meshes,
        Buf::Pumps,
    ],
    workgroup_size: WORKGROUP_SIZE,
    roles: &[
        &[],
        &["PRE_KDK", "APPLY_CHECKPOINT"],
        &["PRE_LEAPFROG", "APPLY_CHECKPOINT"],
        &["PRE_PBF", "APPLY_CHECKPOINT"],
        &["PRE_DFSPH"],
    ],
    role: |plan: &EvaluationPlan| {
        if !plan.sorts() {
            return None;
        }
        Some(match plan.pre {
            PrePhase::None => 0,
            PrePhase::KickDrift => 1,
            PrePhase::LeapfrogDrift => 2,
            PrePhase::PbfPredict => 3,
            PrePhase::DfsphMove => 4,
        })
    },
    dispatch: Dispatch::Threads(|run: &StageRun| {
        if run.buffers.sort_length > 0 {
            run.buffers.sort_length
        } else {
            run.particle_count
        }
    }),
    before: Some(clear_cell_counts),
    after: None,
};

fn clear_cell_counts(encoder: &mut CommandEncoder, run: &StageRun) {
    if run.buffers.sort_length == 0 {
        run.buffers.clear(encoder, Buf::CellCounts);
    }
}
