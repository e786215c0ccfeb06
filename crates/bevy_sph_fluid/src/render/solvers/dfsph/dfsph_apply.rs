//! The first pass of a DFSPH Jacobi iteration: the device's decision to go on, then the
//! stiffness applied to the velocities (`dfsph_apply.wgsl`; CPU twin
//! `sph_core::solver::dfsph::bender2017::apply_stiffness` and the loop of `sph_core::solver::dfsph`).

use crate::render::buffers::Buf;
use crate::render::plan::EvaluationPlan;
use crate::render::solvers::dfsph::phase::{dfsph_parity, DfsphPhase, DfsphSolve};
use crate::render::stage::{copy_solve_arguments, Dispatch, GpuStage};
use bevy::asset::{embedded_asset, load_embedded_asset};
use sph_core::gpu_layout::WORKGROUP_SIZE;
use sph_core::{CpuStage, DfsphStage};

/// v += dt a_p(κ) for every particle while the solve goes on. Roles: per solve, the warm start
/// and iterations reading error sum a or b ([`dfsph_parity`]).
pub const STAGE: GpuStage = GpuStage {
    name: "sph_dfsph_apply",
    cpu_twin: CpuStage::Dfsph(DfsphStage::Apply),
    embed: |app| embedded_asset!(app, "dfsph_apply.wgsl"),
    shader: |server| load_embedded_asset!(server, "dfsph_apply.wgsl"),
    bindings: &[
        Buf::Velocity,
        Buf::VelocityPredicted,
        Buf::AccelerationStart,
        Buf::SortedAccelerationStart,
        Buf::DfsphMirror,
        Buf::NeighborCount,
        Buf::DfsphPairs,
        Buf::Pressure,
        Buf::Clock,
    ],
    workgroup_size: WORKGROUP_SIZE,
    roles: &[
        &["DFSPH_WARM"],
        &[],
        &["FROM_B"],
        &["DIVERGENCE_SOLVE", "DFSPH_WARM"],
        &["DIVERGENCE_SOLVE"],
        &["DIVERGENCE_SOLVE", "FROM_B"],
    ],
    role: |plan: &EvaluationPlan| {
        let (solve, role) = match plan.dfsph {
            DfsphPhase::WarmApply(solve) => (solve, 0),
            // Iteration k applies source k's stiffness.
            DfsphPhase::Iterate(solve, k) => (solve, 1 + dfsph_parity(k)),
            _ => return None,
        };
        Some(
            role + if solve == DfsphSolve::Divergence {
                3
            } else {
                0
            },
        )
    },
    dispatch: Dispatch::Indirect,
    before: None,
    after: Some(copy_solve_arguments),
};
