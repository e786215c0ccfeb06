//! DFSPH's densities and factors after each sort (`dfsph_density.wgsl`; CPU twins
//! `sph_core::neighbor::lists::NeighborLists::rebuild_cubic_spline`, pairs rounded as packed, and
//! `sph_core::solver::dfsph::bender2017::compute_factors`).

use crate::render::buffers::Buf;
use crate::render::plan::EvaluationPlan;
use crate::render::solvers::dfsph::phase::DfsphPhase;
use crate::render::stage::{copy_solve_arguments, Dispatch, GpuStage};
use bevy::asset::{embedded_asset, load_embedded_asset};
use sph_core::gpu_layout::WORKGROUP_SIZE;
use sph_core::{CpuStage, DfsphStage};

/// ρ_i, 1/D_i, Σ_b g_ib, the mirrored share, Σ_b v_b·g_ib, the rise's floor and the neighbour
/// count of every particle, in each DFSPH
/// neighbourhood (the first and after the move); opens the next solve.
pub const STAGE: GpuStage = GpuStage {
    name: "sph_dfsph_density",
    cpu_twin: CpuStage::Dfsph(DfsphStage::Factors),
    embed: |app| embedded_asset!(app, "dfsph_density.wgsl"),
    shader: |server| load_embedded_asset!(server, "dfsph_density.wgsl"),
    bindings: &[
        Buf::Position,
        Buf::Density,
        Buf::AccelerationStart,
        Buf::SortedAccelerationStart,
        Buf::VelocityPredicted,
        Buf::NeighborCount,
        Buf::NeighborLists,
        Buf::DfsphPairs,
        Buf::Pressure,
        Buf::BoundaryPosition,
        Buf::BoundaryVelocity,
        Buf::BoundaryCellStart,
        Buf::DfsphMirror,
        Buf::Clock,
    ],
    workgroup_size: WORKGROUP_SIZE,
    roles: &[&[]],
    role: |plan: &EvaluationPlan| {
        matches!(
            plan.dfsph,
            DfsphPhase::Neighborhood | DfsphPhase::Move { .. }
        )
        .then_some(0)
    },
    dispatch: Dispatch::Threads(GpuStage::per_particle),
    before: None,
    after: Some(copy_solve_arguments),
};
