// Pass 1 of the neighbour sort, fused with the integrator's pre-evaluation phase:
// PRE_KDK   v½ = v + a dt/2; x += v½ dt; collide; v* = v½ + a dt/2   (sph_core::integrate::kick_drift)
// PRE_LEAPFROG  x += v dt + a0 dt²/2; v* = v + a0 dt; collide(x, v*)  (design eqs. 18-19)
// PRE_PBF       x_prev = x; v += g dt; the solids' speculative contact bounds v so that the
//               prediction ends a tenth of a spacing from every surface, its reaction to the
//               body (shaders/speculative_contact.wgsl); x* = x + v dt; collide
//               (Macklin & Müller 2013, Algorithm 1, lines 2-3; x_prev is kept in
//               acceleration_start, which the sort carries along)
// PRE_DFSPH     x += v dt; collide, unless a state is being restored (Bender & Koschier 2017,
//               Algorithm 1, line 8: the move after the constant-density solve)
// (skipped while the clock is frozen), after the rollback checkpoint is saved or restored
// (APPLY_CHECKPOINT: the roles that run right after the time-step pass), then the grid count (cell, rank by atomicAdd, per-cell count) or the hash key of every slot.
#import sph::bindings::{params, particle_state, position_at, velocity_at, velocity_predicted_at, acceleration_at, acceleration_start_at, grid, cell_of_at, rank_in_cell_at, cell_counts, cell_counts_at, sort_keys_at, sort_values_at, shared_state}
#import sph::pumps::in_open_sink
#import sph::types::{drained, DRAINED_BIT}
#import sph::guard::guard
#import sph::clock::{step_dt, frozen}
#import sph::checkpoint::{apply_checkpoint, restoring}
#import sph::neighbors::{grid_cell, grid_index, hash_cell, hash_key}
#ifdef PRE_PBF
#import sph::speculative_contact::speculative_contact
#import sph::body_reactions::{begin_reactions, end_reactions, flush_reaction}
#endif

// Hash mode: the key of a drained particle, after every bucket and before the padding.
const MARKED_KEY: u32 = 0xfffffffeu;

@compute @workgroup_size(#{WORKGROUP_SIZE})
fn main(
    @builtin(global_invocation_id) id: vec3<u32>,
    @builtin(local_invocation_index) local: u32,
) {
#ifdef PRE_PBF
    // The contact's reactions are summed by the workgroup (uniform control flow around `slot`).
    begin_reactions(local, #{WORKGROUP_SIZE}u);
    slot(id.x);
    flush_reaction();
    end_reactions(local, #{WORKGROUP_SIZE}u);
#else
    slot(id.x);
#endif
}

// The integrator's phase and the sort key of slot i.
fn slot(i: u32) {
#ifdef SEARCH_HASH
    if i >= params.sort_length {
        return;
    }
    if i >= params.particle_count {
        // Padding sorts after every real key.
        grid[sort_keys_at(i)] = 0xffffffffu;
        grid[sort_values_at(i)] = i;
        return;
    }
#else
    if i >= params.particle_count {
        return;
    }
#endif
#ifdef APPLY_CHECKPOINT
    apply_checkpoint(i);
#endif
    var x = particle_state[position_at(i)].xyz;
    let dt = step_dt();
    // A particle a drain took stays where it is, still, until the main world drops it.
    let was_drained = drained(particle_state[position_at(i)].w);
    if was_drained {
        particle_state[velocity_at(i)] = vec4<f32>(0.0);
#ifdef PRE_PBF
        // Its velocity from positions (v = (x - x_prev)/dt) starts from here.
        particle_state[acceleration_start_at(i)] = vec4<f32>(x, 0.0);
#endif
    }
    let integrating = !frozen() && !was_drained;
#ifdef PRE_KDK
    if integrating {
    let a = particle_state[acceleration_at(i)].xyz;
    let kicked = particle_state[velocity_at(i)].xyz + a * (0.5 * dt);
    let drifted = x + kicked * dt;
    let moved = guard(drifted, kicked);
    x = moved.x;
    particle_state[velocity_at(i)] = vec4<f32>(moved.v, 0.0);
    particle_state[velocity_predicted_at(i)] = vec4<f32>(moved.v + a * (0.5 * dt), 0.0);
    particle_state[position_at(i)] = vec4<f32>(x, particle_state[position_at(i)].w);
    }
#endif
#ifdef PRE_LEAPFROG
    if integrating {
    let a0 = particle_state[acceleration_start_at(i)].xyz;
    let v = particle_state[velocity_at(i)].xyz;
    let drifted = x + v * dt + a0 * (0.5 * dt * dt);
    let moved = guard(drifted, v + a0 * dt);
    x = moved.x;
    particle_state[velocity_predicted_at(i)] = vec4<f32>(moved.v, 0.0);
    particle_state[position_at(i)] = vec4<f32>(x, particle_state[position_at(i)].w);
    }
#endif
#ifdef PRE_PBF
    if integrating {
    particle_state[acceleration_start_at(i)] = vec4<f32>(x, 0.0);
    let v_g = particle_state[velocity_at(i)].xyz + params.gravity * dt;
    let v = v_g + speculative_contact(x, v_g, vec3<f32>(0.0), dt, 1.0, true) * dt;
    let moved = guard(x + v * dt, v);
    x = moved.x;
    particle_state[velocity_at(i)] = vec4<f32>(moved.v, 0.0);
    particle_state[position_at(i)] = vec4<f32>(x, particle_state[position_at(i)].w);
    }
#endif
#ifdef PRE_DFSPH
    if integrating && !restoring() {
    let v = particle_state[velocity_at(i)].xyz;
    let moved = guard(x + v * dt, v);
    x = moved.x;
    particle_state[velocity_at(i)] = vec4<f32>(moved.v, 0.0);
    particle_state[position_at(i)] = vec4<f32>(x, particle_state[position_at(i)].w);
    }
#endif
    // Drains: a particle inside an open drain is marked (its id's high bit) and sorted to the
    // tail of the live range, after every cell, where no neighbour loop visits it; the sort's
    // pass 2 records how many (docs/scenes.md).
    if !was_drained && params.open_drains > 0u && in_open_sink(x) {
        particle_state[position_at(i)] = vec4<f32>(particle_state[position_at(i)].xyz, bitcast<f32>(bitcast<u32>(particle_state[position_at(i)].w) | DRAINED_BIT));
    }
    if drained(particle_state[position_at(i)].w) {
        let rank = atomicAdd(&shared_state.clock.marked, 1u);
#ifdef SEARCH_HASH
        grid[sort_keys_at(i)] = MARKED_KEY;
        grid[sort_values_at(i)] = i;
#else
        grid[cell_of_at(i)] = params.cell_count;
        grid[rank_in_cell_at(i)] = rank;
#endif
        return;
    }
#ifdef SEARCH_HASH
    grid[sort_keys_at(i)] = hash_key(hash_cell(x));
    grid[sort_values_at(i)] = i;
#else
    let cell = grid_index(grid_cell(x));
    grid[cell_of_at(i)] = cell;
    grid[rank_in_cell_at(i)] = atomicAdd(&cell_counts[cell_counts_at(cell)], 1u);
#endif
}
