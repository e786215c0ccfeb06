// PBF's XSPH viscosity (Macklin & Müller 2013, eq. 17) and the final densities, at the final
// positions (see pbf.wgsl):
// v_i = v*_i + c Σ_j (m/ρ_j) (v*_j - v*_i) W_ij, v* the velocities of the velocity pass and ρ_j
// the last λ pass's densities (normal.y); ρ_i = m Σ_j W_ij + ρ0 Σ_b V_b W_ib (self included);
// the pressure the step's λ stand for, -ρ0 Λ_i / dt² (Λ_i in normal.w, see pbf.wgsl); a = (v - v*) / dt + g, the step's mean acceleration (diagnostics).
// Without VORTICITY this is the step's last pass: pumps, |v + g dt_max| for the time-step
// rule, probes. Rust twins: sph_core::solver::pbf::macklin2013::{xsph, compute_densities,
// equivalent_pressure}, then
// sph_core::flow::pump::apply_pumps.
#import sph::bindings::{params, particle_state, position_at, grid, neighbor_count_at, neighbor_lists_at, velocity_at, particle_scratch, sorted_velocity_at, acceleration_at, particle_scalars, density_at, pressure_at, normal_at, boundary_samples, boundary_position_at}
#import sph::kernels::cubic
#import sph::neighbors::{grid_cell, boundary_range, list_slot}
#import sph::clock::{step_dt, frozen, record_speed}
#import sph::pumps::pumped
#import sph::probes::record_probes
#import sph::pbf::{current_position, mass, rest_density, equivalent_pressure}

@compute @workgroup_size(#{WORKGROUP_SIZE})
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= params.particle_count || frozen() {
        return;
    }
    let sorted = particle_state[position_at(i)].xyz;
    let x_i = current_position(i);
    let v_i = particle_scratch[sorted_velocity_at(i)].xyz;
    let h2 = params.h_squared;
    let m = mass();
    var smoothing = vec3<f32>(0.0);
    var fluid = cubic(0.0);
    for (var k = 0u; k < grid[neighbor_count_at(i)]; k++) {
        let j = grid[neighbor_lists_at(list_slot(i, k))];
        let r = x_i - current_position(j);
        let r2 = dot(r, r);
        let w = cubic(sqrt(r2));
        fluid += w;
        smoothing += (particle_scratch[sorted_velocity_at(j)].xyz - v_i) * (m / particle_state[normal_at(j)].y * w);
    }
    var solid = 0.0;
    let cell = grid_cell(sorted);
    for (var q = 0u; q < 9u; q++) {
        let range = boundary_range(cell, q);
        for (var b = range.x; b < range.y; b++) {
            let sample = boundary_samples[boundary_position_at(b)];
            let paired = sorted - sample.xyz;
            if dot(paired, paired) < h2 {
                let r = x_i - sample.xyz;
                solid += sample.w * cubic(length(r));
            }
        }
    }
    particle_scalars[density_at(i)] = m * fluid + rest_density() * solid;
    let dt = step_dt();
    particle_scalars[pressure_at(i)] = equivalent_pressure(particle_state[normal_at(i)].w, dt);
    var v = v_i + smoothing * params.pbf_xsph_c;
    particle_state[acceleration_at(i)] = vec4<f32>((v - v_i) / dt + params.gravity, 0.0);
#ifndef VORTICITY
    v = pumped(x_i, v, dt);
    record_speed(i, v + params.gravity * params.fixed_dt);
    record_probes(i, x_i, v);
#endif
    particle_state[velocity_at(i)] = vec4<f32>(v, 0.0);
}
