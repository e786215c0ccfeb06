//! One interface over the two backends: the CPU solver stepped directly, and the plugin's GPU
//! passes in a headless app (steps in frames of `substeps`, waited for, state read back on demand).

use crate::scenarios::Setup;
use bevy::prelude::*;
use bevy_sph_fluid::headless;
use bevy_sph_fluid::prelude::*;
use sph_core::{CpuSolver, PipeEmitter, Rollback};
use std::time::Instant;

/// The particle state a scenario measures.
#[derive(Clone, Debug, Default)]
pub struct State {
    /// Positions [m].
    pub positions: Vec<Vec3>,
    /// Velocities [m/s].
    pub velocities: Vec<Vec3>,
    /// Densities [kg/m³].
    pub densities: Vec<f32>,
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
}

/// The CPU reference solver, with the scenario's emitter fed every step.
pub struct CpuSimulation {
    solver: CpuSolver,
    emitter: Option<PipeEmitter>,
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
        solver.spawn(&s.positions(), Vec3::ZERO);
        Ok(Self {
            solver,
            emitter: setup.emitter.clone(),
        })
    }
}

impl Simulation for CpuSimulation {
    fn advance(&mut self, steps: u32) -> Result<(u32, f64), String> {
        let t = Instant::now();
        for _ in 0..steps {
            if let Some(emitter) = &mut self.emitter {
                let dt = self.solver.last_time_step();
                let emission = emitter.emit(dt);
                self.solver.spawn(&emission.positions, emission.velocity);
            }
            self.solver.step();
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
}

/// The plugin's GPU passes in a headless app.
pub struct GpuSimulation {
    app: App,
    adapter: String,
    substeps: u32,
    rollback: Rollback,
}

impl GpuSimulation {
    /// Builds the app, spawns the scenario and takes no step yet (shaders compile on the first).
    pub fn new(setup: &Setup, substeps: u32) -> Result<Self, String> {
        let adapter = headless::vulkan_adapter()?;
        let s = &setup.scene;
        let mut app = headless::headless_app(
            DefaultPlugins.build().disable::<bevy::winit::WinitPlugin>(),
            setup.capacity.max(1) as u32,
            SphBackend::Gpu,
            true,
        );
        headless::spawn_scene(&mut app, s);
        if let Some(emitter) = setup.emitter.clone() {
            app.world_mut().spawn(SphEmitter(emitter));
        }
        app.update();
        Ok(Self {
            app,
            adapter,
            substeps: substeps.max(1),
            rollback: setup.rollback,
        })
    }

    fn stats(&self) -> &SphStats {
        self.app.world().resource::<SphStats>()
    }

    /// Updates (paused) until the GPU clock's readback has caught up with the steps taken, so
    /// time, dt and health are current.
    fn sync_clock(&mut self) {
        for _ in 0..100 {
            let stats = self.stats();
            if stats.clock_steps >= headless::steps_taken(&self.app) || stats.health.is_unstable() {
                return;
            }
            self.app.update();
        }
    }
}

impl Simulation for GpuSimulation {
    fn advance(&mut self, steps: u32) -> Result<(u32, f64), String> {
        let t = Instant::now();
        let mut done = 0;
        while done < steps {
            let k = self.substeps.min(steps - done);
            let before = headless::steps_taken(&self.app);
            self.app.insert_resource(SphControl {
                running: true,
                substeps: k,
                rollback: self.rollback,
                ..default()
            });
            let mut frames = 0;
            while headless::steps_taken(&self.app) == before {
                self.app.update();
                frames += 1;
                if frames > 2000 {
                    return Err(format!(
                        "the GPU stopped stepping: {:?}",
                        self.stats().error
                    ));
                }
            }
            done += (headless::steps_taken(&self.app) - before) as u32;
        }
        self.app.insert_resource(SphControl {
            running: false,
            rollback: self.rollback,
            ..default()
        });
        headless::wait_for_gpu(&self.app);
        let ms = t.elapsed().as_secs_f64() * 1e3;
        self.sync_clock();
        Ok((done, ms))
    }

    fn time(&self) -> f64 {
        self.stats().sim_time
    }

    fn steps(&self) -> u64 {
        headless::steps_taken(&self.app)
    }

    fn last_dt(&self) -> f32 {
        self.stats().time_step
    }

    fn unstable_step(&self) -> Option<u64> {
        match self.stats().health {
            SphHealth::Unstable { step } => Some(step),
            _ => None,
        }
    }

    fn rollbacks(&self) -> u64 {
        self.stats().rollbacks
    }

    fn state(&mut self) -> Result<State, String> {
        let s = headless::snapshot(&mut self.app)?;
        Ok(State {
            positions: s.positions,
            velocities: s.velocities,
            densities: s.densities,
        })
    }

    fn stage_ms(&self) -> Vec<(String, f64)> {
        self.stats().stage_ms.clone()
    }

    fn dispatches_per_step(&self) -> u32 {
        self.stats().dispatches_per_step
    }

    fn gpu_bytes_per_particle(&self) -> u32 {
        self.stats().gpu_bytes_per_particle
    }

    fn adapter(&self) -> String {
        self.adapter.clone()
    }
}
