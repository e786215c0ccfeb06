// The end of a DFSPH solve: the bodies' reactions, the solve's statistics, and after the
// divergence-free solve the step's close.
// - Reactions (Akinci 2012's two-way coupling): each boundary pair's -m a_ib = m κ_i g_ib with
//   the stiffness the solve summed, twice that at a sample that mirrors κ_i, at the sample
//   (summed by shaders/body_reactions.wgsl); the constant-density solve's pass adds the step's
//   hydrostatic rise at the mirroring samples, m (p_b'^rise/ρ0²) g_ib', at the positions the
//   predict pass used (dfsph.wgsl).
// - Thread 0 adds the solve's applied iterations to the clock's sums and keeps its last mean
//   error (the sum its last source wrote: a after an even count, b after an odd one).
//   A solve still open whose decision would go on ran out of the passes the CPU encoded (its
//   iteration budget, src/dfsph_budget.rs): it is counted as cut short.
// - After the constant-density solve (before the move): the solids' speculative contact bounds
//   v so that the drift x += v dt ends a tenth of a spacing from every surface, its reaction to
//   the body (shaders/speculative_contact.wgsl; sph_core::boundary::speculative_contact::stop_before_drift).
// - DIVERGENCE_SOLVE: p_i = (κ_i + κ_i^v) ρ_i², the pumps, the probes.
// Nothing is summed while the clock is frozen or a state is being restored.
// Rust twins: sph_core::solver::dfsph::bender2017::boundary_reactions and BoundaryRise::reactions, the end of
// sph_core::solver::dfsph::DfsphStep::advance, sph_core::flow::pump::apply_pumps (CpuSolver::step).
#import sph::bindings::{params, shared_state, particle_state, position_at, velocity_at, velocity_predicted_at, particle_scalars, density_at, pressure_at, boundary_samples, boundary_position_at, boundary_body, boundary_body_at}
#import sph::kernels::cubic_grad
#import sph::neighbors::{grid_cell, boundary_range}
#import sph::clock::{step_dt, frozen}
#import sph::checkpoint::restoring
#import sph::pumps::pumped
#import sph::probes::record_probes
#import sph::types::drained
#import sph::body_reactions::{begin_reactions, end_reactions, add_reaction, flush_reaction, reactions_read}
#import sph::dfsph::{boundary_neighbors, mass, rest_density, total, mean_error, solve_goes_on, mirrors, samples_mirror, rise_floor, rise_over_rho0_squared}
#import sph::speculative_contact::speculative_contact

fn particle(i: u32) {
    let x = particle_state[position_at(i)];
    let x_i = x.xyz;
    let k = total(i) * mass();
    let mirrored = select(k, 2.0 * k, mirrors(i));
#ifdef DIVERGENCE_SOLVE
    let rises = false;
#else
    let rises = true;
#endif
    let p_floor = rise_floor(i);
    let kept = !drained(x.w);
    // The factors pass counted the samples within h at these positions: none, no reaction;
    // a drained particle gives none either, nor any while no sum is read.
    if (k != 0.0 || rises) && kept && boundary_neighbors(i) > 0.0 && reactions_read() {
        let h2 = params.h_squared;
        let rho0 = rest_density();
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
                let g = cubic_grad(r, sqrt(r2)) * (rho0 * sample.w);
                var f = k;
                if mirror_samples {
                    f = mirrored;
                    if rises {
                        f += mass() * rise_over_rho0_squared(x_i, sample.xyz, p_floor);
                    }
                }
                add_reaction(boundary_body[boundary_body_at(b)], g * f, sample.xyz);
            }
        }
    }
#ifndef DIVERGENCE_SOLVE
    let dt = step_dt();
    let u = particle_state[velocity_at(i)];
    let a_s = speculative_contact(x_i, u.xyz, vec3<f32>(0.0), dt, 1.0, kept);
    particle_state[velocity_at(i)] = vec4<f32>(u.xyz + a_s * dt, u.w);
#endif
#ifdef DIVERGENCE_SOLVE
    let rho = particle_scalars[density_at(i)];
    let sums = particle_state[velocity_predicted_at(i)];
    particle_scalars[pressure_at(i)] = (sums.x + sums.y) * rho * rho;
    let v = pumped(x_i, particle_state[velocity_at(i)].xyz, step_dt());
    particle_state[velocity_at(i)] = vec4<f32>(v, 0.0);
    record_probes(i, x_i, v);
#endif
}

@compute @workgroup_size(#{WORKGROUP_SIZE})
fn main(
    @builtin(global_invocation_id) id: vec3<u32>,
    @builtin(local_invocation_index) local: u32,
) {
    let i = id.x;
    let live = !frozen() && !restoring();
    begin_reactions(local, #{WORKGROUP_SIZE}u);
    if i < params.particle_count && live {
        particle(i);
        flush_reaction();
    }
    end_reactions(local, #{WORKGROUP_SIZE}u);
    if i == 0u && live {
        let applied = shared_state.clock.dfsph_applied;
        let error = mean_error(applied % 2u);
        let open = shared_state.clock.dfsph_done == 0u;
#ifdef DIVERGENCE_SOLVE
        shared_state.clock.divergence_iterations += applied;
        shared_state.clock.divergence_frame_max = max(shared_state.clock.divergence_frame_max, applied);
        shared_state.clock.divergence_error = error;
        if open && solve_goes_on(applied, error) {
            shared_state.clock.divergence_cut_short += 1u;
        }
#else
        shared_state.clock.density_iterations += applied;
        shared_state.clock.density_iterations_max = max(shared_state.clock.density_iterations_max, applied);
        shared_state.clock.density_frame_max = max(shared_state.clock.density_frame_max, applied);
        shared_state.clock.density_error = error;
        if open && solve_goes_on(applied, error) {
            shared_state.clock.density_cut_short += 1u;
        }
#endif
    }
}
