//! The surface's composite (`surface_composite.wgsl`): the lit water over the view's colour,
//! in `Core3dSystems::EarlyPostProcess` (before tonemapping). Specialized by the view's colour
//! format, whether its depth is multisampled, and whether whitewater is drawn over the water.

use super::view::{
    ExtractedSphSurface, GpuSurfaceUniform, SurfaceCompositeVariant, SurfaceParticles,
};
use bevy::asset::{embedded_asset, load_embedded_asset};
use bevy::core_pipeline::FullscreenShader;
use bevy::prelude::*;
use bevy::render::render_resource::binding_types::{
    sampler, texture_2d, texture_depth_2d, texture_depth_2d_multisampled, uniform_buffer,
};
use bevy::render::render_resource::{
    BindGroupLayoutDescriptor, BindGroupLayoutEntries, ColorTargetState, ColorWrites,
    FragmentState, PipelineCache, RenderPipelineDescriptor, Sampler, SamplerBindingType,
    SamplerDescriptor, ShaderStages, SpecializedRenderPipeline, SpecializedRenderPipelines,
    TextureFormat, TextureSampleType,
};
use bevy::render::renderer::RenderDevice;
use bevy::render::view::{Msaa, ViewTarget};

/// Pass name (GPU timings, labels).
pub const NAME: &str = "sph_surface_composite";

/// The composite's layouts (single-sampled and multisampled view depth, without and with
/// whitewater), shader and sampler.
#[derive(Resource)]
pub struct SurfaceCompositePipeline {
    /// `[whitewater][multisampled]`: [`composite_layout`] of each variant.
    pub layouts: [[BindGroupLayoutDescriptor; 2]; 2],
    shader: Handle<Shader>,
    vertex: bevy::render::render_resource::VertexState,
    /// Bilinear, clamped: the scene colour and the thickness.
    pub sampler: Sampler,
}

/// The composite's variant: the view's colour format, whether its depth is multisampled, and
/// whether it reads a whitewater target.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct CompositeKey {
    /// The view target's main texture format.
    pub format: TextureFormat,
    /// MSAA on the view (its depth texture is multisampled).
    pub multisampled: bool,
    /// Whitewater on: the whitewater target is bound and laid over the water.
    pub whitewater: bool,
}

impl SpecializedRenderPipeline for SurfaceCompositePipeline {
    type Key = CompositeKey;

    fn specialize(&self, key: CompositeKey) -> RenderPipelineDescriptor {
        let mut shader_defs = Vec::new();
        if key.multisampled {
            shader_defs.push("MULTISAMPLED_DEPTH".into());
        }
        if key.whitewater {
            shader_defs.push("WHITEWATER".into());
        }
        RenderPipelineDescriptor {
            label: Some(NAME.into()),
            layout: vec![self.layouts[key.whitewater as usize][key.multisampled as usize].clone()],
            vertex: self.vertex.clone(),
            fragment: Some(FragmentState {
                shader: self.shader.clone(),
                shader_defs,
                targets: vec![Some(ColorTargetState {
                    format: key.format,
                    blend: None,
                    write_mask: ColorWrites::ALL,
                })],
                ..default()
            }),
            ..default()
        }
    }
}

/// The composite's group 0: the uniform block, the view's colour and its sampler, the fluid
/// depth, the normals, the thickness, the view's depth (`multisampled` or not) and, with
/// `whitewater`, the whitewater target.
pub fn composite_layout(multisampled: bool, whitewater: bool) -> BindGroupLayoutDescriptor {
    let depth = if multisampled {
        texture_depth_2d_multisampled()
    } else {
        texture_depth_2d()
    };
    let filterable = || texture_2d(TextureSampleType::Float { filterable: true });
    let entries = (
        uniform_buffer::<GpuSurfaceUniform>(true),
        filterable(),
        sampler(SamplerBindingType::Filtering),
        texture_2d(TextureSampleType::Float { filterable: false }),
        filterable(),
        filterable(),
        depth,
    );
    if whitewater {
        let (a, b, c, d, e, f, g) = entries;
        let entries = (a, b, c, d, e, f, g, filterable());
        BindGroupLayoutDescriptor::new(
            NAME,
            &BindGroupLayoutEntries::sequential(ShaderStages::FRAGMENT, entries),
        )
    } else {
        BindGroupLayoutDescriptor::new(
            NAME,
            &BindGroupLayoutEntries::sequential(ShaderStages::FRAGMENT, entries),
        )
    }
}

pub(crate) fn embed(app: &mut App) {
    embedded_asset!(app, "surface_composite.wgsl");
}

pub(crate) fn init_surface_composite_pipeline(
    mut commands: Commands,
    server: Res<AssetServer>,
    device: Res<RenderDevice>,
    fullscreen: Option<Res<FullscreenShader>>,
) {
    // Without Bevy's core pipeline there are no views to draw a surface in.
    let Some(fullscreen) = fullscreen else {
        return;
    };
    commands.insert_resource(SurfaceCompositePipeline {
        layouts: [false, true].map(|whitewater| {
            [false, true].map(|multisampled| composite_layout(multisampled, whitewater))
        }),
        shader: load_embedded_asset!(server.as_ref(), "surface_composite.wgsl"),
        vertex: fullscreen.to_vertex_state(),
        sampler: device.create_sampler(&SamplerDescriptor {
            label: Some(NAME),
            mag_filter: bevy::render::render_resource::FilterMode::Linear,
            min_filter: bevy::render::render_resource::FilterMode::Linear,
            ..default()
        }),
    });
}

/// Chooses each surface view's composite variant.
pub(crate) fn queue_sph_surface_composite(
    mut commands: Commands,
    views: Query<(Entity, &ViewTarget, &Msaa), With<ExtractedSphSurface>>,
    particles: Res<SurfaceParticles>,
    pipeline: Option<Res<SurfaceCompositePipeline>>,
    mut specialized: ResMut<SpecializedRenderPipelines<SurfaceCompositePipeline>>,
    cache: Res<PipelineCache>,
) {
    let Some(pipeline) = pipeline else {
        return;
    };
    for (entity, target, msaa) in &views {
        let key = CompositeKey {
            format: target.main_texture_format(),
            multisampled: msaa.samples() > 1,
            whitewater: particles.diffuse.is_some(),
        };
        let id = specialized.specialize(&cache, &pipeline, key);
        commands.entity(entity).insert(SurfaceCompositeVariant {
            pipeline: id,
            multisampled: key.multisampled,
            whitewater: key.whitewater,
        });
    }
}
