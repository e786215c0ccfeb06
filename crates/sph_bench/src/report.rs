//! The JSON report of one run.

use crate::physical_checks::orifice::OrificeFigures;
use crate::physical_checks::thin_wall::ThinWallFigures;
use crate::physical_checks::u_tube::UTubeFigures;
use serde::Serialize;
use std::collections::BTreeMap;

/// The dam break's front against Martin & Moyce (1952).
#[derive(Clone, Debug, Default, Serialize)]
pub struct DamBreakFigures {
    /// Column width a [m].
    pub column_width_a: f32,
    /// [[t, x]]: front [m] from the wall behind the column, every 0.01 s. The front is the largest
    /// x of the water body connected (particles closer than h) to the particle nearest the
    /// corner behind the column: detached droplets and splashes are not the front.
    pub front: Vec<[f64; 2]>,
    /// [[T, Z]] with T = t sqrt(2g/a), Z = x/a.
    pub front_nd: Vec<[f64; 2]>,
    /// RMS of Z_sim(T) - Z_exp(T) over the experiment's points with T <= 2.5 (null when the run
    /// stopped before T = 2.5).
    pub rms_z_raw: f64,
    /// The same with the experiment's best lag in [0, 0.3] (gate removal) taken out.
    pub rms_z_shifted: f64,
    /// That lag in T.
    pub best_shift: f64,
}

/// One lattice layer's pressure.
#[derive(Clone, Debug, Default, Serialize)]
pub struct Layer {
    /// Mean weight depth [m]: the weight of the water above the particle per unit floor area,
    /// over ρ0 g (see `crate::hydrostatic`).
    pub depth: f64,
    /// Mean SPH pressure [Pa].
    pub pressure: f64,
    /// ρ0 g depth [Pa].
    pub expected: f64,
    /// (pressure - expected) / expected [%].
    pub error_pct: f64,
    /// Mean depth of the particles' current heights below the water's initial surface [m]:
    /// deeper than the weight depth by the column's settling.
    pub depth_below_initial_surface: f64,
    /// The pressure against ρ0 g `depth_below_initial_surface` [%].
    pub error_vs_initial_surface_pct: f64,
}

/// The hydrostatic figures.
#[derive(Clone, Debug, Default, Serialize)]
pub struct HydrostaticFigures {
    /// Layers from the top (layer 0 is the top particle layer).
    pub layers: Vec<Layer>,
    /// Largest |error| of the layers below the top one [%] (target <= 5).
    pub max_error_below_top_pct: f64,
    /// Mean |error| of the layers below the top one [%].
    pub mean_error_below_top_pct: f64,
    /// Largest |error_vs_initial_surface_pct| of the layers below the top one [%].
    pub max_error_vs_initial_surface_pct: f64,
    /// Mean compression error over the averaging window [%] (target <= 1).
    pub density_error_mean_pct: f64,
    /// The mean particle speed of each sample in the averaging window, averaged [m/s]: how still
    /// the tank is on average, where `speed_mean_end` is one instant (DFSPH's tank cycles every
    /// few steps, docs/dfsph.md).
    pub speed_mean_window_mean: f64,
    /// The largest particle speed of each sample in the averaging window, averaged [m/s]: how
    /// still the tank is, where `speed_max_end` is one particle at one instant.
    pub speed_max_window_mean: f64,
    /// The share of the window's samples whose largest speed exceeds
    /// [`crate::hydrostatic::TANK_MAX_SPEED`] [%].
    pub speed_max_window_over_pct: f64,
    /// The water's mean force on the container's walls along gravity over the last 40 % of the
    /// run [N] (null where it is not measured).
    pub walls_force_n: Option<f64>,
    /// That force against the water's weight N m g [%] (target within ±2).
    pub walls_weight_error_pct: Option<f64>,
}

/// The water's force on one collider, averaged over the last 40 % of the run.
#[derive(Clone, Debug, Default, Serialize)]
pub struct ColliderForceReport {
    /// The collider's name in the scenario.
    pub name: String,
    /// Force [N].
    pub force: [f32; 3],
    /// Torque about the collider's origin [N m].
    pub torque: [f32; 3],
    /// Force evaluations averaged.
    pub evaluations: u64,
}

/// Where a scene file's dynamic or hinged collider started and ended (they do not move with
/// `--bodies held`).
#[derive(Clone, Debug, Default, Serialize)]
pub struct BodyMotion {
    /// The collider's name in the file.
    pub name: String,
    /// Its position at the start [m].
    pub start: [f32; 3],
    /// Its position at the end [m].
    pub end: [f32; 3],
    /// The angle it turned through, start to end [rad] (0 to π).
    pub turned_rad: f32,
    /// Whether it came to rest: over the last quarter of the run (at least two samples), every
    /// sample moved slower than `run::bodies::SETTLED_SPEED` and turned slower than
    /// `run::bodies::SETTLED_TURN_RATE`.
    pub settled: bool,
    /// Its pose, velocity and the water's force on it every `run::bodies::BODY_SAMPLE_INTERVAL`
    /// of simulated time.
    pub series: Vec<BodySample>,
}

/// One sample of a body's motion.
#[derive(Clone, Debug, Default, Serialize)]
pub struct BodySample {
    /// Simulated time [s].
    pub t: f64,
    /// Position [m].
    pub position: [f32; 3],
    /// Orientation, quaternion (x, y, z, w).
    pub rotation: [f32; 4],
    /// Mean velocity since the previous sample [m/s] (zero for the first).
    pub velocity: [f32; 3],
    /// Mean rate of turn since the previous sample [rad/s].
    pub turn_rate: f32,
    /// The water's force on it, as last read [N].
    pub force: [f32; 3],
}

/// The buoyancy scenario: the vertical force on the held box against ρ0 g V.
#[derive(Clone, Debug, Default, Serialize)]
pub struct BuoyancyFigures {
    /// ρ0 |g| V of the box [N].
    pub expected_n: f64,
    /// The mean upward force on it over the last 40 % of the run [N].
    pub measured_n: f64,
    /// (measured - expected) / expected [%] (target within ±5).
    pub error_pct: f64,
}

/// `--whitewater on`: the diffuse particles over the run (Ihmsen et al. 2012, stepped on every
/// state sample).
#[derive(Clone, Debug, Default, Serialize)]
pub struct WhitewaterFigures {
    /// Diffuse particles the pool holds at most.
    pub capacity: usize,
    /// Spray at the end (fewer fluid neighbours than `spray_below`).
    pub spray: usize,
    /// Foam at the end.
    pub foam: usize,
    /// Bubbles at the end (more fluid neighbours than `bubble_above`).
    pub bubbles: usize,
    /// The most alive at once.
    pub most_alive: usize,
    /// Born over the run.
    pub born: u64,
    /// Refused by the full pool over the run.
    pub dropped: u64,
    /// Died over the run (foam at the end of its life, any leaving the container).
    pub expired: u64,
    /// Whitewater steps taken (CPU), or samples of the GPU's counts.
    pub steps: u64,
    /// The cost of a whitewater step [ms]: on the CPU the wall clock of the post-process, the
    /// water's view and its neighbour sort included (mean); on the GPU the GPU time of its
    /// stages in a timed frame (they run once a frame) over the frame's steps.
    pub ms_per_step: f64,
    /// What whitewater cost over the whole run [ms]: on the CPU every post-process step's wall
    /// clock, on the GPU [`Self::ms_per_step`] times the run's simulation steps.
    pub ms_total: f64,
    /// [[t, spray, foam, bubbles]] after each step (CPU) or sample (GPU).
    pub counts: Vec<[f64; 4]>,
    /// Where the foam lies at the end: the 5th and the 95th percentile of its positions along
    /// each axis [m] (`None` without foam, and on the GPU, whose diffuse particles stay on the
    /// device).
    pub foam_extent: Option<[[f32; 3]; 2]>,
}

/// A probe's readings over the run (`--scene FILE`).
#[derive(Clone, Debug, Default, Serialize)]
pub struct ProbeSeries {
    /// The probe's name in the file.
    pub name: String,
    /// "level" [m], "flux" [m³/s] or "count" [particles].
    pub kind: String,
    /// The mean value over the second half of the run (null when there was none).
    pub mean_second_half: Option<f64>,
    /// Flux: the mean speed along the normal over the second half [m/s].
    pub mean_speed_second_half: Option<f64>,
    /// [[t, value, particles, mean speed]] (null where the value is undefined: a dry column).
    pub readings: Vec<[f64; 4]>,
}

/// One run's figures (the fields the issue asks for, plus context).
#[derive(Clone, Debug, Default, Serialize)]
pub struct Report {
    /// Scenario name.
    pub scenario: String,
    /// "cpu" or "gpu".
    pub backend: String,
    /// Adapter name ("cpu" on the CPU backend).
    pub adapter: String,
    /// Particles at the start.
    pub particles: usize,
    /// Integrator.
    pub integrator: String,
    /// Neighbour search.
    pub search: String,
    /// Pressure solver: "wcsph" or "dfsph".
    pub solver: String,
    /// DFSPH: constant-density iterations per step, mean over the run (0 with WCSPH).
    pub pressure_iterations_mean: f64,
    /// DFSPH: the most constant-density iterations of any step.
    pub pressure_iterations_max: u32,
    /// DFSPH: divergence-free iterations per step, mean over the run.
    pub divergence_iterations_mean: f64,
    /// DFSPH on the GPU: solves that ran out of the iterations a frame encoded before they
    /// converged (the iteration budget, `bevy_sph_fluid::dfsph_budget`); 0 on the CPU.
    pub solves_cut_short: u64,
    /// Surface tension on.
    pub surface_tension: bool,
    /// dt chosen every step by the CFL rule.
    pub adaptive_time_step: bool,
    /// CFL factor λ of the adaptive rule.
    pub cfl_factor: f32,
    /// Time step [s] (the largest step with the adaptive rule).
    pub dt: f32,
    /// Simulated time / steps [s].
    pub dt_mean: f64,
    /// Steps taken.
    pub steps: u64,
    /// Simulated time [s].
    pub sim_time: f64,
    /// Median wall-clock time per step [ms] (GPU: frames of `substeps` steps, waited to finish).
    pub ms_per_step_median: f64,
    /// Wall-clock cost of one simulated second [s].
    pub cost_per_sim_second_s: f64,
    /// Median milliseconds per particle-step, ×1e6 (ns per particle-step).
    pub ns_per_particle_step: f64,
    /// Compute dispatches per step (GPU).
    pub dispatches_per_step: u32,
    /// Per-stage time [ms] of one evaluation (GPU timestamps) or mean per step (CPU wall clock).
    pub stage_ms: BTreeMap<String, f64>,
    /// Mean compression error [%] at the end.
    pub density_error_mean_pct: f32,
    /// Largest compression error [%] at the end.
    pub density_error_max_pct: f32,
    /// The largest mean compression error seen over the run [%] (sampled every 0.01 s on the
    /// CPU backend and in the GPU's dam-break and hydrostatic runs; the end value otherwise).
    pub density_error_mean_max_pct: f32,
    /// The mean compression error [%] averaged over the run's samples (every 0.01 s; the end
    /// value where the run takes no samples: GPU runs other than the dam break and the tank).
    pub density_error_mean_run_pct: f32,
    /// Particles with NaN/infinite state at the end.
    pub nan_count: usize,
    /// Particles outside the container at the end.
    pub escaped_count: usize,
    /// Particles at the end.
    pub particles_final: usize,
    /// Particles the emitters added during the run.
    pub particles_emitted: u64,
    /// Particles the drains removed during the run.
    pub particles_drained: u64,
    /// particles + emitted − drained − final: 0 when nothing was lost or duplicated.
    pub particle_balance: i64,
    /// The scene file run (`--scene FILE`).
    pub scene_file: Option<String>,
    /// The scene file's own solver when `--solver` replaced it (`solver` is the one that ran).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub solver_replaced: Option<String>,
    /// The scene file's probes, with every reading.
    pub probes: Vec<ProbeSeries>,
    /// A scene file's bodies: "held" in place or moved by "avian" (`--bodies`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub bodies: Option<String>,
    /// A scene file's dynamic and hinged colliders: where they started and ended.
    pub body_motion: Vec<BodyMotion>,
    /// GPU memory per particle slot [bytes]: everything allocated / capacity (GPU backend).
    pub gpu_bytes_per_particle: u32,
    /// GPU memory of one million particles at that rate [MiB].
    pub gpu_mib_per_million: f64,
    /// Unstable steps were rolled back and retried at half the dt (`--rollback on`).
    pub rollback: bool,
    /// Unstable steps rolled back (0 with rollback off).
    pub rollbacks: u64,
    /// The time step in use at the end [s] (after any halving by rollbacks; the adaptive rule's
    /// last dt).
    pub dt_last: f32,
    /// "ok", or "unstable" (a step went unstable and could not be rolled back, or NaN or escaped
    /// particles at the end).
    pub health: String,
    /// The step at which the instability was detected (the run stops there).
    pub unstable_step: Option<u64>,
    /// Mean particle speed at the end [m/s].
    pub speed_mean_end: f32,
    /// Largest particle speed at the end [m/s].
    pub speed_max_end: f32,
    /// Particles the last-resort guard moved out of a solid or back into the box (0 while the
    /// boundary model holds).
    pub boundary_corrections: u64,
    /// Of those, the particles clamped back into the container's box (the rest were inside a
    /// collider).
    pub wall_corrections: u64,
    /// Particles inside any collider at the end (deeper than the guard's tolerance, a
    /// thousandth of the spacing).
    pub inside_collider_count: usize,
    /// Particles of the scenario's blocks left out because they lay inside a collider.
    pub spawns_inside_colliders: u64,
    /// The gate scenario: |left level - right level| at the end [m].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub level_difference_end: Option<f32>,
    /// The water's force on each collider over the last 40 % of the run: the mean over every
    /// force evaluation (CPU backend) or over the frames read back from the device (GPU).
    pub collider_forces: Vec<ColliderForceReport>,
    /// The buoyancy scenario's figures.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub buoyancy: Option<BuoyancyFigures>,
    /// Dam-break scenarios: the front and its error against the experiment.
    #[serde(flatten)]
    pub dam_break: Option<DamBreakFigures>,
    /// The hydrostatic scenario: pressure against depth.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub hydrostatic: Option<HydrostaticFigures>,
    /// The U-tube scenario: the period against the textbook's.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub u_tube: Option<UTubeFigures>,
    /// The orifice scenario: the discharge coefficient against the textbook's.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub orifice: Option<OrificeFigures>,
    /// `--whitewater on`: the diffuse particles.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub whitewater: Option<WhitewaterFigures>,
    /// The thin-wall scenario: the water that passed the wall.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub thin_wall: Option<ThinWallFigures>,
}
