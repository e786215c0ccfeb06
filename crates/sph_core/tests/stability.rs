//! The adaptive time-step rule picks the binding limit, and the instability test catches
//! non-finite states and steps that cross more than h.

use sph_core::glam::Vec3;
use sph_core::stability::{adaptive_time_step, viscous_limit, StepExtremes};
use sph_core::SphParams;

fn adaptive() -> SphParams {
    SphParams {
        adaptive_time_step: true,
        time_step: 1.0,
        viscosity: 0.0,
        ..SphParams::water()
    }
}

fn close(a: f32, b: f32) -> bool {
    (a - b).abs() <= 1e-6 * b.abs()
}

#[test]
fn a_fixed_step_is_the_time_step() {
    let p = SphParams::water();
    let fast = StepExtremes {
        max_speed: 1e3,
        max_acceleration: 1e9,
    };
    assert_eq!(adaptive_time_step(&p, &fast), p.time_step);
}

#[test]
fn each_limit_binds_when_it_is_the_smallest() {
    let p = adaptive();
    let h = p.smoothing_radius;
    let c0 = p.speed_of_sound();
    let at_rest = StepExtremes::default();
    // CFL: λ h / (c0 + v).
    assert!(close(
        adaptive_time_step(&p, &at_rest),
        p.cfl_factor * h / c0
    ));
    let moving = StepExtremes {
        max_speed: 2.0 * c0,
        max_acceleration: 0.0,
    };
    assert!(close(
        adaptive_time_step(&p, &moving),
        p.cfl_factor * h / (3.0 * c0)
    ));
    // Force: 0.25 sqrt(h / a).
    let pushed = StepExtremes {
        max_speed: 0.0,
        max_acceleration: 1e8,
    };
    assert!(close(
        adaptive_time_step(&p, &pushed),
        0.25 * (h / 1e8f32).sqrt()
    ));
    // Viscous: 0.125 h² ρ0 / μ.
    let syrup = SphParams {
        viscosity: 1e4,
        ..p
    };
    let limit = 0.125 * h * h * p.rest_density / 1e4;
    assert!(close(viscous_limit(&syrup), limit));
    assert!(close(adaptive_time_step(&syrup, &at_rest), limit));
    // The largest step bounds them all.
    let capped = SphParams {
        time_step: 1e-7,
        ..p
    };
    assert_eq!(adaptive_time_step(&capped, &at_rest), 1e-7);
}

#[test]
fn non_finite_states_and_steps_crossing_h_are_unstable() {
    let h = 0.04;
    let v = [Vec3::ZERO, Vec3::new(0.0, f32::NAN, 0.0)];
    let a = [Vec3::ZERO; 2];
    let nan = StepExtremes::measure(&v, &a);
    assert_eq!(nan.max_speed, f32::INFINITY, "a NaN is not lost by max");
    assert!(nan.is_unstable(1e-4, h));
    let calm = StepExtremes::measure(&[Vec3::new(3.0, 4.0, 0.0)], &[Vec3::Y]);
    assert_eq!(calm.max_speed, 5.0);
    assert!(!calm.is_unstable(h / 5.0 * 0.99, h));
    assert!(calm.is_unstable(h / 5.0 * 1.01, h));
    let infinite_force = StepExtremes::measure(&[Vec3::ZERO], &[Vec3::splat(f32::INFINITY)]);
    assert!(infinite_force.is_unstable(1e-4, h));
}
