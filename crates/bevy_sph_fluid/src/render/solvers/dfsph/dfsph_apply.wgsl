// The first pass of a DFSPH Jacobi iteration (Bender & Koschier 2017, Algorithms 2 and 3):
// first the decision, then v_i += dt a_i with
// a_i = -Σ_j (κ_i + κ_j) g_ij - κ_i (Σ_b g_ib + Σ_b' g_ib') (the samples b' mirror κ_i; see
// dfsph.wgsl), and the stiffness joins the solve's sum.
// The decision (every thread takes the same): with `applied` iterations done and the last
// source's mean error e (sum a, or FROM_B sum b), the solve goes on while
// (applied < min or e > η) and applied < max; otherwise thread 0 closes it (the remaining
// passes dispatch nothing) and the pass returns. Going on, thread 0 clears the other sum for
// the next source.
// DFSPH_WARM: the warm start's stiffness, applied without a decision (it is the sum already).
// Constant density by default, DIVERGENCE_SOLVE the divergence-free solve's limits.
// Rust twins: sph_core::solver::dfsph::bender2017::apply_stiffness and the loop of
// sph_core::solver::dfsph.
#import sph::bindings::{params, shared_state, particle_state, velocity_at, grid, neighbor_count_at}
#import sph::clock::{step_dt, frozen}
#import sph::checkpoint::restoring
#import sph::dfsph::{Pair, factor, mirrored_grad, pairs, stiffness, total, set_total, mean_error, clear_error, close_solve, solve_goes_on}

// (κ_i + κ_j) g_ij of one pair.
fn pressure_term(k_i: f32, p: Pair) -> vec3<f32> {
    return (k_i + stiffness(p.j)) * p.grad;
}

@compute @workgroup_size(#{WORKGROUP_SIZE})
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if frozen() || restoring() || shared_state.clock.dfsph_done != 0u {
        return;
    }
#ifndef DFSPH_WARM
#ifdef FROM_B
    let read = 1u;
#else
    let read = 0u;
#endif
    if !solve_goes_on(shared_state.clock.dfsph_applied, mean_error(read)) {
        if i == 0u {
            close_solve();
        }
        return;
    }
    if i == 0u {
        clear_error(1u - read);
    }
#endif
    if i >= params.particle_count {
        return;
    }
    let k_i = stiffness(i);
    var a = -k_i * (factor(i).boundary_grad + mirrored_grad(i));
    let fluid = grid[neighbor_count_at(i)];
    for (var k = 0u; k < fluid; k += 2u) {
        let two = pairs(i, k);
        a -= pressure_term(k_i, two.first);
        if k + 1u < fluid {
            a -= pressure_term(k_i, two.second);
        }
    }
    particle_state[velocity_at(i)] = vec4<f32>(particle_state[velocity_at(i)].xyz + a * step_dt(), 0.0);
#ifndef DFSPH_WARM
    set_total(i, total(i) + k_i);
#endif
}
