// a_i = -Σ m (p_i/ρ̂_i² + p_j/ρ̂_j²) ∇W_spiky              (Monaghan 1992, the symmetric form;
//       ρ̂ = max(ρ, ρ0), pressure_density_squared)
//     + (μ/ρ_i) Σ m (v_j - v_i)/ρ_j ∇²W_visc             (design eq. 10, VISCOSITY)
//     - γ Σ K_ij (m C(r) r/|r| + n_i - n_j)               (Akinci 2013, SURFACE_TENSION)
//     - Σ_b ρ0 V_b (p_w/ρ̂_i² + p_b/ρ0²) ∇W_spiky          (Akinci 2012, pressure mirrored:
//       p_w = p_i, or where p_i = 0 the pressure of the water around i,
//       Σ_j (p_j/ρ_j) W_ij / Σ_j W_ij/ρ_j; the sample's p_b = max(p_w + ρ0 g·(x_b - x_i), 0)
//       adds the hydrostatic rise to it, Adami et al. 2012)
//     + (f μ/ρ_i) Σ_b V_b (v_b - v_i) ∇²W_visc            (no-slip bodies, friction f)
//     + g
//     + s Σ_{r<Δx} -V_b (p_c/ρ0) ∇W_spiky                 (the samples' contact,
//       p_c = 2 ρ0 c0² q² (1 + (8 q)⁴), q = 1 - r/Δx, s in [0, 1] the share that stops the
//       approach of v½ (POST_KDK) or v_i within the step (contact_dt) without reversing it;
//       not in SOLVER_DFSPH:
//       sph_core::stage::BoundaryContact)
//     + a_s                                               (the solids' speculative contact:
//       the next drift kept a tenth of a spacing from every collider's and the box's surface;
//       not in SOLVER_DFSPH: shaders/speculative_contact.wgsl)
// The spiky constant of the uniforms carries the rest-lattice gradient correction.
// and the integrator's closing phase on the particle's own velocity (neighbours read only
// positions and predicted velocities, so this is race-free):
// POST_KDK            v = v½ + a dt/2, wall response, pumps, probes (sph_core::integrate::kick)
// POST_LEAPFROG_SAVE  a0 = a                                   (first of two evaluations)
// POST_LEAPFROG_KICK  v += (a0 + a) dt/2, wall response, pumps, probes (design eqs. 20-21)
// HALF_KICK_DRIFT     the next drift starts from v + a dt/2 (the speculative contact's κ = 1/2)
// |a| is recorded for the time-step pass (except by the leapfrog's second evaluation, whose
// acceleration the next step does not start from), |v| by the closing kicks; nothing is
// integrated or recorded while the clock is frozen.
// SOLVER_DFSPH: the non-pressure accelerations a_np only (no pressure terms; DFSPH's solves
// are the pressure), over the lists' pairs, and |v + a_np dt_max| is recorded for its time
// step.
// The reaction -m a_ib of every boundary pair goes to the sample's body (Akinci 2012's two-way
// coupling, summed by shaders/body_reactions.wgsl).
// Rust twin: sph_core::forces (compute_accelerations and its per-body sums).
#import sph::bindings::{params, particle_state, position_at, velocity_at, velocity_predicted_at, acceleration_at, acceleration_start_at, particle_scalars, density_at, pressure_at, normal_at, grid, neighbor_count_at, neighbor_lists_at, boundary_samples, boundary_position_at, boundary_velocity_at, boundary_body, boundary_body_at, shared_state}
#import sph::kernels::{poly6, spiky_grad, viscosity_laplacian, cohesion, collide}
#import sph::neighbors::{home_cell, neighbor_range_count, neighbor_range, accepts, grid_cell, boundary_range, list_slot}
#import sph::clock::{step_dt, frozen, record_speed, record_acceleration}
#import sph::pumps::pumped
#import sph::probes::record_probes
#import sph::types::drained
#import sph::body_reactions::{begin_reactions, end_reactions, add_reaction, flush_reaction}
#import sph::speculative_contact::speculative_contact

// max(ρ, ρ0)², the density the pressure terms divide by: a free-surface particle's SPH density
// is short by the air's share of its kernel (sph_core::forces::pressure_density_squared).
fn pressure_density_squared(rho: f32) -> f32 {
    let r = max(rho, params.rest_density);
    return r * r;
}

fn viscosity_velocity(j: u32) -> vec3<f32> {
#ifdef USE_PREDICTED_VELOCITY
    return particle_state[velocity_predicted_at(j)].xyz;
#else
    return particle_state[velocity_at(j)].xyz;
#endif
}

// p̄_i = Σ_j (p_j/ρ_j) W_ij / Σ_j W_ij/ρ_j, i included (sph_core::forces::pressure_around).
fn pressure_around(x_i: vec3<f32>, c: vec3<i32>) -> f32 {
    let h2 = params.h_squared;
    var weighted = 0.0;
    var weights = 0.0;
    for (var q = 0u; q < neighbor_range_count(); q++) {
        let range = neighbor_range(c, q);
        for (var j = range.x; j < range.y; j++) {
            let x_j = particle_state[position_at(j)].xyz;
            let r = x_i - x_j;
            let r2 = dot(r, r);
            if r2 >= h2 || !accepts(c, q, x_j) {
                continue;
            }
            let w = poly6(r2) / particle_scalars[density_at(j)];
            weighted += w * particle_scalars[pressure_at(j)];
            weights += w;
        }
    }
    if weights > 0.0 {
        return weighted / weights;
    }
    return 0.0;
}

// Sample b's contact acceleration before its stopping share: -V_b (p_c/ρ0) ∇W_spiky(r) with
// p_c = 2 ρ0 c0² q² (1 + (8 q)⁴), q = 1 - r/Δx, zero beyond Δx
// (sph_core::stage::BoundaryContact::push and ::pressure).
fn contact_push(r: vec3<f32>, r_len: f32, volume: f32) -> vec3<f32> {
    let closer = max(1.0 - r_len / params.contact_radius, 0.0);
    let q2 = closer * closer;
    let steep = 64.0 * q2;
    let p_c = params.contact_modulus * q2 * (1.0 + steep * steep);
    if p_c <= 0.0 {
        return vec3<f32>(0.0);
    }
    return spiky_grad(r, r_len) * (-volume * p_c / params.rest_density);
}

// The time step the contact stops approaches within: the step's, chosen by the time-step pass,
// in the closing evaluations (POST_KDK, POST_LEAPFROG_KICK); dt_max in the others, which come
// before it (sph_core::stage::BoundaryContact::time_step).
fn contact_dt() -> f32 {
#ifdef POST_KDK
    return step_dt();
#else
#ifdef POST_LEAPFROG_KICK
    return step_dt();
#else
    return params.max_dt;
#endif
#endif
}

// The share κ of this evaluation's acceleration that the next drift's velocity takes: 1/2 where
// the drift starts from v + a dt/2 (the leapfrog's first evaluation, kick-drift-kick's first
// when its forces were stale: HALF_KICK_DRIFT), else 1 (sph_core::stage::BoundaryContact::
// drift_kick).
fn drift_kick() -> f32 {
#ifdef HALF_KICK_DRIFT
    return 0.5;
#else
    return 1.0;
#endif
}

// The share s in [0, 1] of the summed push that stops the approach within dt without reversing
// it: s |push| dt <= -(v_rel + a_other dt)·push/|push| (BoundaryContact::stopping_scale).
fn contact_stopping_scale(push: vec3<f32>, v_rel: vec3<f32>, a_other: vec3<f32>) -> f32 {
    let magnitude = length(push);
    if !(magnitude > 0.0) {
        return 0.0;
    }
    let dt = contact_dt();
    let approach = -dot(v_rel + a_other * dt, push) / magnitude;
    return clamp(approach / (magnitude * dt), 0.0, 1.0);
}

// Σ_b (push_b·n)₊ over the samples within Δx of x_i (grid cell g); with a nonzero `force`, each
// such sample's body also receives force (push_b·n)₊ (the contact's reaction, shared along n).
fn contact_shares(x_i: vec3<f32>, g: vec3<i32>, n: vec3<f32>, force: vec3<f32>) -> f32 {
    var along = 0.0;
    let reacting = any(force != vec3<f32>(0.0));
    for (var q = 0u; q < 9u; q++) {
        let range = boundary_range(g, q);
        for (var b = range.x; b < range.y; b++) {
            let sample = boundary_samples[boundary_position_at(b)];
            let r = x_i - sample.xyz;
            let r_len = sqrt(dot(r, r));
            if r_len < params.contact_radius {
                let w = max(dot(contact_push(r, r_len, sample.w), n), 0.0);
                along += w;
                if reacting && w > 0.0 {
                    add_reaction(boundary_body[boundary_body_at(b)], force * w, sample.xyz);
                }
            }
        }
    }
    return along;
}

// Whether the boundary samples add anything in this pass: DFSPH's pressure solves answer for
// the boundary, so here only a sample with friction does (params.boundary_friction); otherwise always.
// dambreak32k's walls have none: its samples' loop is skipped.
fn samples_act() -> bool {
#ifdef SOLVER_DFSPH
    return params.boundary_friction > 0.0;
#else
    return true;
#endif
}

@compute @workgroup_size(#{WORKGROUP_SIZE})
fn main(
    @builtin(global_invocation_id) id: vec3<u32>,
    @builtin(local_invocation_index) local: u32,
    @builtin(workgroup_id) group: vec3<u32>,
) {
    begin_reactions(local, #{WORKGROUP_SIZE}u);
    if id.x < params.particle_count {
        particle(id.x);
        flush_reaction();
    }
    end_reactions(local, #{WORKGROUP_SIZE}u);
    if local == 0u && group.x == 0u {
        atomicAdd(&shared_state.body_forces.evaluations, 1u);
    }
}

fn particle(i: u32) {
    let x = particle_state[position_at(i)];
    let x_i = x.xyz;
    let rho_i = particle_scalars[density_at(i)];
    let p_i = particle_scalars[pressure_at(i)] / pressure_density_squared(rho_i);
    let m = params.particle_mass;
    let h2 = params.h_squared;
    let v_i = viscosity_velocity(i);
#ifdef SURFACE_TENSION
    let n_i = particle_state[normal_at(i)].xyz;
    var surface = vec3<f32>(0.0);
#endif
    var pressure_sum = vec3<f32>(0.0);
    var viscosity_sum = vec3<f32>(0.0);
    let c = home_cell(x_i);
#ifdef SOLVER_DFSPH
    // DFSPH's lists hold each particle's pairs within h at these positions (the lists pass after
    // the last move): the cells' pairs without their candidates (a third of the pass's time at
    // dambreak32k on lavapipe).
    let fluid = grid[neighbor_count_at(i)];
    for (var k = 0u; k < fluid; k++) {
        let j = grid[neighbor_lists_at(list_slot(i, k))];
        let x_j = particle_state[position_at(j)].xyz;
        let r = x_i - x_j;
        let r2 = dot(r, r);
        if r2 >= h2 || j == i {
            continue;
        }
#else
    for (var q = 0u; q < neighbor_range_count(); q++) {
        let range = neighbor_range(c, q);
        for (var j = range.x; j < range.y; j++) {
            let x_j = particle_state[position_at(j)].xyz;
            let r = x_i - x_j;
            let r2 = dot(r, r);
            if r2 >= h2 || !accepts(c, q, x_j) {
                continue;
            }
            if j == i {
                continue;
            }
#endif
            let rho_j = particle_scalars[density_at(j)];
            let r_len = sqrt(r2);
#ifndef SOLVER_DFSPH
            pressure_sum -= spiky_grad(r, r_len) * (p_i + particle_scalars[pressure_at(j)] / pressure_density_squared(rho_j));
#endif
#ifdef VISCOSITY
            viscosity_sum += (viscosity_velocity(j) - v_i) * (viscosity_laplacian(r_len) / rho_j);
#endif
#ifdef SURFACE_TENSION
            let correction = 2.0 * params.rest_density / (rho_i + rho_j);
            var pull = vec3<f32>(0.0);
            if r_len > 0.0 {
                pull = r * (m * cohesion(r_len) / r_len);
            }
            surface -= params.surface_tension * correction * (pull + (n_i - particle_state[normal_at(j)].xyz));
#endif
#ifndef SOLVER_DFSPH
        }
#endif
    }
    // The boundary samples (Rust twin: sph_core::forces::boundary_acceleration_at).
    let rho0 = params.rest_density;
    // The wall mirrors p_i, or where the clamp made it zero the Shepard average of the pressure
    // around i (computed only then, at the first sample within h; -1 until then).
    var p_wall = -1.0;
    var own = 0.0;
    let viscous = params.viscosity / rho_i;
    var wall = vec3<f32>(0.0);
    // The contact's pushes, and the samples' velocities weighted by their push.
    var push_sum = vec3<f32>(0.0);
    var push_velocity = vec3<f32>(0.0);
    var push_weight = 0.0;
    let kept = !drained(x.w);
    let g = grid_cell(x_i);
    let sample_cells = select(0u, 9u, samples_act());
    for (var q = 0u; q < sample_cells; q++) {
        let range = boundary_range(g, q);
        for (var b = range.x; b < range.y; b++) {
            let sample = boundary_samples[boundary_position_at(b)];
            let r = x_i - sample.xyz;
            let r2 = dot(r, r);
            if r2 >= h2 {
                continue;
            }
            let r_len = sqrt(r2);
#ifndef SOLVER_DFSPH
            // The velocity is read only within the contact's range.
            if r_len < params.contact_radius {
                let push = contact_push(r, r_len, sample.w);
                let weight = length(push);
                push_sum += push;
                push_velocity += boundary_samples[boundary_velocity_at(b)].xyz * weight;
                push_weight += weight;
            }
#endif
#ifdef SOLVER_DFSPH
            // DFSPH's pressure solves answer for the boundary (dfsph_apply).
            var a_b = vec3<f32>(0.0);
#else
            if p_wall < 0.0 {
                p_wall = particle_scalars[pressure_at(i)];
                if p_wall <= 0.0 {
                    p_wall = pressure_around(x_i, c);
                }
                own = p_wall / pressure_density_squared(rho_i);
            }
            // r = x_i - x_b, so g·(x_b - x_i) = -g·r.
            let p_b = max(p_wall - rho0 * dot(params.gravity, r), 0.0);
            let mirrored = own + p_b / (rho0 * rho0);
            var a_b = spiky_grad(r, r_len) * (-rho0 * sample.w * mirrored);
#endif
            let u = boundary_samples[boundary_velocity_at(b)];
#ifdef SOLVER_DFSPH
            // Without friction the sample adds nothing here, nor a reaction.
            if u.w <= 0.0 {
                continue;
            }
#endif
            if u.w > 0.0 {
                a_b += (u.xyz - v_i) * (u.w * viscous * sample.w * viscosity_laplacian(r_len));
            }
            wall += a_b;
            if kept {
                add_reaction(boundary_body[boundary_body_at(b)], a_b * -m, sample.xyz);
            }
        }
    }
    var a = pressure_sum * m + viscosity_sum * (params.viscosity * m / rho_i) + wall + params.gravity;
#ifdef SURFACE_TENSION
    a += surface;
#endif
    // The velocity the next drift starts from before a: kick-drift-kick's v½ (the closing kick
    // and the next step's first half-kick add a dt), else v_i
    // (sph_core::forces::ForceInputs::contact_velocity).
#ifdef POST_KDK
    let v_contact = particle_state[velocity_at(i)].xyz;
#else
    let v_contact = v_i;
#endif
    if push_weight > 0.0 {
        let scale = contact_stopping_scale(push_sum, v_contact - push_velocity / push_weight, a);
        if scale > 0.0 {
            // The reaction -m s Σ push goes to the samples that push along n = Σ push/|Σ push|,
            // in proportion to (push_b·n)₊ (a sample pushing against n does not lean on i).
            let n = normalize(push_sum);
            let along = contact_shares(x_i, g, n, vec3<f32>(0.0));
            if along > 0.0 && kept {
                contact_shares(x_i, g, n, push_sum * (-m * scale / along));
            }
            a += push_sum * scale;
        }
    }
#ifndef SOLVER_DFSPH
    // The solids' speculative contact (sph_core::boundary::speculative_contact), after every other term.
    a += speculative_contact(x_i, v_contact, a, contact_dt(), drift_kick(), kept);
#endif
    particle_state[acceleration_at(i)] = vec4<f32>(a, 0.0);
    let dt = step_dt();
    if frozen() {
        return;
    }
#ifndef POST_LEAPFROG_KICK
    record_acceleration(i, a);
#endif
#ifdef SOLVER_DFSPH
    // DFSPH's CFL rule reads max |v + a_np dt_max| (sph_core::solver::dfsph::next_time_step).
    record_speed(i, particle_state[velocity_at(i)].xyz + a * params.max_dt);
#endif
#ifdef POST_KDK
    let v = pumped(x_i, collide(x_i, particle_state[velocity_at(i)].xyz + a * (0.5 * dt)).v, dt);
    particle_state[velocity_at(i)] = vec4<f32>(v, 0.0);
    record_speed(i, v);
    record_probes(i, x_i, v);
#endif
#ifdef POST_LEAPFROG_SAVE
    particle_state[acceleration_start_at(i)] = vec4<f32>(a, 0.0);
#endif
#ifdef POST_LEAPFROG_KICK
    let a0 = particle_state[acceleration_start_at(i)].xyz;
    let v = pumped(x_i, collide(x_i, particle_state[velocity_at(i)].xyz + (a0 + a) * (0.5 * dt)).v, dt);
    particle_state[velocity_at(i)] = vec4<f32>(v, 0.0);
    record_speed(i, v);
    record_probes(i, x_i, v);
#endif
}
