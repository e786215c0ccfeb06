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
