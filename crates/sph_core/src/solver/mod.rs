//! The CPU reference solver: structure-of-arrays f32 particle data, rayon-parallel passes, and the
//! same stage order as the GPU pipeline (sort -> density -> [normals] -> forces -> integrate),
//! with the container's walls and the colliders as Akinci 2012 boundary samples
//! ([`crate::boundary::samples`]).

use crate::boundary::collider::Slip;
use crate::boundary::guard::Corrections;
use crate::boundary::samples::{BodyForceSum, Boundary};
use crate::container::BoxContainer;
use crate::diagnostics::{Diagnostics, DiagnosticsInput};
use crate::flow::pump::{apply_pumps, Pump};
use crate::flow::sink::{drained_by_any, Sink};
use crate::frame_budget::{StepDt, FRAME_DONE};
use crate::neighbor::Neighbors;
use crate::params::{Integrator, ParamError, SphParams};
use crate::rollback::{Rollback, RollbackState, Verdict};
use crate::solvers::{Solver, SolverStats};
use crate::stability::StepExtremes;
use glam::Vec3;
use rayon::prelude::*;

mod colliders;
pub mod dfsph;
pub mod pbf;
mod state;
pub mod wcsph;
pub mod whitewater;

use state::SolverParts;
pub use state::{ParticleData, StageTimings};

/// What a spawn did: how many particles were added, how many were refused for capacity and how
/// many were left out because they lay inside (or within half a spacing of) a collider.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SpawnReport {
    /// Particles added.
    pub spawned: usize,
    /// Particles refused because the solver was full.
    pub refused: usize,
    /// Particles left out because they lay inside a collider.
    pub inside_colliders: usize,
}

/// The CPU SPH solver.
#[derive(Clone, Debug)]
pub struct CpuSolver {
    params: SphParams,
    container: BoxContainer,
    capacity: usize,
    neighbors: Neighbors,
    particles: ParticleData,
    scratch: Vec<Vec3>,
    next_id: u32,
    step_count: u64,
    time: f64,
    timings: StageTimings,
    /// Set when particles were added or parameters changed since the last force evaluation, so
    /// the kick-drift-kick integrator must evaluate forces before its first kick.
    forces_stale: bool,
    /// The boundary's membership the forces were last evaluated with.
    boundary_membership: u64,
    /// The time step of the last step [s].
    last_dt: f32,
    /// The last good state (see [`crate::rollback`]), restored when a step goes unstable.
    checkpoint: ParticleData,
    /// Simulated time at the checkpoint [s].
    checkpoint_time: f64,
    /// How unstable steps are handled.
    rollback: Rollback,
    /// Checkpoints, retries and the dt scale.
    rollback_state: RollbackState,
    /// The step (1-based) that went unstable; the solver is frozen until [`CpuSolver::clear`].
    unstable_step: Option<u64>,
    /// The walls' and colliders' samples.
    boundary: Boundary,
    /// Particles the guard moved out of a solid or back into the box since the last clear.
    boundary_corrections: Corrections,
    /// The fluid's force on each boundary body, summed over the evaluations since the last
    /// [`CpuSolver::take_collider_forces`], and the number of those evaluations.
    body_force_sums: (Vec<BodyForceSum>, u64),
    /// The fluid's force on each boundary body in the last evaluation.
    last_body_forces: Vec<BodyForceSum>,
    /// WCSPH's scratch (the equation of state's pressures).
    wcsph: wcsph::WcsphScratch,
    /// DFSPH's per-step scratch (neighbour lists, factors, sources).
    dfsph: dfsph::DfsphScratch,
    /// PBF's per-step scratch (neighbour lists, λ, corrections).
    pbf: pbf::PbfScratch,
    /// What the pressure solves of the last step did.
    solver_stats: SolverStats,
    /// What is left of the frame [s] while [`CpuSolver::advance_by`] steps.
    frame_remaining: Option<f32>,
    /// The pumps every step applies ([`crate::flow::pump`]).
    pumps: Vec<Pump>,
    /// The diffuse particles, when whitewater is on ([`Self::set_whitewater`]).
    whitewater: Option<Box<crate::whitewater::ihmsen2012::Whitewater>>,
}

/// What [`CpuSolver::advance_by`] did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FrameAdvance {
    /// Steps taken (retried steps included).
    pub steps: u32,
    /// Simulated time gained [s]: the duration asked for, less when the step cap was reached or
    /// the solver froze, and negative when a rollback went back past the frame's start.
    pub simulated: f64,
}

/// Adds `forces` (one evaluation's force on each body) to `sums` and keeps them as the last.
fn record_body_forces(
    sums: &mut (Vec<BodyForceSum>, u64),
    last: &mut Vec<BodyForceSum>,
    forces: Vec<BodyForceSum>,
) {
    let (sums, evaluations) = sums;
    sums.resize(forces.len(), BodyForceSum::default());
    sums.iter_mut().zip(&forces).for_each(|(s, f)| s.merge(f));
    *evaluations += 1;
    *last = forces;
}

/// Checks a particle capacity (1 ..= 2^26).
pub fn validate_capacity(capacity: usize) -> Result<(), ParamError> {
    if (1..=1 << 26).contains(&capacity) {
        Ok(())
    } else {
        Err(ParamError {
            field: "capacity",
            value: capacity.to_string(),
            allowed: "[1, 67108864] particles",
        })
    }
}

impl CpuSolver {
    /// A solver for at most `capacity` particles; validates everything first.
    pub fn new(
        params: SphParams,
        container: BoxContainer,
        capacity: usize,
    ) -> Result<Self, ParamError> {
        params.validate()?;
        container.validate()?;
        validate_capacity(capacity)?;
        let neighbors = Neighbors::new(
            params.neighbor_search,
            &container,
            params.smoothing_radius,
            capacity,
        )?;
        Ok(Self {
            boundary: Boundary::new(&container, &params, Slip::default())?,
            boundary_corrections: Corrections::default(),
            body_force_sums: (Vec::new(), 0),
            last_body_forces: Vec::new(),
            wcsph: wcsph::WcsphScratch::default(),
            dfsph: dfsph::DfsphScratch::default(),
            pbf: pbf::PbfScratch::default(),
            solver_stats: SolverStats::default(),
            frame_remaining: None,
            pumps: Vec::new(),
            whitewater: None,
            params,
            container,
            capacity,
            neighbors,
            particles: ParticleData::default(),
            scratch: Vec::new(),
            next_id: 0,
            step_count: 0,
            time: 0.0,
            timings: StageTimings::default(),
            forces_stale: true,
            boundary_membership: 0,
            last_dt: params.time_step,
            checkpoint: ParticleData::default(),
            checkpoint_time: 0.0,
            rollback: Rollback::default(),
            rollback_state: RollbackState::default(),
            unstable_step: None,
        })
    }

    /// The parameters in use.
    pub fn params(&self) -> &SphParams {
        &self.params
    }

    /// Replaces the parameters (validated); a changed neighbour mode or h rebuilds the structure.
    pub fn set_params(&mut self, params: SphParams) -> Result<(), ParamError> {
        params.validate()?;
        if params.neighbor_search != self.params.neighbor_search
            || params.smoothing_radius != self.params.smoothing_radius
        {
            self.neighbors = Neighbors::new(
                params.neighbor_search,
                &self.container,
                params.smoothing_radius,
                self.capacity,
            )?;
        }
        if !self.boundary.matches(&self.container, &params) {
            self.boundary.rebuild_for(&self.container, &params)?;
        }
        self.params = params;
        self.forces_stale = true;
        Ok(())
    }

    /// The container.
    pub fn container(&self) -> &BoxContainer {
        &self.container
    }

    /// Maximum particle count.
    pub fn capacity(&self) -> usize {
        self.capacity
    }

    /// The particle arrays (in the solver's current sort order).
    pub fn particles(&self) -> &ParticleData {
        &self.particles
    }

    /// Live particle count.
    pub fn len(&self) -> usize {
        self.particles.len()
    }

    /// Whether there are no particles.
    pub fn is_empty(&self) -> bool {
        self.particles.is_empty()
    }

    /// Steps taken.
    pub fn step_count(&self) -> u64 {
        self.step_count
    }

    /// Simulated time [s].
    pub fn time(&self) -> f64 {
        self.time
    }

    /// The neighbour-search structure (valid for the current order after a step).
    pub fn neighbors(&self) -> &Neighbors {
        &self.neighbors
    }

    /// Adds particles with one common velocity; refuses (and reports) what exceeds the capacity.
    pub fn spawn(&mut self, positions: &[Vec3], velocity: Vec3) -> SpawnReport {
        self.spawn_each(positions, |_| velocity)
    }

    /// Adds particles with their own velocities (`velocities.len()` must equal `positions.len()`;
    /// missing velocities are zero); refuses what exceeds the capacity.
    pub fn spawn_with_velocities(
        &mut self,
        positions: &[Vec3],
        velocities: &[Vec3],
    ) -> SpawnReport {
        self.spawn_each(positions, |k| {
            velocities.get(k).copied().unwrap_or(Vec3::ZERO)
        })
    }

    fn spawn_each(&mut self, positions: &[Vec3], velocity: impl Fn(usize) -> Vec3) -> SpawnReport {
        let outside: Vec<usize> = (0..positions.len())
            .filter(|&k| self.boundary.admits_spawn(positions[k]))
            .collect();
        let free = self.capacity - self.particles.len();
        let take = outside.len().min(free);
        let p = &mut self.particles;
        let rho0 = self.params.rest_density;
        for &k in &outside[..take] {
            let (x, v) = (positions[k], velocity(k));
            p.position.push(x);
            p.velocity.push(v);
            p.velocity_predicted.push(v);
            p.acceleration.push(Vec3::ZERO);
            p.acceleration_start.push(Vec3::ZERO);
            p.density.push(rho0);
            p.pressure.push(0.0);
            p.normal.push(Vec3::ZERO);
            p.stiffness_density.push(0.0);
            p.position_previous.push(x);
            p.stiffness_divergence.push(0.0);
            p.id.push(self.next_id);
            self.next_id += 1;
        }
        self.forces_stale |= take > 0;
        self.rollback_state.save_requested |= take > 0;
        SpawnReport {
            spawned: take,
            refused: outside.len() - take,
            inside_colliders: positions.len() - outside.len(),
        }
    }

    /// The pumps applied at the end of every step (validated; on error the previous pumps stay
    /// and the error names the pump and the field).
    pub fn set_pumps(&mut self, pumps: &[Pump]) -> Result<(), ParamError> {
        for pump in pumps {
            pump.validate()?;
        }
        self.pumps.clear();
        self.pumps.extend_from_slice(pumps);
        Ok(())
    }

    /// The pumps in use.
    pub fn pumps(&self) -> &[Pump] {
        &self.pumps
    }

    /// Removes every particle inside an open sink and returns how many: from the state and from
    /// the rollback checkpoint, so a rollback never brings a drained particle back.
    pub fn drain(&mut self, sinks: &[Sink]) -> usize {
        if sinks.iter().all(|s| !s.open) || self.particles.is_empty() {
            return 0;
        }
        let doomed: Vec<bool> = self
            .particles
            .position
            .par_iter()
            .map(|&x| drained_by_any(sinks, x))
            .collect();
        let removed_ids = self.particles.remove_flagged(&doomed);
        if removed_ids.is_empty() {
            return 0;
        }
        let removed: std::collections::HashSet<u32> = removed_ids.iter().copied().collect();
        let in_checkpoint: Vec<bool> = self
            .checkpoint
            .id
            .iter()
            .map(|id| removed.contains(id))
            .collect();
        self.checkpoint.remove_flagged(&in_checkpoint);
        self.forces_stale = true;
        self.rollback_state.save_requested = true;
        removed_ids.len()
    }

    /// Removes every particle, resets time and clears an instability freeze, the checkpoint and
    /// the rollback counters.
    pub fn clear(&mut self) {
        self.particles = ParticleData::default();
        self.checkpoint = ParticleData::default();
        self.rollback_state = RollbackState::default();
        self.next_id = 0;
        self.step_count = 0;
        self.time = 0.0;
        self.unstable_step = None;
        self.boundary_corrections = Corrections::default();
        self.body_force_sums = (Vec::new(), 0);
        self.clear_whitewater();
    }

    /// How unstable steps are handled (rollback on by default).
    pub fn rollback(&self) -> Rollback {
        self.rollback
    }

    /// Sets how unstable steps are handled (validated; the previous settings stay on error).
    pub fn set_rollback(&mut self, rollback: Rollback) -> Result<(), ParamError> {
        rollback.validate()?;
        self.rollback = rollback;
        Ok(())
    }

    /// Rollbacks since the last reset.
    pub fn rollbacks(&self) -> u64 {
        self.rollback_state.rollbacks
    }

    /// The factor applied to the time-step rule's dt: 1, or 2^-k after k rollbacks not yet
    /// recovered from.
    pub fn time_step_scale(&self) -> f32 {
        self.rollback_state.dt_scale()
    }

    /// The step (1-based) detected as unstable, if any (see [`crate::stability`]). That step was
    /// rolled back and the solver is frozen: [`Self::step`] does nothing until [`Self::clear`].
    pub fn unstable_step(&self) -> Option<u64> {
        self.unstable_step
    }

    /// The time step of the last step [s] (the adaptive choice with `adaptive_time_step`).
    pub fn last_time_step(&self) -> f32 {
        self.last_dt
    }

    /// The time step the rule gives for the current velocities and accelerations [s]. A step
    /// applies it right before its first integration phase: after the first force evaluation
    /// (symplectic Euler, the design's leapfrog) or with the previous step's closing
    /// acceleration (kick-drift-kick).
    pub fn next_time_step(&self) -> f32 {
        let (params, p, boundary) = (&self.params, &self.particles, &self.boundary);
        match params.solver {
            Solver::Wcsph => wcsph::next_time_step(params, p, boundary),
            Solver::Dfsph => dfsph::next_time_step(params, p, boundary),
            Solver::Pbf => pbf::next_time_step(params, p, boundary),
        }
    }

    /// Force evaluations the next step takes: two for the design's leapfrog, one otherwise, plus
    /// one for kick-drift-kick right after a spawn or parameter change.
    pub fn evaluations_per_step(&self) -> u32 {
        if self.params.solver != Solver::Wcsph {
            return 1;
        }
        match self.params.integrator {
            Integrator::Leapfrog => 2,
            Integrator::SymplecticEuler => 1,
            Integrator::KickDriftKick => {
                let joined = self.boundary.membership() != self.boundary_membership;
                1 + (self.forces_stale || joined) as u32
            }
        }
    }

    /// Advances the simulation by one time step with the selected integrator and time-step rule.
    /// A step that goes unstable is rolled back to the last checkpoint and the next step retries
    /// at half the dt (see [`crate::rollback`]); with rollback off, or out of retries, the state
    /// goes back to the last good one and the solver freezes (see [`Self::unstable_step`]).
    pub fn step(&mut self) {
        if self.unstable_step.is_some() {
            return;
        }
        if self.boundary.membership() != self.boundary_membership {
            self.boundary_membership = self.boundary.membership();
            self.forces_stale = true;
        }
        let state = &mut self.rollback_state;
        if !self.rollback.enabled || state.checkpoint_due(&self.rollback, self.step_count) {
            self.checkpoint.copy_from(&self.particles);
            self.checkpoint_time = self.time;
            state.saved(self.step_count);
        }
        let step_dt = StepDt {
            scale: state.dt_scale(),
            remaining: self.frame_remaining,
        };
        let dt = self.advance(step_dt);
        let p = &mut self.particles;
        apply_pumps(&self.pumps, &p.position, &mut p.velocity, dt);
        let after = StepExtremes::measure(&p.velocity, &p.acceleration);
        let unstable = after.is_unstable_for(self.params.solver, dt, self.params.smoothing_radius);
        match self.rollback_state.after_check(&self.rollback, unstable) {
            Verdict::Stable => {
                self.last_dt = dt;
                self.step_count += 1;
                self.time += dt as f64;
                self.step_whitewater(dt);
            }
            Verdict::Retry => self.restore_checkpoint(),
            Verdict::Freeze => {
                let failed = self.step_count + 1;
                self.restore_checkpoint();
                self.unstable_step = Some(failed);
            }
        }
    }

    /// Advances the simulation by `duration` seconds (a game frame's time) in as many steps as
    /// the time-step rule needs, at most `max_steps`: the frame is split into equal steps no
    /// longer than the rule's dt, so it ends on its time (see [`crate::frame_budget`]). A
    /// non-finite or non-positive `duration` takes no step.
    pub fn advance_by(&mut self, duration: f32, max_steps: u32) -> FrameAdvance {
        let start = self.time;
        let mut steps = 0;
        if duration.is_finite() && duration > 0.0 {
            let end = start + duration as f64;
            while steps < max_steps && self.unstable_step.is_none() {
                let remaining = (end - self.time) as f32;
                if remaining <= FRAME_DONE {
                    break;
                }
                self.frame_remaining = Some(remaining);
                self.step();
                steps += 1;
            }
            self.frame_remaining = None;
        }
        FrameAdvance {
            steps,
            simulated: self.time - start,
        }
    }

    /// The state, step count and time of the checkpoint become current again.
    fn restore_checkpoint(&mut self) {
        self.particles.copy_from(&self.checkpoint);
        self.step_count = self.rollback_state.checkpoint_step;
        self.time = self.checkpoint_time;
        self.forces_stale = true;
    }

    /// One step of the parameters' solver at the dt `step_dt` makes of the rule's; returns its
    /// dt.
    fn advance(&mut self, step_dt: StepDt) -> f32 {
        let colliders = self.boundary.collider_list();
        let guard = self.guard(&colliders);
        let stale = self.forces_stale;
        let solver = self.params.solver;
        let (parts, wcsph, dfsph, pbf) = self.split();
        // Each evaluation's force on the bodies, the solves' statistics, and whether the step
        // leaves the accelerations stale (PBF's end on positions, not on a force evaluation).
        let (dt, corrections, forces, stats, leaves_stale) = match solver {
            Solver::Wcsph => {
                let mut step = wcsph::WcsphStep {
                    parts,
                    scratch: wcsph,
                };
                let o = step.advance(step_dt, stale, &guard);
                (o.dt, o.corrections, o.forces, SolverStats::default(), false)
            }
            Solver::Dfsph => {
                let mut step = dfsph::DfsphStep {
                    parts,
                    scratch: dfsph,
                };
                let o = step.advance(step_dt, stale, &guard);
                (o.dt, o.corrections, vec![o.forces], o.stats, false)
            }
            Solver::Pbf => {
                let mut step = pbf::PbfStep {
                    parts,
                    scratch: pbf,
                };
                let o = step.advance(step_dt, &guard);
                (o.dt, o.corrections, vec![o.forces], o.stats, true)
            }
        };
        for evaluation in forces {
            self.record_body_forces(evaluation);
        }
        self.solver_stats = stats;
        self.forces_stale = leaves_stale;
        self.boundary_corrections += corrections;
        dt
    }

    /// The parts the solvers' steps borrow, and their scratch.
    fn split(
        &mut self,
    ) -> (
        SolverParts<'_>,
        &mut wcsph::WcsphScratch,
        &mut dfsph::DfsphScratch,
        &mut pbf::PbfScratch,
    ) {
        let parts = SolverParts {
            params: &self.params,
            neighbors: &mut self.neighbors,
            particles: &mut self.particles,
            boundary: &mut self.boundary,
            timings: &mut self.timings,
            sort_scratch: &mut self.scratch,
        };
        (parts, &mut self.wcsph, &mut self.dfsph, &mut self.pbf)
    }

    /// Adds one evaluation's (or one DFSPH or PBF step's) force on each body to the sums.
    fn record_body_forces(&mut self, forces: Vec<BodyForceSum>) {
        record_body_forces(
            &mut self.body_force_sums,
            &mut self.last_body_forces,
            forces,
        );
    }

    /// What the pressure solves of the last step did (zeros with WCSPH).
    pub fn solver_stats(&self) -> SolverStats {
        self.solver_stats
    }

    /// Wall-clock time per stage accumulated since creation or [`Self::reset_timings`].
    pub fn timings(&self) -> &StageTimings {
        &self.timings
    }

    /// Zeroes the stage timings.
    pub fn reset_timings(&mut self) {
        self.timings = StageTimings::default();
    }

    /// Diagnostics of the current state.
    pub fn diagnostics(&self) -> Diagnostics {
        let p = &self.particles;
        Diagnostics::measure(
            &self.params,
            &self.container,
            &DiagnosticsInput {
                position: &p.position,
                velocity: &p.velocity,
                density: &p.density,
            },
        )
    }

    /// Mean number of neighbour candidates visited per particle (before the distance check).
    pub fn mean_candidates(&self) -> f32 {
        let p = &self.particles.position;
        if p.is_empty() {
            return 0.0;
        }
        let total: usize = p
            .par_iter()
            .map(|&x| self.neighbors.candidate_count(x))
            .sum();
        total as f32 / p.len() as f32
    }
}
