//! The JSON report of one run.

use serde::Serialize;
use std::collections::BTreeMap;

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
    /// Surface tension on.
    pub surface_tension: bool,
    /// Time step [s].
    pub dt: f32,
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
    /// Particles with NaN/infinite state at the end.
    pub nan_count: usize,
    /// Particles outside the container at the end.
    pub escaped_count: usize,
    /// Particles at the end.
    pub particles_final: usize,
    /// GPU memory per particle slot [bytes]: everything allocated / capacity (GPU backend).
    pub gpu_bytes_per_particle: u32,
    /// GPU memory of one million particles at that rate [MiB].
    pub gpu_mib_per_million: f64,
}
