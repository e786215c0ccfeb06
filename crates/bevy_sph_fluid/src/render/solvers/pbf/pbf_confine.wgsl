// PBF's vorticity confinement (Macklin & Müller 2013, eq. 16, after Fedkiw et al. 2001):
// η_i = Σ_j (m/ρ_j) (|ω_j| - |ω_i|) ∇_i W_ij, N = η/|η| (zero when η is), v_i += dt ε (N × ω_i),
// with ω from the vorticity pass (`sorted_acceleration`); a gains the same push / dt. The
// step's last pass with VORTICITY: pumps, |v + g dt_max| for the time-step rule, probes; then
// the final positions replace the sorted ones. Rust twins:
// sph_core::solver::pbf::xsph_vorticity::confine_vorticity, sph_core::flow::pump::apply_pumps.
#import sph::bindings::{params, grid, neighbor_count_at, neighbor_lists_at, particle_state, velocity_at, acceleration_at, particle_scalars, density_at, particle_scratch, sorted_acceleration_at}
#import sph::kernels::cubic_grad
#import sph::neighbors::list_slot
#import sph::clock::{step_dt, frozen, record_speed}
#import sph::pumps::pumped
#import sph::probes::record_probes
#import sph::pbf::{current_position, mass}

@compute @workgroup_size(#{WORKGROUP_SIZE})
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= params.particle_count || frozen() {
        return;
    }
    let x_i = current_position(i);
    let omega_i = particle_scratch[sorted_acceleration_at(i)].xyz;
    let w_i = length(omega_i);
    var eta = vec3<f32>(0.0);
    for (var k = 0u; k < grid[neighbor_count_at(i)]; k++) {
        let j = grid[neighbor_lists_at(list_slot(i, k))];
        let r = x_i - current_position(j);
        let r2 = dot(r, r);
        let w_j = length(particle_scratch[sorted_acceleration_at(j)].xyz);
        eta += cubic_grad(r, sqrt(r2)) * ((w_j - w_i) * mass() / particle_scalars[density_at(j)]);
    }
    let eta_len = length(eta);
    var n = vec3<f32>(0.0);
    if eta_len > 0.0 && eta_len < 3.0e38 {
        n = eta / eta_len;
    }
    let dt = step_dt();
    let push = cross(n, omega_i) * params.pbf_vorticity_epsilon;
    var v = particle_state[velocity_at(i)].xyz + push * dt;
    particle_state[acceleration_at(i)] = vec4<f32>(particle_state[acceleration_at(i)].xyz + push, 0.0);
    v = pumped(x_i, v, dt);
    record_speed(i, v + params.gravity * params.fixed_dt);
    record_probes(i, x_i, v);
    particle_state[velocity_at(i)] = vec4<f32>(v, 0.0);
}
