//! The solids' speculative contact: the next drift may bring a particle no closer than a margin
//! (a tenth of a spacing) to the exact surface of a collider or of the box's sampled walls. The
//! boundary samples' pressure and contact ([`crate::forces::boundary_acceleration_at`]) act
//! through the kernel, so their push varies along a surface: a particle aimed between the
//! samples meets the surface where the nearest one is 0.87 Δx away, and there the samples'
//! contact is several hundred times weaker than over a sample. A splash then reached the floor in
//! `sph-bench run --scenario obstacles` (docs/boundary.md). This contact reads the distance from
//! the surface itself (the signed distance φ and outward normal n the guard uses).
//!
//! For each surface within reach of the next drift, the velocity the drift starts from,
//! v' = v_c + κ (a + a_s) dt (v_c the contact velocity of [`crate::forces::ForceInputs`], a the
//! particle's other accelerations, a_s this contact's so far, κ the share of this evaluation's
//! acceleration the drift takes, [`NextDrift::kick`]), may approach the surface at most at
//! (φ - margin)/dt, plus the speed at which the solid comes on there (v_s its velocity):
//! v'·n - max(v_s·n, 0) ≥ -max(φ - margin, 0)/dt.
//! A collider keeps one pose through a step and takes the next one after it, so a solid that
//! comes on (v_s·n > 0) must push the particle ahead of its next pose, while one that moves away
//! makes no room during the step: with the approach measured relative to it, water rising under
//! a lifted gate (`sph-bench run --scenario gate --solver pbf`) followed the gate into its
//! bottom face and reached the guard. Where it would approach faster, a_s gains n Δv/(κ dt)
//! with Δv the excess. The contact only stops an approach (perfectly inelastic); it never
//! pushes a particle away, so a particle at rest at its lattice distance Δx/2 from a wall feels
//! nothing. The surfaces are taken one after another, so in a wedge the later one sees the
//! earlier one's stop. The reaction -m n Δv/(κ dt)
//! goes to the surface's body at the particle (Akinci 2012's two-way coupling). This is the
//! speculative contact of rigid-body engines (Catto, Box2D) applied to the particles; the guard
//! ([`crate::boundary::guard`]) still counts any particle that ends up inside. WCSPH applies it at the end
//! of each force evaluation ([`crate::forces::compute_accelerations`]), DFSPH to the velocity
//! its move takes ([`stop_before_drift`]), PBF to the velocity its prediction takes (the same
//! function, before the neighbour sort: [`Boundary::body_origin`] gives the torques' origins).

use crate::boundary::samples::{BodyForceSum, Boundary, WALLS_BODY};
use glam::Vec3;
use rayon::prelude::*;

/// The margin the next drift keeps from a solid's surface, in particle spacings. Well below the
/// rest lattice's Δx/2: the settled `sph-bench` tank never meets it. With a quarter spacing it
/// held the tank's floor-row particles that sit between the floor's samples (166,033 times in the
/// 1 s run), and the tank's largest speed over the last 40 % rose from 0.059 to 0.067 m/s.
pub const SURFACE_MARGIN: f32 = 0.1;

/// The drift that follows an evaluation, as the speculative contact sees it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NextDrift {
    /// Its time step [s].
    pub dt: f32,
    /// The share κ of this evaluation's acceleration its velocity takes: it starts from
    /// v_c + κ a dt ([`crate::stage::BoundaryContact::drift_kick`]).
    pub kick: f32,
    /// The distance it keeps from every surface [m].
    pub margin: f32,
}

/// The speculative contact's acceleration a_s of a particle at `x` (module docs): `v_contact`
/// the velocity the next drift starts from before this evaluation's acceleration, `a` the
/// particle's other accelerations, `drift` the drift that follows, `mass` the particle's mass.
/// With κ = `drift.kick`, the drift's velocity is v_c + κ (a + a_s) dt, and each stop adds
/// n Δv/(κ dt). `reaction(body, force, at)` receives the force on each surface's body. Zero for
/// a non-positive or non-finite dt or κ.
pub fn speculative_contact_at(
    boundary: &Boundary,
    x: Vec3,
    v_contact: Vec3,
    a: Vec3,
    drift: NextDrift,
    mass: f32,
    mut reaction: impl FnMut(u32, Vec3, Vec3),
) -> Vec3 {
    let NextDrift { dt, kick, margin } = drift;
    let step = kick * dt;
    if !(step.is_finite() && step > 0.0) {
        return Vec3::ZERO;
    }
    // A surface farther than this cannot be reached by the next drift (the contact only takes
    // speed away along a normal; twice the reach covers a wedge's second surface).
    let reach = margin + 2.0 * (v_contact + a * step).length() * dt;
    let mut extra = Vec3::ZERO;
    let mut stop = |phi: f32, n: Vec3, v_solid: Vec3, body: u32| {
        let v_next = v_contact + (a + extra) * step;
        let approach = v_next.dot(n) - v_solid.dot(n).max(0.0);
        let allowed = -(phi - margin).max(0.0) / dt;
        if approach < allowed {
            let stopping = n * ((allowed - approach) / step);
            extra += stopping;
            reaction(body, stopping * -mass, x);
        }
    };
    if let Some(walls) = boundary.sampled_walls() {
        let (lo, hi) = (walls.min(), walls.max());
        for axis in 0..3 {
            let n = Vec3::AXES[axis];
            let below = x[axis] - lo[axis];
            if below < reach {
                stop(below, n, Vec3::ZERO, WALLS_BODY);
            }
            let above = hi[axis] - x[axis];
            if above < reach {
                stop(above, -n, Vec3::ZERO, WALLS_BODY);
            }
        }
    }
    for (id, c) in boundary.colliders() {
        if let Some((phi, n)) = c.surface_within(x, reach) {
            stop(phi, n, c.point_velocity(x), id.0 + 1);
        }
    }
    extra
}

/// DFSPH's speculative contact, after the constant-density solve and before the drift
/// x += v dt: every particle's final velocity is bounded as in [`speculative_contact_at`] with no
/// other acceleration and κ = 1 (v += a_s dt). Returns each body's reaction (indexed like
/// [`Boundary::friction`]). DFSPH's solves answer for the boundary through the samples; without
/// this, water driven at a solid between its samples still crossed it (`sph-bench`'s Martin &
/// Moyce dam break with `--solver dfsph`: 333 guard corrections; `obstacles`: 10,931).
pub fn stop_before_drift(
    boundary: &Boundary,
    position: &[Vec3],
    velocity: &mut [Vec3],
    dt: f32,
    margin: f32,
    mass: f32,
) -> Vec<BodyForceSum> {
    let bodies = boundary.body_count();
    let drift = NextDrift {
        dt,
        kick: 1.0,
        margin,
    };
    velocity
        .par_iter_mut()
        .zip(position.par_iter())
        .fold(
            || vec![BodyForceSum::default(); bodies],
            |mut sums, (v, &x)| {
                let a_s =
                    speculative_contact_at(boundary, x, *v, Vec3::ZERO, drift, mass, |b, f, at| {
                        sums[b as usize].add(f, at, boundary.body_origin(b))
                    });
                *v += a_s * dt;
                sums
            },
        )
        .reduce(
            || vec![BodyForceSum::default(); bodies],
            |mut a, b| {
                a.iter_mut().zip(&b).for_each(|(a, b)| a.merge(b));
                a
            },
        )
}
