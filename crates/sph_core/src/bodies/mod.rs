//! Rigid bodies the water carries, advanced at the water's own steps on the device: one step of
//! a body ([`rigid_step`]), its contacts with the solids the device does not move
//! ([`solid_contact`]), and how the device's body and the physics engine's hand each other what
//! only the other saw ([`engine_handoff`]), with the gap between their steps over a window
//! ([`engine_window`]) and the engine's push the device carries on between the engine's states
//! ([`engine_push`]). WGSL twins: `render/bodies/`.

pub mod engine_handoff;
pub mod engine_push;
pub mod engine_window;
pub mod rigid_step;
pub mod solid_contact;
