//! The runtime panel (bevy_egui), sized for a 1280×720 window: the buttons and the statistics at
//! the top, always in view, then the settings in sections that fold and scroll (the water, the
//! stepping, the view), then the live plot.

use crate::obstacles::{Gate, GateLift};
use crate::particles::{ColorMode, ParticleDrawing};
use crate::surface::{surface_controls, RenderMode, RenderView};
use crate::ui::{integrator_combo, plot, slider, viscosity_alpha_slider, DebugView, History};
use crate::{ranges, AppState};
use bevy::ecs::system::SystemParam;
use bevy::prelude::*;
use bevy_egui::egui::{self, Color32, SliderClamping};
use bevy_egui::EguiContexts;
use bevy_sph_fluid::prelude::*;

/// What the panel reads.
#[derive(SystemParam)]
pub struct Readings<'w> {
    stats: Res<'w, SphStats>,
    history: Res<'w, History>,
}

/// What the panel edits.
#[derive(SystemParam)]
pub struct Settings<'w, 's> {
    params: ResMut<'w, SphParams>,
    control: ResMut<'w, SphControl>,
    next: ResMut<'w, NextState<AppState>>,
    gate: Option<ResMut<'w, GateLift>>,
    gates: Query<'w, 's, (), With<Gate>>,
    whitewater: Option<Res<'w, SphWhitewater>>,
    commands: Commands<'w, 's>,
}

/// How the water is drawn.
#[derive(SystemParam)]
pub struct View<'w, 's> {
    render: ResMut<'w, RenderView>,
    surfaces: Query<'w, 's, (&'static mut SphSurface, Option<&'static SphSurfaceStatus>)>,
    drawing: Option<ResMut<'w, ParticleDrawing>>,
    debug: ResMut<'w, DebugView>,
}

/// The runtime panel: controls, statistics, settings and the live plot.
pub fn runtime_panel(
    mut contexts: EguiContexts,
    readings: Readings,
    mut settings: Settings,
    mut view: View,
) -> Result {
    let ctx = contexts.ctx_mut()?;
    let screen = ctx.content_rect().height();
    egui::Window::new("Simulation")
        .anchor(egui::Align2::LEFT_TOP, [8.0, 8.0])
        .default_width(300.0)
        .default_height(screen - 40.0)
        .max_height(screen - 40.0)
        .show(ctx, |ui| {
            buttons(ui, &mut settings);
            statistics(ui, &readings.stats, &readings.history);
            ui.separator();
            egui::ScrollArea::vertical().show(ui, |ui| {
                egui::CollapsingHeader::new("Water")
                    .default_open(true)
                    .show(ui, |ui| water_settings(ui, &mut settings.params));
                egui::CollapsingHeader::new("Stepping")
                    .show(ui, |ui| stepping_settings(ui, &mut settings.control));
                egui::CollapsingHeader::new("View")
                    .default_open(true)
                    .show(ui, |ui| view_settings(ui, &mut view, &readings.stats));
                egui::CollapsingHeader::new("Whitewater").show(ui, |ui| {
                    whitewater_settings(ui, &mut settings, &readings.stats)
                });
                egui::CollapsingHeader::new("Plot")
                    .default_open(true)
                    .show(ui, |ui| plot(ui, &readings.history));
            });
        });
    Ok(())
}

fn buttons(ui: &mut egui::Ui, settings: &mut Settings) {
    let control = &mut settings.control;
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
            settings.next.set(AppState::Setup);
        }
        if let (Some(gate), false) = (settings.gate.as_mut(), settings.gates.is_empty()) {
            let label = if gate.lifting {
                "stop the gate"
            } else {
                "lift the gate"
            };
            if ui.button(label).clicked() {
                gate.lifting = !gate.lifting;
            }
        }
    });
}

/// The statistics, first in the panel so that no section pushes them out of the window.
fn statistics(ui: &mut egui::Ui, stats: &SphStats, history: &History) {
    ui.label(format!(
        "{:?} on {} · FPS {:.1} · {:.0} steps/s",
        stats.backend,
        stats.adapter,
        history.fps(),
        history.steps_per_second()
    ));
    ui.label(format!(
        "real-time factor {:.3} · {} steps / frame · mean compression {:.3} %",
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
    if let Some(d) = stats.diagnostics {
        ui.label(format!(
            "density error {:.2} % mean, {:.2} % max · v_max {:.2} m/s · {:?}",
            d.density_error_mean_pct, d.density_error_max_pct, d.max_speed, stats.health
        ));
    }
    solver_statistics(ui, stats);
    warnings(ui, stats);
}

/// The solvers' iterations and the GPU's costs, where there are any.
fn solver_statistics(ui: &mut egui::Ui, stats: &SphStats) {
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
}

/// Whitewater on or off (`SphWhitewater` with its default settings), its counts, and why it
/// does not run.
fn whitewater_settings(ui: &mut egui::Ui, settings: &mut Settings, stats: &SphStats) {
    let mut on = settings.whitewater.is_some();
    if ui.checkbox(&mut on, "spray, foam and bubbles").changed() {
        if on {
            settings.commands.insert_resource(SphWhitewater::default());
        } else {
            settings.commands.remove_resource::<SphWhitewater>();
        }
    }
    if let Some(c) = stats.whitewater {
        ui.label(format!(
            "spray {} · foam {} · bubbles {} · born {} · dropped {}",
            c.spray, c.foam, c.bubbles, c.born, c.dropped
        ));
    }
    if let Some(error) = &stats.whitewater_error {
        ui.colored_label(Color32::ORANGE, error);
    }
}

/// The flow check, instability and the plugin's errors, in colour.
fn warnings(ui: &mut egui::Ui, stats: &SphStats) {
    if let Some(flow) = &stats.flow_error {
        ui.colored_label(Color32::ORANGE, flow);
    }
    if let SphHealth::Unstable { step } = stats.health {
        ui.colored_label(
            Color32::RED,
            format!("unstable at step {step}: frozen; lower dt or turn on adaptive dt, then Reset"),
        );
    }
    if let Some(error) = &stats.error {
        ui.colored_label(Color32::RED, error);
    }
}

/// The water's parameters; an edit replaces `SphParams` only when something changed.
fn water_settings(ui: &mut egui::Ui, params: &mut SphParams) {
    let mut p = params.0;
    viscosity_alpha_slider(ui, &mut p);
    ui.add(slider(&mut p.stiffness, ranges::STIFFNESS, "stiffness k").logarithmic(true));
    let mut rest_density = p.rest_density;
    ui.add(
        slider(
            &mut rest_density,
            ranges::REST_DENSITY,
            "rest density [kg/m³]",
        )
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
    ui.add(slider(
        &mut p.wall_damping,
        ranges::WALL_DAMPING,
        "wall damping",
    ));
    if p.solver == sph_core::Solver::Pbf {
        ui.add(
            egui::Slider::new(&mut p.pbf.iterations, 1..=20)
                .text("PBF iterations / step")
                .clamping(SliderClamping::Always),
        );
        let epsilon = "PBF vorticity confinement ε [m/s]";
        ui.add(slider(&mut p.pbf.vorticity_epsilon, 0.0..=1.0, epsilon));
        let omega = "PBF over-relaxation ω";
        ui.add(slider(&mut p.pbf.over_relaxation, 1.0..=1.9, omega));
        let weight = "PBF Jacobi weight w";
        ui.add(slider(&mut p.pbf.jacobi_weight, 0.05..=1.0, weight));
    }
    ui.add(slider(
        &mut p.gravity.y,
        ranges::GRAVITY_Y,
        "gravity y [m/s²]",
    ));
    let dt_label = if p.adaptive_time_step {
        "largest dt [s]"
    } else {
        "dt [s]"
    };
    ui.add(slider(&mut p.time_step, ranges::TIME_STEP, dt_label).logarithmic(true));
    ui.checkbox(&mut p.adaptive_time_step, "adaptive dt (CFL)");
    if p.adaptive_time_step {
        ui.add(slider(
            &mut p.cfl_factor,
            ranges::CFL_FACTOR,
            "CFL factor λ",
        ));
    }
    integrator_combo(ui, "runtime", &mut p.integrator);
    if p != params.0 {
        params.0 = p;
    }
}

/// Rollback, real-time stepping or fixed substeps, and the GPU's frame limit with bodies afloat.
fn stepping_settings(ui: &mut egui::Ui, control: &mut SphControl) {
    ui.checkbox(
        &mut control.rollback.enabled,
        "roll back unstable steps (retry at half the dt)",
    );
    let mut real_time = control.real_time.is_some();
    let label = "real time: each frame advances the water by the frame's own time";
    ui.checkbox(&mut real_time, label);
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
    let label = "GPU, bodies afloat: limit the water time a frame covers (their force arrives \
                 a frame or two late)";
    ui.checkbox(&mut limited, label);
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
}

/// Surface or particles, the particles' colour and the debug view.
fn view_settings(ui: &mut egui::Ui, view: &mut View, stats: &SphStats) {
    surface_controls(ui, &mut view.render, &mut view.surfaces, stats);
    let particle_mode = view.render.mode == RenderMode::Particles;
    if let Some(drawing) = view.drawing.as_deref_mut().filter(|_| particle_mode) {
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
    let was = view.debug.0;
    let label = "debug view (grid cells, neighbour counts, velocity arrows)";
    ui.checkbox(&mut view.debug.0, label);
    if let Some(drawing) = view.drawing.as_deref_mut() {
        if view.debug.0 && !was {
            // The debug colours are the particles'.
            view.render.mode = RenderMode::Particles;
            drawing.color_mode = ColorMode::Neighbors;
        } else if !view.debug.0 && was {
            drawing.color_mode = ColorMode::Density;
        }
    }
}
