// Uniform blocks shared by every SPH pass. Rust twin: sph_core::gpu_layout.
#define_import_path sph::types

struct SphUniforms {
    particle_count: u32,
    capacity: u32,
    cell_count: u32,
    table_size: u32,
    // xyz: grid cells per axis; w: bitonic sort length (a power of two).
    grid_dims: vec4<u32>,
    // xyz: grid origin (box minimum); w: cell size h.
    grid_origin: vec4<f32>,
    // xyz: box minimum; w: wall damping.
    box_min: vec4<f32>,
    // xyz: box maximum; w: time step dt.
    box_max: vec4<f32>,
    // xyz: gravity; w: particle mass.
    gravity: vec4<f32>,
    // h, h², 315/(64π h⁹), -945/(32π h⁹)
    kernel_a: vec4<f32>,
    // -45/(π h⁶), 45/(π h⁶), 32/(π h⁹), h⁶/64
    kernel_b: vec4<f32>,
    // ρ0, stiffness k, viscosity μ, surface tension γ
    material: vec4<f32>,
    // x: Tait (1) or linear (0); y: clamp negative pressure; z: adaptive time step; w: the
    // colliders in the guard's list (from the boundary upload)
    flags: vec4<u32>,
    // largest dt, CFL factor λ, viscous limit 0.125 h² ρ0/μ, speed of sound c0
    time_step: vec4<f32>,
    // rollback: enabled (0/1), checkpoint interval, max retries, recovery steps
    rollback: vec4<u32>,
    // real-time mode (sph_core::frame_budget): the frame's time [s] as f32 bits, the steps
    // planned for it, the frame's number, 0; all zero when off
    frame_budget: vec4<u32>,
    // PBF (sph_core::solver::pbf::macklin2013::PbfContext): the cubic spline's k and l, the relaxation
    // ε [1/m²], s_corr's k in λ's units
    pbf_kernel: vec4<f32>,
    // PBF: 1 / W(Δq), XSPH c, vorticity ε [m/s], the correction cap before gravity's term [m]
    pbf: vec4<f32>,
    // PBF: s_corr's n, iterations per step, the neighbour lists' length, 0
    pbf_counts: vec4<u32>,
    // DFSPH (sph_core::solver::dfsph::bender2017): the largest mean density error (fraction of ρ0), the
    // largest mean divergence error [1/s], the factor's cut-off, warm start (1) or not (0)
    dfsph: vec4<f32>,
    // DFSPH: min and max constant-density iterations, min and max divergence-free iterations
    dfsph_counts: vec4<u32>,
    // DFSPH: the spacing Δx [m], the warm starts' fractions of the last stiffness (density,
    // divergence), the largest correction per step (fraction of ρ0)
    dfsph_b: vec4<f32>,
    // Drains: the main world's frame number, the open drains in SphPumps (0 = none), 0, 0.
    drains: vec4<u32>,
    // DFSPH: the divergence-free solve's over-relaxation ω, the constant-density solve's ω;
    // 1 when some boundary sample has friction, else 0; 1 while the boundary samples do not
    // mirror the stiffness, else 0 (z and w from the boundary upload)
    dfsph_c: vec4<f32>,
    // The boundary samples' contact (sph_core::stage::BoundaryContact): its range Δx [m], its
    // pressure at r = 0, 2 ρ0 c0² [Pa]; the free surface's largest pressure ρ0 |g| Δx/2 [Pa];
    // the speculative contact's margin from the solids' surfaces [m]
    boundary_contact: vec4<f32>,
}

// The simulation clock, written only by the GPU (Rust twin: sph_core::gpu_layout::GpuClock).
struct SphClock {
    dt: f32,
    step: u32,
    time_ns_lo: u32,
    time_ns_hi: u32,
    // f32 bits of the largest |v| and |a| of the last step (non-finite compares above finite).
    max_speed_bits: atomic<u32>,
    max_acceleration_bits: atomic<u32>,
    // 0 while healthy, else the step detected as unstable: integration is frozen until reset.
    unstable_step: u32,
    // What the pass right after the time-step pass does with the checkpoint: 0 nothing, 1 save,
    // 2 restore (see shaders/checkpoint.wgsl).
    checkpoint_action: u32,
    // Rollback bookkeeping (Rust twin: sph_core::rollback::RollbackState): rollbacks since the
    // reset, rollbacks since the checkpoint, halvings of dt, stable steps since the last change.
    rollbacks: u32,
    retries: u32,
    halvings: u32,
    stable_steps: u32,
    // The checkpoint: whether one exists, its step and time [ns], the particles it holds.
    has_checkpoint: u32,
    checkpoint_step: u32,
    checkpoint_time_lo: u32,
    checkpoint_time_hi: u32,
    checkpoint_count: u32,
    // Particles the checkpoint held before a restore (the tail beyond are newer spawns).
    restore_count: u32,
    // Set by the CPU when particles were uploaded: take a checkpoint at the next stable step.
    save_requested: u32,
    // The time-step rule's dt before the rollback scale, now and at the checkpoint.
    rule_dt: f32,
    checkpoint_rule_dt: f32,
    // Particles the guard moved out of a collider or back into the box since the reset, and of
    // those the ones clamped back into the box (sph_core::boundary::guard).
    boundary_corrections: atomic<u32>,
    wall_corrections: atomic<u32>,
    // Real-time mode: the frame whose budget is being spent, its time left [s], its steps left.
    budget_frame: u32,
    budget_remaining: f32,
    budget_steps_left: u32,
    // PBF: particles with more neighbours than the lists hold (sph_core::gpu_layout::
    // PBF_MAX_NEIGHBORS), summed over the steps since the reset.
    neighbor_list_overflows: atomic<u32>,
    // DFSPH (see render/solvers/dfsph/dfsph.wgsl): the solve's indirect dispatch arguments (x = 0 once it
    // converged), its converged flag, its applied iterations, its two error sums (64-bit fixed
    // point), the iterations summed since the reset (constant density, its most in one step,
    // divergence-free), the last solves' mean errors.
    dfsph_args_x: u32,
    dfsph_args_y: u32,
    dfsph_args_z: u32,
    dfsph_done: u32,
    dfsph_applied: u32,
    dfsph_error_a_lo: atomic<u32>,
    dfsph_error_a_hi: atomic<u32>,
    dfsph_error_b_lo: atomic<u32>,
    dfsph_error_b_hi: atomic<u32>,
    density_iterations: u32,
    density_iterations_max: u32,
    divergence_iterations: u32,
    density_error: f32,
    divergence_error: f32,
    // Drains: marked particles counted by the sort under way; the last sort's tail and frame.
    marked: atomic<u32>,
    tail_size: u32,
    tail_frame: u32,
    // PBF: the Jacobi iteration under way (from 0; set by each iteration's λ pass).
    pbf_iteration: u32,
    // DFSPH: the most iterations of one step's constant-density and divergence-free solves
    // since the CPU zeroed them (each frame), and the solves cut short by the passes encoded.
    density_frame_max: u32,
    divergence_frame_max: u32,
    density_cut_short: u32,
    divergence_cut_short: u32,
    // Steps begun since the reset, rolled back or not (never goes back; see time_step.wgsl).
    steps_run: u32,
}

struct BitonicStep {
    k: u32,
    j: u32,
    pad_a: u32,
    pad_b: u32,
}

// A collider for the guard (Rust twin: sph_core::gpu_layout::GpuCollider): translation (w = shape
// kind: 0 cuboid, 1 sphere, 2 capsule, 3 cylinder, 4 mesh), rotation quaternion, size (cuboid:
// half extents; sphere: radius; capsule, cylinder: radius, half length; mesh: first node word
// and first triangle word in `meshes` (bit-cast u32), half thickness or -1 when closed; w =
// bounding radius), linear and angular velocity.
struct GpuCollider {
    translation: vec4<f32>,
    rotation: vec4<f32>,
    size: vec4<f32>,
    linear_velocity: vec4<f32>,
    angular_velocity: vec4<f32>,
}

// The fluid's force on each body over a frame (Rust twin: sph_core::gpu_layout::GpuBodyForces):
// per body (32 slots: the walls, then collider slot k at k + 1) six 64-bit fixed-point sums,
// Σ f and Σ x_b × f in units of sph_core::gpu_layout::body_force_unit and body_moment_unit, as
// (low, high) words,
// then the number of force evaluations summed.
struct SphBodyForces {
    sums: array<atomic<u32>, 384>,
    evaluations: atomic<u32>,
    // The number of the frame that wrote the buffer last (the CPU writes it every frame).
    frame: u32,
    pad_b: u32,
    pad_c: u32,
}

// A pump (Rust twin: sph_core::gpu_layout::GpuPump): the box's centre (w = target speed
// [m/s]), the world-to-box rotation quaternion, half extents (w = strength [1/s]) and the unit
// direction it pushes in.
struct GpuPump {
    center_speed: vec4<f32>,
    to_local: vec4<f32>,
    half_extents_strength: vec4<f32>,
    direction: vec4<f32>,
}

// The frame's pumps (Rust twin: sph_core::gpu_layout::GpuPumps).
struct SphPumps {
    count: u32,
    // Open drains, in the slots after the pumps (a pump's box, no strength).
    sink_count: u32,
    pad_b: u32,
    pad_c: u32,
    pumps: array<GpuPump, 16>,
}

// A probe (Rust twin: sph_core::gpu_layout::GpuProbe): centre (w = kind: 0 level, 1 flux,
// 2 count), the world-to-probe rotation, half sizes (level: radius; flux: half width, half
// height, half slab; count: half extents) and the flux normal.
struct GpuProbe {
    center_kind: vec4<f32>,
    to_local: vec4<f32>,
    half: vec4<f32>,
    normal: vec4<f32>,
}

// The frame's probes and their sums (Rust twin: sph_core::gpu_layout::GpuProbes): per probe
// [unused, particles, Σ v·n fixed point, unused] at sums[4k ..]; per Level probe the highest
// particle's key in each of its 128 height bins at level_tops[128k ..].
struct SphProbes {
    count: u32,
    frame: u32,
    samples: atomic<u32>,
    step: u32,
    time_ns_lo: u32,
    time_ns_hi: u32,
    pad_a: u32,
    pad_b: u32,
    probes: array<GpuProbe, 16>,
    sums: array<atomic<u32>, 64>,
    level_tops: array<atomic<u32>, 2048>,
}

// A particle's id carries this bit once a drain took it (sph_core::gpu_layout::DRAINED_BIT).
const DRAINED_BIT: u32 = 0x80000000u;

// Whether the position's w marks a particle a drain took.
fn drained(w: f32) -> bool {
    return (bitcast<u32>(w) & DRAINED_BIT) != 0u;
}
