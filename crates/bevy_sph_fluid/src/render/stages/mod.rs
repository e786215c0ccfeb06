//! One file per stage: each owns its WGSL entry point (same name, `.wgsl`), queues its pipeline
//! variants, and has the system that encodes its dispatch.

pub mod bitonic_sort;
pub mod count_cells;
pub mod density;
pub mod forces;
pub mod hash_offsets;
pub mod integrate;
pub mod normals;
pub mod prefix_sum;
pub mod scatter;
pub mod time_step;

use super::pipelines::{SphPipelines, StagePipelines, VariantKey};
use super::SphRun;
use bevy::ecs::schedule::ScheduleConfigs;
use bevy::ecs::system::ScheduleSystem;
use bevy::prelude::*;
use bevy::render::diagnostic::RecordDiagnostics;
use bevy::render::render_resource::{
    CachedComputePipelineId, ComputePass, ComputePassDescriptor, PipelineCache,
};
use bevy::render::renderer::RenderContext;
use sph_core::gpu_layout::WORKGROUP_SIZE;
use sph_core::NeighborSearch;

/// The shader of every stage.
#[derive(Clone, Debug)]
pub struct StageShaders {
    count_cells: Handle<Shader>,
    prefix_sum: Handle<Shader>,
    bitonic_sort: Handle<Shader>,
    hash_offsets: Handle<Shader>,
    scatter: Handle<Shader>,
    density: Handle<Shader>,
    normals: Handle<Shader>,
    forces: Handle<Shader>,
    integrate: Handle<Shader>,
    time_step: Handle<Shader>,
}

impl StageShaders {
    pub(crate) fn load(asset_server: &AssetServer) -> Self {
        Self {
            count_cells: count_cells::load(asset_server),
            prefix_sum: prefix_sum::load(asset_server),
            bitonic_sort: bitonic_sort::load(asset_server),
            hash_offsets: hash_offsets::load(asset_server),
            scatter: scatter::load(asset_server),
            density: density::load(asset_server),
            normals: normals::load(asset_server),
            forces: forces::load(asset_server),
            integrate: integrate::load(asset_server),
            time_step: time_step::load(asset_server),
        }
    }
}

pub(crate) fn embed_shaders(app: &mut App) {
    count_cells::embed(app);
    prefix_sum::embed(app);
    bitonic_sort::embed(app);
    hash_offsets::embed(app);
    scatter::embed(app);
    density::embed(app);
    normals::embed(app);
    forces::embed(app);
    integrate::embed(app);
    time_step::embed(app);
}

/// Queues every pipeline the variant needs, and nothing it does not.
pub(crate) fn queue_variant(
    pipelines: &SphPipelines,
    cache: &PipelineCache,
    key: &VariantKey,
) -> StagePipelines {
    let s = &pipelines.shaders;
    let q = |label, shader: &Handle<Shader>, extra: &[&'static str]| {
        pipelines.queue(cache, label, shader, key, extra)
    };
    let grid = key.search == NeighborSearch::Grid;
    StagePipelines {
        count_cells: [
            q("sph_count_cells", &s.count_cells, &[]),
            q("sph_count_cells", &s.count_cells, &["PRE_KDK"]),
            q("sph_count_cells", &s.count_cells, &["PRE_LEAPFROG"]),
        ],
        prefix_sum: grid.then(|| q("sph_prefix_sum", &s.prefix_sum, &[])),
        bitonic_sort: (!grid).then(|| q("sph_bitonic_sort", &s.bitonic_sort, &[])),
        hash_offsets: (!grid).then(|| q("sph_hash_offsets", &s.hash_offsets, &[])),
        scatter: q("sph_scatter", &s.scatter, &[]),
        density: q("sph_density", &s.density, &[]),
        normals: key
            .surface_tension
            .then(|| q("sph_normals", &s.normals, &[])),
        forces: [
            q("sph_forces", &s.forces, &[]),
            q(
                "sph_forces",
                &s.forces,
                &["USE_PREDICTED_VELOCITY", "POST_KDK"],
            ),
            q("sph_forces", &s.forces, &["POST_LEAPFROG_SAVE"]),
            q(
                "sph_forces",
                &s.forces,
                &["USE_PREDICTED_VELOCITY", "POST_LEAPFROG_KICK"],
            ),
        ],
        integrate: q("sph_integrate", &s.integrate, &[]),
        time_step: q("sph_time_step", &s.time_step, &[]),
    }
}

/// The stage systems, chained in pipeline order.
pub(crate) fn stage_systems() -> ScheduleConfigs<ScheduleSystem> {
    (
        time_step::sph_time_step,
        count_cells::sph_count_cells,
        prefix_sum::sph_prefix_sum,
        bitonic_sort::sph_bitonic_sort,
        hash_offsets::sph_hash_offsets,
        scatter::sph_scatter,
        density::sph_density,
        normals::sph_normals,
        forces::sph_forces,
        time_step::sph_time_step_before_integrate,
        integrate::sph_integrate,
    )
        .chain()
}

/// Workgroups covering `threads` invocations.
pub fn workgroups(threads: u32) -> u32 {
    threads.div_ceil(WORKGROUP_SIZE)
}

/// Encodes one compute pass named `name` that binds group 0, sets `pipeline` and lets `record`
/// issue its dispatches (returning how many); GPU-timed when the run asks for it.
pub(crate) fn encode_pass(
    ctx: &mut RenderContext,
    run: &mut SphRun,
    cache: &PipelineCache,
    name: &'static str,
    pipeline: CachedComputePipelineId,
    record: impl FnOnce(&mut ComputePass, &SphRun) -> u32,
) {
    let Some(pipeline) = cache.get_compute_pipeline(pipeline) else {
        return;
    };
    let diagnostics = ctx.diagnostic_recorder();
    let diagnostics = diagnostics.as_deref().filter(|_| run.timed);
    let mut pass = ctx
        .command_encoder()
        .begin_compute_pass(&ComputePassDescriptor {
            label: Some(name),
            timestamp_writes: None,
        });
    let span = diagnostics.pass_span(&mut pass, name);
    pass.set_pipeline(pipeline);
    pass.set_bind_group(0, &run.bind_group, &[]);
    let dispatches = record(&mut pass, run);
    span.end(&mut pass);
    run.dispatches += dispatches;
}
