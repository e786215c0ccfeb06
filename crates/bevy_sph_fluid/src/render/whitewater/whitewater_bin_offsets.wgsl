// Whitewater's counting sort, pass 2, in one workgroup: the per-cell counts become, in place,
// each cell's first rank in cell order (an exclusive prefix sum: serial chunk sums, a scan of
// the chunk sums in workgroup memory, sph::scan, then each chunk writes its offsets, as the
// water's prefix_sum); entry cell_count receives the live total.
#import sph::bindings::{params, cell_counts, diffuse_bins_at}
#import sph::scan::{scan_chunk, workgroup_exclusive_scan, scan_total}

const THREADS: u32 = #{WORKGROUP_SIZE}u;

@compute @workgroup_size(#{WORKGROUP_SIZE})
fn main(@builtin(local_invocation_id) lid: vec3<u32>) {
    let t = lid.x;
    let n = params.cell_count;
    let chunk = scan_chunk(t, n);
    var sum = 0u;
    for (var c = chunk.x; c < chunk.y; c++) {
        sum += atomicLoad(&cell_counts[diffuse_bins_at(c)]);
    }
    var running = workgroup_exclusive_scan(t, sum);
    for (var c = chunk.x; c < chunk.y; c++) {
        let count = atomicLoad(&cell_counts[diffuse_bins_at(c)]);
        atomicStore(&cell_counts[diffuse_bins_at(c)], running);
        running += count;
    }
    if t == THREADS - 1u {
        atomicStore(&cell_counts[diffuse_bins_at(n)], scan_total());
    }
}
