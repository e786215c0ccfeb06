//! The logical storage buffers the passes read and write, by name ([`Buf`]); where each lies is
//! `arenas`' business.

/// The logical storage buffers; each is a region of an arena (`Buf::arena`, `render::arenas`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Buf {
    /// Positions (w = id) [m].
    Position = 1,
    /// Velocities [m/s].
    Velocity,
    /// Predicted velocities (what viscosity sees).
    VelocityPredicted,
    /// Accelerations [m/s²].
    Acceleration,
    /// Start-of-step accelerations (the design's leapfrog).
    AccelerationStart,
    /// Densities [kg/m³].
    Density,
    /// Pressures [Pa].
    Pressure,
    /// Akinci normals (surface tension only).
    Normal,
    /// The scatter's sorted copies, in state order.
    SortedPosition,
    /// Sorted velocities.
    SortedVelocity,
    /// Sorted predicted velocities.
    SortedVelocityPredicted,
    /// Sorted accelerations.
    SortedAcceleration,
    /// Sorted start-of-step accelerations.
    SortedAccelerationStart,
    /// Grid: each particle's cell.
    CellOf,
    /// Grid: each particle's rank in its cell.
    RankInCell,
    /// Grid: per-cell counts.
    CellCounts,
    /// Grid: exclusive offsets.
    CellStart,
    /// Hash: sort keys.
    SortKeys,
    /// Hash: sort values (particle indices).
    SortValues,
    /// Hash: per-bucket start + 1.
    BucketStart,
    /// Hash: per-bucket end.
    BucketEnd,
    /// Debug: neighbours within h.
    NeighborCount,
    /// The clock (`GpuClock`).
    Clock,
    /// The rollback checkpoint: position, velocity, acceleration of every slot.
    Checkpoint,
    /// Boundary samples' positions (w = volume V_b), sorted by cell; sized by samples.
    BoundaryPosition,
    /// Boundary samples' velocities (w = friction factor).
    BoundaryVelocity,
    /// Boundary samples' exclusive cell offsets over the dense grid.
    BoundaryCellStart,
    /// The colliders (`GpuCollider`), for the guard.
    Colliders,
    /// Each boundary sample's body (0 the walls, k + 1 collider slot k).
    BoundaryBody,
    /// The fluid's force on each body over the frame (`GpuBodyForces`), read back.
    BodyForces,
    /// The frame's pumps (`GpuPumps`).
    Pumps,
    /// The frame's probes and their sums (`GpuProbes`), read back.
    Probes,
    /// The mesh colliders' hierarchies and triangles, for the guard.
    Meshes,
    /// PBF: each particle's neighbours of the step (pairs within h at the predicted positions),
    /// at most `PBF_MAX_NEIGHBORS`, neighbour k of particle i at `list_slot(i, k)`
    /// (`sph_core::gpu_layout::LIST_TILE`).
    NeighborLists,
    /// DFSPH: the same pairs with their weighted gradient, (m ∇W_ij, j as bits), written with
    /// the factors after each sort and read by every iteration of the solves.
    DfsphPairs,
    /// WCSPH: the equation of state's pressures, from which the free-surface pass writes
    /// [`Buf::Pressure`].
    PressureEos,
    /// DFSPH: the boundary's mirrored share of each particle's factor, (Σ_b g_ib over the
    /// samples that mirror κ_i, 1 when they do), written with the factors after each sort.
    DfsphMirror,
    /// Whitewater: the diffuse pool's slots, (position, class: 0 spray, 1 foam, 2 bubble, -1
    /// empty) in the first `diffuse capacity` elements, then (velocity, lifetime left).
    DiffuseState,
    /// Whitewater: per fluid particle, its surface normal n̂ (Ihmsen et al. 2012), then its
    /// potentials (trapped air, wave crest, kinetic energy, shedding rate [1/s]).
    WhitewaterFluid,
    /// Whitewater: the diffuse pool's free list, popped from the end.
    DiffuseFree,
    /// Whitewater: the pool's counters (`sph_core::gpu_layout::GpuDiffuseCounts`), atomic.
    DiffuseCounts,
    /// Whitewater: the live diffuse particles per grid cell, then (in place) each cell's first
    /// rank in cell order; the last entry is the live total.
    DiffuseBins,
    /// Whitewater: the live slots in cell order, then each slot's cell and rank in its cell.
    DiffuseOrder,
    /// The bodies the device moves: every slot's input, then its state
    /// (`sph_core::gpu_layout::GpuBodyInput`, `GpuBodyState`), as words (`render::bodies`).
    BodyWords,
    /// The boundary samples' positions as uploaded, where the bodies' placement moves a moved
    /// body's samples from; sized by the samples while there are moved bodies.
    BoundaryRest,
    /// The moved bodies' contacts of the step: per collider slot the largest push along each
    /// world axis and sign, as f32 bits (`render::bodies`, `sph_core::bodies::solid_contact`).
    BodyContacts,
    /// PBF: per boundary sample, `PBF_WALL_LIST_WORDS` u32: the bits of its λ_b of the
    /// iteration (the water's λ extrapolated onto it, `sph_core::solver::pbf::wall_lambda`), the
    /// count of particles within h of it at the predicted positions, their indices; sized by
    /// the samples.
    BoundaryLambda,
}

impl Buf {
    /// Every logical buffer, in the order its arena packs them.
    pub const ALL: [Buf; 47] = [
        Buf::Position,
        Buf::Velocity,
        Buf::VelocityPredicted,
        Buf::Acceleration,
        Buf::AccelerationStart,
        Buf::Density,
        Buf::Pressure,
        Buf::Normal,
        Buf::SortedPosition,
        Buf::SortedVelocity,
        Buf::SortedVelocityPredicted,
        Buf::SortedAcceleration,
        Buf::SortedAccelerationStart,
        Buf::CellOf,
        Buf::RankInCell,
        Buf::CellCounts,
        Buf::CellStart,
        Buf::SortKeys,
        Buf::SortValues,
        Buf::BucketStart,
        Buf::BucketEnd,
        Buf::NeighborCount,
        Buf::Clock,
        Buf::Checkpoint,
        Buf::BoundaryPosition,
        Buf::BoundaryVelocity,
        Buf::BoundaryCellStart,
        Buf::Colliders,
        Buf::BoundaryBody,
        Buf::BodyForces,
        Buf::Pumps,
        Buf::Probes,
        Buf::Meshes,
        Buf::NeighborLists,
        Buf::DfsphPairs,
        Buf::PressureEos,
        Buf::DfsphMirror,
        Buf::DiffuseState,
        Buf::WhitewaterFluid,
        Buf::DiffuseFree,
        Buf::DiffuseCounts,
        Buf::DiffuseBins,
        Buf::DiffuseOrder,
        Buf::BodyWords,
        Buf::BoundaryRest,
        Buf::BodyContacts,
        Buf::BoundaryLambda,
    ];
}
