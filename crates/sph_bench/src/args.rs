//! Command-line arguments of `sph-bench`: every error names the option, the value and what is
//! allowed.

use crate::scenarios::Scenario;
use sph_core::{Integrator, NeighborSearch};

/// Which solver runs the scenario.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Backend {
    /// `sph_core::CpuSolver`.
    Cpu,
    /// `SphFluidPlugin` compute passes.
    Gpu,
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
    /// Scenario.
    pub scenario: Scenario,
    /// Backend.
    pub backend: Backend,
    /// Requested particle count (about; `dambreak32k` has its own).
    pub particles: usize,
    /// The dam break's column width a [m].
    pub a: f32,
    /// Integrator.
    pub integrator: Integrator,
    /// Neighbour search.
    pub search: NeighborSearch,
    /// Surface tension on.
    pub surface_tension: bool,
    /// A fixed dt [s] (the largest dt with `adaptive`).
    pub dt: Option<f32>,
    /// The CFL factor λ: of the adaptive rule, or of a fixed dt = λ h / (1.1 c0).
    pub cfl: Option<f32>,
    /// The adaptive CFL time step.
    pub adaptive: bool,
    /// Artificial viscosity α (ν = α h c0 / 10) instead of the scenario's.
    pub viscosity_alpha: Option<f32>,
    /// Duration (the scenario's own when `None`).
    pub duration: Option<Duration>,
    /// Where the JSON goes (stdout when `None`).
    pub json: Option<String>,
    /// Steps per frame on the GPU backend.
    pub substeps: u32,
}

impl Default for RunArgs {
    fn default() -> Self {
        Self {
            scenario: Scenario::DamBreak,
            backend: Backend::Cpu,
            particles: 8_192,
            a: 0.146,
            integrator: Integrator::KickDriftKick,
            search: NeighborSearch::Grid,
            surface_tension: false,
            dt: None,
            cfl: None,
            adaptive: false,
            viscosity_alpha: None,
            duration: None,
            json: None,
            substeps: 10,
        }
    }
}

/// Options of `sph-bench validate`.
#[derive(Clone, Debug, PartialEq)]
pub struct ValidateArgs {
    /// Backend, the dam break's particles and a, viscosity α, substeps and the JSON path.
    pub base: RunArgs,
    /// Particles in the hydrostatic tank (about).
    pub hydrostatic_particles: usize,
}

/// Options of `sph-bench trade`.
#[derive(Clone, Debug, PartialEq)]
pub struct TradeArgs {
    /// Backends to sweep.
    pub backends: Vec<Backend>,
    /// Particle counts of the dam break sweep.
    pub particles: Vec<usize>,
    /// Where the table and the plot go.
    pub out_dir: String,
    /// Include the 31,250-particle peer scene.
    pub dambreak32k: bool,
    /// Steps per frame on the GPU.
    pub substeps: u32,
}

/// Options of `sph-bench soak`.
#[derive(Clone, Debug, PartialEq)]
pub struct SoakArgs {
    /// Backend.
    pub backend: Backend,
    /// Steps.
    pub steps: u64,
    /// Particles.
    pub particles: usize,
    /// Steps per frame on the GPU.
    pub substeps: u32,
    /// Where the JSON goes.
    pub json: Option<String>,
}

/// The usage text.
pub const USAGE: &str = "usage:
  sph-bench run [--scenario dam-break|hydrostatic|pipe-fill|dambreak32k] [--backend cpu|gpu]
       [--particles N] [--a A] [--integrator euler|leapfrog|kdk] [--search grid|hash]
       [--surface-tension on|off] [--dt X] [--cfl X] [--adaptive on|off] [--viscosity-alpha X]
       [--steps N | --time T] [--substeps K] [--json FILE]
  sph-bench validate [--backend cpu|gpu] [--particles N] [--hydrostatic-particles N] [--a A]
       [--viscosity-alpha X] [--substeps K] [--json FILE]
  sph-bench trade [--backends cpu,gpu] [--particles N,N,...] [--out DIR] [--dambreak32k on|off]
       [--substeps K]
  sph-bench soak [--backend cpu|gpu] [--steps N] [--particles N] [--substeps K] [--json FILE]";

/// Walks `--flag value` pairs.
struct Flags<'a> {
    args: &'a [String],
    k: usize,
}

impl<'a> Flags<'a> {
    fn new(args: &'a [String]) -> Self {
        Self { args, k: 0 }
    }

    /// The next (flag, value) pair.
    fn next_pair(&mut self) -> Option<Result<(&'a str, &'a str), String>> {
        let flag = self.args.get(self.k)?.as_str();
        self.k += 2;
        Some(
            self.args
                .get(self.k - 1)
                .map(|v| (flag, v.as_str()))
                .ok_or_else(|| format!("{flag} needs a value\n{USAGE}")),
        )
    }
}

fn number<T: std::str::FromStr + PartialOrd + std::fmt::Display>(
    text: &str,
    flag: &str,
    min: T,
    max: T,
    allowed: &str,
) -> Result<T, String> {
    match text.parse::<T>() {
        Ok(v) if v >= min && v <= max => Ok(v),
        Ok(v) => Err(format!("{flag} = {v}: allowed {allowed}")),
        Err(_) => Err(format!(
            "{flag} = {text:?} is not a number: allowed {allowed}"
        )),
    }
}

fn positive(text: &str, flag: &str, max: f32, allowed: &str) -> Result<f32, String> {
    let v: f32 = number(text, flag, f32::MIN_POSITIVE, max, allowed)?;
    Ok(v)
}

fn on_off(text: &str, flag: &str) -> Result<bool, String> {
    match text {
        "on" => Ok(true),
        "off" => Ok(false),
        other => Err(format!("{flag} = {other:?}: allowed on, off")),
    }
}

fn backend(text: &str, flag: &str) -> Result<Backend, String> {
    match text {
        "cpu" => Ok(Backend::Cpu),
        "gpu" => Ok(Backend::Gpu),
        other => Err(format!("{flag} = {other:?}: allowed cpu, gpu")),
    }
}

const PARTICLES: &str = "1 ..= 4194304";

fn particles(text: &str, flag: &str) -> Result<usize, String> {
    number(text, flag, 1, 4_194_304, PARTICLES)
}

fn substeps(text: &str, flag: &str) -> Result<u32, String> {
    number(text, flag, 1, 64, "1 ..= 64")
}

fn unknown(flag: &str) -> String {
    format!("unknown option {flag:?}\n{USAGE}")
}

/// Applies one option of `run` (also the ones `validate` shares) to `out`.
fn apply_run_flag(out: &mut RunArgs, flag: &str, v: &str) -> Result<(), String> {
    match flag {
        "--scenario" => out.scenario = Scenario::parse(v)?,
        "--backend" => out.backend = backend(v, flag)?,
        "--particles" => out.particles = particles(v, flag)?,
        "--a" => out.a = positive(v, flag, 10.0, "(0, 10] m")?,
        "--integrator" => {
            out.integrator = match v {
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
            out.search = match v {
                "grid" => NeighborSearch::Grid,
                "hash" => NeighborSearch::Hash,
                other => return Err(format!("--search = {other:?}: allowed grid, hash")),
            }
        }
        "--surface-tension" => out.surface_tension = on_off(v, flag)?,
        "--dt" => out.dt = Some(positive(v, flag, 1.0, "(0, 1] s")?),
        "--cfl" => out.cfl = Some(positive(v, flag, 1.0, "(0, 1]")?),
        "--adaptive" => out.adaptive = on_off(v, flag)?,
        "--viscosity-alpha" => out.viscosity_alpha = Some(number(v, flag, 0.0, 10.0, "[0, 10]")?),
        "--steps" => out.duration = Some(Duration::Steps(number(v, flag, 1, u64::MAX, "1 ..")?)),
        "--time" => {
            out.duration = Some(Duration::Time(positive(v, flag, 1e6, "(0, 1e6] s")? as f64))
        }
        "--substeps" => out.substeps = substeps(v, flag)?,
        "--json" => out.json = Some(v.to_string()),
        other => return Err(unknown(other)),
    }
    Ok(())
}

/// Parses the options after `run`.
pub fn parse_run(args: &[String]) -> Result<RunArgs, String> {
    let mut out = RunArgs::default();
    let mut flags = Flags::new(args);
    while let Some(pair) = flags.next_pair() {
        let (flag, v) = pair?;
        apply_run_flag(&mut out, flag, v)?;
    }
    Ok(out)
}

/// Parses the options after `validate`: the shared ones of `run`, and the tank's particles.
pub fn parse_validate(args: &[String]) -> Result<ValidateArgs, String> {
    let mut out = ValidateArgs {
        base: RunArgs {
            particles: 8_000,
            ..Default::default()
        },
        hydrostatic_particles: 8_000,
    };
    let mut flags = Flags::new(args);
    while let Some(pair) = flags.next_pair() {
        let (flag, v) = pair?;
        match flag {
            "--hydrostatic-particles" => out.hydrostatic_particles = particles(v, flag)?,
            "--backend" | "--particles" | "--a" | "--viscosity-alpha" | "--substeps" | "--json" => {
                apply_run_flag(&mut out.base, flag, v)?
            }
            other => return Err(unknown(other)),
        }
    }
    Ok(out)
}

/// Parses the options after `trade`.
pub fn parse_trade(args: &[String]) -> Result<TradeArgs, String> {
    let mut out = TradeArgs {
        backends: vec![Backend::Cpu, Backend::Gpu],
        particles: vec![2_000, 8_000],
        out_dir: "docs".into(),
        dambreak32k: true,
        substeps: 10,
    };
    let mut flags = Flags::new(args);
    while let Some(pair) = flags.next_pair() {
        let (flag, v) = pair?;
        match flag {
            "--backends" => {
                out.backends = v
                    .split(',')
                    .map(|b| backend(b, flag))
                    .collect::<Result<_, _>>()?
            }
            "--particles" => {
                out.particles = v
                    .split(',')
                    .map(|n| particles(n, flag))
                    .collect::<Result<_, _>>()?
            }
            "--out" => out.out_dir = v.to_string(),
            "--dambreak32k" => out.dambreak32k = on_off(v, flag)?,
            "--substeps" => out.substeps = substeps(v, flag)?,
            other => return Err(unknown(other)),
        }
    }
    if out.backends.is_empty() || out.particles.is_empty() {
        return Err("--backends and --particles need at least one value".into());
    }
    Ok(out)
}

/// Parses the options after `soak`.
pub fn parse_soak(args: &[String]) -> Result<SoakArgs, String> {
    let mut out = SoakArgs {
        backend: Backend::Cpu,
        steps: 100_000,
        particles: 4_096,
        substeps: 20,
        json: None,
    };
    let mut flags = Flags::new(args);
    while let Some(pair) = flags.next_pair() {
        let (flag, v) = pair?;
        match flag {
            "--backend" => out.backend = backend(v, flag)?,
            "--steps" => out.steps = number(v, flag, 1, u64::MAX, "1 ..")?,
            "--particles" => out.particles = particles(v, flag)?,
            "--substeps" => out.substeps = substeps(v, flag)?,
            "--json" => out.json = Some(v.to_string()),
            other => return Err(unknown(other)),
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn strings(args: &[&str]) -> Vec<String> {
        args.iter().map(|s| s.to_string()).collect()
    }

    #[test]
    fn run_options_are_parsed() {
        let a = parse_run(&strings(&[
            "--scenario",
            "hydrostatic",
            "--backend",
            "gpu",
            "--adaptive",
            "on",
            "--cfl",
            "0.3",
            "--time",
            "0.5",
        ]))
        .unwrap();
        assert_eq!(a.scenario, Scenario::Hydrostatic);
        assert_eq!(a.backend, Backend::Gpu);
        assert!(a.adaptive);
        assert_eq!(a.cfl, Some(0.3));
        assert_eq!(a.duration, Some(Duration::Time(0.5)));
    }

    #[test]
    fn errors_name_the_option_the_value_and_the_range() {
        let e = parse_run(&strings(&["--dt", "2"])).unwrap_err();
        assert!(
            e.contains("--dt") && e.contains('2') && e.contains("(0, 1] s"),
            "{e}"
        );
        let e = parse_run(&strings(&["--scenario", "flood"])).unwrap_err();
        assert!(e.contains("flood") && e.contains("pipe-fill"), "{e}");
        let e = parse_trade(&strings(&["--particles", "100,x"])).unwrap_err();
        assert!(e.contains("--particles") && e.contains("\"x\""), "{e}");
        let e = parse_soak(&strings(&["--steps"])).unwrap_err();
        assert!(e.contains("needs a value"), "{e}");
    }
}
