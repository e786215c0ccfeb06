//! The surface's settings: [`SphSurface`] on a camera (main world), validated into
//! [`SphSurfaceStatus`]; only validated settings reach the render world.

use bevy::camera::Camera3dDepthTextureUsage;
use bevy::prelude::*;
use bevy::render::render_resource::TextureUsages;

/// Draws the SPH water seen by this camera as a smooth, lit surface (screen-space fluid
/// rendering after van der Laan, Green & Sainz 2009, with the narrow-range depth filter of
/// Truong & Yuksel 2018) instead of nothing. The plugin reads the particle buffers straight on
/// the GPU: no readback, on either backend.
///
/// Edit it at any time: a change is validated by [`SphSurfaceStatus`] and a refused value
/// (field, value, allowed range) leaves the previous settings drawing.
///
/// ```no_run
/// # use bevy::prelude::*;
/// # use bevy_sph_fluid::prelude::*;
/// fn camera(mut commands: Commands) {
///     commands.spawn((Camera3d::default(), SphSurface::default()));
/// }
/// ```
#[derive(Component, Clone, Debug, PartialEq, Reflect)]
#[reflect(Component, Default, Clone)]
pub struct SphSurface {
    /// The surface's depth and thickness are drawn at this fraction of the view's size,
    /// in (0, 1].
    pub resolution_scale: f32,
    /// Radius of the sphere drawn per particle, in particle spacings (0.25 ..= 4).
    pub sphere_scale: f32,
    /// Radius of the depth-smoothing filter [m], >= 0 (0 = no smoothing).
    pub filter_radius: f32,
    /// Separable filter passes (horizontal then vertical), 0 ..= 16.
    pub filter_iterations: u32,
    /// Largest filter radius on screen [pixels of the scaled target], 1 ..= 64: near the camera
    /// the world radius would cover hundreds of pixels.
    pub filter_max_pixels: f32,
    /// Beer-Lambert absorption per metre of water for red, green and blue (each 0 ..= 1000):
    /// light through `t` metres keeps `exp(-absorption t)`.
    pub absorption: Vec3,
    /// Colour reflected by the surface (the sky), linear RGB, each 0 ..= 100.
    pub sky_color: Vec3,
    /// Colour of deep water, linear RGB, each 0 ..= 100: light through `t` metres is
    /// `scene exp(-absorption t) + deep_color (1 - exp(-absorption t))`.
    pub deep_color: Vec3,
    /// Screen-space offset of the refracted scene, as a fraction of the view per metre of
    /// thickness along the normal, 0 ..= 1.
    pub refraction_strength: f32,
    /// Direction toward the sun in world space (not zero), for the specular highlight.
    pub sun_direction: Vec3,
    /// Strength of the specular highlight, 0 ..= 100.
    pub specular: f32,
    /// Draw one pass's output instead of the lit surface (for tuning, and the parity tests).
    pub debug_view: SphSurfaceDebugView,
}

/// What a surface camera draws: the lit surface, or one of its passes' outputs, raw (best seen
/// on an HDR camera without tonemapping).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Reflect)]
#[reflect(Default, Clone)]
#[repr(u32)]
pub enum SphSurfaceDebugView {
    /// The lit water surface.
    #[default]
    None = 0,
    /// The filtered fluid depth: distance along the view axis [m] in r, g and b; 0 without water.
    Depth = 1,
    /// The water's thickness [m] in r, g and b.
    Thickness = 2,
    /// The view-space normal n as 0.5 + 0.5 n in r, g and b; 0 without water.
    Normals = 3,
    /// The whitewater's billboards by class, 1 - e^(-amount): spray in r, foam in g, bubbles
    /// in b; black without whitewater.
    Whitewater = 4,
}

impl Default for SphSurface {
    fn default() -> Self {
        Self {
            resolution_scale: 0.5,
            sphere_scale: 1.0,
            filter_radius: 0.04,
            filter_iterations: 2,
            filter_max_pixels: 24.0,
            absorption: Vec3::new(20.0, 6.0, 3.0),
            sky_color: Vec3::new(0.55, 0.7, 0.9),
            deep_color: Vec3::new(0.01, 0.09, 0.16),
            refraction_strength: 0.15,
            sun_direction: Vec3::new(1.0, 3.0, 2.0),
            specular: 2.0,
            debug_view: SphSurfaceDebugView::None,
        }
    }
}

/// A refused [`SphSurface`] value: which field, the value, what is allowed.
#[derive(Clone, Debug, PartialEq)]
pub struct SphSurfaceError {
    /// The field, such as `resolution_scale`.
    pub field: &'static str,
    /// The value given, formatted.
    pub value: String,
    /// What the field allows.
    pub allowed: &'static str,
}

impl std::fmt::Display for SphSurfaceError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "SphSurface.{} = {}: allowed {}",
            self.field, self.value, self.allowed
        )
    }
}

impl std::error::Error for SphSurfaceError {}

impl SphSurface {
    /// Checks every field; the first refused one is returned.
    pub fn validate(&self) -> Result<(), SphSurfaceError> {
        let scalar = |field, value: f32, ok: bool, allowed| {
            if value.is_finite() && ok {
                Ok(())
            } else {
                Err(SphSurfaceError {
                    field,
                    value: format!("{value}"),
                    allowed,
                })
            }
        };
        let vector = |field, value: Vec3, ok: bool, allowed| {
            if value.is_finite() && ok {
                Ok(())
            } else {
                Err(SphSurfaceError {
                    field,
                    value: format!("{value:?}"),
                    allowed,
                })
            }
        };
        let s = self;
        scalar(
            "resolution_scale",
            s.resolution_scale,
            s.resolution_scale > 0.0 && s.resolution_scale <= 1.0,
            "0 < scale <= 1",
        )?;
        scalar(
            "sphere_scale",
            s.sphere_scale,
            (0.25..=4.0).contains(&s.sphere_scale),
            "0.25 ..= 4 particle spacings",
        )?;
        scalar(
            "filter_radius",
            s.filter_radius,
            s.filter_radius >= 0.0,
            "a radius >= 0 m",
        )?;
        if s.filter_iterations > 16 {
            return Err(SphSurfaceError {
                field: "filter_iterations",
                value: s.filter_iterations.to_string(),
                allowed: "0 ..= 16",
            });
        }
        scalar(
            "filter_max_pixels",
            s.filter_max_pixels,
            (1.0..=64.0).contains(&s.filter_max_pixels),
            "1 ..= 64 pixels",
        )?;
        vector(
            "absorption",
            s.absorption,
            s.absorption.min_element() >= 0.0 && s.absorption.max_element() <= 1000.0,
            "each component 0 ..= 1000 per metre",
        )?;
        vector(
            "sky_color",
            s.sky_color,
            s.sky_color.min_element() >= 0.0 && s.sky_color.max_element() <= 100.0,
            "each component 0 ..= 100 (linear RGB)",
        )?;
        vector(
            "deep_color",
            s.deep_color,
            s.deep_color.min_element() >= 0.0 && s.deep_color.max_element() <= 100.0,
            "each component 0 ..= 100 (linear RGB)",
        )?;
        scalar(
            "refraction_strength",
            s.refraction_strength,
            (0.0..=1.0).contains(&s.refraction_strength),
            "0 ..= 1",
        )?;
        vector(
            "sun_direction",
            s.sun_direction,
            s.sun_direction.try_normalize().is_some(),
            "a direction that normalizes (not zero, not overflowing)",
        )?;
        scalar(
            "specular",
            s.specular,
            (0.0..=100.0).contains(&s.specular),
            "0 ..= 100",
        )
    }
}

/// The settings a surface camera draws with, kept next to its [`SphSurface`] by the plugin: the
/// last valid settings, and why the latest edit was refused (if it was).
#[derive(Component, Clone, Debug, Default, PartialEq, Reflect)]
#[reflect(Component, Default, Clone)]
pub struct SphSurfaceStatus {
    /// The settings drawn: the last edit that passed [`SphSurface::validate`].
    pub applied: SphSurface,
    /// Why the latest edit was refused; `None` once a valid edit is applied.
    pub error: Option<String>,
}

/// Validates new and edited [`SphSurface`] settings: a valid edit is applied, a refused one is
/// named in [`SphSurfaceStatus::error`] (and logged) while the previous settings stay.
pub(crate) fn sph_validate_surfaces(
    mut commands: Commands,
    mut cameras: Query<(Entity, &SphSurface, Option<&mut SphSurfaceStatus>), Changed<SphSurface>>,
) {
    for (entity, surface, status) in &mut cameras {
        let result = surface.validate();
        match (status, result) {
            (Some(mut status), Ok(())) => {
                status.applied = surface.clone();
                status.error = None;
            }
            (Some(mut status), Err(e)) => {
                warn!("{e}; the previous surface settings stay");
                status.error = Some(e.to_string());
            }
            (None, Ok(())) => {
                commands.entity(entity).insert(SphSurfaceStatus {
                    applied: surface.clone(),
                    error: None,
                });
            }
            (None, Err(e)) => {
                warn!("{e}; the surface draws with the default settings");
                commands.entity(entity).insert(SphSurfaceStatus {
                    applied: SphSurface::default(),
                    error: Some(e.to_string()),
                });
            }
        }
    }
}

/// A surface camera just given its `SphSurface`, or whose `Camera3d` changed.
type NewOrChangedSurfaceCamera = (With<SphSurface>, Or<(Added<SphSurface>, Changed<Camera3d>)>);

/// The composite reads the camera's depth texture to hide water behind opaque geometry: a
/// surface camera's depth texture is made bindable.
pub(crate) fn sph_surface_depth_usage(
    mut cameras: Query<&mut Camera3d, NewOrChangedSurfaceCamera>,
) {
    for mut camera in &mut cameras {
        let usage = TextureUsages::from(camera.depth_texture_usages);
        if !usage.contains(TextureUsages::TEXTURE_BINDING) {
            camera.depth_texture_usages =
                Camera3dDepthTextureUsage::from(usage | TextureUsages::TEXTURE_BINDING);
        }
    }
}

/// Removes the status of a camera whose [`SphSurface`] was removed (and not added back).
pub(crate) fn sph_forget_surfaces(
    mut commands: Commands,
    mut removed: RemovedComponents<SphSurface>,
    still: Query<(), With<SphSurface>>,
) {
    for entity in removed.read() {
        if still.contains(entity) {
            continue;
        }
        if let Ok(mut e) = commands.get_entity(entity) {
            e.remove::<SphSurfaceStatus>();
        }
    }
}
