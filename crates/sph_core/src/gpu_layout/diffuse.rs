//! The whitewater pool's counters on the GPU (WGSL: the `DIFFUSE_*` word indices in
//! `bevy_sph_fluid/src/render/whitewater/whitewater.wgsl`), read back every frame.

use bytemuck::{Pod, Zeroable};

/// The diffuse pool's counters, one atomic word each in this order. The pool's slots are not
/// compacted: a dead slot is pushed on a free list, a birth pops one, so `free` is the list's
/// length and the pool holds `capacity - free` live particles.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
pub struct GpuDiffuseCounts {
    /// Free slots: the free list's length.
    pub free: u32,
    /// Diffuse particles born since the pool was made.
    pub born: u32,
    /// Diffuse particles refused by a full pool since it was made.
    pub dropped: u32,
    /// Diffuse particles that died since the pool was made.
    pub expired: u32,
    /// Live spray, as classified by the last step.
    pub spray: u32,
    /// Live foam.
    pub foam: u32,
    /// Live bubbles.
    pub bubbles: u32,
    /// One past the highest slot ever used: the slots worth drawing.
    pub high_water: u32,
}

impl GpuDiffuseCounts {
    /// The counters of an empty pool of `capacity` slots.
    pub fn empty(capacity: u32) -> Self {
        Self {
            free: capacity,
            ..Self::default()
        }
    }

    /// The free list of an empty pool of `capacity` slots: slot 0 on top (the list is popped
    /// from its end), so the pool fills from its first slots.
    pub fn free_list(capacity: u32) -> Vec<u32> {
        (0..capacity).rev().collect()
    }
}
