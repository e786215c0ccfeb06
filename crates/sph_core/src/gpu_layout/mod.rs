//! Plain-old-data mirrors of the GPU buffers (`Gpu*`), shared by the Bevy plugin and the tests,
//! so the CPU and GPU agree on every byte. WGSL twin: `bevy_sph_fluid/src/shaders/types.wgsl`.
//!
//! One file per buffer; every item is re-exported here (`sph_core::gpu_layout::GpuSphParams`).

pub mod bodies;
pub mod body_forces;
pub mod clock;
pub mod colliders;
pub mod diffuse;
pub mod params;
pub mod particles;
pub mod probes;
pub mod pumps;
pub mod shared;
pub mod sizes;

pub use bodies::*;
pub use body_forces::*;
pub use clock::*;
pub use colliders::*;
pub use diffuse::*;
pub use params::*;
pub use particles::*;
pub use probes::*;
pub use pumps::*;
pub use shared::*;
pub use sizes::*;
