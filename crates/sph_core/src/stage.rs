//! The constants every stage reads, gathered once per step from [`SphParams`].

use crate::eos::Eos;
use crate::kernel::Kernels;
use crate::params::SphParams;
use glam::Vec3;

/// Per-step constants shared by the density, normals and forces stages.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StageContext {
    /// Kernel constants for h.
    pub kernels: Kernels,
    /// Equation of state.
    pub eos: Eos,
    /// Particle mass m.
    pub mass: f32,
    /// Rest density ρ0.
    pub rest_density: f32,
    /// Dynamic viscosity μ.
    pub viscosity: f32,
    /// Akinci γ.
    pub surface_tension: f32,
    /// Gravity g.
    pub gravity: Vec3,
}

impl StageContext {
    /// The constants of `params`.
    pub fn new(params: &SphParams) -> Self {
        Self {
            kernels: Kernels::new(params.smoothing_radius),
            eos: Eos::from_params(params),
            mass: params.particle_mass,
            rest_density: params.rest_density,
            viscosity: params.viscosity,
            surface_tension: params.surface_tension,
            gravity: params.gravity,
        }
    }
}

/// The stages of the CPU solver, in pipeline order. The GPU stage registry
/// (`bevy_sph_fluid::render::stages`) names one of these as the CPU twin of each of its passes;
/// several GPU passes may share a twin (count cells, prefix sum and scatter are the CPU's sort).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum CpuStage {
    /// The time-step rule, the stability check and rollback ([`crate::stability`],
    /// [`crate::rollback`]).
    TimeStep,
    /// Neighbour sort: cell counts, offsets and the reorder ([`crate::neighbor`]).
    Sort,
    /// Density and pressure ([`crate::density`]).
    Density,
    /// Akinci 2013 normals ([`crate::surface_tension_akinci2013`]).
    Normals,
    /// Accelerations ([`crate::forces`]).
    Forces,
    /// Integration phases ([`crate::integrate`]).
    Integrate,
}

/// The stages of one force evaluation for `params`, in order: sort, density, normals (with
/// surface tension only), forces. The integrator places the time step and its integration
/// phases around the evaluations.
pub fn evaluation_stages(params: &SphParams) -> Vec<CpuStage> {
    let mut stages = vec![CpuStage::Sort, CpuStage::Density];
    if params.has_surface_tension() {
        stages.push(CpuStage::Normals);
    }
    stages.push(CpuStage::Forces);
    stages
}
