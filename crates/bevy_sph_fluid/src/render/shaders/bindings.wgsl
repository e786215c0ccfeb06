// The one bind group every SPH pass shares (group 0): the uniform block and ten arenas
// (bevy_sph_fluid::render::arenas), so no pass binds more than 8 storage buffers (WebGPU's
// default). A logical buffer is a region of its arena: element i of `velocity` is
// `particle_state[velocity_at(i)]`, at the region's start in `params.buffer_at` (its `Buf` index).
// Particle state is structure-of-arrays; position.w holds the particle id (bit-cast). The
// `sorted_*` regions receive the scatter and are copied back.
#define_import_path sph::bindings

#import sph::types::{SphUniforms, SphShared, GpuCollider}

@group(0) @binding(0) var<uniform> params: SphUniforms;
// Per particle: position (w = id), velocity, predicted velocity (what viscosity sees),
// acceleration, start-of-step acceleration (the design's leapfrog), Akinci normal (PBF: λ and
// density).
@group(0) @binding(1) var<storage, read_write> particle_state: array<vec4<f32>>;
// Per particle: density, pressure and (WCSPH) the equation of state's pressure, from which the
// free-surface pass writes `pressure`.
@group(0) @binding(2) var<storage, read_write> particle_scalars: array<f32>;
// The scatter's sorted copies; the rollback checkpoint, three capacity-long runs (position,
// velocity, acceleration, see shaders/checkpoint.wgsl); DFSPH's boundary share of each
// particle's factor, (Σ_b g_ib over the samples that mirror κ_i, 1 when they do, else 0);
// whitewater's diffuse particles and, per fluid particle, its normal and potentials.
@group(0) @binding(3) var<storage, read_write> particle_scratch: array<vec4<f32>>;
// Grid mode: each particle's cell and rank in it, exclusive cell offsets. Hash mode: the
// bitonic network's (key, particle) pairs, per-bucket start + 1 and end. Neighbours within h of
// each particle (NEIGHBOR_COUNT), and PBF's and DFSPH's lists of the step's neighbours
// (neighbour k of particle i at list_slot(i, k)). The boundary samples' exclusive cell offsets.
// The moved bodies' inputs and states as words (render/bodies/bodies.wgsl).
// Whitewater's free list and its slots in cell order.
@group(0) @binding(4) var<storage, read_write> grid: array<u32>;
// Grid mode: per-cell counts. Whitewater's counters (render/whitewater/whitewater.wgsl) and its
// per-cell counts. The moved bodies' contacts of the step (render/bodies/bodies.wgsl).
@group(0) @binding(5) var<storage, read_write> cell_counts: array<atomic<u32>>;
// The frame's pumps (shaders/pumps.wgsl) and probes (shaders/probes.wgsl), the clock, and the
// fluid's force on each body over the frame (written by the forces pass, read back).
@group(0) @binding(6) var<storage, read_write> shared_state: SphShared;
// The Akinci 2012 boundary samples of the walls and colliders, sorted by cell over the dense
// grid (uploaded by the CPU, sph_core::gpu_layout::GpuBoundarySamples): position (w = volume
// V_b), velocity (w = the body's friction factor, 0 = free slip); then the mesh colliders'
// hierarchies and triangles (sph_core::boundary::trimesh::TriMesh::gpu_words), for the guard;
// with moved bodies, the samples' positions as uploaded (render/bodies/body_placement.wgsl).
@group(0) @binding(7) var<storage, read_write> boundary_samples: array<vec4<f32>>;
// Each boundary sample's body (0 the walls, k + 1 collider slot k), in the samples' order;
// PBF's wall lists and λ_b (render/solvers/pbf/pbf.wgsl's wall_word).
@group(0) @binding(8) var<storage, read_write> boundary_body: array<u32>;
// The colliders, for the guard (params.guard_colliders of them).
@group(0) @binding(9) var<storage, read_write> colliders: array<GpuCollider>;
// DFSPH: the step's pairs with their weighted gradient (m ∇W_ij), packed to 8 bytes, pairs k and
// k + 1 of particle i in one entry (written by the dfsph_density pass after each sort;
// sph::dfsph's pairs).
@group(0) @binding(10) var<storage, read_write> dfsph_pairs: array<vec4<u32>>;

// Where element i of each logical buffer lies in its arena.
fn position_at(i: u32) -> u32 { return params.buffer_at[0].y + i; }
fn velocity_at(i: u32) -> u32 { return params.buffer_at[0].z + i; }
fn velocity_predicted_at(i: u32) -> u32 { return params.buffer_at[0].w + i; }
fn acceleration_at(i: u32) -> u32 { return params.buffer_at[1].x + i; }
fn acceleration_start_at(i: u32) -> u32 { return params.buffer_at[1].y + i; }
fn density_at(i: u32) -> u32 { return params.buffer_at[1].z + i; }
fn pressure_at(i: u32) -> u32 { return params.buffer_at[1].w + i; }
fn normal_at(i: u32) -> u32 { return params.buffer_at[2].x + i; }
fn sorted_position_at(i: u32) -> u32 { return params.buffer_at[2].y + i; }
fn sorted_velocity_at(i: u32) -> u32 { return params.buffer_at[2].z + i; }
fn sorted_velocity_predicted_at(i: u32) -> u32 { return params.buffer_at[2].w + i; }
fn sorted_acceleration_at(i: u32) -> u32 { return params.buffer_at[3].x + i; }
fn sorted_acceleration_start_at(i: u32) -> u32 { return params.buffer_at[3].y + i; }
fn cell_of_at(i: u32) -> u32 { return params.buffer_at[3].z + i; }
fn rank_in_cell_at(i: u32) -> u32 { return params.buffer_at[3].w + i; }
fn cell_counts_at(i: u32) -> u32 { return params.buffer_at[4].x + i; }
fn cell_start_at(i: u32) -> u32 { return params.buffer_at[4].y + i; }
fn sort_keys_at(i: u32) -> u32 { return params.buffer_at[4].z + i; }
fn sort_values_at(i: u32) -> u32 { return params.buffer_at[4].w + i; }
fn bucket_start_at(i: u32) -> u32 { return params.buffer_at[5].x + i; }
fn bucket_end_at(i: u32) -> u32 { return params.buffer_at[5].y + i; }
fn neighbor_count_at(i: u32) -> u32 { return params.buffer_at[5].z + i; }
fn checkpoint_at(i: u32) -> u32 { return params.buffer_at[6].x + i; }
fn boundary_position_at(i: u32) -> u32 { return params.buffer_at[6].y + i; }
fn boundary_velocity_at(i: u32) -> u32 { return params.buffer_at[6].z + i; }
fn boundary_cell_start_at(i: u32) -> u32 { return params.buffer_at[6].w + i; }
fn boundary_body_at(i: u32) -> u32 { return params.buffer_at[7].y + i; }
fn meshes_at(i: u32) -> u32 { return params.buffer_at[8].y + i; }
fn neighbor_lists_at(i: u32) -> u32 { return params.buffer_at[8].z + i; }
fn pressure_eos_at(i: u32) -> u32 { return params.buffer_at[9].x + i; }
fn dfsph_mirror_at(i: u32) -> u32 { return params.buffer_at[9].y + i; }
fn diffuse_state_at(i: u32) -> u32 { return params.buffer_at[9].z + i; }
fn whitewater_fluid_at(i: u32) -> u32 { return params.buffer_at[9].w + i; }
fn diffuse_free_at(i: u32) -> u32 { return params.buffer_at[10].x + i; }
fn diffuse_counts_at(i: u32) -> u32 { return params.buffer_at[10].y + i; }
fn diffuse_bins_at(i: u32) -> u32 { return params.buffer_at[10].z + i; }
fn diffuse_order_at(i: u32) -> u32 { return params.buffer_at[10].w + i; }
fn body_words_at(i: u32) -> u32 { return params.buffer_at[11].x + i; }
fn boundary_rest_at(i: u32) -> u32 { return params.buffer_at[11].y + i; }
fn body_contacts_at(i: u32) -> u32 { return params.buffer_at[11].z + i; }
fn boundary_lambda_at(i: u32) -> u32 { return params.buffer_at[11].w + i; }
