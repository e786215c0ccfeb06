// Whitewater's advection (Ihmsen et al. 2012, §4.3 and §5), one thread per live slot, in cell
// order (whitewater_order): each diffuse particle is classified by its fluid neighbours within h
// and moved over the last step's dt: spray falls under gravity, foam takes the water's
// W̃-weighted mean velocity ṽ and ages, bubbles rise (-k_b g) and are dragged towards ṽ (k_d). Foam at the end of its lifetime
// and any particle outside the container dies: its slot is emptied and pushed on the free list.
// Rust twin: sph_core::whitewater::ihmsen2012::Whitewater::step (advect, then the deaths).
#import sph::bindings::{params, particle_state, position_at, particle_scratch, diffuse_state_at, grid, diffuse_free_at, diffuse_order_at, cell_counts, diffuse_counts_at, diffuse_bins_at, shared_state}
#import sph::neighbors::{home_cell, neighbor_range_count, neighbor_range, accepts}
#import sph::whitewater::{scaled_weight, classify, fluid_velocity, whitewater_dt, EMPTY_SLOT, DIFFUSE_FREE, DIFFUSE_EXPIRED, DIFFUSE_SPRAY}

// The fluid around a point: neighbours within h, and their W̃-weighted mean velocity (zero
// without neighbours).
struct Around {
    count: u32,
    velocity: vec3<f32>,
}

fn fluid_around(x: vec3<f32>) -> Around {
    let c = home_cell(x);
    var out = Around(0u, vec3<f32>(0.0));
    var weight = 0.0;
    var sum = vec3<f32>(0.0);
    for (var q = 0u; q < neighbor_range_count(); q++) {
        let range = neighbor_range(c, q);
        for (var j = range.x; j < range.y; j++) {
            let x_j = particle_state[position_at(j)].xyz;
            let r = x - x_j;
            let r2 = dot(r, r);
            if r2 < params.h_squared && accepts(c, q, x_j) {
                let w = scaled_weight(sqrt(r2));
                out.count += 1u;
                weight += w;
                sum += fluid_velocity(j) * w;
            }
        }
    }
    if weight > 0.0 {
        out.velocity = sum / weight;
    }
    return out;
}

@compute @workgroup_size(#{WORKGROUP_SIZE})
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    // The live slots in cell order (whitewater_order), the count of them last.
    let t = id.x;
    let capacity = params.whitewater_capacity;
    if t >= atomicLoad(&cell_counts[diffuse_bins_at(params.cell_count)]) {
        return;
    }
    let k = grid[diffuse_order_at(t)];
    let state = particle_scratch[diffuse_state_at(k)];
    if state.w < 0.0 {
        return;
    }
    let motion = particle_scratch[diffuse_state_at(capacity + k)];
    let dt = whitewater_dt();
    let water = fluid_around(state.xyz);
    let kind = classify(water.count);
    var v = motion.xyz;
    var lifetime = motion.w;
    switch kind {
        case 0u: {
            v += params.gravity * dt;
        }
        case 1u: {
            v = water.velocity;
            lifetime -= dt;
        }
        default: {
            // k_d is the share of the difference taken in a step: over the frame's steps,
            // 1 - (1 - k_d)^steps.
            let drag = 1.0 - pow(1.0 - params.whitewater_drag, f32(params.whitewater_steps));
            v += -params.whitewater_buoyancy * params.gravity * dt + drag * (water.velocity - v);
        }
    }
    let x = state.xyz + v * dt;
    let outside = any(x < params.box_min) || any(x > params.box_max);
    if (kind == 1u && lifetime <= 0.0) || outside {
        particle_scratch[diffuse_state_at(k)] = vec4<f32>(x, EMPTY_SLOT);
        let top = atomicAdd(&cell_counts[diffuse_counts_at(DIFFUSE_FREE)], 1u);
        grid[diffuse_free_at(top)] = k;
        atomicAdd(&cell_counts[diffuse_counts_at(DIFFUSE_EXPIRED)], 1u);
        return;
    }
    particle_scratch[diffuse_state_at(k)] = vec4<f32>(x, f32(kind));
    particle_scratch[diffuse_state_at(capacity + k)] = vec4<f32>(v, lifetime);
    atomicAdd(&cell_counts[diffuse_counts_at(DIFFUSE_SPRAY + kind)], 1u);
}
