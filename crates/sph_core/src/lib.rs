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

pub mod bodies;
pub mod boundary;
pub mod container;
pub mod density;
pub mod diagnostics;
pub mod eos;
pub mod flow;
pub mod forces;
pub mod frame_budget;
pub mod free_surface_pressure;
pub mod front;
pub mod gpu_dfsph_pairs;
pub mod gpu_layout;
pub mod integrate;
pub mod kernel;
pub mod limits;
pub mod neighbor;
pub mod params;
pub mod rng;
pub mod rollback;
pub mod scenario;
pub mod scene;
pub mod solver;
pub mod solvers;
pub mod spawn;
pub mod stability;
pub mod stage;
pub mod surface_tension_akinci2013;
pub mod whitewater;

pub use boundary::collider::{Collider, ColliderMotion, ColliderShape, Pose, Slip};
pub use boundary::samples::{BodyForce, Boundary, ColliderId};
pub use boundary::trimesh::{SharedTriMesh, TriMesh};
pub use container::{BoxContainer, Walls};
pub use diagnostics::Diagnostics;
pub use eos::Eos;
pub use flow::probe::{ProbeKind, ProbeReading};
pub use flow::pump::Pump;
pub use flow::region::Region;
pub use flow::sink::Sink;
pub use frame_budget::StepDt;
pub use kernel::Kernels;
pub use neighbor::Neighbors;
pub use params::{
    EquationOfState, Integrator, NeighborSearch, ParamError, SpacingDerivation, SphParams,
};
pub use rollback::Rollback;
pub use solver::dfsph::stages::DfsphStage;
pub use solver::pbf::stages::PbfStage;
pub use solver::wcsph::stages::WcsphStage;
pub use solver::{CpuSolver, FrameAdvance, ParticleData, SpawnReport, StageTimings};
pub use solvers::{DfsphSettings, PbfSettings, Solver, SolverStats};
pub use spawn::{BlockSpawn, Emission, PipeEmitter};
pub use stability::StepExtremes;
pub use stage::{CpuStage, StageContext};

/// Re-export of the vector math crate used in the public API.
pub use glam;
