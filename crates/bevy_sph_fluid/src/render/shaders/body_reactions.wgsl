// The fluid's reaction on the bodies (Akinci 2012's two-way coupling), summed without a float
// atomic: each thread sums its particle's reactions per body, the workgroup in 32-bit fixed
// point, and the workgroup adds its total to the frame's 64-bit sums
// (sph_core::gpu_layout::GpuBodyForces). A pass calls begin_reactions, then add_reaction per
// boundary pair of its particle and flush_reaction, then end_reactions, all in uniform control
// flow. Used by the forces pass, PBF's correction and XSPH passes and DFSPH's reactions pass.
// Nothing is summed while no collider is in the boundary (reactions_read).
#define_import_path sph::body_reactions

#import sph::bindings::{params, shared_state}

const BODY_SLOTS: u32 = 32u;
const NO_BODY: u32 = 0xffffffffu;

// The workgroup's sums per body: Σ f and Σ x_b × f, in units of body_force_unit and
// body_moment_unit (zeroed by the
// workgroup itself: Bevy's pipelines do not ask wgpu to zero workgroup memory).
var<workgroup> body_sums: array<atomic<i32>, 192>;

// The thread's running reaction on one body, flushed into body_sums when the body changes.
var<private> reaction_body: u32;
var<private> reaction_force: vec3<f32>;
var<private> reaction_moment: vec3<f32>;

// sph_core::gpu_layout::body_force_unit: a thousandth of a particle's standard weight [N].
fn body_force_unit() -> f32 {
    return max(params.particle_mass * 9.81e-3, 1.0e-30);
}

// sph_core::gpu_layout::body_moment_unit: the moments' unit, 16 times finer [N m].
fn body_moment_unit() -> f32 {
    return body_force_unit() / 16.0;
}

// Whether the sums are read: by a collider's SphColliderForce, or by the container's SphWallForce
// (the walls are body 0). Without a reader nothing is summed, and the passes skip the workgroup
// sums and their two barriers (on dambreak32k about 5 of the forces pass's 19 ms). A uniform's
// value, so the barriers below stay in uniform control flow.
fn reactions_read() -> bool {
    return params.sum_reactions != 0u;
}

fn to_units(v: f32, unit: f32) -> i32 {
    return i32(clamp(round(v / unit), -2.0e9, 2.0e9));
}

fn flush_reaction() {
    if !reactions_read() {
        return;
    }
    let body = reaction_body;
    if body < BODY_SLOTS {
        let base = body * 6u;
        let f = body_force_unit();
        let m = body_moment_unit();
        atomicAdd(&body_sums[base], to_units(reaction_force.x, f));
        atomicAdd(&body_sums[base + 1u], to_units(reaction_force.y, f));
        atomicAdd(&body_sums[base + 2u], to_units(reaction_force.z, f));
        atomicAdd(&body_sums[base + 3u], to_units(reaction_moment.x, m));
        atomicAdd(&body_sums[base + 4u], to_units(reaction_moment.y, m));
        atomicAdd(&body_sums[base + 5u], to_units(reaction_moment.z, m));
    }
    reaction_body = NO_BODY;
    reaction_force = vec3<f32>(0.0);
    reaction_moment = vec3<f32>(0.0);
}

// The force f on body `body` (a sample's boundary_body entry) at `at`.
fn add_reaction(body: u32, f: vec3<f32>, at: vec3<f32>) {
    if !reactions_read() {
        return;
    }
    if body != reaction_body {
        flush_reaction();
        reaction_body = body;
    }
    reaction_force += f;
    reaction_moment += cross(at, f);
}

// Adds a workgroup's sum to the 64-bit (low, high) words of sum k: the low word with its
// carry, then the sign-extended high word.
fn add_to_frame(k: u32, v: i32) {
    let add = bitcast<u32>(v);
    let old = atomicAdd(&shared_state.body_forces.sums[2u * k], add);
    let carry = select(0u, 1u, old + add < old);
    let high = select(0u, 0xffffffffu, v < 0) + carry;
    if high != 0u {
        atomicAdd(&shared_state.body_forces.sums[2u * k + 1u], high);
    }
}

// Zeroes the workgroup's sums (`threads`: the workgroup size) and the thread's running reaction.
fn begin_reactions(local: u32, threads: u32) {
    if !reactions_read() {
        return;
    }
    for (var k = local; k < BODY_SLOTS * 6u; k += threads) {
        atomicStore(&body_sums[k], 0);
    }
    reaction_body = NO_BODY;
    reaction_force = vec3<f32>(0.0);
    reaction_moment = vec3<f32>(0.0);
    workgroupBarrier();
}

// Adds the workgroup's sums to the frame's (after every thread flushed its reaction).
fn end_reactions(local: u32, threads: u32) {
    if !reactions_read() {
        return;
    }
    workgroupBarrier();
    for (var k = local; k < BODY_SLOTS * 6u; k += threads) {
        let v = atomicLoad(&body_sums[k]);
        if v != 0 {
            add_to_frame(k, v);
        }
    }
}
