// Symplectic Euler: v += a dt; x += v dt; guard (sph_core::integrate::euler); pumps;
// probes. The leapfrogs'
// phases are fused into count_cells (before) and forces (after). It runs right after the
// time-step pass, so it saves or restores the rollback checkpoint first, and does not integrate
// a state being restored.
#import sph::bindings::{params, position, velocity, acceleration}
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
    let a = acceleration[i].xyz;
    let v = velocity[i].xyz + a * dt;
    let drifted = position[i].xyz + v * dt;
    let moved = guard(drifted, v);
    let pushed = pumped(moved.x, moved.v, dt);
    position[i] = vec4<f32>(moved.x, position[i].w);
    velocity[i] = vec4<f32>(pushed, 0.0);
    record_speed(i, pushed);
    record_probes(i, moved.x, pushed);
}
