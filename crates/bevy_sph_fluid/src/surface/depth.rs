//! The surface's depth pass (`surface_depth.wgsl`): sphere impostors, depth-tested, write each
//! pixel's nearest water distance into the scaled fluid-depth target.

use super::impostor::impostor_layout;
use super::view::{FLUID_DEPTH_FORMAT, IMPOSTOR_DEPTH_FORMAT};
use bevy::asset::{embedded_asset, load_embedded_asset};
use bevy::prelude::*;
use bevy::render::render_resource::{
    CachedRenderPipelineId, ColorTargetState, ColorWrites, CompareFunction, DepthStencilState,
    FragmentState, PipelineCache, RenderPipelineDescriptor, VertexState,
};

/// Pass name (GPU timings, labels).
pub const NAME: &str = "sph_surface_depth";

/// The depth pass's pipeline.
#[derive(Resource)]
pub struct SurfaceDepthPipeline(pub CachedRenderPipelineId);

pub(crate) fn embed(app: &mut App) {
    embedded_asset!(app, "surface_depth.wgsl");
}

pub(crate) fn init_surface_depth_pipeline(
    mut commands: Commands,
    server: Res<AssetServer>,
    cache: Res<PipelineCache>,
) {
    let shader = load_embedded_asset!(server.as_ref(), "surface_depth.wgsl");
    let id = cache.queue_render_pipeline(RenderPipelineDescriptor {
        label: Some(NAME.into()),
        layout: vec![impostor_layout()],
        vertex: VertexState {
            shader: shader.clone(),
            ..default()
        },
        // Reverse z, as Bevy's views: the nearest sphere has the largest depth.
        depth_stencil: Some(DepthStencilState {
            format: IMPOSTOR_DEPTH_FORMAT,
            depth_write_enabled: Some(true),
            depth_compare: Some(CompareFunction::Greater),
            stencil: default(),
            bias: default(),
        }),
        fragment: Some(FragmentState {
            shader,
            targets: vec![Some(ColorTargetState {
                format: FLUID_DEPTH_FORMAT,
                blend: None,
                write_mask: ColorWrites::ALL,
            })],
            ..default()
        }),
        ..default()
    });
    commands.insert_resource(SurfaceDepthPipeline(id));
}
