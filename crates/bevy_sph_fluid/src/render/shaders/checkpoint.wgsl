// Rollback checkpoints (Rust twin: sph_core::rollback and CpuSolver::step), applied by the pass
// that runs right after the time-step pass: count_cells in its drifting roles (kick-drift-kick,
// the leapfrog's second evaluation), integrate (symplectic Euler).
// SAVE:    the checkpoint takes the particle's position, velocity and acceleration.
// RESTORE: slots the checkpoint held take its state back (the acceleration also becomes the
//          leapfrog's start-of-step a0); slots beyond it hold particles spawned since, which
//          join the checkpoint, so nothing is lost or duplicated.
#define_import_path sph::checkpoint

#import sph::bindings::{params, clock, position, velocity, acceleration, acceleration_start, checkpoint}

const CHECKPOINT_SAVE: u32 = 1u;
const CHECKPOINT_RESTORE: u32 = 2u;

fn apply_checkpoint(i: u32) {
    let n = params.capacity;
    let action = clock.checkpoint_action;
    if action == CHECKPOINT_SAVE || (action == CHECKPOINT_RESTORE && i >= clock.restore_count) {
        checkpoint[i] = position[i];
        checkpoint[n + i] = velocity[i];
        checkpoint[2u * n + i] = acceleration[i];
    } else if action == CHECKPOINT_RESTORE {
        position[i] = checkpoint[i];
        velocity[i] = checkpoint[n + i];
        acceleration[i] = checkpoint[2u * n + i];
        acceleration_start[i] = checkpoint[2u * n + i];
    }
}

// The Euler integrate pass does not integrate a state that is being restored.
fn restoring() -> bool {
    return clock.checkpoint_action == CHECKPOINT_RESTORE;
}
