//! PBF's vorticity confinement pass, the step's last with vorticity confinement: the push
//! N × ω, pumps, probes, then the final positions replace the sorted ones (`pbf_confine.wgsl`;
//! CPU twins `sph_core::solver::pbf::xsph_vorticity::confine_vorticity`, `sph_core::flow::pump::apply_pumps`).

use super::pbf_xsph::copy_final_positions;
use crate::render::buffers::Buf;
use crate::render::plan::EvaluationPlan;
use crate::render::solvers::pbf::phase::{pbf_source, PbfPhase, PBF_SOURCE_ROLES};
use crate::render::stage::{Dispatch, GpuStage};
use bevy::asset::{embedded_asset, load_embedded_asset};
use sph_core::gpu_layout::WORKGROUP_SIZE;
use sph_core::{CpuStage, PbfStage};

/// v_i += dt ε (N_i × ω_i); roles by the buffer holding the final positions.
pub const STAGE: GpuStage = GpuStage {
    name: "sph_pbf_confine",
    cpu_twin: CpuStage::Pbf(PbfStage::Confinement),
    embed: |app| embedded_asset!(app, "pbf_confine.wgsl"),
    shader: |server| load_embedded_asset!(server, "pbf_confine.wgsl"),
    bindings: &[
        Buf::Position,
        Buf::Velocity,
        Buf::Acceleration,
        Buf::Density,
        Buf::SortedPosition,
        Buf::SortedVelocityPredicted,
        Buf::SortedAcceleration,
        Buf::NeighborCount,
        Buf::NeighborLists,
        Buf::Clock,
        Buf::Pumps,
        Buf::Probes,
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
    after: Some(copy_final_positions),
};
