// DFSPH's densities and factors after each sort (Bender & Koschier 2017, eq. 9 with our κ):
// over the lists' pairs and the boundary samples within h,
// ρ_i = m Σ_j W_ij (self included) + Σ_b Ψ_b W_ib,
// D_i = (Σ_j g_ij + Σ_b g_ib + Σ_b' g_ib')·(Σ_j g_ij + Σ_b g_ib) + Σ_j |g_ij|²  ->  1/D_i (0
// below the cut-off params.dfsph_factor_epsilon), b' the samples that mirror κ_i (none while a dynamic
// collider is in the water, sph_core::Boundary::mirrors); unless that D is below half of D without them (a particle pinched between a
// mirrored wall and a body, whose factor the mirror would halve): then none mirrors.
// Besides: Σ_b g_ib, Σ_b' g_ib', Σ_b v_b·g_ib, the neighbour count, the rise's floor
// p̂_i = max((κ_i^ρ + κ_i^v) ρ0², 0) of the solves' totals, and each pair's g_ij for the solves
// (dfsph.wgsl).
// Thread 0 opens the next solve (the divergence-free one after the move).
// Rust twins: sph_core::neighbor::lists::NeighborLists::rebuild (the densities) and
// sph_core::solver::dfsph::bender2017::compute_factors.
#import sph::bindings::{params, particle_state, position_at, particle_scalars, density_at, velocity_predicted_at, grid, neighbor_count_at, neighbor_lists_at, acceleration_start_at, particle_scratch, sorted_acceleration_start_at, dfsph_mirror_at, boundary_samples, boundary_position_at, boundary_velocity_at}
#import sph::kernels::{cubic, cubic_grad}
#import sph::neighbors::{grid_cell, boundary_range, list_slot}
#import sph::dfsph::{mass, rest_density, pair_scale, pair_steps, steps_grad, pack_pair, set_pairs, open_solve, samples_mirror}

// Over the fluid pairs: m Σ_j W_ij (self included), Σ_j g_ij and Σ_j |g_ij|².
struct FluidSums {
    rho: f32,
    grad: vec3<f32>,
    squares: f32,
}

// Pair k of particle i at x_i: adds it to the sums and returns it packed (sph::dfsph's pairs).
// The sums take g_ij as packed, as every iteration reads it (and as the CPU solver rounds it).
fn fluid_pair(i: u32, k: u32, x_i: vec3<f32>, scale: f32, sums: ptr<function, FluidSums>) -> vec2<u32> {
    let m = mass();
    let j = grid[neighbor_lists_at(list_slot(i, k))];
    let r = x_i - particle_state[position_at(j)].xyz;
    let r_len = length(r);
    let steps = pair_steps(cubic_grad(r, r_len) * m, scale);
    let g = steps_grad(steps, scale);
    (*sums).rho += m * cubic(r_len);
    (*sums).grad += g;
    (*sums).squares += dot(g, g);
    return pack_pair(j, steps);
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
    let x_i = particle_state[position_at(i)].xyz;
    let m = mass();
    let rho0 = rest_density();
    let h2 = params.h_squared;
    var fluid_sums = FluidSums(m * cubic(0.0), vec3<f32>(0.0), 0.0);
    let scale = pair_scale();
    let fluid = grid[neighbor_count_at(i)];
    for (var k = 0u; k < fluid; k += 2u) {
        let first = fluid_pair(i, k, x_i, scale, &fluid_sums);
        // Past the list's end: a pair with itself and no gradient, which no reader uses.
        var second = pack_pair(i, vec3<f32>(0.0));
        if k + 1u < fluid {
            second = fluid_pair(i, k + 1u, x_i, scale, &fluid_sums);
        }
        set_pairs(i, k, first, second);
    }
    var rho = fluid_sums.rho;
    let sum = fluid_sums.grad;
    let squares = fluid_sums.squares;
    var boundary_grad = vec3<f32>(0.0);
    var mirrored_grad = vec3<f32>(0.0);
    var boundary_flux = 0.0;
    var solid = 0u;
    let mirror_samples = samples_mirror();
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
            let r_len = sqrt(r2);
            let psi = rho0 * sample.w;
            rho += psi * cubic(r_len);
            let g = cubic_grad(r, r_len) * psi;
            boundary_grad += g;
            if mirror_samples {
                mirrored_grad += g;
            }
            boundary_flux += dot(boundary_samples[boundary_velocity_at(b)].xyz, g);
            solid += 1u;
        }
    }
    let once = dot(sum + boundary_grad, sum + boundary_grad) + squares;
    let mirrored = once + dot(mirrored_grad, sum + boundary_grad);
    let mirror = mirrored >= 0.5 * once;
    let d = select(once, mirrored, mirror);
    let inverse = select(0.0, 1.0 / d, d > params.dfsph_factor_epsilon);
    let totals = particle_state[velocity_predicted_at(i)];
    let p_floor = max((totals.x + totals.y) * rho0 * rho0, 0.0);
    particle_scalars[density_at(i)] = rho;
    particle_state[acceleration_start_at(i)] = vec4<f32>(boundary_grad, inverse);
    particle_scratch[sorted_acceleration_start_at(i)] = vec4<f32>(boundary_flux, f32(fluid + solid), f32(solid), p_floor);
    particle_scratch[dfsph_mirror_at(i)] = select(vec4<f32>(0.0), vec4<f32>(mirrored_grad, 1.0), mirror);
}
