//! Real-time stepping: a frame's time split into steps no longer than the time-step rule allows.
//!
//! A game advances the water by the frame's own time each frame. What is left of the frame,
//! `remaining`, is split into `steps_left` equal steps, each no longer than the rule's dt:
//! `dt = min(dt_rule, remaining / steps_left)`. The CPU solver knows the rule before each step and
//! takes `steps_left = ⌈remaining / dt_rule⌉` ([`steps_to_cover`]), so a frame ends exactly on its
//! time with no sliver of a last step ([`crate::CpuSolver::advance_by`]). The GPU plans the
//! frame's steps from the rule's dt as last read back (a frame or two old) and its time-step pass
//! applies [`budget_dt`] with the planned count (`time_step.wgsl`): it never waits for the CPU,
//! never oversteps the frame, and falls short only when the rule's dt shrank since the readback.

/// Below this remaining time [s] a frame is complete (a tenth of a microsecond: the GPU clock
/// counts whole nanoseconds).
pub const FRAME_DONE: f32 = 1.0e-7;

/// Steps of at most `dt` that cover `duration` (at least 1; 1 for non-finite or non-positive
/// inputs). A relative slack of 1e-4 keeps a duration of exactly n steps at n despite rounding.
pub fn steps_to_cover(duration: f32, dt: f32) -> u32 {
    let n = duration / dt;
    if !(n.is_finite() && n > 0.0) {
        return 1;
    }
    (n * (1.0 - 1.0e-4)).ceil().clamp(1.0, u32::MAX as f32) as u32
}

/// The dt of the next step of a frame with `remaining` seconds left in `steps_left` steps, never
/// longer than the rule's `dt_rule` (WGSL twin: the budget in `time_step.wgsl`).
pub fn budget_dt(dt_rule: f32, remaining: f32, steps_left: u32) -> f32 {
    let share = remaining.max(0.0) / steps_left.max(1) as f32;
    dt_rule.min(share)
}

/// How a step chooses its dt from the rule's: the rollback scale (1, or 2^-k after k rollbacks
/// not yet recovered from), then, in real-time mode, the frame's budget.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepDt {
    /// The rollback scale.
    pub scale: f32,
    /// What is left of the frame [s] in real-time mode; `None` steps at the rule's dt.
    pub remaining: Option<f32>,
}

impl StepDt {
    /// The rule's dt at `scale`, without a frame budget.
    pub fn scaled(scale: f32) -> Self {
        Self {
            scale,
            remaining: None,
        }
    }

    /// The step's dt for the rule's `dt_rule`.
    pub fn of(&self, dt_rule: f32) -> f32 {
        let dt = dt_rule * self.scale;
        match self.remaining {
            Some(remaining) => budget_dt(dt, remaining, steps_to_cover(remaining, dt)),
            None => dt,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn steps_cover_the_frame_without_a_sliver() {
        assert_eq!(steps_to_cover(1.0 / 60.0, 1.0 / 120.0), 2);
        assert_eq!(steps_to_cover(1.0 / 60.0, 3.0e-4), 56);
        assert_eq!(steps_to_cover(1.0e-4, 3.0e-4), 1);
        assert_eq!(steps_to_cover(f32::NAN, 1.0), 1);
        assert_eq!(steps_to_cover(1.0, 0.0), 1);
        let dt = StepDt {
            scale: 1.0,
            remaining: Some(1.0 / 60.0),
        };
        let step = dt.of(3.0e-4);
        assert!(step <= 3.0e-4);
        assert!((56.0 * step - 1.0 / 60.0).abs() < 1e-7, "{step}");
    }

    #[test]
    fn the_rule_and_the_rollback_scale_bound_every_step() {
        assert_eq!(budget_dt(1e-3, 1.0, 2), 1e-3);
        assert_eq!(budget_dt(1e-3, 1e-3, 4), 2.5e-4);
        assert_eq!(budget_dt(1e-3, -1.0, 0), 0.0);
        let halved = StepDt {
            scale: 0.5,
            remaining: Some(1.0 / 60.0),
        };
        assert!(halved.of(1.0 / 120.0) <= 1.0 / 240.0 + 1e-9);
        assert_eq!(StepDt::scaled(0.25).of(4e-4), 1e-4);
    }
}
