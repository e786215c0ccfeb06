// ρ_i = m Σ_j W_poly6(x_i - x_j) (Müller 2003 eq. 3, self included)
//     + ρ0 Σ_b V_b W_poly6(x_i - x_b) (Akinci 2012, the walls' and colliders' samples),
// then p_i from the EOS (into pressure_eos; free_surface_pressure.wgsl writes pressure). Rust twin: sph_core::density. NEIGHBOR_COUNT (debug) also records each particle's neighbours.
#import sph::bindings::{params, particle_state, position_at, particle_scalars, density_at, pressure_eos_at, grid, neighbor_count_at, boundary_samples, boundary_position_at}
#import sph::kernels::{poly6, eos_pressure}
#import sph::neighbors::{home_cell, neighbor_range_count, neighbor_range, accepts, grid_cell, boundary_range}

@compute @workgroup_size(#{WORKGROUP_SIZE})
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= params.particle_count {
        return;
    }
    let x_i = particle_state[position_at(i)].xyz;
    let c = home_cell(x_i);
    let h2 = params.h_squared;
    var sum = 0.0;
    var neighbors = 0u;
    for (var q = 0u; q < neighbor_range_count(); q++) {
        let range = neighbor_range(c, q);
        for (var j = range.x; j < range.y; j++) {
            let x_j = particle_state[position_at(j)].xyz;
            let r = x_i - x_j;
            let r2 = dot(r, r);
            if r2 < h2 && accepts(c, q, x_j) {
                sum += poly6(r2);
                neighbors += 1u;
            }
        }
    }
    var boundary = 0.0;
    let g = grid_cell(x_i);
    for (var q = 0u; q < 9u; q++) {
        let range = boundary_range(g, q);
        for (var b = range.x; b < range.y; b++) {
            let sample = boundary_samples[boundary_position_at(b)];
            let r = x_i - sample.xyz;
            boundary += sample.w * poly6(dot(r, r));
        }
    }
    let rho = params.particle_mass * sum + params.rest_density * boundary;
    particle_scalars[density_at(i)] = rho;
    particle_scalars[pressure_eos_at(i)] = eos_pressure(rho);
#ifdef NEIGHBOR_COUNT
    // Self excluded.
    grid[neighbor_count_at(i)] = neighbors - 1u;
#endif
}
