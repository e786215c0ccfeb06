//! The scene panel (with `--scene FILE`): a slider for each of the scene file's named controls
//! (gate lift, pump crank, drain valve) and each probe's latest reading with a plot of its last
//! readings.

use crate::{AppState, SandboxSet};
use bevy::prelude::*;
use bevy_egui::egui::{self, Color32, SliderClamping};
use bevy_egui::EguiContexts;
use bevy_sph_fluid::prelude::*;
use std::collections::{BTreeMap, VecDeque};

/// Readings kept per probe for the plots.
const PROBE_HISTORY: usize = 200;

/// Each probe's last readings, by entity: (name, kind, values).
#[derive(Resource, Default)]
pub struct ProbeHistory(BTreeMap<Entity, (String, &'static str, VecDeque<f32>)>);

/// Keeps the probes' readings for the panel.
pub fn record_probe_readings(
    mut readings: MessageReader<SphProbeReading>,
    probes: Query<(&SphProbe, Option<&Name>)>,
    mut history: ResMut<ProbeHistory>,
) {
    for r in readings.read() {
        let Ok((probe, name)) = probes.get(r.probe) else {
            continue;
        };
        let kind = match probe.kind {
            SphProbeKind::Level { .. } => "level [m]",
            SphProbeKind::Flux { .. } => "flux [L/s]",
            SphProbeKind::Count { .. } => "particles",
        };
        let scale = if kind.starts_with("flux") { 1e3 } else { 1.0 };
        let entry = history.0.entry(r.probe).or_insert_with(|| {
            let name = name.map_or_else(|| format!("{}", r.probe), |n| n.to_string());
            (name, kind, VecDeque::new())
        });
        if let Some(value) = r.reading.value {
            entry.2.push_back(value * scale);
            if entry.2.len() > PROBE_HISTORY {
                entry.2.pop_front();
            }
        }
    }
    history.0.retain(|entity, _| probes.contains(*entity));
}

/// The scene panel, on the right, while a scene file has controls or probes.
pub fn scene_panel(
    mut contexts: EguiContexts,
    mut scenes: Query<&mut SphSceneControls>,
    history: Res<ProbeHistory>,
) -> Result {
    if scenes.is_empty() && history.0.is_empty() {
        return Ok(());
    }
    egui::Window::new("Scene")
        .anchor(egui::Align2::RIGHT_TOP, [-8.0, 8.0])
        .default_width(280.0)
        .show(contexts.ctx_mut()?, |ui| {
            for mut controls in &mut scenes {
                // Only a moved slider marks the controls changed.
                let mut values: Vec<f32> = controls.0.iter().map(|c| c.value).collect();
                for (value, c) in values.iter_mut().zip(&controls.0) {
                    ui.add(
                        egui::Slider::new(value, c.min..=c.max)
                            .text(&c.name)
                            .clamping(SliderClamping::Always),
                    );
                }
                if values.iter().zip(&controls.0).any(|(v, c)| *v != c.value) {
                    for (c, v) in controls.0.iter_mut().zip(values) {
                        c.value = v;
                    }
                }
            }
            for (name, kind, values) in history.0.values() {
                let last = values.back().copied().unwrap_or(f32::NAN);
                ui.label(format!("{name}: {last:.4} {kind}"));
                plot(ui, values);
            }
        });
    Ok(())
}

fn plot(ui: &mut egui::Ui, values: &VecDeque<f32>) {
    let (rect, _) = ui.allocate_exact_size(egui::vec2(260.0, 36.0), egui::Sense::hover());
    let painter = ui.painter_at(rect);
    painter.rect_filled(rect, 2.0, Color32::from_gray(25));
    let (lo, hi) = values
        .iter()
        .fold((f32::MAX, f32::MIN), |(lo, hi), &v| (lo.min(v), hi.max(v)));
    let span = (hi - lo).max(1e-6);
    let n = values.len().max(2) as f32;
    let points: Vec<egui::Pos2> = values
        .iter()
        .enumerate()
        .map(|(k, &v)| {
            egui::pos2(
                rect.left() + rect.width() * k as f32 / (n - 1.0),
                rect.bottom() - rect.height() * (v - lo) / span,
            )
        })
        .collect();
    painter.add(egui::Shape::line(
        points,
        egui::Stroke::new(1.5, Color32::LIGHT_BLUE),
    ));
}

/// A scene file's panel: its controls and its probes' readings, plotted.
pub struct ScenePanelPlugin;

impl Plugin for ScenePanelPlugin {
    fn build(&self, app: &mut App) {
        app.init_resource::<ProbeHistory>()
            .add_systems(
                Update,
                record_probe_readings
                    .in_set(SandboxSet::Read)
                    .run_if(in_state(AppState::Running)),
            )
            .add_systems(
                bevy_egui::EguiPrimaryContextPass,
                scene_panel.run_if(in_state(AppState::Running)),
            );
    }
}
