//! The start panel and the runtime panel (bevy_egui). Sliders clamp to their ranges, so bad
//! values cannot be entered; the plugin's validation errors are shown in red.

use crate::config::{Preset, SandboxConfig, SpawnMode, BUDGET_RANGE};
use crate::ranges;
use crate::scene_file::{SceneFileKind, SceneFiles};
use crate::{AppState, SandboxSet};
use bevy::diagnostic::{DiagnosticsStore, FrameTimeDiagnosticsPlugin};
use bevy::prelude::*;
use bevy_egui::egui::{self, Color32, SliderClamping};
use bevy_egui::EguiContexts;
use bevy_sph_fluid::prelude::*;
use sph_core::{Integrator, NeighborSearch};
use std::collections::VecDeque;

/// Debug drawing on/off.
#[derive(Resource, Default)]
pub struct DebugView(pub bool);

/// The last seconds of FPS and density error, for the live plot.
#[derive(Resource, Default)]
pub struct History {
    samples: VecDeque<(f32, f32)>,
    last_steps: (f64, u64),
    steps_per_second: f32,
}

const HISTORY_LEN: usize = 240;

impl History {
    /// The last frame's FPS (0 before the first).
    pub fn fps(&self) -> f32 {
        self.samples.back().map_or(0.0, |s| s.0)
    }

    /// Steps per wall-clock second over the last second.
    pub fn steps_per_second(&self) -> f32 {
        self.steps_per_second
    }
}

pub(crate) fn slider<'a>(
    value: &'a mut f32,
    range: std::ops::RangeInclusive<f32>,
    label: &str,
) -> egui::Slider<'a> {
    egui::Slider::new(value, range)
        .text(label)
        .clamping(SliderClamping::Always)
}

pub(crate) fn integrator_combo(ui: &mut egui::Ui, id: &str, integrator: &mut Integrator) {
    egui::ComboBox::from_label("integrator")
        .selected_text(format!("{integrator:?}"))
        .show_ui(ui, |ui| {
            ui.push_id(id, |ui| {
                for choice in [
                    Integrator::KickDriftKick,
                    Integrator::Leapfrog,
                    Integrator::SymplecticEuler,
                ] {
                    ui.selectable_value(integrator, choice, format!("{choice:?}"));
                }
            });
        });
}

/// The viscosity as the artificial viscosity α of ν = α h c0 / 10 (what the presets derive it
/// from), with ν and μ = ρ0 ν in the tooltip. μ is written only when the slider is moved, so an α
/// outside the range (after a stiffness or rest density change) is shown clamped but kept.
pub(crate) fn viscosity_alpha_slider(ui: &mut egui::Ui, p: &mut sph_core::SphParams) {
    let mut alpha = p.artificial_viscosity_alpha();
    let tooltip = format!(
        "Artificial viscosity α (dimensionless, now {alpha:.3}): the kinematic viscosity is \
         ν = α h c0 / 10 = {:.3e} m²/s (h = {:.3} m, speed of sound c0 = {:.1} m/s), \
         applied as the dynamic viscosity μ = ρ0 ν = {:.3e} Pa s. Water's own ν is 1e-6 m²/s; \
         this is numerical damping.",
        p.kinematic_viscosity(),
        p.smoothing_radius,
        p.speed_of_sound(),
        p.viscosity,
    );
    let response = ui
        .add(slider(&mut alpha, ranges::VISCOSITY_ALPHA, "viscosity α").logarithmic(true))
        .on_hover_text(tooltip);
    if response.changed() {
        p.set_artificial_viscosity_alpha(alpha);
    }
}

/// The start screen.
pub fn setup_panel(
    mut contexts: EguiContexts,
    mut config: ResMut<SandboxConfig>,
    mut next: ResMut<NextState<AppState>>,
    files: Res<SceneFiles>,
    stats: Res<SphStats>,
) -> Result {
    egui::Window::new("Aquaplay SPH sandbox")
        .anchor(egui::Align2::CENTER_CENTER, [0.0, 0.0])
        .resizable(false)
        .show(contexts.ctx_mut()?, |ui| {
            ui.label("Choose the scene, then Start.");
            if scene_file_choice(ui, &mut config, &files, &stats, &mut next) {
                return;
            }
            ui.add(
                egui::Slider::new(&mut config.budget, BUDGET_RANGE)
                    .text("particle budget")
                    .logarithmic(true)
                    .clamping(SliderClamping::Always),
            );
            built_in_scene_choices(ui, &mut config);
            if let Err(e) = config.params().validate() {
                ui.colored_label(Color32::RED, e.to_string());
            } else if ui.button("Start").clicked() {
                next.set(AppState::Running);
            }
        });
    Ok(())
}

/// The built-in scene's choices: spawn mode, preset, solver, stepping, search and obstacles.
fn built_in_scene_choices(ui: &mut egui::Ui, config: &mut SandboxConfig) {
    ui.horizontal(|ui| {
        ui.label("spawn");
        for (mode, label) in [
            (SpawnMode::Block, "block"),
            (SpawnMode::Pipe, "pipe jet"),
            (SpawnMode::Both, "both"),
        ] {
            ui.radio_value(&mut config.spawn, mode, label);
        }
    });
    ui.horizontal(|ui| {
        ui.label("preset");
        let before = config.preset;
        ui.radio_value(&mut config.preset, Preset::Water, "SI water");
        ui.radio_value(&mut config.preset, Preset::Design, "design (seed)");
        if config.preset != before {
            config.apply_preset_defaults();
        }
    });
    ui.horizontal(|ui| {
        ui.label("pressure solver");
        ui.radio_value(&mut config.solver, sph_core::Solver::Wcsph, "WCSPH");
        ui.radio_value(&mut config.solver, sph_core::Solver::Dfsph, "DFSPH")
            .on_hover_text(
                "Divergence-free SPH (Bender & Koschier 2017), its own time step, \
                 on either backend (on a software GPU such as lavapipe the CPU \
                 backend, --cpu, is the faster one)",
            );
        ui.radio_value(&mut config.solver, sph_core::Solver::Pbf, "PBF")
            .on_hover_text(
                "Position-based fluids (Macklin & Müller 2013), its own time step, \
                 on either backend",
            );
    });
    let mut integrator = config.integrator;
    integrator_combo(ui, "setup", &mut integrator);
    config.integrator = integrator;
    ui.add(slider(&mut config.time_step, ranges::TIME_STEP, "time step [s]").logarithmic(true));
    ui.checkbox(&mut config.adaptive_time_step, "adaptive dt (CFL)");
    ui.checkbox(
        &mut config.real_time,
        "real time: each frame advances the water by the frame's own time",
    );
    ui.horizontal(|ui| {
        ui.label("neighbour search");
        ui.radio_value(
            &mut config.search,
            NeighborSearch::Grid,
            "grid + counting sort",
        );
        ui.radio_value(
            &mut config.search,
            NeighborSearch::Hash,
            "spatial hash + bitonic",
        );
    });
    ui.checkbox(&mut config.surface_tension, "surface tension (Akinci 2013)");
    ui.horizontal(|ui| {
        ui.label("obstacles");
        ui.checkbox(&mut config.sphere_obstacle, "ball");
        ui.checkbox(&mut config.box_obstacle, "box");
        ui.checkbox(&mut config.gate, "gate");
    });
}

/// The scene-file choice at the top of the start panel. With a file chosen, the file sets the
/// parameters: the panel shows Start (or why the backend cannot run it) and returns true.
fn scene_file_choice(
    ui: &mut egui::Ui,
    config: &mut SandboxConfig,
    files: &SceneFiles,
    stats: &SphStats,
    next: &mut NextState<AppState>,
) -> bool {
    egui::ComboBox::from_label("scene file")
        .selected_text(config.scene.as_deref().unwrap_or("(this panel's scene)"))
        .show_ui(ui, |ui| {
            ui.selectable_value(&mut config.scene, None, "(this panel's scene)");
            for (name, kind) in &files.0 {
                let label = match kind {
                    Ok(kind) => format!("{name} ({})", kind.solver.name()),
                    Err(_) => format!("{name} (does not load)"),
                };
                ui.selectable_value(&mut config.scene, Some(name.clone()), label);
            }
        });
    let Some(chosen) = config.scene.clone() else {
        return false;
    };
    match files
        .0
        .iter()
        .find(|(name, _)| *name == chosen)
        .map(|f| &f.1)
    {
        Some(Ok(SceneFileKind {
            cpu_only: Some(what),
            ..
        })) if stats.backend == SphBackend::Gpu => {
            ui.colored_label(
                Color32::ORANGE,
                format!(
                    "{what} runs on the CPU backend only for now: restart the sandbox with --scene {chosen}"
                ),
            );
        }
        Some(Err(e)) => {
            ui.colored_label(Color32::RED, e);
        }
        _ => {
            ui.label("The file sets the parameters, the container, the colliders and the water.");
            if ui.button("Start").clicked() {
                next.set(AppState::Running);
            }
        }
    }
    true
}

/// Samples FPS and density error for the plot, and steps per second.
pub fn record_history(
    time: Res<Time>,
    stats: Res<SphStats>,
    diagnostics: Res<DiagnosticsStore>,
    mut history: ResMut<History>,
) {
    let fps = diagnostics
        .get(&FrameTimeDiagnosticsPlugin::FPS)
        .and_then(|d| d.smoothed())
        .unwrap_or(0.0) as f32;
    let error = stats
        .diagnostics
        .map(|d| d.density_error_mean_pct)
        .unwrap_or(0.0);
    history.samples.push_back((fps, error));
    while history.samples.len() > HISTORY_LEN {
        history.samples.pop_front();
    }
    let now = time.elapsed_secs_f64();
    let (then, steps) = history.last_steps;
    if now - then >= 1.0 {
        history.steps_per_second =
            (stats.step_count.saturating_sub(steps)) as f32 / (now - then) as f32;
        history.last_steps = (now, stats.step_count);
    }
}

pub(crate) fn plot(ui: &mut egui::Ui, history: &History) {
    let (rect, _) = ui.allocate_exact_size(egui::vec2(260.0, 70.0), egui::Sense::hover());
    let painter = ui.painter_at(rect);
    painter.rect_filled(rect, 2.0, Color32::from_gray(25));
    let n = history.samples.len().max(2) as f32;
    let max_fps = history.samples.iter().map(|s| s.0).fold(1.0, f32::max);
    let max_err = history.samples.iter().map(|s| s.1).fold(0.5, f32::max);
    let line = |value: &dyn Fn(&(f32, f32)) -> f32, color: Color32| {
        let points: Vec<egui::Pos2> = history
            .samples
            .iter()
            .enumerate()
            .map(|(k, s)| {
                egui::pos2(
                    rect.left() + rect.width() * k as f32 / (n - 1.0),
                    rect.bottom() - rect.height() * value(s).clamp(0.0, 1.0),
                )
            })
            .collect();
        painter.add(egui::Shape::line(points, egui::Stroke::new(1.5, color)));
    };
    line(&|s| s.0 / max_fps, Color32::LIGHT_GREEN);
    line(&|s| s.1 / max_err, Color32::LIGHT_BLUE);
    ui.label(format!(
        "green: FPS (max {max_fps:.0}), blue: density error (max {max_err:.2} %)"
    ));
}

/// The start panel and the runtime panel, with the frame-rate history the runtime panel plots.
pub struct PanelsPlugin;

impl Plugin for PanelsPlugin {
    fn build(&self, app: &mut App) {
        app.init_resource::<DebugView>()
            .init_resource::<History>()
            .add_systems(
                Update,
                record_history
                    .in_set(SandboxSet::Read)
                    .run_if(in_state(AppState::Running)),
            )
            .add_systems(
                bevy_egui::EguiPrimaryContextPass,
                (
                    setup_panel.run_if(in_state(AppState::Setup)),
                    crate::runtime_panel::runtime_panel.run_if(in_state(AppState::Running)),
                ),
            );
    }
}
