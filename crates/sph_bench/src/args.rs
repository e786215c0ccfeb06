//! Command-line arguments of `sph-bench` (clap): `--help` gives every option's unit and default,
//! and every error names the option, the value and what is allowed, e.g.
//! `invalid value '2' for '--dt <SECONDS>': 2 is not in (0, 1] s`.

use crate::scenarios::{Bodies, Scenario};
use clap::builder::{PossibleValue, PossibleValuesParser, TypedValueParser};
use clap::{ArgAction, Args, Parser, Subcommand, ValueEnum};
use sph_core::{Integrator, NeighborSearch, Solver};
use std::fmt::Display;
use std::path::PathBuf;
use std::str::FromStr;

/// Runs SPH scenarios on the CPU solver or the GPU plugin and reports speed, accuracy and
/// stability as JSON.
#[derive(Clone, Debug, Parser)]
#[command(name = "sph-bench", version, arg_required_else_help = true)]
pub struct Cli {
    /// No progress bars (they are also hidden when stderr is not a terminal).
    #[arg(long, short, global = true)]
    pub quiet: bool,
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// The commands.
#[derive(Clone, Debug, PartialEq, Subcommand)]
pub enum Command {
    /// Runs one scenario and writes its report as JSON.
    Run(RunArgs),
    /// The Martin & Moyce dam break and the hydrostatic tank against their targets.
    Validate(ValidateArgs),
    /// The speed-against-accuracy study: writes trade.md, trade.png and trade.svg.
    Trade(TradeArgs),
    /// A long dam-break run: health, drift of the density error, particle loss.
    Soak(SoakArgs),
    /// Mutates scene files (truncations, flips, numeric extremes, deleted and duplicated keys)
    /// and loads each mutant: counts what loads, what is refused and what panics.
    FuzzScenes(FuzzArgs),
    /// Converts a scene file into a scene for a larger offline engine (SPlisHSPlasH or
    /// DualSPHysics) in the directory OUT; what the engine cannot express is refused by name and
    /// nothing is written (see docs/export.md).
    Export(ExportArgs),
}

/// Which solver runs the scenario.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Backend {
    /// The CPU reference solver (sph_core::CpuSolver).
    Cpu,
    /// The plugin's compute passes (SphFluidPlugin) on a Vulkan adapter; lavapipe works.
    Gpu,
}

impl Backend {
    /// The command-line name.
    pub fn name(self) -> &'static str {
        match self {
            Backend::Cpu => "cpu",
            Backend::Gpu => "gpu",
        }
    }
}

impl ValueEnum for Bodies {
    fn value_variants<'a>() -> &'a [Self] {
        &[Bodies::Held, Bodies::Avian]
    }

    fn to_possible_value(&self) -> Option<PossibleValue> {
        Some(PossibleValue::new(self.name()).help(match self {
            Bodies::Held => "held where the file puts them; the water's force on them reported",
            Bodies::Avian => "moved by avian on the water's clock (two-way coupling)",
        }))
    }
}

impl ValueEnum for Scenario {
    fn value_variants<'a>() -> &'a [Self] {
        &Scenario::ALL
    }

    fn to_possible_value(&self) -> Option<PossibleValue> {
        Some(PossibleValue::new(self.name()).help(self.description()))
    }
}

/// The integrators by command-line name, with their help.
pub const INTEGRATORS: [(&str, &str, Integrator); 3] = [
    ("euler", "symplectic Euler", Integrator::SymplecticEuler),
    ("leapfrog", "leapfrog (the design's)", Integrator::Leapfrog),
    (
        "kdk",
        "kick-drift-kick (one force evaluation per step)",
        Integrator::KickDriftKick,
    ),
];

/// The neighbour searches by command-line name, with their help.
pub const SEARCHES: [(&str, &str, NeighborSearch); 2] = [
    ("grid", "dense grid", NeighborSearch::Grid),
    ("hash", "spatial hash (the design's)", NeighborSearch::Hash),
];

/// The command-line name of `value` in `table`.
fn name_in<T: PartialEq>(table: &[(&'static str, &str, T)], value: T) -> &'static str {
    table.iter().find(|e| e.2 == value).map_or("?", |e| e.0)
}

/// The command-line name of an integrator.
pub fn integrator_name(integrator: Integrator) -> &'static str {
    name_in(&INTEGRATORS, integrator)
}

/// The command-line name of a neighbour search.
pub fn search_name(search: NeighborSearch) -> &'static str {
    name_in(&SEARCHES, search)
}

/// A parser of the names in `table` (clap lists them in the help and in errors).
fn named<T: Copy + Send + Sync + 'static>(
    table: &'static [(&'static str, &'static str, T)],
) -> impl TypedValueParser<Value = T> {
    let values = table.iter().map(|e| PossibleValue::new(e.0).help(e.1));
    PossibleValuesParser::new(values).try_map(move |name| {
        table
            .iter()
            .find(|e| e.0 == name)
            .map(|e| e.2)
            .ok_or_else(|| format!("{name} is not one of the listed values"))
    })
}

/// The pressure solvers by command-line name, with their help.
pub const SOLVERS: [(&str, &str, Solver); 3] = [
    (
        "wcsph",
        "weakly compressible SPH, dt from the speed of sound",
        Solver::Wcsph,
    ),
    (
        "dfsph",
        "divergence-free SPH (Bender & Koschier 2017), dt from the flow speed",
        Solver::Dfsph,
    ),
    (
        "pbf",
        "position-based fluids (Macklin & Müller 2013), dt from the support radius",
        Solver::Pbf,
    ),
];

fn pbf_iterations(text: &str) -> Result<u32, String> {
    number(text, |v: u32| (1..=100).contains(&v), "1..=100 iterations")
}

fn dfsph_max_iterations(text: &str) -> Result<u32, String> {
    number(
        text,
        |v: u32| (2..=1000).contains(&v),
        "2..=1000 iterations",
    )
}

fn over_relaxation(text: &str) -> Result<f32, String> {
    number(text, |v: f32| (1.0..=1.9).contains(&v), "[1, 1.9]")
}

fn vorticity(text: &str) -> Result<f32, String> {
    number(text, |v: f32| (0.0..=1.0).contains(&v), "[0, 1] m/s")
}

fn solver() -> impl TypedValueParser<Value = Solver> {
    named(&SOLVERS)
}

fn percent(text: &str) -> Result<f32, String> {
    number(text, |v: f32| v > 0.0 && v <= 10.0, "(0, 10] %")
}

fn percent_per_second(text: &str) -> Result<f32, String> {
    number(text, |v: f32| v > 0.0 && v <= 1000.0, "(0, 1000] %/s")
}

fn integrator() -> impl TypedValueParser<Value = Integrator> {
    named(&INTEGRATORS)
}

fn search() -> impl TypedValueParser<Value = NeighborSearch> {
    named(&SEARCHES)
}

/// `on` or `off`.
fn on_off() -> impl TypedValueParser<Value = bool> {
    PossibleValuesParser::new(["on", "off"]).map(|v| v == "on")
}

/// Parses a number and checks it with `ok`; the error names the value and `allowed` (the range
/// with its unit).
fn number<T: FromStr + Display + Copy>(
    text: &str,
    ok: impl Fn(T) -> bool,
    allowed: &str,
) -> Result<T, String> {
    match text.trim().parse::<T>() {
        Ok(v) if ok(v) => Ok(v),
        Ok(v) => Err(format!("{v} is not in {allowed}")),
        Err(_) => Err(format!("not a number: allowed {allowed}")),
    }
}

fn dt(text: &str) -> Result<f32, String> {
    number(text, |v: f32| v > 0.0 && v <= 1.0, "(0, 1] s")
}

fn cfl(text: &str) -> Result<f32, String> {
    number(text, |v: f32| v > 0.0 && v <= 1.0, "(0, 1]")
}

fn column_width(text: &str) -> Result<f32, String> {
    number(text, |v: f32| v > 0.0 && v <= 10.0, "(0, 10] m")
}

fn viscosity_alpha(text: &str) -> Result<f32, String> {
    number(text, |v: f32| (0.0..=10.0).contains(&v), "[0, 10]")
}

fn wall_friction(text: &str) -> Result<f32, String> {
    number(text, |v: f32| (0.0..=100.0).contains(&v), "[0, 100]")
}

fn sim_time(text: &str) -> Result<f32, String> {
    number(text, |v: f32| v > 0.0 && v <= 1e6, "(0, 1e6] s")
}

fn steps(text: &str) -> Result<u64, String> {
    number(text, |v: u64| v >= 1, "1.. steps")
}

fn particles(text: &str) -> Result<usize, String> {
    number(
        text,
        |v: usize| (1..=4_194_304).contains(&v),
        "1..=4194304 particles",
    )
}

fn substeps(text: &str) -> Result<u32, String> {
    number(
        text,
        |v: u32| (1..=64).contains(&v),
        "1..=64 steps per frame",
    )
}

/// How long to run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Duration {
    /// A number of steps.
    Steps(u64),
    /// Simulated seconds.
    Time(f64),
}

/// Options of `sph-bench run`.
#[derive(Clone, Debug, PartialEq, Args)]
pub struct RunArgs {
    /// The scene.
    #[arg(long, value_enum, value_name = "NAME", default_value = "dam-break")]
    pub scenario: Scenario,
    /// Run a scene file (`assets/scenes/*.ron`) instead of a scenario: the file sets the
    /// parameters and the solver; --time or --steps (default 2 s), --backend, --substeps,
    /// --rollback and --json apply. The report adds the particle balance and the probes.
    #[arg(long, value_name = "FILE", conflicts_with = "scenario")]
    pub scene: Option<PathBuf>,
    /// A scene file's dynamic and hinged bodies: held in place, or moved by avian (on either
    /// backend; the CPU backend then runs the plugin in a headless app, and the GPU backend's
    /// frames cover at most the plugin's `max_body_frame_time`, 6 ms of water, whatever
    /// --substeps says, so the bodies' forces lag little).
    #[arg(long, value_enum, default_value = "held", requires = "scene")]
    pub bodies: Bodies,
    /// Which solver runs the scenario.
    #[arg(long, value_enum, default_value = "cpu")]
    pub backend: Backend,
    /// The pressure solver. DFSPH uses its own time-step rule (λ Δx / v_max, at most
    /// √(0.005 Δx / g)), PBF its own (λ h / v_max, at most 1/120 s), unless --dt is given.
    /// [default: wcsph; with --scene, the file's solver, which --solver replaces]
    #[arg(long, value_name = "NAME", value_parser = solver())]
    pub solver: Option<Solver>,
    /// DFSPH: the largest mean density error of the constant-density solve [%] [default: 0.01].
    #[arg(long, value_name = "PERCENT", value_parser = percent)]
    pub density_error: Option<f32>,
    /// DFSPH: the largest mean divergence error of the divergence-free solve [%/s]
    /// [default: 0.1].
    #[arg(long, value_name = "PERCENT_PER_S", value_parser = percent_per_second)]
    pub divergence_error: Option<f32>,
    /// DFSPH: the most iterations of each solve, constant-density and divergence-free
    /// [default: 100].
    #[arg(long, value_name = "N", value_parser = dfsph_max_iterations)]
    pub max_iterations: Option<u32>,
    /// PBF: Jacobi iterations of the density constraint per step [default: 4].
    #[arg(long, value_name = "N", value_parser = pbf_iterations)]
    pub pbf_iterations: Option<u32>,
    /// PBF: vorticity confinement ε [m/s] (0 skips the stage) [default: 0].
    #[arg(long, value_name = "M_PER_S", value_parser = vorticity)]
    pub pbf_vorticity: Option<f32>,
    /// DFSPH: over-relaxation ω of the divergence-free solve's iterations after its first
    /// (1: plain Jacobi) [default: 1.4].
    #[arg(long, value_name = "OMEGA", value_parser = over_relaxation)]
    pub divergence_over_relaxation: Option<f32>,
    /// DFSPH: over-relaxation ω of the constant-density solve's iterations after its first
    /// (1: plain Jacobi) [default: 1.3].
    #[arg(long, value_name = "OMEGA", value_parser = over_relaxation)]
    pub density_over_relaxation: Option<f32>,
    /// PBF: over-relaxation ω of the iterations after the first (1: plain Jacobi)
    /// [default: 1.4].
    #[arg(long, value_name = "OMEGA", value_parser = over_relaxation)]
    pub pbf_over_relaxation: Option<f32>,
    /// DFSPH: warm-start each solve from the previous step's stiffness.
    #[arg(long, value_name = "on|off", value_parser = on_off(), action = ArgAction::Set, default_value = "on")]
    pub warm_start: bool,
    /// About how many particles (dambreak32k has its own 31,250) [particles].
    #[arg(long, value_name = "N", value_parser = particles, default_value = "8192")]
    pub particles: usize,
    /// The dam break's column width a [m].
    #[arg(long = "a", value_name = "METRES", value_parser = column_width, default_value = "0.146")]
    pub a: f32,
    /// Time integrator.
    #[arg(long, value_name = "NAME", value_parser = integrator(), default_value = "kdk")]
    pub integrator: Integrator,
    /// Neighbour search.
    #[arg(long, value_name = "NAME", value_parser = search(), default_value = "grid")]
    pub search: NeighborSearch,
    /// Akinci (2013) surface tension of water.
    #[arg(long, value_name = "on|off", value_parser = on_off(), action = ArgAction::Set, default_value = "off")]
    pub surface_tension: bool,
    /// A fixed time step [s]: the largest one with --adaptive on [default: derived from the
    /// particle spacing].
    #[arg(long, value_name = "SECONDS", value_parser = dt)]
    pub dt: Option<f32>,
    /// The CFL factor λ: of the adaptive rule, or of a fixed dt = λ h / (1.1 c0) [default: 0.4].
    #[arg(long, value_name = "LAMBDA", value_parser = cfl)]
    pub cfl: Option<f32>,
    /// The adaptive time step (CFL, viscous and force limits).
    #[arg(long, value_name = "on|off", value_parser = on_off(), action = ArgAction::Set, default_value = "off")]
    pub adaptive: bool,
    /// Roll unstable steps back to the last checkpoint and retry at half the dt (off: the
    /// first unstable step ends the run).
    #[arg(long, value_name = "on|off", value_parser = on_off(), action = ArgAction::Set, default_value = "on")]
    pub rollback: bool,
    /// Artificial viscosity α of ν = α h c0 / 10 [default: the scenario's, 0.15].
    #[arg(long, value_name = "ALPHA", value_parser = viscosity_alpha)]
    pub viscosity_alpha: Option<f32>,
    /// The container's walls as Akinci 2012 boundary samples (off: only the box's clamp, the
    /// model before the boundary; CPU backend only, for the cost study).
    #[arg(long, value_name = "on|off", value_parser = on_off(), action = ArgAction::Set, default_value = "on")]
    pub walls: bool,
    /// No-slip walls with this friction factor (times the fluid's viscosity); 0 is free slip
    /// [default: the scenario's: no slip (1) for the tanks at rest, free slip otherwise].
    #[arg(long, value_name = "F", value_parser = wall_friction)]
    pub wall_friction: Option<f32>,
    /// Run this many steps [steps] [default: the scenario's own simulated time].
    #[arg(long, value_name = "N", value_parser = steps, conflicts_with = "time")]
    pub steps: Option<u64>,
    /// Run this much simulated time [s] [default: the scenario's own].
    #[arg(long, value_name = "SECONDS", value_parser = sim_time)]
    pub time: Option<f32>,
    /// Steps per frame on the GPU backend [steps].
    #[arg(long, value_name = "K", value_parser = substeps, default_value = "10")]
    pub substeps: u32,
    /// Write the JSON report here [default: stdout].
    #[arg(long, value_name = "FILE")]
    pub json: Option<PathBuf>,
}

impl Default for RunArgs {
    /// The defaults of `sph-bench run` (a unit test checks they agree with the parser's).
    fn default() -> Self {
        Self {
            scenario: Scenario::DamBreak,
            scene: None,
            bodies: Bodies::Held,
            backend: Backend::Cpu,
            solver: None,
            density_error: None,
            divergence_error: None,
            warm_start: true,
            max_iterations: None,
            pbf_iterations: None,
            pbf_vorticity: None,
            pbf_over_relaxation: None,
            divergence_over_relaxation: None,
            density_over_relaxation: None,
            particles: 8_192,
            a: 0.146,
            integrator: Integrator::KickDriftKick,
            search: NeighborSearch::Grid,
            surface_tension: false,
            dt: None,
            cfl: None,
            adaptive: false,
            rollback: true,
            viscosity_alpha: None,
            walls: true,
            wall_friction: None,
            steps: None,
            time: None,
            substeps: 10,
            json: None,
        }
    }
}

impl RunArgs {
    /// How long to run (the scenario's own simulated time when `None`).
    pub fn duration(&self) -> Option<Duration> {
        match (self.steps, self.time) {
            (Some(n), _) => Some(Duration::Steps(n)),
            (None, Some(t)) => Some(Duration::Time(f64::from(t))),
            (None, None) => None,
        }
    }
}

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

#[cfg(test)]
mod tests {
    use super::*;
    use clap::CommandFactory;

    fn parse(args: &[&str]) -> Result<Command, String> {
        let argv = std::iter::once("sph-bench").chain(args.iter().copied());
        Cli::try_parse_from(argv)
            .map(|cli| cli.command)
            .map_err(|e| e.to_string())
    }

    #[test]
    fn the_command_line_is_consistent() {
        Cli::command().debug_assert();
    }

    #[test]
    fn run_options_are_parsed() {
        let Ok(Command::Run(a)) = parse(&[
            "run",
            "--scenario",
            "hydrostatic",
            "--backend",
            "gpu",
            "--adaptive",
            "on",
            "--integrator",
            "leapfrog",
            "--search",
            "hash",
            "--cfl",
            "0.3",
            "--time",
            "0.5",
        ]) else {
            panic!("not a run");
        };
        assert_eq!(a.scenario, Scenario::Hydrostatic);
        assert_eq!(a.backend, Backend::Gpu);
        assert!(a.adaptive);
        assert_eq!(a.integrator, Integrator::Leapfrog);
        assert_eq!(a.search, NeighborSearch::Hash);
        assert_eq!(a.cfl, Some(0.3));
        assert_eq!(a.duration(), Some(Duration::Time(0.5)));
        assert!(a.rollback, "rollback is on by default");
        let Ok(Command::Soak(s)) = parse(&["soak", "--rollback", "off"]) else {
            panic!("not a soak");
        };
        assert!(!s.rollback);
    }

    #[test]
    fn defaults_are_the_documented_ones() {
        assert_eq!(parse(&["run"]).ok(), Some(Command::Run(RunArgs::default())));
        let Ok(Command::Validate(v)) = parse(&["validate"]) else {
            panic!("not a validation");
        };
        assert_eq!((v.particles, v.hydrostatic_particles), (8_000, 8_000));
        assert_eq!(
            v.base(),
            RunArgs {
                particles: 8_000,
                solver: Some(Solver::Wcsph),
                ..Default::default()
            }
        );
        let Ok(Command::Trade(t)) = parse(&["trade"]) else {
            panic!("not a trade study");
        };
        assert_eq!(t.backends, [Backend::Cpu, Backend::Gpu]);
        assert_eq!(t.particles, [2_000, 8_000]);
        assert_eq!(t.out_dir, PathBuf::from("docs"));
        assert!(t.dambreak32k);
        assert_eq!(t.substeps, 10);
        let Ok(Command::Soak(s)) = parse(&["soak"]) else {
            panic!("not a soak");
        };
        assert_eq!(
            (s.backend, s.steps, s.particles),
            (Backend::Cpu, 100_000, 4_096)
        );
        assert_eq!((s.substeps, s.json, s.rollback), (20, None, true));
    }

    #[test]
    fn errors_name_the_option_the_value_and_the_range() {
        let cases: [(&[&str], &[&str]); 9] = [
            (
                &["run", "--dt", "2"],
                &["--dt", "'2'", "2 is not in (0, 1] s"],
            ),
            (&["run", "--dt", "fast"], &["--dt", "'fast'", "(0, 1] s"]),
            (&["run", "--a", "0"], &["--a", "'0'", "(0, 10] m"]),
            (
                &["run", "--scenario", "flood"],
                &["--scenario", "'flood'", "pipe-fill", "dambreak32k"],
            ),
            (
                &["run", "--surface-tension", "yes"],
                &["--surface-tension", "'yes'", "on", "off"],
            ),
            (
                &["run", "--integrator", "rk4"],
                &["--integrator", "'rk4'", "euler", "leapfrog", "kdk"],
            ),
            (
                &["trade", "--particles", "100,x"],
                &["--particles", "'x'", "1..=4194304 particles"],
            ),
            (
                &["validate", "--substeps", "65"],
                &["--substeps", "'65'", "1..=64 steps per frame"],
            ),
            (&["soak", "--steps"], &["--steps", "a value is required"]),
        ];
        for (args, wanted) in cases {
            let e = parse(args).expect_err("an error");
            for w in wanted {
                assert!(e.contains(w), "{args:?}: {w:?} not in {e}");
            }
        }
    }

    #[test]
    fn steps_and_time_exclude_each_other() {
        let e = parse(&["run", "--steps", "5", "--time", "1"]).unwrap_err();
        assert!(e.contains("--steps") && e.contains("--time"), "{e}");
    }

    #[test]
    fn help_gives_every_option_a_unit_or_a_value_list() {
        let mut cli = Cli::command();
        for sub in ["run", "validate", "trade", "soak"] {
            let help = cli
                .find_subcommand_mut(sub)
                .expect("subcommand")
                .render_long_help()
                .to_string();
            for unit in ["[particles]", "[steps]"] {
                assert!(help.contains(unit), "{sub}: no {unit} in\n{help}");
            }
        }
        let run = cli
            .find_subcommand_mut("run")
            .expect("run")
            .render_long_help()
            .to_string();
        for text in ["[s]", "[m]", "dam-break", "kick-drift-kick", "on|off"] {
            assert!(run.contains(text), "no {text} in\n{run}");
        }
    }
}
