//! The particles' sort and ids: the bitonic steps, the id in a position's w and the drained mark.

use bytemuck::{Pod, Zeroable};

/// Length of the bitonic sort: the next power of two >= capacity.
pub fn sort_length(capacity: u32) -> u32 {
    capacity.max(1).next_power_of_two()
}

/// One bitonic merge step (WGSL `BitonicStep`), bound at a dynamic offset per dispatch.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuBitonicStep {
    /// Size of the bitonic sequences being merged.
    pub k: u32,
    /// Compare distance.
    pub j: u32,
    /// Padding.
    pub pad: [u32; 2],
}

/// The (k, j) steps of a bitonic sort of `n` (a power of two) keys: log2(n)(log2(n)+1)/2 steps.
pub fn bitonic_steps(n: u32) -> Vec<GpuBitonicStep> {
    let mut steps = Vec::new();
    let mut k = 2;
    while k <= n {
        let mut j = k / 2;
        while j > 0 {
            steps.push(GpuBitonicStep { k, j, pad: [0; 2] });
            j /= 2;
        }
        k *= 2;
    }
    steps
}

/// The 4-byte word stored in a position's w component: the particle id, bit-cast to f32.
pub fn id_to_w(id: u32) -> f32 {
    f32::from_bits(id)
}

/// The bit of a position's w that marks a particle a drain took (the GPU backend's drains: it
/// stays in the live range, sorted to its tail, until the main world lowers its count).
pub const DRAINED_BIT: u32 = 1 << 31;

/// The particle id stored in a position's w component (without the drained mark).
pub fn w_to_id(w: f32) -> u32 {
    w.to_bits() & !DRAINED_BIT
}
