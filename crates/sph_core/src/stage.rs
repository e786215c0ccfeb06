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
    /// The rest-lattice correction of the pressure gradient, 1 / G
    /// ([`Kernels::lattice_gradient_moment`] times m / (ρ0 Δx³)).
    pub pressure_gradient_scale: f32,
}

impl StageContext {
    /// The constants of `params`.
    pub fn new(params: &SphParams) -> Self {
        let kernels = Kernels::new(params.smoothing_radius);
        Self {
            kernels,
            pressure_gradient_scale: pressure_gradient_scale(params, &kernels),
            eos: Eos::from_params(params),
            mass: params.particle_mass,
            rest_density: params.rest_density,
            viscosity: params.viscosity,
            surface_tension: params.surface_tension,
            gravity: params.gravity,
        }
    }
}

/// 1 / G, the rest-lattice correction of the pressure gradient for `params` (see
/// [`Kernels::lattice_gradient_moment`]).
pub fn pressure_gradient_scale(params: &SphParams, kernels: &Kernels) -> f32 {
    let spacing = params.spacing();
    let volume_scale = params.particle_mass / (params.rest_density * spacing.powi(3));
    let moment = kernels.lattice_gradient_moment(spacing) * volume_scale;
    if moment.is_finite() && moment > 0.0 {
        1.0 / moment
    } else {
        1.0
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
