// DFSPH's predicted velocities (Bender & Koschier 2017, Algorithm 1, line 6): right after the
// time-step pass, the rollback checkpoint is saved or restored, then v* = v + dt a_np with the
// non-pressure accelerations of the forces pass and the boundary's hydrostatic rise
// a_i^rise = -Σ_b' (p_b'^rise/ρ0²) g_ib' over the samples b' within h that mirror (none while a
// dynamic collider is in the water; dfsph.wgsl). Thread 0 opens the constant-density solve.
// Nothing is integrated while the clock is frozen or a state is being restored (the rest of the
// step then leaves the restored state alone, and the move's sort rebuilds its neighbourhood).
// Rust twins: step 3 of sph_core::solver::dfsph::DfsphStep::advance,
// sph_core::solver::dfsph::bender2017::BoundaryRise::predict.
#import sph::bindings::{params, particle_state, position_at, velocity_at, acceleration_at, boundary_samples, boundary_position_at}
#import sph::kernels::cubic_grad
#import sph::neighbors::{grid_cell, boundary_range}
#import sph::clock::{step_dt, frozen}
#import sph::checkpoint::{apply_checkpoint, restoring}
#import sph::dfsph::{open_solve, boundary_neighbors, samples_mirror, rise_floor, rise_over_rho0_squared, rest_density}

// a_i^rise at the factors' positions (none without a sample within h, nor while the samples do
// not mirror).
fn rise(i: u32) -> vec3<f32> {
    var a = vec3<f32>(0.0);
    if boundary_neighbors(i) == 0.0 || !samples_mirror() {
        return a;
    }
    let x_i = particle_state[position_at(i)].xyz;
    let p_floor = rise_floor(i);
    let h2 = params.h_squared;
    let rho0 = rest_density();
    let cell = grid_cell(x_i);
    for (var q = 0u; q < 9u; q++) {
        let range = boundary_range(cell, q);
        for (var b = range.x; b < range.y; b++) {
            let sample = boundary_samples[boundary_position_at(b)];
            let r = x_i - sample.xyz;
            let r2 = dot(r, r);
            if r2 >= h2 {
                continue;
            }
            let g = cubic_grad(r, sqrt(r2)) * (rho0 * sample.w);
            a -= g * rise_over_rho0_squared(x_i, sample.xyz, p_floor);
        }
    }
    return a;
}

@compute @workgroup_size(#{WORKGROUP_SIZE})
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i == 0u {
        open_solve(#{WORKGROUP_SIZE}u);
    }
    if i >= params.particle_count {
        return;
    }
    apply_checkpoint(i);
    if frozen() || restoring() {
        return;
    }
    let v = particle_state[velocity_at(i)].xyz + (particle_state[acceleration_at(i)].xyz + rise(i)) * step_dt();
    particle_state[velocity_at(i)] = vec4<f32>(v, 0.0);
}
