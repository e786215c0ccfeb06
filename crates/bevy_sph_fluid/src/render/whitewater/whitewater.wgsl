// Whitewater's shared pieces (Ihmsen, Akinci, Akinci & Teschner 2012, "Unified spray, foam and
// bubbles for particle-based fluids"; CPU twin sph_core::whitewater::ihmsen2012): the pool's
// counters, the scaled kernel W̃, the clamping Φ, the classes and the random numbers.
#define_import_path sph::whitewater

#import sph::bindings::{params, shared_state, particle_state, velocity_at}

// The counters' words in the cell_counts arena, in sph_core::gpu_layout::GpuDiffuseCounts's
// order.
const DIFFUSE_FREE: u32 = 0u;
const DIFFUSE_BORN: u32 = 1u;
const DIFFUSE_DROPPED: u32 = 2u;
const DIFFUSE_EXPIRED: u32 = 3u;
const DIFFUSE_SPRAY: u32 = 4u;
const DIFFUSE_FOAM: u32 = 5u;
const DIFFUSE_BUBBLES: u32 = 6u;
const DIFFUSE_HIGH_WATER: u32 = 7u;

// A diffuse slot's w: its class (0 spray, 1 foam, 2 bubble), or this when the slot is empty.
const EMPTY_SLOT: f32 = -1.0;

// Below this share of h, a particle's normal sum is the bulk's: no surface
// (ihmsen2012::SURFACE_THRESHOLD).
const SURFACE_THRESHOLD: f32 = 0.2;

// Fluid particle j's velocity as the last step left it. The stages run after the step's first
// sort, into which PBF's prediction is fused: it has added g dt already (Macklin & Müller 2013,
// Algorithm 1, line 2), and its density constraint takes that back later in the step. Read as
// it is, still water would move down at g dt and foam riding it would sink.
fn fluid_velocity(j: u32) -> vec3<f32> {
    let v = particle_state[velocity_at(j)].xyz;
#ifdef SOLVER_PBF
    return v - params.gravity * shared_state.clock.dt;
#else
    return v;
#endif
}

// The time the stages advance the pool by: they run once a frame, in its last step, for all of
// the frame's steps (their dt is the last step's). The diffuse particles are a picture of the
// water and do not act on it, so a frame's step is accurate enough, and the pool's neighbour
// loops, the frame's largest cost with whitewater on, run once instead of once a step.
fn whitewater_dt() -> f32 {
    return shared_state.clock.dt * f32(params.whitewater_steps);
}

// W̃(r) = 1 - r/h within h, else 0 (eq. 2).
fn scaled_weight(r: f32) -> f32 {
    if r < params.h {
        return 1.0 - r / params.h;
    }
    return 0.0;
}

// Φ(I) = (min(I, τ_max) - min(I, τ_min)) / (τ_max - τ_min), in [0, 1] (eq. 1).
fn clamp_potential(value: f32, lo: f32, hi: f32) -> f32 {
    if hi <= lo {
        return 0.0;
    }
    return (min(value, hi) - min(value, lo)) / (hi - lo);
}

// The class of a diffuse particle with `neighbors` fluid particles within h (§4.3): 0 spray
// (fewer than spray_below), 2 bubble (more than bubble_above), else 1 foam.
fn classify(neighbors: u32) -> u32 {
    if neighbors < params.whitewater_spray_below {
        return 0u;
    }
    if neighbors > params.whitewater_bubble_above {
        return 2u;
    }
    return 1u;
}

// Jarzynski & Olano 2020's PCG hash: one u32 to another, well mixed.
fn pcg_hash(x: u32) -> u32 {
    let state = x * 747796405u + 2891336453u;
    let word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

// Uniform in [0, 1): draw k of fluid particle i in this step, from the scene's seed. The CPU
// draws from one sequential stream instead; the two agree in distribution, not number by number.
fn random(i: u32, k: u32) -> f32 {
    let stream = pcg_hash(shared_state.clock.step ^ pcg_hash(i ^ pcg_hash(params.whitewater_seed)));
    return f32(pcg_hash(stream + k) >> 8u) / 16777216.0;
}
