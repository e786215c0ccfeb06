// A DFSPH solve's source and next stiffness (Bender & Koschier 2017, Algorithms 2 and 3, with
// κ = p/ρ²; see dfsph.wgsl), at the current velocities:
// constant density (default):  s_i = clamp(ρ_i + dt Dρ_i/Dt - ρ0, 0, MAX_CORRECTION ρ0),
//                              κ_i = s_i / (dt² D_i), and on the top row (s_i = 0,
//                              ρ_i < TOP_ROW_DENSITY ρ0) as much more as lifts the particle's
//                              sum to its neighbours' |g_ij|-weighted mean sum (the positive
//                              ones, before this iteration's), at most |g| Δx / (2 ρ0);
// divergence-free (DIVERGENCE_SOLVE): s_i = max(Dρ_i/Dt, 0) for particles with at least
//                              INTERIOR_NEIGHBORS neighbours, else 0; κ_i = s_i / (dt D_i).
// The iterations after the solve's first over-relax where s_i > η ρ0: ω κ_i + (ω - 1) κ'_i,
// κ'_i the stiffness applied before, ω the solve's (dfsph.wgsl, over_relaxed).
// DFSPH_WARM: the warm start instead: κ_i = fraction × the stiffness the solve summed last
// step where s_i > 0, else 0, and the sum starts from it.
// Otherwise Σ s_i/ρ0 goes to the error sum the next applying pass reads (TO_B: sum b, else
// a): each thread adds its term in 64-bit fixed point.
// DFSPH_FIRST: the solve's first source (without the warm start its sum starts at 0); the
// sources after it count the iteration the pass before applied.
// Dispatched indirectly: no workgroup runs once the solve converged.
// Rust twins: sph_core::solver::dfsph::bender2017::{density_source, divergence_source,
// stiffness_from_source, TopRowStiffness} and the warm start of sph_core::solver::dfsph.
#import sph::bindings::{params, shared_state, particle_state, velocity_at, particle_scalars, density_at, grid, neighbor_count_at}
#import sph::clock::{step_dt, frozen}
#import sph::checkpoint::restoring
#import sph::dfsph::{Pair, INTERIOR_NEIGHBORS, spacing, rest_density, factor, pairs, stiffness, set_stiffness, over_relaxed, tolerance, total, set_total, add_error}

// (v_i - v_j)·g_ij of one pair.
fn rate_term(v_i: vec3<f32>, p: Pair) -> f32 {
    return dot(v_i - particle_state[velocity_at(p.j)].xyz, p.grad);
}

// The solve's source of particle i (see above).
fn source(i: u32) -> f32 {
    let f = factor(i);
    let v_i = particle_state[velocity_at(i)].xyz;
    var rate = dot(v_i, f.boundary_grad) - f.boundary_flux;
    let fluid = grid[neighbor_count_at(i)];
    for (var k = 0u; k < fluid; k += 2u) {
        let two = pairs(i, k);
        rate += rate_term(v_i, two.first);
        if k + 1u < fluid {
            rate += rate_term(v_i, two.second);
        }
    }
#ifdef DIVERGENCE_SOLVE
    if f.neighbors < INTERIOR_NEIGHBORS {
        return 0.0;
    }
    return max(rate, 0.0);
#else
    let rho0 = rest_density();
    return clamp(particle_scalars[density_at(i)] + step_dt() * rate - rho0, 0.0, params.dfsph_max_correction * rho0);
#endif
}

// Below this fraction of ρ0 a particle without a source is on the free surface
// (sph_core::solver::dfsph::bender2017::TOP_ROW_DENSITY).
const TOP_ROW_DENSITY: f32 = 0.95;

// (|g_ij| κ_j, |g_ij|) of one pair whose neighbour's sum κ_j is positive, else 0.
fn top_row_term(p: Pair) -> vec2<f32> {
    let k_j = total(p.j);
    let w = length(p.grad);
    return select(vec2<f32>(0.0), vec2<f32>(w * k_j, w), k_j > 0.0);
}

// The sum particle i's stiffness rises to on the top row, or -1 (see above; Rust twin:
// sph_core::solver::dfsph::bender2017::TopRowStiffness::targets). Reads the neighbours' sums, which no
// thread of this pass writes.
fn top_row_target(i: u32, s: f32) -> f32 {
    let rho0 = rest_density();
    if s > 0.0 || particle_scalars[density_at(i)] >= TOP_ROW_DENSITY * rho0 {
        return -1.0;
    }
    var sum = 0.0;
    var weights = 0.0;
    let fluid = grid[neighbor_count_at(i)];
    for (var k = 0u; k < fluid; k += 2u) {
        let two = pairs(i, k);
        var term = top_row_term(two.first);
        if k + 1u < fluid {
            term += top_row_term(two.second);
        }
        sum += term.x;
        weights += term.y;
    }
    if weights <= 0.0 {
        return -1.0;
    }
    let cap = length(params.gravity) * spacing() / (2.0 * rho0);
    return min(sum / weights, cap);
}

@compute @workgroup_size(#{WORKGROUP_SIZE})
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    var term = 0.0;
    if i < params.particle_count && !frozen() && !restoring() {
        let s = source(i);
        let dt = step_dt();
#ifdef DFSPH_WARM
#ifdef DIVERGENCE_SOLVE
        let fraction = params.dfsph_divergence_warm_start;
#else
        let fraction = params.dfsph_density_warm_start;
#endif
        let k = select(0.0, total(i) * fraction, s > 0.0);
        set_stiffness(i, k);
        set_total(i, k);
#else
#ifdef DIVERGENCE_SOLVE
        let scale = 1.0 / dt;
#else
        let scale = 1.0 / (dt * dt);
#endif
        let jacobi = scale * s * factor(i).inverse;
#ifdef DFSPH_FIRST
        let k = jacobi;
#else
        // Plain Jacobi where the particle is within the solve's tolerance (η ρ0): no momentum
        // on a particle whose compression is gone (see stiffness_from_source).
        let converged = s <= tolerance() * rest_density();
        let k = select(over_relaxed(jacobi, stiffness(i)), jacobi, converged);
#endif
#ifdef DIVERGENCE_SOLVE
        set_stiffness(i, k);
#else
        // Without the warm start the first iteration's sums start at 0 (none of the
        // neighbours' is positive: no target); the apply pass adds k to the sum.
        var fresh = false;
#ifdef DFSPH_FIRST
        fresh = params.dfsph_warm_start == 0.0;
#endif
        var before = 0.0;
        var lift_to = -1.0;
        if !fresh {
            before = total(i);
            lift_to = top_row_target(i, s);
        }
        set_stiffness(i, k + max(lift_to - (before + k), 0.0));
#endif
#ifdef DFSPH_FIRST
        if params.dfsph_warm_start == 0.0 {
            set_total(i, 0.0);
        }
#endif
        term = s / rest_density();
#endif
    }
#ifndef DFSPH_WARM
    // Each thread with a positive term adds it to the sum itself. Reduced over the workgroup
    // first (one barrier, then thread 0's 63 additions), the pass cost 1.7 times as much on
    // lavapipe, which runs a barrier as a switch between all of the workgroup's SIMD groups
    // (measured with `sph-bench run --backend gpu --solver dfsph`). Integer atomics: the sum does not
    // depend on the order.
    if term > 0.0 {
#ifdef TO_B
        add_error(1u, term);
#else
        add_error(0u, term);
#endif
    }
#ifndef DFSPH_FIRST
    if i == 0u {
        shared_state.clock.dfsph_applied += 1u;
    }
#endif
#endif
}
