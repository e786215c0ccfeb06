//! The plugin backend: `SphFluidPlugin` in a headless Bevy app (its GPU passes, or its CPU
//! backend when avian moves a scene file's bodies), stepped in frames of `substeps` and waited
//! for, its state read back on demand.

use super::{IterationTotals, Simulation, State};
use crate::scenarios::{Bodies, Scenario, ScenarioCollider, Setup};
use crate::scene_run::ProbeLog;
use bevy::prelude::*;
use bevy_sph_fluid::headless;
use bevy_sph_fluid::prelude::*;
use sph_core::Rollback;
use std::time::Instant;

/// Every probe reading the GPU app delivered.
#[derive(Resource, Default)]
struct ProbeReadings(Vec<bevy_sph_fluid::SphProbeReading>);

fn collect_probe_readings(
    mut reader: MessageReader<bevy_sph_fluid::SphProbeReading>,
    mut out: ResMut<ProbeReadings>,
) {
    out.0.extend(reader.read().copied());
}

/// The plugin in a headless app (its GPU passes, or its CPU backend); the scenario's colliders
/// are `SphCollider` entities whose transforms follow their lifts frame by frame, and with
/// [`Bodies::Avian`] a scene file's dynamic and hinged colliders are avian bodies that the
/// water moves (avian on the water's clock, `SphWaterTime`).
pub struct AppSimulation {
    app: App,
    backend: SphBackend,
    /// The CPU backend's pressure iterations, summed frame by frame.
    cpu_iterations: IterationTotals,
    /// The scene file's probe entities, in the file's order.
    probes: Vec<Entity>,
    adapter: String,
    substeps: u32,
    rollback: Rollback,
    colliders: Vec<(ScenarioCollider, Entity)>,
    container: Entity,
    /// Particles of the setup's blocks, before any is left out inside a collider.
    block_particles: u64,
}

impl AppSimulation {
    /// Builds the app, spawns the scenario and takes no step yet (shaders compile on the first).
    pub fn new(setup: &Setup, backend: SphBackend, substeps: u32) -> Result<Self, String> {
        if !setup.walls {
            return Err(
                "--walls off is CPU only (the GPU backend always samples the walls)".into(),
            );
        }
        let adapter = match backend {
            SphBackend::Gpu => headless::gpu_adapter()?,
            SphBackend::Cpu => "cpu".into(),
        };
        let extras = setup.extras.clone().unwrap_or_default();
        let avian = extras.bodies == Bodies::Avian;
        let s = &setup.scene;
        let mut app = headless::headless_app_with(
            DefaultPlugins.build().disable::<bevy::winit::WinitPlugin>(),
            setup.capacity.max(1) as u32,
            backend,
            backend == SphBackend::Gpu,
            |app| {
                if avian {
                    app.add_plugins(avian3d::prelude::PhysicsPlugins::new(SphWaterTime));
                }
            },
        );
        app.insert_resource(SphParams(s.params));
        if let Some(settings) = setup.whitewater.filter(|_| backend == SphBackend::Gpu) {
            // On the device, as a game runs it: once a step, after the step's first sort.
            app.insert_resource(SphWhitewater {
                settings,
                capacity: setup.whitewater_capacity() as u32,
            });
        }
        let container = app.world_mut().spawn(SphContainer(s.container)).id();
        if setup.scenario == Scenario::Hydrostatic {
            // The tank's walls must carry the water's weight. Only this scenario asks, because the
            // GPU sums the reactions only while someone reads them.
            app.world_mut()
                .entity_mut(container)
                .insert(SphWallForce::default());
        }
        if let Some(friction) = setup.wall_friction {
            app.world_mut()
                .entity_mut(container)
                .insert(SphWallSlip(sph_core::Slip::NoSlip { friction }));
        }
        if avian {
            // As a scene asset's: the container's walls, and the colliders below, become avian
            // bodies (static, kinematic, dynamic of the file's mass, hinged).
            app.world_mut()
                .entity_mut(container)
                .insert(SphSceneMember(container));
        }
        app.update();
        let colliders = setup
            .colliders
            .iter()
            .enumerate()
            .map(|(k, c)| {
                let at = c.at(0.0);
                let mut entity = app.world_mut().spawn((
                    SphCollider {
                        shape: at.shape,
                        motion: at.motion,
                        slip: at.slip,
                    },
                    Transform::from_translation(at.pose.translation)
                        .with_rotation(at.pose.rotation),
                ));
                if avian {
                    entity.insert(SphSceneMember(container));
                    let written = extras.colliders.get(k);
                    if let Some(mass) = written.and_then(|w| w.body) {
                        entity.insert(bevy_sph_fluid::scene_asset::SphDynamicBody(mass));
                    }
                    if let Some(hinge) = written.and_then(|w| w.hinge) {
                        entity.insert(bevy_sph_fluid::scene_asset::SphHinge(hinge));
                    }
                }
                (c.clone(), entity.id())
            })
            .collect();
        // Two frames: the colliders' transforms propagate, then the blocks spawn around them.
        app.update();
        app.update();
        for (k, block) in s.blocks.iter().enumerate() {
            app.world_mut().spawn(SphBlockSpawn {
                block: *block,
                velocity: extras
                    .block_velocities
                    .get(k)
                    .copied()
                    .unwrap_or(Vec3::ZERO),
            });
        }
        for emitter in setup.emitter.iter().chain(&extras.emitters) {
            app.world_mut().spawn(SphEmitter(emitter.clone()));
        }
        for (_, pump) in &extras.pumps {
            app.world_mut()
                .spawn(bevy_sph_fluid::SphPump::from_world(pump));
        }
        for sink in extras.sink_list() {
            app.world_mut()
                .spawn(bevy_sph_fluid::SphSink::from_world(&sink));
        }
        let probes = extras
            .probes
            .iter()
            .map(|p| {
                let device = bevy_sph_fluid::SphProbe::from_world(&p.kind, p.every_steps);
                app.world_mut().spawn(device).id()
            })
            .collect();
        app.init_resource::<ProbeReadings>()
            .add_systems(Last, collect_probe_readings);
        app.update();
        // Report what ran, not what was asked for: the plugin falls back to the CPU when the
        // adapter cannot run its passes, and a GPU figure measured on the CPU is a wrong figure.
        let ran = app.world().resource::<SphStats>();
        if ran.backend != backend {
            return Err(format!(
                "the {backend:?} backend was asked for but the plugin runs {:?} (adapter {:?}, \
                 probed {adapter:?}): {}",
                ran.backend,
                ran.adapter,
                ran.fallback_reason
                    .as_deref()
                    .unwrap_or("no reason recorded")
            ));
        }
        let adapter = ran.adapter.clone();
        Ok(Self {
            app,
            backend,
            cpu_iterations: IterationTotals::default(),
            probes,
            adapter,
            substeps: substeps.max(1),
            rollback: setup.rollback,
            colliders,
            container,
            block_particles: setup.scene.particle_count() as u64,
        })
    }

    fn stats(&self) -> &SphStats {
        self.app.world().resource::<SphStats>()
    }

    /// Updates (paused) until the GPU clock's readback has caught up with the steps taken, so
    /// time, dt and health are current.
    fn sync_clock(&mut self) {
        // Bounded by time rather than a count of updates: on a loaded machine (CI's tests in
        // parallel on two cores) a fixed count of 100 waited updates can be too few (pipe_fill.ron
        // was seen stopping at 2.23 s of 2).
        let start = Instant::now();
        while start.elapsed() < std::time::Duration::from_secs(60) {
            let stats = self.stats();
            // `clock_steps_run`, not `clock_steps`: a rollback takes the clock's step back, and
            // a wait for it to reach the steps dispatched would last the whole bound.
            if stats.clock_steps_run >= headless::steps_taken(&self.app)
                || stats.health.is_unstable()
            {
                return;
            }
            // The readback maps once the device is done: without the wait, a busy machine (CI's
            // tests in parallel) went through the 100 updates before it arrived, the run planned
            // its next chunk from a clock 0.2 s old, and pipe_fill.ron on the GPU ended at 2.2 s
            // of the 2 asked.
            headless::wait_for_gpu(&self.app);
            self.app.update();
        }
    }
}

impl Simulation for AppSimulation {
    fn advance(&mut self, steps: u32) -> Result<(u32, f64), String> {
        let t = Instant::now();
        let mut done = 0;
        while done < steps {
            let k = self.substeps.min(steps - done);
            let before = headless::steps_taken(&self.app);
            // The frame's k steps see the lifted colliders at their mid-frame pose.
            let dt = self.app.world().resource::<SphParams>().time_step as f64;
            let t = self.time() + 0.5 * k as f64 * dt;
            for (c, entity) in &self.colliders {
                if c.moves() {
                    let at = c.at(t);
                    if let Some(mut transform) = self.app.world_mut().get_mut::<Transform>(*entity)
                    {
                        transform.translation = at.pose.translation;
                    }
                }
            }
            self.app.insert_resource(SphControl {
                running: true,
                substeps: k,
                rollback: self.rollback,
                // Held bodies do not move, and avian's on the water's clock are moved by the device
                // on the GPU: no force lag to keep short.
                max_body_frame_time: None,
                ..default()
            });
            let mut frames = 0;
            while headless::steps_taken(&self.app) == before {
                self.app.update();
                if self.backend == SphBackend::Cpu {
                    let stats = self.app.world().resource::<SphStats>();
                    let n = stats.frame_steps as u64;
                    let sums = &mut self.cpu_iterations;
                    sums.steps += n;
                    sums.density += (stats.pressure_iterations_mean * n as f32).round() as u64;
                    sums.density_max = sums.density_max.max(stats.pressure_iterations_max);
                    sums.divergence += (stats.divergence_iterations_mean * n as f32).round() as u64;
                }
                frames += 1;
                if frames > 2000 {
                    return Err(format!(
                        "the plugin stopped stepping: {:?}",
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
            pressures: s.pressures,
            ids: s.ids,
        })
    }

    fn stage_ms(&self) -> Vec<(String, f64)> {
        self.stats().stage_ms.clone()
    }

    fn whitewater_counts(&self) -> Option<SphWhitewaterCounts> {
        self.stats().whitewater
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

    fn boundary_corrections(&self) -> (u64, u64) {
        let s = self.stats();
        (s.boundary_corrections, s.wall_corrections)
    }

    fn spawns_inside_colliders(&self) -> u64 {
        // The plugin counts every spawn's left-outs, the emitters' too; the blocks' are those
        // its initial particles lack.
        self.block_particles
            .saturating_sub(self.stats().particles_initial)
    }

    /// The latest frame's forces as the plugin wrote them into `SphColliderForce` (summed on
    /// the device, read back a frame or two late), weighted as one sample.
    fn take_collider_forces(&mut self) -> Option<(Vec<sph_core::BodyForce>, u64)> {
        let world = self.app.world();
        let forces = self
            .colliders
            .iter()
            .map(|(_, entity)| {
                let f = world
                    .get::<SphColliderForce>(*entity)
                    .copied()
                    .unwrap_or_default();
                sph_core::BodyForce {
                    force: f.force,
                    torque: f.torque,
                }
            })
            .collect();
        Some((forces, 1))
    }

    fn wall_force(&self) -> Option<Vec3> {
        let f = self.app.world().get::<SphWallForce>(self.container)?;
        Some(f.force)
    }

    fn iterations(&self) -> IterationTotals {
        if self.backend == SphBackend::Cpu {
            return self.cpu_iterations;
        }
        let world = self.app.world();
        let params = world.resource::<SphParams>();
        match params.solver {
            // DFSPH's solves count their iterations on the device (the clock, read back).
            sph_core::Solver::Dfsph => world
                .get_resource::<bevy_sph_fluid::shared::ClockReadback>()
                .and_then(|c| c.latest)
                .map(|clock| IterationTotals {
                    steps: clock.step as u64,
                    density: clock.density_iterations as u64,
                    density_max: clock.density_iterations_max,
                    divergence: clock.divergence_iterations as u64,
                    cut_short: clock.solves_cut_short(),
                })
                .unwrap_or_default(),
            // The device runs PBF's fixed count of Jacobi iterations every step (WCSPH has
            // none).
            solver => {
                let per_step = if solver == sph_core::Solver::Pbf {
                    params.pbf.iterations
                } else {
                    0
                };
                let steps = self.steps();
                IterationTotals {
                    steps,
                    density: steps * per_step as u64,
                    density_max: per_step,
                    divergence: 0,
                    cut_short: 0,
                }
            }
        }
    }

    fn flow_counts(&self) -> (u64, u64) {
        let stats = self.stats();
        (stats.particles_emitted, stats.particles_drained)
    }

    fn probe_log(&self) -> ProbeLog {
        let mut log = ProbeLog::new_for(self.probes.len());
        if let Some(readings) = self.app.world().get_resource::<ProbeReadings>() {
            for r in &readings.0 {
                if let Some(k) = self.probes.iter().position(|&e| e == r.probe) {
                    log.record(k, r.step, r.sim_time, r.reading);
                }
            }
        }
        log
    }

    /// The colliders at their entities' poses (scripted lifts and paths, or avian's moves).
    fn colliders_now(&self, colliders: &[ScenarioCollider]) -> Vec<sph_core::Collider> {
        let world = self.app.world();
        colliders
            .iter()
            .zip(&self.colliders)
            .map(|(c, (_, entity))| {
                let mut now = c.at(self.time());
                if let Some(transform) = world.get::<GlobalTransform>(*entity) {
                    let (_, rotation, translation) = transform.to_scale_rotation_translation();
                    now.pose.translation = translation;
                    now.pose.rotation = rotation;
                }
                now
            })
            .collect()
    }
}
