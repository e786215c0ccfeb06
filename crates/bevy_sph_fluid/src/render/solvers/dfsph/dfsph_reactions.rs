//! The end of each DFSPH solve: the bodies' reactions and the solve's statistics; after the
//! divergence-free solve the pressures, the pumps and the probes (`dfsph_reactions.wgsl`; CPU
//! twins `sph_core::solver::dfsph::bender2017::boundary_reactions`, the end of `sph_core::solver::dfsph`,
//! `sph_core::flow::pump::apply_pumps`).

use crate::render::buffers::Buf;
use crate::render::plan::EvaluationPlan;
use crate::render::solvers::dfsph::phase::DfsphPhase;
use crate::render::stage::{Dispatch, GpuStage};
use bevy::asset::{embedded_asset, load_embedded_asset};
use sph_core::gpu_layout::WORKGROUP_SIZE;
use sph_core::{CpuStage, DfsphStage};

/// m κ_i g_ib on every boundary pair's body, once per solve; after the constant-density solve the
/// solids' speculative contact on the velocity the move takes. Roles: the constant-density solve
/// (before the move), the divergence-free solve (the step's last pass).
pub const STAGE: GpuStage = GpuStage {
    name: "sph_dfsph_reactions",
    cpu_twin: CpuStage::Dfsph(DfsphStage::Reactions),
    embed: |app| embedded_asset!(app, "dfsph_reactions.wgsl"),
    shader: |server| load_embedded_asset!(server, "dfsph_reactions.wgsl"),
    bindings: &[
        Buf::Position,
        Buf::Velocity,
        Buf::VelocityPredicted,
        Buf::Density,
        Buf::Pressure,
        Buf::SortedAccelerationStart,
        Buf::DfsphMirror,
        Buf::Clock,
        Buf::BoundaryPosition,
        Buf::BoundaryCellStart,
        Buf::BoundaryBody,
        Buf::BodyForces,
        Buf::Colliders,
        Buf::Meshes,
        Buf::Pumps,
        Buf::Probes,
    ],
    workgroup_size: WORKGROUP_SIZE,
    roles: &[&[], &["DIVERGENCE_SOLVE"]],
    role: |plan: &EvaluationPlan| match plan.dfsph {
        DfsphPhase::DensityEnd => Some(0),
        DfsphPhase::Finish => Some(1),
        _ => None,
    },
    dispatch: Dispatch::Threads(GpuStage::per_particle),
    before: None,
    after: None,
};
