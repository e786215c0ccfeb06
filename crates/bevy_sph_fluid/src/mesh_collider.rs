//! Bevy meshes as water colliders: [`SphCollider::from_mesh`] reads a [`Mesh`]'s positions and
//! triangle indices into a [`TriMesh`] (closed when watertight once coincident vertices are
//! welded, otherwise an open shell), and [`render_mesh`] turns a [`TriMesh`] back into a
//! flat-shaded [`Mesh`] to draw it.

use crate::api::SphCollider;
use bevy::asset::RenderAssetUsages;
use bevy::mesh::{Indices, PrimitiveTopology, VertexAttributeValues};
use bevy::prelude::*;
use sph_core::boundary::collider::ColliderError;
use sph_core::{ColliderShape, TriMesh};

fn mesh_error(field: &'static str, value: String, allowed: &'static str) -> ColliderError {
    ColliderError {
        field,
        value,
        allowed,
    }
}

/// The triangles of `mesh` as a [`TriMesh`]: closed when it is watertight, otherwise an open
/// shell of `open_thickness` [m] (about the particle spacing). Refused with the field, the value
/// and what is allowed when the mesh is not a triangle list, has no positions or indices out of
/// range, or [`TriMesh`] refuses it.
pub fn trimesh_from_mesh(mesh: &Mesh, open_thickness: f32) -> Result<TriMesh, ColliderError> {
    if mesh.primitive_topology() != PrimitiveTopology::TriangleList {
        return Err(mesh_error(
            "mesh.primitive_topology",
            format!("{:?}", mesh.primitive_topology()),
            "TriangleList",
        ));
    }
    let positions = match mesh.try_attribute_option(Mesh::ATTRIBUTE_POSITION) {
        Ok(Some(VertexAttributeValues::Float32x3(p))) => p,
        Ok(other) => {
            return Err(mesh_error(
                "mesh.ATTRIBUTE_POSITION",
                other.map_or("missing".into(), |v| format!("{:?} values", v.len())),
                "Float32x3 positions",
            ))
        }
        Err(e) => {
            return Err(mesh_error(
                "mesh",
                format!("{e:?}"),
                "a mesh still in the main world (RenderAssetUsages::MAIN_WORLD)",
            ))
        }
    };
    let vertices: Vec<Vec3> = positions.iter().map(|p| Vec3::from_array(*p)).collect();
    let indices: Vec<u32> = match mesh.try_indices_option() {
        Ok(Some(i)) => i.iter().map(|k| k as u32).collect(),
        // Unindexed: every three vertices are a triangle.
        _ => (0..vertices.len() as u32).collect(),
    };
    TriMesh::new(&vertices, &indices, open_thickness)
}

impl SphCollider {
    /// A static, free-slip collider of `mesh`'s triangles ([`trimesh_from_mesh`]); an open mesh
    /// becomes a shell of `open_thickness` [m].
    pub fn from_mesh(mesh: &Mesh, open_thickness: f32) -> Result<Self, ColliderError> {
        let mesh = trimesh_from_mesh(mesh, open_thickness)?;
        Ok(Self::new(ColliderShape::TriMesh(mesh.into())))
    }
}

/// A flat-shaded [`Mesh`] of `mesh`'s triangles, to draw a mesh collider.
pub fn render_mesh(mesh: &TriMesh) -> Mesh {
    let (vertices, indices) = mesh.indexed();
    let normals: Vec<[f32; 3]> = mesh
        .triangles()
        .iter()
        .flat_map(|t| [t.pseudo_normals[6].to_array(); 3])
        .collect();
    Mesh::new(
        PrimitiveTopology::TriangleList,
        RenderAssetUsages::default(),
    )
    .with_inserted_attribute(
        Mesh::ATTRIBUTE_POSITION,
        vertices.iter().map(|v| v.to_array()).collect::<Vec<_>>(),
    )
    .with_inserted_attribute(Mesh::ATTRIBUTE_NORMAL, normals)
    .with_inserted_indices(Indices::U32(indices.into_iter().flatten().collect()))
}
