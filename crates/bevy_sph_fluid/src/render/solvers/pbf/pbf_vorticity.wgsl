// PBF's vorticity (Macklin & Müller 2013, eq. 15, with the SPH volume m/ρ_j so that ω is in
// 1/s): ω_i = Σ_j (m/ρ_j) (v_j - v_i) × ∇_j W_ij, ∇_j W_ij = -∇_i W_ij, at the final positions
// with the velocities after XSPH and the final densities; into `sorted_acceleration` (see
// pbf.wgsl). Only with VORTICITY. Rust twin: sph_core::solver::pbf::xsph_vorticity::vorticity.
#import sph::bindings::{params, grid, neighbor_count_at, neighbor_lists_at, particle_state, velocity_at, particle_scalars, density_at, particle_scratch, sorted_acceleration_at}
#import sph::kernels::cubic_grad
#import sph::neighbors::list_slot
#import sph::clock::frozen
#import sph::pbf::{current_position, mass}

@compute @workgroup_size(#{WORKGROUP_SIZE})
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= params.particle_count || frozen() {
        return;
    }
    let x_i = current_position(i);
    let v_i = particle_state[velocity_at(i)].xyz;
    var curl = vec3<f32>(0.0);
    for (var k = 0u; k < grid[neighbor_count_at(i)]; k++) {
        let j = grid[neighbor_lists_at(list_slot(i, k))];
        let r = x_i - current_position(j);
        let r2 = dot(r, r);
        let grad_j = -cubic_grad(r, sqrt(r2));
        curl += cross(particle_state[velocity_at(j)].xyz - v_i, grad_j) * (mass() / particle_scalars[density_at(j)]);
    }
    particle_scratch[sorted_acceleration_at(i)] = vec4<f32>(curl, 0.0);
}
