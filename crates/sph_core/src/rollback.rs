//! Rollback of unstable steps, shared by the CPU solver and the GPU `sph_time_step` pass (WGSL
//! twin: `bevy_sph_fluid/src/render/stages/time_step.wgsl` and `shaders/clock.wgsl`).
//!
//! A checkpoint of the particle state (positions, velocities, accelerations) is taken at the
//! start of a step when the previous step was checked and found stable, and at least
//! `checkpoint_interval` steps have passed since the last one (or particles were added, or there
//! is none yet). When the detector of [`crate::stability`] flags a step, the state, the step count
//! and the simulated time go back to the checkpoint and the time step is halved (a halving of
//! the scale applied to every dt the rule gives). After `max_retries` rollbacks without a new
//! checkpoint in between, the simulation is declared unstable and freezes, as without rollback.
//! The halved scale doubles back after [`RECOVERY_STEPS`] stable steps, up to 1.

use crate::params::ParamError;

/// Stable steps after a rollback (or the last recovery) before the dt scale doubles back.
pub const RECOVERY_STEPS: u32 = 256;

/// Most halvings of the time step (2^-16 of the rule's dt).
pub const MAX_HALVINGS: u32 = 16;

/// How unstable steps are handled.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "bevy_reflect", derive(bevy_reflect::Reflect))]
pub struct Rollback {
    /// Roll back and retry at half the dt (true, the default), or freeze at the first unstable
    /// step (false: the largest-stable-dt search turns it off).
    pub enabled: bool,
    /// Steps between checkpoints (1 ..= 4096).
    pub checkpoint_interval: u32,
    /// Rollbacks allowed without a new checkpoint before the health becomes unstable (1 ..= 16).
    pub max_retries: u32,
}

impl Default for Rollback {
    fn default() -> Self {
        Self {
            enabled: true,
            checkpoint_interval: 16,
            max_retries: 6,
        }
    }
}

impl Rollback {
    /// Rollback turned off: the first unstable step freezes the simulation.
    pub fn off() -> Self {
        Self {
            enabled: false,
            ..Self::default()
        }
    }

    /// Checks the ranges; the error names the field, the value and what is allowed.
    pub fn validate(&self) -> Result<(), ParamError> {
        if !(1..=4096).contains(&self.checkpoint_interval) {
            return Err(ParamError {
                field: "rollback.checkpoint_interval",
                value: self.checkpoint_interval.to_string(),
                allowed: "1 ..= 4096 steps",
            });
        }
        if !(1..=MAX_HALVINGS).contains(&self.max_retries) {
            return Err(ParamError {
                field: "rollback.max_retries",
                value: self.max_retries.to_string(),
                allowed: "1 ..= 16",
            });
        }
        Ok(())
    }
}

/// What the rollback machinery decided after a step was checked.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Verdict {
    /// The step was stable: keep going.
    Stable,
    /// Unstable: restore the checkpoint and retry at half the dt.
    Retry,
    /// Unstable and out of retries (or rollback is off): freeze.
    Freeze,
}

/// The rollback bookkeeping (WGSL twin: the rollback fields of `SphClock`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RollbackState {
    /// Rollbacks since the last reset.
    pub rollbacks: u64,
    /// Rollbacks since the last checkpoint.
    pub retries: u32,
    /// The dt scale is 2^-halvings.
    pub halvings: u32,
    /// Stable steps since the last rollback or recovery.
    pub stable_steps: u32,
    /// Whether a checkpoint exists.
    pub has_checkpoint: bool,
    /// The step count at the checkpoint.
    pub checkpoint_step: u64,
    /// Particles were added since the checkpoint: take a new one.
    pub save_requested: bool,
}

impl RollbackState {
    /// The factor applied to the time-step rule's dt.
    pub fn dt_scale(&self) -> f32 {
        (-(self.halvings as f32)).exp2()
    }

    /// Whether a checkpoint is due at the start of step `step_count + 1` (the state is known good).
    pub fn checkpoint_due(&self, settings: &Rollback, step_count: u64) -> bool {
        settings.enabled
            && (!self.has_checkpoint
                || self.save_requested
                || step_count >= self.checkpoint_step + settings.checkpoint_interval as u64)
    }

    /// Records a checkpoint taken at `step_count`.
    pub fn saved(&mut self, step_count: u64) {
        self.has_checkpoint = true;
        self.checkpoint_step = step_count;
        self.save_requested = false;
        self.retries = 0;
    }

    /// Decides what a checked step leads to and updates the counters.
    pub fn after_check(&mut self, settings: &Rollback, unstable: bool) -> Verdict {
        if !unstable {
            self.stable_steps += 1;
            if self.halvings > 0 && self.stable_steps >= RECOVERY_STEPS {
                self.halvings -= 1;
                self.stable_steps = 0;
            }
            return Verdict::Stable;
        }
        if !settings.enabled || !self.has_checkpoint || self.retries >= settings.max_retries {
            return Verdict::Freeze;
        }
        self.rollbacks += 1;
        self.retries += 1;
        self.halvings = (self.halvings + 1).min(MAX_HALVINGS);
        self.stable_steps = 0;
        Verdict::Retry
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn retries_halve_the_step_until_the_limit_then_freeze() {
        let settings = Rollback {
            max_retries: 3,
            ..Rollback::default()
        };
        let mut s = RollbackState::default();
        assert_eq!(s.after_check(&settings, true), Verdict::Freeze, "no checkpoint yet");
        assert!(s.checkpoint_due(&settings, 0));
        s.saved(0);
        for k in 1..=3 {
            assert_eq!(s.after_check(&settings, true), Verdict::Retry);
            assert_eq!(s.dt_scale(), 0.5f32.powi(k));
        }
        assert_eq!(s.after_check(&settings, true), Verdict::Freeze);
        assert_eq!(s.rollbacks, 3);
    }

    #[test]
    fn a_new_checkpoint_resets_the_retries_and_stable_steps_recover_the_scale() {
        let settings = Rollback::default();
        let mut s = RollbackState::default();
        s.saved(0);
        assert_eq!(s.after_check(&settings, true), Verdict::Retry);
        assert!(!s.checkpoint_due(&settings, 10));
        assert!(s.checkpoint_due(&settings, 16));
        s.saved(16);
        assert_eq!(s.retries, 0);
        for _ in 0..RECOVERY_STEPS {
            assert_eq!(s.after_check(&settings, false), Verdict::Stable);
        }
        assert_eq!(s.dt_scale(), 1.0);
    }

    #[test]
    fn off_freezes_at_once_and_bad_settings_are_named() {
        let mut s = RollbackState::default();
        s.saved(0);
        assert_eq!(s.after_check(&Rollback::off(), true), Verdict::Freeze);
        let e = Rollback {
            checkpoint_interval: 0,
            ..Rollback::default()
        }
        .validate()
        .unwrap_err();
        assert_eq!(e.field, "rollback.checkpoint_interval");
        let e = Rollback {
            max_retries: 17,
            ..Rollback::default()
        }
        .validate()
        .unwrap_err();
        assert!(e.to_string().contains("max_retries") && e.to_string().contains("17"));
    }
}
