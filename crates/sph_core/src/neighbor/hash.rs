//! The design's spatial hash: (i, j, k) = floor(x / h), hash = (i·73856093 xor j·19349663 xor
//! k·83492791) mod n; particles sorted by hash, per-hash start/end offsets. A candidate counts only
//! if it really lies in the visited cell (so colliding cells are never visited twice) and closer
//! than h (so hash collisions never change the physics).

use glam::{IVec3, Vec3};

/// The design's three primes.
pub const HASH_PRIMES: [u32; 3] = [73_856_093, 19_349_663, 83_492_791];

/// Marks an empty hash bucket in `cell_start`.
pub const EMPTY_BUCKET: u32 = u32::MAX;

/// Hash-table size for `capacity` particles: the next power of two >= 2 capacity, at least 64.
pub fn hash_table_size(capacity: usize) -> usize {
    (2 * capacity).next_power_of_two().max(64)
}

/// A spatial hash over unbounded space.
#[derive(Clone, Debug)]
pub struct SpatialHash {
    /// Cell edge (= h).
    pub cell_size: f32,
    /// Number of buckets n.
    pub table_size: u32,
    /// Each particle's bucket (sort key).
    pub keys: Vec<u32>,
    /// First sorted slot of each bucket, or [`EMPTY_BUCKET`].
    pub cell_start: Vec<u32>,
    /// One past the last sorted slot of each bucket.
    pub cell_end: Vec<u32>,
    /// Sorted slot -> particle.
    pub order: Vec<u32>,
    sorted_keys: Vec<u32>,
}

impl SpatialHash {
    /// A hash with cells of size `h` and [`hash_table_size`]`(capacity)` buckets.
    pub fn new(h: f32, capacity: usize) -> Self {
        let table_size = hash_table_size(capacity);
        Self {
            cell_size: h,
            table_size: table_size as u32,
            keys: Vec::new(),
            cell_start: vec![EMPTY_BUCKET; table_size],
            cell_end: vec![0; table_size],
            order: Vec::new(),
            sorted_keys: Vec::new(),
        }
    }

    /// Integer cell (i, j, k) = floor(x / h) (NaN maps to 0).
    #[inline]
    pub fn cell_coords(&self, p: Vec3) -> IVec3 {
        (p / self.cell_size).floor().as_ivec3()
    }

    /// The design's hash of a cell, with wrapping 32-bit products as on the GPU.
    #[inline]
    pub fn hash(&self, c: IVec3) -> u32 {
        let h = (c.x as u32).wrapping_mul(HASH_PRIMES[0])
            ^ (c.y as u32).wrapping_mul(HASH_PRIMES[1])
            ^ (c.z as u32).wrapping_mul(HASH_PRIMES[2]);
        h % self.table_size
    }

    /// Computes the keys, sorts the particles by key (stable) and fills the bucket offsets.
    /// Returns the gather order (sorted slot -> particle).
    pub fn sort(&mut self, positions: &[Vec3]) -> &[u32] {
        let mut keys = std::mem::take(&mut self.keys);
        keys.clear();
        keys.extend(positions.iter().map(|&p| self.hash(self.cell_coords(p))));
        self.keys = keys;
        self.order.clear();
        self.order.extend(0..positions.len() as u32);
        let keys = &self.keys;
        self.order.sort_by_key(|&i| keys[i as usize]);
        self.sorted_keys.clear();
        self.sorted_keys
            .extend(self.order.iter().map(|&i| keys[i as usize]));
        self.cell_start.fill(EMPTY_BUCKET);
        let n = self.sorted_keys.len();
        for (k, &key) in self.sorted_keys.iter().enumerate() {
            if k == 0 || self.sorted_keys[k - 1] != key {
                self.cell_start[key as usize] = k as u32;
            }
            if k + 1 == n || self.sorted_keys[k + 1] != key {
                self.cell_end[key as usize] = k as u32 + 1;
            }
        }
        &self.order
    }

    /// Calls `f(j, x_i - x_j, r²)` for every sorted particle j with r < h (i itself included).
    #[inline]
    pub fn for_each_neighbor(
        &self,
        positions: &[Vec3],
        x_i: Vec3,
        mut f: impl FnMut(usize, Vec3, f32),
    ) {
        let h2 = self.cell_size * self.cell_size;
        let c = self.cell_coords(x_i);
        for dz in -1..=1 {
            for dy in -1..=1 {
                for dx in -1..=1 {
                    let cell = c.wrapping_add(IVec3::new(dx, dy, dz));
                    let bucket = self.hash(cell) as usize;
                    let start = self.cell_start[bucket];
                    if start == EMPTY_BUCKET {
                        continue;
                    }
                    let range = start as usize..self.cell_end[bucket] as usize;
                    for (j, &x_j) in positions[range.clone()].iter().enumerate() {
                        let j = range.start + j;
                        let r = x_i - x_j;
                        let r2 = r.length_squared();
                        if r2 < h2 && self.cell_coords(x_j) == cell {
                            f(j, r, r2);
                        }
                    }
                }
            }
        }
    }

    /// Candidates visited for a particle at `x_i` (every particle of the 27 buckets).
    pub fn candidate_count(&self, x_i: Vec3) -> usize {
        let c = self.cell_coords(x_i);
        let mut n = 0;
        for dz in -1..=1 {
            for dy in -1..=1 {
                for dx in -1..=1 {
                    let bucket = self.hash(c.wrapping_add(IVec3::new(dx, dy, dz))) as usize;
                    if self.cell_start[bucket] != EMPTY_BUCKET {
                        n += (self.cell_end[bucket] - self.cell_start[bucket]) as usize;
                    }
                }
            }
        }
        n
    }
}
