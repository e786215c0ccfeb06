//! PBF's XSPH pass: XSPH viscosity with the no-slip walls' share and its reactions on the
//! bodies, and the final densities; without vorticity confinement also the pumps, the speed
//! record and the probes, and then the final positions replace the sorted ones
//! (`pbf_xsph.wgsl`; CPU twins `sph_core::solver::pbf::xsph_vorticity::{xsph_and_densities,
//! wall_friction}`, `sph_core::flow::pump::apply_pumps`).

use crate::render::buffers::Buf;
use crate::render::plan::EvaluationPlan;
use crate::render::solvers::pbf::phase::{pbf_source, PbfPhase, PBF_SOURCE_ROLES};
use crate::render::stage::{Dispatch, GpuStage, StageRun};
use bevy::asset::{embedded_asset, load_embedded_asset};
use bevy::render::render_resource::CommandEncoder;
use sph_core::gpu_layout::WORKGROUP_SIZE;
use sph_core::{CpuStage, PbfStage};

/// The finish's second pass; roles by the buffer holding the final positions.
pub const STAGE: GpuStage = GpuStage {
    name: "sph_pbf_xsph",
    cpu_twin: CpuStage::Pbf(PbfStage::Xsph),
    embed: |app| embedded_asset!(app, "pbf_xsph.wgsl"),
    shader: |server| load_embedded_asset!(server, "pbf_xsph.wgsl"),
    bindings: &[
        Buf::Position,
        Buf::Velocity,
        Buf::SortedPosition,
        Buf::SortedVelocityPredicted,
        Buf::SortedVelocity,
        Buf::Acceleration,
        Buf::Density,
        Buf::Pressure,
        Buf::Normal,
        Buf::NeighborCount,
        Buf::NeighborLists,
        Buf::BoundaryPosition,
        Buf::BoundaryVelocity,
        Buf::BoundaryCellStart,
        Buf::BoundaryBody,
        Buf::BodyForces,
        Buf::Clock,
        Buf::Pumps,
        Buf::Probes,
    ],
    workgroup_size: WORKGROUP_SIZE,
    roles: PBF_SOURCE_ROLES,
    role: |plan: &EvaluationPlan| match plan.pbf {
        PbfPhase::Finish { iterations, .. } => Some(pbf_source(iterations)),
        _ => None,
    },
    dispatch: Dispatch::Threads(GpuStage::per_particle),
    before: None,
    after: Some(|encoder: &mut CommandEncoder, run: &StageRun| {
        if let PbfPhase::Finish {
            vorticity: false, ..
        } = run.plan.pbf
        {
            copy_final_positions(encoder, run);
        }
    }),
};

/// After the finish's last pass: the final positions (with their ids) replace the sorted ones.
/// A copy, not a dispatch; none when the final positions are the sorted ones already.
pub fn copy_final_positions(encoder: &mut CommandEncoder, run: &StageRun) {
    let PbfPhase::Finish { iterations, .. } = run.plan.pbf else {
        return;
    };
    let bytes = 16 * run.particle_count as u64;
    let from = match pbf_source(iterations) {
        1 => Buf::SortedPosition,
        2 => Buf::SortedVelocityPredicted,
        _ => return,
    };
    if bytes > 0 {
        run.buffers.copy(encoder, from, Buf::Position, bytes);
    }
}
