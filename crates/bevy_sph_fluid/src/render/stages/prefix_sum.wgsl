// Pass 2 of the grid sort: exclusive prefix sum of the per-cell counts into cell_start
// (cell_count + 1 entries; the drained particles, in no cell, land after cell_start[cell_count]
// and their count goes to the clock), in one workgroup: serial chunk sums, a scan of the chunk
// sums in workgroup memory (sph::scan), then each chunk writes its offsets.
#import sph::bindings::{params, cell_counts, cell_counts_at, grid, cell_start_at, shared_state}
#import sph::scan::{scan_chunk, workgroup_exclusive_scan, scan_total}

const THREADS: u32 = #{WORKGROUP_SIZE}u;

@compute @workgroup_size(#{WORKGROUP_SIZE})
fn main(@builtin(local_invocation_id) lid: vec3<u32>) {
    let t = lid.x;
    let n = params.cell_count;
    let chunk = scan_chunk(t, n);
    var sum = 0u;
    for (var c = chunk.x; c < chunk.y; c++) {
        sum += atomicLoad(&cell_counts[cell_counts_at(c)]);
    }
    var running = workgroup_exclusive_scan(t, sum);
    for (var c = chunk.x; c < chunk.y; c++) {
        grid[cell_start_at(c)] = running;
        running += atomicLoad(&cell_counts[cell_counts_at(c)]);
    }
    if t == THREADS - 1u {
        // The live particles in cells; the drained ones follow (their cell is n).
        grid[cell_start_at(n)] = scan_total();
        shared_state.clock.tail_size = atomicExchange(&shared_state.clock.marked, 0u);
        shared_state.clock.tail_frame = params.drain_frame;
    }
}
