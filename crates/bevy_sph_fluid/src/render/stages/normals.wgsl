// Akinci 2013 eq. 16: n_i = h Σ_j (m / ρ_j) ∇W(x_i - x_j). Only with surface tension.
// Rust twin: sph_core::surface_tension_akinci2013::compute_normals.
#import sph::bindings::{params, particle_state, position_at, particle_scalars, density_at, normal_at}
#import sph::kernels::poly6_grad
#import sph::neighbors::{home_cell, neighbor_range_count, neighbor_range, accepts}

@compute @workgroup_size(#{WORKGROUP_SIZE})
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= params.particle_count {
        return;
    }
    let x_i = particle_state[position_at(i)].xyz;
    let c = home_cell(x_i);
    let h2 = params.h_squared;
    var sum = vec3<f32>(0.0);
    for (var q = 0u; q < neighbor_range_count(); q++) {
        let range = neighbor_range(c, q);
        for (var j = range.x; j < range.y; j++) {
            let x_j = particle_state[position_at(j)].xyz;
            let r = x_i - x_j;
            let r2 = dot(r, r);
            if r2 < h2 && accepts(c, q, x_j) {
                sum += poly6_grad(r, r2) / particle_scalars[density_at(j)];
            }
        }
    }
    particle_state[normal_at(i)] = vec4<f32>(params.h * params.particle_mass * sum, 0.0);
}
