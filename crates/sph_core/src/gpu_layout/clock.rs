//! The simulation clock (WGSL `SphClock`), written only by the GPU.

use bytemuck::{Pod, Zeroable};

/// The simulation clock (WGSL `SphClock`), a storage buffer written only by the GPU: the
/// `sph_time_step` pass chooses each step's dt from the extremes the last pass of the previous
/// step recorded, advances time and freezes the simulation when a step went unstable.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
pub struct GpuClock {
    /// dt of the step in progress or last taken [s], as f32 bits.
    pub dt_bits: u32,
    /// Steps taken since the reset.
    pub step: u32,
    /// Simulated time [ns], low and high words (exact integer sum of the steps' dt).
    pub time_ns: [u32; 2],
    /// Largest |v| of the last step, f32 bits (non-finite values compare above every finite one).
    pub max_speed_bits: u32,
    /// Largest |a| of the last step, f32 bits.
    pub max_acceleration_bits: u32,
    /// 0 while healthy; otherwise the step (1-based) detected as unstable. Frozen until reset.
    pub unstable_step: u32,
    /// What the pass after the time-step pass does with the checkpoint: 0 nothing, 1 save,
    /// 2 restore.
    pub checkpoint_action: u32,
    /// Rollbacks since the reset.
    pub rollbacks: u32,
    /// Rollbacks since the last checkpoint.
    pub retries: u32,
    /// Halvings of the rule's dt (dt scale 2^-halvings).
    pub halvings: u32,
    /// Stable steps since the last rollback or recovery.
    pub stable_steps: u32,
    /// 1 when a checkpoint exists.
    pub has_checkpoint: u32,
    /// The step count at the checkpoint.
    pub checkpoint_step: u32,
    /// Simulated time at the checkpoint [ns], low and high words.
    pub checkpoint_time_ns: [u32; 2],
    /// Particles the checkpoint holds.
    pub checkpoint_count: u32,
    /// Particles the checkpoint held before the last restore.
    pub restore_count: u32,
    /// Set by the CPU when particles were uploaded: checkpoint at the next stable step.
    pub save_requested: u32,
    /// The rule's dt before the rollback scale [s], f32 bits.
    pub rule_dt_bits: u32,
    /// The rule's dt at the checkpoint [s], f32 bits (a retry takes half of it).
    pub checkpoint_rule_dt_bits: u32,
    /// Particles the guard moved out of a collider or back into the box since the reset (see
    /// [`crate::boundary::guard`]).
    pub boundary_corrections: u32,
    /// Of those, the particles clamped back into the box.
    pub wall_corrections: u32,
    /// Real-time mode: the number of the frame whose budget is being spent.
    pub budget_frame: u32,
    /// What is left of that frame's time [s], f32 bits.
    pub budget_remaining_bits: u32,
    /// Steps left in that frame's plan.
    pub budget_steps_left: u32,
    /// PBF: particles that had more than
    /// [`PBF_MAX_NEIGHBORS`](crate::gpu_layout::PBF_MAX_NEIGHBORS) neighbours in a step's lists
    /// (and lost the rest for that step), summed over the steps since the reset.
    pub neighbor_list_overflows: u32,
    /// DFSPH: the workgroup count of the solve's next pass, then 1, 1: the indirect dispatch
    /// arguments of the solves' passes, 0 once the solve converged (copied to the indirect
    /// buffer after each of them).
    pub dfsph_args: [u32; 3],
    /// DFSPH: 1 once the solve in progress converged.
    pub dfsph_done: u32,
    /// DFSPH: the iterations the solve in progress applied.
    pub dfsph_applied: u32,
    /// DFSPH: the mean-error sums of the solve's sources, two 64-bit fixed-point accumulators
    /// (low, high words; units of [`DFSPH_ERROR_UNIT`] ρ0 or ρ0/s) that the iterations
    /// ping-pong.
    pub dfsph_error: [u32; 4],
    /// DFSPH: constant-density iterations summed over the steps since the reset.
    pub density_iterations: u32,
    /// DFSPH: the most constant-density iterations of one step since the reset.
    pub density_iterations_max: u32,
    /// DFSPH: divergence-free iterations summed over the steps since the reset.
    pub divergence_iterations: u32,
    /// DFSPH: the last constant-density solve's mean error (fraction of ρ0), f32 bits.
    pub density_error_bits: u32,
    /// DFSPH: the last divergence-free solve's mean error [1/s], f32 bits.
    pub divergence_error_bits: u32,
    /// Drains: particles marked as drained counted by the sort under way (the sort's pass 1
    /// adds, pass 2 takes the sum and zeroes it).
    pub marked: u32,
    /// Drains: how many marked particles the last sort moved to the tail of the live range.
    pub tail_size: u32,
    /// Drains: the main world's frame number of that sort (`GpuSphParams::drains[0]`).
    pub tail_frame: u32,
    /// PBF: the Jacobi iteration under way (from 0; set by each iteration's λ pass).
    pub pbf_iteration: u32,
    /// DFSPH: the most iterations one step's constant-density and divergence-free solves took
    /// since the CPU last zeroed them (at the start of every frame with steps, so a reading
    /// holds that frame's most).
    pub dfsph_frame_max: [u32; 2],
    /// DFSPH: the constant-density and divergence-free solves that ran out of the passes the
    /// CPU encoded for them before they converged or reached their most iterations, since the
    /// reset (see `bevy_sph_fluid`'s iteration budget).
    pub dfsph_cut_short: [u32; 2],
    /// Steps the device has begun since the reset, rolled back or not: unlike `step`, it never
    /// goes back, so a readback whose `steps_run` equals the steps dispatched is current.
    pub steps_run: u32,
}

/// The unit of DFSPH's error sums on the device ([`GpuClock::dfsph_error`]): 1e-9 of ρ0 (or
/// ρ0 per second) per particle.
pub const DFSPH_ERROR_UNIT: f64 = 1.0e-9;

impl GpuClock {
    /// dt [s].
    pub fn dt(&self) -> f32 {
        f32::from_bits(self.dt_bits)
    }

    /// Simulated time [s].
    pub fn time(&self) -> f64 {
        ((self.time_ns[1] as u64) << 32 | self.time_ns[0] as u64) as f64 * 1e-9
    }

    /// Byte offset of the `save_requested` flag (written by the CPU after an upload).
    pub const SAVE_REQUESTED_OFFSET: u64 = std::mem::offset_of!(GpuClock, save_requested) as u64;

    /// Byte offset of `dfsph_args` (copied to the indirect buffer after each solve pass).
    pub const DFSPH_ARGS_OFFSET: u64 = std::mem::offset_of!(GpuClock, dfsph_args) as u64;

    /// Byte offset of `dfsph_frame_max` (zeroed by the CPU at the start of every frame).
    pub const DFSPH_FRAME_MAX_OFFSET: u64 = std::mem::offset_of!(GpuClock, dfsph_frame_max) as u64;

    /// Byte offset of `has_checkpoint` (cleared by the CPU when the buffers are reallocated).
    pub const HAS_CHECKPOINT_OFFSET: u64 = std::mem::offset_of!(GpuClock, has_checkpoint) as u64;

    /// DFSPH: solves of both kinds cut short by the encoded iterations since the reset.
    pub fn solves_cut_short(&self) -> u64 {
        self.dfsph_cut_short.iter().map(|&n| n as u64).sum()
    }

    /// The extremes the last step recorded.
    pub fn extremes(&self) -> crate::stability::StepExtremes {
        crate::stability::StepExtremes {
            max_speed: f32::from_bits(self.max_speed_bits),
            max_acceleration: f32::from_bits(self.max_acceleration_bits),
        }
    }
}
