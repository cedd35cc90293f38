//! A flexible pendulum written against the public Rust API of `flexmbs-fe` and `flexmbs-core`.
//!
//! A 1 m steel bar (10 mm x 30 mm, the 10 mm side in the swing plane) is meshed with 20
//! Euler-Bernoulli beam elements, clamped at its first node and reduced to its 5 lowest
//! cantilever modes. It enters the multibody model as a floating-frame-of-reference (FFR) body
//! whose reference frame sits at the clamped node; a revolute joint (axis z) hinges that point to
//! ground. Released at rest in the horizontal position under gravity (-y), it is integrated for
//! 1 s with generalized-alpha. A rigid body with the same mass, centre of mass and inertia is
//! hinged the same way in a second model (the "rigid twin").
//!
//! Printed: energy drift relative to the peak kinetic energy, the largest constraint violation,
//! the range of the elastic tip deflection (body frame y) and the swing angles at t = 1 s.
//! Exits with an error (non-zero status) if the energy drift exceeds 1e-3 of the peak kinetic
//! energy or the constraint violation exceeds 1e-8 m (a CI check).
//!
//! Run: `cargo run --release -p flexmbs-core --example flexible_pendulum`

use flexmbs_core::ffr::{diagonal_inertia, FfrBody, FfrElement};
use flexmbs_core::integrator::{monitor, GenAlpha, GenAlphaSettings};
use flexmbs_core::system::evaluate;
use flexmbs_core::{BodyId, FrameId, Joint, Model, ModelSpec, RigidBody, State, Workspace};
use flexmbs_fe::constraint::BoundaryConditions;
use flexmbs_fe::eigen::EigenOptions;
use flexmbs_fe::element::MassKind;
use flexmbs_fe::mesh::generate::beam_line;
use flexmbs_fe::mesh::{BeamSection, BeamTheory};
use flexmbs_fe::reduction::{modal_analysis, reduce_modal, Provenance, ReducedBody};
use flexmbs_fe::system::FeSystem;
use flexmbs_fe::{Material, UnitSystem};
use nalgebra::{Matrix3, Vector3};
use std::error::Error;

/// Bar length (m).
const LENGTH: f64 = 1.0;
/// Section width in the swing plane (local y = global y, m).
const WIDTH: f64 = 0.010;
/// Section height out of the swing plane (local z = global z, m).
const HEIGHT: f64 = 0.030;
/// Number of beam elements.
const N_ELEMENTS: usize = 20;
/// Number of kept cantilever modes.
const N_MODES: usize = 5;
/// Simulated time (s) and step (s).
const T_END: f64 = 1.0;
const STEP: f64 = 1e-3;
/// CI limits.
const MAX_ENERGY_DRIFT: f64 = 1e-3;
const MAX_CONSTRAINT_VIOLATION: f64 = 1e-8;

/// What one simulation reports.
struct RunSummary {
    /// Largest |E(t) - E(0)| over the run (J).
    energy_drift: f64,
    /// Largest kinetic energy over the run (J).
    peak_kinetic: f64,
    /// Largest |g| over the run (m for the translational rows).
    max_violation: f64,
    /// Cardan angle gamma (rotation about z) of the body reference frame at the end (rad).
    final_angle: f64,
    /// Smallest and largest elastic tip deflection along body y (m); zero for a rigid body.
    tip_range: (f64, f64),
    /// Global tip position at the end.
    final_tip: Vector3<f64>,
}

fn main() -> Result<(), Box<dyn Error>> {
    let steel = Material::steel();
    let section = BeamSection::rectangle(WIDTH, HEIGHT);

    // --- FE model and modal reduction (flexmbs-fe) ---
    let mesh = beam_line(
        [0.0; 3],
        [LENGTH, 0.0, 0.0],
        N_ELEMENTS,
        section,
        BeamTheory::EulerBernoulli,
        [0.0, 1.0, 0.0],
        steel,
        UnitSystem::Si,
    )?;
    let hinge_node = mesh.node_set("start")?[0];
    let tip_node = mesh.node_set("end")?[0];
    let bc = BoundaryConditions {
        fixed: vec![hinge_node],
        ..Default::default()
    };
    let sys = FeSystem::assemble(&mesh, &bc, MassKind::Lumped, &mut |_, _| {})?;
    let modal = modal_analysis(&sys, N_MODES, &EigenOptions::default(), &mut |_| {})?;
    let reduced: ReducedBody = reduce_modal(
        &mesh,
        &sys,
        &modal,
        N_MODES,
        "bar",
        Provenance {
            source: "examples/flexible_pendulum.rs".into(),
            ..Default::default()
        },
    )?;
    println!(
        "FE model: {} nodes, {} free DOFs; kept cantilever modes (Hz): {}",
        mesh.num_nodes(),
        sys.len(),
        reduced
            .frequencies_hz
            .iter()
            .zip(&reduced.labels)
            .map(|(f, l)| format!("{f:.2} ({})", l.dominant))
            .collect::<Vec<_>>()
            .join(", ")
    );

    // --- FFR body (flexmbs-core) ---
    // The mesh is already in SI, so `reduced_body_to_si` is not needed.
    let mut ffr = FfrBody::from_reduced(&reduced, flexmbs_core::ffr::RotationParam::Cardan)?;
    // Lumped node masses lie on the beam axis, so without node rotary inertia the inertia about
    // the bar axis would be zero (a singular mass matrix). Give every node the rotary inertia of
    // its share of the bar: rho * l_j * (I_y + I_z, I_y, I_z) about the body (= beam) axes.
    let node_inertia: Vec<Matrix3<f64>> = (0..reduced.num_nodes())
        .map(|j| {
            let share = if j == hinge_node || j == tip_node {
                0.5
            } else {
                1.0
            };
            let l = share * LENGTH / N_ELEMENTS as f64;
            let rho_l = steel.rho * l;
            diagonal_inertia(Vector3::new(
                rho_l * (section.iy + section.iz),
                rho_l * section.iy,
                rho_l * section.iz,
            ))
        })
        .collect();
    ffr.set_rotary_inertia(&node_inertia)?;

    // Rigid twin: same mass, centre of mass and inertia (undeformed) as the FFR body.
    let props = ffr.rigid_properties();
    let (mass, com, i_origin, i_com) = (
        props.mass,
        props.center_of_mass,
        props.inertia_origin,
        props.inertia_center,
    );
    println!(
        "bar: mass {mass:.4} kg, centre of mass x = {:.4} m, I_zz about the hinge {:.5} kg m^2",
        com.x,
        i_origin[(2, 2)]
    );

    let gravity = Vector3::new(0.0, -9.81, 0.0);
    let tip_u0 = Vector3::from(reduced.nodes[tip_node]);

    // Flexible model: FFR body, reference frame at the hinge node (the clamped node of the modes).
    let mut spec = ModelSpec::new();
    spec.set_gravity(gravity);
    let bar = spec.add_body("bar", FfrElement::new(ffr));
    let ground = spec.add_ground_frame("pivot", Vector3::zeros(), Matrix3::identity());
    let hinge = spec.add_frame("hinge", bar, Vector3::zeros(), Matrix3::identity());
    let flex_tip = spec.add_node_frame("tip", bar, tip_node, tip_u0);
    spec.add_joint(Joint::revolute("hinge", ground, hinge));
    let flexible = spec.compile()?;

    // Rigid twin: reference point = centre of mass, the hinge frame at -com in body axes.
    let mut spec = ModelSpec::new();
    spec.set_gravity(gravity);
    let twin = spec.add_body("twin", RigidBody::new(mass, i_com));
    let ground = spec.add_ground_frame("pivot", Vector3::zeros(), Matrix3::identity());
    let hinge = spec.add_frame("hinge", twin, -com, Matrix3::identity());
    let twin_tip = spec.add_frame("tip", twin, tip_u0 - com, Matrix3::identity());
    spec.add_joint(Joint::revolute("hinge", ground, hinge));
    let rigid = spec.compile()?;
    let mut rigid_start = rigid.initial_state();
    rigid.set_body_pose(&mut rigid_start, twin, com, Matrix3::identity());

    let flexible_start = flexible.initial_state();
    let modes_tip_y: Vec<f64> = {
        // Row of the tip's y translation in the (SI) translational modes, to read the elastic
        // deflection q_f -> u_tip,y.
        let phi = &reduced.modes_t;
        (0..reduced.num_modes())
            .map(|k| phi[(3 * tip_node + 1, k)])
            .collect()
    };
    let flex = simulate(&flexible, flexible_start, bar, flex_tip, Some(&modes_tip_y))?;
    let rig = simulate(&rigid, rigid_start, twin, twin_tip, None)?;

    let report = |name: &str, r: &RunSummary| {
        println!(
            "{name}: energy drift / peak kinetic energy = {:.2e} (peak {:.4} J), max |g| = {:.2e}, \
             swing angle at t = {T_END} s: {:.3} deg (tip at x = {:.4}, y = {:.4} m)",
            r.energy_drift / r.peak_kinetic,
            r.peak_kinetic,
            r.max_violation,
            r.final_angle.to_degrees(),
            r.final_tip.x,
            r.final_tip.y
        )
    };
    report("flexible", &flex);
    report("rigid twin", &rig);
    let reference = rigid_pendulum_angle(mass * gravity.norm() * com.x / i_origin[(2, 2)], T_END);
    println!(
        "rigid twin vs 1-DOF pendulum ODE (RK4, 1e-5 s): {:.2e} deg",
        (rig.final_angle - reference).to_degrees()
    );
    println!(
        "tip elastic deflection (body y): {:.3} mm .. {:.3} mm",
        flex.tip_range.0 * 1e3,
        flex.tip_range.1 * 1e3
    );
    println!(
        "swing angle flexible - rigid at t = {T_END} s: {:.3} deg (reference frame), tip chord: {:.3} deg",
        (flex.final_angle - rig.final_angle).to_degrees(),
        (chord_angle(&flex.final_tip) - chord_angle(&rig.final_tip)).to_degrees()
    );

    for (name, r) in [("flexible", &flex), ("rigid twin", &rig)] {
        if r.energy_drift > MAX_ENERGY_DRIFT * r.peak_kinetic {
            return Err(format!(
                "{name}: energy drift {:.3e} J exceeds {MAX_ENERGY_DRIFT:e} of the peak kinetic energy {:.3e} J",
                r.energy_drift, r.peak_kinetic
            )
            .into());
        }
        if r.max_violation > MAX_CONSTRAINT_VIOLATION {
            return Err(format!(
                "{name}: constraint violation {:.3e} m exceeds {MAX_CONSTRAINT_VIOLATION:e} m",
                r.max_violation
            )
            .into());
        }
    }
    println!("OK: energy drift < {MAX_ENERGY_DRIFT:e} of the peak kinetic energy, |g| < {MAX_CONSTRAINT_VIOLATION:e} m");
    Ok(())
}

/// Independent reference for the rigid twin: `theta'' = -w0^2 cos(theta)` (angle from the
/// horizontal +x axis, gravity -y, `w0^2 = m g c / I_hinge`), released at rest from 0,
/// integrated with classical RK4 and step 1e-5 s.
fn rigid_pendulum_angle(w0_sq: f64, t_end: f64) -> f64 {
    let rhs = |th: f64, om: f64| (om, -w0_sq * th.cos());
    let n = (t_end / 1e-5).round() as usize;
    let h = t_end / n as f64;
    let (mut th, mut om) = (0.0_f64, 0.0_f64);
    for _ in 0..n {
        let k1 = rhs(th, om);
        let k2 = rhs(th + 0.5 * h * k1.0, om + 0.5 * h * k1.1);
        let k3 = rhs(th + 0.5 * h * k2.0, om + 0.5 * h * k2.1);
        let k4 = rhs(th + h * k3.0, om + h * k3.1);
        th += h / 6.0 * (k1.0 + 2.0 * k2.0 + 2.0 * k3.0 + k4.0);
        om += h / 6.0 * (k1.1 + 2.0 * k2.1 + 2.0 * k3.1 + k4.1);
    }
    th
}

/// Angle of the hinge-to-tip chord from the +x axis (rad), continuous through -180 deg.
fn chord_angle(tip: &Vector3<f64>) -> f64 {
    let a = tip.y.atan2(tip.x);
    if a > 0.5 * std::f64::consts::PI {
        a - 2.0 * std::f64::consts::PI
    } else {
        a
    }
}

/// Integrates `model` from `state` to [`T_END`] with fixed-step generalized-alpha and collects
/// the monitors. `tip` is a frame at the tip; `modes_tip_y` the
/// tip's y rows of the modes (flexible body only: the modal coordinates follow the 3 Cardan
/// angles in the body's `q`).
fn simulate(
    model: &Model,
    mut state: State,
    body: BodyId,
    tip: FrameId,
    modes_tip_y: Option<&[f64]>,
) -> Result<RunSummary, Box<dyn Error>> {
    let mut ws = Workspace::new(model);
    let integrator = GenAlpha::new(GenAlphaSettings::default())?;
    integrator.initialize(model, &mut state, &mut ws)?;
    let (e0, g0, _) = monitor(model, &state, &mut ws);
    let mut summary = RunSummary {
        energy_drift: 0.0,
        peak_kinetic: e0.kinetic,
        max_violation: g0,
        final_angle: 0.0,
        tip_range: (0.0, 0.0),
        final_tip: Vector3::zeros(),
    };
    let n_steps = (T_END / STEP).round() as usize;
    for _ in 0..n_steps {
        let stats = integrator.step(model, &mut state, &mut ws, STEP)?;
        summary.energy_drift = summary
            .energy_drift
            .max((stats.energy.total() - e0.total()).abs());
        summary.peak_kinetic = summary.peak_kinetic.max(stats.energy.kinetic);
        summary.max_violation = summary.max_violation.max(stats.g_max);
        if let Some(rows) = modes_tip_y {
            let q_f = &model.body_q(body, &state.q)[6..];
            let w: f64 = rows.iter().zip(q_f).map(|(p, q)| p * q).sum();
            summary.tip_range = (summary.tip_range.0.min(w), summary.tip_range.1.max(w));
        }
    }
    // Body q = [R (3), Cardan x-y-z (3), q_f]: planar motion about z, so gamma is the swing angle.
    let q = model.body_q(body, &state.q);
    summary.final_angle = q[5];
    evaluate(model, &state.q, &state.u, &mut ws.sys).unwrap();
    summary.final_tip = ws.sys.frames[tip.index()].position;
    Ok(summary)
}
