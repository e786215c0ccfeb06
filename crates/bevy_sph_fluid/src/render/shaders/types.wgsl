// Uniform blocks shared by every SPH pass. Rust twin: sph_core::gpu_layout.
#define_import_path sph::types

struct SphUniforms {
    // Live particles.
    particle_count: u32,
    // Particle slots in every buffer.
    capacity: u32,
    // Dense-grid cells (grid mode).
    cell_count: u32,
    // Spatial-hash buckets (hash mode).
    table_size: u32,
    // Grid cells along x, y, z.
    grid_dims: vec3<u32>,
    // The padded sort length (hash mode, a power of two).
    sort_length: u32,
    // Grid origin (the box minimum) [m].
    grid_origin: vec3<f32>,
    // Grid cell size, h [m].
    cell_size: f32,
    // Box minimum [m].
    box_min: vec3<f32>,
    // Wall damping.
    wall_damping: f32,
    // Box maximum [m].
    box_max: vec3<f32>,
    // The fixed time step dt [s] (`SphParams::time_step`).
    fixed_dt: f32,
    // Gravity [m/s²].
    gravity: vec3<f32>,
    // Particle mass m [kg].
    particle_mass: f32,
    // Smoothing radius h [m].
    h: f32,
    // h² [m²].
    h_squared: f32,
    // poly6's constant, 315/(64π h⁹).
    poly6_scale: f32,
    // ∇poly6's constant, -945/(32π h⁹).
    poly6_grad: f32,
    // ∇spiky's constant, -45/(π h⁶), times the pressure-gradient correction of
    // sph_core::stage::StageContext.
    spiky_grad: f32,
    // ∇²viscosity's constant, 45/(π h⁶).
    viscosity_laplacian: f32,
    // Akinci's cohesion constant, 32/(π h⁹).
    cohesion: f32,
    // The cohesion kernel's offset, h⁶/64.
    cohesion_offset: f32,
    // Rest density ρ0 [kg/m³].
    rest_density: f32,
    // Stiffness k.
    stiffness: f32,
    // Dynamic viscosity μ.
    viscosity: f32,
    // Surface tension γ.
    surface_tension: f32,
    // Equation of state: 1 Tait, 0 linear.
    tait: u32,
    // Clamp negative pressure (0/1).
    clamp_negative_pressure: u32,
    // Adaptive time step (0/1).
    adaptive_time_step: u32,
    // Colliders in the guard's list (GpuSphParams::with_boundary).
    guard_colliders: u32,
    // The time-step rule's largest dt [s].
    max_dt: f32,
    // CFL factor λ.
    cfl_factor: f32,
    // The viscous limit 0.125 h² ρ0/μ [s] (f32::MAX without viscosity).
    viscous_limit: f32,
    // Speed of sound c0 [m/s].
    speed_of_sound: f32,
    // Rollback (sph_core::rollback) on (1) or off (0); all four rollback fields are zero until
    // GpuSphParams::with_rollback.
    rollback_enabled: u32,
    // Steps between checkpoints.
    checkpoint_interval: u32,
    // Retries before a step is given up.
    max_retries: u32,
    // Steps at a reduced dt after a rollback.
    recovery_steps: u32,
    // Real-time mode (sph_core::frame_budget): the frame's time [s] as f32 bits; the budget fields
    // are zero (off) until GpuSphParams::with_frame_budget.
    budget_time_bits: u32,
    // The steps planned for the frame (0: no budget).
    budget_steps: u32,
    // The frame's number (a new number starts a new budget).
    budget_frame: u32,
    // The reactions on the boundary bodies are summed (1: a collider, or the walls' force read).
    sum_reactions: u32,
    // PBF (sph_core::solver::pbf::macklin2013::PbfContext): the cubic spline's value constant k.
    pbf_cubic_k: f32,
    // PBF: the cubic spline's gradient constant l.
    pbf_cubic_l: f32,
    // PBF: the relaxation ε [1/m²].
    pbf_relaxation: f32,
    // PBF: s_corr's k in λ's units.
    pbf_s_corr_k: f32,
    // PBF: 1 / W(Δq).
    pbf_inverse_w_dq: f32,
    // PBF: XSPH's c.
    pbf_xsph_c: f32,
    // PBF: vorticity confinement's ε [m/s].
    pbf_vorticity_epsilon: f32,
    // PBF: the correction cap before the step's gravity term
    // (sph_core::solver::pbf::macklin2013::MAX_CORRECTION h) [m].
    pbf_max_correction: f32,
    // PBF: s_corr's n.
    pbf_s_corr_n: u32,
    // PBF: Jacobi iterations per step.
    pbf_iterations: u32,
    // PBF: the neighbour lists' length, PBF_MAX_NEIGHBORS.
    pbf_max_neighbors: u32,
    // PBF: the over-relaxation ω as f32 bits.
    pbf_over_relaxation_bits: u32,
    // DFSPH (sph_core::solver::dfsph::bender2017): the largest mean density error (a fraction of
    // ρ0).
    dfsph_max_density_error: f32,
    // DFSPH: the largest mean divergence error [1/s].
    dfsph_max_divergence_error: f32,
    // DFSPH: the cut-off of an isolated particle's factor (a fraction of the rest lattice's D).
    dfsph_factor_epsilon: f32,
    // DFSPH: warm start (1) or not (0).
    dfsph_warm_start: f32,
    // DFSPH: the constant-density solve's least iterations.
    dfsph_min_density_iterations: u32,
    // DFSPH: the constant-density solve's most iterations.
    dfsph_max_density_iterations: u32,
    // DFSPH: the divergence-free solve's least iterations.
    dfsph_min_divergence_iterations: u32,
    // DFSPH: the divergence-free solve's most iterations.
    dfsph_max_divergence_iterations: u32,
    // The spacing Δx [m] (DFSPH's CFL rule's length).
    spacing: f32,
    // DFSPH: the constant-density solve's warm start fraction
    // (sph_core::solver::dfsph::bender2017::DENSITY_WARM_START).
    dfsph_density_warm_start: f32,
    // DFSPH: the divergence-free solve's warm start fraction
    // (sph_core::solver::dfsph::bender2017::DIVERGENCE_WARM_START).
    dfsph_divergence_warm_start: f32,
    // DFSPH: the largest correction per step
    // (sph_core::solver::dfsph::bender2017::MAX_CORRECTION).
    dfsph_max_correction: f32,
    // Drains: the main world's frame number, recorded with each sort's tail
    // (GpuSphParams::with_drains).
    drain_frame: u32,
    // Drains: the open drains in GpuPumps (0 = none).
    open_drains: u32,
    // PBF: the weight of each Jacobi iteration's λ (sph_core::PbfSettings::jacobi_weight).
    pbf_jacobi_weight: f32,
    // Unused (keeps the block in 16-byte rows).
    drains_unused_w: u32,
    // DFSPH: the divergence-free solve's over-relaxation ω
    // (sph_core::DfsphSettings::divergence_over_relaxation).
    dfsph_divergence_over_relaxation: f32,
    // DFSPH: the constant-density solve's over-relaxation ω
    // (sph_core::DfsphSettings::density_over_relaxation).
    dfsph_density_over_relaxation: f32,
    // 1 when some boundary sample has friction, else 0 (GpuSphParams::with_boundary: without one
    // DFSPH's forces pass skips the samples and the reactions' workgroup sums, which only friction
    // feeds there).
    boundary_friction: f32,
    // 1 while the boundary samples do not mirror DFSPH's stiffness, else 0
    // (GpuBoundarySamples::mirrors, from GpuSphParams::with_boundary).
    unmirrored_samples: f32,
    // The boundary samples' contact (sph_core::stage::BoundaryContact): its range Δx [m].
    contact_radius: f32,
    // The contact's pressure at r = 0, 2 ρ0 c0² [Pa].
    contact_modulus: f32,
    // The free surface's largest pressure ρ0 |g| Δx/2 [Pa]
    // (sph_core::stage::max_surface_pressure).
    max_surface_pressure: f32,
    // The speculative contact's margin from the solids' surfaces [m]
    // (sph_core::boundary::speculative_contact::SURFACE_MARGIN Δx).
    surface_margin: f32,
    // Whitewater (Ihmsen et al. 2012; GpuSphParams::with_whitewater, zero while it is off): the
    // potentials' limits (trapped air [m/s], wave crest, kinetic energy [J/kg]), the rates k_ta
    // and k_wc [1/s], the classes' neighbour bounds, the foam's lifetimes [s], the bubbles'
    // buoyancy and drag, the pool's slots (0: off) and the shedding's seed.
    whitewater_trapped_air_min: f32,
    whitewater_trapped_air_max: f32,
    whitewater_wave_crest_min: f32,
    whitewater_wave_crest_max: f32,
    whitewater_kinetic_min: f32,
    whitewater_kinetic_max: f32,
    whitewater_trapped_air_rate: f32,
    whitewater_wave_crest_rate: f32,
    whitewater_spray_below: u32,
    whitewater_bubble_above: u32,
    whitewater_lifetime_min: f32,
    whitewater_lifetime_max: f32,
    whitewater_buoyancy: f32,
    whitewater_drag: f32,
    whitewater_capacity: u32,
    whitewater_seed: u32,
    // The frame's steps the whitewater stages cover (they run in its last step).
    whitewater_steps: u32,
    // The boundary samples uploaded (render/bodies/body_placement.wgsl).
    boundary_sample_count: u32,
    whitewater_unused_z: u32,
    whitewater_unused_w: u32,
    // Where each packed storage buffer starts in its arena, in elements, at index `Buf as usize`
    // (bevy_sph_fluid::render::arenas), four to a row; read through sph::bindings's `*_at`.
    buffer_at: array<vec4<u32>, 12>,
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

// The small structures every pass may share, in one storage buffer (Rust twin:
// sph_core::gpu_layout::GpuShared), so a pass binds one buffer for all of them.
struct SphShared {
    pumps: SphPumps,
    probes: SphProbes,
    clock: SphClock,
    body_forces: SphBodyForces,
}
