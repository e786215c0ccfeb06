//! The values the options take: the backend, the scenario and body names, the solver, integrator
//! and neighbour-search tables, and the parsers of numbers whose errors name the allowed range
//! with its unit.

use crate::scenarios::{Bodies, Scenario};
use clap::builder::{PossibleValue, PossibleValuesParser, TypedValueParser};
use clap::ValueEnum;
use sph_core::{Integrator, NeighborSearch, Solver};
use std::fmt::Display;
use std::str::FromStr;

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

pub(super) fn pbf_iterations(text: &str) -> Result<u32, String> {
    number(text, |v: u32| (1..=100).contains(&v), "1..=100 iterations")
}

pub(super) fn dfsph_max_iterations(text: &str) -> Result<u32, String> {
    number(
        text,
        |v: u32| (2..=1000).contains(&v),
        "2..=1000 iterations",
    )
}

pub(super) fn over_relaxation(text: &str) -> Result<f32, String> {
    number(text, |v: f32| (1.0..=1.9).contains(&v), "[1, 1.9]")
}

pub(super) fn jacobi_weight(text: &str) -> Result<f32, String> {
    number(text, |v: f32| v > 0.0 && v <= 1.0, "(0, 1]")
}

pub(super) fn vorticity(text: &str) -> Result<f32, String> {
    number(text, |v: f32| (0.0..=1.0).contains(&v), "[0, 1] m/s")
}

pub(super) fn solver() -> impl TypedValueParser<Value = Solver> {
    named(&SOLVERS)
}

pub(super) fn percent(text: &str) -> Result<f32, String> {
    number(text, |v: f32| v > 0.0 && v <= 10.0, "(0, 10] %")
}

pub(super) fn percent_per_second(text: &str) -> Result<f32, String> {
    number(text, |v: f32| v > 0.0 && v <= 1000.0, "(0, 1000] %/s")
}

pub(super) fn integrator() -> impl TypedValueParser<Value = Integrator> {
    named(&INTEGRATORS)
}

pub(super) fn search() -> impl TypedValueParser<Value = NeighborSearch> {
    named(&SEARCHES)
}

/// `on` or `off`.
pub(super) fn on_off() -> impl TypedValueParser<Value = bool> {
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

pub(super) fn dt(text: &str) -> Result<f32, String> {
    number(text, |v: f32| v > 0.0 && v <= 1.0, "(0, 1] s")
}

pub(super) fn cfl(text: &str) -> Result<f32, String> {
    number(text, |v: f32| v > 0.0 && v <= 1.0, "(0, 1]")
}

pub(super) fn column_width(text: &str) -> Result<f32, String> {
    number(text, |v: f32| v > 0.0 && v <= 10.0, "(0, 10] m")
}

pub(super) fn viscosity_alpha(text: &str) -> Result<f32, String> {
    number(text, |v: f32| (0.0..=10.0).contains(&v), "[0, 10]")
}

pub(super) fn wall_friction(text: &str) -> Result<f32, String> {
    number(text, |v: f32| (0.0..=100.0).contains(&v), "[0, 100]")
}

pub(super) fn samples_every(text: &str) -> Result<f32, String> {
    number(text, |v: f32| (1e-3..=10.0).contains(&v), "[0.001, 10] s")
}

pub(super) fn sim_time(text: &str) -> Result<f32, String> {
    number(text, |v: f32| v > 0.0 && v <= 1e6, "(0, 1e6] s")
}

pub(super) fn steps(text: &str) -> Result<u64, String> {
    number(text, |v: u64| v >= 1, "1.. steps")
}

pub(super) fn particles(text: &str) -> Result<usize, String> {
    number(
        text,
        |v: usize| (1..=4_194_304).contains(&v),
        "1..=4194304 particles",
    )
}

pub(super) fn substeps(text: &str) -> Result<u32, String> {
    number(
        text,
        |v: u32| (1..=64).contains(&v),
        "1..=64 steps per frame",
    )
}
