// PBF's XSPH viscosity (Macklin & Müller 2013, eq. 17) and the final densities, at the final
// positions (see pbf.wgsl):
// v_i = v*_i + c Σ_j (m/ρ_j) (v*_j - v*_i) W_ij, v* the velocities of the velocity pass and ρ_j
// the last λ pass's densities (normal.y); ρ_i = m Σ_j W_ij + ρ0 Σ_b V_b W_ib (self included);
// the pressure the step's λ stand for, -(ρ_i² / ρ0) Λ_i / dt² (Λ_i in normal.w, see pbf.wgsl); a = (v - v*) / dt + g, the step's mean acceleration (diagnostics).
// No-slip samples (velocity.w = the body's friction f_b > 0; only when some sample has friction,
// params.boundary_friction) count as water moving with their body:
// v_i += min(c Σ_b f_b V_b W_ib, 1) (v̄_b - v_i), v̄_b their mean velocity by those weights, and
// each sample's body feels -m Δv_i / dt times its share of the weight (Akinci 2012's two-way
// coupling, summed by shaders/body_reactions.wgsl).
// Without VORTICITY this is the step's last pass: pumps, |v + g dt_max| for the time-step
// rule, probes. Rust twins: sph_core::solver::pbf::xsph_vorticity::{xsph_and_densities,
// wall_friction}, sph_core::solver::pbf::macklin2013::equivalent_pressure, then
// sph_core::flow::pump::apply_pumps.
#import sph::bindings::{params, particle_state, position_at, grid, neighbor_count_at, neighbor_lists_at, velocity_at, particle_scratch, sorted_velocity_at, acceleration_at, particle_scalars, density_at, pressure_at, normal_at, boundary_samples, boundary_position_at, boundary_velocity_at, boundary_body, boundary_body_at}
#import sph::kernels::cubic
#import sph::neighbors::{grid_cell, boundary_range, list_slot}
#import sph::clock::{step_dt, frozen, record_speed}
#import sph::pumps::pumped
#import sph::probes::record_probes
#import sph::pbf::{current_position, mass, rest_density, equivalent_pressure}
#import sph::types::drained
#import sph::body_reactions::{begin_reactions, end_reactions, add_reaction, flush_reaction}

@compute @workgroup_size(#{WORKGROUP_SIZE})
fn main(
    @builtin(global_invocation_id) id: vec3<u32>,
    @builtin(local_invocation_index) local: u32,
) {
    // Only the friction has reactions here: without it the pass skips the workgroup sums and
    // their barriers (a uniform, so they stay in uniform control flow).
    let with_friction = params.boundary_friction > 0.0;
    if with_friction {
        begin_reactions(local, #{WORKGROUP_SIZE}u);
    }
    if id.x < params.particle_count && !frozen() {
        particle(id.x);
        if with_friction {
            flush_reaction();
        }
    }
    if with_friction {
        end_reactions(local, #{WORKGROUP_SIZE}u);
    }
}

// The friction factor f_b of sample b (0 on a free-slip body).
fn friction_of(b: u32) -> f32 {
    return max(boundary_samples[boundary_velocity_at(b)].w, 0.0);
}

// What walk_samples sums over a particle's samples: Σ_b V_b W_ib, and with friction
// Σ_b f_b V_b W_ib and Σ_b f_b V_b W_ib v_b.
var<private> solid_sum: f32;
var<private> wall_weight: f32;
var<private> wall_moving: vec3<f32>;

// The boundary samples within h of the sorted position `sorted`, the kernel at `x_i`. Without
// `reaction` it sums them into the private sums above; with it, it gives each no-slip sample
// its share, reaction_per_weight f_b V_b W_ib, once the particle's total weight is known.
fn walk_samples(sorted: vec3<f32>, x_i: vec3<f32>, reaction: bool, reaction_per_weight: vec3<f32>) {
    let with_friction = params.boundary_friction > 0.0;
    let cell = grid_cell(sorted);
    for (var q = 0u; q < 9u; q++) {
        let range = boundary_range(cell, q);
        for (var b = range.x; b < range.y; b++) {
            let sample = boundary_samples[boundary_position_at(b)];
            let paired = sorted - sample.xyz;
            if dot(paired, paired) >= params.h_squared {
                continue;
            }
            if reaction {
                let friction = friction_of(b);
                if friction > 0.0 {
                    let w = friction * sample.w * cubic(length(x_i - sample.xyz));
                    add_reaction(boundary_body[boundary_body_at(b)], reaction_per_weight * w, sample.xyz);
                }
                continue;
            }
            // V_b W_ib, once for the density and the friction's weight f_b V_b W_ib.
            let volume_weight = sample.w * cubic(length(x_i - sample.xyz));
            solid_sum += volume_weight;
            if with_friction {
                let w = friction_of(b) * volume_weight;
                wall_weight += w;
                wall_moving += boundary_samples[boundary_velocity_at(b)].xyz * w;
            }
        }
    }
}

fn particle(i: u32) {
    let sorted = particle_state[position_at(i)].xyz;
    let x_i = current_position(i);
    let v_i = particle_scratch[sorted_velocity_at(i)].xyz;
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
    solid_sum = 0.0;
    wall_weight = 0.0;
    wall_moving = vec3<f32>(0.0);
    walk_samples(sorted, x_i, false, vec3<f32>(0.0));
    let rho = m * fluid + rest_density() * solid_sum;
    particle_scalars[density_at(i)] = rho;
    let dt = step_dt();
    particle_scalars[pressure_at(i)] = equivalent_pressure(particle_state[normal_at(i)].w, rho, dt);
    var v = v_i + smoothing * params.pbf_xsph_c;
    if wall_weight > 0.0 {
        let change = (wall_moving / wall_weight - v_i) * min(params.pbf_xsph_c * wall_weight, 1.0);
        v += change;
        if !drained(particle_state[position_at(i)].w) {
            // The samples again, each with its share of -m Δv / dt.
            walk_samples(sorted, x_i, true, change * (-m / (dt * wall_weight)));
        }
    }
    particle_state[acceleration_at(i)] = vec4<f32>((v - v_i) / dt + params.gravity, 0.0);
#ifndef VORTICITY
    v = pumped(x_i, v, dt);
    record_speed(i, v + params.gravity * params.fixed_dt);
    record_probes(i, x_i, v);
#endif
    particle_state[velocity_at(i)] = vec4<f32>(v, 0.0);
}
