//! Command-line arguments of `sph-bench run`.

use sph_core::{Integrator, NeighborSearch};

/// Which solver runs the scenario.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Backend {
    /// `sph_core::CpuSolver`.
    Cpu,
    /// `SphFluidPlugin` compute passes.
    Gpu,
}

/// How the time step is chosen.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum TimeStep {
    /// The scenario's derived CFL step.
    Default,
    /// A fixed dt [s].
    Fixed(f32),
    /// dt = λ h / (c0 + v_peak).
    Cfl(f32),
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
#[derive(Clone, Debug, PartialEq)]
pub struct RunArgs {
    /// Scenario name (`dam-break`).
    pub scenario: String,
    /// Backend.
    pub backend: Backend,
    /// Requested particle count.
    pub particles: usize,
    /// Integrator.
    pub integrator: Integrator,
    /// Neighbour search.
    pub search: NeighborSearch,
    /// Surface tension on.
    pub surface_tension: bool,
    /// Time step.
    pub time_step: TimeStep,
    /// Duration.
    pub duration: Duration,
    /// Where the JSON goes (stdout when `None`).
    pub json: Option<String>,
    /// Steps per frame on the GPU backend.
    pub substeps: u32,
}

impl Default for RunArgs {
    fn default() -> Self {
        Self {
            scenario: "dam-break".into(),
            backend: Backend::Cpu,
            particles: 8_192,
            integrator: Integrator::KickDriftKick,
            search: NeighborSearch::Grid,
            surface_tension: false,
            time_step: TimeStep::Default,
            duration: Duration::Steps(100),
            json: None,
            substeps: 10,
        }
    }
}

/// The usage text.
pub const USAGE: &str =
    "usage: sph-bench run [--scenario dam-break] [--backend cpu|gpu] [--particles N]
       [--integrator euler|leapfrog|kdk] [--search grid|hash] [--surface-tension on|off]
       [--dt X | --cfl X] [--steps N | --time T] [--substeps K] [--json FILE]
       sph-bench validate [--particles N] [--a A] [--json FILE]";

/// Parses the options after `validate`.
pub fn parse_validate(args: &[String]) -> Result<crate::validate::ValidateArgs, String> {
    let mut out = crate::validate::ValidateArgs {
        particles: 8_000,
        a: 0.146,
        json: None,
    };
    let mut k = 0;
    while k < args.len() {
        let flag = args[k].as_str();
        let v = value(args, k, flag)?;
        match flag {
            "--particles" => out.particles = number(v, flag, "1 ..= 4194304")?,
            "--a" => out.a = number(v, flag, "(0, 10] m")?,
            "--json" => out.json = Some(v.to_string()),
            other => return Err(format!("unknown option {other:?}\n{USAGE}")),
        }
        k += 2;
    }
    if !(1..=4_194_304).contains(&out.particles) {
        return Err(format!(
            "--particles = {}: allowed 1 ..= 4194304",
            out.particles
        ));
    }
    if !(out.a > 0.0 && out.a <= 10.0) {
        return Err(format!("--a = {}: allowed (0, 10] m", out.a));
    }
    Ok(out)
}

fn value<'a>(args: &'a [String], k: usize, flag: &str) -> Result<&'a str, String> {
    args.get(k + 1)
        .map(String::as_str)
        .ok_or_else(|| format!("{flag} needs a value"))
}

fn number<T: std::str::FromStr>(text: &str, flag: &str, allowed: &str) -> Result<T, String> {
    text.parse()
        .map_err(|_| format!("{flag} = {text:?} is not a number: allowed {allowed}"))
}

/// Parses the options after `run`.
pub fn parse_run(args: &[String]) -> Result<RunArgs, String> {
    let mut out = RunArgs::default();
    let mut k = 0;
    while k < args.len() {
        let flag = args[k].as_str();
        let v = value(args, k, flag);
        match flag {
            "--scenario" => out.scenario = v?.to_string(),
            "--backend" => {
                out.backend = match v? {
                    "cpu" => Backend::Cpu,
                    "gpu" => Backend::Gpu,
                    other => return Err(format!("--backend = {other:?}: allowed cpu, gpu")),
                }
            }
            "--particles" => out.particles = number(v?, flag, "1 ..= 4194304")?,
            "--integrator" => {
                out.integrator = match v? {
                    "euler" => Integrator::SymplecticEuler,
                    "leapfrog" => Integrator::Leapfrog,
                    "kdk" => Integrator::KickDriftKick,
                    other => {
                        return Err(format!(
                            "--integrator = {other:?}: allowed euler, leapfrog, kdk"
                        ))
                    }
                }
            }
            "--search" => {
                out.search = match v? {
                    "grid" => NeighborSearch::Grid,
                    "hash" => NeighborSearch::Hash,
                    other => return Err(format!("--search = {other:?}: allowed grid, hash")),
                }
            }
            "--surface-tension" => {
                out.surface_tension = match v? {
                    "on" => true,
                    "off" => false,
                    other => return Err(format!("--surface-tension = {other:?}: allowed on, off")),
                }
            }
            "--dt" => out.time_step = TimeStep::Fixed(number(v?, flag, "(0, 1] s")?),
            "--cfl" => out.time_step = TimeStep::Cfl(number(v?, flag, "(0, 2]")?),
            "--steps" => out.duration = Duration::Steps(number(v?, flag, "1 ..")?),
            "--time" => out.duration = Duration::Time(number(v?, flag, "(0, ..) s")?),
            "--substeps" => out.substeps = number(v?, flag, "1 ..= 64")?,
            "--json" => out.json = Some(v?.to_string()),
            other => return Err(format!("unknown option {other:?}\n{USAGE}")),
        }
        k += 2;
    }
    if !(1..=4_194_304).contains(&out.particles) {
        return Err(format!(
            "--particles = {}: allowed 1 ..= 4194304",
            out.particles
        ));
    }
    if !(1..=64).contains(&out.substeps) {
        return Err(format!("--substeps = {}: allowed 1 ..= 64", out.substeps));
    }
    match out.time_step {
        TimeStep::Fixed(dt) if !(dt > 0.0 && dt <= 1.0) => {
            return Err(format!("--dt = {dt}: allowed (0, 1] s"))
        }
        TimeStep::Cfl(c) if !(c > 0.0 && c <= 2.0) => {
            return Err(format!("--cfl = {c}: allowed (0, 2]"))
        }
        _ => {}
    }
    if out.scenario != "dam-break" {
        return Err(format!(
            "--scenario = {:?}: allowed dam-break",
            out.scenario
        ));
    }
    Ok(out)
}
