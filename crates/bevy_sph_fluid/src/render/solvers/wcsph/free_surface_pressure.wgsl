// p_i = pressure_eos[i] where not 0 (a negative one, with the clamp off, is kept); at the free
// surface, where the clamped equation of state gives 0, the average of the pressures around i
// over the neighbours that have one, Σ_j V_j p_j W_poly6 / Σ_{p_j > 0} V_j W_poly6 (V_j = m/ρ_j;
// 0 without such a neighbour), at most params.max_surface_pressure = ρ0 |g| Δx/2.
// Rust twin: sph_core::free_surface_pressure.
#import sph::bindings::{params, particle_state, position_at, particle_scalars, density_at, pressure_at, pressure_eos_at}
#import sph::kernels::poly6
#import sph::neighbors::{home_cell, neighbor_range_count, neighbor_range, accepts}

@compute @workgroup_size(#{WORKGROUP_SIZE})
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= params.particle_count {
        return;
    }
    let own = particle_scalars[pressure_eos_at(i)];
    if own != 0.0 {
        particle_scalars[pressure_at(i)] = own;
        return;
    }
    let x_i = particle_state[position_at(i)].xyz;
    let c = home_cell(x_i);
    let h2 = params.h_squared;
    var weighted = 0.0;
    var weights = 0.0;
    for (var q = 0u; q < neighbor_range_count(); q++) {
        let range = neighbor_range(c, q);
        for (var j = range.x; j < range.y; j++) {
            let x_j = particle_state[position_at(j)].xyz;
            let r = x_i - x_j;
            let r2 = dot(r, r);
            let p_j = particle_scalars[pressure_eos_at(j)];
            if r2 < h2 && p_j > 0.0 && accepts(c, q, x_j) {
                let w = poly6(r2) / particle_scalars[density_at(j)];
                weighted += w * p_j;
                weights += w;
            }
        }
    }
    var average = 0.0;
    if weights > 0.0 {
        average = weighted / weights;
    }
    particle_scalars[pressure_at(i)] = min(average, params.max_surface_pressure);
}
