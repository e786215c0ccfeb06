//! Options of the commands that take scene files apart rather than run them: `sph-bench
//! fuzz-scenes` and `sph-bench export`.

use super::values::sim_time;
use clap::{Args, ValueEnum};
use std::path::PathBuf;

/// Options of `sph-bench fuzz-scenes`.
#[derive(Clone, Debug, PartialEq, Args)]
pub struct FuzzArgs {
    /// The generator's seed (CI's test uses 0x5EEDF00D, 2,000 per scene).
    #[arg(long, value_name = "N", default_value = "1592651789")]
    pub seed: u64,
    /// Mutants per scene file.
    #[arg(long, value_name = "N", default_value = "100000")]
    pub count: u64,
    /// The scene files [default: assets/scenes/*.ron].
    #[arg(value_name = "FILE")]
    pub scenes: Vec<PathBuf>,
    /// Write the JSON report here [default: stdout].
    #[arg(long, value_name = "FILE")]
    pub json: Option<PathBuf>,
}

/// The engines `sph-bench export` writes for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum ExportTarget {
    /// SPlisHSPlasH: scene.json with OBJ geometry, run by `SPHSimulator scene.json`.
    #[value(name = "splishsplash")]
    Splishsplash,
    /// DualSPHysics: Case_Def.xml with STL geometry, run by GenCase then DualSPHysics.
    #[value(name = "dualsphysics")]
    Dualsphysics,
}

/// Options of `sph-bench export`.
#[derive(Clone, Debug, PartialEq, Args)]
pub struct ExportArgs {
    /// The engine to write for.
    #[arg(long = "to", value_enum, value_name = "ENGINE")]
    pub to: ExportTarget,
    /// The scene file (`assets/scenes/*.ron`).
    #[arg(value_name = "SCENE")]
    pub scene: PathBuf,
    /// The directory to write: new, or empty. It gets the whole export or nothing.
    #[arg(value_name = "OUT")]
    pub out: PathBuf,
    /// Simulated time the exported scene runs for (SPlisHSPlasH's stopAt, DualSPHysics's
    /// TimeMax) [s] (the default of `run --scene`).
    #[arg(long, value_name = "SECONDS", value_parser = sim_time, default_value = "2")]
    pub time: f32,
    /// Leave the scene's probes out instead of refusing it (neither engine's scene file has
    /// probes; measure their output instead).
    #[arg(long)]
    pub drop_probes: bool,
}
