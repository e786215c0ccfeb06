//! The surface's normals (`surface_normals.wgsl`): one fullscreen pass over the scaled target
//! turns the smoothed depth into view-space normals and the water's coverage.

use super::view::{depth_reader_layout, NORMAL_FORMAT};
use bevy::asset::{embedded_asset, load_embedded_asset};
use bevy::core_pipeline::FullscreenShader;
use bevy::prelude::*;
use bevy::render::render_resource::{
    BindGroupLayoutDescriptor, CachedRenderPipelineId, ColorTargetState, ColorWrites,
    FragmentState, PipelineCache, RenderPipelineDescriptor,
};

/// Pass name (GPU timings, labels).
pub const NAME: &str = "sph_surface_normals";

/// The normals pass's layout and pipeline.
#[derive(Resource)]
pub struct SurfaceNormalsPipeline {
    /// Group 0: the uniform block and the smoothed depth.
    pub layout: BindGroupLayoutDescriptor,
    /// The pipeline.
    pub pipeline: CachedRenderPipelineId,
}

pub(crate) fn embed(app: &mut App) {
    embedded_asset!(app, "surface_normals.wgsl");
}

/// The normals pass's group 0: the uniform block and the filtered depth.
pub fn normals_layout() -> BindGroupLayoutDescriptor {
    depth_reader_layout(NAME)
}

pub(crate) fn init_surface_normals_pipeline(
    mut commands: Commands,
    server: Res<AssetServer>,
    cache: Res<PipelineCache>,
    fullscreen: Option<Res<FullscreenShader>>,
) {
    // Without Bevy's core pipeline there are no views to draw a surface in.
    let Some(fullscreen) = fullscreen else {
        return;
    };
    let layout = normals_layout();
    let pipeline = cache.queue_render_pipeline(RenderPipelineDescriptor {
        label: Some(NAME.into()),
        layout: vec![layout.clone()],
        vertex: fullscreen.to_vertex_state(),
        fragment: Some(FragmentState {
            shader: load_embedded_asset!(server.as_ref(), "surface_normals.wgsl"),
            targets: vec![Some(ColorTargetState {
                format: NORMAL_FORMAT,
                blend: None,
                write_mask: ColorWrites::ALL,
            })],
            ..default()
        }),
        ..default()
    });
    commands.insert_resource(SurfaceNormalsPipeline { layout, pipeline });
}
