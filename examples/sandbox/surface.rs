//! How the water is drawn: particles (sphere impostors coloured by density, the debug view) or
//! the plugin's screen-space surface (`SphSurface` on the camera), and the surface's live
//! settings in the runtime panel.

use crate::scene::ParticleMesh;
use crate::{AppState, SandboxSet};
use bevy::prelude::*;
use bevy_egui::egui::{self, Color32, SliderClamping};
use bevy_sph_fluid::prelude::*;

/// Particles or surface.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum RenderMode {
    /// Sphere impostors coloured by density, speed, pressure or neighbours (the debug view).
    Particles,
    /// The plugin's water surface.
    #[default]
    Surface,
}

/// One of the surface's passes shown raw (`--surface-view`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum SurfaceView {
    /// The lit water surface.
    #[default]
    Lit,
    /// The filtered fluid depth.
    Depth,
    /// The water's thickness.
    Thickness,
    /// The view-space normals.
    Normals,
    /// The whitewater by class: spray red, foam green, bubbles blue.
    Whitewater,
}

impl SurfaceView {
    /// The plugin's debug view.
    pub fn debug_view(self) -> SphSurfaceDebugView {
        match self {
            SurfaceView::Lit => SphSurfaceDebugView::None,
            SurfaceView::Depth => SphSurfaceDebugView::Depth,
            SurfaceView::Thickness => SphSurfaceDebugView::Thickness,
            SurfaceView::Normals => SphSurfaceDebugView::Normals,
            SurfaceView::Whitewater => SphSurfaceDebugView::Whitewater,
        }
    }
}

/// The chosen mode, `--hide-particles` (nothing drawn, to time the simulation alone) and the
/// surface's first view.
#[derive(Resource, Clone, Copy, Debug, Default)]
pub struct RenderView {
    /// Particles or surface.
    pub mode: RenderMode,
    /// Draw no water at all.
    pub hide_water: bool,
    /// What the surface shows when it is put on the camera.
    pub surface_view: SurfaceView,
}

/// Puts `SphSurface` on the camera in surface mode (keeping its settings while it stays), and
/// shows the particle mesh only in particle mode.
pub fn apply_render_mode(
    mut commands: Commands,
    view: Res<RenderView>,
    cameras: Query<(Entity, Has<SphSurface>), With<Camera3d>>,
    mut particles: Query<&mut Visibility, With<ParticleMesh>>,
) {
    let surface = view.mode == RenderMode::Surface && !view.hide_water;
    for (camera, has) in &cameras {
        if surface && !has {
            commands.entity(camera).insert(SphSurface {
                debug_view: view.surface_view.debug_view(),
                ..default()
            });
        } else if !surface && has {
            commands.entity(camera).remove::<SphSurface>();
        }
    }
    let wanted = if view.mode == RenderMode::Particles && !view.hide_water {
        Visibility::Inherited
    } else {
        Visibility::Hidden
    };
    for mut visibility in &mut particles {
        if *visibility != wanted {
            *visibility = wanted;
        }
    }
}

fn f32_slider<'a>(
    value: &'a mut f32,
    range: std::ops::RangeInclusive<f32>,
    text: &str,
) -> egui::Slider<'a> {
    egui::Slider::new(value, range)
        .text(text)
        .clamping(SliderClamping::Always)
}

/// The render mode choice and, in surface mode, the surface's settings and GPU times.
pub fn surface_controls(
    ui: &mut egui::Ui,
    view: &mut RenderView,
    surfaces: &mut Query<(&mut SphSurface, Option<&SphSurfaceStatus>)>,
    stats: &SphStats,
) {
    ui.horizontal(|ui| {
        ui.label("draw");
        ui.radio_value(&mut view.mode, RenderMode::Particles, "particles");
        ui.radio_value(&mut view.mode, RenderMode::Surface, "surface");
    });
    let Some((mut surface, status)) = surfaces.iter_mut().next() else {
        return;
    };
    let mut s = surface.clone();
    surface_settings(ui, &mut s);
    if s != *surface {
        *surface = s;
    }
    if let Some(error) = status.and_then(|s| s.error.as_ref()) {
        ui.colored_label(Color32::RED, error);
    }
    let times: Vec<String> = stats
        .surface_ms
        .iter()
        .map(|(name, ms)| format!("{} {ms:.2}", name.trim_start_matches("sph_surface_")))
        .collect();
    if !times.is_empty() {
        ui.label(format!("surface GPU ms: {}", times.join(", ")));
    }
}

/// The surface's settings, edited on a copy (`s`) that replaces the component when it changed.
fn surface_settings(ui: &mut egui::Ui, s: &mut SphSurface) {
    ui.add(f32_slider(
        &mut s.resolution_scale,
        0.1..=1.0,
        "surface resolution scale",
    ));
    ui.add(f32_slider(
        &mut s.sphere_scale,
        0.25..=4.0,
        "sphere radius [spacings]",
    ));
    ui.add(f32_slider(
        &mut s.filter_radius,
        0.0..=0.2,
        "filter radius [m]",
    ));
    ui.add(
        egui::Slider::new(&mut s.filter_iterations, 0..=16)
            .text("filter iterations")
            .clamping(SliderClamping::Always),
    );
    ui.add(f32_slider(
        &mut s.refraction_strength,
        0.0..=1.0,
        "refraction strength",
    ));
    ui.horizontal(|ui| {
        ui.label("absorption r g b [1/m]");
        for k in 0..3 {
            ui.add(
                egui::DragValue::new(&mut s.absorption[k])
                    .range(0.0..=50.0)
                    .speed(0.05),
            );
        }
    });
    ui.horizontal(|ui| {
        ui.label("sky colour");
        let mut rgb = s.sky_color.to_array();
        ui.color_edit_button_rgb(&mut rgb);
        s.sky_color = Vec3::from_array(rgb);
        ui.label("deep-water colour");
        let mut rgb = s.deep_color.to_array();
        ui.color_edit_button_rgb(&mut rgb);
        s.deep_color = Vec3::from_array(rgb);
    });
    // Wrapped, so the fifth view does not widen the panel over the scene.
    ui.horizontal_wrapped(|ui| {
        ui.label("show");
        for (view, label) in [
            (SphSurfaceDebugView::None, "surface"),
            (SphSurfaceDebugView::Depth, "depth"),
            (SphSurfaceDebugView::Thickness, "thickness"),
            (SphSurfaceDebugView::Normals, "normals"),
            (SphSurfaceDebugView::Whitewater, "whitewater"),
        ] {
            ui.radio_value(&mut s.debug_view, view, label);
        }
    });
}

/// Particles or surface, as [`RenderView`] says (inserted by `main` from the command line).
pub struct RenderModePlugin;

impl Plugin for RenderModePlugin {
    fn build(&self, app: &mut App) {
        app.add_systems(
            Update,
            apply_render_mode
                .in_set(SandboxSet::Scene)
                .run_if(in_state(AppState::Running)),
        );
    }
}
