//! `CpuSolver`'s walls and colliders: the boundary samples, adding, moving and removing
//! colliders, the water's force on them, and the guard's corrections.

use crate::boundary::collider::{Collider, ColliderError, Pose, Slip};
use crate::boundary::guard::{Corrections, Guard};
use crate::boundary::samples::{BodyForce, Boundary, ColliderId};
use crate::solver::CpuSolver;
use glam::Vec3;
use rayon::prelude::*;

impl CpuSolver {
    /// The walls' and colliders' boundary samples.
    pub fn boundary(&self) -> &Boundary {
        &self.boundary
    }

    /// The boundary, to add, move or remove colliders through [`Boundary`]'s own API (when a
    /// collider joins or leaves, forces are re-evaluated before the next step; a move keeps the
    /// last step's, as on the GPU).
    pub fn boundary_mut(&mut self) -> &mut Boundary {
        &mut self.boundary
    }

    /// Force evaluations summed into the collider forces since the last
    /// [`Self::take_collider_forces`].
    pub fn collider_force_evaluations(&self) -> u64 {
        self.body_force_sums.1
    }

    /// Samples the container's walls with slip `slip` (the default: no slip), or with `None`
    /// leaves them to the last-resort clamp alone (the box without a boundary model).
    pub fn set_wall_boundary(&mut self, slip: Option<Slip>) {
        self.boundary.set_walls(slip);
        self.forces_stale = true;
    }

    /// Adds a collider (validated: the error names the field, the value and the range; nothing
    /// changes on error). Its samples join the boundary at the next step.
    pub fn add_collider(&mut self, collider: Collider) -> Result<ColliderId, ColliderError> {
        let id = self.boundary.add(collider)?;
        self.forces_stale = true;
        Ok(id)
    }

    /// Removes a collider; false when the handle is unknown.
    pub fn remove_collider(&mut self, id: ColliderId) -> bool {
        let removed = self.boundary.remove(id);
        self.forces_stale |= removed;
        removed
    }

    /// Moves a collider to `pose` with the given velocities (what the fluid sees of a kinematic
    /// or dynamic collider); validated, nothing changes on error.
    pub fn set_collider_motion(
        &mut self,
        id: ColliderId,
        pose: Pose,
        linear_velocity: Vec3,
        angular_velocity: Vec3,
    ) -> Result<(), ColliderError> {
        self.boundary
            .set_motion(id, pose, linear_velocity, angular_velocity)
    }

    /// Tells the solver the mass of the body behind dynamic collider `id` (`None`: unknown), so
    /// that DFSPH's solves let the body give way within a frame ([`crate::boundary::free_bodies`]); see
    /// [`Boundary::set_mass`]. Refused unless finite and positive; nothing changes on error.
    pub fn set_collider_mass(
        &mut self,
        id: ColliderId,
        mass: Option<f32>,
    ) -> Result<(), ColliderError> {
        self.boundary.set_mass(id, mass)
    }

    /// The colliders with their handles.
    pub fn colliders(&self) -> impl Iterator<Item = (ColliderId, &Collider)> {
        self.boundary.colliders()
    }

    /// The fluid's force and torque on collider `id`, averaged over the force evaluations since
    /// the last call of [`Self::take_collider_forces`].
    pub fn collider_force(&self, id: ColliderId) -> Option<BodyForce> {
        self.boundary.collider(id)?;
        let (sums, n) = &self.body_force_sums;
        let s = sums.get(id.0 as usize + 1).copied().unwrap_or_default();
        let n = (*n).max(1) as f64;
        Some(BodyForce {
            force: (s.force / n).as_vec3(),
            torque: (s.torque / n).as_vec3(),
        })
    }

    /// The fluid's force and torque on the walls (body 0), averaged like [`Self::collider_force`].
    pub fn wall_force(&self) -> BodyForce {
        let (sums, n) = &self.body_force_sums;
        let s = sums.first().copied().unwrap_or_default();
        let n = (*n).max(1) as f64;
        BodyForce {
            force: (s.force / n).as_vec3(),
            torque: (s.torque / n).as_vec3(),
        }
    }

    /// Every collider's averaged force (see [`Self::collider_force`]); starts a new average.
    /// The forces taken are what the engine that moves the dynamic bodies receives: DFSPH's
    /// solves measure a body's give against them ([`crate::boundary::free_bodies`]).
    pub fn take_collider_forces(&mut self) -> Vec<(ColliderId, BodyForce)> {
        let forces: Vec<(ColliderId, BodyForce)> = self
            .colliders()
            .filter_map(|(id, _)| self.collider_force(id).map(|f| (id, f)))
            .collect();
        if self.body_force_sums.1 > 0 {
            self.dfsph
                .free_bodies
                .set_references(forces.iter().map(|(id, f)| (id.0 as usize + 1, f.force)));
        }
        self.body_force_sums = (Vec::new(), 0);
        forces
    }

    /// Particles the guard moved out of a solid or back into the box since the last clear (0
    /// while the boundary model holds).
    pub fn boundary_corrections(&self) -> u64 {
        self.boundary_corrections.total()
    }

    /// The corrections by kind: out of colliders, back into the box.
    pub fn corrections(&self) -> Corrections {
        self.boundary_corrections
    }

    /// The last-resort guard of this solver's box and `colliders` (its own, in the world).
    pub(super) fn guard<'a>(&self, colliders: &'a [Collider]) -> Guard<'a> {
        Guard {
            walls: self.container.walls(self.params.wall_damping),
            colliders,
            tolerance: crate::boundary::guard::tolerance(self.params.spacing()),
        }
    }

    /// Particles inside any collider now (deeper than the guard's tolerance).
    pub fn inside_collider_count(&self) -> usize {
        let colliders = self.boundary.collider_list();
        let guard = self.guard(&colliders);
        self.particles
            .position
            .par_iter()
            .filter(|&&x| guard.inside_any(x, guard.tolerance))
            .count()
    }
}
