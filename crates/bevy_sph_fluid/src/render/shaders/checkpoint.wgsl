// Rollback checkpoints (Rust twin: sph_core::rollback and CpuSolver::step), applied by the pass
// that runs right after the time-step pass: count_cells in its drifting roles (kick-drift-kick,
// the leapfrog's second evaluation), integrate (symplectic Euler).
// SAVE:    the checkpoint takes the particle's position, velocity and acceleration.
// RESTORE: slots the checkpoint held take its state back (the acceleration also becomes the
//          leapfrog's start-of-step a0); slots beyond it hold particles spawned since, which
//          join the checkpoint, so nothing is lost or duplicated.
#define_import_path sph::checkpoint

#import sph::bindings::{params, shared_state, particle_state, position_at, velocity_at, acceleration_at, acceleration_start_at, particle_scratch, checkpoint_at}

const CHECKPOINT_SAVE: u32 = 1u;
const CHECKPOINT_RESTORE: u32 = 2u;

fn apply_checkpoint(i: u32) {
    let n = params.capacity;
    let action = shared_state.clock.checkpoint_action;
    if action == CHECKPOINT_SAVE || (action == CHECKPOINT_RESTORE && i >= shared_state.clock.restore_count) {
        particle_scratch[checkpoint_at(i)] = particle_state[position_at(i)];
        particle_scratch[checkpoint_at(n + i)] = particle_state[velocity_at(i)];
        particle_scratch[checkpoint_at(2u * n + i)] = particle_state[acceleration_at(i)];
    } else if action == CHECKPOINT_RESTORE {
        particle_state[position_at(i)] = particle_scratch[checkpoint_at(i)];
        particle_state[velocity_at(i)] = particle_scratch[checkpoint_at(n + i)];
        particle_state[acceleration_at(i)] = particle_scratch[checkpoint_at(2u * n + i)];
        particle_state[acceleration_start_at(i)] = particle_scratch[checkpoint_at(2u * n + i)];
    }
}

// The Euler integrate pass does not integrate a state that is being restored.
fn restoring() -> bool {
    return shared_state.clock.checkpoint_action == CHECKPOINT_RESTORE;
}
