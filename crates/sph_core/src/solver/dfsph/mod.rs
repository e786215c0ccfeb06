//! `CpuSolver`'s DFSPH step (`DfsphStep`), the simulation loop of Bender & Koschier 2017 over the
//! stages of [`crate::solver::dfsph::bender2017`]:
//!
//! 1. non-pressure accelerations a_np (viscosity, surface tension, gravity, boundary friction)
//!    at the step's start, where densities, factors and lists are already known;
//! 2. dt from the flow speed ([`dfsph_time_step`]);
//! 3. predicted velocities v* = v + dt (a_np + a_rise), with the boundary's hydrostatic rise
//!    ([`crate::solver::dfsph::bender2017::BoundaryRise`]);
//! 4. the constant-density solve corrects v* until the predicted density error is small;
//! 5. the solids' speculative contact bounds v* so that the drift ends a tenth of a spacing from
//!    every surface ([`crate::boundary::speculative_contact::stop_before_drift`]), x += dt v*, the guard;
//! 6. neighbour sort, densities, lists and factors at the new positions;
//! 7. the divergence-free solve corrects v until Dρ/Dt is small.
//!
//! Each solve warm-starts from its stiffness of the previous step where the fluid is compressed
//! and runs iterations of two passes (apply the stiffness, predict the error), what the GPU's
//! two dispatches per iteration will be.

pub mod bender2017;
pub mod settings;
pub mod stages;

use super::state::{timed, ParticleData, SolverParts};
use crate::boundary::free_bodies::{FreeBodies, GivingSolve};
use crate::boundary::guard::Corrections;
use crate::boundary::guard::Guard;
use crate::boundary::samples::BodyForceSum;
use crate::boundary::samples::Boundary;
use crate::boundary::speculative_contact::{stop_before_drift, SURFACE_MARGIN};
use crate::forces::{compute_accelerations, ForceInputs};
use crate::frame_budget::StepDt;
use crate::kernel::CubicSpline;
use crate::neighbor::lists::{ListSource, NeighborLists};
use crate::params::SphParams;
use crate::solver::dfsph::bender2017::{
    apply_stiffness, boundary_reactions, compute_factors, density_source, dfsph_time_step,
    divergence_source, rest_lattice_factor, stiffness_from_source, BoundaryRise, OverRelaxation,
    ParticleFactor, TopRowStiffness, DENSITY_WARM_START, DIVERGENCE_WARM_START,
};
use crate::solver::dfsph::stages::DfsphStage;
use crate::solvers::SolverStats;
use crate::stability::largest_magnitude;
use crate::stage::{CpuStage, StageContext};
use crate::surface_tension_akinci2013::compute_normals;
use glam::Vec3;
use rayon::prelude::*;

/// The stages of one DFSPH step for `params`, each once in order: the sort, the lists, the
/// densities and factors, the normals with surface tension, the non-pressure forces, v*, the
/// solves' two passes and their reactions (the solves repeat them; the move and the second
/// neighbourhood run the first stages again).
pub fn step_stages(params: &SphParams) -> Vec<CpuStage> {
    let mut stages = vec![
        CpuStage::Sort,
        CpuStage::NeighborLists,
        CpuStage::Dfsph(DfsphStage::Factors),
    ];
    if params.has_surface_tension() {
        stages.push(CpuStage::Normals);
    }
    stages.extend([
        CpuStage::Forces,
        CpuStage::Dfsph(DfsphStage::Predict),
        CpuStage::Dfsph(DfsphStage::Apply),
        CpuStage::Dfsph(DfsphStage::Source),
        CpuStage::Dfsph(DfsphStage::Reactions),
    ]);
    stages
}

/// DFSPH's per-step scratch arrays.
#[derive(Clone, Debug)]
pub(super) struct DfsphScratch {
    lists: NeighborLists,
    factors: Vec<ParticleFactor>,
    source: Vec<f32>,
    stiffness: Vec<f32>,
    /// The top row's targets of the iteration ([`TopRowStiffness::targets`]).
    top_row: Vec<f32>,
    /// The kernel of DFSPH's densities and gradients.
    kernel: CubicSpline,
    /// D_i of the rest lattice for `kernel`.
    rest_factor: f32,
    /// The dynamic bodies' give across the frame's steps ([`crate::boundary::free_bodies`]).
    pub(super) free_bodies: FreeBodies,
}

impl Default for DfsphScratch {
    fn default() -> Self {
        Self {
            lists: NeighborLists::default(),
            factors: Vec::new(),
            source: Vec::new(),
            stiffness: Vec::new(),
            top_row: Vec::new(),
            kernel: CubicSpline::new(1.0, 0.5),
            rest_factor: 0.0,
            free_bodies: FreeBodies::default(),
        }
    }
}

/// Which of the two solves.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Solve {
    Density,
    Divergence,
}

/// What one solve did.
struct SolveOutcome {
    iterations: u32,
    error: f32,
    reactions: Vec<BodyForceSum>,
}

/// The time step DFSPH's rule gives now: [`dfsph_time_step`] of the largest speed the
/// non-pressure accelerations would give over the largest step, max |v + a_np dt_max|, and of
/// the boundary's samples.
pub(super) fn next_time_step(params: &SphParams, p: &ParticleData, boundary: &Boundary) -> f32 {
    let horizon = params.time_step;
    let fluid = largest_magnitude(p.len(), |i| p.velocity[i] + p.acceleration[i] * horizon);
    dfsph_time_step(params, fluid.max(boundary.max_speed()))
}

/// What the DFSPH step borrows from the solver.
pub(super) struct DfsphStep<'a> {
    pub parts: SolverParts<'a>,
    pub scratch: &'a mut DfsphScratch,
}

/// What one DFSPH step did.
pub(super) struct DfsphOutcome {
    pub dt: f32,
    pub corrections: Corrections,
    /// The fluid's force on each boundary body.
    pub forces: Vec<BodyForceSum>,
    pub stats: SolverStats,
}

impl DfsphStep<'_> {
    /// Sort, densities, neighbour lists and factors at the current positions.
    fn neighborhood(&mut self, ctx: &StageContext) {
        // A few hundred kernel evaluations: cheaper to redo each step than to track h and m.
        let kernel = CubicSpline::new(
            self.parts.params.smoothing_radius,
            self.parts.params.spacing(),
        );
        self.scratch.kernel = kernel;
        self.scratch.rest_factor = rest_lattice_factor(self.parts.params);
        self.parts.sort_by_cell();
        let (neighbors, p, t) = (
            &*self.parts.neighbors,
            &mut *self.parts.particles,
            &mut *self.parts.timings,
        );
        let boundary = &*self.parts.boundary;
        let s = &mut *self.scratch;
        timed(&mut t.density, || {
            let n = p.len();
            p.density.resize(n, 0.0);
            s.factors.resize(n, ParticleFactor::default());
            s.source.resize(n, 0.0);
            s.stiffness.resize(n, 0.0);
            let kernel = s.kernel;
            s.lists.rebuild_cubic_spline(
                ListSource {
                    neighbors,
                    positions: &p.position,
                    boundary: Some(boundary),
                    mass: ctx.mass,
                    rest_density: ctx.rest_density,
                },
                &kernel,
                &mut p.density,
            );
            p.stiffness_density.resize(n, 0.0);
            p.stiffness_divergence.resize(n, 0.0);
            compute_factors(
                &s.lists,
                Some(boundary),
                Some((&p.stiffness_density, &p.stiffness_divergence)),
                ctx.rest_density,
                s.rest_factor,
                &mut s.factors,
            );
        });
    }

    /// One of the two solves on the current velocities (Bender & Koschier 2017: the
    /// constant-density solve on v*, the divergence-free solve on v). `base`: the step's forces
    /// on each body before the solve, for the bodies that give way ([`crate::boundary::free_bodies`]).
    fn solve(&mut self, solve: Solve, dt: f32, base: &[BodyForceSum]) -> SolveOutcome {
        let start = std::time::Instant::now();
        let settings = self.parts.params.dfsph;
        let rho0 = self.parts.params.rest_density;
        let mass = self.parts.params.particle_mass;
        let top_row_cap =
            self.parts.params.gravity.length() * self.parts.params.spacing() / (2.0 * rho0);
        let (p, s) = (&mut *self.parts.particles, &mut *self.scratch);
        let mut giving = GivingSolve::new(&s.free_bodies, self.parts.boundary, &s.lists, base);
        let n = p.len();
        let (total, scale, min, max, eta) = match solve {
            Solve::Density => (
                &mut p.stiffness_density,
                1.0 / (dt * dt),
                settings.min_density_iterations,
                settings.max_density_iterations,
                settings.max_density_error,
            ),
            Solve::Divergence => (
                &mut p.stiffness_divergence,
                1.0 / dt,
                settings.min_divergence_iterations,
                settings.max_divergence_iterations,
                settings.max_divergence_error,
            ),
        };
        let mean_error = |s: &mut DfsphScratch, v: &[Vec3], density: &[f32]| {
            let sum = match solve {
                Solve::Density => {
                    density_source(&s.lists, v, density, &s.factors, rho0, dt, &mut s.source)
                }
                Solve::Divergence => divergence_source(&s.lists, v, &s.factors, &mut s.source),
            };
            (sum / (n.max(1) as f64 * rho0 as f64)) as f32
        };
        if settings.warm_start {
            // Only where the fluid is compressed now: elsewhere last step's pressure is gone.
            mean_error(s, &p.velocity, &p.density);
            let fraction = match solve {
                Solve::Density => DENSITY_WARM_START,
                Solve::Divergence => DIVERGENCE_WARM_START,
            };
            s.stiffness
                .par_iter_mut()
                .zip(total.par_iter_mut())
                .zip(s.source.par_iter())
                .for_each(|((k, sum), &source)| {
                    *k = if source > 0.0 { *sum * fraction } else { 0.0 };
                    *sum = *k;
                });
            apply_stiffness(&s.lists, &s.stiffness, &s.factors, dt, &mut p.velocity);
        } else {
            total.fill(0.0);
        }
        if let Some(g) = &mut giving {
            g.update(total, mass, dt, &mut s.factors);
        }
        let mut error = mean_error(s, &p.velocity, &p.density);
        let mut iterations = 0;
        while (iterations < min || error > eta) && iterations < max {
            // Both solves' iterations after their first are over-relaxed, each by its ω.
            let omega = match solve {
                Solve::Density => settings.density_over_relaxation,
                Solve::Divergence => settings.divergence_over_relaxation,
            };
            let relaxation = (iterations > 0).then_some(OverRelaxation {
                omega,
                converged_source: eta * rho0,
            });
            // The top row's stiffness (the constant-density solve's; the divergence-free solve
            // leaves the free surface alone, INTERIOR_NEIGHBORS).
            let top_row = matches!(solve, Solve::Density).then(|| {
                TopRowStiffness {
                    source: &s.source,
                    density: &p.density,
                    rest_density: rho0,
                    cap: top_row_cap,
                }
                .targets(&s.lists, total, &mut s.top_row);
                &s.top_row[..]
            });
            stiffness_from_source(
                &s.source,
                &s.factors,
                scale,
                relaxation,
                top_row,
                &mut s.stiffness,
                total,
            );
            apply_stiffness(&s.lists, &s.stiffness, &s.factors, dt, &mut p.velocity);
            if let Some(g) = &mut giving {
                g.update(total, mass, dt, &mut s.factors);
            }
            error = mean_error(s, &p.velocity, &p.density);
            iterations += 1;
        }
        if let Some(g) = giving {
            g.restore(&mut s.factors);
        }
        let reactions = boundary_reactions(&s.lists, self.parts.boundary, &s.factors, total, mass);
        self.parts.timings.pressure_solve += start.elapsed();
        SolveOutcome {
            iterations,
            error,
            reactions,
        }
    }

    /// One DFSPH step at the dt `step_dt` makes of the rule's. `stale`: the densities, lists and
    /// factors do not hold for the current positions (spawns, parameter changes).
    pub fn advance(&mut self, step_dt: StepDt, stale: bool, guard: &Guard) -> DfsphOutcome {
        let ctx = StageContext::new(self.parts.params);
        let boundary_moved = self.parts.boundary.sort();
        if stale || boundary_moved {
            self.neighborhood(&ctx);
        }
        self.scratch.free_bodies.sync(self.parts.boundary);
        // 1. Non-pressure accelerations at the step's start.
        let (neighbors, p, t) = (
            &*self.parts.neighbors,
            &mut *self.parts.particles,
            &mut *self.parts.timings,
        );
        if self.parts.params.has_surface_tension() {
            timed(&mut t.normals, || {
                compute_normals(&ctx, neighbors, &p.position, &p.density, &mut p.normal)
            });
        }
        let input = ForceInputs {
            position: &p.position,
            velocity: &p.velocity,
            contact_velocity: &p.velocity,
            density: &p.density,
            pressure: &p.pressure,
            normal: &p.normal,
            boundary: Some(&*self.parts.boundary),
            with_pressure: false,
        };
        let mut forces = timed(&mut t.forces, || {
            compute_accelerations(&ctx, neighbors, &input, &mut p.acceleration)
        });
        // 2.-3. The time step and the predicted velocities.
        let dt = step_dt.of(next_time_step(
            self.parts.params,
            self.parts.particles,
            self.parts.boundary,
        ));
        let (p, s) = (&mut *self.parts.particles, &*self.scratch);
        let rise = BoundaryRise {
            positions: &p.position,
            factors: &s.factors,
            gravity: ctx.gravity,
            rest_density: ctx.rest_density,
        };
        let rise_reactions = rise.reactions(
            &s.lists,
            self.parts.boundary,
            self.parts.params.particle_mass,
        );
        rise.predict(
            &s.lists,
            self.parts.boundary,
            &p.acceleration,
            dt,
            &mut p.velocity,
        );
        forces
            .iter_mut()
            .zip(&rise_reactions)
            .for_each(|(sum, r)| sum.merge(r));
        // 4. Constant density.
        let density = self.solve(Solve::Density, dt, &forces);
        // 5. Move, no closer than the margin to a solid (the speculative contact).
        let p = &mut *self.parts.particles;
        let contact = timed(&mut self.parts.timings.integrate, || {
            stop_before_drift(
                self.parts.boundary,
                &p.position,
                &mut p.velocity,
                dt,
                SURFACE_MARGIN * ctx.contact.radius,
                ctx.mass,
            )
        });
        for reactions in [&contact, &density.reactions] {
            forces
                .iter_mut()
                .zip(reactions)
                .for_each(|(sum, r)| sum.merge(r));
        }
        let corrections: Corrections = timed(&mut self.parts.timings.integrate, || {
            p.position
                .par_iter_mut()
                .zip(p.velocity.par_iter_mut())
                .map(|(x, v)| {
                    *x += *v * dt;
                    guard.apply(x, v)
                })
                .sum()
        });
        // 6.-7. The new neighbourhood, divergence-free velocities.
        self.neighborhood(&ctx);
        let divergence = self.solve(Solve::Divergence, dt, &forces);
        let p = &mut *self.parts.particles;
        p.pressure
            .par_iter_mut()
            .enumerate()
            .for_each(|(i, pressure)| {
                let rho = p.density[i];
                *pressure = (p.stiffness_density[i] + p.stiffness_divergence[i]) * rho * rho;
            });
        forces
            .iter_mut()
            .zip(&divergence.reactions)
            .for_each(|(sum, r)| sum.merge(r));
        self.scratch
            .free_bodies
            .end_step(self.parts.boundary, &forces, dt);
        DfsphOutcome {
            dt,
            corrections,
            forces,
            stats: SolverStats {
                density_iterations: density.iterations,
                divergence_iterations: divergence.iterations,
                density_error: density.error,
                divergence_error: divergence.error,
            },
        }
    }
}
