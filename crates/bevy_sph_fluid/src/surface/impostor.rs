//! What the impostor passes share (`surface_impostor.wgsl`): their bind group (the uniform
//! block and the particle positions), its layout, and the additive pipeline of the passes that
//! sum over every particle (thickness, whitewater).

use super::view::{GpuSurfaceUniform, SurfaceUniforms};
use bevy::prelude::*;
use bevy::render::render_resource::binding_types::{
    storage_buffer_read_only_sized, uniform_buffer,
};
use bevy::render::render_resource::{
    BindGroup, BindGroupEntries, BindGroupLayoutDescriptor, BindGroupLayoutEntries, BlendComponent,
    BlendFactor, BlendOperation, BlendState, Buffer, ColorTargetState, ColorWrites, FragmentState,
    PipelineCache, RenderPipelineDescriptor, ShaderStages, TextureFormat, VertexState,
};
use bevy::render::renderer::RenderDevice;

/// Group 0 of the impostor passes: the uniform block (dynamic offset) and the positions.
pub fn impostor_layout() -> BindGroupLayoutDescriptor {
    BindGroupLayoutDescriptor::new(
        "sph_surface_impostor",
        &BindGroupLayoutEntries::sequential(
            ShaderStages::VERTEX_FRAGMENT,
            (
                uniform_buffer::<GpuSurfaceUniform>(true),
                storage_buffer_read_only_sized(false, None),
            ),
        ),
    )
}

/// The impostor passes' group 0 for this frame's uniforms and `positions`.
pub fn impostor_bind_group(
    device: &RenderDevice,
    cache: &PipelineCache,
    uniforms: &SurfaceUniforms,
    positions: &Buffer,
) -> Option<BindGroup> {
    Some(device.create_bind_group(
        "sph_surface_impostor",
        &cache.get_bind_group_layout(&impostor_layout()),
        &BindGroupEntries::sequential((uniforms.0.binding()?, positions.as_entire_binding())),
    ))
}

/// The pipeline of an impostor pass that adds every fragment into a `format` target, not
/// depth-tested: `shader`'s `vertex` and `fragment`, labelled `label`.
pub fn additive_impostor_pipeline(
    label: &'static str,
    shader: Handle<Shader>,
    format: TextureFormat,
) -> RenderPipelineDescriptor {
    let add = BlendComponent {
        src_factor: BlendFactor::One,
        dst_factor: BlendFactor::One,
        operation: BlendOperation::Add,
    };
    RenderPipelineDescriptor {
        label: Some(label.into()),
        layout: vec![impostor_layout()],
        vertex: VertexState {
            shader: shader.clone(),
            ..default()
        },
        fragment: Some(FragmentState {
            shader,
            targets: vec![Some(ColorTargetState {
                format,
                blend: Some(BlendState {
                    color: add,
                    alpha: add,
                }),
                write_mask: ColorWrites::ALL,
            })],
            ..default()
        }),
        ..default()
    }
}
