//! Symplectic-Euler integration pass (`integrate.wgsl`; CPU twin `sph_core::integrate::euler`),
//! which also applies the rollback checkpoint. The leapfrogs fuse their phases into the count
//! and forces passes instead.

use crate::render::buffers::Buf;
use crate::render::plan::EvaluationPlan;
use crate::render::stage::{Dispatch, GpuStage};
use bevy::asset::{embedded_asset, load_embedded_asset};
use sph_core::gpu_layout::WORKGROUP_SIZE;
use sph_core::CpuStage;

/// v += a dt; x += v dt; collide — only in a symplectic-Euler evaluation.
pub const STAGE: GpuStage = GpuStage {
    name: "sph_integrate",
    cpu_twin: CpuStage::Integrate,
    embed: |app| embedded_asset!(app, "integrate.wgsl"),
    shader: |server| load_embedded_asset!(server, "integrate.wgsl"),
    bindings: &[
        Buf::Position,
        Buf::Velocity,
        Buf::Acceleration,
        Buf::AccelerationStart,
        Buf::Clock,
        Buf::Checkpoint,
        Buf::Colliders,
        Buf::Meshes,
        Buf::Pumps,
        Buf::Probes,
    ],
    workgroup_size: WORKGROUP_SIZE,
    roles: &[&[]],
    role: |plan: &EvaluationPlan| plan.euler.then_some(0),
    dispatch: Dispatch::Threads(GpuStage::per_particle),
    before: None,
    after: None,
};
