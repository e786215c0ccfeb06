//! A dynamic body's velocity as DFSPH's solves see it within a frame: the body gives way.
//!
//! A physics engine moves a dynamic collider once a frame, with the water's mean force of that
//! frame, while the water takes several steps against the pose and the velocity the engine left.
//! To the solves the body is then kinematic: a heavy box settling on a layer of water keeps its
//! frame-start speed for the whole frame, the constant-density solve pushes as hard as it takes to
//! move the water out of its way at that speed, and the frame's mean force throws the box back;
//! the next frame the same happens the other way. Measured (`tests/free_bodies.rs`, a box of
//! 1,500 kg/m³ moved once per 1/60 s frame onto the tank's floor): without its mass the resting
//! box rattles at up to 0.25 m/s, the water's force off its 25 N weight by up to 52 N; with it,
//! 0.072 m/s and within 10.2 N of the weight (0.019 m/s and 3.1 N before DFSPH's floor mirrored
//! the stiffness: the box now trembles on the last layer of water, pinched by the floor).
//!
//! With the body's mass M known ([`crate::Boundary::set_mass`]), its samples move in the solves
//! with the engine's velocity plus
//!
//!   Δv_B = Σ_{earlier steps of the frame} dt (F_B − F_ref)/M + dt (F_B^now − F_ref)/M,
//!
//! F_B the water's force on the body in a step (F_B^now: the forces of the current step so far,
//! the current solve's pressure updated at every iteration) and F_ref the frame-mean force the
//! engine last received, with which (and gravity and its contacts) it already moved the body.
//! An iteration that pushes harder than the reference slows the body's approach in the next
//! iteration's sources, so the water's impulse over a frame is what stops the body, not what
//! moves water out of the way of an unstoppable one. The pose stays the engine's, and only the
//! linear velocity gives way (a coupled solve for the body's velocity, as Gissler et al. 2019
//! "Interlinked SPH pressure solvers for strong fluid-rigid coupling" do for the full rigid
//! motion, here by a fixed-point update between the Jacobi sweeps).
//!
//! The reaction of a pair is m κ_i g_ib (`crate::solver::dfsph::bender2017::boundary_reactions`), so the
//! solve's force on body B is Σ_i m κ_i G_iB with G_iB = Σ_{b ∈ B} g_ib, and Δv_B enters particle
//! i's rate of density change through the samples' flux Σ_b v_b·g_ib as Δv_B·G_iB.

use crate::boundary::samples::{BodyForceSum, Boundary};
use crate::neighbor::lists::NeighborLists;
use crate::solver::dfsph::bender2017::ParticleFactor;
use glam::Vec3;

/// One body's state across the frame's steps.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct FreeBody {
    /// The frame-mean force the engine last received [N] (`None` before the first).
    reference: Option<Vec3>,
    /// Σ dt (F_B − F_ref)/M over the steps since the engine last placed the body [m/s].
    gained: Vec3,
    /// [`Boundary::placements`] when `gained` was last reset.
    placements: u64,
}

/// The dynamic bodies' give across a frame, by body index (as [`Boundary::body`]).
#[derive(Clone, Debug, Default)]
pub struct FreeBodies {
    bodies: Vec<FreeBody>,
}

impl FreeBodies {
    /// Records the frame-mean force the engine receives for each body (body index, force). The
    /// frame's gain ends with it: the engine moves the body with that force, and its next
    /// velocity has the gain in it.
    pub fn set_references(&mut self, forces: impl IntoIterator<Item = (usize, Vec3)>) {
        for (body, force) in forces {
            if self.bodies.len() <= body {
                self.bodies.resize(body + 1, FreeBody::default());
            }
            self.bodies[body].reference = Some(force);
            self.bodies[body].gained = Vec3::ZERO;
        }
    }

    /// Follows the boundary: one entry per body, and no gain for a body the engine placed since
    /// (its new velocity has the gain in it), also when it was placed without taking the forces.
    pub fn sync(&mut self, boundary: &Boundary) {
        self.bodies
            .resize(boundary.body_count(), FreeBody::default());
        for (k, body) in self.bodies.iter_mut().enumerate() {
            let placements = boundary.placements(k);
            if placements != body.placements {
                body.placements = placements;
                body.gained = Vec3::ZERO;
            }
        }
    }

    /// M and F_ref of body `k` when it gives way: a dynamic collider with a mass, whose engine
    /// has received a force.
    fn giving(&self, boundary: &Boundary, k: usize) -> Option<(f32, Vec3)> {
        let reference = self.bodies.get(k)?.reference?;
        Some((boundary.free_mass(k)?, reference))
    }

    /// After a step of length `dt` whose force on each body was `forces`: the gain grows by
    /// dt (F_B − F_ref)/M.
    pub fn end_step(&mut self, boundary: &Boundary, forces: &[BodyForceSum], dt: f32) {
        for (k, f) in forces.iter().enumerate() {
            if let Some((mass, reference)) = self.giving(boundary, k) {
                self.bodies[k].gained += dt * (f.force.as_vec3() - reference) / mass;
            }
        }
    }
}

/// One body as a solve sees it.
#[derive(Clone, Copy, Debug)]
struct SolveBody {
    mass: f32,
    /// The gain of the frame's earlier steps [m/s].
    gained: Vec3,
    /// The step's forces before this solve, less the reference [N].
    base: Vec3,
    /// The velocity added to the samples' flux so far [m/s].
    applied: Vec3,
}

/// The particles next to giving bodies during one solve, and what the solve added to their
/// factors' boundary flux.
#[derive(Clone, Debug)]
pub struct GivingSolve {
    /// (particle, body index, G_iB).
    touching: Vec<(u32, u32, Vec3)>,
    /// By body index; `None` for bodies that do not give way.
    bodies: Vec<Option<SolveBody>>,
}

impl GivingSolve {
    /// The solve's view of the giving bodies; `base` holds the step's forces on each body before
    /// the solve (non-pressure, and for the divergence-free solve the constant-density solve's
    /// and the contact's). `None` when no body gives way.
    pub fn new(
        free: &FreeBodies,
        boundary: &Boundary,
        lists: &NeighborLists,
        base: &[BodyForceSum],
    ) -> Option<Self> {
        let bodies: Vec<Option<SolveBody>> = (0..boundary.body_count())
            .map(|k| {
                let (mass, reference) = free.giving(boundary, k)?;
                let before = base.get(k).map_or(Vec3::ZERO, |f| f.force.as_vec3());
                Some(SolveBody {
                    mass,
                    gained: free.bodies[k].gained,
                    base: before - reference,
                    applied: Vec3::ZERO,
                })
            })
            .collect();
        if bodies.iter().all(Option::is_none) {
            return None;
        }
        let touching = lists.fold(
            Vec::new,
            |mut out, i, pairs| {
                let start = out.len();
                for pair in pairs.boundary {
                    let k = boundary.body[pair.index as usize];
                    if bodies[k as usize].is_none() {
                        continue;
                    }
                    match out[start..].iter_mut().find(|(_, body, _)| *body == k) {
                        Some((_, _, g)) => *g += pair.grad,
                        None => out.push((i as u32, k, pair.grad)),
                    }
                }
                out
            },
            |mut a, b| {
                a.extend(b);
                a
            },
        );
        Some(Self { touching, bodies })
    }

    /// Moves the giving bodies' samples, in the factors' boundary flux, to the velocity the
    /// solve's stiffness `total` gives them: Δv_B = gained + dt (base + Σ_i m κ_i G_iB)/M.
    pub fn update(&mut self, total: &[f32], mass: f32, dt: f32, factors: &mut [ParticleFactor]) {
        let mut force = vec![Vec3::ZERO; self.bodies.len()];
        for &(i, k, g) in &self.touching {
            force[k as usize] += mass * total[i as usize] * g;
        }
        let mut change = vec![Vec3::ZERO; self.bodies.len()];
        for (k, body) in self.bodies.iter_mut().enumerate() {
            if let Some(b) = body {
                let velocity = b.gained + dt * (b.base + force[k]) / b.mass;
                change[k] = velocity - b.applied;
                b.applied = velocity;
            }
        }
        for &(i, k, g) in &self.touching {
            factors[i as usize].boundary_flux += change[k as usize].dot(g);
        }
    }

    /// Takes the added velocity back out of the factors (they outlive the solve).
    pub fn restore(self, factors: &mut [ParticleFactor]) {
        for &(i, k, g) in &self.touching {
            if let Some(b) = self.bodies[k as usize] {
                factors[i as usize].boundary_flux -= b.applied.dot(g);
            }
        }
    }
}
