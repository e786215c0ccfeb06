//! PBF's velocity pass: v = (x - x_prev) / dt from the final positions, and the guard
//! (`pbf_velocity.wgsl`; CPU twin: step 4 of `sph_core::solver::pbf`).

use crate::render::buffers::Buf;
use crate::render::plan::EvaluationPlan;
use crate::render::solvers::pbf::phase::{pbf_source, PbfPhase, PBF_SOURCE_ROLES};
use crate::render::stage::{Dispatch, GpuStage};
use bevy::asset::{embedded_asset, load_embedded_asset};
use sph_core::gpu_layout::WORKGROUP_SIZE;
use sph_core::{CpuStage, PbfStage};

/// The finish's first pass; roles by the buffer holding the final positions (the source of
/// iteration `iterations`, [`pbf_source`]).
pub const STAGE: GpuStage = GpuStage {
    name: "sph_pbf_velocity",
    cpu_twin: CpuStage::Pbf(PbfStage::Velocity),
    embed: |app| embedded_asset!(app, "pbf_velocity.wgsl"),
    shader: |server| load_embedded_asset!(server, "pbf_velocity.wgsl"),
    bindings: &[
        Buf::Position,
        Buf::SortedPosition,
        Buf::SortedVelocityPredicted,
        Buf::SortedVelocity,
        Buf::AccelerationStart,
        Buf::BodyForces,
        Buf::Clock,
        Buf::Colliders,
        Buf::Meshes,
    ],
    workgroup_size: WORKGROUP_SIZE,
    roles: PBF_SOURCE_ROLES,
    role: |plan: &EvaluationPlan| match plan.pbf {
        PbfPhase::Finish { iterations, .. } => Some(pbf_source(iterations)),
        _ => None,
    },
    dispatch: Dispatch::Threads(GpuStage::per_particle),
    before: None,
    after: None,
};
