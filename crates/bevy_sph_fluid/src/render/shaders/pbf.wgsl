// Position-based fluids (Macklin & Müller 2013) on the GPU: where each PBF pass finds its
// arrays. Rust twin: sph_core::pbf_macklin2013 and sph_core::solver::pbf.
//
// The sort leaves the predicted positions x* in `position`, the positions at the step's start
// in `acceleration_start` (the prediction keeps them there; the sort carries them along). The
// sorted positions stay as they are until the step's last pass: they decide the step's pairs
// (the pbf_neighbors pass lists each particle's neighbours within h at x*, as the CPU's
// NeighborLists, and the boundary loops take the samples within h at x*), while the kernels
// are evaluated at the current positions, which the Jacobi iterations ping-pong between two scratch buffers the sort no longer needs:
// iteration 0 reads `position` and writes A (`sorted_position`), odd iterations read A and
// write B (`sorted_velocity_predicted`), even ones read B and write A (roles PBF_FROM_A,
// PBF_FROM_B; render::plan::pbf_source). Each particle's λ_i and ρ_i go to `normal` (x, y);
// the velocities before XSPH to `sorted_velocity`, the vorticity ω to `sorted_acceleration`.
#define_import_path sph::pbf

#import sph::bindings::{params, position, sorted_position, sorted_velocity_predicted}

// The current position of particle j (the iteration's source buffer).
fn current_position(j: u32) -> vec3<f32> {
#ifdef PBF_FROM_A
    return sorted_position[j].xyz;
#else
#ifdef PBF_FROM_B
    return sorted_velocity_predicted[j].xyz;
#else
    return position[j].xyz;
#endif
#endif
}

// Writes particle i's corrected position into the next iteration's source buffer, with its id
// (position.w), so that the finish can copy the final buffer over `position` as it is.
fn write_next_position(i: u32, x: vec3<f32>) {
    let moved = vec4<f32>(x, position[i].w);
#ifdef PBF_FROM_A
    sorted_velocity_predicted[i] = moved;
#else
    sorted_position[i] = moved;
#endif
}

// Writes particle i's position into the buffer the role reads (the finish's final positions).
fn write_current_position(i: u32, x: vec3<f32>) {
    let moved = vec4<f32>(x, position[i].w);
#ifdef PBF_FROM_A
    sorted_position[i] = moved;
#else
#ifdef PBF_FROM_B
    sorted_velocity_predicted[i] = moved;
#else
    position[i] = moved;
#endif
#endif
}

// The particle mass m.
fn mass() -> f32 {
    return params.gravity.w;
}

// ρ0.
fn rest_density() -> f32 {
    return params.material.x;
}
