//! A DFSPH solve's source, next stiffness and error sum (`dfsph_source.wgsl`; CPU twins
//! `sph_core::solver::dfsph::bender2017::{density_source, divergence_source, stiffness_from_source}`).

use crate::render::buffers::Buf;
use crate::render::plan::EvaluationPlan;
use crate::render::solvers::dfsph::phase::{dfsph_parity, DfsphPhase, DfsphSolve};
use crate::render::stage::{Dispatch, GpuStage};
use bevy::asset::{embedded_asset, load_embedded_asset};
use sph_core::gpu_layout::WORKGROUP_SIZE;
use sph_core::{CpuStage, DfsphStage};

/// The second pass of every Jacobi iteration, and each solve's first source (or its warm
/// start's). Roles: per solve, the warm start, the first source, and the sources into error
/// sum a or b ([`dfsph_parity`]).
pub const STAGE: GpuStage = GpuStage {
    name: "sph_dfsph_source",
    cpu_twin: CpuStage::Dfsph(DfsphStage::Source),
    embed: |app| embedded_asset!(app, "dfsph_source.wgsl"),
    shader: |server| load_embedded_asset!(server, "dfsph_source.wgsl"),
    bindings: &[
        Buf::Velocity,
        Buf::VelocityPredicted,
        Buf::Density,
        Buf::AccelerationStart,
        Buf::SortedAccelerationStart,
        Buf::NeighborCount,
        Buf::DfsphPairs,
        Buf::Pressure,
        Buf::Clock,
    ],
    workgroup_size: WORKGROUP_SIZE,
    roles: &[
        &["DFSPH_WARM"],
        &["DFSPH_FIRST"],
        &[],
        &["TO_B"],
        &["DIVERGENCE_SOLVE", "DFSPH_WARM"],
        &["DIVERGENCE_SOLVE", "DFSPH_FIRST"],
        &["DIVERGENCE_SOLVE"],
        &["DIVERGENCE_SOLVE", "TO_B"],
    ],
    role: |plan: &EvaluationPlan| {
        let (solve, role) = match plan.dfsph {
            DfsphPhase::Predict { warm } => (DfsphSolve::Density, if warm { 0 } else { 1 }),
            DfsphPhase::Move { warm } => (DfsphSolve::Divergence, if warm { 0 } else { 1 }),
            DfsphPhase::WarmApply(solve) => (solve, 1),
            // Source k + 1 of the solve.
            DfsphPhase::Iterate(solve, k) => (solve, 2 + dfsph_parity(k + 1)),
            _ => return None,
        };
        Some(
            role + if solve == DfsphSolve::Divergence {
                4
            } else {
                0
            },
        )
    },
    dispatch: Dispatch::Indirect,
    before: None,
    after: None,
};
