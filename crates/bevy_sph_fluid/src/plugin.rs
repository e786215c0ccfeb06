//! [`SphFluidPlugin`]: registers the API, the main-world systems, the readback and the render
//! world, in that order.

use crate::api::*;
use crate::sets::SphSystems;
use crate::shared::SphSimulation;
use crate::{cpu_buffers, readback, render, scene_asset, simulation, whitewater};
use bevy::ecs::schedule::{InternedScheduleLabel, ScheduleLabel};
use bevy::prelude::*;

/// The SPH water plugin. Add it after `DefaultPlugins`.
#[derive(Clone, Debug)]
pub struct SphFluidPlugin {
    /// Particle slots in every buffer (fixed for the app's life).
    pub capacity: u32,
    /// The requested backend.
    pub backend: SphBackend,
    /// The main-world schedule that runs the simulation systems (default `Update`).
    pub schedule: InternedScheduleLabel,
}

impl Default for SphFluidPlugin {
    fn default() -> Self {
        Self {
            capacity: 32_768,
            backend: SphBackend::Gpu,
            schedule: Update.intern(),
        }
    }
}

impl SphFluidPlugin {
    /// A plugin with `capacity` particle slots on the requested backend.
    pub fn new(capacity: u32, backend: SphBackend) -> Self {
        Self {
            capacity,
            backend,
            ..Default::default()
        }
    }
}

impl Plugin for SphFluidPlugin {
    fn build(&self, app: &mut App) {
        app.register_type::<SphParams>()
            .register_type::<SphControl>()
            .register_type::<SphStats>()
            .register_type::<SphContainer>()
            .register_type::<SphCollider>()
            .register_type::<SphWallSlip>()
            .register_type::<SphColliderForce>()
            .register_type::<SphWallForce>()
            .register_type::<SphColliderMass>()
            .register_type::<SphRigidBody>()
            .init_resource::<crate::colliders::SphColliderMap>()
            .init_resource::<SphParams>()
            .init_resource::<SphControl>()
            .init_resource::<SphStats>()
            .insert_resource(SphCapacity(self.capacity))
            .register_type::<SphCapacity>()
            .add_message::<SphReadbackRequest>()
            .add_message::<SphSnapshot>()
            .insert_resource(SphSimulation::new(self.capacity, self.backend));
        app.configure_sets(
            self.schedule,
            (SphSystems::Prepare, SphSystems::Step, SphSystems::Writeback).chain(),
        );
        simulation::add_systems(app, self.schedule);
        readback::add_systems(app, self.schedule);
        whitewater::add_systems(app, self.schedule);
        cpu_buffers::add_systems(app, self.schedule);
        scene_asset::add_systems(app, self.schedule);
        crate::flow::add_systems(app, self.schedule);
        crate::moved_bodies::add_systems(app, self.schedule);
        #[cfg(feature = "avian")]
        crate::avian_coupling::add_systems(app, self.schedule);
        // Spawns consumed by the render world are cleared before the next frame's spawners run.
        app.add_systems(First, simulation::clear_frame);
        render::build(app);
        crate::surface::build(app, self.schedule);
    }

    fn finish(&self, app: &mut App) {
        simulation::resolve_backend(app);
    }
}
