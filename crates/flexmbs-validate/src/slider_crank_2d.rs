//! `slider_crank_2d` (seed 001 §5.1): rigid crank 0.15 m at a prescribed 150 rad/s, flexible
//! connecting rod 0.3 m (solid circle 6 mm, E = 200 GPa, rho = 7870 kg/m^3) as ONE FFR body with
//! free-free beam modes, slider of half the rod mass on a frictionless prismatic joint, gravity 0.
//! Lagrange-multiplier joints at the rod's end-node frames. Output: the rod midpoint deflection
//! perpendicular to the pin-slider chord over 4 revolutions. The reference (10+ superelements)
//! comes with the superelement issue; until then no quantity has a reference.

use crate::ValidationResult;
use anyhow::{Context, Result};
use flexmbs_core::ffr::{FfrBody, FfrElement, RotationParam as FfrRot};
use flexmbs_core::integrator::{GenAlpha, GenAlphaSettings};
use flexmbs_core::{
    FrameKinematics, Joint, LocalFrame, ModelSpec, PrescribedMotion, RigidBody, TimeFunction,
    Workspace,
};
use flexmbs_fe::constraint::BoundaryConditions;
use flexmbs_fe::eigen::EigenOptions;
use flexmbs_fe::element::MassKind;
use flexmbs_fe::mesh::generate::beam_line;
use flexmbs_fe::mesh::{BeamSection, BeamTheory};
use flexmbs_fe::reduction::{modal_analysis, reduce_modal, Provenance};
use flexmbs_fe::system::FeSystem;
use flexmbs_fe::{Material, UnitSystem};
use flexmbs_io::plot::{LinePlot, Series, Style};
use nalgebra::{Matrix3, Vector3};
use std::f64::consts::PI;
use std::path::Path;

const CRANK: f64 = 0.15;
const ROD: f64 = 0.3;
const OMEGA: f64 = 150.0;
const ELEMENTS: usize = 20;

/// Simulates 4 revolutions with `modes` free-free rod modes; returns (crank angle, w_mid) samples and
/// the largest position-constraint violation.
pub fn simulate(modes: usize, h: f64) -> Result<(Vec<(f64, f64)>, f64)> {
    let material = Material {
        e: 200e9,
        nu: 0.3,
        rho: 7870.0,
    };
    let mesh = beam_line(
        [0.0; 3],
        [ROD, 0.0, 0.0],
        ELEMENTS,
        BeamSection::circle(0.006),
        BeamTheory::EulerBernoulli,
        [0.0, 1.0, 0.0],
        material,
        UnitSystem::Si,
    )?;
    let sys = FeSystem::assemble(
        &mesh,
        &BoundaryConditions::default(),
        MassKind::Lumped,
        &mut |_, _| {},
    )?;
    let modal = modal_analysis(&sys, modes, &EigenOptions::default(), &mut |_| {})?;
    let body = reduce_modal(&mesh, &sys, &modal, modes, "rod", Provenance::default())?;
    let rod_mass: f64 = body
        .node_masses
        .as_ref()
        .context("lumped rod masses")?
        .iter()
        .sum();
    let rod = FfrElement::new(FfrBody::from_reduced(&body, FfrRot::Cardan)?);

    let mut spec = ModelSpec::new();
    let i3 = Matrix3::identity();
    let crank = spec.add_body(
        "crank",
        RigidBody::new(0.1, Matrix3::from_diagonal(&Vector3::new(1e-5, 2e-4, 2e-4))),
    );
    let rod_id = spec.add_body("rod", rod);
    let slider = spec.add_body("slider", RigidBody::new(0.5 * rod_mass, i3 * 1e-6));
    let g0 = spec.add_ground_frame("pivot", Vector3::zeros(), i3);
    let gs = spec.add_ground_frame("guide", Vector3::zeros(), i3);
    let c0 = spec.add_frame(
        "crank pivot",
        crank,
        Vector3::new(-CRANK / 2.0, 0.0, 0.0),
        i3,
    );
    let c1 = spec.add_frame("crank pin", crank, Vector3::new(CRANK / 2.0, 0.0, 0.0), i3);
    let r0 = spec.add_node_frame("rod A", rod_id, 0, Vector3::zeros());
    let r1 = spec.add_node_frame("rod B", rod_id, ELEMENTS, Vector3::new(ROD, 0.0, 0.0));
    let s0 = spec.add_frame("slider", slider, Vector3::zeros(), i3);
    spec.add_joint(Joint::revolute("crank drive", g0, c0).with_prescribed(
        PrescribedMotion::RevoluteRate {
            initial_angle: 0.0,
            rate: TimeFunction::Constant(OMEGA),
        },
    ));
    spec.add_joint(Joint::revolute("crank-rod", c1, r0));
    spec.add_joint(Joint::new(
        "rod-slider",
        r1,
        s0,
        [true, true, false, false, false, false],
    ));
    spec.add_joint(Joint::prismatic("slider guide", gs, s0));
    let model = spec.compile()?;
    let mut s = model.initial_state();
    // crank angle 0, rod straight along x, rigid-mechanism velocities
    model.set_body_pose(&mut s, crank, Vector3::new(CRANK / 2.0, 0.0, 0.0), i3);
    model.set_body_pose(&mut s, rod_id, Vector3::new(CRANK, 0.0, 0.0), i3);
    model.set_body_pose(&mut s, slider, Vector3::new(CRANK + ROD, 0.0, 0.0), i3);
    let w = Vector3::new(0.0, 0.0, OMEGA);
    model.set_body_velocity(
        &mut s,
        crank,
        Vector3::new(0.0, OMEGA * CRANK / 2.0, 0.0),
        w,
    );
    model.set_body_velocity(
        &mut s,
        rod_id,
        Vector3::new(0.0, OMEGA * CRANK, 0.0),
        Vector3::new(0.0, 0.0, -OMEGA * CRANK / ROD),
    );
    let mut ws = Workspace::new(&model);
    let ga = GenAlpha::new(GenAlphaSettings {
        rho_inf: 0.8,
        ..GenAlphaSettings::default()
    })?;
    ga.initialize(&model, &mut s, &mut ws)?;
    let rb = &model.bodies[rod_id.0];
    let mut fk = FrameKinematics::for_body(&model, rod_id);
    let mid = ELEMENTS / 2;
    let mut e = rb.element.new_scratch();
    let mut node_pos = |q: &[f64], u: &[f64], n: usize| {
        let f = LocalFrame {
            position: Vector3::from(body.nodes[n]),
            rotation: i3,
            mesh_node: Some(n),
        };
        if rb.element.update_kinematics(q, u, &mut e).is_err() {
            return Vector3::from_element(f64::NAN);
        }
        rb.element.frame_kinematics(q, u, &mut e, &f, &mut fk);
        fk.position
    };
    let mut out = Vec::new();
    let mut g_max: f64 = 0.0;
    let mut k = 0usize;
    ga.integrate(
        &model,
        &mut s,
        &mut ws,
        h,
        4.0 * 2.0 * PI / OMEGA,
        |st, stats| {
            k += 1;
            g_max = g_max.max(stats.g_max);
            if k.is_multiple_of(10) {
                let (q, u) = (model.body_q(rod_id, &st.q), model.body_u(rod_id, &st.u));
                let (a, b, m) = (
                    node_pos(q, u, 0),
                    node_pos(q, u, ELEMENTS),
                    node_pos(q, u, mid),
                );
                let chord = (b - a).normalize();
                let normal = Vector3::new(-chord[1], chord[0], 0.0);
                out.push((OMEGA * st.t, (m - a).dot(&normal)));
            }
        },
    )
    .context("time integration of the slider-crank")?;
    Ok((out, g_max))
}

/// Runs the case.
pub fn run(out: &Path, quiet: bool) -> Result<ValidationResult> {
    let mut res = ValidationResult::new("slider_crank_2d");
    let mut series = Vec::new();
    for modes in [2usize, 4] {
        let (w, g_max) = simulate(modes, 1e-5)?;
        let rev1: Vec<f64> = w.iter().filter(|p| p.0 <= 2.0 * PI).map(|p| p.1).collect();
        let max = rev1.iter().copied().fold(f64::MIN, f64::max);
        let min = rev1.iter().copied().fold(f64::MAX, f64::min);
        if !quiet {
            eprintln!("  FFR rod, {modes} modes: w_mid in revolution 1 in [{min:.4e}, {max:.4e}] m, max |g| {g_max:.2e}");
        }
        let suffix = if modes == 4 {
            "_ffr".to_string()
        } else {
            format!("_ffr_{modes}modes")
        };
        res.record(&format!("w_mid_max_rev1{suffix}"), max);
        res.record(&format!("w_mid_min_rev1{suffix}"), min);
        res.record(&format!("constraint_violation_max{suffix}"), g_max);
        // the only checkable property until the superelement reference exists: the index-3 position
        // constraints hold (bound fixed before the run)
        if g_max.is_nan() || g_max > 1e-8 {
            res.pass = false;
        }
        series.push(Series {
            name: format!("FFR rod, {modes} free-free modes"),
            points: w.iter().map(|p| (p.0 / (2.0 * PI), p.1 * 1e3)).collect(),
            style: Style::Line,
        });
    }
    let plot = LinePlot {
        title: "Flexible slider-crank: rod midpoint deflection".into(),
        x_label: "crank revolutions".into(),
        y_label: "w_mid [mm]".into(),
        series,
        log_x: false,
        log_y: false,
    };
    plot.write(&out.join("w_mid.png"))?;
    plot.write(&out.join("w_mid.svg"))?;
    Ok(res)
}
