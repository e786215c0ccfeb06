//! The render world, one way: the frame plan is extracted (`extract`), the GPU buffers
//! (`buffers`: the logical buffers of `buf` packed into the arenas of `arenas`) are prepared
//! (`prepare`), the pipelines of the scene's stage list are queued and bound (`pipelines`, from
//! the registry in `stages`, the solvers' folders in `solvers` and `whitewater`), and `simulate` encodes the
//! stages once per force evaluation of every step, then copies the state where the main world
//! reads it. This module only wires them.

pub mod arenas;
pub mod bodies;
pub mod buf;
pub mod buffers;
pub mod extract;
pub mod limits;
pub mod pipelines;
pub mod plan;
pub mod prepare;
pub mod simulate;
pub mod solvers;
pub mod stage;
pub mod stages;
pub mod whitewater;

use crate::sets::{SphGraphSystems, SphStep};
use crate::shared::SphRenderFeedback;
use bevy::core_pipeline::schedule::camera_driver;
use bevy::prelude::*;
use bevy::render::renderer::{RenderGraph, RenderGraphSystems};
use bevy::render::{ExtractSchedule, Render, RenderApp, RenderStartup, RenderSystems};
use bevy::shader::load_shader_library;

pub(crate) fn build(app: &mut App) {
    load_shader_library!(app, "shaders/types.wgsl");
    load_shader_library!(app, "shaders/bindings.wgsl");
    load_shader_library!(app, "shaders/kernels.wgsl");
    load_shader_library!(app, "shaders/scan.wgsl");
    load_shader_library!(app, "shaders/neighbors.wgsl");
    load_shader_library!(app, "shaders/clock.wgsl");
    load_shader_library!(app, "shaders/checkpoint.wgsl");
    load_shader_library!(app, "shaders/guard.wgsl");
    load_shader_library!(app, "shaders/pumps.wgsl");
    load_shader_library!(app, "shaders/probes.wgsl");
    load_shader_library!(app, "shaders/body_reactions.wgsl");
    load_shader_library!(app, "shaders/speculative_contact.wgsl");
    load_shader_library!(app, "solvers/pbf/pbf.wgsl");
    load_shader_library!(app, "solvers/dfsph/dfsph.wgsl");
    load_shader_library!(app, "whitewater/whitewater.wgsl");
    load_shader_library!(app, "bodies/bodies.wgsl");
    let mut embedded = Vec::new();
    for stage in stages::all_stages() {
        if !embedded.contains(&stage.name) {
            (stage.embed)(app);
            embedded.push(stage.name);
        }
    }
    let feedback = SphRenderFeedback::default();
    app.insert_resource(feedback.clone());
    let Some(render_app) = app.get_sub_app_mut(RenderApp) else {
        return;
    };
    let mut step = bevy::ecs::schedule::Schedule::new(SphStep);
    step.configure_sets(SphGraphSystems);
    render_app
        .insert_resource(feedback)
        .init_resource::<buffers::SphGpuState>()
        .init_resource::<extract::ExtractedSphFrame>()
        .add_schedule(step)
        .add_systems(SphStep, simulate::sph_encode_stages.in_set(SphGraphSystems))
        .add_systems(ExtractSchedule, extract::extract_sph_frame)
        .add_systems(RenderStartup, pipelines::init_sph_pipelines)
        .add_systems(
            Render,
            (
                (pipelines::queue_sph_pipelines, prepare::prepare_sph_buffers)
                    .in_set(RenderSystems::PrepareResources),
                pipelines::prepare_sph_bind_groups.in_set(RenderSystems::PrepareBindGroups),
            ),
        )
        .add_systems(
            RenderGraph,
            (simulate::sph_simulate, simulate::sph_publish_state)
                .chain()
                .in_set(RenderGraphSystems::Render)
                .before(camera_driver),
        );
}
