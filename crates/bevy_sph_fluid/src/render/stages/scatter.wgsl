// Pass 3 of the sort: move every particle's state to its sorted slot in the sorted_* buffers
// (grid: cell_start[cell] + rank; hash: slot k gathers particle sort_values[k]).
#import sph::bindings::{params, particle_state, position_at, velocity_at, velocity_predicted_at, acceleration_at, acceleration_start_at, particle_scratch, sorted_position_at, sorted_velocity_at, sorted_velocity_predicted_at, sorted_acceleration_at, sorted_acceleration_start_at, grid, cell_of_at, rank_in_cell_at, cell_start_at, sort_values_at}

@compute @workgroup_size(#{WORKGROUP_SIZE})
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= params.particle_count {
        return;
    }
#ifdef SEARCH_HASH
    let src = grid[sort_values_at(i)];
    let dst = i;
#else
    let src = i;
    let dst = grid[cell_start_at(grid[cell_of_at(i)])] + grid[rank_in_cell_at(i)];
#endif
    particle_scratch[sorted_position_at(dst)] = particle_state[position_at(src)];
    particle_scratch[sorted_velocity_at(dst)] = particle_state[velocity_at(src)];
    particle_scratch[sorted_velocity_predicted_at(dst)] = particle_state[velocity_predicted_at(src)];
    particle_scratch[sorted_acceleration_at(dst)] = particle_state[acceleration_at(src)];
    particle_scratch[sorted_acceleration_start_at(dst)] = particle_state[acceleration_start_at(src)];
}
