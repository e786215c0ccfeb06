//! The CPU backend: the reference solver (`sph_core::CpuSolver`) stepped directly, with the
//! scenario's emitters, drains, probes and scripted colliders handled here step by step.

use super::{IterationTotals, Simulation, State};
use crate::scenarios::{ScenarioCollider, Setup};
use crate::scene_run::ProbeLog;
use bevy::prelude::Vec3;
use sph_core::{ColliderId, CpuSolver, PipeEmitter};
use std::time::Instant;

/// The CPU reference solver, with the scenario's emitter fed every step and its kinematic
/// colliders moved before every step.
pub struct CpuSimulation {
    solver: CpuSolver,
    emitters: Vec<PipeEmitter>,
    /// The scene file's drains and probes.
    sinks: Vec<sph_core::Sink>,
    probes: Vec<sph_core::scene::SceneProbe>,
    probe_log: ProbeLog,
    /// Particles emitted and drained since the start.
    flow_counts: (u64, u64),
    colliders: Vec<(ScenarioCollider, ColliderId)>,
    spawns_inside_colliders: u64,
    iterations: IterationTotals,
}

impl CpuSimulation {
    /// Builds the solver and spawns the scenario's blocks.
    pub fn new(setup: &Setup) -> Result<Self, String> {
        let s = &setup.scene;
        let mut solver = CpuSolver::new(s.params, s.container, setup.capacity.max(1))
            .map_err(|e| e.to_string())?;
        solver
            .set_rollback(setup.rollback)
            .map_err(|e| e.to_string())?;
        if !setup.walls {
            solver.set_wall_boundary(None);
        } else if let Some(friction) = setup.wall_friction {
            solver.set_wall_boundary(Some(sph_core::Slip::NoSlip { friction }));
        }
        let mut colliders = Vec::new();
        for c in &setup.colliders {
            let id = solver
                .add_collider(c.at(0.0))
                .map_err(|e| format!("collider {}: {e}", c.name))?;
            colliders.push((c.clone(), id));
        }
        let mut inside = 0;
        match &setup.extras {
            Some(extras) => {
                for (k, block) in s.blocks.iter().enumerate() {
                    let v = extras
                        .block_velocities
                        .get(k)
                        .copied()
                        .unwrap_or(Vec3::ZERO);
                    inside += solver.spawn(&block.positions(), v).inside_colliders;
                }
                solver
                    .set_pumps(&extras.pump_list())
                    .map_err(|e| e.to_string())?;
            }
            None => inside = solver.spawn(&s.positions(), Vec3::ZERO).inside_colliders,
        }
        let extras = setup.extras.clone().unwrap_or_default();
        Ok(Self {
            solver,
            emitters: setup
                .emitter
                .iter()
                .cloned()
                .chain(extras.emitters.iter().cloned())
                .collect(),
            sinks: extras.sink_list(),
            probe_log: ProbeLog::new(&extras.probes),
            probes: extras.probes,
            flow_counts: (0, 0),
            colliders,
            spawns_inside_colliders: inside as u64,
            iterations: IterationTotals::default(),
        })
    }

    /// Reads the probes that are due.
    fn measure_probes(&mut self) {
        let step = self.solver.step_count();
        let p = self.solver.particles();
        for (k, probe) in self.probes.iter().enumerate() {
            if self.probe_log.due(k, probe.every_steps, step) {
                let reading = probe.kind.measure(
                    self.solver.params(),
                    self.solver.container(),
                    &p.position,
                    &p.velocity,
                );
                self.probe_log.record(k, step, self.solver.time(), reading);
            }
        }
    }

    /// Moves the lifted colliders to their pose at the middle of the next step.
    fn move_colliders(&mut self) {
        let t = self.solver.time() + 0.5 * self.solver.last_time_step() as f64;
        for (c, id) in &self.colliders {
            if c.moves() {
                let at = c.at(t);
                // The pose is valid for every t (a translation along y of a valid collider).
                let _ = self.solver.set_collider_motion(
                    *id,
                    at.pose,
                    at.linear_velocity,
                    at.angular_velocity,
                );
            }
        }
    }
}

impl Simulation for CpuSimulation {
    fn advance(&mut self, steps: u32) -> Result<(u32, f64), String> {
        let t = Instant::now();
        for _ in 0..steps {
            for emitter in &mut self.emitters {
                let dt = self.solver.last_time_step();
                let emission = emitter.emit(dt);
                self.flow_counts.0 += self
                    .solver
                    .spawn(&emission.positions, emission.velocity)
                    .spawned as u64;
            }
            self.move_colliders();
            let before = self.solver.step_count();
            self.solver.step();
            if self.solver.step_count() > before {
                let stats = self.solver.solver_stats();
                self.iterations
                    .add(stats.density_iterations, stats.divergence_iterations);
            }
            self.flow_counts.1 += self.solver.drain(&self.sinks) as u64;
            self.measure_probes();
        }
        Ok((steps, t.elapsed().as_secs_f64() * 1e3))
    }

    fn time(&self) -> f64 {
        self.solver.time()
    }

    fn steps(&self) -> u64 {
        self.solver.step_count()
    }

    fn last_dt(&self) -> f32 {
        self.solver.last_time_step()
    }

    fn unstable_step(&self) -> Option<u64> {
        self.solver.unstable_step()
    }

    fn rollbacks(&self) -> u64 {
        self.solver.rollbacks()
    }

    fn state(&mut self) -> Result<State, String> {
        let p = self.solver.particles();
        Ok(State {
            positions: p.position.clone(),
            velocities: p.velocity.clone(),
            densities: p.density.clone(),
            pressures: p.pressure.clone(),
            ids: p.id.clone(),
        })
    }

    fn stage_ms(&self) -> Vec<(String, f64)> {
        let steps = self.solver.step_count().max(1) as f64;
        self.solver
            .timings()
            .stages()
            .iter()
            .map(|(name, t)| (name.to_string(), t.as_secs_f64() * 1e3 / steps))
            .collect()
    }

    fn dispatches_per_step(&self) -> u32 {
        0
    }

    fn gpu_bytes_per_particle(&self) -> u32 {
        0
    }

    fn adapter(&self) -> String {
        "cpu".into()
    }

    fn boundary_corrections(&self) -> (u64, u64) {
        let c = self.solver.corrections();
        (c.total(), c.walls)
    }

    fn spawns_inside_colliders(&self) -> u64 {
        self.spawns_inside_colliders
    }

    fn wall_force(&self) -> Option<Vec3> {
        Some(self.solver.wall_force().force)
    }

    fn take_collider_forces(&mut self) -> Option<(Vec<sph_core::BodyForce>, u64)> {
        let n = self.solver.collider_force_evaluations();
        let forces = self.solver.take_collider_forces();
        let by_id: Vec<sph_core::BodyForce> = self
            .colliders
            .iter()
            .map(|(_, id)| {
                forces
                    .iter()
                    .find(|(k, _)| k == id)
                    .map(|(_, f)| *f)
                    .unwrap_or_default()
            })
            .collect();
        Some((by_id, n))
    }

    fn iterations(&self) -> IterationTotals {
        self.iterations
    }

    fn flow_counts(&self) -> (u64, u64) {
        self.flow_counts
    }

    fn probe_log(&self) -> ProbeLog {
        self.probe_log.clone()
    }
}
