//! The bodies' motion at the end of every step (`body_motion.wgsl`; CPU twin
//! `sph_core::bodies::engine_handoff::DeviceBody`): the step's force from the sums, the rigid
//! step, the engine's state, the contacts with the solids the device does not move
//! (`sph_core::bodies::solid_contact`), and at the frame's last step the frame's record.

use crate::render::buffers::Buf;
use crate::render::plan::EvaluationPlan;
use crate::render::stage::{Dispatch, GpuStage};
use bevy::asset::{embedded_asset, load_embedded_asset};
use sph_core::gpu_layout::GPU_MOVED_BODIES;
use sph_core::CpuStage;

/// One thread per collider slot; role 1 at the frame's last step (its record).
pub const STAGE: GpuStage = GpuStage {
    name: "sph_body_motion",
    cpu_twin: CpuStage::Bodies,
    embed: |app| embedded_asset!(app, "body_motion.wgsl"),
    shader: |server| load_embedded_asset!(server, "body_motion.wgsl"),
    bindings: &[
        Buf::BodyWords,
        Buf::BodyForces,
        Buf::Clock,
        Buf::Colliders,
        Buf::BodyContacts,
    ],
    workgroup_size: 32,
    roles: &[&[], &["FRAME_END"]],
    role: |plan: &EvaluationPlan| plan.move_bodies.map(|frame_end| frame_end as usize),
    dispatch: Dispatch::Threads(|_| GPU_MOVED_BODIES as u32),
    before: None,
    after: None,
};

#[cfg(test)]
mod tests {
    use super::*;

    /// The motion pass orders its rounds across the bodies with workgroup barriers, so one
    /// workgroup must hold every slot.
    #[test]
    fn one_workgroup_holds_every_body() {
        assert!(GPU_MOVED_BODIES <= STAGE.workgroup_size as usize);
    }
}
