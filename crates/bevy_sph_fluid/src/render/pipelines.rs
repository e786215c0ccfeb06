//! Bind-group layouts and the compute pipelines of each shader variant. Variants come from shader
//! defs: the search mode (`SEARCH_HASH`), `SURFACE_TENSION`, `VISCOSITY`, and each stage's role
//! in the integrator; a scene only compiles and runs the variant it needs.

use super::stages;
use super::{ExtractedSphFrame, ForcesRole, PrePhase};
use bevy::platform::collections::HashMap;
use bevy::prelude::*;
use bevy::render::render_resource::binding_types::{storage_buffer_sized, uniform_buffer_sized};
use bevy::render::render_resource::{
    BindGroupLayoutDescriptor, BindGroupLayoutEntry, CachedComputePipelineId,
    ComputePipelineDescriptor, PipelineCache, ShaderStages,
};
use bevy::shader::ShaderDefVal;
use sph_core::{NeighborSearch, SphParams};
use std::num::NonZeroU64;

/// Storage buffers in the shared group 0 (bindings 1 ..= 23).
pub const STORAGE_BINDINGS: u32 = 23;

/// Which variant of the pipelines a parameter set needs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct VariantKey {
    /// Neighbour-search mode.
    pub search: NeighborSearch,
    /// Surface tension on (normals pass, cohesion and curvature terms).
    pub surface_tension: bool,
    /// Viscosity term on.
    pub viscosity: bool,
    /// The density pass records neighbour counts (debug views).
    pub neighbor_counts: bool,
}

impl VariantKey {
    /// The variant `params` need.
    pub fn of(params: &SphParams, neighbor_counts: bool) -> Self {
        Self {
            search: params.neighbor_search,
            surface_tension: params.has_surface_tension(),
            viscosity: params.has_viscosity(),
            neighbor_counts,
        }
    }

    /// Shader defs common to every stage of this variant.
    pub fn shader_defs(&self) -> Vec<ShaderDefVal> {
        let mut defs = Vec::new();
        if self.search == NeighborSearch::Hash {
            defs.push("SEARCH_HASH".into());
        }
        if self.surface_tension {
            defs.push("SURFACE_TENSION".into());
        }
        if self.viscosity {
            defs.push("VISCOSITY".into());
        }
        if self.neighbor_counts {
            defs.push("NEIGHBOR_COUNT".into());
        }
        defs
    }
}

/// The pipelines of one variant. Stages a variant does not need are `None` and never dispatched.
#[derive(Clone, Debug, PartialEq)]
pub struct StagePipelines {
    /// Count cells (or hash keys) for each pre-phase: none, kick-drift, leapfrog drift.
    pub count_cells: [CachedComputePipelineId; 3],
    /// Grid prefix sum.
    pub prefix_sum: Option<CachedComputePipelineId>,
    /// Hash mode: bitonic sort step and bucket offsets.
    pub bitonic_sort: Option<CachedComputePipelineId>,
    /// Hash mode: bucket offsets.
    pub hash_offsets: Option<CachedComputePipelineId>,
    /// Scatter.
    pub scatter: CachedComputePipelineId,
    /// Density and pressure.
    pub density: CachedComputePipelineId,
    /// Normals (surface tension only).
    pub normals: Option<CachedComputePipelineId>,
    /// Forces for each role: plain, kick close, leapfrog first, leapfrog second.
    pub forces: [CachedComputePipelineId; 4],
    /// Symplectic Euler integration.
    pub integrate: CachedComputePipelineId,
    /// The clock: stability check, dt, time.
    pub time_step: CachedComputePipelineId,
}

impl StagePipelines {
    /// Every pipeline of the variant.
    pub fn all(&self) -> Vec<CachedComputePipelineId> {
        let mut ids = self.count_cells.to_vec();
        ids.extend(self.prefix_sum);
        ids.extend(self.bitonic_sort);
        ids.extend(self.hash_offsets);
        ids.extend([self.scatter, self.density, self.integrate, self.time_step]);
        ids.extend(self.normals);
        ids.extend(self.forces);
        ids
    }

    /// The count pipeline for a pre-phase.
    pub fn count_for(&self, pre: PrePhase) -> CachedComputePipelineId {
        self.count_cells[pre as usize]
    }

    /// The forces pipeline for a role.
    pub fn forces_for(&self, role: ForcesRole) -> CachedComputePipelineId {
        self.forces[role as usize]
    }
}

/// Layouts, shaders and the variants queued so far.
#[derive(Resource)]
pub struct SphPipelines {
    /// Group 0: the uniform and every storage buffer.
    pub layout: BindGroupLayoutDescriptor,
    /// Group 1 of the bitonic sort: one step, at a dynamic offset.
    pub bitonic_layout: BindGroupLayoutDescriptor,
    /// The stage shaders.
    pub shaders: stages::StageShaders,
    /// Pipelines per variant.
    pub variants: HashMap<VariantKey, StagePipelines>,
}

impl SphPipelines {
    /// Queues one pipeline of `shader` with the variant's defs plus `extra` defs.
    pub fn queue(
        &self,
        cache: &PipelineCache,
        label: &'static str,
        shader: &Handle<Shader>,
        key: &VariantKey,
        extra: &[&'static str],
    ) -> CachedComputePipelineId {
        let mut shader_defs = key.shader_defs();
        shader_defs.extend(extra.iter().map(|&d| d.into()));
        let mut layout = vec![self.layout.clone()];
        if label == "sph_bitonic_sort" {
            layout.push(self.bitonic_layout.clone());
        }
        cache.queue_compute_pipeline(ComputePipelineDescriptor {
            label: Some(label.into()),
            layout,
            shader: shader.clone(),
            shader_defs,
            ..default()
        })
    }
}

pub(crate) fn init_sph_pipelines(mut commands: Commands, asset_server: Res<AssetServer>) {
    let mut entries: Vec<BindGroupLayoutEntry> =
        vec![uniform_buffer_sized(false, None).build(0, ShaderStages::COMPUTE)];
    for binding in 1..=STORAGE_BINDINGS {
        entries.push(storage_buffer_sized(false, None).build(binding, ShaderStages::COMPUTE));
    }
    let bitonic = [uniform_buffer_sized(true, NonZeroU64::new(16)).build(0, ShaderStages::COMPUTE)];
    commands.insert_resource(SphPipelines {
        layout: BindGroupLayoutDescriptor::new("sph_state", &entries),
        bitonic_layout: BindGroupLayoutDescriptor::new("sph_bitonic_step", &bitonic),
        shaders: stages::StageShaders::load(&asset_server),
        variants: HashMap::default(),
    });
}

/// Queues the pipelines of the variant this frame's parameters need (once per variant).
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
    let key = VariantKey::of(&frame.params, frame.neighbor_counts);
    if pipelines.variants.contains_key(&key) {
        return;
    }
    let stage = stages::queue_variant(&pipelines, &cache, &key);
    pipelines.variants.insert(key, stage);
}
