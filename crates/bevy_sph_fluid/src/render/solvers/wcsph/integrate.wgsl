// Symplectic Euler: v += a dt; x += v dt; guard (sph_core::integrate::euler); pumps;
// probes. The leapfrogs'
// phases are fused into count_cells (before) and forces (after). It runs right after the
// time-step pass, so it saves or restores the rollback checkpoint first, and does not integrate
// a state being restored.
#import sph::bindings::{params, particle_state, position_at, velocity_at, acceleration_at}
#import sph::guard::guard
#import sph::clock::{step_dt, frozen, record_speed}
#import sph::checkpoint::{apply_checkpoint, restoring}
#import sph::pumps::pumped
#import sph::probes::record_probes

@compute @workgroup_size(#{WORKGROUP_SIZE})
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= params.particle_count {
        return;
    }
    apply_checkpoint(i);
    if frozen() || restoring() {
        return;
    }
    let dt = step_dt();
    let a = particle_state[acceleration_at(i)].xyz;
    let v = particle_state[velocity_at(i)].xyz + a * dt;
    let drifted = particle_state[position_at(i)].xyz + v * dt;
    let moved = guard(drifted, v);
    let pushed = pumped(moved.x, moved.v, dt);
    particle_state[position_at(i)] = vec4<f32>(moved.x, particle_state[position_at(i)].w);
    particle_state[velocity_at(i)] = vec4<f32>(pushed, 0.0);
    record_speed(i, pushed);
    record_probes(i, moved.x, pushed);
}
