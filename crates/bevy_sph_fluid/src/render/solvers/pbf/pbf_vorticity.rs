//! PBF's vorticity pass, with vorticity confinement only (`pbf_vorticity.wgsl`; CPU twin
//! `sph_core::solver::pbf::xsph_vorticity::vorticity`).

use crate::render::buffers::Buf;
use crate::render::plan::EvaluationPlan;
use crate::render::solvers::pbf::phase::{pbf_source, PbfPhase, PBF_SOURCE_ROLES};
use crate::render::stage::{Dispatch, GpuStage};
use bevy::asset::{embedded_asset, load_embedded_asset};
use sph_core::gpu_layout::WORKGROUP_SIZE;
use sph_core::{CpuStage, PbfStage};

/// ω_i at the final positions; roles by the buffer holding them.
pub const STAGE: GpuStage = GpuStage {
    name: "sph_pbf_vorticity",
    cpu_twin: CpuStage::Pbf(PbfStage::Vorticity),
    embed: |app| embedded_asset!(app, "pbf_vorticity.wgsl"),
    shader: |server| load_embedded_asset!(server, "pbf_vorticity.wgsl"),
    bindings: &[
        Buf::Position,
        Buf::Velocity,
        Buf::Density,
        Buf::SortedPosition,
        Buf::SortedVelocityPredicted,
        Buf::SortedAcceleration,
        Buf::NeighborCount,
        Buf::NeighborLists,
        Buf::Clock,
    ],
    workgroup_size: WORKGROUP_SIZE,
    roles: PBF_SOURCE_ROLES,
    role: |plan: &EvaluationPlan| match plan.pbf {
        PbfPhase::Finish {
            iterations,
            vorticity: true,
        } => Some(pbf_source(iterations)),
        _ => None,
    },
    dispatch: Dispatch::Threads(GpuStage::per_particle),
    before: None,
    after: None,
};
