//! What a run measures on the particle state: the samples taken every [`SAMPLE_INTERVAL`] while
//! it runs (the dam break's front, the tank's layers, the U-tube's legs, the sluice's tank, the
//! density error), the diagnostics, and
//! the level difference of a gated tank at the end.

use crate::args::Backend;
use crate::hydrostatic::HydrostaticSampler;
use crate::physical_checks::orifice::OrificeSampler;
use crate::physical_checks::thin_wall::ThinWallSampler;
use crate::physical_checks::u_tube::UTubeSampler;
use crate::report::DamBreakFigures;
use crate::scenarios::{Scenario, Setup, G};
use crate::sim::State;
use crate::whitewater::WhitewaterSampler;
use bevy_sph_fluid::prelude::SphWhitewaterCounts;
use sph_core::diagnostics::DiagnosticsInput;
use sph_core::front::surge_front;
use sph_core::Diagnostics;

/// Interval between samples of the state [s].
pub const SAMPLE_INTERVAL: f64 = 0.01;

/// What a scenario records while it runs.
#[derive(Default)]
pub(super) struct Samples {
    pub(super) dam_break: Option<DamBreakFigures>,
    pub(super) hydrostatic: Option<HydrostaticSampler>,
    pub(super) u_tube: Option<UTubeSampler>,
    pub(super) orifice: Option<OrificeSampler>,
    pub(super) thin_wall: Option<ThinWallSampler>,
    pub(super) whitewater: Option<WhitewaterSampler>,
    /// The largest mean compression error seen [%].
    pub(super) density_error_peak: f32,
    /// Σ and count of the sampled mean compression errors [%].
    density_error_sum: f64,
    density_error_samples: u64,
    /// Sample the density even without a dam break or a tank (cheap on the CPU).
    track_density: bool,
}

impl Samples {
    /// The samplers of `setup` for a run that ends at `end` [s].
    pub(super) fn for_setup(setup: &Setup, backend: Backend, end: f64) -> Self {
        Self {
            track_density: backend == Backend::Cpu,
            density_error_sum: 0.0,
            density_error_samples: 0,
            dam_break: setup.column_width_a.map(|a| DamBreakFigures {
                column_width_a: a,
                ..Default::default()
            }),
            hydrostatic: setup
                .water_depth
                .map(|_| HydrostaticSampler::new(setup, end)),
            u_tube: (setup.scenario == Scenario::UTube).then(UTubeSampler::default),
            orifice: (setup.scenario == Scenario::Orifice).then(OrificeSampler::default),
            thin_wall: (setup.scenario == Scenario::ThinWall).then(ThinWallSampler::default),
            whitewater: setup
                .whitewater
                .map(|settings| WhitewaterSampler::new(setup, settings, backend == Backend::Gpu)),
            density_error_peak: 0.0,
        }
    }

    pub(super) fn wanted(&self) -> bool {
        self.track_density
            || self.dam_break.is_some()
            || self.hydrostatic.is_some()
            || self.u_tube.is_some()
            || self.orifice.is_some()
            || self.thin_wall.is_some()
            || self.whitewater.is_some()
    }

    /// The mean of the sampled mean compression errors, or `end` without samples.
    pub(super) fn density_error_run(&self, end: f32) -> f32 {
        if self.density_error_samples == 0 {
            end
        } else {
            (self.density_error_sum / self.density_error_samples as f64) as f32
        }
    }

    /// Records the samplers at `time` over `state`; `whitewater` is the simulation's own
    /// whitewater counts when it runs it (the GPU's stages), else the sampler steps its own.
    pub(super) fn record(
        &mut self,
        setup: &Setup,
        time: f64,
        state: &State,
        whitewater: Option<SphWhitewaterCounts>,
    ) -> Result<(), String> {
        if let Some(w) = &mut self.whitewater {
            if !w.on_the_device() {
                w.record(setup, time, state)?;
            } else if let Some(counts) = whitewater {
                w.record_counts(time, counts);
            }
        }
        let d = diagnostics(setup, state);
        self.density_error_peak = self.density_error_peak.max(d.density_error_mean_pct);
        self.density_error_sum += d.density_error_mean_pct as f64;
        self.density_error_samples += 1;
        if let Some(d) = &mut self.dam_break {
            let a = d.column_width_a as f64;
            let link = setup.scene.params.smoothing_radius;
            let x = surge_front(&state.positions, &setup.scene.container, link).unwrap_or(0.0);
            d.front.push([time, x as f64]);
            d.front_nd.push([time * (2.0 * G / a).sqrt(), x as f64 / a]);
        }
        if let Some(h) = &mut self.hydrostatic {
            h.record(setup, time, state);
        }
        if let Some(u) = &mut self.u_tube {
            u.record(time, &state.positions);
        }
        if let Some(o) = &mut self.orifice {
            o.record(time, &state.positions);
        }
        if let Some(w) = &mut self.thin_wall {
            w.record(&state.positions);
        }
        Ok(())
    }
}

/// Diagnostics of `state` in the scenario.
pub fn diagnostics(setup: &Setup, state: &State) -> Diagnostics {
    Diagnostics::measure(
        &setup.scene.params,
        &setup.scene.container,
        &DiagnosticsInput {
            position: &state.positions,
            velocity: &state.velocities,
            density: &state.densities,
        },
    )
}

/// The water level of each basin (the 98th percentile of the heights of the particles more than
/// 4 spacings from the gate and the side walls) and their difference [m].
pub fn level_difference(state: &State, gate_x: f32, spacing: f32) -> f32 {
    let level = |left: bool| {
        let mut y: Vec<f32> = state
            .positions
            .iter()
            .filter(|x| {
                let away = (x.x - gate_x).abs() > 4.0 * spacing;
                away && (x.x < gate_x) == left
            })
            .map(|x| x.y)
            .collect();
        if y.is_empty() {
            return 0.0;
        }
        y.sort_by(f32::total_cmp);
        y[((y.len() - 1) as f32 * 0.98) as usize]
    };
    (level(true) - level(false)).abs()
}
