//! `examples/mbs/smooth_drive_arm.toml`: the solid link driven by a quintic smooth step and
//! carrying its payload on the rigid end-face interface rings, after the move, at the first
//! frequency of a clamped Euler-Bernoulli beam with a tip mass (an independent closed form: the
//! interface frame makes the weld transmit the link's slope and the payload's inertia).

use crate::common;

use flexmbs_io::results::read_results;
use flexmbs_sim::run::{run_model, RunOptions};
use std::path::Path;

/// First root of `1 + cos l cosh l + mu l (cos l sinh l - sin l cosh l) = 0` (clamped-free beam,
/// tip mass ratio `mu = M / (rho A L)`), by bisection on [0.5, 1.875].
fn tip_mass_eigenvalue(mu: f64) -> f64 {
    let f = |l: f64| 1.0 + l.cos() * l.cosh() + mu * l * (l.cos() * l.sinh() - l.sin() * l.cosh());
    let (mut a, mut b) = (0.5, 1.875);
    assert!(f(a) * f(b) < 0.0);
    for _ in 0..100 {
        let c = 0.5 * (a + b);
        if f(a) * f(c) <= 0.0 {
            b = c;
        } else {
            a = c;
        }
    }
    0.5 * (a + b)
}

#[test]
fn residual_vibration_at_the_clamped_beam_with_tip_mass_frequency() {
    let file =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/mbs/smooth_drive_arm.toml");
    let cm = flexmbs_sim::load_model(&file).unwrap();
    assert!(cm.warnings.is_empty(), "{:?}", cm.warnings);
    let out = common::work_dir("smooth-drive-arm", "run");
    run_model(&cm, &RunOptions::new(&out), &mut |_| {}).unwrap();
    let r = read_results(&out.join("results.h5")).unwrap();
    let w = r.series("elbow.deformation.y").unwrap();
    // zero crossings after the move (ends at 0.5 s), linearly interpolated
    let mut crossings = Vec::new();
    for k in 1..r.time.len() {
        let (t0, t1, w0, w1) = (r.time[k - 1], r.time[k], w[k - 1], w[k]);
        if t0 > 0.55 && (w0 > 0.0) != (w1 > 0.0) {
            crossings.push(t0 + (t1 - t0) * w0 / (w0 - w1));
        }
    }
    assert!(crossings.len() > 10, "{crossings:?}");
    let f = (crossings.len() - 1) as f64 / 2.0 / (crossings[crossings.len() - 1] - crossings[0]);
    // link 0.5 m x 20 mm (in plane) x 5 mm, E 70 GPa, rho 2700; payload 0.2 kg (its 1e-5 kg m^2
    // rotary inertia is 2e-4 of M L^2 and neglected)
    let (e, rho, b, h, l, m_tip) = (70e9, 2700.0, 0.02, 0.005, 0.5, 0.2);
    let (area, i) = (b * h, h * b * b * b / 12.0);
    let lam = tip_mass_eigenvalue(m_tip / (rho * area * l));
    let f_ref =
        lam * lam / (2.0 * std::f64::consts::PI) * (e * i / (rho * area * l.powi(4))).sqrt();
    let rel = (f - f_ref) / f_ref;
    eprintln!(
        "residual vibration {f:.4} Hz, clamped beam with tip mass {f_ref:.4} Hz, rel. {rel:e}"
    );
    // 0.5 %: shear flexibility of the solid (L / b = 25) and the period error of
    // generalized-alpha at 40 steps per period are each of order 0.1 %
    assert!(rel.abs() < 5e-3, "{f} Hz vs {f_ref} Hz");
}
