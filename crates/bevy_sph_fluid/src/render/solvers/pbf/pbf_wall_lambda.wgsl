// The walls' share of PBF's pressure: each boundary sample takes the λ of the water around it,
// λ_b = Σ_i λ_i W_ib / Σ_i W_ib (the Shepard average of Adami et al. 2012's extrapolation onto
// the wall, eq. 27 without its hydrostatic term), for the correction pass, whose samples push
// with V_b (λ_i + λ_b) ∇W_ib -> boundary_lambda[b].x (0 with no particle in reach).
// The particles are those within h of the sample at the sorted predicted positions, the pairs
// of the step's other passes (see pbf.wgsl); W is evaluated at the iteration's positions.
// Rust twin: sph_core::solver::pbf::wall_lambda::extrapolate_wall_lambda.
#import sph::bindings::{params, particle_state, position_at, normal_at, boundary_samples, boundary_position_at, boundary_lambda_at}
#import sph::kernels::cubic
#import sph::neighbors::{home_cell, neighbor_range_count, neighbor_range, accepts}
#import sph::clock::frozen
#import sph::pbf::current_position

@compute @workgroup_size(#{WORKGROUP_SIZE})
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let b = id.x;
    if b >= params.boundary_sample_count || frozen() {
        return;
    }
    let x_b = boundary_samples[boundary_position_at(b)].xyz;
    let c = home_cell(x_b);
    let h2 = params.h_squared;
    var weighted = 0.0;
    var weight = 0.0;
    for (var q = 0u; q < neighbor_range_count(); q++) {
        let range = neighbor_range(c, q);
        for (var j = range.x; j < range.y; j++) {
            let sorted = particle_state[position_at(j)].xyz;
            let paired = sorted - x_b;
            if dot(paired, paired) >= h2 || !accepts(c, q, sorted) {
                continue;
            }
            let w = cubic(length(current_position(j) - x_b));
            weighted += w * particle_state[normal_at(j)].x;
            weight += w;
        }
    }
    var lambda = 0.0;
    if weight > 0.0 {
        lambda = weighted / weight;
    }
    boundary_samples[boundary_lambda_at(b)] = vec4<f32>(lambda, 0.0, 0.0, 0.0);
}
