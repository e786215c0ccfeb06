//! Simulation parameters with units, the two presets, the design's "automatic parameter
//! calculation" from a particle spacing, and validation with errors that name the field.

use crate::kernel::Kernels;
use crate::solver::dfsph::settings::{dfsph_max_time_step, DfsphSettings};
use crate::solver::pbf::settings::{PbfSettings, PBF_CFL_FACTOR, PBF_MAX_TIME_STEP};
use crate::solvers::Solver;
use glam::Vec3;
use std::fmt;

/// Equation of state turning density into pressure.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "bevy_reflect", derive(bevy_reflect::Reflect))]
pub enum EquationOfState {
    /// p = k (ρ - ρ0) (Müller 2003 eq. 12); k in m²/s² (Pa per kg/m³).
    Linear,
    /// p = k ((ρ/ρ0)⁷ - 1) (Tait, Becker & Teschner 2007); k = B in Pa.
    #[default]
    Tait,
}

/// Time integrator.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "bevy_reflect", derive(bevy_reflect::Reflect))]
pub enum Integrator {
    /// Symplectic (semi-implicit) Euler: v += a dt, then x += v dt. One force evaluation per step.
    SymplecticEuler,
    /// The design's leapfrog (Cossins variant, design eqs. 18-21): forces at the start of the step
    /// and again at the drifted positions with a predicted velocity. Two force evaluations per step.
    Leapfrog,
    /// Kick-drift-kick leapfrog: the end-of-step acceleration is reused as the next step's start,
    /// so one force evaluation per step; viscosity sees the predicted velocity v½ + a dt/2.
    #[default]
    KickDriftKick,
}

/// Neighbour-search structure.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "bevy_reflect", derive(bevy_reflect::Reflect))]
pub enum NeighborSearch {
    /// Dense uniform grid over the container (cell = h) built by a counting sort. Our default.
    #[default]
    Grid,
    /// The design's spatial hash (primes 73856093, 19349663, 83492791) sorted by hash.
    Hash,
}

/// Every parameter of the SPH model, in SI units unless a preset says otherwise.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "bevy_reflect", derive(bevy_reflect::Reflect))]
pub struct SphParams {
    /// Rest density ρ0 [kg/m³].
    pub rest_density: f32,
    /// Mass of every particle m [kg].
    pub particle_mass: f32,
    /// Kernel support radius h [m]; also the grid cell size.
    pub smoothing_radius: f32,
    /// Pressure stiffness k: Tait's B [Pa], or the linear law's k [m²/s²].
    pub stiffness: f32,
    /// Which equation of state maps density to pressure.
    pub equation_of_state: EquationOfState,
    /// Clamp negative pressures to zero (avoids tensile clumping at free surfaces).
    pub clamp_negative_pressure: bool,
    /// Dynamic viscosity μ [Pa·s] of Müller 2003 eq. 14; 0 switches the term off. The presets use
    /// it as an artificial viscosity: see [`Self::artificial_viscosity_alpha`].
    pub viscosity: f32,
    /// Akinci 2013 surface tension coefficient γ [N·m³/kg², acceleration per unit γ is
    /// m_j C(r) + Δn]; 0 switches surface tension (and the normals pass) off.
    pub surface_tension: f32,
    /// Gravitational acceleration g [m/s²].
    pub gravity: Vec3,
    /// Fraction of the normal velocity kept after a wall bounce, in [0, 1].
    pub wall_damping: f32,
    /// Time step dt [s]; with [`Self::adaptive_time_step`] the largest step allowed.
    pub time_step: f32,
    /// Choose every step's dt by the CFL rule of [`crate::stability::adaptive_time_step`]
    /// (bounded by `time_step`) instead of using `time_step` as is.
    pub adaptive_time_step: bool,
    /// CFL factor λ of the adaptive rule dt = λ h / (c0 + v_max), in (0, 1].
    pub cfl_factor: f32,
    /// Time integrator.
    pub integrator: Integrator,
    /// Neighbour-search structure.
    pub neighbor_search: NeighborSearch,
    /// The pressure solver ([`Self::use_solver`] also sets its own time-step rule).
    pub solver: Solver,
    /// Settings of [`Solver::Dfsph`].
    pub dfsph: DfsphSettings,
    /// Settings of [`Solver::Pbf`].
    pub pbf: PbfSettings,
}

/// A parameter outside its allowed range: names the field, the value and the range.
#[derive(Clone, Debug, PartialEq)]
pub struct ParamError {
    /// The field's name, e.g. `smoothing_radius`.
    pub field: &'static str,
    /// The offending value, formatted.
    pub value: String,
    /// The allowed range, e.g. `(0, 1000] m`.
    pub allowed: &'static str,
}

impl fmt::Display for ParamError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "invalid SPH parameter `{}` = {}: allowed {}",
            self.field, self.value, self.allowed
        )
    }
}

impl std::error::Error for ParamError {}

/// Checks `min < value <= max` (or `min <= value` when `min_inclusive`), rejecting NaN and infinity.
pub(crate) fn check_range(
    field: &'static str,
    value: f32,
    min: f32,
    min_inclusive: bool,
    max: f32,
    allowed: &'static str,
) -> Result<(), ParamError> {
    let above_min = if min_inclusive {
        value >= min
    } else {
        value > min
    };
    if value.is_finite() && above_min && value <= max {
        Ok(())
    } else {
        Err(ParamError {
            field,
            value: format!("{value}"),
            allowed,
        })
    }
}

/// Inputs of the design's "automatic parameter calculation" (see [`SphParams::from_spacing`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpacingDerivation {
    /// Initial particle spacing Δx [m].
    pub spacing: f32,
    /// Rest density ρ0 [kg/m³].
    pub rest_density: f32,
    /// The largest flow speed the scene is expected to reach [m/s], e.g. √(2 g H) for a column of
    /// height H.
    pub expected_peak_speed: f32,
    /// CFL factor λ of dt = λ h / (c0 + v_peak).
    pub cfl: f32,
    /// Artificial-viscosity strength α of ν = α h c0 / 10 (the 3-D equivalent of Monaghan's α).
    pub viscosity_alpha: f32,
}

impl Default for SpacingDerivation {
    fn default() -> Self {
        Self {
            spacing: 0.02,
            rest_density: 1000.0,
            expected_peak_speed: 3.0,
            cfl: DEFAULT_CFL_FACTOR,
            viscosity_alpha: DEFAULT_VISCOSITY_ALPHA,
        }
    }
}

/// A surface tension γ for SI water scenes (Akinci 2013's order of magnitude, as used by
/// SPlisHSPlasH's scenes); the water preset starts with surface tension off.
pub const WATER_SURFACE_TENSION: f32 = 0.05;

/// The artificial viscosity α of the derived parameters. Measured with the Akinci 2012 walls
/// (free slip) on the Martin & Moyce dam break at 8,000 particles: α = 0.05 puts the front 5 %
/// ahead (RMS Z 0.146), 0.1 gives 0.081, 0.15 gives 0.057, 0.2 gives 0.040 (docs/boundary.md).
pub const DEFAULT_VISCOSITY_ALPHA: f32 = 0.15;

/// DFSPH's artificial viscosity α in the water preset: [`SphParams::use_solver`] scales the
/// viscosity by [`DFSPH_VISCOSITY_SCALE`] on entering DFSPH, which turns the preset's
/// [`DEFAULT_VISCOSITY_ALPHA`] into this. With the mirrored boundary (docs/dfsph.md) DFSPH at
/// α = 0.15 puts the Martin & Moyce front 0.12 T ahead (RMS Z 0.128 at 8,000 particles); α = 0.2
/// gives 0.107, 0.25 gives 0.085 and 0.3 gives 0.063, while the tank at rest stays within 2.3 %
/// (α = 0.25) and 2.5 % (0.3) of hydrostatic pressure and calm (0.0013 m/s at the end).
pub const DFSPH_VISCOSITY_ALPHA: f32 = 0.25;

/// How much more viscosity DFSPH takes than WCSPH and PBF on the same scene:
/// [`DFSPH_VISCOSITY_ALPHA`] / [`DEFAULT_VISCOSITY_ALPHA`] (5/3).
pub const DFSPH_VISCOSITY_SCALE: f32 = DFSPH_VISCOSITY_ALPHA / DEFAULT_VISCOSITY_ALPHA;

/// The CFL factor λ of the derived and the adaptive time steps.
pub const DEFAULT_CFL_FACTOR: f32 = 0.4;

/// Ratio h / Δx: a cell of size h then holds 8 lattice particles, 27 cells hold 216 candidates.
pub const SMOOTHING_RATIO: f32 = 2.0;

impl SphParams {
    /// The design document's parameter table ("seed"): μ 0.02, k 1, ρ0 1, γ 1, wall damping 0.5,
    /// dt 0.005 s, leapfrog, Tait, with h = 0.1 and m = ρ0 (h/2)³.
    pub fn seed() -> Self {
        let h = 0.1;
        let spacing = h / SMOOTHING_RATIO;
        Self {
            rest_density: 1.0,
            particle_mass: spacing * spacing * spacing,
            smoothing_radius: h,
            stiffness: 1.0,
            equation_of_state: EquationOfState::Tait,
            clamp_negative_pressure: true,
            viscosity: 0.02,
            surface_tension: 1.0,
            gravity: Vec3::new(0.0, -9.81, 0.0),
            wall_damping: 0.5,
            time_step: 0.005,
            adaptive_time_step: false,
            cfl_factor: DEFAULT_CFL_FACTOR,
            integrator: Integrator::Leapfrog,
            neighbor_search: NeighborSearch::Grid,
            solver: Solver::Wcsph,
            dfsph: DfsphSettings::default(),
            pbf: PbfSettings::default(),
        }
    }

    /// Water in SI units at the default spacing of 0.02 m (see [`SpacingDerivation::default`]).
    pub fn water() -> Self {
        Self::from_spacing(SpacingDerivation::default())
    }

    /// The design's automatic parameter calculation: m = ρ0 Δx³ / L, h = 2 Δx, c0 = 10 v_peak
    /// (density fluctuations ~ (v/c0)² = 1%), Tait B = ρ0 c0² / 7, ν = α h c0 / 10,
    /// dt = λ h / (c0 + v_peak). Surface tension starts off (0). L = Σ_lattice W Δx³ (1.0098 at
    /// h = 2 Δx, [`Kernels::lattice_sum`]) makes the rest lattice exactly ρ0, so water spawned on
    /// the lattice starts without pressure (SPlisHSPlasH scales its particle volume for the same
    /// reason).
    pub fn from_spacing(d: SpacingDerivation) -> Self {
        let h = SMOOTHING_RATIO * d.spacing;
        let c0 = 10.0 * d.expected_peak_speed;
        Self {
            rest_density: d.rest_density,
            particle_mass: d.rest_density * d.spacing.powi(3)
                / Kernels::new(h).lattice_sum(d.spacing),
            smoothing_radius: h,
            stiffness: d.rest_density * c0 * c0 / 7.0,
            equation_of_state: EquationOfState::Tait,
            clamp_negative_pressure: true,
            viscosity: viscosity_from_alpha(d.viscosity_alpha, d.rest_density, h, c0),
            surface_tension: 0.0,
            gravity: Vec3::new(0.0, -9.81, 0.0),
            wall_damping: 0.5,
            time_step: d.cfl * h / (c0 + d.expected_peak_speed),
            adaptive_time_step: false,
            cfl_factor: d.cfl,
            integrator: Integrator::KickDriftKick,
            neighbor_search: NeighborSearch::Grid,
            solver: Solver::Wcsph,
            dfsph: DfsphSettings::default(),
            pbf: PbfSettings::default(),
        }
    }

    /// Switches to `solver` with its own time-step rule: for WCSPH the fixed dt of
    /// [`Self::from_spacing`] (λ h / (c0 + v_peak) with v_peak = c0 / 10), for DFSPH the adaptive
    /// rule λ Δx / v_max clamped to [`dfsph_max_time_step`], for PBF λ h / v_max clamped to
    /// [`PBF_MAX_TIME_STEP`] with λ = `cfl_factor` set to [`PBF_CFL_FACTOR`]. Leaving PBF for
    /// another solver sets λ back to [`DEFAULT_CFL_FACTOR`]; otherwise λ stays. Entering DFSPH
    /// multiplies the viscosity by [`DFSPH_VISCOSITY_SCALE`] (the water preset's α = 0.15 becomes
    /// [`DFSPH_VISCOSITY_ALPHA`]; a viscosity of 0 stays off) and leaving DFSPH divides it back;
    /// otherwise the viscosity stays, as do the other fields. Set `cfl_factor` or the viscosity
    /// after this call to choose other values.
    pub fn use_solver(&mut self, solver: Solver) {
        if self.solver == Solver::Pbf && solver != Solver::Pbf {
            self.cfl_factor = DEFAULT_CFL_FACTOR;
        }
        match (self.solver == Solver::Dfsph, solver == Solver::Dfsph) {
            (false, true) => self.viscosity *= DFSPH_VISCOSITY_SCALE,
            (true, false) => self.viscosity /= DFSPH_VISCOSITY_SCALE,
            _ => {}
        }
        self.solver = solver;
        match solver {
            Solver::Wcsph => {
                let c0 = self.speed_of_sound();
                self.time_step = self.cfl_factor * self.smoothing_radius / (1.1 * c0);
                self.adaptive_time_step = false;
            }
            Solver::Dfsph => {
                self.time_step = dfsph_max_time_step(self.spacing(), self.gravity.length());
                self.adaptive_time_step = true;
            }
            Solver::Pbf => {
                self.cfl_factor = PBF_CFL_FACTOR;
                self.time_step = PBF_MAX_TIME_STEP;
                self.adaptive_time_step = true;
            }
        }
    }

    /// The lattice spacing Δx = h / 2 these parameters were derived for.
    pub fn spacing(&self) -> f32 {
        self.smoothing_radius / SMOOTHING_RATIO
    }

    /// Speed of sound at rest c0 = sqrt(dp/dρ): sqrt(7 k / ρ0) for Tait, sqrt(k) for linear.
    pub fn speed_of_sound(&self) -> f32 {
        match self.equation_of_state {
            EquationOfState::Tait => (7.0 * self.stiffness / self.rest_density).sqrt(),
            EquationOfState::Linear => self.stiffness.sqrt(),
        }
    }

    /// Kinematic viscosity ν = μ / ρ0 [m²/s].
    pub fn kinematic_viscosity(&self) -> f32 {
        self.viscosity / self.rest_density
    }

    /// The artificial-viscosity strength α (dimensionless) that the dynamic viscosity μ stands for:
    /// α = 10 ν / (h c0) with ν = μ / ρ0 and c0 = [`Self::speed_of_sound`], the inverse of
    /// ν = α h c0 / 10 of [`Self::from_spacing`] (the 3-D equivalent of Monaghan's α). Not finite
    /// when ρ0, h or c0 is zero (values that [`Self::validate`] refuses).
    pub fn artificial_viscosity_alpha(&self) -> f32 {
        10.0 * self.kinematic_viscosity() / (self.smoothing_radius * self.speed_of_sound())
    }

    /// Sets the dynamic viscosity from an artificial-viscosity strength α: μ = ρ0 ν with
    /// ν = α h c0 / 10 (see [`Self::artificial_viscosity_alpha`]). It reads the current ρ0, h and
    /// stiffness (through c0), so set those first.
    pub fn set_artificial_viscosity_alpha(&mut self, alpha: f32) {
        self.viscosity = viscosity_from_alpha(
            alpha,
            self.rest_density,
            self.smoothing_radius,
            self.speed_of_sound(),
        );
    }

    /// CFL number dt (c0 + v_max) / h for a given peak speed.
    pub fn cfl_number(&self, max_speed: f32) -> f32 {
        self.time_step * (self.speed_of_sound() + max_speed) / self.smoothing_radius
    }

    /// Checks every field; the error names the first field out of range, its value and the range.
    pub fn validate(&self) -> Result<(), ParamError> {
        check_range(
            "rest_density",
            self.rest_density,
            0.0,
            false,
            1.0e5,
            "(0, 1e5] kg/m^3",
        )?;
        check_range(
            "particle_mass",
            self.particle_mass,
            0.0,
            false,
            1.0e6,
            "(0, 1e6] kg",
        )?;
        check_range(
            "smoothing_radius",
            self.smoothing_radius,
            1.0e-5,
            true,
            1.0e3,
            "[1e-5, 1e3] m",
        )?;
        check_range(
            "stiffness",
            self.stiffness,
            0.0,
            false,
            1.0e12,
            "(0, 1e12] (Pa for Tait, m^2/s^2 for linear)",
        )?;
        check_range(
            "viscosity",
            self.viscosity,
            0.0,
            true,
            1.0e6,
            "[0, 1e6] Pa s",
        )?;
        check_range(
            "surface_tension",
            self.surface_tension,
            0.0,
            true,
            1.0e6,
            "[0, 1e6]",
        )?;
        let g = self.gravity;
        if !(g.is_finite() && g.length() <= 1.0e3) {
            return Err(ParamError {
                field: "gravity",
                value: format!("{g}"),
                allowed: "finite, |g| <= 1e3 m/s^2",
            });
        }
        check_range("wall_damping", self.wall_damping, 0.0, true, 1.0, "[0, 1]")?;
        check_range("time_step", self.time_step, 0.0, false, 1.0, "(0, 1] s")?;
        check_range("cfl_factor", self.cfl_factor, 0.0, false, 1.0, "(0, 1]")?;
        self.dfsph.validate()?;
        self.pbf.validate()
    }

    /// Whether the surface-tension stage (normals pass and cohesion/curvature terms) is needed.
    pub fn has_surface_tension(&self) -> bool {
        self.surface_tension > 0.0
    }

    /// Whether the viscosity term is needed.
    pub fn has_viscosity(&self) -> bool {
        self.viscosity > 0.0
    }
}

/// Dynamic viscosity μ = ρ0 ν [Pa·s] of an artificial viscosity α, ν = α h c0 / 10 [m²/s].
fn viscosity_from_alpha(alpha: f32, rest_density: f32, h: f32, c0: f32) -> f32 {
    rest_density * (alpha * h * c0 / 10.0)
}

impl Default for SphParams {
    fn default() -> Self {
        Self::water()
    }
}

/// Checks `min <= max` of an iteration range and `max` in [1, 1000].
fn check_iterations(
    min_field: &'static str,
    max_field: &'static str,
    min: u32,
    max: u32,
) -> Result<(), ParamError> {
    if !(1..=1000).contains(&max) {
        return Err(ParamError {
            field: max_field,
            value: max.to_string(),
            allowed: "[1, 1000] iterations",
        });
    }
    if min > max {
        return Err(ParamError {
            field: min_field,
            value: min.to_string(),
            allowed: "[0, the largest iteration count]",
        });
    }
    Ok(())
}

impl DfsphSettings {
    /// Checks every field; the error names the first field out of range.
    pub fn validate(&self) -> Result<(), ParamError> {
        check_range(
            "dfsph.max_density_error",
            self.max_density_error,
            0.0,
            false,
            0.1,
            "(0, 0.1] (a fraction of ρ0)",
        )?;
        check_range(
            "dfsph.max_divergence_error",
            self.max_divergence_error,
            0.0,
            false,
            10.0,
            "(0, 10] 1/s",
        )?;
        check_iterations(
            "dfsph.min_density_iterations",
            "dfsph.max_density_iterations",
            self.min_density_iterations,
            self.max_density_iterations,
        )?;
        check_iterations(
            "dfsph.min_divergence_iterations",
            "dfsph.max_divergence_iterations",
            self.min_divergence_iterations,
            self.max_divergence_iterations,
        )?;
        check_range(
            "dfsph.divergence_over_relaxation",
            self.divergence_over_relaxation,
            1.0,
            true,
            1.9,
            "[1, 1.9] (1: plain Jacobi)",
        )?;
        check_range(
            "dfsph.density_over_relaxation",
            self.density_over_relaxation,
            1.0,
            true,
            1.9,
            "[1, 1.9] (1: plain Jacobi)",
        )
    }
}

impl PbfSettings {
    /// Checks every field; the error names the first field out of range.
    pub fn validate(&self) -> Result<(), ParamError> {
        if !(1..=100).contains(&self.iterations) {
            return Err(ParamError {
                field: "pbf.iterations",
                value: self.iterations.to_string(),
                allowed: "[1, 100] iterations",
            });
        }
        check_range(
            "pbf.relaxation",
            self.relaxation,
            0.0,
            false,
            10.0,
            "(0, 10]",
        )?;
        check_range("pbf.s_corr_k", self.s_corr_k, 0.0, true, 1.0, "[0, 1]")?;
        if !(1..=8).contains(&self.s_corr_n) {
            return Err(ParamError {
                field: "pbf.s_corr_n",
                value: self.s_corr_n.to_string(),
                allowed: "[1, 8]",
            });
        }
        check_range(
            "pbf.s_corr_dq",
            self.s_corr_dq,
            0.0,
            false,
            0.9,
            "(0, 0.9] h",
        )?;
        check_range("pbf.xsph_c", self.xsph_c, 0.0, true, 1.0, "[0, 1]")?;
        check_range(
            "pbf.vorticity_epsilon",
            self.vorticity_epsilon,
            0.0,
            true,
            1.0,
            "[0, 1] m/s",
        )?;
        check_range(
            "pbf.over_relaxation",
            self.over_relaxation,
            1.0,
            true,
            1.9,
            "[1, 1.9] (1: plain Jacobi)",
        )?;
        check_range(
            "pbf.jacobi_weight",
            self.jacobi_weight,
            0.0,
            false,
            1.0,
            "(0, 1] (1: plain Jacobi)",
        )
    }
}
