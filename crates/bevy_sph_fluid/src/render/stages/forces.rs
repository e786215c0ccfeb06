//! Forces pass with the integrator's closing phase (`forces.wgsl`; CPU twins
//! `sph_core::forces` and `sph_core::integrate::{kick, leapfrog_kick}`).

use crate::render::buffers::Buf;
use crate::render::plan::{EvaluationPlan, ForcesRole};
use crate::render::solvers::dfsph::phase::DfsphPhase;
use crate::render::stage::{Dispatch, GpuStage};
use bevy::asset::{embedded_asset, load_embedded_asset};
use sph_core::gpu_layout::WORKGROUP_SIZE;
use sph_core::CpuStage;

/// Pressure, viscosity, surface tension, the boundary samples' pressure and friction, and gravity
/// for every particle, and the reaction on each boundary body summed over the frame. Roles: plain
/// (symplectic Euler, DFSPH's non-pressure accelerations), kick-drift-kick closing kick,
/// leapfrog first evaluation (keep a0), leapfrog second (kick), kick-drift-kick's first
/// evaluation with stale forces.
pub const STAGE: GpuStage = GpuStage {
    name: "sph_forces",
    cpu_twin: CpuStage::Forces,
    embed: |app| embedded_asset!(app, "forces.wgsl"),
    shader: |server| load_embedded_asset!(server, "forces.wgsl"),
    bindings: &[
        Buf::Position,
        Buf::Velocity,
        Buf::VelocityPredicted,
        Buf::Acceleration,
        Buf::AccelerationStart,
        Buf::Density,
        Buf::Pressure,
        Buf::Normal,
        Buf::NeighborCount,
        Buf::NeighborLists,
        Buf::CellStart,
        Buf::BucketStart,
        Buf::BucketEnd,
        Buf::Clock,
        Buf::BoundaryPosition,
        Buf::BoundaryVelocity,
        Buf::BoundaryCellStart,
        Buf::BoundaryBody,
        Buf::BodyForces,
        Buf::Colliders,
        Buf::Meshes,
        Buf::Pumps,
        Buf::Probes,
    ],
    workgroup_size: WORKGROUP_SIZE,
    roles: &[
        &[],
        &["USE_PREDICTED_VELOCITY", "POST_KDK"],
        &["POST_LEAPFROG_SAVE", "HALF_KICK_DRIFT"],
        &["USE_PREDICTED_VELOCITY", "POST_LEAPFROG_KICK"],
        // Kick-drift-kick's first evaluation with stale forces: its drift starts from v + a dt/2.
        &["HALF_KICK_DRIFT"],
    ],
    role: |plan: &EvaluationPlan| {
        // DFSPH: the non-pressure accelerations, once per step.
        if plan.dfsph != DfsphPhase::None {
            return matches!(plan.dfsph, DfsphPhase::Predict { .. }).then_some(0);
        }
        Some(match plan.forces {
            ForcesRole::Plain if plan.euler => 0,
            ForcesRole::Plain => 4,
            ForcesRole::KickClose => 1,
            ForcesRole::LeapfrogFirst => 2,
            ForcesRole::LeapfrogSecond => 3,
        })
    },
    dispatch: Dispatch::Threads(GpuStage::per_particle),
    before: None,
    after: None,
};
