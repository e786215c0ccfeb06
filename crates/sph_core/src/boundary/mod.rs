//! Walls and solids: the Akinci 2012 boundary samples the water meets ([`samples`],
//! [`akinci2012`]), the colliders' shapes and motions ([`collider`]) and how they are sampled
//! ([`sampling`], [`sampling_mesh`], [`trimesh`]), the contact that keeps particles out of them
//! ([`speculative_contact`], [`guard`]), and the bodies the water moves ([`free_bodies`],
//! [`paddle_wheel`]).

pub mod akinci2012;
pub mod collider;
pub mod collider_error;
pub mod free_bodies;
pub mod guard;
pub mod paddle_wheel;
pub mod samples;
pub mod sampling;
pub mod sampling_mesh;
pub mod speculative_contact;
pub mod triangle;
pub mod trimesh;
pub mod trimesh_bvh;
