//! # bevy_sph_fluid
//!
//! `SphFluidPlugin`: SPH water whose every stage is a GPU compute pass in Bevy's render graph,
//! with the `sph_core` CPU solver as the reference and the fallback.
//!
//! ```no_run
//! use bevy::prelude::*;
//! use bevy_sph_fluid::prelude::*;
//! use sph_core::{BlockSpawn, BoxContainer};
//!
//! App::new()
//!     .add_plugins(DefaultPlugins)
//!     .add_plugins(SphFluidPlugin::default())
//!     .add_systems(Startup, |mut commands: Commands| {
//!         commands.spawn(SphContainer(BoxContainer::from_min_max(Vec3::ZERO, Vec3::splat(1.0))));
//!         let block = BlockSpawn::new(Vec3::ZERO, Vec3::new(0.3, 0.6, 0.3), 0.02);
//!         commands.spawn(SphBlockSpawn { block, velocity: Vec3::ZERO });
//!     })
//!     .run();
//! ```
//!
//! Data flows one way: [`SphParams`] and the spawner components (main world) are extracted
//! every frame, uploaded to structure-of-arrays GPU buffers, stepped by the stage systems of
//! [`SphGraphSystems`], and read back only on a [`SphReadbackRequest`].

pub mod api;
pub mod headless;
mod readback;
pub mod render;
mod simulation;

pub use api::*;
pub use render::SphGraphSystems;

use bevy::ecs::schedule::{InternedScheduleLabel, ScheduleLabel};
use bevy::prelude::*;

/// Commonly used items.
pub mod prelude {
    pub use crate::api::*;
    pub use crate::{SphFluidPlugin, SphSystems};
}

/// The public, chained phases of the main-world simulation systems, for users to order against.
#[derive(SystemSet, Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SphSystems {
    /// Container, reset and spawners turn into this frame's work.
    Prepare,
    /// The step (CPU backend) or the frame plan for the render world (GPU backend).
    Step,
    /// Statistics and readback results.
    Writeback,
}

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
            .init_resource::<SphParams>()
            .init_resource::<SphControl>()
            .init_resource::<SphStats>()
            .insert_resource(SphCapacity(self.capacity))
            .register_type::<SphCapacity>()
            .add_message::<SphReadbackRequest>()
            .add_message::<SphSnapshot>()
            .insert_resource(simulation::SphSimulation::new(self.capacity, self.backend));
        app.configure_sets(
            self.schedule,
            (SphSystems::Prepare, SphSystems::Step, SphSystems::Writeback).chain(),
        );
        simulation::add_systems(app, self.schedule);
        readback::add_systems(app, self.schedule);
        // Spawns consumed by the render world are cleared before the next frame's spawners run.
        app.add_systems(First, simulation::clear_frame);
        render::build(app);
    }

    fn finish(&self, app: &mut App) {
        simulation::resolve_backend(app);
        render::finish(app);
    }
}
