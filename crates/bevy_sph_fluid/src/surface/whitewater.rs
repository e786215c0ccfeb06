//! The surface's whitewater pass (`surface_whitewater.wgsl`): the diffuse particles of
//! [`SphWhitewater`](crate::SphWhitewater) as soft view-facing discs, their weights added per
//! class into the scaled whitewater target, which the composite lays over the water. Its
//! pipeline is queued the first frame whitewater is on: without whitewater it is never compiled.

use super::impostor::additive_impostor_pipeline;
use super::view::{SurfaceParticles, WHITEWATER_FORMAT};
use bevy::asset::{embedded_asset, load_embedded_asset};
use bevy::prelude::*;
use bevy::render::render_resource::{CachedRenderPipelineId, PipelineCache};

/// Pass name (GPU timings, labels).
pub const NAME: &str = "sph_surface_whitewater";

/// The whitewater pass's pipeline.
#[derive(Resource)]
pub struct SurfaceWhitewaterPipeline(pub CachedRenderPipelineId);

pub(crate) fn embed(app: &mut App) {
    embedded_asset!(app, "surface_whitewater.wgsl");
}

/// Queues the pass's pipeline once there are diffuse particles to draw.
pub(crate) fn queue_sph_surface_whitewater(
    mut commands: Commands,
    particles: Res<SurfaceParticles>,
    queued: Option<Res<SurfaceWhitewaterPipeline>>,
    server: Res<AssetServer>,
    cache: Res<PipelineCache>,
) {
    if queued.is_some() || particles.diffuse.is_none() {
        return;
    }
    let shader = load_embedded_asset!(server.as_ref(), "surface_whitewater.wgsl");
    let id =
        cache.queue_render_pipeline(additive_impostor_pipeline(NAME, shader, WHITEWATER_FORMAT));
    commands.insert_resource(SurfaceWhitewaterPipeline(id));
}
