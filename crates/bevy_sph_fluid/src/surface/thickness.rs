//! The surface's thickness pass (`surface_thickness.wgsl`): the same impostors, not
//! depth-tested, add every sphere's chord (weighted to water volume) into the scaled thickness
//! target.

use super::impostor::impostor_layout;
use super::view::THICKNESS_FORMAT;
use bevy::asset::{embedded_asset, load_embedded_asset};
use bevy::prelude::*;
use bevy::render::render_resource::{
    BlendComponent, BlendFactor, BlendOperation, BlendState, CachedRenderPipelineId,
    ColorTargetState, ColorWrites, FragmentState, PipelineCache, RenderPipelineDescriptor,
    VertexState,
};

/// Pass name (GPU timings, labels).
pub const NAME: &str = "sph_surface_thickness";

/// The thickness pass's pipeline.
#[derive(Resource)]
pub struct SurfaceThicknessPipeline(pub CachedRenderPipelineId);

pub(crate) fn embed(app: &mut App) {
    embedded_asset!(app, "surface_thickness.wgsl");
}

pub(crate) fn init_surface_thickness_pipeline(
    mut commands: Commands,
    server: Res<AssetServer>,
    cache: Res<PipelineCache>,
) {
    let shader = load_embedded_asset!(server.as_ref(), "surface_thickness.wgsl");
    let add = BlendComponent {
        src_factor: BlendFactor::One,
        dst_factor: BlendFactor::One,
        operation: BlendOperation::Add,
    };
    let id = cache.queue_render_pipeline(RenderPipelineDescriptor {
        label: Some(NAME.into()),
        layout: vec![impostor_layout()],
        vertex: VertexState {
            shader: shader.clone(),
            ..default()
        },
        fragment: Some(FragmentState {
            shader,
            targets: vec![Some(ColorTargetState {
                format: THICKNESS_FORMAT,
                blend: Some(BlendState {
                    color: add,
                    alpha: add,
                }),
                write_mask: ColorWrites::ALL,
            })],
            ..default()
        }),
        ..default()
    });
    commands.insert_resource(SurfaceThicknessPipeline(id));
}
