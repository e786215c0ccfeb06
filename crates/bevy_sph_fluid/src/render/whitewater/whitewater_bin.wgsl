// Whitewater's counting sort, pass 1, one thread per pool slot: each live diffuse particle
// counts itself in its grid cell and keeps its cell and its rank there. The pool's slots are in
// no spatial order (a slot is reused wherever its next particle is born); the advection visits
// them in cell order, so that neighbouring threads search the same cells, as the water's
// passes do.
#import sph::bindings::{params, particle_scratch, diffuse_state_at, grid, diffuse_order_at, cell_counts, diffuse_bins_at}
#import sph::neighbors::{grid_cell, grid_index}

@compute @workgroup_size(#{WORKGROUP_SIZE})
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let k = id.x;
    let capacity = params.whitewater_capacity;
    if k >= capacity {
        return;
    }
    let state = particle_scratch[diffuse_state_at(k)];
    if state.w < 0.0 {
        return;
    }
    let cell = grid_index(grid_cell(state.xyz));
    grid[diffuse_order_at(capacity + k)] = cell;
    grid[diffuse_order_at(2u * capacity + k)] = atomicAdd(&cell_counts[diffuse_bins_at(cell)], 1u);
}
