//! DFSPH's pairs as the GPU keeps them (`dfsph_pairs`, written by the factors pass, read by
//! every iteration): 8 bytes a pair, two pairs to a 16-byte entry. On lavapipe every load whose
//! address varies across the SIMD lanes runs as a loop over the lanes, so an iteration's pair
//! loop costs what its loads issue: with 16-byte pairs two per pair (the pair, the neighbour's
//! value), packed one and a half (docs/dfsph.md, "Packed pairs"). The price is g_ij in 15-bit
//! fixed point (to 3e-5 of the largest |g_ij|) and at most 2^18 particles on GPU DFSPH.
//!
//! The CPU solver rounds its fluid pairs' g_ij the same way ([`round`], in
//! [`crate::neighbor::lists::NeighborLists::rebuild_cubic_spline`]), so both backends solve with
//! the same g_ij. Without it a violent impact (a block at 20 m/s into colliders, 28 %
//! compressed) differed by 3.6e-3 in density between them: the pressure accelerations
//! Σ_j (κ_i + κ_j) g_ij of a compressed particle cancel to a small part of their terms, and the
//! rounding does not. WGSL twin: `pair_scale`, `pair_steps`, `pack_pair` and `unpack_pair` in
//! the plugin's `render/solvers/dfsph/dfsph.wgsl`.

use glam::Vec3;

/// Bits of a packed DFSPH pair's neighbour index on the GPU ([`pack`]).
pub const INDEX_BITS: u32 = 18;

/// The most particles GPU DFSPH holds: a packed pair's neighbour index has
/// [`INDEX_BITS`] bits. The CPU solver has no such limit.
pub const MAX_PARTICLES: u32 = 1 << INDEX_BITS;

/// Bits of each of g_ij's components in a packed DFSPH pair ([`pack`]).
pub const GRAD_BITS: u32 = 15;

/// Steps of a packed component each way from 0: a component is kept to within half a step,
/// scale / (2 · 16,383).
const STEPS: f32 = ((1 << (GRAD_BITS - 1)) - 1) as f32;
const ZERO: f32 = (1 << (GRAD_BITS - 1)) as f32;

/// The largest |g_ij| = m |∇W| of the cubic spline whose gradient constant is `kernel_l`
/// ([`crate::kernel::CubicSpline::l`]): its slope l q (3q - 2) peaks at q = 1/3, above its
/// l (1 - q)² beyond q = 1/2. The scale of every packed pair. WGSL twin: `pair_scale`.
pub fn scale(mass: f32, kernel_l: f32) -> f32 {
    mass * kernel_l / 3.0
}

/// One step of a packed component of `scale`: [`round`] moves a component by at most half of
/// it (inside ±`scale`).
pub fn step(scale: f32) -> f32 {
    scale / STEPS
}

/// g_ij's components in steps of `scale` / 16,383, clamped to ±16,383 (ties to even).
#[inline(always)]
fn steps(grad: Vec3, scale: f32) -> Vec3 {
    ((grad / scale).clamp(Vec3::NEG_ONE, Vec3::ONE) * STEPS).map(f32::round_ties_even)
}

/// g_ij as a packed pair keeps it: `unpack(pack(j, grad, scale), scale).1`, without the
/// packing. WGSL twin: `steps_grad(pair_steps(grad, scale), scale)`.
#[inline(always)]
pub fn round(grad: Vec3, scale: f32) -> Vec3 {
    steps(grad, scale) * step(scale)
}

/// A DFSPH pair as the GPU's factors pass stores it in `dfsph_pairs` (8 bytes, two pairs to a
/// 16-byte entry, so that an iteration's pair loop issues one load per two pairs): the
/// neighbour index `j` (below [`MAX_PARTICLES`]) and g_ij = m ∇W_ij as fixed point
/// of `scale` (the largest |g_ij|), as one 64-bit field, `[0]` the low word: j in bits 0-17,
/// then x, y, z in [`GRAD_BITS`] bits each. Components beyond ±scale are clamped.
/// WGSL twin: `pack_pair` in the plugin's `render/solvers/dfsph/dfsph.wgsl`.
pub fn pack(j: u32, grad: Vec3, scale: f32) -> [u32; 2] {
    let [x, y, z] = (steps(grad, scale) + ZERO).to_array().map(|c| c as u32);
    [
        j | (x << INDEX_BITS),
        (x >> (32 - INDEX_BITS)) | (y << 1) | (z << (1 + GRAD_BITS)),
    ]
}

/// The neighbour index and g_ij of a pair packed by [`pack`] with the same scale.
/// WGSL twin: `unpack_pair` in the plugin's `render/solvers/dfsph/dfsph.wgsl`.
pub fn unpack(packed: [u32; 2], scale: f32) -> (u32, Vec3) {
    let bits = |word: u32, offset: u32, count: u32| (word >> offset) & ((1 << count) - 1);
    let low_bits = 32 - INDEX_BITS;
    let x = bits(packed[0], INDEX_BITS, low_bits) | (bits(packed[1], 0, 1) << low_bits);
    let y = bits(packed[1], 1, GRAD_BITS);
    let z = bits(packed[1], 1 + GRAD_BITS, GRAD_BITS);
    let component = |c: u32| (c as f32 - ZERO) * step(scale);
    (
        bits(packed[0], 0, INDEX_BITS),
        Vec3::new(component(x), component(y), component(z)),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_pair_keeps_its_index_and_its_gradient_to_half_a_step() {
        let scale = 3.7e4;
        let half_step = 0.5 * step(scale) * 1.0001;
        let grads = [
            Vec3::ZERO,
            Vec3::new(scale, -scale, 0.5 * scale),
            Vec3::new(-0.123 * scale, 0.999 * scale, -0.77 * scale),
            Vec3::new(1e-3 * scale, -2e-5 * scale, 0.3333 * scale),
        ];
        for j in [0, 1, 12_345, MAX_PARTICLES - 1] {
            for g in grads {
                let (k, back) = unpack(pack(j, g, scale), scale);
                assert_eq!(k, j);
                assert!((back - g).abs().max_element() <= half_step, "{g} -> {back}");
                // Antisymmetric: g_ji = -g_ij exactly, so the pair's forces cancel.
                let (_, mirrored) = unpack(pack(j, -g, scale), scale);
                assert_eq!(mirrored, -back);
            }
        }
    }

    #[test]
    fn rounding_is_what_a_pair_keeps() {
        let scale = scale(0.008, 1.9e6);
        let mut rng = crate::rng::SplitMix64::new(3);
        let mut component = || rng.range(-1.2 * scale, 1.2 * scale);
        for _ in 0..1000 {
            let g = Vec3::new(component(), component(), component());
            assert_eq!(round(g, scale), unpack(pack(5, g, scale), scale).1, "{g}");
        }
    }

    #[test]
    fn a_gradient_beyond_the_scale_is_clamped_to_it() {
        let (_, back) = unpack(pack(7, Vec3::new(2.0, -5.0, 1.0), 1.0), 1.0);
        assert_eq!(back, Vec3::new(1.0, -1.0, 1.0));
    }
}
