//! The C^2 check of `sliding_balls` on a curved contour: a light ball kept on the neutral axis of
//! a stiff quarter ring (an FFR body of beam elements, clamped at one end) slides along it at
//! constant speed, so its acceleration is the centripetal `v^2 / R` and turns smoothly with the
//! ball. A contour through the nodes that is only C^0 (degree 1: a polygon) turns the velocity
//! in jumps at the nodes (an impact at each kink), one that is only C^1 (degree 2) changes the
//! curvature, hence the guide's force, in jumps; the cubic contour (C^2) does neither.
//!
//! The checks, on the step-to-step change of the ball's discrete acceleration (relative to
//! `v0^2 / R`): (1) at most [`JUMP_TOLERANCE`] for the cubic contour, which the polygon must fail
//! (fixed before the first run: a velocity jump); (2) at most [`TURNING_FACTOR`] times the turning
//! of the acceleration per step, `v h / R`, for the cubic contour, which the quadratic contour must
//! fail (set after the first runs had shown that (1) does not see a C^1 contour: README). The
//! straight beam of `sliding_balls` cannot show either: its deflection turns the axis by about
//! 1e-5 rad per element, and the velocity jumps at the kinks of a polygon axis are far below the
//! ball's accelerations from the beam's vibration there.

use crate::ValidationResult;
use anyhow::{Context, Result};
use flexmbs_core::contact::{CurveGuide, NeutralCurve};
use flexmbs_core::ffr::contour::{ContourSettings, FfrCurveContour};
use flexmbs_core::ffr::{FfrBody, FfrElement, RotationParam};
use flexmbs_core::integrator::{drive, MoreauSettings, MoreauStepper, StepControl, Stepper};
use flexmbs_core::{BodyId, Joint, ModelSpec, RigidBody, Workspace};
use flexmbs_fe::reduction::ReducedBody;
use nalgebra::{Matrix3, Vector3};
use std::ops::ControlFlow;
use std::path::Path;

/// Radius of the ring's axis (m).
pub const RADIUS: f64 = 0.5;
/// Beam elements along the quarter ring (5.625 deg each).
pub const ELEMENTS: usize = 16;
/// The ball's mass (kg): light against the ring (12.6 kg), so that the ring's vibration under
/// the moving load stays small against the curvature jumps of a quadratic contour (with 10 g the
/// vibration's acceleration jumps, 1.2e-3 of `v0^2 / R`, hid them).
pub const BALL_MASS: f64 = 0.001;
/// The ball's initial speed along the ring (m/s).
pub const SPEED: f64 = 1.0;
/// Fixed Moreau step (s).
pub const STEP: f64 = 1e-4;
/// Largest step-to-step change of the ball's acceleration, relative to `SPEED^2 / RADIUS`; fixed
/// before the first run (with the first run's step of 1 ms, five times the turning of the
/// acceleration per step).
pub const JUMP_TOLERANCE: f64 = 0.01;
/// Largest step-to-step change of the ball's acceleration in multiples of its turning per step,
/// `SPEED * STEP / RADIUS` (set after the first runs: measured 1.05 for the cubic contour, 3.3 for
/// the quadratic one).
pub const TURNING_FACTOR: f64 = 2.0;

/// Angle of node `i` (rad): elements of 3.75 and 7.5 deg in turn (a graded mesh: on a uniform
/// mesh of a circle the curvature jumps of a quadratic contour are too small to see).
pub fn node_angle(i: usize) -> f64 {
    let a = std::f64::consts::FRAC_PI_2 / (1.5 * ELEMENTS as f64);
    a * (i + i / 2) as f64
}

/// The CalculiX deck of the quarter ring: B31 elements on `(R sin t, R (1 - cos t), 0)`,
/// `t = 0 .. pi/2`, steel 40 x 40 mm, node set `CLAMP` at `t = 0`.
pub fn arc_deck() -> String {
    let mut d = String::from("*NODE\n");
    for i in 0..=ELEMENTS {
        let t = node_angle(i);
        let (x, y) = (RADIUS * t.sin(), RADIUS * (1.0 - t.cos()));
        d += &format!("{}, {x:.15e}, {y:.15e}, 0.0\n", i + 1);
    }
    d += "*ELEMENT, TYPE=B31, ELSET=EALL\n";
    for e in 1..=ELEMENTS {
        d += &format!("{e}, {e}, {}\n", e + 1);
    }
    d += "*NSET, NSET=CLAMP\n1\n*MATERIAL, NAME=STEEL\n*ELASTIC\n210e9, 0.3\n*DENSITY\n7850.\n";
    d += "*BEAM SECTION, ELSET=EALL, MATERIAL=STEEL, SECTION=RECT\n0.04, 0.04\n0., 0., 1.\n";
    d
}

/// The FE body of the ring (6 clamped modes, lumped mass: the FFR body's consistent-mass
/// invariants need the translational mass blocks of solid elements).
const ARC_BODY: &str = r#"
[body]
name = "ring"
units = "SI"

[body.mesh]
type = "calculix"
deck = "arc.inp"
matrices = "flexmbs"

[body.boundary]
fixed = ["CLAMP"]

[body.reduction]
method = "modal"
modes = 6
mass = "lumped"
"#;

/// The reduced ring.
pub struct Ring {
    /// 6 clamped modes.
    pub reduced: ReducedBody,
    /// The beam nodes' rotary inertias (SI), as a multibody model applies them.
    pub rotary: Vec<Matrix3<f64>>,
}

/// Writes the deck (`arc.inp`) into `dir` (created) and reduces the ring.
pub fn reduce_ring(dir: &Path) -> Result<Ring> {
    std::fs::create_dir_all(dir)?;
    std::fs::write(dir.join("arc.inp"), arc_deck())?;
    let file = dir.join("arc.toml");
    let spec = flexmbs_io::model::parse_fe_model(ARC_BODY, &file)?.body;
    let prepared = flexmbs_reduce::pipeline::prepare(&spec, dir, &mut |_| {})?;
    let reduced = flexmbs_reduce::pipeline::run_reduction(&spec, &prepared, &mut |_| {})?;
    let rotary =
        flexmbs_reduce::full_mass::beam_node_rotary_inertias(&prepared.mesh, reduced.nodes.len())
            .map_err(anyhow::Error::msg)?
            .context("the ring's beam nodes carry rotations")?;
    Ok(Ring { reduced, rotary })
}

/// What a run on the ring gives.
#[derive(Debug, Clone, Default)]
pub struct ArcRun {
    /// Degree of the axis contour.
    pub degree: usize,
    /// Largest |a_k - a_(k-1)| / (v0^2 / R) over the steps, `a_k = (v_k - v_(k-1)) / ((h_(k-1) +
    /// h_k) / 2)` (the last step is shorter).
    pub jump_max: f64,
    /// Largest | |a_k| - v_k^2 / R | / (v0^2 / R): how well the contour's curvature is the ring's.
    pub curvature_dev_max: f64,
    /// 1 - |v_end| / v0: speed lost (a polygon loses it at each kink).
    pub speed_loss: f64,
    /// (angle of the ball along the ring in degrees, |a| / (v0^2 / R)) every step.
    pub acceleration: Vec<(f64, f64)>,
    /// Steps.
    pub steps: usize,
}

/// The ball on the ring with an axis contour of `degree`: from the node at 11.25 deg, along the
/// ring at [`SPEED`] to 78.75 deg (12 elements), fixed Moreau steps of [`STEP`].
pub fn simulate_arc(ring: &Ring, degree: usize) -> Result<ArcRun> {
    let mut ffr = FfrBody::from_reduced(&ring.reduced, RotationParam::Cardan)?;
    ffr.set_rotary_inertia(&ring.rotary)?;
    let nodes = &ring.reduced.nodes;
    let angle = |p: &[f64; 3]| p[0].atan2(RADIUS - p[1]);
    let mut line: Vec<usize> = (0..nodes.len()).collect();
    line.sort_by(|&a, &b| angle(&nodes[a]).total_cmp(&angle(&nodes[b])));
    let settings = ContourSettings {
        degree,
        ..ContourSettings::default()
    };
    let curve = FfrCurveContour::new(&ffr, &line, settings).context("ring axis curve")?;
    let mut spec = ModelSpec::new();
    let b = spec.add_body("ring", FfrElement::new(ffr));
    let fb = spec.add_frame("ring", b, Vector3::zeros(), Matrix3::identity());
    let fg = spec.add_ground_frame("ground", Vector3::zeros(), Matrix3::identity());
    spec.add_joint(Joint::fixed("clamp", fg, fb));
    let m = spec.add_body(
        "ball",
        RigidBody::new(BALL_MASS, Matrix3::identity() * 1e-8),
    );
    let fm = spec.add_frame("ball", m, Vector3::zeros(), Matrix3::identity());
    let axis = NeutralCurve::new(fb, curve, 0.0)?;
    spec.add_guide(CurveGuide::new("guide", axis, fm, Vector3::z(), false));
    let model = spec.compile()?;
    let m = BodyId(1);
    let t0 = node_angle(2);
    let mut s = model.initial_state();
    let p0 = Vector3::new(RADIUS * t0.sin(), RADIUS * (1.0 - t0.cos()), 0.0);
    model.set_body_pose(&mut s, m, p0, Matrix3::identity());
    let v0 = SPEED * Vector3::new(t0.cos(), t0.sin(), 0.0);
    model.set_body_velocity(&mut s, m, v0, Vector3::zeros());
    let mut ws = Workspace::new(&model);
    let mut stepper = MoreauStepper::new(MoreauSettings::default());
    stepper.set_end_monitor(false);
    stepper.initialize(&model, &mut s, &mut ws)?;
    let a0 = SPEED * SPEED / RADIUS;
    let mut run = ArcRun {
        degree,
        ..ArcRun::default()
    };
    let (mut v_prev, mut a_prev): (Vector3<f64>, Option<Vector3<f64>>) = (v0, None);
    let mut h_prev = STEP;
    let t_end = (node_angle(ELEMENTS - 2) - t0) * RADIUS / SPEED;
    drive(
        &mut stepper,
        &model,
        &mut s,
        &mut ws,
        StepControl::Fixed { h: STEP },
        t_end,
        |s, st| {
            run.steps += 1;
            let q = model.body_q(m, &s.q);
            let v = Vector3::from_column_slice(&model.body_u(m, &s.u)[..3]);
            // Moreau's velocity at the end of a step follows the contour's tangent at the step's
            // midpoint: successive velocities are half a step before and after a step end
            let a = (v - v_prev) / (0.5 * (h_prev + st.h));
            (v_prev, h_prev) = (v, st.h);
            // the first step takes up the start's mismatch with the guide (none here: the ball
            // starts on a node, with the ring's tangent velocity); it is still left out
            if run.steps > 1 {
                if let Some(ap) = a_prev {
                    run.jump_max = run.jump_max.max((a - ap).norm() / a0);
                }
                a_prev = Some(a);
                let dev = (a.norm() - v.norm_squared() / RADIUS).abs() / a0;
                run.curvature_dev_max = run.curvature_dev_max.max(dev);
                let theta = q[0].atan2(RADIUS - q[1]).to_degrees();
                run.acceleration.push((theta, a.norm() / a0));
            }
            ControlFlow::Continue(())
        },
    )?;
    run.speed_loss = 1.0 - v_prev.norm() / SPEED;
    Ok(run)
}

/// Runs degrees 1, 2, 3 and records the checks (module documentation): the cubic contour passes
/// both, the polygon must fail the first and the quadratic contour the second (otherwise the
/// checks cannot fail). Returns the runs.
pub fn check_arc(
    res: &mut ValidationResult,
    dir: &Path,
    log: &dyn Fn(&str),
) -> Result<Vec<ArcRun>> {
    let ring = reduce_ring(dir).context("reducing the quarter ring")?;
    let turning = SPEED * STEP / RADIUS;
    let mut runs = Vec::new();
    for degree in [1, 2, 3] {
        let r = simulate_arc(&ring, degree)?;
        log(&format!(
            "quarter ring, contour degree {degree}: largest acceleration jump {:.3e} of v0^2/R \
             ({:.2} x the turning per step), curvature deviation {:.3e}, speed loss {:.3e}, {} \
             steps",
            r.jump_max,
            r.jump_max / turning,
            r.curvature_dev_max,
            r.speed_loss,
            r.steps
        ));
        res.record(&format!("arc_jump_max_degree{degree}"), r.jump_max);
        res.record(
            &format!("arc_jump_turning_degree{degree}"),
            r.jump_max / turning,
        );
        res.record(
            &format!("arc_curvature_dev_degree{degree}"),
            r.curvature_dev_max,
        );
        res.record(&format!("arc_speed_loss_degree{degree}"), r.speed_loss);
        runs.push(r);
    }
    res.limit(
        "arc_no_velocity_jumps_degree3",
        runs[2].jump_max,
        JUMP_TOLERANCE,
    );
    res.limit(
        "arc_no_force_jumps_degree3",
        runs[2].jump_max / turning,
        TURNING_FACTOR,
    );
    // the checks must see the kinks of a polygon and the curvature jumps of a quadratic contour
    for (name, detected) in [
        (
            "arc_check_detects_degree1",
            runs[0].jump_max > JUMP_TOLERANCE,
        ),
        (
            "arc_check_detects_degree2",
            runs[1].jump_max / turning > TURNING_FACTOR,
        ),
    ] {
        res.record(name, f64::from(u8::from(detected)));
        if !detected {
            res.fail(name);
        }
    }
    Ok(runs)
}
