//! What the two impostor passes share (`surface_impostor.wgsl`): their bind group (the uniform
//! block and the particle positions) and its layout.

use super::view::{GpuSurfaceUniform, SurfaceUniforms};
use bevy::render::render_resource::binding_types::{
    storage_buffer_read_only_sized, uniform_buffer,
};
use bevy::render::render_resource::{
    BindGroup, BindGroupEntries, BindGroupLayoutDescriptor, BindGroupLayoutEntries, Buffer,
    PipelineCache, ShaderStages,
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
