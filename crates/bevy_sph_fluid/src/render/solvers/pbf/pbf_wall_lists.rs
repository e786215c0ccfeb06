//! PBF's wall lists: the particles within h of each boundary sample at the predicted positions,
//! once a step after the sort (`pbf_wall_lists.wgsl`; CPU twin
//! `sph_core::solver::pbf::wall_lambda::SampleNeighbors::rebuild`).

use crate::render::buffers::Buf;
use crate::render::plan::EvaluationPlan;
use crate::render::solvers::pbf::phase::PbfPhase;
use crate::render::stage::{Dispatch, GpuStage, StageRun};
use bevy::asset::{embedded_asset, load_embedded_asset};
use sph_core::gpu_layout::WORKGROUP_SIZE;
use sph_core::{CpuStage, PbfStage};

/// The samples' side of the step's pairs, one thread per sample, in the prediction's pass
/// after the neighbour lists.
pub const STAGE: GpuStage = GpuStage {
    name: "sph_pbf_wall_lists",
    cpu_twin: CpuStage::Pbf(PbfStage::WallLists),
    embed: |app| embedded_asset!(app, "pbf_wall_lists.wgsl"),
    shader: |server| load_embedded_asset!(server, "pbf_wall_lists.wgsl"),
    bindings: &[
        Buf::Position,
        Buf::CellStart,
        Buf::BucketStart,
        Buf::BucketEnd,
        Buf::BoundaryPosition,
        Buf::BoundaryLambda,
        Buf::Clock,
    ],
    workgroup_size: WORKGROUP_SIZE,
    roles: &[&[]],
    role: |plan: &EvaluationPlan| (plan.pbf == PbfPhase::Predict).then_some(0),
    dispatch: Dispatch::Threads(|run: &StageRun| run.boundary_samples.max(1)),
    before: None,
    after: None,
};
