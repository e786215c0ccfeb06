//! Density and pressure pass (`density.wgsl`; CPU twin `sph_core::density`).

use super::{encode_pass, workgroups};
use crate::render::SphRun;
use bevy::asset::{embedded_asset, load_embedded_asset};
use bevy::prelude::*;
use bevy::render::render_resource::PipelineCache;
use bevy::render::renderer::RenderContext;

pub(crate) fn embed(app: &mut App) {
    embedded_asset!(app, "density.wgsl");
}

pub(crate) fn load(asset_server: &AssetServer) -> Handle<Shader> {
    load_embedded_asset!(asset_server, "density.wgsl")
}

/// ρ_i = m Σ W_poly6, p_i = EOS(ρ_i) for every particle.
pub fn sph_density(mut ctx: RenderContext, mut run: ResMut<SphRun>, cache: Res<PipelineCache>) {
    let pipeline = run.pipelines.density;
    encode_pass(
        &mut ctx,
        &mut run,
        &cache,
        "sph_density",
        pipeline,
        |pass, run| {
            pass.dispatch_workgroups(workgroups(run.particle_count), 1, 1);
            1
        },
    );
}
