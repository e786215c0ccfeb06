//! `--whitewater on`: the diffuse particles of Ihmsen et al. 2012 (`sph_core::whitewater`) over a
//! run's water, with their counts per class and the cost of a step. On the CPU they are stepped
//! as a post-process on every state sample (every 0.01 s of simulated time); on the GPU the
//! plugin's whitewater stages run them every step, and each sample reads their counts.

use crate::report::WhitewaterFigures;
use crate::scenarios::Setup;
use crate::sim::State;
use bevy_sph_fluid::prelude::SphWhitewaterCounts;
use sph_core::whitewater::ihmsen2012::{FluidView, Whitewater};
use sph_core::whitewater::pool::DiffuseKind;
use sph_core::whitewater::settings::WhitewaterSettings;
use std::time::Instant;

/// The pool and its running figures.
pub(crate) struct WhitewaterSampler {
    whitewater: Whitewater,
    last_time: Option<f64>,
    figures: WhitewaterFigures,
    ms_sum: f64,
    /// The counts came from the simulation's own whitewater (the GPU's stages).
    on_the_device: bool,
}

impl WhitewaterSampler {
    /// An empty pool of `setup`'s whitewater capacity ([`Setup::whitewater_capacity`]), with
    /// `settings`; or, `on_the_device`, a reader of the simulation's own whitewater.
    pub(crate) fn new(setup: &Setup, settings: WhitewaterSettings, on_the_device: bool) -> Self {
        let capacity = setup.whitewater_capacity();
        Self {
            whitewater: Whitewater::new(settings, setup.scene.container, capacity, 1),
            last_time: None,
            figures: WhitewaterFigures {
                capacity,
                ..Default::default()
            },
            ms_sum: 0.0,
            on_the_device,
        }
    }

    /// Whether the simulation runs the whitewater itself (the GPU's stages).
    pub(crate) fn on_the_device(&self) -> bool {
        self.on_the_device
    }

    /// A sample of the simulation's own whitewater at `time`: its counts as read back.
    pub(crate) fn record_counts(&mut self, time: f64, counts: SphWhitewaterCounts) {
        let f = &mut self.figures;
        f.steps += 1;
        (f.born, f.dropped, f.expired) = (counts.born, counts.dropped, counts.expired);
        let [spray, foam, bubbles] =
            [counts.spray, counts.foam, counts.bubbles].map(|n| n as usize);
        (f.spray, f.foam, f.bubbles) = (spray, foam, bubbles);
        f.counts
            .push([time, spray as f64, foam as f64, bubbles as f64]);
        f.most_alive = f.most_alive.max(spray + foam + bubbles);
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

    /// The figures of a run of `run_steps` simulation steps; `stage_ms` are the simulation's
    /// per-stage times of a pass (the GPU's whitewater stages among them when it ran its own,
    /// once a frame of `frame_steps`).
    pub(crate) fn finish(
        mut self,
        stage_ms: &[(String, f64)],
        frame_steps: u32,
        run_steps: u64,
    ) -> WhitewaterFigures {
        if self.on_the_device {
            let per_frame: f64 = stage_ms
                .iter()
                .filter(|(name, _)| name.contains("whitewater"))
                .map(|(_, ms)| ms)
                .sum();
            self.figures.ms_per_step = per_frame / frame_steps.max(1) as f64;
            self.figures.ms_total = self.figures.ms_per_step * run_steps as f64;
            return self.figures;
        }
        let pool = &self.whitewater.pool;
        let [spray, foam, bubbles] = pool.counts();
        let f = &mut self.figures;
        (f.spray, f.foam, f.bubbles) = (spray, foam, bubbles);
        f.ms_per_step = self.ms_sum / f.steps.max(1) as f64;
        f.ms_total = self.ms_sum;
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
    use crate::report::WhitewaterFigures;
    use crate::run::{configured_setup, run_setup};
    use crate::scenarios::Scenario;

    /// A 1,000-particle dam break with `--whitewater on`, run for 0.4 s on `backend`: its
    /// arguments and its whitewater figures, after checking that it shed some and that every
    /// diffuse particle is accounted for (born = alive + expired, the refusals counted apart).
    fn dam_break_whitewater(backend: Backend) -> (RunArgs, WhitewaterFigures) {
        let args = RunArgs {
            scenario: Scenario::DamBreak,
            particles: 1_000,
            whitewater: true,
            ..Default::default()
        };
        let setup = configured_setup(&args);
        let report = run_setup(&setup, backend, 1, Duration::Time(0.4), &Bars::new(true)).unwrap();
        let w = report.whitewater.expect("whitewater figures");
        let alive = w.spray + w.foam + w.bubbles;
        assert!(w.born > 0, "{w:?}");
        assert_eq!(w.born, alive as u64 + w.expired, "{w:?}");
        assert_eq!(w.capacity, setup.whitewater_capacity());
        (args, w)
    }

    /// A small dam break sheds whitewater where it hits the far wall, and every diffuse particle
    /// is accounted for: born = alive + expired, the refusals counted apart.
    #[test]
    fn a_dam_break_sheds_whitewater_and_counts_every_diffuse_particle() {
        let (args, w) = dam_break_whitewater(Backend::Cpu);
        let alive = w.spray + w.foam + w.bubbles;
        assert!(alive <= w.capacity);
        assert_eq!(w.counts.len() as u64, w.steps);
        // Without the flag nothing is measured.
        let plain = configured_setup(&RunArgs {
            whitewater: false,
            ..args
        });
        assert!(plain.whitewater.is_none());
    }

    /// On the GPU the plugin's stages run the whitewater once a frame: each sample reads their
    /// counts, every diffuse particle is accounted for, and the stages' GPU time is the cost.
    #[test]
    fn on_the_gpu_the_plugins_stages_run_it_and_each_sample_reads_their_counts() {
        let (_, w) = dam_break_whitewater(Backend::Gpu);
        assert!(w.steps >= 30 && w.counts.len() as u64 == w.steps, "{w:?}");
        assert!(w.ms_per_step > 0.0, "the stages' GPU time: {w:?}");
        assert!(
            w.foam_extent.is_none(),
            "the GPU's particles stay on the device"
        );
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
