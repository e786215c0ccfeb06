//! One interface over the two backends: the CPU solver stepped directly, and the plugin in a
//! headless app (its GPU passes, or its CPU backend when avian moves a scene file's bodies;
//! steps in frames of `substeps`, waited for, state read back on demand).
//!
//! The interface and the state it reads back are here; the backends are in `cpu`
//! ([`cpu::CpuSimulation`]) and `app` ([`app::AppSimulation`]).

pub mod app;
pub mod cpu;

use crate::scenarios::ScenarioCollider;
use crate::scene_run::ProbeLog;
use bevy::prelude::Vec3;

/// The particle state a scenario measures.
#[derive(Clone, Debug, Default)]
pub struct State {
    /// Positions [m].
    pub positions: Vec<Vec3>,
    /// Velocities [m/s].
    pub velocities: Vec<Vec3>,
    /// Densities [kg/m³].
    pub densities: Vec<f32>,
    /// Pressures [Pa], as the solver keeps them (a DFSPH pressure is the solves' stiffness times
    /// ρ², not a function of the density).
    pub pressures: Vec<f32>,
    /// Particle ids, as the solver (or the device) holds them.
    pub ids: Vec<u32>,
}

/// Pressure-solver iterations summed over steps (DFSPH; zeros with WCSPH).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct IterationTotals {
    /// Steps counted.
    pub steps: u64,
    /// Σ constant-density iterations.
    pub density: u64,
    /// The most constant-density iterations of one step.
    pub density_max: u32,
    /// Σ divergence-free iterations.
    pub divergence: u64,
    /// Solves the GPU cut short at its iteration budget (`SphStats::dfsph_solves_cut_short`;
    /// 0 on the CPU).
    pub cut_short: u64,
}

impl IterationTotals {
    /// Adds one step's iterations.
    pub fn add(&mut self, density: u32, divergence: u32) {
        self.steps += 1;
        self.density += density as u64;
        self.density_max = self.density_max.max(density);
        self.divergence += divergence as u64;
    }

    /// (mean constant-density, largest, mean divergence-free) iterations per step.
    pub fn means(&self) -> (f64, u32, f64) {
        let n = self.steps.max(1) as f64;
        (
            self.density as f64 / n,
            self.density_max,
            self.divergence as f64 / n,
        )
    }
}

/// A running simulation on either backend.
pub trait Simulation {
    /// Takes up to `steps` steps; returns how many were taken and the wall-clock time [ms].
    fn advance(&mut self, steps: u32) -> Result<(u32, f64), String>;
    /// Simulated time [s].
    fn time(&self) -> f64;
    /// Steps taken.
    fn steps(&self) -> u64;
    /// dt of the last step [s].
    fn last_dt(&self) -> f32;
    /// The step detected as unstable (and not rolled back), if any.
    fn unstable_step(&self) -> Option<u64>;
    /// Unstable steps rolled back so far.
    fn rollbacks(&self) -> u64;
    /// The current state (a readback on the GPU).
    fn state(&mut self) -> Result<State, String>;
    /// Stage name -> mean ms per step (CPU) or per evaluation (GPU timestamps).
    fn stage_ms(&self) -> Vec<(String, f64)>;
    /// Compute dispatches per step (0 on the CPU).
    fn dispatches_per_step(&self) -> u32;
    /// GPU bytes per particle slot (0 on the CPU).
    fn gpu_bytes_per_particle(&self) -> u32;
    /// Adapter name.
    fn adapter(&self) -> String;
    /// Particles the last-resort guard corrected so far: in all, and clamped into the box.
    fn boundary_corrections(&self) -> (u64, u64);
    /// Particles of the setup's blocks left out of the initial spawn because they lay inside a
    /// collider (an emitter's left-outs are never emitted, so never counted).
    fn spawns_inside_colliders(&self) -> u64;
    /// The water's force on each of the setup's colliders averaged since the last call, with
    /// the number of force evaluations averaged (CPU), or the last frame's as read back from
    /// the device, weighted as one (GPU).
    fn take_collider_forces(&mut self) -> Option<(Vec<sph_core::BodyForce>, u64)>;
    /// The water's force on the container's walls, averaged like the colliders' and read before
    /// [`Self::take_collider_forces`] starts the next average (`None` where it is not measured:
    /// the plugin's backends measure it for the hydrostatic tank only).
    fn wall_force(&self) -> Option<Vec3>;
    /// The pressure solver's iterations so far.
    fn iterations(&self) -> IterationTotals;
    /// Particles emitted and drained since the start.
    fn flow_counts(&self) -> (u64, u64);
    /// The scene file's probe readings so far (empty without probes).
    fn probe_log(&self) -> ProbeLog;
    /// The whitewater's counts, when the simulation runs it itself (the plugin's GPU stages);
    /// `None` when the run steps it over the read-back state instead.
    fn whitewater_counts(&self) -> Option<bevy_sph_fluid::prelude::SphWhitewaterCounts> {
        None
    }
    /// Each of the setup's colliders as it stands now: where its script puts it at the current
    /// time, or where avian moved it.
    fn colliders_now(&self, colliders: &[ScenarioCollider]) -> Vec<sph_core::Collider> {
        colliders.iter().map(|c| c.at(self.time())).collect()
    }
}
