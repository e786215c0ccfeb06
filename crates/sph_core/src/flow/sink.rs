//! Sinks: drain volumes that remove the particles inside them and count them
//! ([`crate::CpuSolver::drain`]). Particles are conserved otherwise: initial + emitted − drained
//! = live, at every step.

use crate::flow::region::Region;
use crate::params::ParamError;
use glam::Vec3;

/// A drain: while open, every particle inside its box is removed.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "bevy_reflect", derive(bevy_reflect::Reflect))]
pub struct Sink {
    /// The drain's volume.
    pub region: Region,
    /// Whether it drains (a closed drain removes nothing).
    pub open: bool,
}

impl Sink {
    /// Checks the box.
    pub fn validate(&self) -> Result<(), ParamError> {
        self.region.validate("sink.region")
    }

    /// Whether the sink is open and `x` lies inside it.
    #[inline]
    pub fn drains(&self, x: Vec3) -> bool {
        self.open && self.region.contains(x)
    }
}

/// Whether any of `sinks` drains a particle at `x`.
#[inline]
pub fn drained_by_any(sinks: &[Sink], x: Vec3) -> bool {
    sinks.iter().any(|s| s.drains(x))
}
