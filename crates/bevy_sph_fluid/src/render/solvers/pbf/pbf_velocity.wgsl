// PBF's velocities (Macklin & Müller 2013, Algorithm 1, lines 21-23): after the step's Jacobi
// iterations, v_i = (x_i - x_prev,i) / dt from the final positions and the step's start
// (`acceleration_start`, see pbf.wgsl), then the guard (sph_core::boundary::guard) on both. The
// guarded position stays in the final buffer; the velocity goes to `sorted_velocity`, where
// the XSPH pass reads every neighbour's. While the clock is frozen the sorted positions are
// the final ones. The step counts as one force evaluation of the bodies' sums.
// Rust twin: step 4 of sph_core::solver::pbf (PbfStep::advance).
#import sph::bindings::{params, particle_state, position_at, particle_scratch, sorted_velocity_at, acceleration_start_at, shared_state}
#import sph::guard::guard
#import sph::clock::{step_dt, frozen}
#import sph::pbf::{current_position, write_current_position}

@compute @workgroup_size(#{WORKGROUP_SIZE})
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i == 0u && !frozen() {
        atomicAdd(&shared_state.body_forces.evaluations, 1u);
    }
    if i >= params.particle_count {
        return;
    }
    if frozen() {
        write_current_position(i, particle_state[position_at(i)].xyz);
        return;
    }
    let x = current_position(i);
    let v = (x - particle_state[acceleration_start_at(i)].xyz) / step_dt();
    let moved = guard(x, v);
    write_current_position(i, moved.x);
    particle_scratch[sorted_velocity_at(i)] = vec4<f32>(moved.v, 0.0);
}
