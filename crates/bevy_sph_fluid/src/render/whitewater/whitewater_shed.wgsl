// Whitewater's potentials and shedding (Ihmsen et al. 2012, §4.1-4.2), one thread per fluid
// particle. With v_ij = v_i - v_j and x̂_ij = x_ij / |x_ij|:
// - trapped air: Σ_j |v_ij| (1 - v̂_ij·x̂_ij) W̃_ij (eq. 3);
// - wave crest: Σ_j (1 - n̂_i·n̂_j) W̃_ij over the surface neighbours behind i's surface
//   (x̂_ji·n̂_i < 0), counted only while i moves out along its normal (v̂_i·n̂_i >= 0.6; eqs. 4-6);
// - kinetic energy: |v_i|²/2 per unit mass.
// The particle sheds n_d = Φ_k (k_ta Φ_ta + k_wc Φ_wc) dt diffuse particles (eq. 7): the whole
// part, and one more with the remainder's probability, each popped from the free list (counted
// as dropped when it is empty) and placed at random in the cylinder of radius Δx/2 its velocity
// sweeps over the step, with that velocity plus its offset from the axis (eqs. 8-9). The
// potentials and the rate go to the second half of whitewater_fluid, for checks. A particle
// slower than the kinetic energy's lower limit sheds nothing whatever its other potentials
// (Φ_k = 0 multiplies them): it skips their neighbour loop and records them as -1.
// Rust twin: sph_core::whitewater::ihmsen2012 (FluidView::potentials, shed_count, Whitewater).
#import sph::bindings::{params, particle_state, position_at, particle_scratch, whitewater_fluid_at, diffuse_state_at, grid, diffuse_free_at, cell_counts, diffuse_counts_at, shared_state}
#import sph::neighbors::{home_cell, neighbor_range_count, neighbor_range, accepts}
#import sph::whitewater::{scaled_weight, clamp_potential, random, fluid_velocity, whitewater_dt, DIFFUSE_FREE, DIFFUSE_BORN, DIFFUSE_DROPPED, DIFFUSE_SPRAY, DIFFUSE_HIGH_WATER}

// The most diffuse particles one fluid particle sheds in a run (once a frame); the rest are
// counted as dropped (a bound on the loop for settings and frames far beyond the defaults:
// 10,000/s at the largest rate over a 1 ms step shed 10).
const MAX_SHED_PER_RUN: u32 = 256u;

// Two unit vectors that make an orthonormal basis with the unit vector n (Duff et al. 2017,
// as glam's any_orthonormal_pair).
fn orthonormal_pair(n: vec3<f32>) -> array<vec3<f32>, 2> {
    let sign = select(-1.0, 1.0, n.z >= 0.0);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    return array<vec3<f32>, 2>(
        vec3<f32>(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x),
        vec3<f32>(b, sign + n.y * n.y * a, -n.y),
    );
}

// One diffuse particle shed by fluid particle i (its s-th this step) at x moving at v.
fn shed(i: u32, s: u32, x: vec3<f32>, v: vec3<f32>, dt: f32) {
    let top = atomicSub(&cell_counts[diffuse_counts_at(DIFFUSE_FREE)], 1u);
    if bitcast<i32>(top) <= 0 {
        // Empty: undo, and count the particle the full pool refused.
        atomicAdd(&cell_counts[diffuse_counts_at(DIFFUSE_FREE)], 1u);
        atomicAdd(&cell_counts[diffuse_counts_at(DIFFUSE_DROPPED)], 1u);
        return;
    }
    let slot = grid[diffuse_free_at(top - 1u)];
    let speed = length(v);
    var axis = vec3<f32>(0.0);
    var e = array<vec3<f32>, 2>(vec3<f32>(1.0, 0.0, 0.0), vec3<f32>(0.0, 0.0, 1.0));
    if speed > 0.0 {
        axis = v / speed;
        e = orthonormal_pair(axis);
    }
    let k = 1u + 4u * s;
    let radius = 0.5 * params.spacing * sqrt(random(i, k));
    let angle = 6.283185307 * random(i, k + 1u);
    let along = random(i, k + 2u) * speed * dt;
    let offset = radius * (cos(angle) * e[0] + sin(angle) * e[1]);
    let lo = params.whitewater_lifetime_min;
    let lifetime = lo + (params.whitewater_lifetime_max - lo) * random(i, k + 3u);
    let capacity = params.whitewater_capacity;
    // Born as spray; the next step's advection classifies it.
    particle_scratch[diffuse_state_at(slot)] = vec4<f32>(x + offset + along * axis, 0.0);
    particle_scratch[diffuse_state_at(capacity + slot)] = vec4<f32>(v + offset, lifetime);
    atomicAdd(&cell_counts[diffuse_counts_at(DIFFUSE_BORN)], 1u);
    atomicAdd(&cell_counts[diffuse_counts_at(DIFFUSE_SPRAY)], 1u);
    atomicMax(&cell_counts[diffuse_counts_at(DIFFUSE_HIGH_WATER)], slot + 1u);
}

@compute @workgroup_size(#{WORKGROUP_SIZE})
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= params.particle_count {
        return;
    }
    let x_i = particle_state[position_at(i)].xyz;
    let v_i = fluid_velocity(i);
    let kinetic_energy = 0.5 * dot(v_i, v_i);
    let kinetic = clamp_potential(kinetic_energy, params.whitewater_kinetic_min, params.whitewater_kinetic_max);
    if kinetic <= 0.0 {
        particle_scratch[whitewater_fluid_at(params.capacity + i)] = vec4<f32>(-1.0, -1.0, kinetic_energy, 0.0);
        return;
    }
    let n_i = particle_scratch[whitewater_fluid_at(i)].xyz;
    let c = home_cell(x_i);
    var trapped_air = 0.0;
    var curvature = 0.0;
    for (var q = 0u; q < neighbor_range_count(); q++) {
        let range = neighbor_range(c, q);
        for (var j = range.x; j < range.y; j++) {
            let x_j = particle_state[position_at(j)].xyz;
            let x_ij = x_i - x_j;
            let r2 = dot(x_ij, x_ij);
            if j == i || r2 <= 0.0 || r2 >= params.h_squared || !accepts(c, q, x_j) {
                continue;
            }
            let r = sqrt(r2);
            let w = scaled_weight(r);
            let x_hat = x_ij / r;
            let v_ij = v_i - fluid_velocity(j);
            let speed = length(v_ij);
            if speed > 0.0 {
                trapped_air += speed * (1.0 - dot(v_ij / speed, x_hat)) * w;
            }
            // Only surface neighbours behind i's surface bend it (the bulk has no normal).
            let n_j = particle_scratch[whitewater_fluid_at(j)].xyz;
            if any(n_i != vec3<f32>(0.0)) && any(n_j != vec3<f32>(0.0)) && dot(-x_hat, n_i) < 0.0 {
                curvature += (1.0 - dot(n_i, n_j)) * w;
            }
        }
    }
    let speed = length(v_i);
    var wave_crest = 0.0;
    if speed > 0.0 && dot(v_i / speed, n_i) >= 0.6 {
        wave_crest = curvature;
    }
    let rate = kinetic
        * (params.whitewater_trapped_air_rate
            * clamp_potential(trapped_air, params.whitewater_trapped_air_min, params.whitewater_trapped_air_max)
            + params.whitewater_wave_crest_rate
            * clamp_potential(wave_crest, params.whitewater_wave_crest_min, params.whitewater_wave_crest_max));
    particle_scratch[whitewater_fluid_at(params.capacity + i)] =
        vec4<f32>(trapped_air, wave_crest, kinetic_energy, rate);
    let dt = whitewater_dt();
    let expected = rate * dt;
    let whole = floor(expected);
    var count = u32(whole);
    if random(i, 0u) < expected - whole {
        count += 1u;
    }
    if count > MAX_SHED_PER_RUN {
        atomicAdd(&cell_counts[diffuse_counts_at(DIFFUSE_DROPPED)], count - MAX_SHED_PER_RUN);
        count = MAX_SHED_PER_RUN;
    }
    for (var s = 0u; s < count; s++) {
        shed(i, s, x_i, v_i, dt);
    }
}
