//! The main world's frame plan, copied into the render world every frame.

use crate::shared::{SphFrame, SphSimulation};
use bevy::prelude::*;
use bevy::render::Extract;

/// The main world's frame plan, in the render world.
#[derive(Resource, Clone, Default, Deref)]
pub struct ExtractedSphFrame(pub SphFrame);

pub(crate) fn extract_sph_frame(mut commands: Commands, sim: Extract<Res<SphSimulation>>) {
    commands.insert_resource(ExtractedSphFrame(sim.frame.clone()));
}
