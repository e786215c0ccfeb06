//! `CpuSolver`'s PBF step (`PbfStep`), the simulation loop of Macklin & Müller 2013
//! (Algorithm 1) over the passes of [`crate::solver::pbf::macklin2013`]:
//!
//! 1. v += dt g; the solids' speculative contact bounds v so that the prediction ends a tenth
//!    of a spacing from every surface ([`stop_before_drift`]); predicted positions
//!    x* = x + dt v; the guard;
//! 2. neighbour sort and lists on the predicted positions;
//! 3. `iterations` times: λ_i, the boundary samples' λ_b ([`wall_lambda`]), then the
//!    corrections Δp_i, x* += Δp (over-relaxed after the first), then the contact with the
//!    solids ([`solid_contact`]);
//! 4. v = (x* - x) / dt, the guard, XSPH viscosity with the no-slip bodies' share of it
//!    ([`xsph_vorticity::wall_friction`]); x = x*; the pressure equivalent to the step's λ
//!    ([`macklin2013::equivalent_pressure`]);
//! 5. optionally, vorticity confinement.
//!
//! Viscosity and surface tension of the WCSPH forces pass are not applied (XSPH stands for the
//! viscosity, at no-slip walls too); the boundary's reactions are summed for the colliders every
//! iteration, and the walls' friction once a step.

pub mod macklin2013;
pub mod settings;
pub mod solid_contact;
pub mod stages;
pub mod wall_lambda;
pub mod xsph_vorticity;

use super::state::{timed, ParticleData, SolverParts};
use crate::boundary::guard::{Corrections, Guard};
use crate::boundary::samples::{BodyForceSum, Boundary};
use crate::boundary::speculative_contact::{stop_before_drift, SURFACE_MARGIN};
use crate::frame_budget::StepDt;
use crate::neighbor::lists::IndexLists;
use crate::params::SphParams;
use crate::solver::pbf::macklin2013::{
    apply_corrections, compute_corrections, compute_lambdas, constraint_violation,
    correction_weight, equivalent_pressure, Constraint, Correction, CorrectionStep, PbfContext,
};
use crate::solver::pbf::stages::PbfStage;
use crate::solver::pbf::wall_lambda::{extrapolate_wall_lambda, SampleNeighbors};
use crate::solver::pbf::xsph_vorticity::{confine_vorticity, vorticity, xsph_and_densities};
use crate::solvers::SolverStats;
use crate::stability::largest_magnitude;
use crate::stage::CpuStage;
use glam::Vec3;
use rayon::prelude::*;

/// The stages of one PBF step for `params`, each once in order: the sort of the predicted
/// positions, the neighbour lists and the samples' lists, λ, the samples' λ and the corrections
/// (repeated `pbf.iterations` times), the velocities, XSPH, and with vorticity confinement its
/// two stages. The time step and the prediction come before.
pub fn step_stages(params: &SphParams) -> Vec<CpuStage> {
    let mut stages = vec![
        CpuStage::Sort,
        CpuStage::NeighborLists,
        CpuStage::Pbf(PbfStage::WallLists),
        CpuStage::Pbf(PbfStage::Lambda),
        CpuStage::Pbf(PbfStage::WallLambda),
        CpuStage::Pbf(PbfStage::Correction),
        CpuStage::Pbf(PbfStage::Velocity),
        CpuStage::Pbf(PbfStage::Xsph),
    ];
    if params.pbf.vorticity_epsilon > 0.0 {
        stages.extend([
            CpuStage::Pbf(PbfStage::Vorticity),
            CpuStage::Pbf(PbfStage::Confinement),
        ]);
    }
    stages
}

/// PBF's per-step scratch arrays.
#[derive(Clone, Debug, Default)]
pub(super) struct PbfScratch {
    lists: IndexLists,
    constraint: Vec<Constraint>,
    /// Each particle's Σ_k c_k λ_k over the step's iterations ([`equivalent_pressure`]).
    lambda_sum: Vec<f32>,
    corrections: Vec<Correction>,
    /// Each particle's move in the last iteration (for the over-relaxation).
    moved: Vec<Vec3>,
    velocity: Vec<Vec3>,
    omega: Vec<Vec3>,
    confined: Vec<Vec3>,
    /// The fluid particles within reach of each boundary sample over the step.
    samples: SampleNeighbors,
    /// Each boundary sample's λ_b of the iteration ([`wall_lambda`]).
    wall_lambda: Vec<f32>,
}

/// PBF's time step: `params.time_step` when fixed; with `params.adaptive_time_step`,
/// min(time_step, λ h / v_max) with v_max = max |v + g dt_max| (a particle moves at most λ h in
/// a step, so the neighbours found on the predicted positions stay the ones that matter).
pub(super) fn next_time_step(params: &SphParams, p: &ParticleData, boundary: &Boundary) -> f32 {
    if !params.adaptive_time_step {
        return params.time_step;
    }
    let g = params.gravity * params.time_step;
    let fluid = largest_magnitude(p.len(), |i| p.velocity[i] + g).max(boundary.max_speed());
    let dt = if fluid > 0.0 {
        params
            .time_step
            .min(params.cfl_factor * params.smoothing_radius / fluid)
    } else {
        params.time_step
    };
    if dt.is_finite() && dt > 0.0 {
        dt
    } else {
        params.time_step
    }
}

/// What the PBF step borrows from the solver.
pub(super) struct PbfStep<'a> {
    pub parts: SolverParts<'a>,
    pub scratch: &'a mut PbfScratch,
}

/// What one PBF step did.
pub(super) struct PbfOutcome {
    pub dt: f32,
    pub corrections: Corrections,
    /// The fluid's force on each boundary body over the step.
    pub forces: Vec<BodyForceSum>,
    pub stats: SolverStats,
}

impl PbfStep<'_> {
    /// One PBF step at the dt `step_dt` makes of the rule's.
    pub fn advance(&mut self, step_dt: StepDt, guard: &Guard) -> PbfOutcome {
        let params = self.parts.params;
        let dt = step_dt.of(next_time_step(
            params,
            self.parts.particles,
            self.parts.boundary,
        ));
        let ctx = PbfContext::of(params).for_step(params.gravity.length(), dt);
        let (p, t, s) = (
            &mut *self.parts.particles,
            &mut *self.parts.timings,
            &mut *self.scratch,
        );
        let boundary = &*self.parts.boundary;
        let margin = SURFACE_MARGIN * params.spacing();
        // 1. Gravity, the contact and the predicted positions.
        let (mut corrections, mut forces) = timed(&mut t.integrate, || {
            p.position_previous.clone_from(&p.position);
            p.velocity
                .par_iter_mut()
                .for_each(|v| *v += params.gravity * dt);
            let (x, v) = (&p.position, &mut p.velocity);
            let forces = stop_before_drift(boundary, x, v, dt, margin, params.particle_mass);
            let corrections: Corrections = p
                .position
                .par_iter_mut()
                .zip(p.velocity.par_iter_mut())
                .map(|(x, v)| {
                    *x += *v * dt;
                    guard.apply(x, v)
                })
                .sum();
            (corrections, forces)
        });
        // 2. Neighbours of the predicted positions.
        self.parts.sort_by_cell();
        let (neighbors, boundary) = (&*self.parts.neighbors, &*self.parts.boundary);
        let (p, t) = (&mut *self.parts.particles, &mut *self.parts.timings);
        let n = p.len();
        s.constraint.resize(n, Constraint::default());
        s.lambda_sum.resize(n, 0.0);
        s.corrections.resize(n, Correction::default());
        s.velocity.resize(n, Vec3::ZERO);
        // The passes read only the neighbours' indices (they evaluate the kernel at the moving
        // positions).
        timed(&mut t.density, || {
            s.lists
                .rebuild_indices(neighbors, &p.position, Some(boundary));
            s.samples.rebuild(&s.lists, boundary.position.len());
        });
        // 3. The constraint's Jacobi iterations.
        let iterations = params.pbf.iterations;
        let mut error = 0.0;
        s.moved.clear();
        s.moved.resize(n, Vec3::ZERO);
        timed(&mut t.pressure_solve, || {
            for k in 0..iterations {
                compute_lambdas(
                    &ctx,
                    &s.lists,
                    &p.position,
                    Some(boundary),
                    &mut s.constraint,
                );
                let weight = correction_weight(&ctx, k, iterations);
                s.lambda_sum
                    .par_iter_mut()
                    .zip(s.constraint.par_iter())
                    .for_each(|(sum, c)| {
                        let before = if k == 0 { 0.0 } else { *sum };
                        *sum = before + weight * c.lambda;
                    });
                extrapolate_wall_lambda(
                    &ctx,
                    &s.samples,
                    &p.position,
                    boundary,
                    &s.constraint,
                    &mut s.wall_lambda,
                );
                compute_corrections(
                    &ctx,
                    &s.lists,
                    &p.position,
                    Some((boundary, &s.wall_lambda)),
                    &s.constraint,
                    &mut s.corrections,
                );
                let step = CorrectionStep {
                    iteration: k,
                    iterations,
                    dt,
                    boundary,
                    wall_lambda: &s.wall_lambda,
                    constraint: &s.constraint,
                    corrections: &s.corrections,
                    contact_margin: Some(margin),
                };
                let reactions =
                    apply_corrections(&ctx, &s.lists, step, &mut p.position, &mut s.moved);
                for (f, r) in forces.iter_mut().zip(&reactions) {
                    f.merge(r);
                }
            }
            // The last λ pass's violation (before its correction).
            error = constraint_violation(&ctx, &s.constraint) / n.max(1) as f64;
        });
        // 4. Velocities from the positions, the guard, XSPH.
        timed(&mut t.integrate, || {
            let inverse_dt = 1.0 / dt;
            corrections += p
                .position
                .par_iter_mut()
                .zip(p.velocity.par_iter_mut())
                .zip(p.position_previous.par_iter())
                .map(|((x, v), &x0)| {
                    *v = (*x - x0) * inverse_dt;
                    guard.apply(x, v)
                })
                .sum::<Corrections>();
        });
        timed(&mut t.forces, || {
            // The densities of the last λ pass (before its correction) weigh XSPH.
            let friction = xsph_and_densities(
                &ctx,
                &s.lists,
                &p.position,
                Some(boundary),
                &s.constraint,
                &p.velocity,
                &mut s.velocity,
                &mut p.density,
                dt,
            );
            for (f, r) in forces.iter_mut().zip(&friction) {
                f.merge(r);
            }
            std::mem::swap(&mut p.velocity, &mut s.velocity);
        });
        // s.velocity now holds the velocities before XSPH.
        if ctx.vorticity_epsilon > 0.0 {
            timed(&mut t.forces, || {
                s.omega.resize(n, Vec3::ZERO);
                s.confined.resize(n, Vec3::ZERO);
                vorticity(
                    &ctx,
                    &s.lists,
                    &p.position,
                    &p.density,
                    &p.velocity,
                    &mut s.omega,
                );
                confine_vorticity(
                    &ctx,
                    &s.lists,
                    &p.position,
                    &p.density,
                    &s.omega,
                    dt,
                    &p.velocity,
                    &mut s.confined,
                );
                std::mem::swap(&mut p.velocity, &mut s.confined);
            });
        }
        let inverse_dt = 1.0 / dt;
        p.pressure
            .par_iter_mut()
            .zip(s.lambda_sum.par_iter().zip(p.density.par_iter()))
            .for_each(|(pressure, (&sum, &rho))| {
                *pressure = equivalent_pressure(&ctx, sum, rho, dt)
            });
        // The step's mean acceleration, for the stability check and the diagnostics.
        p.acceleration
            .par_iter_mut()
            .zip(p.velocity.par_iter().zip(s.velocity.par_iter()))
            .for_each(|(a, (&v, &v_before_xsph))| {
                *a = (v - v_before_xsph) * inverse_dt + params.gravity
            });
        PbfOutcome {
            dt,
            corrections,
            forces,
            stats: SolverStats {
                density_iterations: iterations,
                divergence_iterations: 0,
                density_error: error as f32,
                divergence_error: 0.0,
            },
        }
    }
}
