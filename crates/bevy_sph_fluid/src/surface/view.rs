//! The render world's side of a surface camera: what is extracted (the validated settings, the
//! particle buffer and count), the per-view uniform block and the per-view textures.

use super::settings::{SphSurface, SphSurfaceStatus};
use crate::api::SphGpuBuffers;
use crate::shared::SphSimulation;
use crate::whitewater::SphDiffuseParticles;
use bevy::math::UVec4;
use bevy::prelude::*;
use bevy::render::render_resource::{
    DynamicUniformBuffer, Extent3d, ShaderType, TextureDescriptor, TextureDimension, TextureFormat,
    TextureUsages,
};
use bevy::render::renderer::{RenderDevice, RenderQueue};
use bevy::render::storage::ShaderBuffer;
use bevy::render::sync_world::RenderEntity;
use bevy::render::texture::{CachedTexture, TextureCache};
use bevy::render::view::ExtractedView;
use bevy::render::Extract;

/// Format of the surface's depth targets: view-space distance along the view axis [m], 0 where
/// no water is drawn.
pub const FLUID_DEPTH_FORMAT: TextureFormat = TextureFormat::R32Float;
/// Format of the thickness target (additive blending needs a blendable format).
pub const THICKNESS_FORMAT: TextureFormat = TextureFormat::R16Float;
/// Format of the normals target: xyz the view-space normal, w the water's coverage (filterable,
/// so the composite upsamples it bilinearly).
pub const NORMAL_FORMAT: TextureFormat = TextureFormat::Rgba16Float;
/// Format of the whitewater target: each class's summed billboard weights (spray r, foam g,
/// bubbles b) and, in a, spray's and foam's weights times their distance along the view axis
/// (additive blending; a / (r + g) is their mean depth, for the opaque geometry's test).
pub const WHITEWATER_FORMAT: TextureFormat = TextureFormat::Rgba16Float;
/// A diffuse particle's billboard radius per particle spacing Δx: smaller than the fluid's
/// spheres, as Ihmsen et al. 2012 draw their spray and foam.
pub const DIFFUSE_RADIUS_SCALE: f32 = 0.5;
/// Format of the impostors' depth-test attachment.
pub const IMPOSTOR_DEPTH_FORMAT: TextureFormat = TextureFormat::Depth32Float;

/// A surface camera's settings in the render world.
#[derive(Component, Clone, Debug)]
pub struct ExtractedSphSurface(pub SphSurface);

/// The particles a surface is drawn from: the position buffer (the GPU backend's, or the CPU
/// backend's copy in the same layout), the live count and the drawn sphere radius.
#[derive(Resource, Clone, Debug, Default)]
pub struct SurfaceParticles {
    /// `array<vec4<f32>>` of positions, when the plugin has made its buffers.
    pub position: Option<Handle<ShaderBuffer>>,
    /// Live particles (slots `0..count`).
    pub count: u32,
    /// Particle spacing Δx [m] of the running parameters.
    pub spacing: f32,
    /// The diffuse particles' `array<vec4<f32>>` (xyz the position, w the class: 0 spray,
    /// 1 foam, 2 bubble, negative an empty slot), while whitewater is on.
    pub diffuse: Option<Handle<ShaderBuffer>>,
    /// The slots worth drawing (`SphDiffuseParticles::slots`).
    pub diffuse_count: u32,
    /// The container's corners [m], once the simulation has one.
    pub container: Option<(Vec3, Vec3)>,
}

/// A 3D camera's render-world entity, its surface status, and whether it has a surface.
type SurfaceCamera = (
    RenderEntity,
    Option<&'static SphSurfaceStatus>,
    Has<SphSurface>,
);

/// Copies every surface camera's applied settings, and the particle buffer, into the render
/// world; a camera that lost its `SphSurface` loses the extracted settings too.
pub(crate) fn extract_sph_surfaces(
    mut commands: Commands,
    cameras: Extract<Query<SurfaceCamera, With<Camera3d>>>,
    sim: Extract<Res<SphSimulation>>,
    buffers: Extract<Option<Res<SphGpuBuffers>>>,
    diffuse: Extract<Option<Res<SphDiffuseParticles>>>,
) {
    for (render_entity, status, has_surface) in &cameras {
        let Ok(mut entity) = commands.get_entity(render_entity) else {
            continue;
        };
        match status.filter(|_| has_surface) {
            Some(status) => entity.insert(ExtractedSphSurface(status.applied.clone())),
            None => entity.remove::<(
                ExtractedSphSurface,
                SurfaceViewResources,
                SurfaceCompositeVariant,
            )>(),
        };
    }
    commands.insert_resource(SurfaceParticles {
        position: buffers.as_ref().map(|b| b.position.clone()),
        count: sim.particle_count,
        spacing: sim.frame.params.spacing(),
        diffuse: diffuse.as_ref().and_then(|d| d.buffer.clone()),
        diffuse_count: diffuse.as_ref().map_or(0, |d| d.slots),
        container: sim.container.as_ref().map(|c| (c.min(), c.max())),
    });
}

/// The uniform block every surface shader reads (`surface_types.wgsl`).
#[derive(Clone, Copy, Debug, Default, ShaderType)]
pub struct GpuSurfaceUniform {
    /// Projection of the view.
    pub clip_from_view: Mat4,
    /// Its inverse.
    pub view_from_clip: Mat4,
    /// World to view space.
    pub view_from_world: Mat4,
    /// Absorption per metre (rgb), w unused.
    pub absorption: Vec4,
    /// Sky colour (linear rgb), w unused.
    pub sky_color: Vec4,
    /// Deep-water colour (linear rgb), w unused.
    pub deep_color: Vec4,
    /// Toward the sun in view space (xyz, unit), w = specular strength.
    pub sun_direction: Vec4,
    /// View to world space.
    pub world_from_view: Mat4,
    /// The container's lower corner [m] (xyz), w = 1 when a container is known.
    pub container_min: Vec4,
    /// The container's upper corner [m] (xyz), w = how near a wall the water touches it [m].
    pub container_max: Vec4,
    /// Size of the scaled depth and thickness targets [pixels].
    pub target_size: Vec2,
    /// Size of the view [pixels].
    pub view_size: Vec2,
    /// Top-left corner of the view in its render target [pixels] (a `Camera::viewport`).
    pub view_origin: Vec2,
    /// Live diffuse particles (whitewater; 0 without).
    pub diffuse_count: u32,
    /// Radius of each diffuse particle's billboard [m].
    pub diffuse_radius: f32,
    /// Live particles.
    pub particle_count: u32,
    /// Radius of each particle's sphere [m].
    pub sphere_radius: f32,
    /// Filter radius [m].
    pub filter_radius: f32,
    /// Largest filter radius [pixels of the scaled target].
    pub filter_max_pixels: f32,
    /// Depth range of the narrow-range filter [m].
    pub depth_range: f32,
    /// Refraction offset per metre of thickness (fraction of the view).
    pub refraction_strength: f32,
    /// 1 for an orthographic projection.
    pub orthographic: u32,
    /// Water volume per sphere volume (Δx³ / (4/3 π r³)): summed chords times this is the
    /// water's thickness.
    pub chord_weight: f32,
    /// `SphSurfaceDebugView` as a number (0 = the lit surface).
    pub debug_view: u32,
}

impl GpuSurfaceUniform {
    /// The block for a view of `view_size` pixels with this projection and camera pose, drawing
    /// `particle_count` particles of spacing `spacing` [m] with `settings`.
    pub fn new(
        settings: &SphSurface,
        clip_from_view: Mat4,
        world_from_view: Mat4,
        view_size: UVec2,
        particle_count: u32,
        spacing: f32,
    ) -> Self {
        Self::placed(
            settings,
            clip_from_view,
            world_from_view,
            UVec4::new(0, 0, view_size.x, view_size.y),
            particle_count,
            spacing,
        )
    }

    /// [`Self::new`] for a view at `viewport` (x, y, width, height) in its render target.
    pub fn placed(
        settings: &SphSurface,
        clip_from_view: Mat4,
        world_from_view: Mat4,
        viewport: UVec4,
        particle_count: u32,
        spacing: f32,
    ) -> Self {
        let view_size = viewport.zw();
        let view_size = view_size.max(UVec2::ONE);
        let size = (view_size.as_vec2() * settings.resolution_scale)
            .ceil()
            .as_uvec2()
            .max(UVec2::ONE);
        let view_from_world = world_from_view.inverse();
        let sun = view_from_world
            .transform_vector3(settings.sun_direction)
            .normalize_or(Vec3::Y);
        let sphere_radius = settings.sphere_scale * spacing;
        Self {
            clip_from_view,
            view_from_clip: clip_from_view.inverse(),
            view_from_world,
            absorption: settings.absorption.extend(0.0),
            sky_color: settings.sky_color.extend(0.0),
            deep_color: settings.deep_color.extend(0.0),
            sun_direction: sun.extend(settings.specular),
            world_from_view,
            container_min: Vec4::ZERO,
            container_max: Vec4::ZERO,
            target_size: size.as_vec2(),
            view_size: view_size.as_vec2(),
            view_origin: viewport.xy().as_vec2(),
            diffuse_count: 0,
            diffuse_radius: DIFFUSE_RADIUS_SCALE * spacing,
            particle_count,
            sphere_radius,
            filter_radius: settings.filter_radius,
            filter_max_pixels: settings.filter_max_pixels,
            // Surfaces nearer than two spheres belong together (Truong & Yuksel 2018's range).
            depth_range: 4.0 * sphere_radius,
            refraction_strength: settings.refraction_strength,
            orthographic: (clip_from_view.w_axis.w == 1.0) as u32,
            chord_weight: spacing.powi(3)
                / (4.0 / 3.0 * std::f32::consts::PI * sphere_radius.powi(3)).max(1e-30),
            debug_view: settings.debug_view as u32,
        }
    }

    /// The container whose walls the water touches, `(min, max)` [m]: where the surface lies
    /// within one and a half sphere radii of a wall, it is the water's face against the wall
    /// (seen through it), not a surface to the air, and the composite draws no sun highlight
    /// there. `None`: no container, highlights everywhere.
    pub fn touch_walls(&mut self, container: Option<(Vec3, Vec3)>) {
        let Some((min, max)) = container else {
            self.container_min = Vec4::ZERO;
            self.container_max = Vec4::ZERO;
            return;
        };
        self.container_min = min.extend(1.0);
        self.container_max = max.extend(1.5 * self.sphere_radius);
    }
}

/// A surface view's composite pipeline and the layout it was made with.
#[derive(Component)]
pub struct SurfaceCompositeVariant {
    /// The specialized pipeline.
    pub pipeline: bevy::render::render_resource::CachedRenderPipelineId,
    /// Whether the view's depth is multisampled.
    pub multisampled: bool,
    /// Whether it reads the whitewater target.
    pub whitewater: bool,
}

/// Every surface camera's uniform block this frame.
#[derive(Resource, Default)]
pub struct SurfaceUniforms(pub DynamicUniformBuffer<GpuSurfaceUniform>);

/// A surface camera's textures and uniform offset this frame.
#[derive(Component)]
pub struct SurfaceViewResources {
    /// Offset of its block in [`SurfaceUniforms`].
    pub uniform_offset: u32,
    /// Depth-test attachment of the impostor pass.
    pub impostor_depth: CachedTexture,
    /// Fluid depth: the impostors write `[0]`, the filter ping-pongs `[0]` -> `[1]` -> `[0]`.
    pub fluid_depth: [CachedTexture; 2],
    /// The smoothed depth's normals and coverage.
    pub normals: CachedTexture,
    /// Summed chord lengths through the particles' spheres [m].
    pub thickness: CachedTexture,
    /// The whitewater's billboards ([`WHITEWATER_FORMAT`]), while whitewater is on.
    pub whitewater: Option<CachedTexture>,
}

/// Writes each surface camera's uniform block and takes its textures from the cache.
pub(crate) fn prepare_sph_surface_views(
    mut commands: Commands,
    views: Query<(Entity, &ExtractedView, &ExtractedSphSurface)>,
    particles: Res<SurfaceParticles>,
    mut uniforms: ResMut<SurfaceUniforms>,
    mut cache: ResMut<TextureCache>,
    device: Res<RenderDevice>,
    queue: Res<RenderQueue>,
) {
    let count = views.iter().len();
    let Some(mut writer) = uniforms.0.get_writer(count, &device, &queue) else {
        return;
    };
    for (entity, view, surface) in &views {
        let settings = &surface.0;
        let mut block = GpuSurfaceUniform::placed(
            settings,
            view.clip_from_view,
            view.world_from_view.to_matrix(),
            view.viewport,
            particles.count,
            particles.spacing,
        );
        block.diffuse_count = particles.diffuse_count;
        block.touch_walls(particles.container);
        let size = block.target_size.as_uvec2();
        let uniform_offset = writer.write(&block);
        let mut texture = |label: &'static str, format: TextureFormat| {
            cache.get(
                &device,
                TextureDescriptor {
                    label: Some(label),
                    size: Extent3d {
                        width: size.x,
                        height: size.y,
                        depth_or_array_layers: 1,
                    },
                    mip_level_count: 1,
                    sample_count: 1,
                    dimension: TextureDimension::D2,
                    format,
                    usage: TextureUsages::RENDER_ATTACHMENT | TextureUsages::TEXTURE_BINDING,
                    view_formats: &[],
                },
            )
        };
        let resources = SurfaceViewResources {
            uniform_offset,
            impostor_depth: texture("sph_surface_impostor_depth", IMPOSTOR_DEPTH_FORMAT),
            fluid_depth: [
                texture("sph_surface_depth_a", FLUID_DEPTH_FORMAT),
                texture("sph_surface_depth_b", FLUID_DEPTH_FORMAT),
            ],
            normals: texture("sph_surface_normals", NORMAL_FORMAT),
            thickness: texture("sph_surface_thickness", THICKNESS_FORMAT),
            whitewater: particles
                .diffuse
                .is_some()
                .then(|| texture("sph_surface_whitewater", WHITEWATER_FORMAT)),
        };
        commands.entity(entity).insert(resources);
    }
}

/// The group 0 of a full-screen pass that reads one depth target: the uniform block (dynamic
/// offset) and the depth (the filter and the normals passes).
pub fn depth_reader_layout(
    label: &'static str,
) -> bevy::render::render_resource::BindGroupLayoutDescriptor {
    use bevy::render::render_resource::binding_types::{texture_2d, uniform_buffer};
    use bevy::render::render_resource::{
        BindGroupLayoutDescriptor, BindGroupLayoutEntries, ShaderStages, TextureSampleType,
    };
    BindGroupLayoutDescriptor::new(
        label,
        &BindGroupLayoutEntries::sequential(
            ShaderStages::FRAGMENT,
            (
                uniform_buffer::<GpuSurfaceUniform>(true),
                texture_2d(TextureSampleType::Float { filterable: false }),
            ),
        ),
    )
}
