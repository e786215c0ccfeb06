//! Main-world collider systems: every [`SphCollider`] entity becomes a collider of the backend's
//! boundary ([`sph_core::Boundary`], the CPU solver's or the GPU backend's), resampled when the
//! component changes, moved when its [`GlobalTransform`] moves (kinematic and dynamic colliders
//! carry the velocity of that move over the frame's simulated time), removed with the
//! component; and the water's force on each collider is written back to [`SphColliderForce`]
//! (CPU: the solver's sums; GPU: the device's sums, read back asynchronously).

use crate::api::*;
use crate::shared::{BodyForceReadback, SphSimulation};
use bevy::platform::collections::HashMap;
use bevy::prelude::*;
use sph_core::boundary::collider::ColliderError;
use sph_core::gpu_layout::GPU_BODY_SLOTS;
use sph_core::{Collider, ColliderId, ColliderMotion, ColliderShape, Pose};

/// What the boundary holds for one entity.
#[derive(Clone, Debug, PartialEq)]
pub struct TrackedCollider {
    /// The boundary's handle.
    pub id: ColliderId,
    /// The component and scale it was sampled from.
    pub sampled: (SphCollider, Vec3),
    /// The pose it was last placed at.
    pub pose: Pose,
    /// The mass the boundary was last told ([`SphColliderMass`]).
    pub mass: Option<f32>,
}

/// The entities' colliders in the backend's boundary.
#[derive(Resource, Default, Debug)]
pub struct SphColliderMap {
    /// By entity.
    pub tracked: HashMap<Entity, TrackedCollider>,
    /// The boundary epoch the handles belong to (a rebuilt CPU solver starts a new one).
    pub epoch: u64,
}

/// The shape scaled by a transform's scale: per axis for a cuboid, uniformly otherwise.
fn scaled_shape(shape: &ColliderShape, scale: Vec3) -> Result<ColliderShape, ColliderError> {
    if !scale.is_finite() || scale.min_element() <= 0.0 {
        return Err(ColliderError {
            field: "transform.scale",
            value: format!("{scale}"),
            allowed: "finite and positive on every axis",
        });
    }
    let uniform = (scale.max_element() - scale.min_element()) <= 1e-4 * scale.max_element();
    Ok(match *shape {
        ColliderShape::Cuboid { half_extents } => ColliderShape::Cuboid {
            half_extents: half_extents * scale,
        },
        // A mesh takes any scale; at scale one it stays the same shared mesh.
        ColliderShape::TriMesh(ref mesh) if scale == Vec3::ONE => {
            ColliderShape::TriMesh(mesh.clone())
        }
        ColliderShape::TriMesh(ref mesh) => ColliderShape::TriMesh(mesh.scaled(scale)?.into()),
        _ if !uniform => {
            return Err(ColliderError {
                field: "transform.scale",
                value: format!("{scale}"),
                allowed: "a uniform scale for spheres, capsules and cylinders",
            })
        }
        ColliderShape::Sphere { radius } => ColliderShape::Sphere {
            radius: radius * scale.x,
        },
        ColliderShape::Capsule {
            radius,
            half_length,
        } => ColliderShape::Capsule {
            radius: radius * scale.x,
            half_length: half_length * scale.x,
        },
        ColliderShape::Cylinder {
            radius,
            half_length,
        } => ColliderShape::Cylinder {
            radius: radius * scale.x,
            half_length: half_length * scale.x,
        },
    })
}

fn refuse(entity: Entity, e: ColliderError, stats: &mut SphStats) {
    let error = SphColliderError {
        entity,
        field: e.field.to_string(),
        value: e.value,
        allowed: e.allowed.to_string(),
    };
    warn!("SphFluidPlugin: {error}");
    stats.collider_errors.push(error);
}

/// An entity's collider, transforms, parent and body mass.
type SyncedCollider<'a> = (
    Entity,
    &'a SphCollider,
    &'a GlobalTransform,
    &'a Transform,
    Option<&'a ChildOf>,
    Option<&'a SphColliderMass>,
);

/// Adds, resamples, moves and removes the entities' colliders, and tells the boundary their
/// bodies' masses.
pub(crate) fn sph_sync_colliders(
    colliders: Query<SyncedCollider>,
    mut removed: RemovedComponents<SphCollider>,
    params: Res<SphParams>,
    mut map: ResMut<SphColliderMap>,
    mut sim: ResMut<SphSimulation>,
    mut stats: ResMut<SphStats>,
) {
    stats.collider_errors.clear();
    let Some(container) = sim.container else {
        return;
    };
    let tau = sim.plan.duration;
    if sim.boundary_epoch != map.epoch {
        map.tracked.clear();
        map.epoch = sim.boundary_epoch;
    }
    let Some(boundary) = sim.boundary_mut(&container, &params.0) else {
        return;
    };
    for entity in removed.read() {
        if let Some(t) = map.tracked.remove(&entity) {
            boundary.remove(t.id);
        }
    }
    let mut seen = Vec::new();
    for (entity, collider, global, local, parent, mass) in &colliders {
        seen.push(entity);
        let mass = mass.map(|m| m.0);
        // A root entity's `Transform` is its global one, and fresher: a physics engine that
        // moved the body earlier in the frame (avian in the fixed schedule) wrote `Transform`,
        // and `GlobalTransform` follows only in `PostUpdate`. Read from it, the water would see
        // the body a frame late, and a heavy body resting on water bobbed higher each time.
        let (scale, rotation, translation) = match parent {
            None => (local.scale, local.rotation, local.translation),
            Some(_) => global.to_scale_rotation_translation(),
        };
        let pose = Pose {
            translation,
            rotation,
        };
        let tracked = map.tracked.get(&entity).cloned();
        let resample = tracked
            .as_ref()
            .is_none_or(|t| t.sampled.0 != *collider || t.sampled.1 != scale);
        if resample {
            if let Some(t) = &tracked {
                boundary.remove(t.id);
                map.tracked.remove(&entity);
            }
            let added = scaled_shape(&collider.shape, scale).and_then(|shape| {
                boundary.add(Collider {
                    shape,
                    pose,
                    linear_velocity: Vec3::ZERO,
                    angular_velocity: Vec3::ZERO,
                    motion: collider.motion,
                    slip: collider.slip,
                })
            });
            match added {
                Ok(id) => {
                    map.tracked.insert(
                        entity,
                        TrackedCollider {
                            id,
                            sampled: (collider.clone(), scale),
                            pose,
                            mass: None,
                        },
                    );
                }
                Err(e) => refuse(entity, e, &mut stats),
            }
        }
        let Some(t) = map.tracked.get_mut(&entity) else {
            continue;
        };
        if t.mass != mass {
            match boundary.set_mass(t.id, mass) {
                Ok(()) => t.mass = mass,
                Err(e) => refuse(entity, e, &mut stats),
            }
        }
        if resample {
            continue;
        }
        let Some(t) = tracked else { continue };
        let moving = collider.motion != ColliderMotion::Static;
        let (linear, angular) = if moving && tau > 0.0 {
            let delta = pose.rotation * t.pose.rotation.inverse();
            let (axis, angle) = delta.to_axis_angle();
            (
                (pose.translation - t.pose.translation) / tau,
                axis * (angle / tau),
            )
        } else {
            (Vec3::ZERO, Vec3::ZERO)
        };
        if pose == t.pose && linear == Vec3::ZERO {
            let was_moving = boundary.collider(t.id).is_some_and(|c| {
                c.linear_velocity != Vec3::ZERO || c.angular_velocity != Vec3::ZERO
            });
            if !was_moving {
                continue;
            }
        }
        match boundary.set_motion(t.id, pose, linear, angular) {
            Ok(()) => {
                if let Some(t) = map.tracked.get_mut(&entity) {
                    t.pose = pose;
                }
            }
            Err(e) => refuse(entity, e, &mut stats),
        }
    }
    // Entities that lost their transform or were despawned without a removal event.
    let gone: Vec<Entity> = map
        .tracked
        .keys()
        .filter(|e| !seen.contains(e))
        .copied()
        .collect();
    for entity in gone {
        if let Some(t) = map.tracked.remove(&entity) {
            boundary.remove(t.id);
        }
    }
    if let Some(first) = stats.collider_errors.first() {
        stats.error = Some(first.to_string());
    }
}

/// Writes the water's force on every collider into its [`SphColliderForce`], and on the walls
/// into the container's [`SphWallForce`]: the CPU solver's mean over the frame's evaluations,
/// or on the GPU backend the device's sums of one frame as read back (a frame or two late,
/// never stalling).
pub(crate) fn sph_write_collider_forces(
    map: Res<SphColliderMap>,
    params: Res<SphParams>,
    mut sim: ResMut<SphSimulation>,
    gpu: Option<ResMut<BodyForceReadback>>,
    mut forces: Query<(Entity, &mut SphColliderForce)>,
    mut walls: Query<&mut SphWallForce>,
) {
    let (by_id, wall): (HashMap<ColliderId, sph_core::BodyForce>, _) = match sim.backend {
        SphBackend::Cpu => {
            let Some(solver) = &mut sim.cpu else {
                return;
            };
            if solver.collider_force_evaluations() == 0 {
                return;
            }
            // Read before the take, which starts the next average.
            let wall = solver.wall_force();
            (solver.take_collider_forces().into_iter().collect(), wall)
        }
        SphBackend::Gpu => {
            let Some(sums) = gpu.and_then(|mut g| g.latest.take()) else {
                return;
            };
            let Some(boundary) = sim.gpu_boundary.as_ref() else {
                return;
            };
            let mass = params.particle_mass;
            let wall = sums.mean(0, mass, Vec3::ZERO).unwrap_or_default();
            let by_id = boundary
                .colliders()
                .filter_map(|(id, c)| {
                    let force = sums.mean(id.0 as usize + 1, mass, c.pose.translation);
                    if force.is_none() {
                        warn_once!(
                            "SphFluidPlugin: the GPU sums the forces of {} colliders at most; \
                             collider slot {} gets none",
                            GPU_BODY_SLOTS - 1,
                            id.0
                        );
                    }
                    force.map(|f| (id, f))
                })
                .collect();
            (by_id, wall)
        }
    };
    let wall = SphWallForce {
        force: wall.force,
        torque: wall.torque,
    };
    for mut out in &mut walls {
        if *out != wall {
            *out = wall;
        }
    }
    for (entity, mut out) in &mut forces {
        let Some(t) = map.tracked.get(&entity) else {
            continue;
        };
        if let Some(f) = by_id.get(&t.id) {
            let value = SphColliderForce {
                force: f.force,
                torque: f.torque,
            };
            if *out != value {
                *out = value;
            }
        }
    }
}
