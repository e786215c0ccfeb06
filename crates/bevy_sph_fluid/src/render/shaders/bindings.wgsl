// The one bind group every SPH pass shares (group 0). Particle state is structure-of-arrays;
// position.w holds the particle id (bit-cast). `sorted_*` receive the scatter and are copied back.
#define_import_path sph::bindings

#import sph::types::{SphUniforms, SphClock, GpuCollider, SphBodyForces, SphPumps, SphProbes}

@group(0) @binding(0) var<uniform> params: SphUniforms;
@group(0) @binding(1) var<storage, read_write> position: array<vec4<f32>>;
@group(0) @binding(2) var<storage, read_write> velocity: array<vec4<f32>>;
@group(0) @binding(3) var<storage, read_write> velocity_predicted: array<vec4<f32>>;
@group(0) @binding(4) var<storage, read_write> acceleration: array<vec4<f32>>;
@group(0) @binding(5) var<storage, read_write> acceleration_start: array<vec4<f32>>;
@group(0) @binding(6) var<storage, read_write> density: array<f32>;
@group(0) @binding(7) var<storage, read_write> pressure: array<f32>;
@group(0) @binding(8) var<storage, read_write> normal: array<vec4<f32>>;
@group(0) @binding(9) var<storage, read_write> sorted_position: array<vec4<f32>>;
@group(0) @binding(10) var<storage, read_write> sorted_velocity: array<vec4<f32>>;
@group(0) @binding(11) var<storage, read_write> sorted_velocity_predicted: array<vec4<f32>>;
@group(0) @binding(12) var<storage, read_write> sorted_acceleration: array<vec4<f32>>;
@group(0) @binding(13) var<storage, read_write> sorted_acceleration_start: array<vec4<f32>>;
// Grid mode: each particle's cell, its rank in the cell, per-cell counts, exclusive offsets.
@group(0) @binding(14) var<storage, read_write> cell_of: array<u32>;
@group(0) @binding(15) var<storage, read_write> rank_in_cell: array<u32>;
@group(0) @binding(16) var<storage, read_write> cell_counts: array<atomic<u32>>;
@group(0) @binding(17) var<storage, read_write> cell_start: array<u32>;
// Hash mode: (key, particle) pairs sorted by the bitonic network, per-bucket start + 1 and end.
@group(0) @binding(18) var<storage, read_write> sort_keys: array<u32>;
@group(0) @binding(19) var<storage, read_write> sort_values: array<u32>;
@group(0) @binding(20) var<storage, read_write> bucket_start: array<u32>;
@group(0) @binding(21) var<storage, read_write> bucket_end: array<u32>;
// Debug: neighbours within h of each particle (written by the density pass with NEIGHBOR_COUNT).
@group(0) @binding(22) var<storage, read_write> neighbor_count: array<u32>;
// The clock: each step's dt, simulated time, the step's extremes and the instability freeze.
@group(0) @binding(23) var<storage, read_write> clock: SphClock;
// Rollback: the last good state, three arrays of capacity vec4s (position, velocity,
// acceleration) one after the other (see shaders/checkpoint.wgsl).
@group(0) @binding(24) var<storage, read_write> checkpoint: array<vec4<f32>>;
// The Akinci 2012 boundary samples of the walls and colliders, sorted by cell over the dense
// grid (uploaded by the CPU, sph_core::gpu_layout::GpuBoundarySamples): position (w = volume
// V_b), velocity (w = the body's friction factor, 0 = free slip), exclusive cell offsets.
@group(0) @binding(25) var<storage, read_write> boundary_position: array<vec4<f32>>;
@group(0) @binding(26) var<storage, read_write> boundary_velocity: array<vec4<f32>>;
@group(0) @binding(27) var<storage, read_write> boundary_cell_start: array<u32>;
// The colliders, for the guard (params.guard_colliders of them).
@group(0) @binding(28) var<storage, read_write> colliders: array<GpuCollider>;
// Each boundary sample's body (0 the walls, k + 1 collider slot k), in the samples' order.
@group(0) @binding(29) var<storage, read_write> boundary_body: array<u32>;
// The fluid's force on each body over the frame (written by the forces pass, read back).
@group(0) @binding(30) var<storage, read_write> body_forces: SphBodyForces;
// The frame's pumps (see shaders/pumps.wgsl).
@group(0) @binding(31) var<storage, read_write> pumps: SphPumps;
// The frame's probes and their sums (see shaders/probes.wgsl), read back every frame.
@group(0) @binding(32) var<storage, read_write> probes: SphProbes;
// The mesh colliders' hierarchies and triangles (sph_core::boundary::trimesh::TriMesh::gpu_words), for
// the guard.
@group(0) @binding(33) var<storage, read_write> meshes: array<vec4<f32>>;
// PBF and DFSPH: each particle's neighbours of the step, neighbour k of particle i at
// list_slot(i, k) (written by the neighbor_lists pass; its count in neighbor_count).
@group(0) @binding(34) var<storage, read_write> neighbor_lists: array<u32>;
// DFSPH: the same pairs with their weighted gradient (m ∇W_ij), packed to 8 bytes, pairs k and
// k + 1 of particle i in one entry (written by the dfsph_density pass after each sort;
// sph::dfsph's pairs).
@group(0) @binding(35) var<storage, read_write> dfsph_pairs: array<vec4<u32>>;
// WCSPH: the equation of state's pressures (written by the density pass), from which the
// free-surface pass writes `pressure`.
@group(0) @binding(36) var<storage, read_write> pressure_eos: array<f32>;
// DFSPH: the boundary's mirrored share of each particle's factor, (Σ_b g_ib over the samples
// that mirror κ_i, 1 when they do, else 0) (written by the dfsph_density pass after each sort).
@group(0) @binding(37) var<storage, read_write> dfsph_mirror: array<vec4<f32>>;
