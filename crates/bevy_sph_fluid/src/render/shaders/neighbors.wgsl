// Neighbour search: the dense grid (9 contiguous rows of 3 cells) or the design's spatial hash
// (27 buckets, a candidate counts only if it lies in the visited cell). Rust twin:
// sph_core::neighbor.
#define_import_path sph::neighbors

#import sph::bindings::{params, grid, cell_start_at, bucket_start_at, bucket_end_at, boundary_cell_start_at}

fn grid_cell(p: vec3<f32>) -> vec3<i32> {
    let c = vec3<i32>(floor((p - params.grid_origin) / params.cell_size));
    return clamp(c, vec3<i32>(0), vec3<i32>(params.grid_dims) - 1);
}

fn grid_index(c: vec3<i32>) -> u32 {
    let d = params.grid_dims;
    return u32(c.x) + d.x * (u32(c.y) + d.y * u32(c.z));
}

// (i, j, k) = floor(x / h).
fn hash_cell(p: vec3<f32>) -> vec3<i32> {
    return vec3<i32>(floor(p / params.cell_size));
}

// The design's hash: (i·73856093 xor j·19349663 xor k·83492791) mod n, in wrapping u32.
fn hash_key(c: vec3<i32>) -> u32 {
    let h = (u32(c.x) * 73856093u) ^ (u32(c.y) * 19349663u) ^ (u32(c.z) * 83492791u);
    return h % params.table_size;
}

// The cell a particle's neighbour loop starts from.
fn home_cell(p: vec3<f32>) -> vec3<i32> {
#ifdef SEARCH_HASH
    return hash_cell(p);
#else
    return grid_cell(p);
#endif
}

// How many slot ranges the neighbour loop visits.
fn neighbor_range_count() -> u32 {
#ifdef SEARCH_HASH
    return 27u;
#else
    return 9u;
#endif
}

fn hash_offset(q: u32) -> vec3<i32> {
    return vec3<i32>(i32(q % 3u) - 1, i32((q / 3u) % 3u) - 1, i32(q / 9u) - 1);
}

// The q-th range of sorted slots around home cell c: a grid row (dy, dz) spanning x-1..x+1,
// or one hash bucket.
fn neighbor_range(c: vec3<i32>, q: u32) -> vec2<u32> {
#ifdef SEARCH_HASH
    let b = hash_key(c + hash_offset(q));
    let s = grid[bucket_start_at(b)];
    if s == 0u {
        return vec2<u32>(0u, 0u);
    }
    return vec2<u32>(s - 1u, grid[bucket_end_at(b)]);
#else
    let cells = grid_row_cells(c, q);
    if cells.x > cells.y {
        return vec2<u32>(0u, 0u);
    }
    return vec2<u32>(grid[cell_start_at(cells.x)], grid[cell_start_at(cells.y + 1u)]);
#endif
}

// The first and last cell of grid row q (dy, dz) spanning x-1..x+1 around the cell c, or (1, 0)
// when the row lies outside the grid.
fn grid_row_cells(c: vec3<i32>, q: u32) -> vec2<u32> {
    let dims = vec3<i32>(params.grid_dims);
    let y = c.y + i32(q % 3u) - 1;
    let z = c.z + i32(q / 3u) - 1;
    if y < 0 || y >= dims.y || z < 0 || z >= dims.z {
        return vec2<u32>(1u, 0u);
    }
    let x0 = max(c.x - 1, 0);
    let x1 = min(c.x + 1, dims.x - 1);
    return vec2<u32>(grid_index(vec3<i32>(x0, y, z)), grid_index(vec3<i32>(x1, y, z)));
}

// Where the lists keep particle i's k-th neighbour (`neighbor_lists`; `dfsph_pairs` tiles the
// same way two pairs to an entry, sph::dfsph's pairs_slot): in tiles of
// LIST_TILE particles, each tile's entries row by row (entry k of the tile's particles side by
// side, then entry k + 1; sph_core::gpu_layout::LIST_TILE). A SIMD group of consecutive
// particles reads one contiguous row per k, and the rows follow each other, so a pass over the
// lists streams through memory. Laid out k * capacity + i instead, the rows lay 512 KiB apart
// at 32,768 particles: every k another page, and a dambreak32k DFSPH step with 8 + 8 iterations
// pinned took 375 ms on lavapipe against 273 tiled (medians of 7; docs/dfsph.md, "Tiled lists").
const LIST_TILE: u32 = 8u;

fn list_slot(i: u32, k: u32) -> u32 {
    return tiled_slot(i, k, params.pbf_max_neighbors);
}

// Entry k of particle i in tiles of LIST_TILE particles with `rows` entries each.
fn tiled_slot(i: u32, k: u32, rows: u32) -> u32 {
    return ((i / LIST_TILE) * rows + k) * LIST_TILE + i % LIST_TILE;
}

// Whether a candidate at x_j in range q really belongs to it (hash collisions never count).
fn accepts(c: vec3<i32>, q: u32, x_j: vec3<f32>) -> bool {
#ifdef SEARCH_HASH
    return all(hash_cell(x_j) == c + hash_offset(q));
#else
    return true;
#endif
}

// The q-th (of 9) range of sorted boundary samples around the grid cell c: the boundary samples
// are sorted over the dense grid in both search modes (Rust twin: sph_core::boundary::samples).
fn boundary_range(c: vec3<i32>, q: u32) -> vec2<u32> {
    let cells = grid_row_cells(c, q);
    if cells.x > cells.y {
        return vec2<u32>(0u, 0u);
    }
    return vec2<u32>(grid[boundary_cell_start_at(cells.x)], grid[boundary_cell_start_at(cells.y + 1u)]);
}
