// Reading the clock from the integrating passes (see stages/time_step.wgsl).
#define_import_path sph::clock

#import sph::bindings::{shared_state, particle_state, position_at}
#import sph::types::drained

// dt of the step in progress, chosen by the time-step pass at the start of the step.
fn step_dt() -> f32 {
    return shared_state.clock.dt;
}

// Integration stops (state frozen) once a step was detected as unstable.
fn frozen() -> bool {
    return shared_state.clock.unstable_step != 0u;
}

// Record particle i's |v| (a step's final velocity) and |a| (the acceleration the next
// integration phase uses) for the time-step pass; a particle a drain took is no longer water
// and is left out. Lengths are non-negative, so their f32 bits order like the values; NaN and
// infinity order above them all.
fn record_speed(i: u32, v: vec3<f32>) {
    if !drained(particle_state[position_at(i)].w) {
        atomicMax(&shared_state.clock.max_speed_bits, bitcast<u32>(length(v)));
    }
}

fn record_acceleration(i: u32, a: vec3<f32>) {
    if !drained(particle_state[position_at(i)].w) {
        atomicMax(&shared_state.clock.max_acceleration_bits, bitcast<u32>(length(a)));
    }
}

// Count a particle the guard moved out of a collider or (`wall`) back into the box.
fn record_correction(wall: bool) {
    atomicAdd(&shared_state.clock.boundary_corrections, 1u);
    if wall {
        atomicAdd(&shared_state.clock.wall_corrections, 1u);
    }
}
