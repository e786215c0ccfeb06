//! The surface's passes for one view, in `Core3dSystems::EarlyPostProcess`: depth, thickness,
//! whitewater (while it is on), the filter's iterations, normals, then the composite into the
//! view target. Each pass is GPU-timed under its name when `RenderDiagnosticsPlugin` is added.

use super::composite::{SurfaceCompositePipeline, NAME as COMPOSITE};
use super::depth::{SurfaceDepthPipeline, NAME as DEPTH};
use super::filter::{SurfaceFilterPipelines, NAME as FILTER};
use super::impostor::impostor_bind_group;
use super::normals::{SurfaceNormalsPipeline, NAME as NORMALS};
use super::thickness::{SurfaceThicknessPipeline, NAME as THICKNESS};
use super::view::{
    ExtractedSphSurface, SurfaceCompositeVariant, SurfaceParticles, SurfaceUniforms,
    SurfaceViewResources,
};
use super::whitewater::{SurfaceWhitewaterPipeline, NAME as WHITEWATER};
use bevy::prelude::*;
use bevy::render::diagnostic::RecordDiagnostics;
use bevy::render::render_asset::RenderAssets;
use bevy::render::render_resource::{
    BindGroup, BindGroupEntries, LoadOp, Operations, PipelineCache, RenderPassColorAttachment,
    RenderPassDepthStencilAttachment, RenderPassDescriptor, RenderPipeline, StoreOp, TextureView,
};
use bevy::render::renderer::{RenderContext, ViewQuery};
use bevy::render::storage::GpuShaderBuffer;
use bevy::render::view::{ViewDepthTexture, ViewTarget};

/// Every pipeline the passes use, once compiled.
struct Pipelines<'a> {
    depth: &'a RenderPipeline,
    thickness: &'a RenderPipeline,
    filter: [&'a RenderPipeline; 2],
    normals: &'a RenderPipeline,
    composite: &'a RenderPipeline,
    /// The whitewater pass's, once compiled, when the composite variant reads whitewater.
    whitewater: Option<&'a RenderPipeline>,
    /// The filter's, normals' and composite's resources (their bind-group layouts).
    layouts: (
        &'a SurfaceFilterPipelines,
        &'a SurfaceNormalsPipeline,
        &'a SurfaceCompositePipeline,
    ),
}

/// The surface's pipeline resources (each exists once its pipelines are queued) and the cache
/// that compiles them.
#[derive(bevy::ecs::system::SystemParam)]
pub(crate) struct SurfacePipelineResources<'w> {
    depth: Option<Res<'w, SurfaceDepthPipeline>>,
    thickness: Option<Res<'w, SurfaceThicknessPipeline>>,
    filter: Option<Res<'w, SurfaceFilterPipelines>>,
    normals: Option<Res<'w, SurfaceNormalsPipeline>>,
    composite: Option<Res<'w, SurfaceCompositePipeline>>,
    whitewater: Option<Res<'w, SurfaceWhitewaterPipeline>>,
    cache: Res<'w, PipelineCache>,
}

impl SurfacePipelineResources<'_> {
    /// Every pipeline of the passes, with the view's composite `variant`, once all are compiled.
    fn compiled(&self, variant: &SurfaceCompositeVariant) -> Option<Pipelines<'_>> {
        let (Some(depth), Some(thickness), Some(filter), Some(normals), Some(composite)) = (
            &self.depth,
            &self.thickness,
            &self.filter,
            &self.normals,
            &self.composite,
        ) else {
            return None;
        };
        let cache = &self.cache;
        // Until the whitewater pass compiles, the water is drawn without it.
        let whitewater = self
            .whitewater
            .as_ref()
            .filter(|_| variant.whitewater)
            .and_then(|pipeline| cache.get_render_pipeline(pipeline.0));
        Some(Pipelines {
            depth: cache.get_render_pipeline(depth.0)?,
            thickness: cache.get_render_pipeline(thickness.0)?,
            filter: [
                cache.get_render_pipeline(filter.directions[0])?,
                cache.get_render_pipeline(filter.directions[1])?,
            ],
            normals: cache.get_render_pipeline(normals.pipeline)?,
            composite: cache.get_render_pipeline(variant.pipeline)?,
            whitewater,
            layouts: (filter, normals, composite),
        })
    }
}

/// Draws the water surface of the current view.
pub(crate) fn sph_surface_passes(
    view: ViewQuery<(
        &ViewTarget,
        &ViewDepthTexture,
        &SurfaceViewResources,
        &SurfaceCompositeVariant,
        &ExtractedSphSurface,
    )>,
    particles: Res<SurfaceParticles>,
    buffers: Res<RenderAssets<GpuShaderBuffer>>,
    uniforms: Res<SurfaceUniforms>,
    pipeline_resources: SurfacePipelineResources,
    mut ctx: RenderContext,
) {
    let (target, view_depth, resources, variant, settings) = view.into_inner();
    let Some(pipelines) = pipeline_resources.compiled(variant) else {
        return;
    };
    let cache = &pipeline_resources.cache;
    let (filter, normals, composite) = pipelines.layouts;
    let Some(positions) = particles
        .position
        .as_ref()
        .and_then(|handle| buffers.get(handle))
    else {
        return;
    };
    let device = ctx.render_device().clone();
    let Some(impostors) = impostor_bind_group(&device, cache, &uniforms, &positions.buffer) else {
        return;
    };
    let Some(uniform) = uniforms.0.binding() else {
        return;
    };
    let offset = [resources.uniform_offset];
    let diagnostics = ctx.diagnostic_recorder();
    let diagnostics = diagnostics.as_deref();
    let count = particles.count;

    // Depth: the nearest sphere per pixel.
    {
        let mut pass = ctx
            .command_encoder()
            .begin_render_pass(&RenderPassDescriptor {
                label: Some(DEPTH),
                color_attachments: &[Some(clear_attachment(
                    &resources.fluid_depth[0].default_view,
                ))],
                depth_stencil_attachment: Some(RenderPassDepthStencilAttachment {
                    view: &resources.impostor_depth.default_view,
                    depth_ops: Some(Operations {
                        load: LoadOp::Clear(0.0),
                        store: StoreOp::Discard,
                    }),
                    stencil_ops: None,
                }),
                ..Default::default()
            });
        let span = diagnostics.pass_span(&mut pass, DEPTH);
        pass.set_pipeline(pipelines.depth);
        pass.set_bind_group(0, &impostors, &offset);
        pass.draw(0..billboard_vertices(count), 0..1);
        span.end(&mut pass);
    }
    // Thickness: every sphere's chord, summed.
    {
        let mut pass = ctx
            .command_encoder()
            .begin_render_pass(&RenderPassDescriptor {
                label: Some(THICKNESS),
                color_attachments: &[Some(clear_attachment(&resources.thickness.default_view))],
                ..Default::default()
            });
        let span = diagnostics.pass_span(&mut pass, THICKNESS);
        pass.set_pipeline(pipelines.thickness);
        pass.set_bind_group(0, &impostors, &offset);
        pass.draw(0..billboard_vertices(count), 0..1);
        span.end(&mut pass);
    }
    // Whitewater: every diffuse particle's disc, added by class (the target only cleared until
    // the pass compiles or while its buffer uploads).
    if let Some(target) = &resources.whitewater {
        let draw = pipelines.whitewater.zip(
            particles
                .diffuse
                .as_ref()
                .and_then(|handle| buffers.get(handle))
                .and_then(|diffuse| {
                    impostor_bind_group(&device, cache, &uniforms, &diffuse.buffer)
                }),
        );
        let mut pass = ctx
            .command_encoder()
            .begin_render_pass(&RenderPassDescriptor {
                label: Some(WHITEWATER),
                color_attachments: &[Some(clear_attachment(&target.default_view))],
                ..Default::default()
            });
        if let Some((pipeline, group)) = draw {
            let span = diagnostics.pass_span(&mut pass, WHITEWATER);
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, &group, &offset);
            pass.draw(0..billboard_vertices(particles.diffuse_count), 0..1);
            span.end(&mut pass);
        }
    }
    // The filter: [0] -> [1] along the rows, [1] -> [0] down the columns, per iteration.
    let filter_layout = cache.get_bind_group_layout(&filter.layout);
    let reads: [BindGroup; 2] = [0, 1].map(|k| {
        device.create_bind_group(
            FILTER,
            &filter_layout,
            &BindGroupEntries::sequential((
                uniform.clone(),
                &resources.fluid_depth[k].default_view,
            )),
        )
    });
    for pass_index in 0..2 * settings.0.filter_iterations {
        let direction = (pass_index % 2) as usize;
        let mut pass = ctx
            .command_encoder()
            .begin_render_pass(&RenderPassDescriptor {
                label: Some(FILTER),
                color_attachments: &[Some(clear_attachment(
                    &resources.fluid_depth[1 - direction].default_view,
                ))],
                ..Default::default()
            });
        let span = diagnostics.pass_span(&mut pass, filter_pass_name(pass_index));
        pass.set_pipeline(pipelines.filter[direction]);
        pass.set_bind_group(0, &reads[direction], &offset);
        pass.draw(0..3, 0..1);
        span.end(&mut pass);
    }
    // Normals of the smoothed depth.
    {
        let group = device.create_bind_group(
            NORMALS,
            &cache.get_bind_group_layout(&normals.layout),
            &BindGroupEntries::sequential((
                uniform.clone(),
                &resources.fluid_depth[0].default_view,
            )),
        );
        let mut pass = ctx
            .command_encoder()
            .begin_render_pass(&RenderPassDescriptor {
                label: Some(NORMALS),
                color_attachments: &[Some(clear_attachment(&resources.normals.default_view))],
                ..Default::default()
            });
        let span = diagnostics.pass_span(&mut pass, NORMALS);
        pass.set_pipeline(pipelines.normals);
        pass.set_bind_group(0, &group, &offset);
        pass.draw(0..3, 0..1);
        span.end(&mut pass);
    }
    // Composite into the view target.
    let post_process = target.post_process_write();
    let layout = cache.get_bind_group_layout(
        &composite.layouts[variant.whitewater as usize][variant.multisampled as usize],
    );
    let entries = (
        uniform,
        post_process.source,
        &composite.sampler,
        &resources.fluid_depth[0].default_view,
        &resources.normals.default_view,
        &resources.thickness.default_view,
        view_depth.view(),
    );
    let composite_group = match (variant.whitewater, &resources.whitewater) {
        (true, Some(white)) => {
            let (a, b, c, d, e, f, g) = entries;
            let entries = (a, b, c, d, e, f, g, &white.default_view);
            device.create_bind_group(COMPOSITE, &layout, &BindGroupEntries::sequential(entries))
        }
        (false, _) => {
            device.create_bind_group(COMPOSITE, &layout, &BindGroupEntries::sequential(entries))
        }
        // The variant and the view's textures disagree for a frame after whitewater turns on
        // or off: draw nothing rather than bind the wrong layout.
        (true, None) => return,
    };
    let mut pass = ctx
        .command_encoder()
        .begin_render_pass(&RenderPassDescriptor {
            label: Some(COMPOSITE),
            color_attachments: &[Some(RenderPassColorAttachment {
                view: post_process.destination,
                depth_slice: None,
                resolve_target: None,
                ops: Operations::default(),
            })],
            ..Default::default()
        });
    let span = diagnostics.pass_span(&mut pass, COMPOSITE);
    pass.set_pipeline(pipelines.composite);
    pass.set_bind_group(0, &composite_group, &offset);
    pass.draw(0..3, 0..1);
    span.end(&mut pass);
}

/// The GPU-timing name of the filter's pass `index` (two per iteration); the main world sums
/// them into one `sph_surface_filter` figure.
pub fn filter_pass_name(index: u32) -> String {
    format!("{FILTER}_{index}")
}

/// A colour attachment cleared to 0 (no water) and stored.
fn clear_attachment(view: &TextureView) -> RenderPassColorAttachment<'_> {
    RenderPassColorAttachment {
        view,
        depth_slice: None,
        resolve_target: None,
        ops: Operations {
            load: LoadOp::Clear(Default::default()),
            store: StoreOp::Store,
        },
    }
}

/// The vertices an impostor pass draws for `slots` particle slots: one triangle each, in one
/// instance (`surface_impostor.wgsl`).
fn billboard_vertices(slots: u32) -> u32 {
    slots.saturating_mul(3)
}
