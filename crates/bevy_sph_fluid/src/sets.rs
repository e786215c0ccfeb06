//! The plugin's system sets and its step schedule: the lowest module, imported by the ones that
//! add systems, importing none of them.

use bevy::ecs::schedule::ScheduleLabel;
use bevy::prelude::*;

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

/// The public set of the render world's stage encoder in the [`SphStep`] schedule: it encodes
/// the passes of the scene's stage list (`render::stages::stage_list`) for one force evaluation.
#[derive(SystemSet, Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct SphGraphSystems;

/// One force evaluation, run by `sph_simulate` (Bevy's `RenderGraph` schedule, before the camera
/// driver) as often as the integrator and the substeps need: substeps and the design's
/// two-evaluation leapfrog repeat the stages in an interleaved order that a once-per-frame chain
/// could not express.
#[derive(ScheduleLabel, Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct SphStep;
