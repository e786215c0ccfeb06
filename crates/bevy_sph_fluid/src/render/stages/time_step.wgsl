// Right before each step's first integration phase, one thread (CPU twin: sph_core::stability,
// sph_core::rollback and CpuSolver::step); the extremes are the last step's final |v| and the
// |a| about to be used:
// 1. the previous step is unstable when a recorded |v| or |a| is not finite or v_max dt > h;
// 2. an unstable step is rolled back: the next pass restores the checkpoint, step and time go
//    back to it, and dt is halved (TIME_STEP_BEFORE_INTEGRATE, symplectic Euler: this step's
//    integrate pass restores instead of integrating and the next step retries); without
//    rollback, without a checkpoint or out of retries, the clock freezes integration until reset
//    (after restoring the last good state when rollback is on);
// 3. a stable step counts towards recovering a halved dt, and the next pass saves a checkpoint
//    when one is due (none yet, particles were added, or `interval` steps since the last);
// 4. dt = time_step, or with the adaptive rule
//    min(time_step, λ h / (c0 + v_max), 0.125 h² ρ0/μ, 0.25 sqrt(h / a_max)), times 2^-halvings
//    (SOLVER_PBF: min(time_step, λ h / v_max), and only a non-finite state is unstable;
//    SOLVER_DFSPH: min(time_step, λ Δx / v_max, 0.125 h² ρ0/μ));
// 5. real-time mode (sph_core::frame_budget::budget_dt): a new frame number starts a budget of
//    the frame's time in its planned steps; dt = min(dt, remaining / steps left), so the frame
//    never oversteps its time and ends on it when the plan's step count was right;
// 6. step += 1, time += dt (in whole nanoseconds, exact), the extremes are cleared.
#import sph::bindings::{params, shared_state}

const NON_FINITE: u32 = 0x7f800000u;
const SAVE: u32 = 1u;
const RESTORE: u32 = 2u;
const MAX_HALVINGS: u32 = 16u;

fn add_ns(lo: u32, hi: u32, dt: f32) -> vec2<u32> {
    let ticks = u32(round(dt * 1.0e9));
    let low = lo + ticks;
    return vec2<u32>(low, hi + select(0u, 1u, low < ticks));
}

// Step and time go back to the checkpoint; the next pass restores its particles.
fn restore() {
    shared_state.clock.checkpoint_action = RESTORE;
    shared_state.clock.restore_count = shared_state.clock.checkpoint_count;
    shared_state.clock.checkpoint_count = params.particle_count;
    shared_state.clock.step = shared_state.clock.checkpoint_step;
    shared_state.clock.time_ns_lo = shared_state.clock.checkpoint_time_lo;
    shared_state.clock.time_ns_hi = shared_state.clock.checkpoint_time_hi;
}

fn scale() -> f32 {
    return exp2(-f32(shared_state.clock.halvings));
}

@compute @workgroup_size(#{WORKGROUP_SIZE})
fn main() {
    // Counted before anything can return: the CPU compares it with the steps it dispatched to
    // know that a readback is current, which `step` cannot tell once a rollback took it back.
    shared_state.clock.steps_run += 1u;
    shared_state.clock.checkpoint_action = 0u;
    if shared_state.clock.unstable_step != 0u {
        return;
    }
    let speed_bits = atomicLoad(&shared_state.clock.max_speed_bits);
    let acceleration_bits = atomicLoad(&shared_state.clock.max_acceleration_bits);
    atomicStore(&shared_state.clock.max_speed_bits, 0u);
    atomicStore(&shared_state.clock.max_acceleration_bits, 0u);
    let v_max = bitcast<f32>(speed_bits);
    let a_max = bitcast<f32>(acceleration_bits);
    let h = params.cell_size;
    let checked = shared_state.clock.step > 0u;
#ifdef SOLVER_PBF
    // PBF moves particles by positions: only a non-finite state is unstable
    // (sph_core::stability, Solver::Pbf).
    let unstable = checked && (speed_bits >= NON_FINITE || acceleration_bits >= NON_FINITE);
#else
    let unstable = checked && (speed_bits >= NON_FINITE || acceleration_bits >= NON_FINITE || v_max * shared_state.clock.dt > h);
#endif
    var rule_dt: f32;
    if unstable {
        let can_retry = params.rollback_enabled != 0u && shared_state.clock.has_checkpoint != 0u;
        if !can_retry || shared_state.clock.retries >= params.max_retries {
            shared_state.clock.unstable_step = shared_state.clock.step;
            if can_retry {
                restore();
            }
            return;
        }
        shared_state.clock.rollbacks += 1u;
        shared_state.clock.retries += 1u;
        shared_state.clock.halvings = min(shared_state.clock.halvings + 1u, MAX_HALVINGS);
        shared_state.clock.stable_steps = 0u;
        restore();
#ifdef TIME_STEP_BEFORE_INTEGRATE
        return;
#else
        rule_dt = shared_state.clock.checkpoint_rule_dt;
#endif
    } else {
        if checked {
            shared_state.clock.stable_steps += 1u;
            if shared_state.clock.halvings > 0u && shared_state.clock.stable_steps >= params.recovery_steps {
                shared_state.clock.halvings -= 1u;
                shared_state.clock.stable_steps = 0u;
            }
        }
        rule_dt = params.max_dt;
#ifdef SOLVER_PBF
        // PBF's rule (sph_core::solver::pbf::next_time_step): min(time_step, λ h / v_max) with
        // v_max = max |v + g dt_max|, as the finish pass records it.
        if params.adaptive_time_step != 0u && v_max > 0.0 {
            rule_dt = min(rule_dt, params.cfl_factor * h / v_max);
        }
#else
#ifdef SOLVER_DFSPH
        // DFSPH's rule (sph_core::solver::dfsph::bender2017::dfsph_time_step): min(time_step, λ Δx / v_max,
        // 0.125 h² ρ0/μ) with v_max = max |v + a_np dt_max|, as the forces pass records it.
        if params.adaptive_time_step != 0u {
            if v_max > 0.0 {
                rule_dt = min(rule_dt, params.cfl_factor * params.spacing / v_max);
            }
            rule_dt = min(rule_dt, params.viscous_limit);
        }
#else
        if params.adaptive_time_step != 0u {
            rule_dt = min(rule_dt, params.cfl_factor * h / (params.speed_of_sound + v_max));
            rule_dt = min(rule_dt, params.viscous_limit);
            if a_max > 0.0 {
                rule_dt = min(rule_dt, 0.25 * sqrt(h / a_max));
            }
        }
#endif
#endif
        let due = shared_state.clock.has_checkpoint == 0u || shared_state.clock.save_requested != 0u || shared_state.clock.step >= shared_state.clock.checkpoint_step + params.checkpoint_interval;
        if params.rollback_enabled != 0u && due {
            shared_state.clock.checkpoint_action = SAVE;
            shared_state.clock.has_checkpoint = 1u;
            shared_state.clock.checkpoint_step = shared_state.clock.step;
            shared_state.clock.checkpoint_time_lo = shared_state.clock.time_ns_lo;
            shared_state.clock.checkpoint_time_hi = shared_state.clock.time_ns_hi;
            shared_state.clock.checkpoint_count = params.particle_count;
            shared_state.clock.checkpoint_rule_dt = rule_dt;
            shared_state.clock.save_requested = 0u;
            shared_state.clock.retries = 0u;
        }
    }
    shared_state.clock.rule_dt = rule_dt;
    var dt = rule_dt * scale();
    if params.budget_steps != 0u {
        if shared_state.clock.budget_frame != params.budget_frame {
            shared_state.clock.budget_frame = params.budget_frame;
            shared_state.clock.budget_remaining = bitcast<f32>(params.budget_time_bits);
            shared_state.clock.budget_steps_left = params.budget_steps;
        }
        let left = max(shared_state.clock.budget_steps_left, 1u);
        dt = min(dt, max(shared_state.clock.budget_remaining, 0.0) / f32(left));
        shared_state.clock.budget_remaining -= dt;
        shared_state.clock.budget_steps_left = left - 1u;
    }
    shared_state.clock.dt = dt;
    shared_state.clock.step += 1u;
    let time = add_ns(shared_state.clock.time_ns_lo, shared_state.clock.time_ns_hi, dt);
    shared_state.clock.time_ns_lo = time.x;
    shared_state.clock.time_ns_hi = time.y;
}
