//! `rotating_beam` (seed 001 §5.2), FFR part: aluminium tube (outer radius 10 mm, wall 1 mm,
//! E = 70 GPa, rho = 2700 kg/m^3, L = 1 m) hinged at its left end and driven at a constant
//! 100 rad/s about the hinge axis z; a 50 N tip force fixed in the rotating frame (direction of
//! rotation) during the first 0.01 s. Three models:
//! - linear FFR body (cantilever modes, no geometric stiffening): must oscillate at the
//!   spin-softened frequency `sqrt(omega_0^2 - Omega^2)` of its first chordwise mode (with
//!   mass-normalised modes the centrifugal term of the FFR equations adds exactly `-Omega^2`);
//! - FFR body with geometric stiffening (unit-load method, `flexmbs_fe::geometric`);
//! - the geometrically nonlinear reference: a planar finite-segment chain in minimal coordinates
//!   ([`crate::rotating_beam_reference`]), converged in the number of segments.
//!
//! - chains of 1, 2, 3, 10 superelements, floating frames at the centres of mass or at the
//!   interface points ([`crate::rotating_beam_superelement`]).
//!
//! The tip force acts at the tip node with its direction fixed in the floating (hub) frame: the
//! node frame is taken without rotational modes, so it does not follow the tip slope.

use crate::complex_beam_frequencies::zero_crossing_frequency;
use crate::rotating_beam_reference::ChainModel;
use crate::ValidationResult;
use anyhow::{Context, Result};
use flexmbs_core::ffr::{FfrBody, FfrElement, RotationParam as FfrRot};
use flexmbs_core::integrator::{GenAlpha, GenAlphaSettings};
use flexmbs_core::{
    Joint, Load, LoadCoordinates, ModelSpec, PrescribedMotion, TimeFunction, Workspace,
};
use flexmbs_fe::constraint::BoundaryConditions;
use flexmbs_fe::eigen::EigenOptions;
use flexmbs_fe::element::MassKind;
use flexmbs_fe::geometric::{geometric_stiffness, GeometricStiffness, InertialLoad};
use flexmbs_fe::mesh::generate::beam_line;
use flexmbs_fe::mesh::{BeamSection, BeamTheory};
use flexmbs_fe::reduction::{modal_analysis, reduce_modal, Provenance, ReducedBody};
use flexmbs_fe::system::FeSystem;
use flexmbs_fe::{Material, UnitSystem};
use flexmbs_io::plot::{LinePlot, Series, Style};
use nalgebra::{Matrix3, Vector3};
use std::path::Path;

const OMEGA: f64 = 100.0;
const ELEMENTS: usize = 20;
const MODES: usize = 4;
const FORCE: f64 = 50.0;
const PULSE: f64 = 0.01;
const T_END: f64 = 0.3;
const H: f64 = 2e-5;
/// Segment counts of the reference's convergence study (the last one is the reference).
pub const SEGMENTS: [usize; 4] = [10, 20, 40, 60];

/// Tip deflection history of the FFR model: `(t, w)`.
fn simulate_ffr(
    body: &ReducedBody,
    geometric: Option<&GeometricStiffness>,
) -> Result<(Vec<f64>, Vec<f64>)> {
    let tip = ELEMENTS;
    let mut ffr = FfrBody::from_reduced(body, FfrRot::Cardan)?;
    // node frame without rotational modes: the tip force keeps its direction in the hub frame
    ffr.modes_r = None;
    if let Some(g) = geometric {
        ffr = ffr.with_geometric_stiffening(g)?;
    }
    let mut spec = ModelSpec::new();
    let i3 = Matrix3::identity();
    let b = spec.add_body("tube", FfrElement::new(ffr));
    let hinge_g = spec.add_ground_frame("hinge", Vector3::zeros(), i3);
    let hinge_b = spec.add_frame("hinge", b, Vector3::zeros(), i3);
    let tip_f = spec.add_node_frame("tip", b, tip, Vector3::new(1.0, 0.0, 0.0));
    spec.add_joint(Joint::revolute("drive", hinge_g, hinge_b).with_prescribed(
        PrescribedMotion::RevoluteRate {
            initial_angle: 0.0,
            rate: TimeFunction::Constant(OMEGA),
        },
    ));
    spec.add_load(Load::Force {
        frame: tip_f,
        vector: Vector3::new(0.0, FORCE, 0.0),
        time: TimeFunction::Pulse {
            t0: 0.0,
            t1: PULSE,
            value: 1.0,
        },
        coordinates: LoadCoordinates::Frame,
    });
    let model = spec.compile()?;
    let mut s = model.initial_state();
    model.set_body_velocity(&mut s, b, Vector3::zeros(), Vector3::new(0.0, 0.0, OMEGA));
    let mut ws = Workspace::new(&model);
    let ga = GenAlpha::new(GenAlphaSettings {
        rho_inf: 0.9,
        ..GenAlphaSettings::default()
    })?;
    ga.initialize(&model, &mut s, &mut ws)?;

    let phi_tip: Vec<f64> = (0..MODES).map(|k| body.modes_t[(3 * tip + 1, k)]).collect();
    let (mut t, mut w) = (vec![0.0], vec![0.0]);
    ga.integrate(&model, &mut s, &mut ws, H, T_END, |st, _| {
        t.push(st.t);
        let qf = &model.body_q(b, &st.q)[6..];
        w.push((0..MODES).map(|k| phi_tip[k] * qf[k]).sum());
    })
    .context("time integration of the rotating beam")?;
    Ok((t, w))
}

/// First peak of the response: the extreme value before the first zero crossing after start.
pub fn first_peak(w: &[f64]) -> f64 {
    let mut peak = 0.0f64;
    for &x in w.iter().skip(1) {
        if peak != 0.0 && x * peak < 0.0 {
            break;
        }
        if x.abs() > peak.abs() {
            peak = x;
        }
    }
    peak
}

/// Angular frequency after the pulse from the zero crossings of `w` for `t > 1.05 PULSE`.
pub fn omega_after_pulse(t: &[f64], w: &[f64]) -> Option<f64> {
    let after: Vec<usize> = (0..t.len()).filter(|&i| t[i] > 1.05 * PULSE).collect();
    let ta: Vec<f64> = after.iter().map(|&i| t[i]).collect();
    let wa: Vec<f64> = after.iter().map(|&i| w[i]).collect();
    zero_crossing_frequency(&ta, &wa).map(|f| 2.0 * std::f64::consts::PI * f)
}

/// Runs the case.
pub fn run(out: &Path, quiet: bool) -> Result<ValidationResult> {
    let material = Material {
        e: 70e9,
        nu: 0.3,
        rho: 2700.0,
    };
    let section = BeamSection::tube(0.01, 0.001);
    let mesh = beam_line(
        [0.0; 3],
        [1.0, 0.0, 0.0],
        ELEMENTS,
        section,
        BeamTheory::EulerBernoulli,
        [0.0, 1.0, 0.0],
        material,
        UnitSystem::Si,
    )?;
    let bc = BoundaryConditions {
        fixed: mesh.node_set("start")?.to_vec(),
        rigid: vec![],
    };
    let sys = FeSystem::assemble(&mesh, &bc, MassKind::Lumped, &mut |_, _| {})?;
    let modal = modal_analysis(&sys, MODES, &EigenOptions::default(), &mut |_| {})?;
    let body = reduce_modal(&mesh, &sys, &modal, MODES, "tube", Provenance::default())?;
    let geo = geometric_stiffness(
        &mesh,
        &sys,
        &body,
        MassKind::Lumped,
        &InertialLoad::centrifugal(),
        &[],
    )?;
    let tip = ELEMENTS;
    // first chordwise (y) mode
    let k_y = (0..MODES)
        .max_by(|&a, &b| {
            body.modes_t[(3 * tip + 1, a)]
                .abs()
                .total_cmp(&body.modes_t[(3 * tip + 1, b)].abs())
        })
        .context("no modes")?;
    let omega0 = 2.0 * std::f64::consts::PI * body.frequencies_hz[k_y];
    let softened = (omega0 * omega0 - OMEGA * OMEGA).sqrt();

    let (t_lin, w_lin) = simulate_ffr(&body, None)?;
    let (t_geo, w_geo) = simulate_ffr(&body, Some(&geo))?;
    let omega_lin = omega_after_pulse(&t_lin, &w_lin).context("no oscillation (linear FFR)")?;
    let omega_geo = omega_after_pulse(&t_geo, &w_geo).context("no oscillation (stiffened FFR)")?;
    let (peak_lin, peak_geo) = (first_peak(&w_lin), first_peak(&w_geo));

    // reference: planar finite-segment chain, converged in the number of segments
    let mut res = ValidationResult::new("rotating_beam");
    let mut reference = None;
    let mut previous: Option<(usize, f64, f64)> = None;
    for &n in &SEGMENTS {
        let chain = ChainModel {
            n,
            length: 1.0,
            rho_a: material.rho * section.area,
            ei: material.e * section.iz,
            omega: OMEGA,
            force: FORCE,
            pulse_end: PULSE,
        };
        let run = chain
            .simulate(T_END, 1e-5, H)
            .context("reference chain: mass matrix not positive definite")?;
        let om = omega_after_pulse(&run.t, &run.w).context("no oscillation (reference)")?;
        let pk = first_peak(&run.w);
        if !quiet {
            eprintln!(
                "  reference n = {n:3}: h = {:.2e} s, peak {pk:.6} m, omega {om:.4} rad/s",
                run.h
            );
        }
        res.record(&format!("reference_tip_w_peak_n{n}"), pk);
        res.record(&format!("reference_omega_after_pulse_n{n}"), om);
        if n == SEGMENTS[SEGMENTS.len() - 1] {
            // Richardson extrapolation with the previous count (second-order chain): an estimate
            // of the remaining discretization error of the reference, recorded, not used
            if let Some((n0, pk0, om0)) = previous {
                let r = (n0 * n0) as f64 / ((n * n) as f64 - (n0 * n0) as f64);
                res.record("reference_tip_w_peak_extrapolated", pk + r * (pk - pk0));
                res.record(
                    "reference_omega_after_pulse_extrapolated",
                    om + r * (om - om0),
                );
            }
        }
        previous = Some((n, pk, om));
        reference = Some((run, pk, om));
    }
    let (ref_run, ref_peak, ref_omega) = reference.context("no reference run")?;
    if !quiet {
        eprintln!(
            "  omega_0 = {omega0:.3} rad/s; linear FFR {omega_lin:.3} rad/s (softened {softened:.3}), peak {peak_lin:.4e} m"
        );
        eprintln!(
            "  stiffened FFR {omega_geo:.3} rad/s, peak {peak_geo:.4e} m; reference {ref_omega:.3} rad/s, peak {ref_peak:.4e} m"
        );
    }
    res.record("omega_0_nonrotating", omega0);
    res.record("tip_w_peak_ffr_linear", peak_lin);
    // the period estimate from ~5 zero crossings over 0.29 s resolves the frequency to ~0.2 %;
    // generalized-alpha (h = 2e-5 s) adds ~(omega h)^2 / 12 = 1e-7
    res.check("omega_after_pulse_ffr_linear", omega_lin, softened, 5e-3);
    res.check("tip_w_peak_ffr", peak_geo, ref_peak, 0.03);
    res.check("omega_after_pulse_ffr", omega_geo, ref_omega, 0.01);
    let pts = |t: &[f64], w: &[f64]| -> Vec<(f64, f64)> {
        t.iter()
            .zip(w)
            .step_by(10)
            .map(|(a, b)| (*a, b * 1e3))
            .collect()
    };
    let n_ref = SEGMENTS[SEGMENTS.len() - 1];
    let plot = LinePlot {
        title: "Rotating tube (100 rad/s): tip deflection in the rotating frame".into(),
        x_label: "t [s]".into(),
        y_label: "w_tip [mm]".into(),
        series: vec![
            Series {
                name: "FFR, 4 modes, no geometric stiffening".into(),
                points: pts(&t_lin, &w_lin),
                style: Style::Line,
            },
            Series {
                name: "FFR, 4 modes, geometric stiffening".into(),
                points: pts(&t_geo, &w_geo),
                style: Style::Line,
            },
            Series {
                name: format!("reference: nonlinear {n_ref}-segment chain"),
                points: pts(&ref_run.t, &ref_run.w),
                style: Style::Line,
            },
        ],
        log_x: false,
        log_y: false,
    };
    plot.write(&out.join("w_tip.png"))?;
    plot.write(&out.join("w_tip.svg"))?;
    crate::rotating_beam_superelement::run_chains(
        &mut res,
        (&ref_run.t, &ref_run.w, ref_peak, ref_omega),
        H,
        T_END,
        out,
        quiet,
    )?;
    Ok(res)
}
