//! Pipelines and bind groups from the stage registry: each stage gets a bind-group layout of the
//! arenas of the buffers it declares, and one compute pipeline per role and scene variant.
//! Variants come from shader defs: the search mode (`SEARCH_HASH`), `SURFACE_TENSION`,
//! `VISCOSITY`, `NEIGHBOR_COUNT`, the stage's role defs and its `WORKGROUP_SIZE`; a scene only
//! compiles and runs the stages of its list.

use super::buffers::{SphGpuState, BITONIC_STRIDE};
use super::extract::ExtractedSphFrame;
use super::plan::VariantKey;
use super::stage::{Dispatch, GpuStage, QueuedStage};
use super::stages;
use crate::api::STATUS_COMPILING_SHADERS;
use bevy::platform::collections::HashMap;
use bevy::prelude::*;
use bevy::render::render_resource::binding_types::{storage_buffer_sized, uniform_buffer_sized};
use bevy::render::render_resource::{
    BindGroupEntry, BindGroupLayoutDescriptor, BindGroupLayoutEntry, BindingResource,
    BufferBinding, CachedComputePipelineId, CachedPipelineState, ComputePipelineDescriptor,
    PipelineCache, ShaderStages,
};
use bevy::render::renderer::RenderDevice;
use bevy::shader::ShaderDefVal;
use std::num::NonZeroU64;

/// Layouts, shaders and the variants queued so far.
#[derive(Resource)]
pub struct SphPipelines {
    /// Each stage's group 0 (by stage name): the uniform block and its declared buffers.
    pub layouts: HashMap<&'static str, BindGroupLayoutDescriptor>,
    /// Group 1 of the bitonic sort: one step, at a dynamic offset.
    pub bitonic_layout: BindGroupLayoutDescriptor,
    /// Each stage's shader, by stage name.
    pub shaders: HashMap<&'static str, Handle<Shader>>,
    /// The stage list of each variant queued so far, with its pipelines.
    pub variants: HashMap<VariantKey, Vec<QueuedStage>>,
}

/// The group-0 layout of `stage`: the uniform at binding 0 and the arenas of its buffers.
pub fn stage_layout(stage: &GpuStage) -> BindGroupLayoutDescriptor {
    let mut entries: Vec<BindGroupLayoutEntry> =
        vec![uniform_buffer_sized(false, None).build(0, ShaderStages::COMPUTE)];
    for arena in stage.arenas() {
        entries
            .push(storage_buffer_sized(false, None).build(arena.binding(), ShaderStages::COMPUTE));
    }
    BindGroupLayoutDescriptor::new(stage.name, &entries)
}

pub(crate) fn init_sph_pipelines(mut commands: Commands, asset_server: Res<AssetServer>) {
    let bitonic = [uniform_buffer_sized(true, NonZeroU64::new(16)).build(0, ShaderStages::COMPUTE)];
    let mut layouts = HashMap::default();
    let mut shaders = HashMap::default();
    for stage in stages::all_stages() {
        layouts.insert(stage.name, stage_layout(stage));
        shaders
            .entry(stage.name)
            .or_insert_with(|| (stage.shader)(&asset_server));
    }
    commands.insert_resource(SphPipelines {
        layouts,
        bitonic_layout: BindGroupLayoutDescriptor::new("sph_bitonic_step", &bitonic),
        shaders,
        variants: HashMap::default(),
    });
}

impl SphPipelines {
    /// Queues the pipeline of one role of `stage` in the variant `key`.
    fn queue(
        &self,
        cache: &PipelineCache,
        stage: &GpuStage,
        key: &VariantKey,
        role: &[&'static str],
    ) -> Option<CachedComputePipelineId> {
        let mut shader_defs = key.shader_defs();
        shader_defs.extend(role.iter().map(|&d| ShaderDefVal::from(d)));
        shader_defs.push(ShaderDefVal::UInt(
            "WORKGROUP_SIZE".into(),
            stage.workgroup_size,
        ));
        let mut layout = vec![self.layouts.get(stage.name)?.clone()];
        if matches!(stage.dispatch, Dispatch::BitonicSteps) {
            layout.push(self.bitonic_layout.clone());
        }
        Some(cache.queue_compute_pipeline(ComputePipelineDescriptor {
            label: Some(stage.name.into()),
            layout,
            shader: self.shaders.get(stage.name)?.clone(),
            shader_defs,
            ..default()
        }))
    }
}

/// Queues the pipelines of the stage list this frame's parameters need (once per variant).
pub(crate) fn queue_sph_pipelines(
    frame: Res<ExtractedSphFrame>,
    pipelines: Option<ResMut<SphPipelines>>,
    cache: Res<PipelineCache>,
) {
    let Some(mut pipelines) = pipelines else {
        return;
    };
    if !frame.active {
        return;
    }
    let key = VariantKey::of_frame(&frame);
    if pipelines.variants.contains_key(&key) {
        return;
    }
    let queued = stages::stage_list(&key)
        .into_iter()
        .map(|stage| QueuedStage {
            stage,
            pipelines: stage
                .roles
                .iter()
                .filter_map(|role| pipelines.queue(&cache, stage, &key, role))
                .collect(),
        })
        .collect();
    pipelines.variants.insert(key, queued);
}

/// Why a stage list cannot run yet, or `None` when all its pipelines are ready.
pub fn pipelines_not_ready(cache: &PipelineCache, list: &[QueuedStage]) -> Option<String> {
    for queued in list {
        if queued.pipelines.len() != queued.stage.roles.len() {
            return Some(format!(
                "gpu: no layout or shader for {}",
                queued.stage.name
            ));
        }
        for &id in &queued.pipelines {
            match cache.get_compute_pipeline_state(id) {
                CachedPipelineState::Ok(_) => {}
                CachedPipelineState::Err(e) => return Some(format!("gpu: shader error: {e}")),
                _ => return Some(STATUS_COMPILING_SHADERS.to_string()),
            }
        }
    }
    None
}

/// (Re)creates every stage's bind group, and the bitonic steps' group 1, after a reallocation.
pub(crate) fn prepare_sph_bind_groups(
    pipelines: Option<Res<SphPipelines>>,
    cache: Res<PipelineCache>,
    device: Res<RenderDevice>,
    mut state: ResMut<SphGpuState>,
) {
    let Some(pipelines) = pipelines else {
        return;
    };
    if !state.bind_groups.is_empty() && state.bind_group_generation == state.generation {
        return;
    }
    let Some(buffers) = state.buffers.clone() else {
        return;
    };
    state.bind_groups.clear();
    for stage in stages::all_stages() {
        let Some(layout) = pipelines.layouts.get(stage.name) else {
            continue;
        };
        let mut entries = vec![BindGroupEntry {
            binding: 0,
            resource: buffers.uniform.as_entire_binding(),
        }];
        entries.extend(stage.arenas().into_iter().map(|arena| BindGroupEntry {
            binding: arena.binding(),
            resource: buffers.arena(arena).as_entire_binding(),
        }));
        let group =
            device.create_bind_group(stage.name, &cache.get_bind_group_layout(layout), &entries);
        state.bind_groups.insert(stage.name, group);
    }
    let step = BufferBinding {
        buffer: &buffers.bitonic_steps,
        offset: 0,
        size: NonZeroU64::new(16),
    };
    let bitonic = device.create_bind_group(
        "sph_bitonic_step",
        &cache.get_bind_group_layout(&pipelines.bitonic_layout),
        &[BindGroupEntry {
            binding: 0,
            resource: BindingResource::Buffer(step),
        }],
    );
    let offsets = (0..buffers.bitonic_step_count)
        .map(|k| k * BITONIC_STRIDE as u32)
        .collect();
    state.bitonic_bind_group = Some((bitonic, offsets));
    state.bind_group_generation = state.generation;
}
