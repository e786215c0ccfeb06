//! Scenes as data: the RON scene file's format ([`spec`]), how a file is parsed, checked and
//! built into a scene ([`build`], [`setup`]), where an error is ([`error`]), the scene's named
//! controls ([`controls`]), and the mutations the fuzz test loads ([`mutations`]).
//!
//! The file's types are re-exported here: `sph_core::scene::SceneFile`.

pub mod build;
pub mod controls;
pub mod error;
pub mod mutations;
pub mod setup;
pub mod spec;
pub mod whitewater;

pub use error::SceneError;
pub use setup::{BodyMass, Hinge, SceneCollider, SceneProbe, SceneSetup};
pub use spec::*;
