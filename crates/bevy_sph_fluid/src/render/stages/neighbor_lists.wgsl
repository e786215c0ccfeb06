// PBF's neighbour lists (Macklin & Müller 2013, Algorithm 1, line 5): after the sort of the
// predicted positions x*, the particles j != i within h of i at x*, at most
// sph_core::gpu_layout::PBF_MAX_NEIGHBORS (params.pbf_max_neighbors) of them (neighbour k at list_slot(i, k)), and their
// number in neighbor_count. The step's other PBF passes loop over these lists and evaluate the
// kernel at their own positions. A particle with more neighbours keeps the first ones found and
// is counted in the clock. Rust twin: sph_core::neighbor::lists::NeighborLists::rebuild.
#import sph::bindings::{params, particle_state, position_at, grid, neighbor_count_at, neighbor_lists_at, shared_state}
#import sph::neighbors::{home_cell, neighbor_range_count, neighbor_range, accepts, list_slot}

@compute @workgroup_size(#{WORKGROUP_SIZE})
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= params.particle_count {
        return;
    }
    let x_i = particle_state[position_at(i)].xyz;
    let c = home_cell(x_i);
    let h2 = params.h_squared;
    let most = params.pbf_max_neighbors;
    var count = 0u;
    var overflow = false;
    for (var q = 0u; q < neighbor_range_count(); q++) {
        let range = neighbor_range(c, q);
        for (var j = range.x; j < range.y; j++) {
            let x_j = particle_state[position_at(j)].xyz;
            let r = x_i - x_j;
            if j == i || dot(r, r) >= h2 || !accepts(c, q, x_j) {
                continue;
            }
            if count < most {
                grid[neighbor_lists_at(list_slot(i, count))] = j;
                count += 1u;
            } else {
                overflow = true;
            }
        }
    }
    grid[neighbor_count_at(i)] = count;
    if overflow {
        atomicAdd(&shared_state.clock.neighbor_list_overflows, 1u);
    }
}
