//! `CpuSolver`'s WCSPH step (`WcsphStep`): force evaluations at the stages of
//! [`step_stages`] (sort by cell, density and the equation of state's
//! pressure, the free surface's pressure, normals for surface tension, accelerations) around the
//! integrator's phases ([`crate::integrate`]):
//!
//! - symplectic Euler: evaluate, choose dt, v += dt a, x += dt v;
//! - the design's leapfrog: evaluate, choose dt, drift with a, evaluate at the drifted
//!   positions, kick with the mean of both accelerations;
//! - kick-drift-kick: (evaluate only when the last closing kick left no valid acceleration),
//!   choose dt, kick and drift, evaluate, kick.
//!
//! Each evaluation's force on the bodies is returned for the frame's sums.

pub mod stages;

use super::state::{timed, ParticleData, SolverParts};
use crate::boundary::guard::{Corrections, Guard};
use crate::boundary::samples::{BodyForceSum, Boundary};
use crate::density::compute_density_pressure;
use crate::forces::{compute_accelerations, ForceInputs};
use crate::frame_budget::StepDt;
use crate::free_surface_pressure::extrapolate_free_surface_pressure;
use crate::integrate;
use crate::params::{Integrator, SphParams};

use crate::solver::wcsph::stages::WcsphStage;
use crate::stability::{adaptive_time_step, StepExtremes};
use crate::stage::{CpuStage, StageContext};
use crate::surface_tension_akinci2013::compute_normals;

/// The stages of one WCSPH force evaluation for `params`, in order: sort, density, the free
/// surface's pressure, normals (with surface tension only), forces. The integrator places the
/// time step and its integration phases around the evaluations.
pub fn step_stages(params: &SphParams) -> Vec<CpuStage> {
    let mut stages = vec![
        CpuStage::Sort,
        CpuStage::Wcsph(WcsphStage::Density),
        CpuStage::Wcsph(WcsphStage::FreeSurfacePressure),
    ];
    if params.has_surface_tension() {
        stages.push(CpuStage::Normals);
    }
    stages.push(CpuStage::Forces);
    stages
}

/// WCSPH's scratch: the equation of state's pressures of the last evaluation, before the free
/// surface's ([`crate::free_surface_pressure`]).
#[derive(Clone, Debug, Default)]
pub(super) struct WcsphScratch {
    eos_pressure: Vec<f32>,
}

/// WCSPH's time step: `params.time_step` when fixed; with `params.adaptive_time_step`, the CFL,
/// force and viscous limits of [`adaptive_time_step`] at the last accelerations, the boundary's
/// fastest sample counted as a speed.
pub(super) fn next_time_step(params: &SphParams, p: &ParticleData, boundary: &Boundary) -> f32 {
    if !params.adaptive_time_step {
        return params.time_step;
    }
    let mut extremes = StepExtremes::measure(&p.velocity, &p.acceleration);
    extremes.max_speed = extremes.max_speed.max(boundary.max_speed());
    adaptive_time_step(params, &extremes)
}

/// What the WCSPH step borrows from the solver.
pub(super) struct WcsphStep<'a> {
    pub parts: SolverParts<'a>,
    pub scratch: &'a mut WcsphScratch,
}

/// What a WCSPH step did.
pub(super) struct WcsphOutcome {
    pub dt: f32,
    pub corrections: Corrections,
    /// Each evaluation's force on each body, in order.
    pub forces: Vec<Vec<BodyForceSum>>,
}

impl WcsphStep<'_> {
    /// One step with the parameters' integrator at the dt `step_dt` makes of the rule's; `stale`
    /// when the last closing kick left no valid acceleration (kick-drift-kick evaluates first).
    pub fn advance(&mut self, step_dt: StepDt, stale: bool, guard: &Guard) -> WcsphOutcome {
        let params = *self.parts.params;
        // The contact stops approaches within dt_max in an evaluation before this step's dt is
        // chosen, and within this step's dt in the closing one (the GPU's roles do the same).
        let ctx = StageContext::new(&params);
        let mut forces = Vec::new();
        let mut corrections = Corrections::default();
        let dt = match params.integrator {
            Integrator::SymplecticEuler => {
                forces.push(self.evaluate(&ctx, true));
                let dt = step_dt.of(self.next_time_step());
                let p = &mut *self.parts.particles;
                corrections += timed(&mut self.parts.timings.integrate, || {
                    integrate::euler(&mut p.position, &mut p.velocity, &p.acceleration, dt, guard)
                });
                dt
            }
            Integrator::KickDriftKick => {
                if stale {
                    forces.push(self.evaluate(&ctx.with_half_kick_drift(), true));
                }
                let dt = step_dt.of(self.next_time_step());
                let p = &mut *self.parts.particles;
                corrections += timed(&mut self.parts.timings.integrate, || {
                    integrate::kick_drift(
                        &mut p.position,
                        &mut p.velocity,
                        &mut p.velocity_predicted,
                        &p.acceleration,
                        dt,
                        guard,
                    )
                });
                forces.push(self.evaluate(&ctx.with_step_dt(dt), false));
                let p = &mut *self.parts.particles;
                timed(&mut self.parts.timings.integrate, || {
                    integrate::kick(&mut p.position, &mut p.velocity, &p.acceleration, dt, guard)
                });
                dt
            }
            Integrator::Leapfrog => {
                forces.push(self.evaluate(&ctx.with_half_kick_drift(), true));
                let dt = step_dt.of(self.next_time_step());
                let p = &mut *self.parts.particles;
                corrections += timed(&mut self.parts.timings.integrate, || {
                    p.acceleration_start.copy_from_slice(&p.acceleration);
                    integrate::leapfrog_drift(
                        &mut p.position,
                        &p.velocity,
                        &mut p.velocity_predicted,
                        &p.acceleration_start,
                        dt,
                        guard,
                    )
                });
                forces.push(self.evaluate(&ctx.with_step_dt(dt), false));
                let p = &mut *self.parts.particles;
                timed(&mut self.parts.timings.integrate, || {
                    integrate::leapfrog_kick(
                        &mut p.position,
                        &mut p.velocity,
                        &p.acceleration_start,
                        &p.acceleration,
                        dt,
                        guard,
                    )
                });
                dt
            }
        };
        WcsphOutcome {
            dt,
            corrections,
            forces,
        }
    }

    fn next_time_step(&self) -> f32 {
        let parts = &self.parts;
        next_time_step(parts.params, parts.particles, parts.boundary)
    }

    /// One force evaluation: the stages of [`step_stages`] in order at the current
    /// positions; the viscosity term reads `velocity_predicted` unless `use_velocity`. Returns
    /// the evaluation's force on each body.
    fn evaluate(&mut self, ctx: &StageContext, use_velocity: bool) -> Vec<BodyForceSum> {
        let params = *self.parts.params;
        let mut forces = Vec::new();
        for stage in step_stages(&params) {
            let parts = &mut self.parts;
            let (neighbors, p, t) = (
                &*parts.neighbors,
                &mut *parts.particles,
                &mut *parts.timings,
            );
            let boundary = &*parts.boundary;
            match stage {
                CpuStage::Sort => parts.sort_by_cell(),
                CpuStage::Wcsph(WcsphStage::Density) => timed(&mut t.density, || {
                    compute_density_pressure(
                        ctx,
                        neighbors,
                        &p.position,
                        Some(boundary),
                        &mut p.density,
                        &mut p.pressure,
                    )
                }),
                CpuStage::Wcsph(WcsphStage::FreeSurfacePressure) => timed(&mut t.density, || {
                    let eos_pressure = &mut self.scratch.eos_pressure;
                    std::mem::swap(eos_pressure, &mut p.pressure);
                    p.pressure.resize(eos_pressure.len(), 0.0);
                    extrapolate_free_surface_pressure(
                        ctx,
                        neighbors,
                        &p.position,
                        &p.density,
                        eos_pressure,
                        &mut p.pressure,
                    )
                }),
                CpuStage::Normals => timed(&mut t.normals, || {
                    compute_normals(ctx, neighbors, &p.position, &p.density, &mut p.normal)
                }),
                CpuStage::Forces => {
                    let current_or_predicted = |current: bool| {
                        if current {
                            &p.velocity
                        } else {
                            &p.velocity_predicted
                        }
                    };
                    let input = ForceInputs {
                        position: &p.position,
                        velocity: current_or_predicted(use_velocity),
                        // Kick-drift-kick's closing evaluation: v½, which the next drift
                        // starts from plus a dt (the leapfrog's stays on its prediction).
                        contact_velocity: current_or_predicted(
                            use_velocity || params.integrator == Integrator::KickDriftKick,
                        ),
                        density: &p.density,
                        pressure: &p.pressure,
                        normal: &p.normal,
                        boundary: Some(boundary),
                        with_pressure: true,
                    };
                    forces = timed(&mut t.forces, || {
                        compute_accelerations(ctx, neighbors, &input, &mut p.acceleration)
                    });
                }
                // The integrator's phases (placed by `advance`), whitewater (after a stable
                // step); the other solvers' stages are never in WCSPH's list.
                CpuStage::TimeStep
                | CpuStage::Integrate
                | CpuStage::Whitewater
                | CpuStage::Bodies
                | CpuStage::NeighborLists
                | CpuStage::Dfsph(_)
                | CpuStage::Pbf(_) => {}
            }
        }
        forces
    }
}
