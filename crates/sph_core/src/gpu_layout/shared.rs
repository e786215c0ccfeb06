//! The small structures every pass may share, in one storage buffer (WGSL `SphShared`), so a pass
//! binds one buffer for all of them: WebGPU allows 8 storage buffers per shader stage.

use crate::gpu_layout::body_forces::GpuBodyForces;
use crate::gpu_layout::clock::GpuClock;
use crate::gpu_layout::probes::GpuProbes;
use crate::gpu_layout::pumps::GpuPumps;
use bytemuck::{Pod, Zeroable};

/// The pumps, the probes, the clock and the body forces, one after the other (WGSL `SphShared`,
/// the same members in the same order). The structures with 16-byte members come first, so
/// every member starts where WGSL's storage layout puts it; the shader tests compare the offsets.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct GpuShared {
    /// The frame's pumps.
    pub pumps: GpuPumps,
    /// The frame's probes and their sums.
    pub probes: GpuProbes,
    /// The clock.
    pub clock: GpuClock,
    /// The fluid's force on each body over the frame.
    pub body_forces: GpuBodyForces,
}

impl GpuShared {
    /// Where the pumps start [bytes].
    pub const PUMPS_OFFSET: u64 = std::mem::offset_of!(GpuShared, pumps) as u64;
    /// Where the probes start [bytes].
    pub const PROBES_OFFSET: u64 = std::mem::offset_of!(GpuShared, probes) as u64;
    /// Where the clock starts [bytes].
    pub const CLOCK_OFFSET: u64 = std::mem::offset_of!(GpuShared, clock) as u64;
    /// Where the body forces start [bytes].
    pub const BODY_FORCES_OFFSET: u64 = std::mem::offset_of!(GpuShared, body_forces) as u64;
    /// The buffer's size: WGSL rounds a structure with 16-byte members up to 16 bytes.
    pub const BYTES: u64 = (std::mem::size_of::<GpuShared>() as u64).next_multiple_of(16);
}
