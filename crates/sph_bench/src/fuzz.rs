//! `sph-bench fuzz-scenes`: the scene-file fuzzer of `sph_core::scene::mutations` (the one CI
//! runs in `crates/sph_core/tests/scene_fuzz.rs`), for as many mutants as asked.

use crate::args::FuzzArgs;
use crate::progress::Bars;
use serde::Serialize;
use sph_core::scene::mutations::{load, mutant};
use std::time::Instant;

/// What a fuzzing run found.
#[derive(Clone, Debug, Default, Serialize)]
pub struct FuzzReport {
    /// The generator's seed.
    pub seed: u64,
    /// Mutants per scene file.
    pub count_per_scene: u64,
    /// The scene files mutated.
    pub scenes: Vec<String>,
    /// Mutants that built.
    pub loaded: u64,
    /// Mutants refused with a `SceneError`.
    pub refused: u64,
    /// Mutants whose load panicked: scene, mutant index and mutations (empty when none).
    pub panicked: Vec<String>,
    /// The slowest load [ms], and which.
    pub slowest_ms: f64,
    /// The slowest mutant: scene, index and mutations.
    pub slowest: String,
    /// Wall time of the run [s].
    pub wall_seconds: f64,
}

/// Mutates every scene `count` times from `seed` and loads each mutant.
pub fn run(args: &FuzzArgs, bars: &Bars) -> Result<FuzzReport, String> {
    let files = if args.scenes.is_empty() {
        let dir = std::path::Path::new("assets/scenes");
        let mut found: Vec<_> = std::fs::read_dir(dir)
            .map_err(|e| {
                format!(
                    "cannot list {}: {e} (run from the repository's root, or name the files)",
                    dir.display()
                )
            })?
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.extension().is_some_and(|x| x == "ron"))
            .collect();
        found.sort();
        found
    } else {
        args.scenes.clone()
    };
    let mut report = FuzzReport {
        seed: args.seed,
        count_per_scene: args.count,
        ..FuzzReport::default()
    };
    let start = Instant::now();
    // A panic is recorded, not printed: the report lists them.
    let hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(|_| {}));
    for path in &files {
        let name = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|e| format!("cannot read {name}: {e}"))?;
        report.scenes.push(name.clone());
        let mut progress = bars.run(format!("fuzz {name}"), args.count);
        for index in 0..args.count {
            let m = mutant(&text, args.seed, index);
            let began = Instant::now();
            let outcome = std::panic::catch_unwind(|| load(&m.text, &name).map(drop));
            let ms = began.elapsed().as_secs_f64() * 1e3;
            let case = format!("{name} #{index}: {:?}", m.mutations);
            match outcome {
                Ok(Ok(())) => report.loaded += 1,
                Ok(Err(_)) => report.refused += 1,
                Err(_) => report.panicked.push(case.clone()),
            }
            if ms > report.slowest_ms {
                report.slowest_ms = ms;
                report.slowest = case;
            }
            if index % 1024 == 0 {
                progress.set(index, format!("{} panicked", report.panicked.len()));
            }
        }
        progress.finish();
    }
    std::panic::set_hook(hook);
    report.wall_seconds = start.elapsed().as_secs_f64();
    Ok(report)
}
