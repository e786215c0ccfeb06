// PBF's position correction (Macklin & Müller 2013, eqs. 12-14): at the iteration's positions,
// Δp_i = Σ_j (m/ρ0) (λ_i + λ_j + s_corr) ∇W_ij + Σ_b V_b (λ_i + λ_b) ∇W_ib (λ_b the samples'
// λ of the iteration, pbf_wall_lambda.wgsl),
// s_corr = -k (W(r_ij) / W(Δq))^n (the artificial pressure against tensile clumping),
// at most max(0.1 h, 2 |g| dt²) long (sph_core::solver::pbf::macklin2013::PbfContext::for_step);
// x_i + Δp_i, over-relaxed after the first iteration, goes to the next iteration's buffer
// (see pbf.wgsl).
// The boundary's reaction (Akinci 2012's two-way coupling in PBF's position form): sample b
// moves i by V_b (λ_i + λ_b) ∇W_ib, so its body feels -m times that / dt² at the sample, weighted by
// the iteration's share of the step's moves (correction_weight), summed by
// shaders/body_reactions.wgsl over the step's iterations.
// The iteration's λ_i joins the step's sum Λ_i (normal.w, pbf.wgsl's sum_lambda).
// Then the contact with the solids: a particle nearer than the margin to a surface is projected
// back onto it, its body feeling -m δ c / dt² with c the projection's share of the step's moves
// (carried_weight; shaders/speculative_contact.wgsl's contact_projection).
// Rust twins: sph_core::solver::pbf::macklin2013::{compute_corrections, apply_corrections},
// sph_core::solver::pbf::solid_contact::project_out_of_solids.
#import sph::bindings::{params, particle_state, position_at, grid, neighbor_count_at, neighbor_lists_at, normal_at, boundary_samples, boundary_position_at, boundary_body, boundary_body_at}
#import sph::kernels::{cubic, cubic_grad}
#import sph::neighbors::{grid_cell, boundary_range, list_slot}
#import sph::clock::{step_dt, frozen}
#import sph::pbf::{current_position, write_next_position, mass, rest_density, relaxed_position, correction_weight, carried_weight, sum_lambda, wall_lambda}
#import sph::speculative_contact::contact_projection
#import sph::types::drained
#import sph::body_reactions::{begin_reactions, end_reactions, add_reaction, flush_reaction}

@compute @workgroup_size(#{WORKGROUP_SIZE})
fn main(
    @builtin(global_invocation_id) id: vec3<u32>,
    @builtin(local_invocation_index) local: u32,
) {
    begin_reactions(local, #{WORKGROUP_SIZE}u);
    if id.x < params.particle_count && !frozen() {
        particle(id.x);
        flush_reaction();
    }
    end_reactions(local, #{WORKGROUP_SIZE}u);
}

// (W(r) / W(Δq))^n by repeated products (n is small, 1 to 8).
fn s_corr(w: f32) -> f32 {
    let base = w * params.pbf_inverse_w_dq;
    var power = 1.0;
    for (var k = 0u; k < params.pbf_s_corr_n; k++) {
        power *= base;
    }
    return -params.pbf_s_corr_k * power;
}

fn particle(i: u32) {
    let sorted = particle_state[position_at(i)].xyz;
    let x_i = current_position(i);
    let l_i = particle_state[normal_at(i)].x;
    sum_lambda(i, l_i);
    let h2 = params.h_squared;
    let m = mass();
    let scale = m / rest_density();
    var sum = vec3<f32>(0.0);
    for (var k = 0u; k < grid[neighbor_count_at(i)]; k++) {
        let j = grid[neighbor_lists_at(list_slot(i, k))];
        let r = x_i - current_position(j);
        let r2 = dot(r, r);
        let r_len = sqrt(r2);
        let weight = scale * (l_i + particle_state[normal_at(j)].x + s_corr(cubic(r_len)));
        sum += cubic_grad(r, r_len) * weight;
    }
    let dt = step_dt();
    let reaction = -m * correction_weight() / (dt * dt);
    let kept = !drained(particle_state[position_at(i)].w);
    let cell = grid_cell(sorted);
    for (var q = 0u; q < 9u; q++) {
        let range = boundary_range(cell, q);
        for (var b = range.x; b < range.y; b++) {
            let sample = boundary_samples[boundary_position_at(b)];
            let paired = sorted - sample.xyz;
            if dot(paired, paired) >= h2 {
                continue;
            }
            let r = x_i - sample.xyz;
            let r2 = dot(r, r);
            let l_b = wall_lambda(b);
            let moved = cubic_grad(r, sqrt(r2)) * (sample.w * (l_i + l_b));
            sum += moved;
            if l_i + l_b != 0.0 && kept {
                add_reaction(boundary_body[boundary_body_at(b)], moved * reaction, sample.xyz);
            }
        }
    }
    let g = length(params.gravity);
    let cap = max(params.pbf_max_correction, 2.0 * g * dt * dt);
    let length_sum = length(sum);
    if length_sum > cap {
        sum *= cap / length_sum;
    }
    let relaxed = relaxed_position(i, x_i + sum);
    let projection = -m * carried_weight() / (dt * dt);
    write_next_position(i, contact_projection(relaxed, projection, kept));
}
