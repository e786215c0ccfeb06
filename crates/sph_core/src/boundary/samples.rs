//! The boundary the fluid meets, as data (`docs/design_boundary_akinci2012.md` §4): the
//! container's walls and every collider, each sampled once into Akinci 2012 boundary samples
//! (local positions, volumes V_b), placed in the world by its pose and sorted into a dense grid
//! over the container, so the density and forces passes visit them like fluid neighbours. A
//! shape is sampled again only when it is added; a pose or velocity change only re-places and
//! re-sorts the samples. The physics of the samples is in [`crate::boundary::akinci2012`].

use crate::boundary::akinci2012::{boundary_volumes, calibrate_gamma};
use crate::boundary::collider::{Collider, ColliderError, ColliderMotion, Pose, Slip};
use crate::boundary::sampling::{container_shell, sample_shape};
use crate::container::BoxContainer;
use crate::kernel::Kernels;
use crate::neighbor::grid::DenseGrid;
use crate::params::{ParamError, SphParams};
use glam::{DVec3, Vec3};

/// A collider's handle in a solver's boundary.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct ColliderId(pub u32);

/// The body index of the container's walls in [`Boundary::body`]; collider slot k is body k + 1.
pub const WALLS_BODY: u32 = 0;

/// The fluid's force and torque on a body, averaged over force evaluations.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BodyForce {
    /// Force [N].
    pub force: Vec3,
    /// Torque about the collider's pose origin [N m].
    pub torque: Vec3,
}

/// Sums of a body's reaction over force evaluations (f64, so long sums stay exact enough).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BodyForceSum {
    /// Σ force [N].
    pub force: DVec3,
    /// Σ torque [N m].
    pub torque: DVec3,
}

impl BodyForceSum {
    /// Adds the force `f` acting at `at`, with the torque about `origin`.
    pub fn add(&mut self, f: Vec3, at: Vec3, origin: Vec3) {
        self.force += f.as_dvec3();
        self.torque += (at - origin).cross(f).as_dvec3();
    }

    /// Adds another sum.
    pub fn merge(&mut self, other: &Self) {
        self.force += other.force;
        self.torque += other.torque;
    }
}

/// Samples of one body with their volumes: in the collider's frame, or in the world for the walls.
#[derive(Clone, Debug)]
struct SampleSet {
    local: Vec<Vec3>,
    volume: Vec<f32>,
}

/// One collider with its samples.
#[derive(Clone, Debug)]
struct Body {
    collider: Collider,
    samples: SampleSet,
    /// A dynamic collider's mass [kg] when the engine that moves it told (see
    /// [`Boundary::set_mass`]).
    mass: Option<f32>,
    /// How often [`Boundary::set_motion`] placed it.
    placements: u64,
}

/// The samples of the walls and the colliders, sorted by cell, and what they came from.
#[derive(Clone, Debug)]
pub struct Boundary {
    container: BoxContainer,
    spacing: f32,
    kernels: Kernels,
    /// The volume factor γ of the two-layer layout (see [`calibrate_gamma`]).
    gamma: f32,
    /// The fluid particle's volume m/ρ0 over the lattice cell Δx³ (1/L with the derived mass,
    /// [`crate::Kernels::lattice_sum`]); every sample volume is scaled by it, so the boundary
    /// completes the rest lattice to exactly ρ0.
    volume_scale: f32,
    walls: Option<(SampleSet, Slip)>,
    slots: Vec<Option<Body>>,
    /// The grid the samples are sorted into (same origin, cell size and dims as the fluid's).
    pub grid: DenseGrid,
    /// Sorted sample positions [m].
    pub position: Vec<Vec3>,
    /// Sorted sample volumes V_b [m³].
    pub volume: Vec<f32>,
    /// Sorted sample velocities [m/s].
    pub velocity: Vec<Vec3>,
    /// Sorted sample bodies ([`WALLS_BODY`], or collider slot + 1).
    pub body: Vec<u32>,
    /// Each body's friction factor (0 = free slip), by body index.
    pub friction: Vec<f32>,
    /// Whether each body is a dynamic collider, by body index.
    pub dynamic: Vec<bool>,
    /// Each body's pose origin (the torque's reference point), by body index.
    pub origin: Vec<Vec3>,
    sorted: bool,
    /// Changes when a collider is added or removed (unique across boundaries).
    membership: u64,
}

/// The source of [`Boundary::membership`] values.
static MEMBERSHIP: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(1);

fn next_membership() -> u64 {
    MEMBERSHIP.fetch_add(1, std::sync::atomic::Ordering::Relaxed)
}

impl Boundary {
    /// A value that changes whenever a collider joins or leaves (and differs between
    /// boundaries): a backend that keeps forces from the last step re-evaluates them then, as
    /// the CPU solver does.
    pub fn membership(&self) -> u64 {
        self.membership
    }

    /// The boundary of `container` for `params`: the walls sampled (Akinci 2012) with slip
    /// `wall_slip`, no colliders yet.
    pub fn new(
        container: &BoxContainer,
        params: &SphParams,
        wall_slip: Slip,
    ) -> Result<Self, ParamError> {
        let spacing = params.spacing();
        crate::limits::check_container(container, params.smoothing_radius, spacing)?;
        let kernels = Kernels::new(params.smoothing_radius);
        let mut boundary = Self {
            container: *container,
            spacing,
            kernels,
            gamma: calibrate_gamma(spacing, &kernels),
            volume_scale: Self::volume_scale(params),
            walls: None,
            slots: Vec::new(),
            grid: DenseGrid::new(container, params.smoothing_radius)?,
            position: Vec::new(),
            volume: Vec::new(),
            velocity: Vec::new(),
            body: Vec::new(),
            friction: Vec::new(),
            dynamic: Vec::new(),
            origin: Vec::new(),
            sorted: false,
            membership: next_membership(),
        };
        boundary.set_walls(Some(wall_slip));
        boundary.sort();
        Ok(boundary)
    }

    /// The volumes V_b of a shape's samples: the lattice cell of each sample where the sampling
    /// is a lattice (cuboids: exact at faces, edges and corners, as for the walls), otherwise
    /// Akinci's γ / Σ W; both scaled to the fluid particle's volume.
    fn volumes(&self, samples: &crate::boundary::sampling::ShapeSamples) -> Vec<f32> {
        if samples.cell_volume.len() == samples.len() {
            samples
                .cell_volume
                .iter()
                .map(|v| v * self.volume_scale)
                .collect()
        } else {
            boundary_volumes(
                &samples.position,
                &self.kernels,
                self.gamma * self.volume_scale,
            )
        }
    }

    /// m / (ρ0 Δx³) of `params`.
    pub fn volume_scale(params: &SphParams) -> f32 {
        params.particle_mass / (params.rest_density * params.spacing().powi(3))
    }

    /// Removes the walls' samples (the container is then only the last-resort clamp), or puts
    /// them back with slip `slip`.
    pub fn set_walls(&mut self, slip: Option<Slip>) {
        match slip {
            None => self.walls = None,
            Some(slip) => {
                // The shell is the fluid lattice mirrored through the walls, so each sample
                // stands for one lattice cell, as a fluid particle does: exact at walls, edges and
                // corners alike (Akinci's Σ W volumes would under-weight the edges).
                let (shell, cell) = container_shell(&self.container, self.spacing);
                let local = shell.position;
                let volume = vec![cell * self.volume_scale; local.len()];
                self.walls = Some((SampleSet { local, volume }, slip));
            }
        }
        self.sorted = false;
    }

    /// The walls' slip, or `None` when the walls are not sampled.
    pub fn wall_slip(&self) -> Option<Slip> {
        self.walls.as_ref().map(|(_, slip)| *slip)
    }

    /// The container's box when its walls are sampled, else `None`.
    pub fn sampled_walls(&self) -> Option<&BoxContainer> {
        self.walls.as_ref().map(|_| &self.container)
    }

    /// The spacing the shapes were sampled at [m].
    pub fn spacing(&self) -> f32 {
        self.spacing
    }

    /// The layout factor γ of the volumes.
    pub fn gamma(&self) -> f32 {
        self.gamma
    }

    /// Samples `collider` (validated first) and adds it; returns its handle.
    pub fn add(&mut self, collider: Collider) -> Result<ColliderId, ColliderError> {
        collider.validate()?;
        let size = collider.bounding_radius();
        let limit = 2.0 * self.container.size().length();
        if size > limit {
            return Err(ColliderError {
                field: "shape",
                value: format!("{size} m bounding radius"),
                allowed: "at most twice the container's diagonal",
            });
        }
        crate::limits::check_shape_samples(&collider.shape, self.spacing)?;
        let samples = sample_shape(&collider.shape, self.spacing);
        let volume = self.volumes(&samples);
        let local = samples.position;
        let body = Body {
            collider,
            samples: SampleSet { local, volume },
            mass: None,
            placements: 0,
        };
        let slot = match self.slots.iter().position(Option::is_none) {
            Some(free) => {
                self.slots[free] = Some(body);
                free
            }
            None => {
                self.slots.push(Some(body));
                self.slots.len() - 1
            }
        };
        self.sorted = false;
        self.membership = next_membership();
        Ok(ColliderId(slot as u32))
    }

    /// Removes a collider; false when the handle is unknown.
    pub fn remove(&mut self, id: ColliderId) -> bool {
        let removed = self
            .slots
            .get_mut(id.0 as usize)
            .and_then(Option::take)
            .is_some();
        self.sorted &= !removed;
        if removed {
            self.membership = next_membership();
        }
        removed
    }

    /// The collider behind a handle.
    pub fn collider(&self, id: ColliderId) -> Option<&Collider> {
        self.slots
            .get(id.0 as usize)
            .and_then(|s| s.as_ref().map(|b| &b.collider))
    }

    /// Every collider with its handle.
    pub fn colliders(&self) -> impl Iterator<Item = (ColliderId, &Collider)> {
        self.slots
            .iter()
            .enumerate()
            .filter_map(|(k, s)| s.as_ref().map(|b| (ColliderId(k as u32), &b.collider)))
    }

    /// Moves a collider: a new pose and velocities (validated; a static collider keeps zero
    /// velocity). Its samples are re-placed at the next sort.
    pub fn set_motion(
        &mut self,
        id: ColliderId,
        pose: Pose,
        linear_velocity: Vec3,
        angular_velocity: Vec3,
    ) -> Result<(), ColliderError> {
        let Some(body) = self.slots.get_mut(id.0 as usize).and_then(Option::as_mut) else {
            return Err(ColliderError {
                field: "id",
                value: id.0.to_string(),
                allowed: "a collider of this solver",
            });
        };
        let mut moved = body.collider.clone();
        moved.pose = pose;
        if moved.motion != ColliderMotion::Static {
            moved.linear_velocity = linear_velocity;
            moved.angular_velocity = angular_velocity;
        }
        moved.validate()?;
        body.collider = moved;
        body.placements += 1;
        self.sorted = false;
        Ok(())
    }

    /// Tells the boundary the mass of the body behind a dynamic collider (`None`: unknown, the
    /// default), so that DFSPH's solves let the body give way to the water's pressure within a
    /// frame (`crate::boundary::free_bodies`). Refused unless finite and positive; nothing changes on
    /// error. A static or kinematic collider keeps the mass but ignores it.
    pub fn set_mass(&mut self, id: ColliderId, mass: Option<f32>) -> Result<(), ColliderError> {
        if let Some(m) = mass {
            if !m.is_finite() || m <= 0.0 {
                return Err(ColliderError {
                    field: "mass",
                    value: m.to_string(),
                    allowed: "finite and > 0 kg",
                });
            }
        }
        let Some(body) = self.slots.get_mut(id.0 as usize).and_then(Option::as_mut) else {
            return Err(ColliderError {
                field: "id",
                value: id.0.to_string(),
                allowed: "a collider of this solver",
            });
        };
        body.mass = mass;
        Ok(())
    }

    /// Whether the samples mirror DFSPH's stiffness κ_i (`crate::solver::dfsph::bender2017`), all of them
    /// or none: only while every dynamic collider's
    /// mass is known ([`Self::set_mass`]), so that it gives way in the solves
    /// ([`crate::boundary::free_bodies`]).
    /// - A body that cannot give way must not answer twice: with the mirror the water threw a
    ///   heavy one (`tests/free_bodies.rs`: 2,400 m/s against 0.25 m/s without).
    /// - Nor may the walls around it: a heavy box resting on the floor, with the floor
    ///   answering twice and the box once, bounced on the water between them whenever its force
    ///   reached it a few steps late (the GPU's readback), and was thrown off the floor. A
    ///   particle that touched the box answering once was not enough (docs/dfsph.md).
    pub fn mirrors(&self) -> bool {
        self.slots
            .iter()
            .flatten()
            .all(|b| b.collider.motion != ColliderMotion::Dynamic || b.mass.is_some())
    }

    /// The mass of body `body` (a body index, as in [`Self::body`]) when it is a dynamic
    /// collider with a known mass ([`Self::set_mass`]), else `None` (the walls, static and
    /// kinematic colliders, and dynamic ones whose mass was not given).
    pub fn free_mass(&self, body: usize) -> Option<f32> {
        let slot = self.slots.get(body.checked_sub(1)?)?.as_ref()?;
        (slot.collider.motion == ColliderMotion::Dynamic)
            .then_some(slot.mass)
            .flatten()
    }

    /// How often body `body` (a body index) was placed by [`Self::set_motion`] (0 for the walls
    /// and unknown bodies): a new placement carries the engine's new velocity.
    pub fn placements(&self, body: usize) -> u64 {
        body.checked_sub(1)
            .and_then(|k| self.slots.get(k))
            .and_then(Option::as_ref)
            .map_or(0, |b| b.placements)
    }

    /// Whether a particle may be spawned at `x`: at least 0.45 Δx outside every collider (closer
    /// than half a spacing to a solid, it would start inside the solid's boundary layer).
    pub fn admits_spawn(&self, x: Vec3) -> bool {
        let clearance = 0.45 * self.spacing;
        self.colliders()
            .all(|(_, c)| c.signed_distance(x) >= clearance)
    }

    /// The colliders, in slot order.
    pub fn collider_list(&self) -> Vec<Collider> {
        self.colliders().map(|(_, c)| c.clone()).collect()
    }

    /// Number of sorted samples (inside the grid's reach).
    pub fn len(&self) -> usize {
        self.position.len()
    }

    /// Whether there are no samples.
    pub fn is_empty(&self) -> bool {
        self.position.is_empty()
    }

    /// Whether this boundary was built for `container` and the spacing, h and particle volume of
    /// `params`.
    pub fn matches(&self, container: &BoxContainer, params: &SphParams) -> bool {
        self.container == *container
            && self.spacing == params.spacing()
            && self.kernels.h == params.smoothing_radius
            && self.volume_scale == Self::volume_scale(params)
    }

    /// Rebuilds the walls and resamples every collider for a new container or new parameters,
    /// keeping every collider's handle.
    pub fn rebuild_for(
        &mut self,
        container: &BoxContainer,
        params: &SphParams,
    ) -> Result<(), ParamError> {
        let mut fresh = Self::new(container, params, Slip::Free)?;
        fresh.set_walls(self.wall_slip());
        for body in self.slots.iter_mut().flatten() {
            let samples = sample_shape(&body.collider.shape, fresh.spacing);
            let volume = fresh.volumes(&samples);
            body.samples = SampleSet {
                local: samples.position,
                volume,
            };
        }
        fresh.slots = std::mem::take(&mut self.slots);
        fresh.sorted = false;
        *self = fresh;
        Ok(())
    }

    /// Places every body's samples by its pose, drops those more than h outside the container
    /// (no particle can reach them) and a collider's behind the sampled walls (the walls' own
    /// samples stand there), and sorts the rest by cell. Does nothing when nothing moved
    /// since the last sort; returns whether it sorted.
    pub fn sort(&mut self) -> bool {
        if self.sorted {
            return false;
        }
        let (mut position, mut volume, mut velocity, mut body) =
            (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        let reach = self.kernels.h;
        let container = self.container;
        let (lo, hi) = (container.min(), container.max());
        // A collider's samples behind a sampled wall or under the floor stand where the wall's
        // own samples stand: together they would press the water with twice the wall and kick
        // it at the first step (tests/boundary.rs). They are left out, so a
        // collider through a wall meets the water as one that ends at it. Above the walls' top
        // nothing else is sampled, and a collider's samples there stay.
        let walls_sampled = self.walls.is_some();
        let behind_a_wall = |x: Vec3| {
            walls_sampled
                && x.y <= hi.y
                && (x.x < lo.x || x.x > hi.x || x.z < lo.z || x.z > hi.z || x.y < lo.y)
        };
        let mut place = |set: &SampleSet, index: u32, to_world: &dyn Fn(Vec3) -> (Vec3, Vec3)| {
            for (&local, &v) in set.local.iter().zip(&set.volume) {
                let (x, u) = to_world(local);
                let doubled = index != WALLS_BODY && behind_a_wall(x);
                if container.contains(x, reach) && !doubled {
                    position.push(x);
                    volume.push(v);
                    velocity.push(u);
                    body.push(index);
                }
            }
        };
        self.friction.clear();
        self.dynamic.clear();
        self.origin.clear();
        self.friction
            .push(self.walls.as_ref().map_or(0.0, |(_, slip)| slip.friction()));
        self.dynamic.push(false);
        self.origin.push(Vec3::ZERO);
        if let Some((set, _)) = &self.walls {
            place(set, WALLS_BODY, &|x| (x, Vec3::ZERO));
        }
        for (k, slot) in self.slots.iter().enumerate() {
            self.friction
                .push(slot.as_ref().map_or(0.0, |b| b.collider.slip.friction()));
            let dynamic = slot.as_ref().is_some_and(|b| {
                b.collider.motion == crate::boundary::collider::ColliderMotion::Dynamic
            });
            self.dynamic.push(dynamic);
            self.origin.push(
                slot.as_ref()
                    .map_or(Vec3::ZERO, |b| b.collider.pose.translation),
            );
            if let Some(b) = slot {
                let c = &b.collider;
                place(&b.samples, k as u32 + 1, &|local| {
                    let x = c.pose.to_world(local);
                    (x, c.point_velocity(x))
                });
            }
        }
        let order = self.grid.sort(&position);
        self.position = order.iter().map(|&k| position[k as usize]).collect();
        self.volume = order.iter().map(|&k| volume[k as usize]).collect();
        self.velocity = order.iter().map(|&k| velocity[k as usize]).collect();
        self.body = order.iter().map(|&k| body[k as usize]).collect();
        self.sorted = true;
        true
    }

    /// Body `body`'s pose origin (the torque's reference point) as the colliders stand now:
    /// [`Boundary::origin`] is placed with the samples at the sort, and a pass before it (PBF's
    /// prediction) reads the pose from here.
    pub fn body_origin(&self, body: u32) -> Vec3 {
        match body.checked_sub(1) {
            Some(k) => self
                .slots
                .get(k as usize)
                .and_then(|s| s.as_ref())
                .map_or(Vec3::ZERO, |b| b.collider.pose.translation),
            None => Vec3::ZERO,
        }
    }

    /// Number of bodies (walls + collider slots), the length of a per-body force table.
    pub fn body_count(&self) -> usize {
        1 + self.slots.len()
    }

    /// The largest speed of any sample [m/s] (for the time-step rule).
    pub fn max_speed(&self) -> f32 {
        self.velocity.iter().map(|v| v.length()).fold(0.0, f32::max)
    }
}
