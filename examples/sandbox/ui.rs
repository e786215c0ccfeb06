//! The start panel and the runtime panel (bevy_egui). Sliders clamp to their ranges, so bad
//! values cannot be entered; the plugin's validation errors are shown in red.

use crate::config::{Preset, SandboxConfig, SpawnMode, BUDGET_RANGE};
use crate::obstacles::{Gate, GateLift};
use crate::particles::{ColorMode, ParticleDrawing};
use crate::ranges;
use crate::scene_file::{SceneFileKind, SceneFiles};
use crate::surface::{surface_controls, RenderMode, RenderView};
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

fn slider<'a>(
    value: &'a mut f32,
    range: std::ops::RangeInclusive<f32>,
    label: &str,
) -> egui::Slider<'a> {
    egui::Slider::new(value, range)
        .text(label)
        .clamping(SliderClamping::Always)
}

fn integrator_combo(ui: &mut egui::Ui, id: &str, integrator: &mut Integrator) {
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
fn viscosity_alpha_slider(ui: &mut egui::Ui, p: &mut sph_core::SphParams) {
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
            ui.add(
                slider(&mut config.time_step, ranges::TIME_STEP, "time step [s]").logarithmic(true),
            );
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
            if let Err(e) = config.params().validate() {
                ui.colored_label(Color32::RED, e.to_string());
            } else if ui.button("Start").clicked() {
                next.set(AppState::Running);
            }
        });
    Ok(())
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

fn plot(ui: &mut egui::Ui, history: &History) {
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

/// The runtime panel: parameters, controls, statistics and the live plot.
#[allow(clippy::too_many_arguments)]
pub fn runtime_panel(
    mut contexts: EguiContexts,
    mut params: ResMut<SphParams>,
    mut control: ResMut<SphControl>,
    stats: Res<SphStats>,
    history: Res<History>,
    mut debug: ResMut<DebugView>,
    drawing: Option<ResMut<ParticleDrawing>>,
    mut next: ResMut<NextState<AppState>>,
    gate: Option<ResMut<GateLift>>,
    gates: Query<(), With<Gate>>,
    mut render: ResMut<RenderView>,
    mut surfaces: Query<(&mut SphSurface, Option<&SphSurfaceStatus>)>,
) -> Result {
    egui::Window::new("Simulation")
        .anchor(egui::Align2::LEFT_TOP, [8.0, 8.0])
        .default_width(300.0)
        .show(contexts.ctx_mut()?, |ui| {
            if let (Some(mut gate), false) = (gate, gates.is_empty()) {
                let label = if gate.lifting {
                    "stop the gate"
                } else {
                    "lift the gate"
                };
                if ui.button(label).clicked() {
                    gate.lifting = !gate.lifting;
                }
            }
            let mut p = params.0;
            viscosity_alpha_slider(ui, &mut p);
            ui.add(slider(&mut p.stiffness, ranges::STIFFNESS, "stiffness k").logarithmic(true));
            let mut rest_density = p.rest_density;
            ui.add(
                slider(&mut rest_density, ranges::REST_DENSITY, "rest density [kg/m³]")
                    .logarithmic(true),
            );
            if rest_density != p.rest_density {
                ranges::set_rest_density(&mut p, rest_density);
            }
            ui.add(slider(
                &mut p.surface_tension,
                ranges::SURFACE_TENSION,
                "surface tension γ",
            ));
            ui.add(slider(&mut p.wall_damping, ranges::WALL_DAMPING, "wall damping"));
            if p.solver == sph_core::Solver::Pbf {
                ui.add(
                    egui::Slider::new(&mut p.pbf.iterations, 1..=20)
                        .text("PBF iterations / step")
                        .clamping(SliderClamping::Always),
                );
                ui.add(slider(
                    &mut p.pbf.vorticity_epsilon,
                    0.0..=1.0,
                    "PBF vorticity confinement ε [m/s]",
                ));
                ui.add(slider(
                    &mut p.pbf.over_relaxation,
                    1.0..=1.9,
                    "PBF over-relaxation ω",
                ));
            }
            ui.add(slider(&mut p.gravity.y, ranges::GRAVITY_Y, "gravity y [m/s²]"));
            let dt_label = if p.adaptive_time_step {
                "largest dt [s]"
            } else {
                "dt [s]"
            };
            ui.add(slider(&mut p.time_step, ranges::TIME_STEP, dt_label).logarithmic(true));
            ui.checkbox(&mut p.adaptive_time_step, "adaptive dt (CFL)");
            if p.adaptive_time_step {
                ui.add(slider(&mut p.cfl_factor, ranges::CFL_FACTOR, "CFL factor λ"));
            }
            integrator_combo(ui, "runtime", &mut p.integrator);
            if p != params.0 {
                params.0 = p;
            }
            ui.checkbox(
                &mut control.rollback.enabled,
                "roll back unstable steps (retry at half the dt)",
            );
            let mut real_time = control.real_time.is_some();
            ui.checkbox(
                &mut real_time,
                "real time: each frame advances the water by the frame's own time",
            );
            match (real_time, control.real_time) {
                (true, None) => control.real_time = Some(SphRealTime::default()),
                (false, Some(_)) => control.real_time = None,
                _ => {}
            }
            if let Some(limits) = control.real_time.as_mut() {
                ui.add(
                    egui::Slider::new(&mut limits.max_frame_time, 0.005..=0.2)
                        .text("largest frame time [s]")
                        .logarithmic(true)
                        .clamping(SliderClamping::Always),
                );
                ui.add(
                    egui::Slider::new(&mut limits.max_steps, 1..=MAX_SUBSTEPS)
                        .text("most steps / frame")
                        .clamping(SliderClamping::Always),
                );
            } else {
                ui.add(
                    egui::Slider::new(&mut control.substeps, 1..=16)
                        .text("substeps / frame")
                        .clamping(SliderClamping::Always),
                );
            }
            let mut limited = control.max_body_frame_time.is_some();
            ui.checkbox(
                &mut limited,
                "GPU, bodies afloat: limit the water time a frame covers (their force arrives a \
                 frame or two late)",
            );
            match (limited, control.max_body_frame_time) {
                (true, None) => control.max_body_frame_time = Some(DEFAULT_MAX_BODY_FRAME_TIME),
                (false, Some(_)) => control.max_body_frame_time = None,
                _ => {}
            }
            if let Some(most) = control.max_body_frame_time.as_mut() {
                ui.add(
                    egui::Slider::new(most, 0.001..=0.05)
                        .text("most water time / frame with bodies [s]")
                        .logarithmic(true)
                        .clamping(SliderClamping::Always),
                );
            }
            ui.horizontal(|ui| {
                let label = if control.running { "Pause" } else { "Run" };
                if ui.button(label).clicked() {
                    control.running = !control.running;
                }
                if ui.button("Step").clicked() {
                    control.single_step = true;
                }
                if ui.button("Reset").clicked() {
                    control.reset = true;
                }
                if ui.button("Setup").clicked() {
                    next.set(AppState::Setup);
                }
            });
            surface_controls(ui, &mut render, &mut surfaces, &stats);
            let mut drawing_mode = drawing;
            let particle_mode = render.mode == RenderMode::Particles;
            if let Some(drawing) = drawing_mode.as_deref_mut().filter(|_| particle_mode) {
                ui.horizontal(|ui| {
                    ui.label("colour");
                    for (mode, label) in [
                        (ColorMode::Density, "density"),
                        (ColorMode::Speed, "speed"),
                        (ColorMode::Pressure, "pressure"),
                        (ColorMode::Neighbors, "neighbours"),
                    ] {
                        ui.radio_value(&mut drawing.color_mode, mode, label);
                    }
                });
            }
            let was = debug.0;
            ui.checkbox(
                &mut debug.0,
                "debug view (grid cells, neighbour counts, velocity arrows)",
            );
            if let Some(drawing) = drawing_mode.as_deref_mut() {
                if debug.0 && !was {
                    // The debug colours are the particles'.
                    render.mode = RenderMode::Particles;
                    drawing.color_mode = ColorMode::Neighbors;
                } else if !debug.0 && was {
                    drawing.color_mode = ColorMode::Density;
                }
            }
            ui.separator();
            let fps = history.samples.back().map(|s| s.0).unwrap_or(0.0);
            ui.label(format!(
                "{:?} on {} · FPS {fps:.1} · {:.0} steps/s",
                stats.backend, stats.adapter, history.steps_per_second
            ));
            ui.label(format!(
                "real-time factor {:.3} (simulated s per wall-clock s) · {} steps / frame · mean compression {:.3} %",
                stats.real_time_factor, stats.frame_steps, stats.density_error_mean_pct
            ));
            ui.label(format!(
                "particles {} / {} (refused {}) · t = {:.3} s · step {} · dt {:.2e} s · rollbacks {}",
                stats.particle_count,
                stats.capacity,
                stats.refused_spawns,
                stats.sim_time,
                stats.step_count,
                stats.time_step,
                stats.rollbacks
            ));
            if stats.particles_emitted > 0 || stats.particles_drained > 0 {
                ui.label(format!(
                    "balance: {} initial + {} emitted − {} drained − {} live = {}",
                    stats.particles_initial,
                    stats.particles_emitted,
                    stats.particles_drained,
                    stats.particle_count,
                    stats.particle_balance()
                ));
            }
            if let Some(flow) = &stats.flow_error {
                ui.colored_label(Color32::ORANGE, flow);
            }
            if stats.pressure_iterations_mean > 0.0 {
                ui.label(format!(
                    "solver iterations per step: density {:.1} (max {}), divergence {:.1}",
                    stats.pressure_iterations_mean,
                    stats.pressure_iterations_max,
                    stats.divergence_iterations_mean
                ));
            }
            if stats.dfsph_solves_cut_short > 0 {
                ui.label(format!(
                    "solves cut short by the GPU's iteration budget: {}",
                    stats.dfsph_solves_cut_short
                ));
            }
            if stats.frames_held_for_body_forces > 0 {
                ui.label(format!(
                    "frames the water waited for the bodies' forces: {}",
                    stats.frames_held_for_body_forces
                ));
            }
            if let SphHealth::Unstable { step } = stats.health {
                ui.colored_label(
                    Color32::RED,
                    format!(
                        "unstable at step {step}: frozen; lower dt or turn on adaptive dt, then Reset"
                    ),
                );
            }
            if let Some(d) = stats.diagnostics {
                ui.label(format!(
                    "density error {:.2} % mean, {:.2} % max · v_max {:.2} m/s · {:?}",
                    d.density_error_mean_pct, d.density_error_max_pct, d.max_speed, stats.health
                ));
            }
            ui.label(format!(
                "{} dispatches / step · {} B / particle on the GPU",
                stats.dispatches_per_step, stats.gpu_bytes_per_particle
            ));
            let stages: Vec<String> = stats
                .stage_ms
                .iter()
                .map(|(name, ms)| format!("{} {ms:.2}", name.trim_start_matches("sph_")))
                .collect();
            if !stages.is_empty() {
                ui.label(format!("GPU ms: {}", stages.join(", ")));
            }
            if let Some(error) = &stats.error {
                ui.colored_label(Color32::RED, error);
            }
            plot(ui, &history);
        });
    Ok(())
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
                    runtime_panel.run_if(in_state(AppState::Running)),
                ),
            );
    }
}
