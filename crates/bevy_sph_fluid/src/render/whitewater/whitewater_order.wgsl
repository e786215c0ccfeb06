// Whitewater's counting sort, pass 3, one thread per pool slot: each live slot writes itself at
// its cell's first rank plus its rank in the cell, so that diffuse_order lists the live slots in
// cell order for the advection.
#import sph::bindings::{params, particle_scratch, diffuse_state_at, grid, diffuse_order_at, cell_counts, diffuse_bins_at}

@compute @workgroup_size(#{WORKGROUP_SIZE})
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let k = id.x;
    let capacity = params.whitewater_capacity;
    if k >= capacity {
        return;
    }
    if particle_scratch[diffuse_state_at(k)].w < 0.0 {
        return;
    }
    let cell = grid[diffuse_order_at(capacity + k)];
    let rank = grid[diffuse_order_at(2u * capacity + k)];
    grid[diffuse_order_at(atomicLoad(&cell_counts[diffuse_bins_at(cell)]) + rank)] = k;
}
