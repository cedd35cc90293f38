//! The full-FE reference of `point_mass_on_beam` (`point_mass_on_beam_full_fe`): unit tests of the
//! reference itself, and the step and mode studies behind the README's tables (ignored: minutes).

use flexmbs_validate::point_mass_on_beam::{reduce_beam_with, BEAM};
use flexmbs_validate::point_mass_on_beam_convergence::{mode_study, penalty_setup, step_study};
use flexmbs_validate::point_mass_on_beam_full_fe::{
    assemble_full_fe, contact_weights, simulate_penalty_impact, simulate_penalty_impact_from,
    static_response, y_dof_at, FullFeBeam, Interpolation,
};
use nalgebra::{DMatrix, DVector};
use std::path::Path;

/// The benchmark's beam with 10 x 2 x 2 hex20 (1026 free DOFs): fast enough for unit tests.
fn coarse_spec() -> String {
    BEAM.replace("divisions = [25, 5, 5]", "divisions = [10, 2, 2]")
        .replace("modes = 100", "modes = 2")
}

fn coarse() -> FullFeBeam {
    assemble_full_fe(&coarse_spec()).unwrap()
}

/// Contact weights of the coarse mesh at (235, 25) mm.
fn coarse_weights(beam: &FullFeBeam, how: Interpolation) -> Vec<f64> {
    contact_weights(beam, how, [0.235, 0.025], 0.05, [0.025, 0.025], [10, 2])
        .unwrap()
        .dense(beam.k.nrows())
}

/// The static response to a unit load at the contact point equals a dense LU solve (nalgebra)
/// to round-off.
#[test]
fn static_response_equals_dense_solve() {
    let beam = coarse();
    let n = beam.k.nrows();
    let w = coarse_weights(&beam, Interpolation::Nurbs);
    let u = static_response(&beam.k, &w).unwrap();
    let mut k = DMatrix::<f64>::zeros(n, n);
    for j in 0..n {
        for (&i, &v) in beam
            .k
            .row_idx_of_col_raw(j)
            .iter()
            .zip(beam.k.val_of_col(j))
        {
            k[(i, j)] += v;
        }
    }
    let dense = k.lu().solve(&DVector::from_column_slice(&w)).unwrap();
    let diff = (DVector::from_column_slice(&u) - &dense).norm() / dense.norm();
    assert!(diff < 1e-10, "relative difference {diff:e}");
}

/// Both interpolations reproduce bilinear fields exactly (the cubic tensor-product spline and the
/// serendipity quad contain them), so they are partitions of unity.
#[test]
fn contact_weights_reproduce_linear_fields() {
    let beam = assemble_full_fe(BEAM).unwrap();
    let n = beam.k.nrows();
    for how in [Interpolation::Nurbs, Interpolation::Hex20Face] {
        let w = contact_weights(&beam, how, [0.235, 0.025], 0.05, [0.01, 0.01], [25, 5]).unwrap();
        // u_y = x (2 - 5 z), zero on the clamped face x = 0 (where the weights have no term)
        let mut u = vec![0.0; n];
        for (node, dofs) in beam.dofs.iter().enumerate() {
            if let Some(d) = dofs[1] {
                let p = beam.nodes[node];
                u[d] = p[0] * (2.0 - 5.0 * p[2]);
            }
        }
        // bilinear: the tensor-product spline and the serendipity quad contain it
        let exact = 0.235 * (2.0 - 5.0 * 0.025);
        let got = w.dot(&u);
        assert!((got - exact).abs() < 1e-12, "{how:?}: {got} vs {exact}");
        let mut ones = vec![0.0; n];
        for (node, dofs) in beam.dofs.iter().enumerate() {
            if let Some(d) = dofs[1] {
                ones[d] = beam.nodes[node][0] / 0.235;
            }
        }
        assert!((w.dot(&ones) - 1.0).abs() < 1e-12, "{how:?}");
    }
}

/// Without contact, the structure started in its first clamped mode (from the modal analysis)
/// vibrates at the modal analysis's first frequency: Newmark's period error `(omega h)^2 / 12`
/// is 2e-5 at 400 steps per period; the crossings are found to 1e-6 of the period by linear
/// interpolation.
#[test]
fn free_vibration_at_first_modal_frequency() {
    let text = coarse_spec();
    let spec = flexmbs_io::model::parse_fe_model(&text, Path::new("coarse.toml"))
        .unwrap()
        .body;
    let prepared = flexmbs_reduce::pipeline::prepare(&spec, Path::new("."), &mut |_| {}).unwrap();
    let reduced = flexmbs_reduce::pipeline::run_reduction(&spec, &prepared, &mut |_| {}).unwrap();
    let f1 = reduced.frequencies_hz[0];
    let beam = coarse();
    let n = beam.k.nrows();
    let mut v0 = vec![0.0; n];
    for (node, dofs) in beam.dofs.iter().enumerate() {
        assert_eq!(reduced.nodes[node], beam.nodes[node]);
        for (dir, d) in dofs.iter().enumerate() {
            if let Some(d) = d {
                v0[*d] = reduced.modes_t[(3 * node + dir, 0)];
            }
        }
    }
    let mut probe = vec![0.0; n];
    probe[y_dof_at(&beam, [0.25, 0.05, 0.025]).unwrap()] = 1.0;
    let w = coarse_weights(&beam, Interpolation::Nurbs);
    let h = 1.0 / (400.0 * f1);
    let mut p = penalty_setup(h, 3.2 / f1);
    p.y0 = 1.0; // the mass far away: no contact
    p.v0 = 0.0;
    let r = simulate_penalty_impact_from(&beam.k, &beam.m, &w, &probe, &p, Some(&v0)).unwrap();
    assert!(r.force.iter().all(|&f| f == 0.0));
    // u = phi sin(omega t): zero crossings at multiples of T / 2
    let crossings: Vec<f64> = (1..r.t.len())
        .filter(|&i| r.probe[i - 1] * r.probe[i] < 0.0)
        .map(|i| {
            let (a, b) = (r.probe[i - 1], r.probe[i]);
            r.t[i - 1] + h * a / (a - b)
        })
        .collect();
    assert!(crossings.len() >= 6, "{} crossings", crossings.len());
    let period =
        2.0 * (crossings[crossings.len() - 1] - crossings[0]) / (crossings.len() - 1) as f64;
    let rel = (1.0 / period - f1).abs() / f1;
    assert!(rel < 1e-4, "f {} vs modal {f1}: {rel:e}", 1.0 / period);
    // energy of the linear trapezoidal rule: conserved to round-off
    assert!(r.energy_error < 1e-10, "energy error {:e}", r.energy_error);
}

/// The impact with the penalty law: the total energy (kinetic + elastic + penalty) is conserved
/// up to the error of the contact switching, which shrinks with the step.
#[test]
fn penalty_impact_energy_shrinks_with_step() {
    let beam = coarse();
    let n = beam.k.nrows();
    let w = coarse_weights(&beam, Interpolation::Nurbs);
    let probe = vec![0.0; n];
    let errors: Vec<f64> = [2e-5, 1e-5, 5e-6]
        .iter()
        .map(|&h| {
            simulate_penalty_impact(&beam.k, &beam.m, &w, &probe, &penalty_setup(h, 0.03))
                .unwrap()
                .energy_error
        })
        .collect();
    // measured: 19 (!), 1.2e-3, 4.8e-4: at 2e-5 s the stiff penalty oscillation of the
    // surface (omega h of order 1) pumps energy at the switches
    assert!(errors[2] < 1e-3, "{errors:?}");
    assert!(errors[1] < errors[0] && errors[2] < errors[1], "{errors:?}");
}

fn log(s: &str) {
    println!("{s}");
}

/// The mode study (10 ... 200 modes, FFR S4 and the reference's integrator on the modal basis,
/// h = 1e-5 s, 0.1 s); writes the `node_full_fe` and `mass_full_fe` plots into the case's folder.
/// Tens of minutes on a busy 2-core machine.
#[test]
#[ignore = "study behind the README table: 6 FFR runs up to 200 modes and the full FE, tens of minutes; not part of CI"]
fn full_fe_mode_study() {
    let beam = reduce_beam_with(200).unwrap();
    let out = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../validation/point_mass_on_beam");
    let counts = [10, 20, 40, 60, 100, 200];
    let rows = mode_study(&beam, &counts, 1e-5, &out, &log).unwrap();
    println!("{}", rows.join("\n"));
}

/// The step study of the reference (h = 1e-5, 5e-6, 2.5e-6 s and the hex20 face weights at
/// 1e-5 s, to 0.035 s: the contact phase up to past the largest deflection).
#[test]
#[ignore = "step study of the full-FE reference down to h = 2.5e-6 s, several minutes; not part of CI"]
fn full_fe_step_study() {
    let rows = step_study(1e-5, 0.035, &log).unwrap();
    println!("{}", rows.join("\n"));
}
