// PBF's constraint (Macklin & Müller 2013, eqs. 1-11): at the iteration's positions,
// ρ_i = m Σ_j W_ij (self included) + ρ0 Σ_b V_b W_ib (Akinci 2012's boundary samples),
// C_i = max(ρ_i/ρ0 - 1, 0) (only compression is a violation),
// ∇_i C_i = Σ_j (m/ρ0) ∇W_ij + Σ_b V_b ∇W_ib, ∇_j C_i = -(m/ρ0) ∇W_ij,
// λ_i = -w C_i / (Σ_k |∇_k C_i|² + ε) (w the weight of weighted Jacobi)  ->  normal[i] = (λ_i, ρ_i, C_i, Λ_i), the step's weighted
// sum Λ_i of the λ kept (pbf.wgsl, sum_lambda).
// W is the cubic spline. The pairs are those within h at the sorted predicted positions (see
// pbf.wgsl); nothing moves while the clock is frozen.
// Rust twin: sph_core::solver::pbf::macklin2013::compute_lambdas.
#import sph::bindings::{params, particle_state, position_at, grid, neighbor_count_at, neighbor_lists_at, normal_at, boundary_samples, boundary_position_at}
#import sph::kernels::{cubic, cubic_grad}
#import sph::neighbors::{grid_cell, boundary_range, list_slot}
#import sph::clock::frozen
#import sph::pbf::{current_position, mass, rest_density, count_iteration}

@compute @workgroup_size(#{WORKGROUP_SIZE})
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    count_iteration(i);
    if i >= params.particle_count || frozen() {
        return;
    }
    let sorted = particle_state[position_at(i)].xyz;
    let x_i = current_position(i);
    let h2 = params.h_squared;
    let m = mass();
    let rho0 = rest_density();
    let scale = m / rho0;
    var rho = m * cubic(0.0);
    var grad_i = vec3<f32>(0.0);
    var squares = 0.0;
    for (var k = 0u; k < grid[neighbor_count_at(i)]; k++) {
        let j = grid[neighbor_lists_at(list_slot(i, k))];
        let r = x_i - current_position(j);
        let r2 = dot(r, r);
        let r_len = sqrt(r2);
        rho += m * cubic(r_len);
        let g = cubic_grad(r, r_len) * scale;
        grad_i += g;
        squares += dot(g, g);
    }
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
            let r_len = sqrt(r2);
            rho += rho0 * sample.w * cubic(r_len);
            grad_i += cubic_grad(r, r_len) * sample.w;
        }
    }
    let constraint = max(rho / rho0 - 1.0, 0.0);
    // Weighted Jacobi (sph_core::PbfSettings::jacobi_weight).
    let lambda = -params.pbf_jacobi_weight * constraint / (dot(grad_i, grad_i) + squares + params.pbf_relaxation);
    particle_state[normal_at(i)] = vec4<f32>(lambda, rho, constraint, particle_state[normal_at(i)].w);
}
