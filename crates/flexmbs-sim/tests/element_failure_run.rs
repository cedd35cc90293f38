//! A run whose element fails an internal solve (`ElementError::InternalSolve`) ends with an error
//! naming the body, the time and the cause, and leaves a readable results file with status
//! `failed` holding the rows up to the failed step (the run-level counterpart of
//! `flexmbs-core/tests/element_errors.rs`).

use faer::MatMut;
use flexmbs_core::{
    Element, ElementError, ElementScratch, FrameKinematics, LocalFrame, NodeKind, SolverError,
    TangentScratch,
};
use flexmbs_io::results::{read_results, RunStatus};
use flexmbs_sim::run::{run_model, RunError, RunOptions};
use nalgebra::{Matrix3, Vector3};

/// The compiled point mass, plus an internal Newton solve in [`Element::update`]: the angle
/// `phi` of an arm of length `ARM` that reaches the bead's height, `ARM sin(phi) = -z`, which has
/// no solution once the bead has fallen below `-ARM` (the solve then fails after 50 iterations,
/// as a superelement's floating-frame recovery does). Every other query is the point mass's.
#[derive(Debug)]
struct ArmSolve(Box<dyn Element>);

const ARM: f64 = 0.05;

fn arm_angle(z: f64) -> Result<f64, ElementError> {
    let (mut phi, mut r) = (-z / ARM, f64::INFINITY);
    for _ in 0..50 {
        r = ARM * phi.sin() + z;
        if r.abs() <= 1e-14 * ARM {
            return Ok(phi);
        }
        phi -= r / (ARM * phi.cos());
    }
    Err(ElementError::InternalSolve {
        what: "arm angle from the bead height",
        residual: r.abs(),
        iterations: 50,
    })
}

impl Element for ArmSolve {
    fn node_kinds(&self) -> &[NodeKind] {
        self.0.node_kinds()
    }
    fn nq(&self) -> usize {
        self.0.nq()
    }
    fn nu(&self) -> usize {
        self.0.nu()
    }
    fn reference_coordinates(&self, q: &mut [f64], u: &mut [f64]) {
        self.0.reference_coordinates(q, u)
    }
    fn set_pose(&self, q: &mut [f64], p: &Vector3<f64>, r: &Matrix3<f64>) {
        self.0.set_pose(q, p, r)
    }
    fn set_velocity(&self, q: &[f64], u: &mut [f64], v: &Vector3<f64>, w: &Vector3<f64>) {
        self.0.set_velocity(q, u, v, w)
    }
    fn q_dot(&self, q: &[f64], u: &[f64], q_dot: &mut [f64]) {
        self.0.q_dot(q, u, q_dot)
    }
    fn new_scratch(&self) -> ElementScratch {
        self.0.new_scratch()
    }
    fn update(&self, q: &[f64], u: &[f64], s: &mut ElementScratch) -> Result<(), ElementError> {
        arm_angle(q[2])?;
        self.0.update(q, u, s)
    }
    fn mass_matrix(&self, q: &[f64], s: &mut ElementScratch, m: MatMut<'_, f64>) {
        self.0.mass_matrix(q, s, m)
    }
    fn forces(
        &self,
        t: f64,
        q: &[f64],
        u: &[f64],
        g: &Vector3<f64>,
        s: &mut ElementScratch,
        h: &mut [f64],
    ) {
        self.0.forces(t, q, u, g, s, h)
    }
    fn frame_kinematics(
        &self,
        q: &[f64],
        u: &[f64],
        s: &mut ElementScratch,
        f: &LocalFrame,
        out: &mut FrameKinematics,
    ) {
        self.0.frame_kinematics(q, u, s, f, out)
    }
    #[allow(clippy::too_many_arguments)]
    fn force_tangents(
        &self,
        t: f64,
        q: &[f64],
        u: &[f64],
        g: &Vector3<f64>,
        s: &mut ElementScratch,
        dh_dq: MatMut<'_, f64>,
        dh_du: MatMut<'_, f64>,
        fd: &mut TangentScratch,
    ) {
        self.0.force_tangents(t, q, u, g, s, dh_dq, dh_du, fd)
    }
    fn kinetic_energy(&self, q: &[f64], u: &[f64], s: &mut ElementScratch) -> f64 {
        self.0.kinetic_energy(q, u, s)
    }
    fn gravity_potential(&self, q: &[f64], g: &Vector3<f64>, s: &mut ElementScratch) -> f64 {
        self.0.gravity_potential(q, g, s)
    }
}

const FALL: &str = r#"
[model]
name = "bead_fall"
gravity = [0, 0, -9.81]

[solver]
type = "generalized-alpha"
h = "1 ms"
t_end = "0.5 s"

[[body]]
name = "bead"
type = "point_mass"
mass = "0.2 kg"

[output]
signals = ["bead.position"]
"#;

/// The bead falls from rest (g = 9.81 m/s^2 along -z) and passes z = -ARM at t = sqrt(2 ARM / g)
/// = 0.101 s: the step that would take it there fails, the run stops with the body, the time
/// and the failed solve, and the results file (status `failed`, the failure message) holds the
/// rows up to the start of that step, the last one below the arm's reach.
#[test]
fn failed_internal_solve_ends_the_run_naming_body_time_and_cause() {
    let file = flexmbs_io::test_tools::scratch_dir("model").join("bead-fall.toml");
    let mut cm = flexmbs_sim::compile_model(FALL, &file).unwrap();
    let b = cm.model.body_id("bead").unwrap();
    let body = &mut cm.model.bodies[b.index()];
    let inner = std::mem::replace(
        &mut body.element,
        Box::new(flexmbs_core::point_mass::PointMass::new(1.0)),
    );
    body.element = Box::new(ArmSolve(inner));
    let out = flexmbs_io::test_tools::scratch_dir("sim-test-bead");
    let _ = std::fs::remove_dir_all(&out);
    let err = run_model(&cm, &RunOptions::new(&out), &mut |_| {}).unwrap_err();
    let msg = err.to_string();
    eprintln!("{msg}");
    let RunError::Solver {
        t, results, source, ..
    } = &err
    else {
        panic!("expected a solver error, got {err}");
    };
    let t_reach = (2.0 * ARM / 9.81_f64).sqrt();
    assert!(
        *t <= t_reach && *t > t_reach - 3e-3,
        "failure at t = {t}, the bead reaches z = -{ARM} at {t_reach}"
    );
    let SolverError::Element { body, cause, .. } = &**source else {
        panic!("expected an element error, got {source}");
    };
    assert_eq!(body, "bead");
    assert!(
        matches!(**cause, ElementError::InternalSolve { iterations: 50, .. }),
        "{cause:?}"
    );
    for part in [
        "bead",
        "t = ",
        "arm angle from the bead height did not converge",
    ] {
        assert!(msg.contains(part), "{part:?} missing in: {msg}");
    }
    let r = read_results(results).unwrap();
    let RunStatus::Failed { message, .. } = &r.status else {
        panic!("status {:?}", r.status);
    };
    assert!(
        message.contains("bead") && message.contains("did not converge"),
        "{message}"
    );
    let last = *r.time.last().unwrap();
    assert!(
        (last - t).abs() < 1e-12,
        "last row at {last}, failure at {t}"
    );
    assert_eq!(r.time.len(), (t / 1e-3).round() as usize + 1);
    let z = r.series("bead.position.z").unwrap();
    assert!(z.iter().all(|&z| z >= -ARM), "{:?}", z.last());
    let _ = std::fs::remove_dir_all(&out);
}
