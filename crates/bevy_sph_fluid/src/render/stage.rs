//! The stage registry's vocabulary: a [`GpuStage`] is what one `stages/<name>.rs` +
//! `stages/<name>.wgsl` pair declares (bindings, shader defs, workgroup size, dispatch size, CPU
//! twin), and [`encode_stage`] turns it into a compute pass. The list of stages a scene runs is
//! in `stages/mod.rs`.

use super::arenas::Arena;
use super::buffers::{Buf, GpuBuffers};
use super::plan::EvaluationPlan;
use bevy::prelude::*;
use bevy::render::diagnostic::RecordDiagnostics;
use bevy::render::render_resource::{
    BindGroup, CachedComputePipelineId, CommandEncoder, ComputePassDescriptor, PipelineCache,
};
use bevy::render::renderer::RenderContext;
use sph_core::CpuStage;

/// How many invocations a stage's pass runs.
#[derive(Clone, Copy, Debug)]
pub enum Dispatch {
    /// One dispatch of this many invocations (rounded up to whole workgroups).
    Threads(fn(&StageRun) -> u32),
    /// One dispatch over the sort slots per bitonic step, group 1 at the step's dynamic offset.
    BitonicSteps,
    /// One indirect dispatch whose workgroup count the device wrote (DFSPH's solve passes:
    /// none once the solve converged), from `GpuBuffers::dfsph_arguments`.
    Indirect,
}

/// Copies the DFSPH solve's dispatch arguments from the clock to the indirect buffer (after each
/// pass that may change them: a pass cannot read its own dispatch arguments from a buffer it
/// binds for writing).
pub fn copy_solve_arguments(encoder: &mut CommandEncoder, run: &StageRun) {
    let (shared, clock) = run.buffers.at(Buf::Clock);
    encoder.copy_buffer_to_buffer(
        shared,
        clock + sph_core::gpu_layout::GpuClock::DFSPH_ARGS_OFFSET,
        &run.buffers.dfsph_arguments,
        0,
        Some(12),
    );
}

/// A GPU stage, declared by its `stages/<name>.rs` as a `const` and listed in `stages/mod.rs`.
#[derive(Clone, Copy, Debug)]
pub struct GpuStage {
    /// Pass label, pipeline label and GPU timing name (`render/<name>/elapsed_gpu`).
    pub name: &'static str,
    /// The `sph_core` stage this pass mirrors (parity tests compare against it).
    pub cpu_twin: CpuStage,
    /// Embeds the stage's WGSL in the binary (`embedded_asset!` in the stage's file).
    pub embed: fn(&mut App),
    /// Loads the embedded WGSL.
    pub shader: fn(&AssetServer) -> Handle<Shader>,
    /// The logical storage buffers the shader uses (the uniform block is always bound); the
    /// stage's bind-group layout holds their arenas ([`GpuStage::arenas`]), so wgpu refuses a
    /// shader that uses another arena.
    pub bindings: &'static [Buf],
    /// Invocations per workgroup, passed to the WGSL as the shader def `WORKGROUP_SIZE`.
    pub workgroup_size: u32,
    /// Shader defs of each pipeline role (one pipeline per role and scene variant).
    pub roles: &'static [&'static [&'static str]],
    /// The role an evaluation runs the stage in, or `None` to skip it in that evaluation.
    pub role: fn(&EvaluationPlan) -> Option<usize>,
    /// The dispatch size.
    pub dispatch: Dispatch,
    /// Commands encoded before the pass (buffer clears).
    pub before: Option<fn(&mut CommandEncoder, &StageRun)>,
    /// Commands encoded after the pass (buffer copies).
    pub after: Option<fn(&mut CommandEncoder, &StageRun)>,
}

impl GpuStage {
    /// The arenas this stage binds: those of its buffers, each once, in binding order.
    pub fn arenas(&self) -> Vec<Arena> {
        let mut arenas: Vec<Arena> = self.bindings.iter().map(|buf| buf.arena()).collect();
        arenas.sort();
        arenas.dedup();
        arenas
    }

    /// A stage that runs its only role in every evaluation: every WCSPH force evaluation, and
    /// PBF's prediction (its pass that sorts; the iterations and the finish skip it).
    pub fn every_evaluation(plan: &EvaluationPlan) -> Option<usize> {
        plan.sorts().then_some(0)
    }

    /// A stage that runs once a frame, after the first sort of the frame's last step, where the
    /// grid and the state agree (whitewater's stages).
    pub fn after_the_steps_first_sort(plan: &EvaluationPlan) -> Option<usize> {
        (plan.step_first_sort && plan.sorts()).then_some(0)
    }

    /// One invocation per live particle.
    pub fn per_particle(run: &StageRun) -> u32 {
        run.particle_count
    }
}

/// A stage of the scene's list with its queued pipelines (one per role).
#[derive(Clone, Debug)]
pub struct QueuedStage {
    /// The stage.
    pub stage: &'static GpuStage,
    /// Its pipeline for each role.
    pub pipelines: Vec<CachedComputePipelineId>,
}

/// Everything the stage encoder needs for the evaluation being encoded.
#[derive(Resource, Clone)]
pub struct StageRun {
    /// The scene's stage list with its pipelines.
    pub stages: Vec<QueuedStage>,
    /// Each stage's group 0, by stage name.
    pub bind_groups: bevy::platform::collections::HashMap<&'static str, BindGroup>,
    /// Group 1 of the bitonic sort and each step's dynamic offset (hash mode).
    pub bitonic: Option<(BindGroup, Vec<u32>)>,
    /// The buffers, for clears and copies.
    pub buffers: GpuBuffers,
    /// Live particles.
    pub particle_count: u32,
    /// Boundary samples uploaded.
    pub boundary_samples: u32,
    /// The evaluation being encoded.
    pub plan: EvaluationPlan,
    /// Record GPU timestamps for this evaluation.
    pub timed: bool,
    /// Dispatches encoded so far this frame.
    pub dispatches: u32,
}

/// Encodes one stage for the current evaluation: its `before` commands, a compute pass named
/// after it (GPU-timed when the run asks) with its dispatches, its `after` commands. A stage the
/// evaluation skips, or whose pipeline or bind group is missing, encodes nothing.
pub fn encode_stage(
    ctx: &mut RenderContext,
    run: &mut StageRun,
    cache: &PipelineCache,
    queued: &QueuedStage,
) {
    let stage = queued.stage;
    let Some(role) = (stage.role)(&run.plan) else {
        return;
    };
    let (Some(pipeline), Some(bind_group)) = (
        queued
            .pipelines
            .get(role)
            .and_then(|&id| cache.get_compute_pipeline(id)),
        run.bind_groups.get(stage.name),
    ) else {
        return;
    };
    if let Some(before) = stage.before {
        before(ctx.command_encoder(), run);
    }
    let diagnostics = ctx.diagnostic_recorder();
    let diagnostics = diagnostics.as_deref().filter(|_| run.timed);
    let mut pass = ctx
        .command_encoder()
        .begin_compute_pass(&ComputePassDescriptor {
            label: Some(stage.name),
            timestamp_writes: None,
        });
    let span = diagnostics.pass_span(&mut pass, stage.name);
    pass.set_pipeline(pipeline);
    pass.set_bind_group(0, bind_group, &[]);
    let workgroups = |threads: u32| threads.div_ceil(stage.workgroup_size);
    let dispatches = match stage.dispatch {
        Dispatch::Threads(threads) => {
            pass.dispatch_workgroups(workgroups(threads(run)), 1, 1);
            1
        }
        Dispatch::BitonicSteps => match &run.bitonic {
            Some((group, offsets)) => {
                for &offset in offsets {
                    pass.set_bind_group(1, group, &[offset]);
                    pass.dispatch_workgroups(workgroups(run.buffers.sort_length), 1, 1);
                }
                offsets.len() as u32
            }
            None => 0,
        },
        Dispatch::Indirect => {
            pass.dispatch_workgroups_indirect(&run.buffers.dfsph_arguments, 0);
            1
        }
    };
    span.end(&mut pass);
    drop(pass);
    run.dispatches += dispatches;
    if let Some(after) = stage.after {
        after(ctx.command_encoder(), run);
    }
}
