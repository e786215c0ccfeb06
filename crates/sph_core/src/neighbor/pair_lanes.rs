//! Neighbours gathered into lanes, so that the kernel evaluations of a pair loop vectorise.
//!
//! A pass that evaluates the kernel per pair (PBF's, whose positions move every iteration) is
//! bound by one square root and one division per pair when it runs one pair at a time: both are
//! slow scalar instructions, and a float sum cannot be reordered by the compiler. Gathering
//! [`LANES`] neighbours' offsets into arrays and summing into one accumulator per lane lets the
//! compiler evaluate the lanes side by side, with the same arithmetic per pair. Lanes past the
//! end of a list hold an offset beyond the support, so the kernel is zero there.
//!
//! The build targets baseline x86-64 (SSE: four lanes per instruction). Where the CPU has AVX2
//! and FMA ([`wide_lanes`]), the passes run copies of their per-particle loops compiled for
//! them (eight lanes per instruction): measured on the PBF λ pass at 31,250 particles, 1.33
//! against 1.96 ms (docs/pbf.md). The two copies gather differently (the `WIDE` parameter of
//! [`Lanes::gather`]), as each compiles best that way.

use glam::Vec3;

/// Pairs evaluated side by side.
pub const LANES: usize = 8;

/// Whether the CPU runs the passes' AVX2 + FMA + POPCNT copies (x86-64 CPUs since about 2013;
/// never on other architectures): every feature any `#[target_feature]` copy enables, so that
/// none runs on a CPU without it. Cached by the standard library after the first call.
#[inline]
pub fn wide_lanes() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::arch::is_x86_feature_detected!("avx2")
            && std::arch::is_x86_feature_detected!("fma")
            && std::arch::is_x86_feature_detected!("popcnt")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

/// The offsets r = x_i - x_j of up to [`LANES`] neighbours, one array per component, and their
/// squared lengths (unused lanes hold an offset beyond the support).
#[derive(Clone, Copy, Debug)]
pub struct Lanes {
    /// r.x per lane.
    pub x: [f32; LANES],
    /// r.y per lane.
    pub y: [f32; LANES],
    /// r.z per lane.
    pub z: [f32; LANES],
    /// |r|² per lane, filled by `gather::<false>` only (see [`Lanes::r2`]).
    squared: [f32; LANES],
}

impl Lanes {
    /// The offsets from `x_i` to `positions[j]` for the indices in `block` (at most [`LANES`]);
    /// unused lanes get an offset of length `beyond` (at least the kernel's support). `WIDE`
    /// (the AVX2 copies) leaves |r|² to [`Lanes::r2`] in the consumer's loop; otherwise it is
    /// computed here for every lane.
    #[inline(always)]
    pub fn gather<const WIDE: bool>(
        x_i: Vec3,
        positions: &[Vec3],
        block: &[u32],
        beyond: f32,
    ) -> Self {
        let mut lanes = Self {
            x: [beyond; LANES],
            y: [0.0; LANES],
            z: [0.0; LANES],
            squared: [0.0; LANES],
        };
        #[cfg(target_arch = "x86_64")]
        if WIDE && wide_lanes() {
            if let Some(full) = full_block(block, positions.len()) {
                // SAFETY: the CPU has AVX2 (`wide_lanes()`, a cached flag); `full_block`
                // checked the indices.
                unsafe { gather_offsets_avx2(x_i, positions, full, &mut lanes) };
                return lanes;
            }
        }
        for (l, &j) in block.iter().enumerate().take(LANES) {
            let r = x_i - positions[j as usize];
            lanes.x[l] = r.x;
            lanes.y[l] = r.y;
            lanes.z[l] = r.z;
        }
        if !WIDE {
            // Every lane's |r|², the unused ones' (beyond²) included.
            for l in 0..LANES {
                lanes.squared[l] =
                    lanes.x[l] * lanes.x[l] + lanes.y[l] * lanes.y[l] + lanes.z[l] * lanes.z[l];
            }
        }
        lanes
    }

    /// |r|² of lane `l`, with the `WIDE` the lanes were gathered with.
    #[inline(always)]
    pub fn r2<const WIDE: bool>(&self, l: usize) -> f32 {
        if WIDE {
            self.x[l] * self.x[l] + self.y[l] * self.y[l] + self.z[l] * self.z[l]
        } else {
            self.squared[l]
        }
    }
}

/// `block` as a full block of [`LANES`] indices, each below `len`; `None` for a list's last,
/// shorter block (or an index out of bounds, which the scalar path then reports). A shorter
/// block stays on the scalar path: measured on the PBF passes (docs/pbf.md), padding it into
/// a local array, or loading and gathering it under a mask, cost more than it saved.
#[inline(always)]
fn full_block(block: &[u32], len: usize) -> Option<&[u32; LANES]> {
    let full = <&[u32; LANES]>::try_from(block).ok()?;
    full.iter().all(|&j| (j as usize) < len).then_some(full)
}

/// The offsets from `x_i` to the eight `positions[j]` of `block` into `lanes`, by three AVX2
/// gathers (one per component, from the Vec3 array's stride of three floats) instead of 24
/// scalar loads and stores; the stores of whole lanes then forward to the consumer's loads.
///
/// # Safety
/// The CPU has AVX2, and every index of `block` is below `positions.len()`.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
#[inline]
unsafe fn gather_offsets_avx2(
    x_i: Vec3,
    positions: &[Vec3],
    block: &[u32; LANES],
    lanes: &mut Lanes,
) {
    use std::arch::x86_64::*;
    debug_assert!(block.iter().all(|&j| (j as usize) < positions.len()));
    let base = positions.as_ptr() as *const f32;
    // SAFETY: the caller's contract: AVX2, and 3 j + 2 < 3 len for every j of `block`.
    unsafe {
        let index = _mm256_loadu_si256(block.as_ptr() as *const __m256i);
        let index = _mm256_add_epi32(index, _mm256_add_epi32(index, index));
        let x = _mm256_i32gather_ps::<4>(base, index);
        let y = _mm256_i32gather_ps::<4>(base.add(1), index);
        let z = _mm256_i32gather_ps::<4>(base.add(2), index);
        _mm256_storeu_ps(
            lanes.x.as_mut_ptr(),
            _mm256_sub_ps(_mm256_set1_ps(x_i.x), x),
        );
        _mm256_storeu_ps(
            lanes.y.as_mut_ptr(),
            _mm256_sub_ps(_mm256_set1_ps(x_i.y), y),
        );
        _mm256_storeu_ps(
            lanes.z.as_mut_ptr(),
            _mm256_sub_ps(_mm256_set1_ps(x_i.z), z),
        );
    }
}

/// Sums of [`LANES`] lanes, folded to one value at the end of a particle's loop.
#[inline(always)]
pub fn lane_sum(lanes: &[f32; LANES]) -> f32 {
    lanes.iter().sum()
}
