//! An element that cannot be evaluated at a state ends the integration with
//! `SolverError::Element`, naming the body, the time and the element's cause: a failed internal
//! solve of a test element, and a rigid body whose Cardan angles reach beta = 90 deg.

use faer::MatMut;
use flexmbs_core::integrator::{AdaptiveSettings, GenAlpha, GenAlphaSettings};
use flexmbs_core::rotation::RotationError;
use flexmbs_core::{
    Element, ElementError, ElementScratch, FrameKinematics, LocalFrame, ModelSpec, NodeKind,
    RigidBody, SolverError, Workspace,
};
use nalgebra::{Matrix3, Vector3};

/// A bead of mass `m` on the x axis held by a torsion spring `k` on a rigid arm of length `l`:
/// the bead at `x` turns the arm by `phi` with `x = l sin(phi)`, potential `1/2 k phi^2`, so the
/// generalized force is `-k phi / (l cos phi)`. `phi` is found by Newton in [`Element::update`];
/// beyond the arm's reach (`|x| > l`) there is no solution and the solve fails.
#[derive(Debug)]
struct ArmBead {
    mass: f64,
    stiffness: f64,
    length: f64,
}

impl ArmBead {
    /// `phi` with `l sin(phi) = x`, Newton from `x / l`.
    fn arm_angle(&self, x: f64) -> Result<f64, ElementError> {
        let (l, mut phi, mut r) = (self.length, x / self.length, f64::INFINITY);
        for _ in 0..50 {
            r = l * phi.sin() - x;
            if r.abs() <= 1e-14 * l {
                return Ok(phi);
            }
            phi -= r / (l * phi.cos());
        }
        Err(ElementError::InternalSolve {
            what: "arm angle from the bead position",
            residual: r.abs(),
            iterations: 50,
        })
    }
}

impl Element for ArmBead {
    fn node_kinds(&self) -> &[NodeKind] {
        &[NodeKind::Vector(1)]
    }
    fn nq(&self) -> usize {
        1
    }
    fn nu(&self) -> usize {
        1
    }
    fn reference_coordinates(&self, q: &mut [f64], u: &mut [f64]) {
        q[0] = 0.0;
        u[0] = 0.0;
    }
    fn set_pose(&self, q: &mut [f64], p: &Vector3<f64>, _r: &Matrix3<f64>) {
        q[0] = p.x;
    }
    fn set_velocity(&self, _q: &[f64], u: &mut [f64], v: &Vector3<f64>, _w: &Vector3<f64>) {
        u[0] = v.x;
    }
    fn q_dot(&self, _q: &[f64], u: &[f64], q_dot: &mut [f64]) {
        q_dot[0] = u[0];
    }
    fn new_scratch(&self) -> ElementScratch {
        ElementScratch::new(0.0_f64)
    }
    fn update(&self, q: &[f64], _u: &[f64], s: &mut ElementScratch) -> Result<(), ElementError> {
        *s.get_mut::<f64>() = self.arm_angle(q[0])?;
        Ok(())
    }
    fn mass_matrix(&self, _q: &[f64], _s: &mut ElementScratch, mut m: MatMut<'_, f64>) {
        m[(0, 0)] = self.mass;
    }
    fn forces(
        &self,
        _t: f64,
        _q: &[f64],
        _u: &[f64],
        g: &Vector3<f64>,
        s: &mut ElementScratch,
        h: &mut [f64],
    ) {
        let phi = *s.get::<f64>();
        h[0] = self.mass * g.x - self.stiffness * phi / (self.length * phi.cos());
    }
    fn frame_kinematics(
        &self,
        q: &[f64],
        u: &[f64],
        _s: &mut ElementScratch,
        f: &LocalFrame,
        out: &mut FrameKinematics,
    ) {
        *out = FrameKinematics::new(1);
        out.position = Vector3::new(q[0], 0.0, 0.0);
        out.rotation = f.rotation;
        out.velocity = Vector3::new(u[0], 0.0, 0.0);
        out.jac_t[(0, 0)] = 1.0;
    }
    fn kinetic_energy(&self, _q: &[f64], u: &[f64], _s: &mut ElementScratch) -> f64 {
        0.5 * self.mass * u[0] * u[0]
    }
    fn gravity_potential(&self, q: &[f64], g: &Vector3<f64>, _s: &mut ElementScratch) -> f64 {
        -self.mass * g.x * q[0]
    }
}

/// Pulled outward by a 10 m/s^2 field, the bead reaches the end of the 1 m arm (energy: the field
/// does 10 J, the spring stores at most 1/2 (pi/2)^2 = 1.23 J, so it gets there, at about
/// t = 0.47 s) and the next Newton iterate lies beyond it: the run stops with the body, the time
/// and the failed internal solve, not with a NaN residual.
#[test]
fn failed_internal_solve_names_body_time_and_cause() {
    let mut spec = ModelSpec::new();
    let bead = ArmBead {
        mass: 1.0,
        stiffness: 1.0,
        length: 1.0,
    };
    spec.add_body("bead", bead);
    spec.set_gravity(Vector3::new(10.0, 0.0, 0.0));
    let model = spec.compile().unwrap();
    let mut s = model.initial_state();
    let mut ws = Workspace::new(&model);
    let ga = GenAlpha::new(GenAlphaSettings::default()).unwrap();
    ga.initialize(&model, &mut s, &mut ws).unwrap();
    let mut x_max: f64 = 0.0;
    let err = ga
        .integrate(&model, &mut s, &mut ws, 1e-3, 2.0, |st, _| {
            x_max = x_max.max(st.q[0])
        })
        .unwrap_err();
    let msg = err.to_string();
    eprintln!("{msg}");
    let SolverError::Element { body, t, h, cause } = &err else {
        panic!("expected an element error, got {err}");
    };
    assert_eq!(body, "bead");
    assert_eq!(*h, 1e-3);
    assert!((0.3..0.7).contains(t), "failure at t = {t}");
    assert!(
        matches!(**cause, ElementError::InternalSolve { iterations: 50, .. }),
        "{cause:?}"
    );
    assert!(x_max > 0.9 && x_max <= 1.0, "last accepted x = {x_max}");
    assert!(msg.contains("bead") && msg.contains("t = ") && msg.contains("did not converge"));
}

/// With adaptive steps an iterate beyond the arm's reach is retried with smaller steps (the bead
/// gets within 1e-3 of the end, the fixed 1 ms step of the test above stops at 0.9); the run
/// still ends at the end of the arm (the spring force diverges there), with the cause of the last
/// rejection rather than "step size below minimum".
#[test]
fn adaptive_run_retries_then_names_the_element_cause() {
    let mut spec = ModelSpec::new();
    let bead = ArmBead {
        mass: 1.0,
        stiffness: 1.0,
        length: 1.0,
    };
    spec.add_body("bead", bead);
    spec.set_gravity(Vector3::new(10.0, 0.0, 0.0));
    let model = spec.compile().unwrap();
    let mut s = model.initial_state();
    let mut ws = Workspace::new(&model);
    let ga = GenAlpha::new(GenAlphaSettings {
        rho_inf: 0.8,
        ..GenAlphaSettings::default()
    })
    .unwrap();
    ga.initialize(&model, &mut s, &mut ws).unwrap();
    let ctl = AdaptiveSettings {
        h_init: 1e-3,
        h_min: 1e-9,
        ..AdaptiveSettings::default()
    };
    let mut x_max: f64 = 0.0;
    let err = ga
        .integrate_adaptive(&model, &mut s, &mut ws, &ctl, 2.0, |st, _| {
            x_max = x_max.max(st.q[0])
        })
        .unwrap_err();
    eprintln!("{err}");
    // at the end of the arm the spring force and its tangent diverge: the last halved step fails
    // on an iterate beyond the arm (the element), in Newton, or on a singular iteration matrix;
    // whichever it is, with its cause
    match &err {
        SolverError::Element { body, t, h, cause } => {
            assert_eq!(body, "bead");
            assert!(*h < 2e-9, "gave up at step {h}");
            assert!((0.3..0.7).contains(t), "failure at t = {t}");
            assert!(
                matches!(**cause, ElementError::InternalSolve { .. }),
                "{cause:?}"
            );
        }
        SolverError::NewtonFailed { t, h, .. } | SolverError::Singular { t, h, .. } => {
            assert!(*h < 2e-9, "gave up at step {h}");
            assert!((0.3..0.7).contains(t), "failure at t = {t}");
        }
        other => panic!("expected the cause of the last rejection, got {other}"),
    }
    assert!(x_max > 0.999 && x_max <= 1.0, "last accepted x = {x_max}");
}

/// A rigid body with Cardan angles spinning about the global y axis at 15.708 rad/s: beta grows
/// by exactly h omega per step (no forces, no gyroscopic moment about a principal axis) and lands
/// on 90 deg after 100 steps of 1 ms, where the parametrization is singular. The step to
/// t = 0.1 s fails with the body, the time and the cause (not as a singular iteration matrix).
#[test]
fn cardan_singularity_names_body_time_and_cause() {
    let mut spec = ModelSpec::new();
    let b = spec.add_body(
        "block",
        RigidBody::new(2.0, Matrix3::from_diagonal(&Vector3::new(0.01, 0.02, 0.03))),
    );
    let omega = std::f64::consts::FRAC_PI_2 / 0.1;
    let model = spec.compile().unwrap();
    let mut s = model.initial_state();
    model.set_body_velocity(&mut s, b, Vector3::zeros(), Vector3::new(0.0, omega, 0.0));
    let mut ws = Workspace::new(&model);
    let ga = GenAlpha::new(GenAlphaSettings::default()).unwrap();
    ga.initialize(&model, &mut s, &mut ws).unwrap();
    let err = ga
        .integrate(&model, &mut s, &mut ws, 1e-3, 0.2, |_, _| {})
        .unwrap_err();
    eprintln!("{err}");
    let SolverError::Element { body, t, cause, .. } = &err else {
        panic!("expected an element error, got {err}");
    };
    assert_eq!(body, "block");
    assert!((t - 0.099).abs() < 1e-9, "failure at t = {t}");
    let ElementError::Rotation(RotationError::CardanSingular { beta, .. }) = **cause else {
        panic!("{cause:?}");
    };
    assert!(
        (beta - std::f64::consts::FRAC_PI_2).abs() < 1e-8,
        "beta = {beta}"
    );
}
