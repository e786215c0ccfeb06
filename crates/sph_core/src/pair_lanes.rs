//! Neighbours gathered into lanes, so that the kernel evaluations of a pair loop vectorise.
//!
//! A pass that evaluates the kernel per pair (PBF's, whose positions move every iteration) is
//! bound by one square root and one division per pair when it runs one pair at a time: both are
//! slow scalar instructions, and a float sum cannot be reordered by the compiler. Gathering
//! [`LANES`] neighbours' offsets into arrays and summing into one accumulator per lane lets the
//! compiler evaluate the lanes side by side (SSE on any x86-64, wider where the build allows),
//! with the same arithmetic per pair. Lanes past the end of a list hold an offset beyond the
//! support, so the kernel is zero there.

use glam::Vec3;

/// Pairs evaluated side by side.
pub const LANES: usize = 8;

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
    /// |r|² per lane.
    pub r2: [f32; LANES],
}

impl Lanes {
    /// The offsets from `x_i` to `positions[j]` for the indices in `block` (at most [`LANES`]);
    /// unused lanes get an offset of length `beyond` (at least the kernel's support).
    #[inline(always)]
    pub fn gather(x_i: Vec3, positions: &[Vec3], block: &[u32], beyond: f32) -> Self {
        let mut lanes = Self {
            x: [beyond; LANES],
            y: [0.0; LANES],
            z: [0.0; LANES],
            r2: [0.0; LANES],
        };
        for (l, &j) in block.iter().enumerate().take(LANES) {
            let r = x_i - positions[j as usize];
            lanes.x[l] = r.x;
            lanes.y[l] = r.y;
            lanes.z[l] = r.z;
        }
        // Every lane's |r|², the unused ones' (beyond²) included.
        for l in 0..LANES {
            lanes.r2[l] =
                lanes.x[l] * lanes.x[l] + lanes.y[l] * lanes.y[l] + lanes.z[l] * lanes.z[l];
        }
        lanes
    }
}

/// Sums of [`LANES`] lanes, folded to one value at the end of a particle's loop.
#[inline(always)]
pub fn lane_sum(lanes: &[f32; LANES]) -> f32 {
    lanes.iter().sum()
}
