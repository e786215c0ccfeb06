// DFSPH's predicted velocities (Bender & Koschier 2017, Algorithm 1, line 6): right after the
// time-step pass, the rollback checkpoint is saved or restored, then v* = v + dt a_np with the
// non-pressure accelerations of the forces pass. Thread 0 opens the constant-density solve.
// Nothing is integrated while the clock is frozen or a state is being restored (the rest of the
// step then leaves the restored state alone, and the move's sort rebuilds its neighbourhood).
// Rust twin: step 3 of sph_core::solver::dfsph::DfsphStep::advance.
#import sph::bindings::{params, velocity, acceleration}
#import sph::clock::{step_dt, frozen}
#import sph::checkpoint::{apply_checkpoint, restoring}
#import sph::dfsph::open_solve

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
    let v = velocity[i].xyz + acceleration[i].xyz * step_dt();
    velocity[i] = vec4<f32>(v, 0.0);
}
