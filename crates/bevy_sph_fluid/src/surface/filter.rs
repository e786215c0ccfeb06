//! The surface's depth filter (`surface_filter.wgsl`): a narrow-range Gaussian, one direction
//! per fullscreen pass; each iteration is a horizontal then a vertical pass.

use super::view::{depth_reader_layout, FLUID_DEPTH_FORMAT};
use bevy::asset::{embedded_asset, load_embedded_asset};
use bevy::core_pipeline::FullscreenShader;
use bevy::prelude::*;
use bevy::render::render_resource::{
    BindGroupLayoutDescriptor, CachedRenderPipelineId, ColorTargetState, ColorWrites,
    FragmentState, PipelineCache, RenderPipelineDescriptor,
};

/// Pass name (GPU timings, labels).
pub const NAME: &str = "sph_surface_filter";

/// The filter's layout and its two pipelines, `[horizontal, vertical]`.
#[derive(Resource)]
pub struct SurfaceFilterPipelines {
    /// Group 0: the uniform block and the depth read.
    pub layout: BindGroupLayoutDescriptor,
    /// Along the rows, then down the columns.
    pub directions: [CachedRenderPipelineId; 2],
}

pub(crate) fn embed(app: &mut App) {
    embedded_asset!(app, "surface_filter.wgsl");
}

/// The filter passes' group 0: the uniform block and the depth being filtered.
pub fn filter_layout() -> BindGroupLayoutDescriptor {
    depth_reader_layout(NAME)
}

pub(crate) fn init_surface_filter_pipelines(
    mut commands: Commands,
    server: Res<AssetServer>,
    cache: Res<PipelineCache>,
    fullscreen: Option<Res<FullscreenShader>>,
) {
    // Without Bevy's core pipeline there are no views to draw a surface in.
    let Some(fullscreen) = fullscreen else {
        return;
    };
    let shader = load_embedded_asset!(server.as_ref(), "surface_filter.wgsl");
    let layout = filter_layout();
    let queue = |defs: Vec<bevy::shader::ShaderDefVal>| {
        cache.queue_render_pipeline(RenderPipelineDescriptor {
            label: Some(NAME.into()),
            layout: vec![layout.clone()],
            vertex: fullscreen.to_vertex_state(),
            fragment: Some(FragmentState {
                shader: shader.clone(),
                shader_defs: defs,
                targets: vec![Some(ColorTargetState {
                    format: FLUID_DEPTH_FORMAT,
                    blend: None,
                    write_mask: ColorWrites::ALL,
                })],
                ..default()
            }),
            ..default()
        })
    };
    let directions = [queue(vec![]), queue(vec!["FILTER_VERTICAL".into()])];
    commands.insert_resource(SurfaceFilterPipelines { layout, directions });
}
