//! Dense uniform grid over the container (cell size h) with a counting sort: count per cell ->
//! exclusive prefix sum -> scatter, the same three passes as the GPU pipeline.

#[cfg(target_arch = "x86_64")]
use super::group_avx2::append_hits;
use super::group_avx2::WIDTH;
use crate::container::BoxContainer;
use crate::neighbor::pair_lanes::wide_lanes;
use crate::params::ParamError;
use glam::{IVec3, UVec3, Vec3};

pub use crate::limits::MAX_GRID_CELLS;

/// The most particles of one cell whose neighbours [`DenseGrid::append_group_neighbors`] finds
/// together.
pub const GROUP: usize = 4;

/// A dense grid whose cells are numbered x-fastest: `index = x + dims.x (y + dims.y z)`.
#[derive(Clone, Debug)]
pub struct DenseGrid {
    /// Lower corner of cell (0, 0, 0).
    pub origin: Vec3,
    /// Cell edge (= h).
    pub cell_size: f32,
    /// Cells along each axis.
    pub dims: UVec3,
    /// Particles per cell (pass 1).
    pub counts: Vec<u32>,
    /// `cell_start[c]..cell_start[c + 1]` are the sorted slots of cell c (pass 2), length cells + 1.
    pub cell_start: Vec<u32>,
    /// Each particle's rank within its cell, in arrival order (pass 1).
    pub rank: Vec<u32>,
    /// Each particle's cell (pass 1).
    pub cell_of: Vec<u32>,
    /// Sorted slot -> particle (pass 3).
    pub order: Vec<u32>,
}

impl DenseGrid {
    /// A grid covering `container` with cells of size `h`.
    pub fn new(container: &BoxContainer, h: f32) -> Result<Self, ParamError> {
        let cells = crate::limits::grid_cells(container, h)?;
        let dims = (container.size() / h).ceil().max(Vec3::ONE);
        let dims = dims.as_uvec3();
        Ok(Self {
            origin: container.min(),
            cell_size: h,
            dims,
            counts: vec![0; cells as usize],
            cell_start: vec![0; cells as usize + 1],
            rank: Vec::new(),
            cell_of: Vec::new(),
            order: Vec::new(),
        })
    }

    /// Number of cells.
    pub fn cell_count(&self) -> usize {
        self.counts.len()
    }

    /// Integer cell coordinates of `p`, clamped into the grid (NaN lands in cell 0).
    #[inline]
    pub fn cell_coords(&self, p: Vec3) -> UVec3 {
        let c = ((p - self.origin) / self.cell_size).floor().as_ivec3();
        c.clamp(IVec3::ZERO, self.dims.as_ivec3() - 1).as_uvec3()
    }

    /// Linear index of a cell.
    #[inline]
    pub fn cell_index(&self, c: UVec3) -> usize {
        (c.x + self.dims.x * (c.y + self.dims.y * c.z)) as usize
    }

    /// Pass 1, count: each particle's cell, its rank in the cell, and the per-cell counts.
    pub fn count_cells(&mut self, positions: &[Vec3]) {
        self.counts.fill(0);
        self.cell_of.clear();
        self.rank.clear();
        for &p in positions {
            let cell = self.cell_index(self.cell_coords(p));
            self.cell_of.push(cell as u32);
            self.rank.push(self.counts[cell]);
            self.counts[cell] += 1;
        }
    }

    /// Pass 2: exclusive prefix sum of the counts into `cell_start`.
    pub fn prefix_sum(&mut self) {
        let mut sum = 0u32;
        for (start, &count) in self.cell_start.iter_mut().zip(&self.counts) {
            *start = sum;
            sum += count;
        }
        self.cell_start[self.counts.len()] = sum;
    }

    /// Pass 3, scatter: particle i goes to slot `cell_start[cell] + rank`.
    pub fn scatter(&mut self) {
        self.order.resize(self.cell_of.len(), 0);
        for (i, (&cell, &rank)) in self.cell_of.iter().zip(&self.rank).enumerate() {
            self.order[(self.cell_start[cell as usize] + rank) as usize] = i as u32;
        }
    }

    /// The three passes; returns the gather order (sorted slot -> particle).
    pub fn sort(&mut self, positions: &[Vec3]) -> &[u32] {
        self.count_cells(positions);
        self.prefix_sum();
        self.scatter();
        &self.order
    }

    /// Calls `f` with each of the (up to) nine contiguous slot ranges that cover the 27 cells
    /// around `x_i`: cells adjacent along x are adjacent in memory.
    #[inline]
    fn for_each_row(&self, x_i: Vec3, mut f: impl FnMut(usize, usize)) {
        let c = self.cell_coords(x_i);
        let x0 = c.x.saturating_sub(1);
        let x1 = (c.x + 1).min(self.dims.x - 1);
        for z in c.z.saturating_sub(1)..=(c.z + 1).min(self.dims.z - 1) {
            for y in c.y.saturating_sub(1)..=(c.y + 1).min(self.dims.y - 1) {
                let first = self.cell_index(UVec3::new(x0, y, z));
                let last = self.cell_index(UVec3::new(x1, y, z));
                f(
                    self.cell_start[first] as usize,
                    self.cell_start[last + 1] as usize,
                );
            }
        }
    }

    /// Calls `f(j, x_i - x_j, r²)` for every sorted particle j with r < h (i itself included).
    /// Candidates are first compacted branch-free into a small batch, so the distance test does
    /// not mispredict on the ~80 % of candidates that lie outside the support.
    #[inline]
    pub fn for_each_neighbor(
        &self,
        positions: &[Vec3],
        x_i: Vec3,
        mut f: impl FnMut(usize, Vec3, f32),
    ) {
        const BATCH: usize = 64;
        let h2 = self.cell_size * self.cell_size;
        let mut batch = [0u32; BATCH];
        let mut len = 0;
        let mut flush = |batch: &[u32]| {
            for &j in batch {
                let r = x_i - positions[j as usize];
                f(j as usize, r, r.length_squared());
            }
        };
        self.for_each_row(x_i, |start, end| {
            for (j, &x_j) in positions[start..end].iter().enumerate() {
                batch[len] = (start + j) as u32;
                len += ((x_i - x_j).length_squared() < h2) as usize;
                if len == BATCH {
                    flush(&batch);
                    len = 0;
                }
            }
        });
        flush(&batch[..len]);
    }

    /// Appends to `out[g]` the index of every point j of `points` (sorted by this grid) other
    /// than `skip[g]` within h of `members[g]`, for the longest run of `members` (at most
    /// [`GROUP`]) that shares the first one's cell; returns the run's length (at least 1 when
    /// there are members). The run shares the 27 cells' candidates, so each candidate is loaded
    /// once and tested against the whole run: [`GROUP`] independent compactions instead of one
    /// chain per particle (the lists' build cost, docs/pbf.md).
    /// Where the CPU has AVX2 ([`wide_lanes`]), candidates are tested eight at a time
    /// (`group_avx2`); the lists are the same.
    #[inline]
    pub fn append_group_neighbors(
        &self,
        points: &[Vec3],
        members: &[Vec3],
        skip: [usize; GROUP],
        out: &mut [Vec<u32>; GROUP],
    ) -> usize {
        self.append_group_neighbors_in(points, members, skip, out, wide_lanes())
    }

    /// [`Self::append_group_neighbors`], with the AVX2 tests when `wide` (and the CPU has them).
    #[inline]
    fn append_group_neighbors_in(
        &self,
        points: &[Vec3],
        members: &[Vec3],
        skip: [usize; GROUP],
        out: &mut [Vec<u32>; GROUP],
        wide: bool,
    ) -> usize {
        let wide = wide && wide_lanes();
        // Candidates tested between two flushes of the batches.
        const SEGMENT: usize = 64;
        const CAP: usize = 2 * SEGMENT;
        let Some(&leader) = members.first() else {
            return 0;
        };
        let cell = self.cell_coords(leader);
        let count = members
            .iter()
            .take(GROUP)
            .take_while(|&&x| self.cell_coords(x) == cell)
            .count();
        let h2 = self.cell_size * self.cell_size;
        // Missing members sit at infinity: no candidate is within h of them.
        let mut x = [Vec3::splat(f32::INFINITY); GROUP];
        x[..count].copy_from_slice(&members[..count]);
        // Room for a whole block's store past CAP (`group_avx2::append_hits`).
        let mut batch = [[0u32; CAP + WIDTH]; GROUP];
        let mut len = [0usize; GROUP];
        self.for_each_row(leader, |start, end| {
            let mut from = start;
            while from < end {
                let to = (from + SEGMENT).min(end);
                for g in 0..GROUP {
                    if len[g] > CAP - SEGMENT {
                        out[g].extend_from_slice(&batch[g][..len[g]]);
                        len[g] = 0;
                    }
                }
                #[cfg(target_arch = "x86_64")]
                if wide && to <= points.len() {
                    let mut rows = batch.each_mut().map(|b| &mut b[..]);
                    // SAFETY: `wide_lanes()` holds; from <= to <= points.len(); each batch has
                    // CAP + WIDTH slots and at most CAP - SEGMENT used, and to - from <= SEGMENT.
                    from = unsafe {
                        append_hits(points, (from, to), &x, &skip, h2, &mut rows, &mut len)
                    };
                }
                let _ = wide;
                for (j, &x_j) in (from..to).zip(&points[from..to]) {
                    for g in 0..GROUP {
                        batch[g][len[g]] = j as u32;
                        len[g] += ((x[g] - x_j).length_squared() < h2 && j != skip[g]) as usize;
                    }
                }
                from = to;
            }
        });
        for g in 0..count {
            out[g].extend_from_slice(&batch[g][..len[g]]);
        }
        count
    }

    /// Σ_j w(r²) over the candidates of the 27 cells, for a weight `w` that is zero for r >= h
    /// (e.g. poly6): branch-free, with four independent accumulators so the additions pipeline.
    #[inline]
    pub fn sum_over_candidates(
        &self,
        positions: &[Vec3],
        x_i: Vec3,
        w: impl Fn(f32) -> f32,
    ) -> f32 {
        let mut acc = [0.0f32; 4];
        self.for_each_row(x_i, |start, end| {
            let row = &positions[start..end];
            let mut quads = row.chunks_exact(4);
            for quad in &mut quads {
                for (a, &x_j) in acc.iter_mut().zip(quad) {
                    *a += w((x_i - x_j).length_squared());
                }
            }
            for &x_j in quads.remainder() {
                acc[0] += w((x_i - x_j).length_squared());
            }
        });
        (acc[0] + acc[1]) + (acc[2] + acc[3])
    }

    /// Σ_j c_j w(r²) over the candidates of the 27 cells, with per-point weights `weights` (the
    /// boundary samples' volumes), for a weight `w` that is zero for r >= h: branch-free.
    #[inline]
    pub fn weighted_sum_over_candidates(
        &self,
        positions: &[Vec3],
        weights: &[f32],
        x_i: Vec3,
        w: impl Fn(f32) -> f32,
    ) -> f32 {
        let mut acc = [0.0f32; 2];
        self.for_each_row(x_i, |start, end| {
            for (k, (&x_j, &c)) in positions[start..end]
                .iter()
                .zip(&weights[start..end])
                .enumerate()
            {
                acc[k & 1] += c * w((x_i - x_j).length_squared());
            }
        });
        acc[0] + acc[1]
    }

    /// Candidates visited for a particle at `x_i` (all particles of the 27 cells).
    pub fn candidate_count(&self, x_i: Vec3) -> usize {
        let mut n = 0;
        self.for_each_row(x_i, |start, end| n += end - start);
        n
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::SplitMix64;

    #[test]
    fn the_wide_and_the_scalar_tests_list_the_same_neighbours() {
        let container = BoxContainer::from_min_max(Vec3::ZERO, Vec3::splat(0.3));
        let h = 0.04;
        let mut grid = DenseGrid::new(&container, h).expect("a small grid");
        let mut rng = SplitMix64::new(7);
        let cloud: Vec<Vec3> = (0..3000)
            .map(|_| Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 0.3)
            .collect();
        let order = grid.sort(&cloud).to_vec();
        let sorted: Vec<Vec3> = order.iter().map(|&k| cloud[k as usize]).collect();
        let (mut listed, mut i) = (0, 0);
        while i < sorted.len() {
            let members = &sorted[i..(i + GROUP).min(sorted.len())];
            let skip = std::array::from_fn(|g| i + g);
            let mut wide: [Vec<u32>; GROUP] = Default::default();
            let mut scalar: [Vec<u32>; GROUP] = Default::default();
            let count = grid.append_group_neighbors_in(&sorted, members, skip, &mut wide, true);
            let again = grid.append_group_neighbors_in(&sorted, members, skip, &mut scalar, false);
            assert_eq!(count, again);
            assert_eq!(wide, scalar, "the run from {i}");
            for (g, list) in wide.iter().enumerate().take(count) {
                let x = sorted[i + g];
                let expected: Vec<u32> = (0..sorted.len() as u32)
                    .filter(|&j| {
                        j as usize != i + g && (x - sorted[j as usize]).length_squared() < h * h
                    })
                    .collect();
                assert_eq!(list, &expected, "particle {}", i + g);
                listed += list.len();
            }
            i += count;
        }
        assert!(
            listed > 10 * sorted.len(),
            "a dense enough cloud: {listed} pairs"
        );
    }
}
