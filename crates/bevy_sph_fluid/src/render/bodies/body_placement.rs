//! The bodies' placement at the start of every step (`body_placement.wgsl`; CPU twin
//! `sph_core::bodies::rigid_step::RigidState`): each moved body's collider and boundary samples
//! where the device holds it.

use crate::render::buffers::Buf;
use crate::render::plan::EvaluationPlan;
use crate::render::stage::{Dispatch, GpuStage, StageRun};
use bevy::asset::{embedded_asset, load_embedded_asset};
use sph_core::gpu_layout::{GPU_MOVED_BODIES, WORKGROUP_SIZE};
use sph_core::CpuStage;

/// One thread per boundary sample (and at least one per collider slot).
pub const STAGE: GpuStage = GpuStage {
    name: "sph_body_placement",
    cpu_twin: CpuStage::Bodies,
    embed: |app| embedded_asset!(app, "body_placement.wgsl"),
    shader: |server| load_embedded_asset!(server, "body_placement.wgsl"),
    bindings: &[
        Buf::BodyWords,
        Buf::BoundaryPosition,
        Buf::BoundaryVelocity,
        Buf::BoundaryRest,
        Buf::BoundaryBody,
        Buf::Colliders,
        Buf::Meshes,
        Buf::BodyContacts,
        Buf::Clock,
    ],
    workgroup_size: WORKGROUP_SIZE,
    roles: &[&[]],
    role: |plan: &EvaluationPlan| plan.place_bodies.then_some(0),
    dispatch: Dispatch::Threads(|run: &StageRun| run.boundary_samples.max(GPU_MOVED_BODIES as u32)),
    before: None,
    after: None,
};
