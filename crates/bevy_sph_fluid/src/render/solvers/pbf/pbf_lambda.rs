//! PBF's constraint pass: λ_i and ρ_i at the iteration's positions (`pbf_lambda.wgsl`; CPU twin
//! `sph_core::solver::pbf::macklin2013::compute_lambdas`).

use crate::render::buffers::Buf;
use crate::render::plan::EvaluationPlan;
use crate::render::solvers::pbf::phase::{pbf_source, PbfPhase, PBF_SOURCE_ROLES};
use crate::render::stage::{Dispatch, GpuStage};
use bevy::asset::{embedded_asset, load_embedded_asset};
use sph_core::gpu_layout::WORKGROUP_SIZE;
use sph_core::{CpuStage, PbfStage};

/// λ_i = -C_i / (Σ_k |∇_k C_i|² + ε) for every particle, in each Jacobi iteration; roles by
/// where the iteration reads the positions ([`pbf_source`]).
pub const STAGE: GpuStage = GpuStage {
    name: "sph_pbf_lambda",
    cpu_twin: CpuStage::Pbf(PbfStage::Lambda),
    embed: |app| embedded_asset!(app, "pbf_lambda.wgsl"),
    shader: |server| load_embedded_asset!(server, "pbf_lambda.wgsl"),
    bindings: &[
        Buf::Position,
        Buf::SortedPosition,
        Buf::SortedVelocityPredicted,
        Buf::Normal,
        Buf::NeighborCount,
        Buf::NeighborLists,
        Buf::BoundaryPosition,
        Buf::BoundaryCellStart,
        Buf::Clock,
    ],
    workgroup_size: WORKGROUP_SIZE,
    roles: PBF_SOURCE_ROLES,
    role: |plan: &EvaluationPlan| match plan.pbf {
        PbfPhase::Iterate(k) => Some(pbf_source(k)),
        _ => None,
    },
    dispatch: Dispatch::Threads(GpuStage::per_particle),
    before: None,
    after: None,
};
