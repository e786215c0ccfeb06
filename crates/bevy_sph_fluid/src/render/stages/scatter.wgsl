// Pass 3 of the sort: move every particle's state to its sorted slot in the sorted_* buffers
// (grid: cell_start[cell] + rank; hash: slot k gathers particle sort_values[k]).
#import sph::bindings::{params, position, velocity, velocity_predicted, acceleration, acceleration_start, sorted_position, sorted_velocity, sorted_velocity_predicted, sorted_acceleration, sorted_acceleration_start, cell_of, rank_in_cell, cell_start, sort_values}

@compute @workgroup_size(#{WORKGROUP_SIZE})
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= params.particle_count {
        return;
    }
#ifdef SEARCH_HASH
    let src = sort_values[i];
    let dst = i;
#else
    let src = i;
    let dst = cell_start[cell_of[i]] + rank_in_cell[i];
#endif
    sorted_position[dst] = position[src];
    sorted_velocity[dst] = velocity[src];
    sorted_velocity_predicted[dst] = velocity_predicted[src];
    sorted_acceleration[dst] = acceleration[src];
    sorted_acceleration_start[dst] = acceleration_start[src];
}
