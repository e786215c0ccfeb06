//! The solver's particle arrays and stage timings, shared by the WCSPH step (`solver/mod.rs`)
//! and the DFSPH step (`solver/dfsph/mod.rs`).

use crate::boundary::samples::Boundary;
use crate::neighbor::Neighbors;
use crate::params::SphParams;
use glam::Vec3;
use std::time::{Duration, Instant};

/// The parts of the solver that the DFSPH and PBF steps borrow.
pub(crate) struct SolverParts<'a> {
    pub params: &'a SphParams,
    pub neighbors: &'a mut Neighbors,
    pub particles: &'a mut ParticleData,
    pub boundary: &'a mut Boundary,
    pub timings: &'a mut StageTimings,
    /// The reorder's scratch array.
    pub sort_scratch: &'a mut Vec<Vec3>,
}

impl SolverParts<'_> {
    /// Re-places the boundary samples if they moved and sorts the particles by cell at their
    /// current positions (timed as the sort stage).
    pub fn sort_by_cell(&mut self) {
        let (neighbors, p, boundary) = (
            &mut *self.neighbors,
            &mut *self.particles,
            &mut *self.boundary,
        );
        let sort_scratch = &mut *self.sort_scratch;
        timed(&mut self.timings.sort, || {
            let _ = boundary.sort();
            let order = neighbors.sort(&p.position);
            p.reorder(order, sort_scratch);
        });
    }
}

/// Structure-of-arrays particle state, kept in the neighbour-sort order of the last evaluation.
#[derive(Clone, Debug, Default)]
pub struct ParticleData {
    /// Positions x [m].
    pub position: Vec<Vec3>,
    /// Velocities v [m/s] (mid-step v½ inside a kick-drift-kick step).
    pub velocity: Vec<Vec3>,
    /// The velocity the viscosity term sees during a force evaluation.
    pub velocity_predicted: Vec<Vec3>,
    /// Accelerations a [m/s²] of the last force evaluation.
    pub acceleration: Vec<Vec3>,
    /// The design's leapfrog: the start-of-step acceleration a0.
    pub acceleration_start: Vec<Vec3>,
    /// Densities ρ [kg/m³].
    pub density: Vec<f32>,
    /// Pressures p [Pa].
    pub pressure: Vec<f32>,
    /// Akinci normals (only maintained with surface tension).
    pub normal: Vec<Vec3>,
    /// Stable particle identifiers (spawn order), so sorted states can be compared.
    pub id: Vec<u32>,
    /// DFSPH: the constant-density solve's stiffness κ of the last step [m⁵/(kg s²)], its warm
    /// start (see [`crate::solver::dfsph::bender2017`]); zero with WCSPH.
    pub stiffness_density: Vec<f32>,
    /// DFSPH: the divergence-free solve's stiffness of the last step, likewise.
    pub stiffness_divergence: Vec<f32>,
    /// PBF: the positions at the start of the step, while the constraint moves the predicted
    /// ones in `position`.
    pub position_previous: Vec<Vec3>,
}

impl ParticleData {
    /// Number of particles.
    pub fn len(&self) -> usize {
        self.position.len()
    }

    /// Whether there are no particles.
    pub fn is_empty(&self) -> bool {
        self.position.is_empty()
    }

    /// Copies `other` into `self`, reusing the allocations.
    pub(crate) fn copy_from(&mut self, other: &Self) {
        self.position.clone_from(&other.position);
        self.velocity.clone_from(&other.velocity);
        self.velocity_predicted
            .clone_from(&other.velocity_predicted);
        self.acceleration.clone_from(&other.acceleration);
        self.acceleration_start
            .clone_from(&other.acceleration_start);
        self.density.clone_from(&other.density);
        self.pressure.clone_from(&other.pressure);
        self.normal.clone_from(&other.normal);
        self.id.clone_from(&other.id);
        self.stiffness_density.clone_from(&other.stiffness_density);
        self.stiffness_divergence
            .clone_from(&other.stiffness_divergence);
        self.position_previous.clone_from(&other.position_previous);
    }

    /// Removes the particles whose `flag` is set (`flag.len()` must equal [`Self::len`]; extra
    /// particles are kept), keeping the others' order; returns the removed particles' ids.
    pub(crate) fn remove_flagged(&mut self, flag: &[bool]) -> Vec<u32> {
        let removed: Vec<u32> = self
            .id
            .iter()
            .zip(flag)
            .filter(|(_, &f)| f)
            .map(|(&id, _)| id)
            .collect();
        if removed.is_empty() {
            return removed;
        }
        fn keep<T: Copy>(field: &mut Vec<T>, flag: &[bool]) {
            let mut k = 0;
            field.retain(|_| {
                let drop = flag.get(k).copied().unwrap_or(false);
                k += 1;
                !drop
            });
        }
        for field in [
            &mut self.position,
            &mut self.velocity,
            &mut self.velocity_predicted,
            &mut self.acceleration,
            &mut self.acceleration_start,
            &mut self.normal,
            &mut self.position_previous,
        ] {
            keep(field, flag);
        }
        for field in [
            &mut self.density,
            &mut self.pressure,
            &mut self.stiffness_density,
            &mut self.stiffness_divergence,
        ] {
            keep(field, flag);
        }
        keep(&mut self.id, flag);
        removed
    }

    /// Gathers every per-particle array by `order` (sorted slot k takes particle order[k]).
    pub(crate) fn reorder(&mut self, order: &[u32], scratch: &mut Vec<Vec3>) {
        for field in [
            &mut self.position,
            &mut self.velocity,
            &mut self.velocity_predicted,
            &mut self.acceleration,
            &mut self.acceleration_start,
            &mut self.position_previous,
        ] {
            scratch.clear();
            scratch.extend(order.iter().map(|&i| field[i as usize]));
            std::mem::swap(field, scratch);
        }
        let id: Vec<u32> = order.iter().map(|&i| self.id[i as usize]).collect();
        self.id = id;
        for field in [&mut self.stiffness_density, &mut self.stiffness_divergence] {
            let sorted: Vec<f32> = order.iter().map(|&i| field[i as usize]).collect();
            *field = sorted;
        }
    }
}

/// Wall-clock time spent in each stage since the solver was created (or the timings were reset).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StageTimings {
    /// Neighbour sort and reorder (count, prefix sum, scatter; or hash sort).
    pub sort: Duration,
    /// Density and pressure.
    pub density: Duration,
    /// Akinci normals.
    pub normals: Duration,
    /// Accelerations.
    pub forces: Duration,
    /// Integration and wall collisions.
    pub integrate: Duration,
    /// DFSPH: neighbour lists, factors and the two pressure solves.
    pub pressure_solve: Duration,
}

impl StageTimings {
    /// (stage name, time) pairs in pipeline order.
    pub fn stages(&self) -> [(&'static str, Duration); 6] {
        [
            ("sort", self.sort),
            ("density", self.density),
            ("normals", self.normals),
            ("forces", self.forces),
            ("pressure solve", self.pressure_solve),
            ("integrate", self.integrate),
        ]
    }
}

/// Runs `f`, adding its wall-clock time to `slot`.
pub(crate) fn timed<R>(slot: &mut Duration, f: impl FnOnce() -> R) -> R {
    let t = Instant::now();
    let result = f();
    *slot += t.elapsed();
    result
}
