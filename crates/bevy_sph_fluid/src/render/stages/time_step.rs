//! The time step, right before each step's first integration phase (`time_step.wgsl`; CPU twin
//! `sph_core::stability`, `sph_core::rollback` and `CpuSolver::step`): checks the previous step's
//! recorded extremes for instability (rolling back to the checkpoint, or freezing the clock),
//! chooses dt (fixed, or the adaptive CFL rule, times the rollback scale) and advances the
//! simulated time, all on the GPU, so the CPU never waits for the maximum speed.

use crate::render::buffers::Buf;
use crate::render::plan::{EvaluationPlan, TimeStepPoint};
use crate::render::stage::{Dispatch, GpuStage};
use bevy::asset::{embedded_asset, load_embedded_asset};
use sph_core::CpuStage;

const BASE: GpuStage = GpuStage {
    name: "sph_time_step",
    cpu_twin: CpuStage::TimeStep,
    embed: |app| embedded_asset!(app, "time_step.wgsl"),
    shader: |server| load_embedded_asset!(server, "time_step.wgsl"),
    bindings: &[Buf::Clock],
    workgroup_size: 1,
    roles: &[&[]],
    role: GpuStage::every_evaluation,
    dispatch: Dispatch::Threads(|_| 1),
    before: None,
    after: None,
};

/// One thread before a drifting count pass (kick-drift-kick, the leapfrog's second evaluation).
pub const AT_START: GpuStage = GpuStage {
    role: |plan: &EvaluationPlan| (plan.time_step == TimeStepPoint::Start).then_some(0),
    ..BASE
};

/// One thread between the forces and the integrate pass (symplectic Euler): a rollback found
/// here is restored by the integrate pass, and the next step retries.
pub const BEFORE_INTEGRATE: GpuStage = GpuStage {
    roles: &[&["TIME_STEP_BEFORE_INTEGRATE"]],
    role: |plan: &EvaluationPlan| (plan.time_step == TimeStepPoint::BeforeIntegrate).then_some(0),
    ..BASE
};
