//! Parameter presets, derivation and validation.

use sph_core::glam::{Vec2, Vec3};
use sph_core::solver::validate_capacity;
use sph_core::{
    BoxContainer, CpuSolver, Eos, EquationOfState, Integrator, SpacingDerivation, SphParams,
};

#[test]
fn presets_are_valid_and_follow_the_design() {
    let seed = SphParams::seed();
    seed.validate().unwrap();
    assert_eq!(seed.viscosity, 0.02);
    assert_eq!(seed.stiffness, 1.0);
    assert_eq!(seed.rest_density, 1.0);
    assert_eq!(seed.surface_tension, 1.0);
    assert_eq!(seed.wall_damping, 0.5);
    assert_eq!(seed.time_step, 0.005);
    assert_eq!(seed.integrator, Integrator::Leapfrog);
    assert_eq!(seed.equation_of_state, EquationOfState::Tait);
    let water = SphParams::water();
    water.validate().unwrap();
    assert_eq!(water.rest_density, 1000.0);
    assert!((water.gravity.y + 9.81).abs() < 1e-6);
}

#[test]
fn derivation_from_spacing() {
    let d = SpacingDerivation {
        spacing: 0.01,
        rest_density: 1000.0,
        expected_peak_speed: 2.0,
        cfl: 0.4,
        viscosity_alpha: 0.05,
    };
    let p = SphParams::from_spacing(d);
    // m = ρ0 Δx³ / L, with L the rest lattice's kernel sum (1.0098 at h = 2 Δx).
    let lattice = sph_core::Kernels::new(0.02).lattice_sum(0.01);
    assert!((lattice - 1.0098).abs() < 1e-3, "lattice sum {lattice}");
    assert!((p.particle_mass * lattice - 1000.0 * 1e-6).abs() < 1e-9);
    assert!((p.smoothing_radius - 0.02).abs() < 1e-7);
    // c0 = 10 v_peak = 20 m/s, B = ρ0 c0² / 7.
    assert!((p.stiffness - 1000.0 * 400.0 / 7.0).abs() < 1e-2);
    assert!((p.speed_of_sound() - 20.0).abs() < 1e-4);
    assert!((p.time_step - 0.4 * 0.02 / 22.0).abs() < 1e-8);
    assert!((p.cfl_number(2.0) - 0.4).abs() < 1e-5);
}

#[test]
fn artificial_viscosity_alpha_round_trips_through_the_dynamic_viscosity() {
    // The water preset is derived with α = 0.05: h = 0.04 m, c0 = 30 m/s, ν = α h c0 / 10.
    let water = SphParams::water();
    let alpha = SpacingDerivation::default().viscosity_alpha;
    assert!((water.artificial_viscosity_alpha() - alpha).abs() < 1e-6);
    assert!((water.kinematic_viscosity() - alpha * 0.04 * 30.0 / 10.0).abs() < 1e-7);
    assert!((water.viscosity - 1000.0 * water.kinematic_viscosity()).abs() < 1e-4);
    // The design's μ = 0.02 Pa s at ρ0 = 1, h = 0.1 m, c0 = √7 m/s.
    let seed = SphParams::seed();
    let seed_alpha = 10.0 * 0.02 / (0.1 * 7f32.sqrt());
    assert!((seed.artificial_viscosity_alpha() - seed_alpha).abs() < 1e-5);
    for base in [water, seed] {
        for alpha in [0.0, 1e-3, 0.05, 0.5, 4.0] {
            let mut p = base;
            p.set_artificial_viscosity_alpha(alpha);
            let nu = alpha * p.smoothing_radius * p.speed_of_sound() / 10.0;
            assert!(
                (p.kinematic_viscosity() - nu).abs() <= 1e-6 * nu,
                "α {alpha}"
            );
            let back = p.artificial_viscosity_alpha();
            assert!((back - alpha).abs() <= 1e-6 * alpha, "α {alpha} -> {back}");
            assert_eq!(p.has_viscosity(), alpha > 0.0);
        }
    }
}

#[test]
fn equations_of_state() {
    let tait = Eos {
        law: EquationOfState::Tait,
        stiffness: 7.0,
        rest_density: 1000.0,
        clamp_negative: false,
    };
    assert_eq!(tait.pressure(1000.0), 0.0);
    assert!((tait.pressure(1100.0) - 7.0 * (1.1f32.powi(7) - 1.0)).abs() < 1e-4);
    assert!(tait.pressure(900.0) < 0.0);
    let clamped = Eos {
        clamp_negative: true,
        ..tait
    };
    assert_eq!(clamped.pressure(900.0), 0.0);
    let linear = Eos {
        law: EquationOfState::Linear,
        stiffness: 2.0,
        rest_density: 1.0,
        clamp_negative: false,
    };
    assert!((linear.pressure(1.5) - 1.0).abs() < 1e-6);
    assert!((linear.pressure(0.5) + 1.0).abs() < 1e-6);
}

type Mutation = fn(&mut SphParams);

#[test]
fn every_invalid_parameter_is_rejected_by_name() {
    let cases: Vec<(&str, Mutation)> = vec![
        ("rest_density", |p| p.rest_density = 0.0),
        ("rest_density", |p| p.rest_density = -1.0),
        ("rest_density", |p| p.rest_density = f32::NAN),
        ("rest_density", |p| p.rest_density = 1e9),
        ("particle_mass", |p| p.particle_mass = 0.0),
        ("particle_mass", |p| p.particle_mass = f32::INFINITY),
        ("smoothing_radius", |p| p.smoothing_radius = 0.0),
        ("smoothing_radius", |p| p.smoothing_radius = -0.1),
        ("smoothing_radius", |p| p.smoothing_radius = f32::NAN),
        ("stiffness", |p| p.stiffness = 0.0),
        ("stiffness", |p| p.stiffness = -5.0),
        ("viscosity", |p| p.viscosity = -0.1),
        ("viscosity", |p| p.viscosity = f32::NAN),
        ("surface_tension", |p| p.surface_tension = -1.0),
        ("surface_tension", |p| p.surface_tension = f32::INFINITY),
        ("gravity", |p| p.gravity = Vec3::new(0.0, f32::NAN, 0.0)),
        ("gravity", |p| p.gravity = Vec3::new(0.0, -1e6, 0.0)),
        ("wall_damping", |p| p.wall_damping = -0.1),
        ("wall_damping", |p| p.wall_damping = 1.5),
        ("time_step", |p| p.time_step = 0.0),
        ("time_step", |p| p.time_step = -0.001),
        ("time_step", |p| p.time_step = f32::NAN),
        ("time_step", |p| p.time_step = 10.0),
        ("cfl_factor", |p| p.cfl_factor = 0.0),
        ("cfl_factor", |p| p.cfl_factor = 1.5),
        ("cfl_factor", |p| p.cfl_factor = f32::NAN),
    ];
    for (field, mutate) in cases {
        let mut p = SphParams::water();
        mutate(&mut p);
        let err = p.validate().expect_err(field);
        assert_eq!(err.field, field);
        let message = err.to_string();
        assert!(
            message.contains(field) && message.contains("allowed"),
            "{message}"
        );
        // The solver refuses them too.
        assert!(CpuSolver::new(p, BoxContainer::default(), 10).is_err());
    }
}

#[test]
fn invalid_capacity_and_container_are_rejected_by_name() {
    assert_eq!(validate_capacity(0).unwrap_err().field, "capacity");
    let err = CpuSolver::new(SphParams::water(), BoxContainer::default(), 0).unwrap_err();
    assert_eq!(err.field, "capacity");
    let flat = BoxContainer::from_floor(Vec3::ZERO, Vec2::new(1.0, 1.0), 0.0);
    assert_eq!(flat.validate().unwrap_err().field, "container.wall_height");
    let nan = BoxContainer::from_floor(Vec3::ZERO, Vec2::new(f32::NAN, 1.0), 1.0);
    assert_eq!(nan.validate().unwrap_err().field, "container.floor_size.x");
    // A grid too fine for its box is refused with the field to change.
    let mut p = SphParams::water();
    p.smoothing_radius = 1e-4;
    let err = CpuSolver::new(p, BoxContainer::default(), 10).unwrap_err();
    assert_eq!(err.field, "smoothing_radius");
}

#[test]
fn container_from_floor_plate() {
    let c = BoxContainer::from_floor(Vec3::new(1.0, 0.5, -1.0), Vec2::new(2.0, 4.0), 3.0);
    assert_eq!(c.min(), Vec3::new(0.0, 0.5, -3.0));
    assert_eq!(c.max(), Vec3::new(2.0, 3.5, 1.0));
    assert!(c.contains(Vec3::new(1.0, 1.0, 0.0), 0.0));
    assert!(!c.contains(Vec3::new(1.0, 0.4, 0.0), 0.0));
}
