//! PBF's wall pass: each boundary sample's λ_b, the water's λ around it
//! (`pbf_wall_lambda.wgsl`; CPU twin
//! `sph_core::solver::pbf::wall_lambda::extrapolate_wall_lambda`).

use crate::render::buffers::Buf;
use crate::render::plan::EvaluationPlan;
use crate::render::solvers::pbf::phase::{pbf_source, PbfPhase, PBF_SOURCE_ROLES};
use crate::render::stage::{Dispatch, GpuStage, StageRun};
use bevy::asset::{embedded_asset, load_embedded_asset};
use sph_core::gpu_layout::WORKGROUP_SIZE;
use sph_core::{CpuStage, PbfStage};

/// λ_b for every boundary sample, in each Jacobi iteration between the λ and the correction
/// passes; one thread per sample, roles by where the iteration reads the positions
/// ([`pbf_source`]).
pub const STAGE: GpuStage = GpuStage {
    name: "sph_pbf_wall_lambda",
    cpu_twin: CpuStage::Pbf(PbfStage::WallLambda),
    embed: |app| embedded_asset!(app, "pbf_wall_lambda.wgsl"),
    shader: |server| load_embedded_asset!(server, "pbf_wall_lambda.wgsl"),
    bindings: &[
        Buf::Position,
        Buf::SortedPosition,
        Buf::SortedVelocityPredicted,
        Buf::Normal,
        Buf::BoundaryPosition,
        Buf::BoundaryLambda,
        Buf::Clock,
    ],
    workgroup_size: WORKGROUP_SIZE,
    roles: PBF_SOURCE_ROLES,
    role: |plan: &EvaluationPlan| match plan.pbf {
        PbfPhase::Iterate(k) => Some(pbf_source(k)),
        _ => None,
    },
    dispatch: Dispatch::Threads(|run: &StageRun| run.boundary_samples.max(1)),
    before: None,
    after: None,
};
