//! Options of the studies built from runs: `sph-bench validate`, `trade` and `soak`.

use super::run::RunArgs;
use super::values::{
    column_width, on_off, particles, sim_time, solver, steps, substeps, viscosity_alpha, Backend,
};
use crate::scenarios::Bodies;
use clap::{ArgAction, Args};
use sph_core::Solver;
use std::path::PathBuf;

/// Options of `sph-bench validate`.
#[derive(Clone, Debug, PartialEq, Args)]
pub struct ValidateArgs {
    /// Which solver runs the scenario.
    #[arg(long, value_enum, default_value = "cpu")]
    pub backend: Backend,
    /// The pressure solver (DFSPH with its own time-step rule).
    #[arg(long, value_name = "NAME", value_parser = solver(), default_value = "wcsph")]
    pub solver: Solver,
    /// About how many particles in the dam break [particles].
    #[arg(long, value_name = "N", value_parser = particles, default_value = "8000")]
    pub particles: usize,
    /// About how many particles in the hydrostatic tank [particles].
    #[arg(long, value_name = "N", value_parser = particles, default_value = "8000")]
    pub hydrostatic_particles: usize,
    /// The dam break's column width a [m].
    #[arg(long = "a", value_name = "METRES", value_parser = column_width, default_value = "0.146")]
    pub a: f32,
    /// Artificial viscosity α of ν = α h c0 / 10 [default: the scenarios', 0.05].
    #[arg(long, value_name = "ALPHA", value_parser = viscosity_alpha)]
    pub viscosity_alpha: Option<f32>,
    /// Roll unstable steps back to the last checkpoint and retry at half the dt (off: the
    /// first unstable step ends the run).
    #[arg(long, value_name = "on|off", value_parser = on_off(), action = ArgAction::Set, default_value = "on")]
    pub rollback: bool,
    /// Steps per frame on the GPU backend [steps].
    #[arg(long, value_name = "K", value_parser = substeps, default_value = "10")]
    pub substeps: u32,
    /// Write the JSON report here [default: stdout].
    #[arg(long, value_name = "FILE")]
    pub json: Option<PathBuf>,
}

impl ValidateArgs {
    /// The options of the dam-break run (the tank's differ in scenario and particles).
    pub fn base(&self) -> RunArgs {
        RunArgs {
            backend: self.backend,
            solver: Some(self.solver),
            particles: self.particles,
            a: self.a,
            viscosity_alpha: self.viscosity_alpha,
            rollback: self.rollback,
            substeps: self.substeps,
            json: self.json.clone(),
            ..Default::default()
        }
    }
}

/// Options of `sph-bench trade`.
#[derive(Clone, Debug, PartialEq, Args)]
pub struct TradeArgs {
    /// Backends to sweep, comma-separated.
    #[arg(
        long,
        value_enum,
        value_name = "LIST",
        value_delimiter = ',',
        default_value = "cpu,gpu"
    )]
    pub backends: Vec<Backend>,
    /// Particle counts of the dam-break sweep, comma-separated [particles].
    #[arg(long, value_name = "N,N,...", value_parser = particles, value_delimiter = ',', default_value = "2000,8000")]
    pub particles: Vec<usize>,
    /// Directory of trade.md, trade.png and trade.svg.
    #[arg(long = "out", value_name = "DIR", default_value = "docs")]
    pub out_dir: PathBuf,
    /// Include the 31,250-particle peer scene.
    #[arg(long, value_name = "on|off", value_parser = on_off(), action = ArgAction::Set, default_value = "on")]
    pub dambreak32k: bool,
    /// Run the physical checks: every solver at its defaults in the tank at rest, the held box,
    /// the thin wall, the U-tube, the orifice and the dam break (CPU).
    #[arg(long, value_name = "on|off", value_parser = on_off(), action = ArgAction::Set, default_value = "on")]
    pub checks: bool,
    /// Steps per frame on the GPU backend [steps].
    #[arg(long, value_name = "K", value_parser = substeps, default_value = "10")]
    pub substeps: u32,
}

/// Options of `sph-bench soak`.
#[derive(Clone, Debug, PartialEq, Args)]
pub struct SoakArgs {
    /// Which solver runs the scenario.
    #[arg(long, value_enum, default_value = "cpu")]
    pub backend: Backend,
    /// Steps to run [steps].
    #[arg(long, value_name = "N", value_parser = steps, default_value = "100000")]
    pub steps: u64,
    /// Soak a scene file instead of the dam break, for --time of simulated time: resident
    /// memory and the particles read back from the solver are checked every simulated minute.
    #[arg(long, value_name = "FILE")]
    pub scene: Option<PathBuf>,
    /// A scene file's dynamic and hinged bodies: held in place, or moved by avian.
    #[arg(long, value_enum, default_value = "held", requires = "scene")]
    pub bodies: Bodies,
    /// Simulated time of a scene soak [s].
    #[arg(long, value_name = "SECONDS", value_parser = sim_time, default_value = "600", requires = "scene")]
    pub time: f32,
    /// About how many particles in the dam break [particles].
    #[arg(long, value_name = "N", value_parser = particles, default_value = "4096")]
    pub particles: usize,
    /// Roll unstable steps back to the last checkpoint and retry at half the dt (off: the
    /// first unstable step ends the run).
    #[arg(long, value_name = "on|off", value_parser = on_off(), action = ArgAction::Set, default_value = "on")]
    pub rollback: bool,
    /// Steps per frame on the GPU backend [steps].
    #[arg(long, value_name = "K", value_parser = substeps, default_value = "20")]
    pub substeps: u32,
    /// Write the JSON report here [default: stdout].
    #[arg(long, value_name = "FILE")]
    pub json: Option<PathBuf>,
}
