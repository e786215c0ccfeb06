//! `CpuSolver`'s optional whitewater ([`crate::whitewater`]): off unless asked for, and then it
//! costs nothing; when on, the diffuse particles take a step over the water after every stable
//! step. They never act on the water.

use super::CpuSolver;
use crate::params::ParamError;
use crate::whitewater::ihmsen2012::{FluidView, Whitewater};
use crate::whitewater::settings::{check_capacity, WhitewaterSettings};

pub use crate::whitewater::settings::MAX_WHITEWATER_CAPACITY;

/// The seed of a solver's whitewater: the same scene sheds the same diffuse particles.
pub const WHITEWATER_SEED: u64 = 0x5EED;

impl CpuSolver {
    /// Turns whitewater on with `settings` and a pool of `capacity` diffuse particles (an empty
    /// pool; one turned on before is dropped), or off with `None`. Refused with the field's name
    /// when a setting or the capacity (1 ..= [`MAX_WHITEWATER_CAPACITY`]) is out of range;
    /// nothing changes then.
    pub fn set_whitewater(
        &mut self,
        whitewater: Option<(WhitewaterSettings, usize)>,
    ) -> Result<(), ParamError> {
        let Some((settings, capacity)) = whitewater else {
            self.whitewater = None;
            return Ok(());
        };
        settings.validate()?;
        check_capacity(capacity)?;
        self.whitewater = Some(Box::new(self.empty_whitewater(settings, capacity)));
        Ok(())
    }

    /// An empty pool in this solver's container, seeded as every solver's is.
    fn empty_whitewater(&self, settings: WhitewaterSettings, capacity: usize) -> Whitewater {
        Whitewater::new(settings, self.container, capacity, WHITEWATER_SEED)
    }

    /// The diffuse particles, while whitewater is on.
    pub fn whitewater(&self) -> Option<&Whitewater> {
        self.whitewater.as_deref()
    }

    /// One whitewater step of `dt` over the water as it is now.
    pub(super) fn step_whitewater(&mut self, dt: f32) {
        let Some(white) = self.whitewater.as_deref_mut() else {
            return;
        };
        let p = &self.particles;
        // The solver's own grid over this container at this h exists, so the view's can too.
        let Ok(fluid) = FluidView::new(
            &p.position,
            &p.velocity,
            &self.container,
            self.params.smoothing_radius,
        ) else {
            return;
        };
        white.step(&fluid, self.params.gravity, self.params.spacing(), dt);
    }

    /// Empties the whitewater's pool, keeping its settings (with [`Self::clear`]).
    pub(super) fn clear_whitewater(&mut self) {
        if let Some(white) = self.whitewater.as_deref() {
            let empty = self.empty_whitewater(white.settings, white.pool.capacity());
            self.whitewater = Some(Box::new(empty));
        }
    }
}
