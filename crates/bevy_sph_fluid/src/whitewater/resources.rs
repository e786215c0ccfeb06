//! Whitewater's resources: [`SphWhitewater`] (on, with its settings) and [`SphDiffuseParticles`]
//! (the diffuse particles for drawing).

use bevy::prelude::*;
use bevy::render::storage::ShaderBuffer;
use sph_core::whitewater::pool::DiffuseKind;
use sph_core::whitewater::settings::WhitewaterSettings;

/// Whitewater on, with these settings and a pool of `capacity` diffuse particles. Insert the
/// resource to turn it on, change it to restart the pool with new settings, remove it to turn it
/// off. A setting out of range is refused by name in [`SphStats::whitewater_error`](crate::api::SphStats::whitewater_error), and the
/// whitewater running before (or none) stays.
#[derive(Resource, Clone, Copy, Debug, PartialEq)]
pub struct SphWhitewater {
    /// Potentials' limits, rates, classes and motion.
    pub settings: WhitewaterSettings,
    /// The most diffuse particles at once (1 ..= 2^24); the ones shed beyond are counted in
    /// [`SphWhitewaterCounts::dropped`](crate::api::SphWhitewaterCounts::dropped).
    pub capacity: u32,
}

impl Default for SphWhitewater {
    /// The default settings and room for 65,536 diffuse particles.
    fn default() -> Self {
        Self {
            settings: WhitewaterSettings::default(),
            capacity: 65_536,
        }
    }
}

/// The diffuse particles as of the last frame, for drawing (empty while whitewater is off).
#[derive(Resource, Clone, Debug, Default)]
pub struct SphDiffuseParticles {
    /// Positions [m] (CPU backend; the GPU backend's stay on the device, in `buffer`).
    pub position: Vec<Vec3>,
    /// Each one's class: spray, foam or bubble (CPU backend).
    pub kind: Vec<DiffuseKind>,
    /// The particles in a buffer of the pool's capacity, what the surface draws: one
    /// `vec4<f32>` a slot, xyz the position and w the class ([`diffuse_class_w`]; negative: an
    /// empty slot). `None` while whitewater is off.
    pub buffer: Option<Handle<ShaderBuffer>>,
    /// The slots of `buffer` worth drawing, `0..slots`: the live particles on the CPU backend,
    /// the highest slot used so far on the GPU backend (as last read back).
    pub slots: u32,
}

/// The drawing buffer's w of an empty slot.
pub const EMPTY_SLOT_W: f32 = -1.0;

/// The class of a diffuse particle as the drawing buffer's w: 0 spray, 1 foam, 2 bubble.
pub fn diffuse_class_w(kind: DiffuseKind) -> f32 {
    match kind {
        DiffuseKind::Spray => 0.0,
        DiffuseKind::Foam => 1.0,
        DiffuseKind::Bubble => 2.0,
    }
}
