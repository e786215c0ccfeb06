//! Options of `sph-bench run` and how long a run lasts.

use super::values::{
    cfl, column_width, dfsph_max_iterations, dt, integrator, jacobi_weight, on_off,
    over_relaxation, particles, pbf_iterations, percent, percent_per_second, samples_every, search,
    sim_time, solver, steps, substeps, viscosity_alpha, vorticity, wall_friction, Backend,
};
use crate::scenarios::{Bodies, Scenario};
use clap::{ArgAction, Args};
use sph_core::{Integrator, NeighborSearch, Solver};
use std::path::PathBuf;

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
    /// A scene file's dynamic and hinged bodies: held in place, or moved by avian on the water's
    /// clock (on either backend; the CPU backend then runs the plugin in a headless app, and on
    /// the GPU the device moves the bodies with the water at every step, avian's state joining
    /// once a frame: docs/scenes.md, "Bodies on the GPU").
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
    /// PBF: Jacobi iterations of the density constraint per step [default: 6].
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
    /// PBF: the weight of each Jacobi iteration's λ (1: plain Jacobi) [default: 2/3].
    #[arg(long, value_name = "W", value_parser = jacobi_weight)]
    pub pbf_jacobi_weight: Option<f32>,
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
    /// Diffuse particles after Ihmsen et al. 2012 over the water (spray, foam, bubbles),
    /// stepped on the CPU on every state sample: their counts per class, where the foam lies
    /// and the cost of a step in the JSON's `whitewater`. With --scene, the file's own
    /// `whitewater` runs whether or not this is on.
    #[arg(long, value_name = "on|off", value_parser = on_off(), action = ArgAction::Set, default_value = "off")]
    pub whitewater: bool,
    /// No-slip walls with this friction factor (times the fluid's viscosity; PBF: times XSPH's
    /// c); 0 is free slip
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
    /// Sample the state and the bodies every this much simulated time [s] [default: the state
    /// every 0.01 s, the bodies every 0.05 s]. In the plugin's app (the GPU backend, and avian
    /// bodies on the CPU) each sample pauses the app until its clock is read back.
    #[arg(long, value_name = "SECONDS", value_parser = samples_every)]
    pub samples_every: Option<f32>,
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
            pbf_jacobi_weight: None,
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
            whitewater: false,
            wall_friction: None,
            steps: None,
            time: None,
            substeps: 10,
            samples_every: None,
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
