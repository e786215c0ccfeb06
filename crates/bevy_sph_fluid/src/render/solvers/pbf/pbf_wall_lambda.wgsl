// The walls' share of PBF's pressure: each boundary sample takes the λ of the water around it,
// λ_b = Σ_i λ_i W_ib / Σ_i W_ib (the Shepard average of Adami et al. 2012's extrapolation onto
// the wall, eq. 27 without its hydrostatic term), for the correction pass, whose samples push
// with V_b (λ_i + λ_b) ∇W_ib -> word 0 of the sample's wall list (0 with no particle in reach).
// The particles are the step's, listed by pbf_wall_lists; W is evaluated at the iteration's
// positions. Rust twin: sph_core::solver::pbf::wall_lambda::extrapolate_wall_lambda.
#import sph::bindings::{params, particle_state, normal_at, boundary_samples, boundary_position_at, boundary_body}
#import sph::kernels::cubic
#import sph::clock::frozen
#import sph::pbf::{current_position, wall_word}

@compute @workgroup_size(#{WORKGROUP_SIZE})
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let b = id.x;
    if b >= params.boundary_sample_count || frozen() {
        return;
    }
    let x_b = boundary_samples[boundary_position_at(b)].xyz;
    var weighted = 0.0;
    var weight = 0.0;
    for (var k = 0u; k < boundary_body[wall_word(b, 1u)]; k++) {
        let j = boundary_body[wall_word(b, 2u + k)];
        let w = cubic(length(current_position(j) - x_b));
        weighted += w * particle_state[normal_at(j)].x;
        weight += w;
    }
    var lambda = 0.0;
    if weight > 0.0 {
        lambda = weighted / weight;
    }
    boundary_body[wall_word(b, 0u)] = bitcast<u32>(lambda);
}
