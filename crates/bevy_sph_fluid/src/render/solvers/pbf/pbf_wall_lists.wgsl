// PBF's wall lists (the samples' side of the step's pairs): after the sort of the predicted
// positions x*, the particles within h of each boundary sample at x*, as the particles' own
// boundary loops find them (pbf.wgsl), at most PBF_MAX_WALL_NEIGHBORS of them, in words 2.. of
// the sample's wall list and their count in word 1 (pbf.wgsl's wall_word). A sample with more
// keeps the first found and is counted in the clock with the particles' overflows. The
// iterations' pbf_wall_lambda passes read these lists.
// Rust twin: sph_core::solver::pbf::wall_lambda::SampleNeighbors::rebuild.
#import sph::bindings::{params, particle_state, position_at, boundary_samples, boundary_position_at, boundary_body, shared_state}
#import sph::neighbors::{home_cell, neighbor_range_count, neighbor_range, accepts}
#import sph::pbf::{PBF_MAX_WALL_NEIGHBORS, wall_word}

@compute @workgroup_size(#{WORKGROUP_SIZE})
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let b = id.x;
    if b >= params.boundary_sample_count {
        return;
    }
    let x_b = boundary_samples[boundary_position_at(b)].xyz;
    let c = home_cell(x_b);
    let h2 = params.h_squared;
    var count = 0u;
    var overflow = false;
    for (var q = 0u; q < neighbor_range_count(); q++) {
        let range = neighbor_range(c, q);
        for (var j = range.x; j < range.y; j++) {
            let x_j = particle_state[position_at(j)].xyz;
            let r = x_j - x_b;
            if dot(r, r) >= h2 || !accepts(c, q, x_j) {
                continue;
            }
            if count < PBF_MAX_WALL_NEIGHBORS {
                boundary_body[wall_word(b, 2u + count)] = j;
                count += 1u;
            } else {
                overflow = true;
            }
        }
    }
    boundary_body[wall_word(b, 1u)] = count;
    if overflow {
        atomicAdd(&shared_state.clock.neighbor_list_overflows, 1u);
    }
}
