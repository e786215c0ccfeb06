//! DFSPH's iteration budget on the GPU backend: how many Jacobi iterations of each solve the
//! CPU encodes per step.
//!
//! The device decides when a solve has converged and turns its remaining passes into indirect
//! dispatches of no workgroup (`render/solvers/dfsph/dfsph.wgsl`), so the CPU never waits. But an empty
//! dispatch still costs about 0.3 ms on lavapipe, and encoding each solve's most iterations
//! (100 + 100 by default, 400 dispatches a step) when a step takes about 20 spent a third of a
//! dambreak32k step on passes that do nothing (docs/dfsph.md). The budget encodes what recent
//! steps needed with a margin instead:
//!
//! - before any reading, each solve's most iterations (the settings');
//! - then `m + m/4 + 8`, with `m` the most iterations one step of that solve took in the last
//!   frames read back (the clock's `density_frame_max` and `divergence_frame_max`; at least [`WINDOW`] frames, and all
//!   those of the last [`WINDOW_STEPS`] steps), clamped to the settings' least and most.
//!   Measured on dambreak32k (docs/dfsph.md): `2 m + 8` encoded the divergence-free solve's
//!   most (100) at nearly every frame for a mean of 32 a step; `m + m/4 + 8` encodes about 70
//!   and cut 7 of 446 solves short (5 with `2 m + 8`); `m + 8` cut 9 short, and the doubling
//!   that follows each (below) left it no cheaper;
//! - a solve that ran out of passes before it converged (the clock's `density_cut_short` and `divergence_cut_short`, counted
//!   by the device) enters the window as if it had needed twice the budget it had, so the next
//!   frames encode at least double.
//!
//! A solve cut short is a step less converged than the settings ask: `SphStats` reports them
//! (`dfsph_solves_cut_short`), and sph-bench's JSON (`solves_cut_short`).

use sph_core::gpu_layout::GpuClock;
use sph_core::DfsphSettings;

/// How many frames' readings the budget remembers. 4: a rare step that took the settings'
/// most holds the budget up for 4 frames only (a window of 16 kept dambreak32k's
/// divergence-free budget at 100 all along; docs/dfsph.md).
pub const WINDOW: usize = 4;

/// The budget also remembers every frame of this many recent steps: at one or two steps a frame
/// (a game's), 4 frames would be a handful of steps (measured in the floating-box test with
/// plain-Jacobi solves, 68 divergence-free iterations a step: 121 solves cut short with 4
/// frames of 2 steps).
pub const WINDOW_STEPS: u32 = 32;

/// At most this many frames are remembered (frames of a single step).
const MOST_FRAMES: usize = WINDOW_STEPS as usize;

/// The most iterations recent steps of one solve took, and the solve's cut-short count at the
/// last reading.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
struct SolveHistory {
    /// The last readings' clock step and most iterations, newest last.
    recent: Vec<(u32, u32)>,
    /// The device's cut-short count at the last reading.
    cut_short: u32,
}

impl SolveHistory {
    /// Adds the reading at clock step `step`, then forgets the oldest readings beyond the last
    /// [`WINDOW`] frames that are also older than [`WINDOW_STEPS`] steps.
    fn push(&mut self, step: u32, most: u32) {
        self.recent.push((step, most));
        while self.recent.len() > MOST_FRAMES
            || (self.recent.len() > WINDOW && step.saturating_sub(self.recent[0].0) >= WINDOW_STEPS)
        {
            self.recent.remove(0);
        }
    }

    /// The budget from this history for a solve of `least..=most` iterations.
    fn budget(&self, least: u32, most: u32) -> u32 {
        let floor = least.max(1).min(most);
        match self.recent.iter().map(|&(_, m)| m).max() {
            None => most,
            Some(m) => m.saturating_add(m / 4).saturating_add(8).clamp(floor, most),
        }
    }
}

/// The iteration budget of the GPU backend's DFSPH solves (see the module's docs).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct DfsphIterationBudget {
    /// Constant-density, divergence-free.
    solves: [SolveHistory; 2],
    /// The clock's step at the last reading (a reading seen twice counts once).
    last_step: Option<u32>,
    /// Encode exactly these iterations, whatever the readings say (tests, tools).
    pinned: Option<[u32; 2]>,
}

impl DfsphIterationBudget {
    /// A budget that encodes `iterations` (constant-density, divergence-free) per step,
    /// clamped to the settings' range, and ignores the readings: for tests and tools that need
    /// a fixed dispatch count.
    pub fn pinned(iterations: [u32; 2]) -> Self {
        Self {
            pinned: Some(iterations),
            ..Self::default()
        }
    }

    /// The iterations to encode per step this frame: constant-density, divergence-free.
    pub fn encoded(&self, settings: &DfsphSettings) -> [u32; 2] {
        let ranges = [
            (
                settings.min_density_iterations,
                settings.max_density_iterations,
            ),
            (
                settings.min_divergence_iterations,
                settings.max_divergence_iterations,
            ),
        ];
        std::array::from_fn(|s| {
            let (least, most) = ranges[s];
            match self.pinned {
                Some(p) => p[s].clamp(least.max(1).min(most), most),
                None => self.solves[s].budget(least, most),
            }
        })
    }

    /// Takes a clock reading, encoded at `encoded` iterations per step (what
    /// [`Self::encoded`] said when the frame that reading covers was planned; readings arrive a
    /// frame or two late, so the newest budget stands in for it). A reading of a frame
    /// without DFSPH steps (both maxima 0) or seen before is skipped; a reset (counts going
    /// back) starts the history again.
    pub fn observe(&mut self, clock: &GpuClock, encoded: [u32; 2]) {
        if self.last_step == Some(clock.step) {
            return;
        }
        if self.last_step.is_some_and(|last| clock.step < last) {
            self.solves = Default::default();
        }
        self.last_step = Some(clock.step);
        let ran = clock.density_frame_max > 0 || clock.divergence_frame_max > 0;
        for (s, solve) in self.solves.iter_mut().enumerate() {
            let cut = clock.dfsph_cut_short()[s];
            let newly_cut = cut.saturating_sub(solve.cut_short) > 0;
            solve.cut_short = cut;
            if newly_cut {
                solve.push(clock.step, encoded[s].saturating_mul(2));
            } else if ran {
                solve.push(clock.step, clock.dfsph_frame_max()[s]);
            }
        }
    }

    /// Solves cut short since the reset, as of the last reading.
    pub fn cut_short(&self) -> u64 {
        self.solves.iter().map(|s| s.cut_short as u64).sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn reading(step: u32, most: [u32; 2], cut: [u32; 2]) -> GpuClock {
        GpuClock {
            step,
            density_frame_max: most[0],
            divergence_frame_max: most[1],
            density_cut_short: cut[0],
            divergence_cut_short: cut[1],
            ..GpuClock::default()
        }
    }

    #[test]
    fn the_budget_starts_at_the_most_and_follows_the_readings_with_a_margin() {
        let settings = DfsphSettings::default();
        let mut budget = DfsphIterationBudget::default();
        assert_eq!(budget.encoded(&settings), [100, 100]);
        budget.observe(&reading(10, [4, 20], [0, 0]), [100, 100]);
        assert_eq!(budget.encoded(&settings), [13, 33]);
        // The window's most counts, not the last reading's.
        budget.observe(&reading(20, [2, 10], [0, 0]), [13, 33]);
        assert_eq!(budget.encoded(&settings), [13, 33]);
        // After WINDOW readings of 10 steps each (and WINDOW_STEPS steps) the old peak is
        // forgotten.
        for k in 0..WINDOW as u32 {
            budget.observe(&reading(30 + 10 * k, [2, 10], [0, 0]), [13, 33]);
        }
        assert_eq!(budget.encoded(&settings), [10, 20]);
    }

    #[test]
    fn at_one_step_a_frame_the_budget_remembers_the_last_window_steps() {
        let settings = DfsphSettings::default();
        let mut budget = DfsphIterationBudget::default();
        budget.observe(&reading(10, [4, 20], [0, 0]), [100, 100]);
        for step in 11..10 + WINDOW_STEPS {
            budget.observe(&reading(step, [2, 10], [0, 0]), [13, 33]);
        }
        assert_eq!(budget.encoded(&settings), [13, 33]);
        budget.observe(&reading(10 + WINDOW_STEPS, [2, 10], [0, 0]), [13, 33]);
        assert_eq!(budget.encoded(&settings), [10, 20]);
    }

    #[test]
    fn a_solve_cut_short_doubles_its_budget_and_the_same_reading_counts_once() {
        let settings = DfsphSettings::default();
        let mut budget = DfsphIterationBudget::default();
        budget.observe(&reading(10, [4, 20], [0, 0]), [100, 100]);
        assert_eq!(budget.encoded(&settings), [13, 33]);
        budget.observe(&reading(20, [4, 33], [0, 1]), [13, 33]);
        // The cut solve counts as having needed 2 × 33 = 66: 66 + 16 + 8.
        assert_eq!(budget.encoded(&settings), [13, 90]);
        assert_eq!(budget.cut_short(), 1);
        budget.observe(&reading(20, [4, 33], [0, 1]), [13, 90]);
        assert_eq!(budget.cut_short(), 1);
        // A reset takes the step back: the history starts again.
        budget.observe(&reading(3, [3, 8], [0, 0]), [13, 90]);
        assert_eq!(budget.encoded(&settings), [11, 18]);
        assert_eq!(budget.cut_short(), 0);
    }

    #[test]
    fn the_budget_keeps_to_the_settings_range_and_skips_frames_without_steps() {
        let settings = DfsphSettings {
            min_density_iterations: 12,
            max_divergence_iterations: 20,
            ..DfsphSettings::default()
        };
        let mut budget = DfsphIterationBudget::default();
        budget.observe(&reading(5, [0, 0], [0, 0]), [100, 20]);
        assert_eq!(budget.encoded(&settings), [100, 20]);
        budget.observe(&reading(6, [2, 19], [0, 0]), [100, 20]);
        assert_eq!(budget.encoded(&settings), [12, 20]);
        let pinned = DfsphIterationBudget::pinned([1, 50]);
        assert_eq!(pinned.encoded(&settings), [12, 20]);
    }
}
