//! A water surface drawn from the particles in screen space, per camera: add
//! [`SphSurface`](crate::SphSurface) to a `Camera3d`. The passes, each a `.rs` + `.wgsl` pair
//! over the scaled targets of the view:
//! `depth` (nearest sphere impostor), `thickness` (summed chords), `whitewater` (the diffuse
//! particles' billboards by class, while whitewater is on), `filter` (narrow-range
//! smoothing of the depth, Truong & Yuksel 2018), `normals` (of the smoothed depth), then
//! `composite` (Fresnel, refraction, absorption, highlight) into the view's colour before
//! tonemapping (van der Laan, Green & Sainz 2009). This module only wires them.

pub mod composite;
pub mod cpu_twin;
pub mod depth;
pub mod filter;
pub mod impostor;
pub mod normals;
pub mod passes;
pub mod settings;
pub mod thickness;
mod timings;
pub mod view;
pub mod whitewater;

use bevy::core_pipeline::{schedule::Core3d, Core3dSystems};
use bevy::prelude::*;
use bevy::render::render_resource::SpecializedRenderPipelines;
use bevy::render::{ExtractSchedule, Render, RenderApp, RenderStartup, RenderSystems};
use bevy::shader::load_shader_library;

pub(crate) fn build(app: &mut App, schedule: bevy::ecs::schedule::InternedScheduleLabel) {
    load_shader_library!(app, "surface_types.wgsl");
    load_shader_library!(app, "surface_impostor.wgsl");
    depth::embed(app);
    thickness::embed(app);
    filter::embed(app);
    normals::embed(app);
    composite::embed(app);
    whitewater::embed(app);
    app.register_type::<settings::SphSurface>()
        .register_type::<settings::SphSurfaceStatus>()
        .register_type::<settings::SphSurfaceDebugView>()
        .add_systems(
            schedule,
            (
                settings::sph_forget_surfaces,
                settings::sph_validate_surfaces,
                settings::sph_surface_depth_usage,
                timings::sph_record_surface_timings,
            )
                .chain(),
        );
    let Some(render_app) = app.get_sub_app_mut(RenderApp) else {
        return;
    };
    render_app
        .init_resource::<view::SurfaceUniforms>()
        .init_resource::<view::SurfaceParticles>()
        .init_resource::<SpecializedRenderPipelines<composite::SurfaceCompositePipeline>>()
        .add_systems(
            RenderStartup,
            (
                depth::init_surface_depth_pipeline,
                thickness::init_surface_thickness_pipeline,
                filter::init_surface_filter_pipelines,
                normals::init_surface_normals_pipeline,
                composite::init_surface_composite_pipeline,
            ),
        )
        .add_systems(ExtractSchedule, view::extract_sph_surfaces)
        .add_systems(
            Render,
            (
                (
                    composite::queue_sph_surface_composite,
                    whitewater::queue_sph_surface_whitewater,
                )
                    .in_set(RenderSystems::Queue),
                view::prepare_sph_surface_views.in_set(RenderSystems::PrepareResources),
            ),
        )
        .add_systems(
            Core3d,
            passes::sph_surface_passes.in_set(Core3dSystems::EarlyPostProcess),
        );
}
