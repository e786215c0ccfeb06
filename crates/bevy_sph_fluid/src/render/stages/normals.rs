//! Akinci 2013 normals pass (`normals.wgsl`; CPU twin
//! `sph_core::surface_tension_akinci2013::compute_normals`). Only with surface tension.

use super::{encode_pass, workgroups};
use crate::render::SphRun;
use bevy::asset::{embedded_asset, load_embedded_asset};
use bevy::prelude::*;
use bevy::render::render_resource::PipelineCache;
use bevy::render::renderer::RenderContext;

pub(crate) fn embed(app: &mut App) {
    embedded_asset!(app, "normals.wgsl");
}

pub(crate) fn load(asset_server: &AssetServer) -> Handle<Shader> {
    load_embedded_asset!(asset_server, "normals.wgsl")
}

/// n_i = h Σ (m/ρ_j) ∇W for every particle; no dispatch without surface tension.
pub fn sph_normals(mut ctx: RenderContext, mut run: ResMut<SphRun>, cache: Res<PipelineCache>) {
    let Some(pipeline) = run.pipelines.normals else {
        return;
    };
    encode_pass(
        &mut ctx,
        &mut run,
        &cache,
        "sph_normals",
        pipeline,
        |pass, run| {
            pass.dispatch_workgroups(workgroups(run.particle_count), 1, 1);
            1
        },
    );
}
