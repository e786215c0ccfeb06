// Whitewater's surface normals (Ihmsen et al. 2012, §4.1): n̂_i, the unit vector away from the
// W̃-weighted centre of i's neighbours, Σ_j x_ij W̃_ij, or zero in the bulk (the sum shorter than
// SURFACE_THRESHOLD h). Written to the first half of whitewater_fluid for the shedding pass.
// Thread 0 zeroes the class counters, which the advection and the shedding count again.
// Rust twin: sph_core::whitewater::ihmsen2012::FluidView (its normals).
#import sph::bindings::{params, particle_state, position_at, particle_scratch, whitewater_fluid_at, cell_counts, diffuse_counts_at}
#import sph::neighbors::{home_cell, neighbor_range_count, neighbor_range, accepts}
#import sph::whitewater::{scaled_weight, SURFACE_THRESHOLD, DIFFUSE_SPRAY, DIFFUSE_FOAM, DIFFUSE_BUBBLES}

@compute @workgroup_size(#{WORKGROUP_SIZE})
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i == 0u {
        atomicStore(&cell_counts[diffuse_counts_at(DIFFUSE_SPRAY)], 0u);
        atomicStore(&cell_counts[diffuse_counts_at(DIFFUSE_FOAM)], 0u);
        atomicStore(&cell_counts[diffuse_counts_at(DIFFUSE_BUBBLES)], 0u);
    }
    if i >= params.particle_count {
        return;
    }
    let x_i = particle_state[position_at(i)].xyz;
    let c = home_cell(x_i);
    var sum = vec3<f32>(0.0);
    for (var q = 0u; q < neighbor_range_count(); q++) {
        let range = neighbor_range(c, q);
        for (var j = range.x; j < range.y; j++) {
            let x_j = particle_state[position_at(j)].xyz;
            let r = x_i - x_j;
            let r2 = dot(r, r);
            if r2 < params.h_squared && accepts(c, q, x_j) {
                sum += r * scaled_weight(sqrt(r2));
            }
        }
    }
    var normal = vec3<f32>(0.0);
    if length(sum) >= SURFACE_THRESHOLD * params.h {
        normal = normalize(sum);
    }
    particle_scratch[whitewater_fluid_at(i)] = vec4<f32>(normal, 0.0);
}
