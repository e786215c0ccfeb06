//! The simulation clock (WGSL `SphClock`), written only by the GPU.

use bytemuck::{Pod, Zeroable};

/// The simulation clock (WGSL `SphClock`, the same names in the same order), a member of the
/// shared storage structure ([`crate::gpu_layout::GpuShared`]) written only by the GPU: the
/// `sph_time_step` pass chooses each step's dt from the extremes the last pass of the previous
/// step recorded, advances time and freezes the simulation when a step went unstable.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuClock {
    /// dt of the step in progress or last taken [s].
    pub dt: f32,
    /// Steps taken since the reset.
    pub step: u32,
    /// Simulated time [ns], low word (the time is the exact integer sum of the steps' dt).
    pub time_ns_lo: u32,
    /// Simulated time [ns], high word.
    pub time_ns_hi: u32,
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
    /// Simulated time at the checkpoint [ns], low word.
    pub checkpoint_time_lo: u32,
    /// Simulated time at the checkpoint [ns], high word.
    pub checkpoint_time_hi: u32,
    /// Particles the checkpoint holds.
    pub checkpoint_count: u32,
    /// Particles the checkpoint held before the last restore.
    pub restore_count: u32,
    /// Set by the CPU when particles were uploaded: checkpoint at the next stable step.
    pub save_requested: u32,
    /// The rule's dt before the rollback scale [s].
    pub rule_dt: f32,
    /// The rule's dt at the checkpoint [s] (a retry takes half of it).
    pub checkpoint_rule_dt: f32,
    /// Particles the guard moved out of a collider or back into the box since the reset (see
    /// [`crate::boundary::guard`]).
    pub boundary_corrections: u32,
    /// Of those, the particles clamped back into the box.
    pub wall_corrections: u32,
    /// Real-time mode: the number of the frame whose budget is being spent.
    pub budget_frame: u32,
    /// What is left of that frame's time [s].
    pub budget_remaining: f32,
    /// Steps left in that frame's plan.
    pub budget_steps_left: u32,
    /// PBF: particles that had more than
    /// [`PBF_MAX_NEIGHBORS`](crate::gpu_layout::PBF_MAX_NEIGHBORS) neighbours in a step's lists
    /// (and lost the rest for that step), and boundary samples with more than
    /// [`PBF_MAX_WALL_NEIGHBORS`](crate::gpu_layout::PBF_MAX_WALL_NEIGHBORS) particles in reach,
    /// summed over the steps since the reset.
    pub neighbor_list_overflows: u32,
    /// DFSPH: the workgroup count of the solve's next pass, 0 once the solve converged; with
    /// `dfsph_args_y` and `dfsph_args_z` (1, 1) the indirect dispatch arguments of the solves'
    /// passes (copied to the indirect buffer after each of them).
    pub dfsph_args_x: u32,
    /// DFSPH: the indirect dispatch's y workgroups (1).
    pub dfsph_args_y: u32,
    /// DFSPH: the indirect dispatch's z workgroups (1).
    pub dfsph_args_z: u32,
    /// DFSPH: 1 once the solve in progress converged.
    pub dfsph_done: u32,
    /// DFSPH: the iterations the solve in progress applied.
    pub dfsph_applied: u32,
    /// DFSPH: the mean-error sums of the solve's sources, two 64-bit fixed-point accumulators
    /// (units of [`DFSPH_ERROR_UNIT`] ρ0 or ρ0/s) that the iterations ping-pong: a's low word.
    pub dfsph_error_a_lo: u32,
    /// DFSPH: accumulator a's high word.
    pub dfsph_error_a_hi: u32,
    /// DFSPH: accumulator b's low word.
    pub dfsph_error_b_lo: u32,
    /// DFSPH: accumulator b's high word.
    pub dfsph_error_b_hi: u32,
    /// DFSPH: constant-density iterations summed over the steps since the reset.
    pub density_iterations: u32,
    /// DFSPH: the most constant-density iterations of one step since the reset.
    pub density_iterations_max: u32,
    /// DFSPH: divergence-free iterations summed over the steps since the reset.
    pub divergence_iterations: u32,
    /// DFSPH: the last constant-density solve's mean error (fraction of ρ0).
    pub density_error: f32,
    /// DFSPH: the last divergence-free solve's mean error [1/s].
    pub divergence_error: f32,
    /// Drains: particles marked as drained counted by the sort under way (the sort's pass 1
    /// adds, pass 2 takes the sum and zeroes it).
    pub marked: u32,
    /// Drains: how many marked particles the last sort moved to the tail of the live range.
    pub tail_size: u32,
    /// Drains: the main world's frame number of that sort ([`GpuSphParams::drain_frame`](crate::gpu_layout::GpuSphParams::drain_frame)).
    pub tail_frame: u32,
    /// PBF: the Jacobi iteration under way (from 0; set by each iteration's λ pass).
    pub pbf_iteration: u32,
    /// DFSPH: the most iterations one step's constant-density solve took since the CPU last
    /// zeroed it (at the start of every frame with steps, so a reading holds that frame's most).
    pub density_frame_max: u32,
    /// DFSPH: the same for the divergence-free solve.
    pub divergence_frame_max: u32,
    /// DFSPH: the constant-density solves that ran out of the passes the CPU encoded for them
    /// before they converged or reached their most iterations, since the reset (see
    /// `bevy_sph_fluid`'s iteration budget).
    pub density_cut_short: u32,
    /// DFSPH: the same for the divergence-free solve.
    pub divergence_cut_short: u32,
    /// Steps the device has begun since the reset, rolled back or not: unlike `step`, it never
    /// goes back, so a readback whose `steps_run` equals the steps dispatched is current.
    pub steps_run: u32,
}

/// The unit of DFSPH's error sums on the device ([`GpuClock::dfsph_error_a_lo`] and the rest): 1e-9 of ρ0 (or
/// ρ0 per second) per particle.
pub const DFSPH_ERROR_UNIT: f64 = 1.0e-9;

impl GpuClock {
    /// Simulated time [s].
    pub fn time(&self) -> f64 {
        ((self.time_ns_hi as u64) << 32 | self.time_ns_lo as u64) as f64 * 1e-9
    }

    /// Byte offset of the `save_requested` flag (written by the CPU after an upload).
    pub const SAVE_REQUESTED_OFFSET: u64 = std::mem::offset_of!(GpuClock, save_requested) as u64;

    /// Byte offset of the DFSPH dispatch arguments `dfsph_args_x`, `_y`, `_z` (copied to the
    /// indirect buffer after each solve pass).
    pub const DFSPH_ARGS_OFFSET: u64 = std::mem::offset_of!(GpuClock, dfsph_args_x) as u64;

    /// Byte offset of `density_frame_max` and `divergence_frame_max` (zeroed by the CPU at the
    /// start of every frame).
    pub const DFSPH_FRAME_MAX_OFFSET: u64 =
        std::mem::offset_of!(GpuClock, density_frame_max) as u64;

    /// Byte offset of `has_checkpoint` (cleared by the CPU when the buffers are reallocated).
    pub const HAS_CHECKPOINT_OFFSET: u64 = std::mem::offset_of!(GpuClock, has_checkpoint) as u64;

    /// DFSPH: the most iterations of this frame's constant-density and divergence-free solves.
    pub fn dfsph_frame_max(&self) -> [u32; 2] {
        [self.density_frame_max, self.divergence_frame_max]
    }

    /// DFSPH: the constant-density and divergence-free solves cut short since the reset.
    pub fn dfsph_cut_short(&self) -> [u32; 2] {
        [self.density_cut_short, self.divergence_cut_short]
    }

    /// DFSPH: solves of both kinds cut short by the encoded iterations since the reset.
    pub fn solves_cut_short(&self) -> u64 {
        self.density_cut_short as u64 + self.divergence_cut_short as u64
    }

    /// The extremes the last step recorded.
    pub fn extremes(&self) -> crate::stability::StepExtremes {
        crate::stability::StepExtremes {
            max_speed: f32::from_bits(self.max_speed_bits),
            max_acceleration: f32::from_bits(self.max_acceleration_bits),
        }
    }
}
