//! `--whitewater on`: the diffuse particles of Ihmsen et al. 2012 (`sph_core::whitewater`) over a
//! run's water, stepped as a post-process on every state sample (every 0.01 s of simulated time)
//! of either backend, with their counts per class and the cost of a step.

use crate::report::WhitewaterFigures;
use crate::scenarios::Setup;
use crate::sim::State;
use sph_core::whitewater::ihmsen2012::{FluidView, Whitewater};
use sph_core::whitewater::settings::WhitewaterSettings;
use std::time::Instant;

/// Diffuse particles the pool holds per fluid slot of the scenario.
pub const POOL_PER_PARTICLE: usize = 4;

/// The pool and its running figures.
pub(crate) struct WhitewaterSampler {
    whitewater: Whitewater,
    last_time: Option<f64>,
    figures: WhitewaterFigures,
    ms_sum: f64,
}

impl WhitewaterSampler {
    /// An empty pool of [`POOL_PER_PARTICLE`] slots per fluid slot of `setup`, with `settings`.
    pub(crate) fn new(setup: &Setup, settings: WhitewaterSettings) -> Self {
        let capacity = setup.capacity.saturating_mul(POOL_PER_PARTICLE);
        Self {
            whitewater: Whitewater::new(settings, setup.scene.container, capacity, 1),
            last_time: None,
            figures: WhitewaterFigures {
                capacity,
                ..Default::default()
            },
            ms_sum: 0.0,
        }
    }

    /// One whitewater step over `state` at `time`, of the simulated time since the last sample
    /// (the first sample only starts the clock).
    pub(crate) fn record(&mut self, setup: &Setup, time: f64, state: &State) -> Result<(), String> {
        let Some(last) = self.last_time.replace(time) else {
            return Ok(());
        };
        let dt = (time - last) as f32;
        if dt <= 0.0 {
            return Ok(());
        }
        let params = &setup.scene.params;
        let start = Instant::now();
        let fluid = FluidView::new(
            &state.positions,
            &state.velocities,
            &setup.scene.container,
            params.smoothing_radius,
        )
        .map_err(|e| format!("whitewater: {e}"))?;
        let step = self
            .whitewater
            .step(&fluid, params.gravity, params.spacing(), dt);
        self.ms_sum += start.elapsed().as_secs_f64() * 1e3;
        let f = &mut self.figures;
        f.steps += 1;
        f.born += step.born;
        f.dropped += step.dropped;
        f.expired += step.expired;
        let [spray, foam, bubbles] = self.whitewater.pool.counts();
        f.counts
            .push([time, spray as f64, foam as f64, bubbles as f64]);
        f.most_alive = f.most_alive.max(self.whitewater.pool.len());
        Ok(())
    }

    /// The figures of the run.
    pub(crate) fn finish(mut self) -> WhitewaterFigures {
        let [spray, foam, bubbles] = self.whitewater.pool.counts();
        let f = &mut self.figures;
        (f.spray, f.foam, f.bubbles) = (spray, foam, bubbles);
        f.ms_per_step = self.ms_sum / f.steps.max(1) as f64;
        self.figures
    }
}

#[cfg(test)]
mod tests {
    use crate::args::{Backend, Duration, RunArgs};
    use crate::progress::Bars;
    use crate::run::{configured_setup, run_setup};
    use crate::scenarios::Scenario;

    /// A small dam break sheds whitewater where it hits the far wall, and every diffuse particle
    /// is accounted for: born = alive + expired, the refusals counted apart.
    #[test]
    fn a_dam_break_sheds_whitewater_and_counts_every_diffuse_particle() {
        let args = RunArgs {
            scenario: Scenario::DamBreak,
            particles: 1_000,
            whitewater: true,
            ..Default::default()
        };
        let setup = configured_setup(&args);
        let report = run_setup(
            &setup,
            Backend::Cpu,
            1,
            Duration::Time(0.4),
            &Bars::new(true),
        )
        .unwrap();
        let w = report.whitewater.expect("whitewater figures");
        let alive = w.spray + w.foam + w.bubbles;
        assert!(w.born > 0, "{w:?}");
        assert_eq!(w.born, alive as u64 + w.expired, "{w:?}");
        assert!(alive <= w.capacity);
        assert_eq!(w.counts.len() as u64, w.steps);
        // Without the flag nothing is measured.
        let plain = configured_setup(&RunArgs {
            whitewater: false,
            ..args
        });
        assert!(plain.whitewater.is_none());
    }
}
