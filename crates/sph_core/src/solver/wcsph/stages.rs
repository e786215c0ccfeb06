//! WCSPH's own CPU stages, the twins of its GPU passes (the shared ones are
//! [`crate::stage::CpuStage`]'s own variants). A leaf module, so that `stage.rs` can list it.

/// A stage only WCSPH's force evaluation runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum WcsphStage {
    /// Density and the equation of state's pressure ([`crate::density`]).
    Density,
    /// The pressure of free-surface particles, extrapolated from the water around them
    /// ([`crate::free_surface_pressure`]).
    FreeSurfacePressure,
}
