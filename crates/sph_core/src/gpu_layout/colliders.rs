//! The colliders and the boundary samples as the GPU reads them.

use bytemuck::{Pod, Zeroable};
use glam::Vec3;

/// A collider as the GPU guard reads it (WGSL `GpuCollider`): where it is, its shape and its
/// velocity. Rust twin: [`crate::boundary::collider::Collider`].
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuCollider {
    /// Translation [m]; w = shape kind (0 cuboid, 1 sphere, 2 capsule, 3 cylinder, 4 mesh).
    pub translation: [f32; 4],
    /// Rotation quaternion (x, y, z, w).
    pub rotation: [f32; 4],
    /// Cuboid: half extents; sphere: (radius, 0, 0); capsule and cylinder: (radius,
    /// half_length, 0); mesh: (first node word, first triangle word, both bit-cast u32, half
    /// thickness or -1 when closed); w = bounding radius.
    pub size: [f32; 4],
    /// Linear velocity [m/s] (zero for static colliders); w = the collider's body index in
    /// the reactions (slot + 1, [`crate::boundary::samples::WALLS_BODY`] being 0), as u32 bits.
    pub linear_velocity: [f32; 4],
    /// Angular velocity [rad/s].
    pub angular_velocity: [f32; 4],
}

impl GpuCollider {
    /// The GPU form of `c`, body `body` in the reactions; a mesh's words start at `mesh_offset`
    /// in [`GpuBoundarySamples::meshes`].
    pub fn of(c: &crate::boundary::collider::Collider, mesh_offset: u32, body: u32) -> Self {
        use crate::boundary::collider::{ColliderMotion, ColliderShape};
        let (kind, size) = match c.shape {
            ColliderShape::Cuboid { half_extents } => (0.0, half_extents),
            ColliderShape::Sphere { radius } => (1.0, Vec3::new(radius, 0.0, 0.0)),
            ColliderShape::Capsule {
                radius,
                half_length,
            } => (2.0, Vec3::new(radius, half_length, 0.0)),
            ColliderShape::Cylinder {
                radius,
                half_length,
            } => (3.0, Vec3::new(radius, half_length, 0.0)),
            // Nodes from the offset, triangles after them, the shell's half thickness (-1:
            // closed).
            ColliderShape::TriMesh(ref mesh) => (
                4.0,
                Vec3::new(
                    f32::from_bits(mesh_offset),
                    f32::from_bits(mesh_offset + 2 * mesh.nodes().len() as u32),
                    mesh.thickness().map_or(-1.0, |t| 0.5 * t),
                ),
            ),
        };
        let moving = c.motion != ColliderMotion::Static;
        let v = |x: Vec3| {
            let x = if moving { x } else { Vec3::ZERO };
            [x.x, x.y, x.z, 0.0]
        };
        let t = c.pose.translation;
        let q = c.pose.rotation;
        Self {
            translation: [t.x, t.y, t.z, kind],
            rotation: [q.x, q.y, q.z, q.w],
            size: [size.x, size.y, size.z, c.bounding_radius()],
            linear_velocity: {
                let [x, y, z, _] = v(c.linear_velocity);
                [x, y, z, f32::from_bits(body)]
            },
            angular_velocity: v(c.angular_velocity),
        }
    }
}

/// The boundary samples as the GPU reads them, in the order of the grid sort
/// ([`crate::Boundary`]): `position` (xyz, w = volume V_b), `velocity` (xyz, w = the body's
/// friction factor, 0 = free slip) and `cell_start` (cells + 1 exclusive offsets over the
/// container's dense grid, the same grid the fluid uses in grid mode).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct GpuBoundarySamples {
    /// Positions [m], w = V_b [m³].
    pub position: Vec<[f32; 4]>,
    /// Velocities [m/s], w = friction factor.
    pub velocity: Vec<[f32; 4]>,
    /// Exclusive cell offsets, cells + 1 entries.
    pub cell_start: Vec<u32>,
    /// The colliders, for the guard.
    pub colliders: Vec<GpuCollider>,
    /// Each sample's body: 0 the walls, k + 1 the collider slot k ([`crate::ColliderId`]).
    pub body: Vec<u32>,
    /// Whether the samples mirror DFSPH's stiffness and hold the hydrostatic rise
    /// (`crate::solver::dfsph::bender2017`): unless a dynamic collider is in the boundary. The GPU does not
    /// let a body give way in the solves ([`crate::boundary::free_bodies`]), so it follows
    /// [`crate::Boundary::mirrors`] as if no mass were known. The plugin passes it on in
    /// [`GpuSphParams::unmirrored_samples`](crate::gpu_layout::GpuSphParams::unmirrored_samples).
    pub mirrors: bool,
    /// The mesh colliders' hierarchies and triangles ([`crate::TriMesh::gpu_words`]), one after
    /// the other.
    pub meshes: Vec<[f32; 4]>,
    /// [`crate::Boundary::membership`]: a change means a collider joined or left.
    pub membership: u64,
}

impl GpuBoundarySamples {
    /// The sorted samples of `boundary` (sort it first).
    pub fn of(boundary: &crate::Boundary) -> Self {
        let position = boundary
            .position
            .iter()
            .zip(&boundary.volume)
            .map(|(p, &v)| [p.x, p.y, p.z, v])
            .collect();
        let velocity = boundary
            .velocity
            .iter()
            .zip(&boundary.body)
            .map(|(u, &b)| [u.x, u.y, u.z, boundary.friction[b as usize]])
            .collect();
        let mut meshes = Vec::new();
        let colliders = boundary
            .colliders()
            .map(|(id, c)| {
                let offset = meshes.len() as u32;
                if let crate::boundary::collider::ColliderShape::TriMesh(mesh) = &c.shape {
                    meshes.extend(mesh.gpu_words());
                }
                GpuCollider::of(c, offset, id.0 + 1)
            })
            .collect();
        Self {
            position,
            velocity,
            cell_start: boundary.grid.cell_start.clone(),
            colliders,
            body: boundary.body.clone(),
            mirrors: !boundary.dynamic.contains(&true),
            meshes,
            membership: boundary.membership(),
        }
    }
}
