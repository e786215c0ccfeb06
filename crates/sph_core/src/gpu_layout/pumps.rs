//! The frame's pumps as the GPU applies them.

use bytemuck::{Pod, Zeroable};

/// Most pumps the GPU applies (the rest are left out and reported).
pub const MAX_GPU_PUMPS: usize = 16;

/// A pump as the GPU reads it (WGSL `GpuPump`). Rust twin: [`crate::flow::pump::Pump`].
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuPump {
    /// The box's centre [m]; w = the target speed [m/s].
    pub center_speed: [f32; 4],
    /// The inverse of the box's rotation (world to box frame), quaternion (x, y, z, w).
    pub to_local: [f32; 4],
    /// The box's half extents [m]; w = the strength [1/s].
    pub half_extents_strength: [f32; 4],
    /// The unit direction it pushes in (world).
    pub direction: [f32; 4],
}

/// The pumps of a frame (WGSL `SphPumps`): how many, then up to [`MAX_GPU_PUMPS`].
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuPumps {
    /// Pumps in use.
    pub count: u32,
    /// Open drains, in the slots after the pumps (as boxes: centre, rotation, half extents).
    pub sink_count: u32,
    /// Padding to 16 bytes.
    pub pad: [u32; 2],
    /// The pumps, then the drains; slots past `count + sink_count` are ignored.
    pub pumps: [GpuPump; MAX_GPU_PUMPS],
}

impl GpuPumps {
    /// The GPU form of the first [`MAX_GPU_PUMPS`] of `pumps` (validated ones: a zero direction
    /// stays zero and pushes nothing).
    pub fn of(pumps: &[crate::flow::pump::Pump]) -> Self {
        let mut out = Self::default();
        for (slot, p) in out.pumps.iter_mut().zip(pumps) {
            let c = p.region.pose.translation;
            let q = p.region.pose.rotation.inverse();
            let h = p.region.half_extents;
            let d = p.direction.normalize_or_zero();
            *slot = GpuPump {
                center_speed: [c.x, c.y, c.z, p.speed],
                to_local: [q.x, q.y, q.z, q.w],
                half_extents_strength: [h.x, h.y, h.z, p.strength],
                direction: [d.x, d.y, d.z, 0.0],
            };
        }
        out.count = pumps.len().min(MAX_GPU_PUMPS) as u32;
        out
    }

    /// [`Self::of`] `pumps`, then the open ones of `sinks` in the slots left (a pump's box with
    /// no strength); returns the drains that found no slot.
    pub fn with_sinks(
        pumps: &[crate::flow::pump::Pump],
        sinks: &[crate::flow::sink::Sink],
    ) -> (Self, usize) {
        let mut out = Self::of(pumps);
        let open: Vec<&crate::flow::sink::Sink> = sinks.iter().filter(|s| s.open).collect();
        let first = out.count as usize;
        for (slot, sink) in out.pumps[first..].iter_mut().zip(&open) {
            let c = sink.region.pose.translation;
            let q = sink.region.pose.rotation.inverse();
            let h = sink.region.half_extents;
            *slot = GpuPump {
                center_speed: [c.x, c.y, c.z, 0.0],
                to_local: [q.x, q.y, q.z, q.w],
                half_extents_strength: [h.x, h.y, h.z, 0.0],
                direction: [0.0; 4],
            };
        }
        out.sink_count = open.len().min(MAX_GPU_PUMPS - first) as u32;
        (out, open.len() - out.sink_count as usize)
    }
}
