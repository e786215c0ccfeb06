//! The distance tests of [`super::grid::DenseGrid::append_group_neighbors`] eight candidates at
//! a time with AVX2: one gather per component, one compare per member, and a branch-free
//! left-packing store of the hits (the permutation of each 8-bit mask from a 1 KiB table)
//! instead of eight dependent scalar compactions per member.

use glam::Vec3;

/// Candidates per test.
pub const WIDTH: usize = 8;

/// For each 8-bit mask, the lanes of its set bits in order, four bits per lane (lane k of the
/// packed result in bits 4k..4k+4).
const PACK: [u32; 256] = {
    let mut table = [0u32; 256];
    let mut mask = 0;
    while mask < 256 {
        let (mut packed, mut slot, mut lane) = (0u32, 0, 0);
        while lane < 8 {
            if mask & (1 << lane) != 0 {
                packed |= (lane as u32) << (4 * slot);
                slot += 1;
            }
            lane += 1;
        }
        table[mask] = packed;
        mask += 1;
    }
    table
};

/// Tests the candidates `from..` of `points` in blocks of [`WIDTH`] (as many whole blocks as fit
/// before `to`) against the `GROUP` members `x` (at infinity when missing) and appends the index of
/// each candidate within `h2` of member g, other than `skip[g]`, to `batch[g][len[g]..]`;
/// returns where it stopped (the rest, fewer than [`WIDTH`], is the caller's).
///
/// # Safety
/// The CPU has AVX2, `from <= to <= points.len()`, and every `batch[g]` has room for
/// `to - from + WIDTH` more entries after `len[g]` (a store writes a whole block).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,popcnt")]
pub unsafe fn append_hits<const GROUP: usize>(
    points: &[Vec3],
    (from, to): (usize, usize),
    x: &[Vec3; GROUP],
    skip: &[usize; GROUP],
    h2: f32,
    batch: &mut [&mut [u32]; GROUP],
    len: &mut [usize; GROUP],
) -> usize {
    use std::arch::x86_64::*;
    debug_assert!(from <= to && to <= points.len());
    let base = points.as_ptr() as *const f32;
    let mut j = from;
    // SAFETY: the caller's contract: AVX2; j + WIDTH <= to <= len keeps every gather within
    // `points`; each store lands within the room the caller left.
    unsafe {
        let stride = _mm256_setr_epi32(0, 3, 6, 9, 12, 15, 18, 21);
        let shifts = _mm256_setr_epi32(0, 4, 8, 12, 16, 20, 24, 28);
        let lanes = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
        let h2 = _mm256_set1_ps(h2);
        while j + WIDTH <= to {
            let at = base.add(3 * j);
            let px = _mm256_i32gather_ps::<4>(at, stride);
            let py = _mm256_i32gather_ps::<4>(at.add(1), stride);
            let pz = _mm256_i32gather_ps::<4>(at.add(2), stride);
            let index = _mm256_add_epi32(_mm256_set1_epi32(j as i32), lanes);
            for g in 0..GROUP {
                let dx = _mm256_sub_ps(_mm256_set1_ps(x[g].x), px);
                let dy = _mm256_sub_ps(_mm256_set1_ps(x[g].y), py);
                let dz = _mm256_sub_ps(_mm256_set1_ps(x[g].z), pz);
                let r2 = _mm256_fmadd_ps(dz, dz, _mm256_fmadd_ps(dy, dy, _mm256_mul_ps(dx, dx)));
                let near = _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_LT_OQ>(r2, h2)) as u32;
                let itself = _mm256_movemask_ps(_mm256_castsi256_ps(_mm256_cmpeq_epi32(
                    index,
                    _mm256_set1_epi32(skip[g] as u32 as i32),
                ))) as u32;
                let hits = near & !itself;
                let order = _mm256_and_si256(
                    _mm256_srlv_epi32(_mm256_set1_epi32(PACK[hits as usize] as i32), shifts),
                    _mm256_set1_epi32(0xF),
                );
                let packed = _mm256_add_epi32(_mm256_set1_epi32(j as i32), order);
                let out = batch[g].as_mut_ptr().add(len[g]);
                _mm256_storeu_si256(out as *mut __m256i, packed);
                len[g] += hits.count_ones() as usize;
            }
            j += WIDTH;
        }
    }
    j
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_table_packs_the_set_lanes_in_order() {
        for (mask, &packed) in PACK.iter().enumerate() {
            let lanes: Vec<u32> = (0..mask.count_ones())
                .map(|k| (packed >> (4 * k)) & 0xF)
                .collect();
            let expected: Vec<u32> = (0..8).filter(|l| mask & (1 << l) != 0).collect();
            assert_eq!(lanes, expected, "mask {mask:08b}");
        }
    }
}
