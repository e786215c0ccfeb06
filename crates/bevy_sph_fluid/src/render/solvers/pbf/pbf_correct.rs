//! PBF's correction pass: Δp_i with the artificial pressure, into the next iteration's
//! positions, and the bodies' reactions (`pbf_correct.wgsl`; CPU twins
//! `sph_core::solver::pbf::macklin2013::{compute_corrections, apply_corrections}`).

use crate::render::buffers::Buf;
use crate::render::plan::EvaluationPlan;
use crate::render::solvers::pbf::phase::{pbf_source, PbfPhase, PBF_SOURCE_ROLES};
use crate::render::stage::{Dispatch, GpuStage};
use bevy::asset::{embedded_asset, load_embedded_asset};
use sph_core::gpu_layout::WORKGROUP_SIZE;
use sph_core::{CpuStage, PbfStage};

/// x_i += Δp_i into the other scratch buffer, in each Jacobi iteration after the λ pass; roles
/// by where the iteration reads the positions ([`pbf_source`]).
pub const STAGE: GpuStage = GpuStage {
    name: "sph_pbf_correct",
    cpu_twin: CpuStage::Pbf(PbfStage::Correction),
    embed: |app| embedded_asset!(app, "pbf_correct.wgsl"),
    shader: |server| load_embedded_asset!(server, "pbf_correct.wgsl"),
    bindings: &[
        Buf::Position,
        Buf::SortedPosition,
        Buf::SortedVelocityPredicted,
        Buf::Normal,
        Buf::NeighborCount,
        Buf::NeighborLists,
        Buf::BoundaryPosition,
        Buf::BoundaryLambda,
        Buf::BoundaryCellStart,
        Buf::BoundaryBody,
        Buf::BodyForces,
        Buf::Clock,
        Buf::Colliders,
        Buf::Meshes,
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
