//! `sph-bench run --scene FILE`: a scene file (`sph_core::scene::file`) as a setup, with its
//! emitters, drains, pumps and probes; the probes' readings go into the report.

use crate::report::ProbeSeries;
use crate::scenarios::{Bodies, Scenario, ScenarioCollider, SceneExtras, Setup};
use sph_core::scenario::Scene;
use sph_core::scene::{SceneFile, SceneProbe};
use sph_core::{ProbeKind, ProbeReading, Rollback};
use std::path::Path;

/// How long a scene file runs unless `--time` or `--steps` says otherwise [s].
pub const SCENE_DURATION: f64 = 2.0;

/// Reads, parses and builds `path`; the error names the file, the line and the field.
pub fn setup_from_file(path: &Path) -> Result<Setup, String> {
    let file = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|e| format!("{file}: cannot read: {e}"))?;
    let built = SceneFile::parse(&text, &file)
        .and_then(|s| s.build(&file, &text))
        .map_err(|e| e.to_string())?;
    let scene = Scene {
        params: built.params,
        container: built.container,
        blocks: built.blocks.iter().map(|(b, _)| *b).collect(),
    };
    // Room for the blocks and what the emitters may add (20,000 for an endless one), at most
    // sph_core::limits::MAX_SPAWN_PARTICLES more: an emitter's `total` may be any u64.
    let emitted = built
        .emitters
        .iter()
        .map(|e| e.total.unwrap_or(20_000))
        .fold(0u64, u64::saturating_add)
        .min(sph_core::limits::MAX_SPAWN_PARTICLES);
    let capacity = scene.particle_count() + emitted as usize;
    Ok(Setup {
        scenario: Scenario::SceneFile,
        capacity: capacity.max(1),
        duration: SCENE_DURATION,
        column_width_a: None,
        water_depth: None,
        rollback: Rollback::default(),
        emitter: None,
        colliders: built
            .colliders
            .iter()
            .map(|c| ScenarioCollider {
                name: c.name.clone(),
                collider: c.collider.clone(),
                lift: None,
                path: (!c.path.is_empty()).then(|| c.clone()),
            })
            .collect(),
        gate_x: None,
        walls: true,
        wall_friction: None,
        whitewater: built.whitewater.map(|(settings, _)| settings),
        extras: Some(SceneExtras {
            file,
            emitters: built.emitters.clone(),
            block_velocities: built.blocks.iter().map(|(_, v)| *v).collect(),
            sinks: built.sinks.clone(),
            pumps: built.pumps.clone(),
            probes: built.probes.clone(),
            colliders: built.colliders.clone(),
            bodies: Bodies::Held,
            solver_replaced: None,
        }),
        scene,
    })
}

/// The readings of every probe, as they arrive.
#[derive(Clone, Debug, Default)]
pub struct ProbeLog {
    /// Per probe: (simulated time, reading).
    pub readings: Vec<Vec<(f64, ProbeReading)>>,
    /// Per probe: the step of its last reading.
    last_step: Vec<Option<u64>>,
}

impl ProbeLog {
    /// A log for `probes`.
    pub fn new(probes: &[SceneProbe]) -> Self {
        Self::new_for(probes.len())
    }

    /// A log for `n` probes.
    pub fn new_for(n: usize) -> Self {
        Self {
            readings: vec![Vec::new(); n],
            last_step: vec![None; n],
        }
    }

    /// Whether probe `k` is due at `step` (every `every_steps` steps; a step count that went
    /// back, after a rollback, makes it due again).
    pub fn due(&self, k: usize, every_steps: u32, step: u64) -> bool {
        match self.last_step.get(k).copied().flatten() {
            Some(at) => step < at || step >= at + every_steps as u64,
            None => true,
        }
    }

    /// Records probe `k`'s reading at `step` and `time`.
    pub fn record(&mut self, k: usize, step: u64, time: f64, reading: ProbeReading) {
        if let (Some(series), Some(last)) = (self.readings.get_mut(k), self.last_step.get_mut(k)) {
            series.push((time, reading));
            *last = Some(step);
        }
    }

    /// The report's series, with each probe's mean over the second half of the run.
    pub fn report(&self, probes: &[SceneProbe], end: f64) -> Vec<ProbeSeries> {
        probes
            .iter()
            .zip(&self.readings)
            .map(|(probe, series)| {
                let late: Vec<f32> = series
                    .iter()
                    .filter(|(t, _)| *t >= 0.5 * end)
                    .filter_map(|(_, r)| r.value)
                    .collect();
                let speeds: Vec<f32> = series
                    .iter()
                    .filter(|(t, _)| *t >= 0.5 * end)
                    .filter_map(|(_, r)| r.mean_speed)
                    .collect();
                let mean = |v: &[f32]| {
                    (!v.is_empty())
                        .then(|| v.iter().map(|&x| x as f64).sum::<f64>() / v.len() as f64)
                };
                ProbeSeries {
                    name: probe.name.clone(),
                    kind: match probe.kind {
                        ProbeKind::Level { .. } => "level",
                        ProbeKind::Flux { .. } => "flux",
                        ProbeKind::Count { .. } => "count",
                    }
                    .into(),
                    mean_second_half: mean(&late),
                    mean_speed_second_half: mean(&speeds),
                    readings: series
                        .iter()
                        .map(|(t, r)| {
                            [
                                *t,
                                r.value.map_or(f64::NAN, f64::from),
                                r.particles as f64,
                                r.mean_speed.map_or(f64::NAN, f64::from),
                            ]
                        })
                        .collect(),
                }
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_shipped_scenes_are_setups_and_a_bad_file_names_its_line() {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/scenes");
        let pipe = setup_from_file(&dir.join("pipe_fill.ron")).unwrap();
        let extras = pipe.extras.as_ref().unwrap();
        assert_eq!(extras.emitters.len(), 1);
        assert!(pipe.capacity >= 8000);
        let bad = std::env::temp_dir().join(format!("sph_bench_bad_{}.ron", std::process::id()));
        std::fs::write(
            &bad,
            "(\n  container: (min: (0.0, 0.0, 0.0), max: (1.0, 1.0, 1.0)),\n  sinks: [(name: \"d\", min: (0.0, 0.0, 0.0), max: (0.0, 0.1, 0.1))],\n)",
        )
        .unwrap();
        let e = setup_from_file(&bad).unwrap_err();
        assert!(e.contains(":3:") && e.contains("sinks[0]"), "{e}");
    }
}

#[cfg(test)]
mod shipped_scenes {
    use crate::args::{Backend, RunArgs};
    use crate::progress::Bars;
    use crate::run::run;
    use std::path::Path;

    /// Runs `file` for `seconds` on `backend` and checks health, the balance and the probes;
    /// from 2 s on, aquaplay's drain must have taken water.
    fn runs_for(file: &str, backend: Backend, seconds: f32) {
        let path = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../assets/scenes")
            .join(file);
        let args = RunArgs {
            scene: Some(path),
            time: Some(seconds),
            backend,
            ..Default::default()
        };
        let report = run(&args, &Bars::new(true)).unwrap_or_else(|e| panic!("{file}: {e}"));
        assert_eq!(report.health, "ok", "{file}");
        // The GPU plans a frame's steps ahead and may end a few steps past the time asked.
        let past = if backend == Backend::Gpu { 0.1 } else { 0.01 };
        assert!(
            report.sim_time > f64::from(seconds) - 0.01
                && report.sim_time < f64::from(seconds) + past,
            "{file}: {}",
            report.sim_time
        );
        assert_eq!(report.particle_balance, 0, "{file}");
        assert_eq!(
            report.particles + report.particles_emitted as usize
                - report.particles_drained as usize,
            report.particles_final,
            "{file}"
        );
        assert!(
            report.probes.iter().all(|p| !p.readings.is_empty()),
            "{file}"
        );
        if file == "aquaplay.ron" && seconds >= 2.0 {
            assert!(
                report.particles_drained > 0,
                "{file}: its drain took nothing"
            );
        }
    }

    #[test]
    fn every_shipped_scene_runs_two_seconds_on_the_cpu() {
        for file in [
            "dam_break.ron",
            "pipe_fill.ron",
            "gate.ron",
            "lock.ron",
            "aquaplay.ron",
            "ramp.ron",
            "basin_jet.ron",
        ] {
            runs_for(file, Backend::Cpu, 2.0);
        }
    }

    /// The GPU runs every shipped scene, every solver, through this runner: WCSPH (the ramp's
    /// meshes guarded on the device), PBF (the pipe, the lock, aquaplay's drain, pump and
    /// probes) and DFSPH (the gate). Half a second each: `tests/device_conservation.rs` runs
    /// every scene 2 s on lavapipe through the plugin, drains included.
    #[test]
    fn every_shipped_scene_runs_half_a_second_on_the_gpu() {
        for file in [
            "dam_break.ron",
            "ramp.ron",
            "pipe_fill.ron",
            "lock.ron",
            "gate.ron",
            "aquaplay.ron",
            "basin_jet.ron",
        ] {
            runs_for(file, Backend::Gpu, 0.5);
        }
    }
}
