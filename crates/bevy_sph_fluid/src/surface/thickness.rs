//! The surface's thickness pass (`surface_thickness.wgsl`): the same impostors, not
//! depth-tested, add every sphere's chord (weighted to water volume) into the scaled thickness
//! target.

use super::impostor::additive_impostor_pipeline;
use super::view::THICKNESS_FORMAT;
use bevy::asset::{embedded_asset, load_embedded_asset};
use bevy::prelude::*;
use bevy::render::render_resource::{CachedRenderPipelineId, PipelineCache};

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
    let id =
        cache.queue_render_pipeline(additive_impostor_pipeline(NAME, shader, THICKNESS_FORMAT));
    commands.insert_resource(SurfaceThicknessPipeline(id));
}
