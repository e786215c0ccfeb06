//! DFSPH's predicted velocities v* = v + dt (a_np + a_rise) after the time step, with the
//! rollback checkpoint (`dfsph_predict.wgsl`; CPU twins: step 3 of `sph_core::solver::dfsph`,
//! `sph_core::solver::dfsph::bender2017::BoundaryRise::predict`).

use crate::render::buffers::Buf;
use crate::render::plan::EvaluationPlan;
use crate::render::solvers::dfsph::phase::DfsphPhase;
use crate::render::stage::{copy_solve_arguments, Dispatch, GpuStage};
use bevy::asset::{embedded_asset, load_embedded_asset};
use sph_core::gpu_layout::WORKGROUP_SIZE;
use sph_core::{CpuStage, DfsphStage};

/// The checkpoint, then v += dt (a + a_rise) for every particle, once per DFSPH step; opens the
/// constant-density solve.
pub const STAGE: GpuStage = GpuStage {
    name: "sph_dfsph_predict",
    cpu_twin: CpuStage::Dfsph(DfsphStage::Predict),
    embed: |app| embedded_asset!(app, "dfsph_predict.wgsl"),
    shader: |server| load_embedded_asset!(server, "dfsph_predict.wgsl"),
    bindings: &[
        Buf::Position,
        Buf::Velocity,
        Buf::Acceleration,
        Buf::AccelerationStart,
        Buf::SortedAccelerationStart,
        Buf::BoundaryPosition,
        Buf::BoundaryCellStart,
        Buf::Clock,
        Buf::Checkpoint,
    ],
    workgroup_size: WORKGROUP_SIZE,
    roles: &[&[]],
    role: |plan: &EvaluationPlan| matches!(plan.dfsph, DfsphPhase::Predict { .. }).then_some(0),
    dispatch: Dispatch::Threads(GpuStage::per_particle),
    before: None,
    after: Some(copy_solve_arguments),
};
