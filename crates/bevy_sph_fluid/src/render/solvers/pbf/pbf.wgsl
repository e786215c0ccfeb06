// Position-based fluids (Macklin & Müller 2013) on the GPU: where each PBF pass finds its
// arrays. Rust twin: sph_core::solver::pbf::macklin2013 and sph_core::solver::pbf.
//
// The sort leaves the predicted positions x* in `position`, the positions at the step's start
// in `acceleration_start` (the prediction keeps them there; the sort carries them along). The
// sorted positions stay as they are until the step's last pass: they decide the step's pairs
// (the neighbor_lists pass lists each particle's neighbours within h at x*, as the CPU's
// NeighborLists, and the boundary loops take the samples within h at x*), while the kernels
// are evaluated at the current positions, which the Jacobi iterations ping-pong between two scratch buffers the sort no longer needs:
// iteration 0 reads `position` and writes A (`sorted_position`), odd iterations read A and
// write B (`sorted_velocity_predicted`), even ones read B and write A (roles PBF_FROM_A,
// PBF_FROM_B; render::solvers::pbf::phase::pbf_source). Iterations after the first are over-relaxed
// (x_{k+1} = x_{k-1} + ω (x_k + Δp_k - x_{k-1})): x_{k-1} is still in the buffer iteration k
// writes, and iteration 0 leaves x_0 in B for iteration 1. The iteration's number is in
// clock.pbf_iteration (set by the λ pass). Each particle's λ_i and ρ_i go to `normal` (x, y),
// the step's weighted λ sum to its w (sum_lambda); the velocities before XSPH to
// `sorted_velocity`, the vorticity ω to `sorted_acceleration`.
#define_import_path sph::pbf

#import sph::bindings::{params, particle_state, position_at, particle_scratch, sorted_position_at, sorted_velocity_predicted_at, normal_at, shared_state, boundary_body, boundary_lambda_at}

// The current position of particle j (the iteration's source buffer).
fn current_position(j: u32) -> vec3<f32> {
#ifdef PBF_FROM_A
    return particle_scratch[sorted_position_at(j)].xyz;
#else
#ifdef PBF_FROM_B
    return particle_scratch[sorted_velocity_predicted_at(j)].xyz;
#else
    return particle_state[position_at(j)].xyz;
#endif
#endif
}

// Writes particle i's corrected position into the next iteration's source buffer, with its id
// (position.w), so that the finish can copy the final buffer over `position` as it is.
fn write_next_position(i: u32, x: vec3<f32>) {
    let moved = vec4<f32>(x, particle_state[position_at(i)].w);
#ifdef PBF_FROM_A
    particle_scratch[sorted_velocity_predicted_at(i)] = moved;
#else
    particle_scratch[sorted_position_at(i)] = moved;
#endif
}

// The over-relaxation ω of the iterations after the first.
fn over_relaxation() -> f32 {
    return bitcast<f32>(params.pbf_over_relaxation_bits);
}

// Particle i's next position from its corrected one, x_k + Δp_k: over-relaxed against x_{k-1}
// after the first iteration; the first keeps x_0 in B, where iteration 1 finds it.
// Rust twin: sph_core::solver::pbf::macklin2013::over_relax (as moves u_k = x_{k+1} - x_k).
fn relaxed_position(i: u32, corrected: vec3<f32>) -> vec3<f32> {
#ifdef PBF_FROM_A
    let before = particle_scratch[sorted_velocity_predicted_at(i)].xyz;
    return before + over_relaxation() * (corrected - before);
#else
#ifdef PBF_FROM_B
    let before = particle_scratch[sorted_position_at(i)].xyz;
    return before + over_relaxation() * (corrected - before);
#else
    particle_scratch[sorted_velocity_predicted_at(i)] = particle_state[position_at(i)];
    return corrected;
#endif
#endif
}

// The share of the iteration under way's correction in the step's moves (the bodies'
// reactions are weighted by it). Rust twin: sph_core::solver::pbf::macklin2013::correction_weight.
fn correction_weight() -> f32 {
    let k = shared_state.clock.pbf_iteration;
    if k == 0u {
        return carried_weight();
    }
    return over_relaxation() * carried_weight();
}

// The share of a move made at the end of the iteration under way (the contact's projection) in
// the step's moves: each later iteration carries (ω - 1) of the one before, Σ_{m < K - k} (ω - 1)^m.
// Rust twin: sph_core::solver::pbf::macklin2013::carried_weight.
fn carried_weight() -> f32 {
    let omega = over_relaxation();
    var sum = 0.0;
    var power = 1.0;
    for (var m = shared_state.clock.pbf_iteration; m < params.pbf_iterations; m++) {
        sum += power;
        power *= omega - 1.0;
    }
    return sum;
}

// Adds particle i's λ of the iteration under way, weighted by its share of the step's moves,
// to Λ_i = Σ_k c_k λ_k in normal[i].w (the first iteration starts it): the pressure the step's
// λ stand for is -(ρ_i² / ρ0) Λ_i / dt² (pbf_xsph). Only the w of i's own slot is written, while the pass
// reads the neighbours' λ in x. Rust twin: the λ sums of sph_core::solver::pbf's step and
// sph_core::solver::pbf::macklin2013::equivalent_pressure.
fn sum_lambda(i: u32, l_i: f32) {
#ifdef PBF_FROM_A
    let before = particle_state[normal_at(i)].w;
#else
#ifdef PBF_FROM_B
    let before = particle_state[normal_at(i)].w;
#else
    let before = 0.0;
#endif
#endif
    particle_state[normal_at(i)].w = before + correction_weight() * l_i;
}

// Counts the iterations in clock.pbf_iteration: the λ pass's first thread (`i` = 0) sets it.
fn count_iteration(i: u32) {
    if i != 0u {
        return;
    }
#ifdef PBF_FROM_A
    shared_state.clock.pbf_iteration += 1u;
#else
#ifdef PBF_FROM_B
    shared_state.clock.pbf_iteration += 1u;
#else
    shared_state.clock.pbf_iteration = 0u;
#endif
#endif
}

// Writes particle i's position into the buffer the role reads (the finish's final positions).
fn write_current_position(i: u32, x: vec3<f32>) {
    let moved = vec4<f32>(x, particle_state[position_at(i)].w);
#ifdef PBF_FROM_A
    particle_scratch[sorted_position_at(i)] = moved;
#else
#ifdef PBF_FROM_B
    particle_scratch[sorted_velocity_predicted_at(i)] = moved;
#else
    particle_state[position_at(i)] = moved;
#endif
#endif
}

// The most particles a boundary sample's wall list keeps
// (sph_core::gpu_layout::PBF_MAX_WALL_NEIGHBORS).
const PBF_MAX_WALL_NEIGHBORS: u32 = 62u;

// Where word w of boundary sample b's wall list lies: 0 holds the bits of its λ_b
// (pbf_wall_lambda), 1 the count of particles within h of it at x* (pbf_wall_lists), 2 + k the
// k-th of them.
fn wall_word(b: u32, w: u32) -> u32 {
    return boundary_lambda_at(b * (PBF_MAX_WALL_NEIGHBORS + 2u) + w);
}

// Boundary sample b's λ_b of the iteration.
fn wall_lambda(b: u32) -> f32 {
    return bitcast<f32>(boundary_body[wall_word(b, 0u)]);
}

// The particle mass m.
fn mass() -> f32 {
    return params.particle_mass;
}

// ρ0.
fn rest_density() -> f32 {
    return params.rest_density;
}

// The pressure a step's weighted λ sum stands for at the density ρ, -(ρ² / ρ0) Λ / dt², never
// negative. Rust twin: sph_core::solver::pbf::macklin2013::equivalent_pressure.
fn equivalent_pressure(lambda_sum: f32, density: f32, dt: f32) -> f32 {
    let p = -density * density * lambda_sum / (rest_density() * dt * dt);
    if p > 0.0 && p < 3.0e38 {
        return p;
    }
    return 0.0;
}

