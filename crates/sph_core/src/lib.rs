#![warn(missing_docs)]
//! # sph_core
//!
//! The physics of our GPU SPH water, with no Bevy and no wgpu: parameters and presets, Müller 2003
//! kernels, equations of state, symmetric pressure and viscosity forces, Akinci 2013 surface
//! tension, three integrators, the box container, neighbour search (dense grid + counting sort, or
//! the design's spatial hash), spawners, diagnostics, and [`CpuSolver`], the reference every GPU
//! pass is tested against.
//!
//! ```
//! use sph_core::{BlockSpawn, BoxContainer, CpuSolver, SphParams};
//! use glam::Vec3;
//!
//! let params = SphParams::water();
//! let container = BoxContainer::from_min_max(Vec3::ZERO, Vec3::new(0.4, 0.4, 0.2));
//! let mut solver = CpuSolver::new(params, container, 10_000).unwrap();
//! let block = BlockSpawn::new(Vec3::ZERO, Vec3::new(0.1, 0.2, 0.1), params.spacing());
//! solver.spawn(&block.positions(), Vec3::ZERO);
//! solver.step();
//! assert_eq!(solver.diagnostics().non_finite_count, 0);
//! ```

pub mod boundary;
pub mod boundary_akinci2012;
pub mod collider;
pub mod collider_error;
pub mod container;
pub mod density;
pub mod dfsph_bender2017;
pub mod diagnostics;
pub mod eos;
pub mod forces;
pub mod frame_budget;
pub mod free_bodies;
pub mod free_surface_pressure;
pub mod front;
pub mod gpu_dfsph_pairs;
pub mod gpu_layout;
pub mod guard;
pub mod integrate;
pub mod kernel;
pub mod limits;
pub mod neighbor;
pub mod neighbor_lists;
pub mod paddle_wheel;
pub mod pair_lanes;
pub mod params;
pub mod pbf_macklin2013;
pub mod probe;
pub mod pump;
pub mod region;
pub mod rng;
pub mod rollback;
pub mod sampling;
pub mod sampling_mesh;
pub mod scenario;
pub mod scene_controls;
pub mod scene_file;
pub mod scene_mutations;
pub mod sink;
pub mod solver;
pub mod solvers;
pub mod spawn;
pub mod speculative_contact;
pub mod stability;
pub mod stage;
pub mod surface_tension_akinci2013;
pub mod triangle;
pub mod trimesh;
pub mod trimesh_bvh;

pub use boundary::{BodyForce, Boundary, ColliderId};
pub use collider::{Collider, ColliderMotion, ColliderShape, Pose, Slip};
pub use container::{BoxContainer, Walls};
pub use diagnostics::Diagnostics;
pub use eos::Eos;
pub use frame_budget::StepDt;
pub use kernel::Kernels;
pub use neighbor::Neighbors;
pub use params::{
    EquationOfState, Integrator, NeighborSearch, ParamError, SpacingDerivation, SphParams,
};
pub use probe::{ProbeKind, ProbeReading};
pub use pump::Pump;
pub use region::Region;
pub use rollback::Rollback;
pub use sink::Sink;
pub use solver::{CpuSolver, FrameAdvance, ParticleData, SpawnReport, StageTimings};
pub use solvers::{DfsphSettings, PbfSettings, Solver, SolverStats};
pub use spawn::{BlockSpawn, Emission, PipeEmitter};
pub use stability::StepExtremes;
pub use stage::{CpuStage, StageContext};
pub use trimesh::{SharedTriMesh, TriMesh};

/// Re-export of the vector math crate used in the public API.
pub use glam;
