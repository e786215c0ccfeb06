//! PBF's contact with the solids inside its position iterations (Macklin et al. 2014, "Unified
//! particle physics for real-time applications", §5 and §6: particle-shape contacts are
//! constraints projected with the fluid's, not an afterthought). The boundary samples push
//! through the kernel, so a particle aimed between them, or squeezed against a wall by its
//! neighbours' corrections, could still end inside a solid and be caught by the last-resort guard.
//! Here every Jacobi iteration ends by projecting each particle that came closer than the
//! speculative contact's margin to the exact surface of a collider or of the box's sampled walls
//! back onto that margin: φ(x) ≥ margin, x += n (margin - φ); the box's faces all at once (a
//! clamp), then the colliders one after another. The projection joins the iteration's
//! move u_k, so the later iterations' over-relaxation carries it on as it carries the
//! corrections, and in all it moves the particle by c δ with c = `carried_weight` (in `macklin2013`). A move of
//! the step changes the particle's momentum by m c δ / dt: the surface's body feels
//! -m c δ / dt² at the particle (Akinci 2012's two-way coupling). Together with the speculative
//! contact before the prediction ([`crate::boundary::speculative_contact::stop_before_drift`]),
//! which keeps the prediction itself out of the solids, no particle reaches the guard
//! (docs/pbf.md).
//! `macklin2013::apply_corrections` projects each particle right after its move, in the same
//! pass.
//! WGSL twin: `contact_projection` in shaders/speculative_contact.wgsl, called by pbf_correct.wgsl.

use crate::boundary::samples::{Boundary, WALLS_BODY};
use glam::Vec3;

/// Projects a particle at `x` out of every surface nearer than `margin`, and gives each
/// projection's move to `moved(body, δ, x after it)`.
#[inline]
pub fn project_out_of_solids(
    boundary: &Boundary,
    x: &mut Vec3,
    margin: f32,
    mut moved: impl FnMut(u32, Vec3, Vec3),
) {
    if let Some(walls) = boundary.sampled_walls() {
        // All six faces at once: their projections are independent for a box wider than two
        // margins.
        let inside = x.clamp(walls.min() + margin, walls.max() - margin);
        if inside != *x {
            let delta = inside - *x;
            *x = inside;
            moved(WALLS_BODY, delta, *x);
        }
    }
    for (id, c) in boundary.colliders() {
        if let Some((phi, n)) = c.surface_within(*x, margin) {
            if phi < margin {
                let delta = n * (margin - phi);
                *x += delta;
                moved(id.0 + 1, delta, *x);
            }
        }
    }
}
