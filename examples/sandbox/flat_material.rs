//! A flat, unlit colour material for the scene's floor, pipe and glass walls (cheap on a
//! software rasterizer, where the PBR fragment shader dominates the frame).

use bevy::prelude::*;
use bevy::reflect::TypePath;
use bevy::render::render_resource::AsBindGroup;
use bevy::shader::ShaderRef;

/// Flat colour; blended when its alpha is below one.
#[derive(Asset, TypePath, AsBindGroup, Debug, Clone)]
pub struct FlatMaterial {
    /// Linear RGBA.
    #[uniform(0)]
    pub color: LinearRgba,
}

impl FlatMaterial {
    /// A material of colour `color`.
    pub fn new(color: Color) -> Self {
        Self {
            color: color.to_linear(),
        }
    }
}

impl Material for FlatMaterial {
    fn fragment_shader() -> ShaderRef {
        "shaders/sandbox_flat.wgsl".into()
    }

    fn alpha_mode(&self) -> AlphaMode {
        if self.color.alpha < 1.0 {
            AlphaMode::Blend
        } else {
            AlphaMode::Opaque
        }
    }
}
