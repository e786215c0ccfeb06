//! `--whitewater on`: the diffuse particles of Ihmsen et al. 2012 (`sph_core::whitewater`) over a
//! run's water, stepped as a post-process on every state sample (every 0.01 s of simulated time)
//! of either backend, with their counts per class and the cost of a step.

use crate::report::WhitewaterFigures;
use crate::scenarios::Setup;
use crate::sim::State;
use sph_core::whitewater::ihmsen2012::{FluidView, Whitewater};
use sph_core::whitewater::pool::DiffuseKind;
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
        let pool = &self.whitewater.pool;
        let [spray, foam, bubbles] = pool.counts();
        let f = &mut self.figures;
        (f.spray, f.foam, f.bubbles) = (spray, foam, bubbles);
        f.ms_per_step = self.ms_sum / f.steps.max(1) as f64;
        let foam: Vec<_> = (0..pool.len())
            .filter(|&i| pool.kind[i] == DiffuseKind::Foam)
            .map(|i| pool.position[i])
            .collect();
        f.foam_extent = extent(&foam);
        self.figures
    }
}

/// The 5th and the 95th percentile of `points` along each axis, or `None` without points.
fn extent(points: &[sph_core::glam::Vec3]) -> Option<[[f32; 3]; 2]> {
    if points.is_empty() {
        return None;
    }
    let mut low = [0.0; 3];
    let mut high = [0.0; 3];
    for axis in 0..3 {
        let mut values: Vec<f32> = points.iter().map(|p| p[axis]).collect();
        values.sort_by(f32::total_cmp);
        let at = |share: f32| values[((values.len() - 1) as f32 * share).round() as usize];
        (low[axis], high[axis]) = (at(0.05), at(0.95));
    }
    Some([low, high])
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

    /// A scene file's `whitewater` runs with its settings, and `--whitewater on` adds the
    /// defaults to a file without; the foam's extent lies inside the container.
    #[test]
    fn a_scene_files_whitewater_runs_and_the_flag_adds_it_to_one_without() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/scenes");
        let text = std::fs::read_to_string(dir.join("basin_jet.ron")).unwrap();
        let with = text.replacen(
            "solver:",
            "whitewater: (trapped_air_rate: 80.0),\n    solver:",
            1,
        );
        let file = std::env::temp_dir().join(format!("sph_bench_white_{}.ron", std::process::id()));
        std::fs::write(&file, with).unwrap();
        let setup = crate::scene_run::setup_from_file(&file).unwrap();
        let _ = std::fs::remove_file(&file);
        let settings = setup.whitewater.expect("the file's whitewater");
        assert_eq!(settings.trapped_air_rate, 80.0);
        let run = |scene: std::path::PathBuf, whitewater: bool| {
            let args = RunArgs {
                scene: Some(scene),
                time: Some(0.6),
                whitewater,
                ..Default::default()
            };
            crate::run::run(&args, &Bars::new(true)).unwrap()
        };
        let plain = run(dir.join("basin_jet.ron"), false);
        assert!(plain.whitewater.is_none());
        let flagged = run(dir.join("basin_jet.ron"), true);
        let w = flagged
            .whitewater
            .expect("--whitewater on adds the defaults");
        assert!(w.born > 0, "{w:?}");
        let [low, high] = w.foam_extent.expect("foam where the jet lands");
        assert!(low.iter().zip(&high).all(|(l, h)| l <= h));
        assert!(low.iter().all(|&c| c >= 0.0) && high[0] <= 1.0 && high[2] <= 0.3);
    }
}
