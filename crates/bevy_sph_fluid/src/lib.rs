#![warn(missing_docs)]
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
//! Data flows one way, and so do the modules' imports: [`api`] (resources, components,
//! messages) and `sets` at the bottom; [`shared`] (the frame plan and the render world's
//! feedback); the main-world systems (`simulation`, `readback`); the render world ([`render`]:
//! extract -> buffers -> the stage list's passes); the plugin that wires them; [`headless`] apps
//! on top. No module imports one that imports it back (`tests/module_imports.rs`).

pub mod api;
#[cfg(feature = "avian")]
pub mod avian_coupling;
pub mod colliders;
mod cpu_buffers;
pub mod dfsph_budget;
pub mod flow;
pub mod headless;
pub mod mesh_collider;
pub mod moved_bodies;
mod plugin;
mod readback;
pub mod render;
pub mod scene_asset;
mod sets;
pub mod shared;
mod simulation;
pub mod surface;
pub mod whitewater;

pub use api::*;
#[cfg(feature = "avian")]
pub use avian_coupling::SphWaterTime;
pub use flow::{SphProbe, SphProbeKind, SphProbeReading, SphPump, SphSink};
pub use plugin::SphFluidPlugin;
pub use scene_asset::{
    SphDynamicBody, SphHinge, SphScene, SphSceneAsset, SphSceneControls, SphSceneMember,
};
pub use sets::{SphGraphSystems, SphStep, SphSystems};
pub use surface::settings::{SphSurface, SphSurfaceDebugView, SphSurfaceError, SphSurfaceStatus};
pub use whitewater::{SphDiffuseParticles, SphWhitewater};

/// Commonly used items.
pub mod prelude {
    pub use crate::api::*;
    #[cfg(feature = "avian")]
    pub use crate::avian_coupling::SphWaterTime;
    pub use crate::flow::{SphProbe, SphProbeKind, SphProbeReading, SphPump, SphSink};
    pub use crate::plugin::SphFluidPlugin;
    pub use crate::scene_asset::{SphScene, SphSceneAsset, SphSceneControls, SphSceneMember};
    pub use crate::sets::SphSystems;
    pub use crate::surface::settings::{
        SphSurface, SphSurfaceDebugView, SphSurfaceError, SphSurfaceStatus,
    };
    pub use crate::whitewater::{SphDiffuseParticles, SphWhitewater};
}
