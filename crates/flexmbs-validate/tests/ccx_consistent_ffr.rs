//! FFR bodies with consistent-mass invariants from CalculiX-exported matrices
//! (`examples/calculix_beam.toml`: the 40 x 2 x 2 C3D20R steel cantilever, 1 m x 20 mm x 20 mm,
//! clamped by the deck's `*BOUNDARY`). Skipped, with the reason printed, without `ccx`.

use flexmbs_core::ffr::{consistent_mass_to_si, reduced_body_to_si, FfrBody, RotationParam};
use flexmbs_io::model::read_fe_model;
use flexmbs_reduce::full_mass::reduce_with_mass;
use flexmbs_validate::complex_beam_ccx::isotropy_deviation;
use std::path::Path;

/// The ccx mass is block-isotropic (relative deviation < 1e-12: ccx writes the x, y, z entries
/// identically), so `from_consistent` accepts it; the invariants give the beam's mass
/// rho V = 3.14 kg (1e-10; the fixed nodes' mass is kept by the free export), its centroidal
/// J_xx = m (b^2 + h^2) / 12 = 2.0933e-4 kg m^2 (1e-10) and m_ff = Phi^T M Phi (1e-12);
/// the frequencies equal the recipe's CalculiX values (16.73174, 104.6634 Hz, 1e-6).
#[test]
fn ccx_beam_consistent_invariants() {
    if flexmbs_io::test_tools::ccx_or_skip("ccx_beam_consistent_invariants").is_none() {
        return;
    }
    let model = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/calculix_beam.toml");
    let spec = read_fe_model(&model).unwrap().body;
    let r = reduce_with_mass(&spec, model.parent().unwrap(), &mut |_| {}).unwrap();
    let iso = isotropy_deviation(&r.mass);
    assert!(iso < 1e-12, "isotropy deviation {iso:e}");
    let body = reduced_body_to_si(&r.body);
    let m = consistent_mass_to_si(&r.mass, r.body.units);
    let ffr = FfrBody::from_reduced_consistent(&body, &m, RotationParam::Quaternion).unwrap();
    let inv = &ffr.invariants;
    let mass = 7850.0 * 1.0 * 0.02 * 0.02;
    assert!((inv.i1 - mass).abs() < 1e-10 * mass, "mass {}", inv.i1);
    let c = inv.i_bar / inv.i1;
    assert!((c - nalgebra::Vector3::new(0.5, 0.0, 0.0)).norm() < 1e-10);
    let jxx = inv.i_kl[(1, 1)] + inv.i_kl[(2, 2)] - inv.i1 * (c[1] * c[1] + c[2] * c[2]);
    let jxx_exact = mass * (0.02f64.powi(2) * 2.0) / 12.0;
    assert!(
        (jxx - jxx_exact).abs() < 1e-10 * jxx_exact,
        "J_xx {jxx:e} vs {jxx_exact:e}"
    );
    eprintln!(
        "isotropy {iso:e}, mass {} kg, J_xx {jxx:e} kg m^2, f1 {} Hz",
        inv.i1, body.frequencies_hz[0]
    );
    let n = body.num_modes();
    for i in 0..n {
        for j in 0..n {
            let d = (inv.m_ff[(i, j)] - body.m_red[(i, j)]).abs();
            assert!(d < 1e-12, "m_ff({i},{j}) deviates by {d:e}");
        }
    }
    for (f, r) in body
        .frequencies_hz
        .iter()
        .zip([16.73174, 16.73174, 104.6634])
    {
        assert!((f - r).abs() < 1e-6 * r, "{f} vs {r}");
    }
}
