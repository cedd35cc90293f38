//! Physical pendulum on a revolute joint: period vs the analytic values.
use crate::common;
use common::*;
use flexmbs_core::integrator::{GenAlpha, GenAlphaSettings};
use flexmbs_core::*;
use std::f64::consts::PI;

fn simulate(
    p: &Pendulum,
    theta0: f64,
    rho: f64,
    h: f64,
    t_end: f64,
) -> (Vec<(f64, f64)>, Vec<f64>, f64) {
    let ga = GenAlpha::new(GenAlphaSettings {
        rho_inf: rho,
        ..Default::default()
    })
    .unwrap();
    let mut s = p.state(theta0);
    let mut ws = Workspace::new(&p.model);
    ga.initialize(&p.model, &mut s, &mut ws).unwrap();
    let mut samples = vec![(0.0, p.angle(&s))];
    let mut energy = Vec::new();
    let mut g_max: f64 = 0.0;
    ga.integrate(&p.model, &mut s, &mut ws, h, t_end, |s, st| {
        samples.push((s.t, p.angle(s)));
        energy.push(st.energy.total());
        g_max = g_max.max(st.g_max);
    })
    .unwrap();
    (samples, energy, g_max)
}

/// Small amplitude (0.01 rad): period vs `2 pi sqrt((I_c + m L^2) / (m g L))`, tolerance 1e-4
/// relative (the finite-amplitude correction theta0^2/16 = 6e-6 is inside it).
#[test]
fn small_amplitude_period_matches_physical_pendulum() {
    for rot in [RotationParam::Cardan, RotationParam::Quaternion] {
        let p = Pendulum::new(rot);
        let t0 = 2.0 * PI / p.omega0();
        let (samples, _, g_max) = simulate(&p, 0.01, 0.9, 1e-3, 2.6 * t0);
        let period = mean_period(&samples);
        let rel = (period - t0).abs() / t0;
        println!("{rot:?}: period {period}, analytic {t0}, rel err {rel:e}, max|g| {g_max:e}");
        assert!(rel < 1e-4, "relative period error {rel}");
        assert!(g_max < 1e-10);
    }
}

/// 90 degree amplitude: period `4 K(sin 45°) / omega0` (K by the AGM), tolerance 1e-5 relative
/// at h = 2.5e-4; energy drift with rho_inf = 0.9 below 2e-6 of m g L over ~2 periods
/// (rho_inf = 1 is not used: with index-3 constraints the multipliers are then undamped and
/// grow from round-off, see docs/engine.md).
#[test]
fn large_amplitude_period_matches_elliptic_integral() {
    let p = Pendulum::new(RotationParam::Cardan);
    let t_exact = 4.0 * elliptic_k((PI / 4.0).sin()) / p.omega0();
    let (samples, energy, _) = simulate(&p, PI / 2.0, 0.9, 2.5e-4, 2.3 * t_exact);
    let period = mean_period(&samples);
    let rel = (period - t_exact).abs() / t_exact;
    let scale = p.m * p.g * p.l;
    let drift = energy
        .iter()
        .map(|e| (e - energy[0]).abs())
        .fold(0.0, f64::max)
        / scale;
    println!("period {period}, exact {t_exact}, rel err {rel:e}, energy drift {drift:e}");
    assert!(rel < 1e-5, "relative period error {rel}");
    assert!(drift < 2e-6, "energy drift {drift}");
}

/// Adaptive generalized-alpha (atol = rtol = 1e-8) on the 90° pendulum: period within 1e-5 of
/// the elliptic-integral value, steps actually vary, constraints hold to 1e-10.
#[test]
fn adaptive_step_large_amplitude_period() {
    use flexmbs_core::integrator::AdaptiveSettings;
    let p = Pendulum::new(RotationParam::Cardan);
    let t_exact = 4.0 * elliptic_k((PI / 4.0).sin()) / p.omega0();
    let ga = GenAlpha::new(GenAlphaSettings::default()).unwrap();
    let mut s = p.state(PI / 2.0);
    let mut ws = Workspace::new(&p.model);
    ga.initialize(&p.model, &mut s, &mut ws).unwrap();
    let ctl = AdaptiveSettings {
        atol: 1e-8,
        rtol: 1e-8,
        h_init: 1e-4,
        ..Default::default()
    };
    let mut samples = vec![(0.0, p.angle(&s))];
    let (mut h_min, mut h_max, mut g_max) = (f64::INFINITY, 0.0_f64, 0.0_f64);
    ga.integrate_adaptive(&p.model, &mut s, &mut ws, &ctl, 2.3 * t_exact, |s, st| {
        samples.push((s.t, p.angle(s)));
        (h_min, h_max, g_max) = (h_min.min(st.h), h_max.max(st.h), g_max.max(st.g_max));
    })
    .unwrap();
    let rel = (mean_period(&samples) - t_exact).abs() / t_exact;
    println!(
        "adaptive: {} steps, h in [{h_min:e}, {h_max:e}], period rel err {rel:e}",
        samples.len() - 1
    );
    assert!(rel < 1e-5, "{rel}");
    assert!(h_max > 2.0 * h_min);
    assert!(g_max < 1e-10);
}

/// Adaptive steps with `rho_inf = 1` on a constrained model are refused up front: without
/// numerical damping the spurious step-frequency oscillation of the constraint forces enters the
/// error estimate and the step collapses (a double pendulum fell to 3e-9 s and the run never
/// ended). With `rho_inf` just below 1 the same pendulum runs.
#[test]
fn adaptive_step_refuses_undamped_constrained_model() {
    use flexmbs_core::integrator::AdaptiveSettings;
    use flexmbs_core::SolverError;
    let p = Pendulum::new(RotationParam::Cardan);
    let ctl = AdaptiveSettings {
        h_init: 1e-3,
        ..Default::default()
    };
    for (rho_inf, refused) in [(1.0, true), (0.95, false)] {
        let ga = GenAlpha::new(GenAlphaSettings {
            rho_inf,
            ..Default::default()
        })
        .unwrap();
        let mut s = p.state(PI / 2.0);
        let mut ws = Workspace::new(&p.model);
        ga.initialize(&p.model, &mut s, &mut ws).unwrap();
        let r = ga.integrate_adaptive(&p.model, &mut s, &mut ws, &ctl, 0.5, |_, _| {});
        if refused {
            assert!(
                matches!(
                    r,
                    Err(SolverError::InvalidSetting {
                        name: "rho_inf",
                        ..
                    })
                ),
                "{r:?}"
            );
            assert_eq!(s.t, 0.0);
        } else {
            r.unwrap();
            assert!((s.t - 0.5).abs() < 1e-12);
        }
    }
}
