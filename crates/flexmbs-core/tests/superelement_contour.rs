//! Neutral contours on superelement bodies ([`flexmbs_core::contour_source`]): a cubic curve
//! through the FE nodes of a beam-segment superelement, evaluated from the superelement's
//! [`NeutralContourSource`] at a tumbling, deformed state.
//! - node interpolation: at the node parameters the contour point is the material point
//!   `x_j + R_j (X_0 + Φ q_loc)` of the FE node, and at the interface nodes the interface node's
//!   own absolute position (from the coordinates alone): to 1e-12;
//! - the contour point's Jacobian equals central differences of its position over the body's
//!   coordinates (perturbed through `Element::integrate_position`) to 1e-7 of its largest entry,
//!   and its velocity equals `J u` to round-off;
//! - the frame's rotation map `J_π`, its frame-axes rows and the field-coordinate rows `J_q`
//!   equal central differences of `R_j` and `q_loc`.

use faer::Mat;
use flexmbs_core::contour_source::{ContourNodes, NeutralContourSource, NodeTable};
use flexmbs_core::element::{Element, LocalFrame};
use flexmbs_core::ffr::contour::{ContourSettings, FfrCurveContour};
use flexmbs_core::superelement::{
    beam_segment_basis, beam_segment_contour_nodes, BeamSegmentSpec, FrameLocation, Superelement,
    SuperelementEval,
};
use flexmbs_fe::element::MassKind;
use flexmbs_fe::mesh::{BeamSection, BeamTheory};
use flexmbs_fe::Material;
use nalgebra::{Matrix3, Rotation3, Vector3};

fn spec(frame: FrameLocation) -> BeamSegmentSpec {
    BeamSegmentSpec {
        length: 0.8,
        material: Material {
            e: 70e9,
            nu: 0.3,
            rho: 2700.0,
        },
        section: BeamSection::tube(0.01, 0.001),
        theory: BeamTheory::EulerBernoulli,
        elements: 6,
        internal_modes: 3,
        frame,
    }
}

fn rnd(seed: &mut u64) -> f64 {
    *seed = seed
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    ((*seed >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
}

struct Case {
    se: Superelement,
    nodes: NodeTable,
    curve: FfrCurveContour,
    q: Vec<f64>,
    u: Vec<f64>,
}

/// The segment placed at a random pose, deformed by a random position increment of size
/// `amp` (interfaces and internal modes), with random velocities.
fn case(frame: FrameLocation, seed: &mut u64, amp: f64) -> Case {
    let sp = spec(frame);
    let (data, v, _) = beam_segment_basis(&sp, MassKind::Consistent).unwrap();
    let nodes = beam_segment_contour_nodes(&sp, &data, &v);
    let se = Superelement::new(data).unwrap();
    let line: Vec<usize> = (0..nodes.num_nodes()).collect();
    let curve = FfrCurveContour::new(&nodes, &line, ContourSettings::default()).unwrap();
    let mut q0 = vec![0.0; se.nq()];
    let mut u = vec![0.0; se.nu()];
    se.reference_coordinates(&mut q0, &mut u);
    let a = *Rotation3::from_scaled_axis(Vector3::new(0.4, -0.9, 0.7)).matrix();
    se.set_pose(&mut q0, &Vector3::new(0.3, -0.2, 0.5), &a);
    let dv: Vec<f64> = (0..se.nu()).map(|_| amp * rnd(seed)).collect();
    let mut q = q0.clone();
    se.integrate_position(&q0, &dv, &mut q);
    for x in &mut u {
        *x = rnd(seed);
    }
    Case {
        se,
        nodes,
        curve,
        q,
        u,
    }
}

/// Evaluates the element at `q` and calls `f` with its contour source.
fn with_source<R>(c: &Case, q: &[f64], f: impl FnOnce(&dyn NeutralContourSource) -> R) -> R {
    let mut scratch = c.se.new_scratch();
    c.se.update(q, &c.u, &mut scratch).unwrap();
    f(scratch
        .contour_source()
        .expect("a superelement supplies contours"))
}

/// Floating-frame origin and velocity (the frame at the floating frame's origin).
fn frame_origin(c: &Case, q: &[f64]) -> (Vector3<f64>, Vector3<f64>) {
    let mut scratch = c.se.new_scratch();
    c.se.update(q, &c.u, &mut scratch).unwrap();
    let mut k = flexmbs_core::element::FrameKinematics::new(c.se.nu());
    let lf = LocalFrame::at(Vector3::zeros());
    c.se.frame_kinematics(q, &c.u, &mut scratch, &lf, &mut k);
    (k.position, k.velocity)
}

/// The global contour point at `eta` for coordinates `q`.
fn point(c: &Case, q: &[f64], eta: f64) -> Vector3<f64> {
    let (r, rd) = frame_origin(c, q);
    with_source(c, q, |s| {
        let mut st = c.curve.state().unwrap();
        c.curve.update(s, &mut st).unwrap();
        c.curve.point(&r, &rd, s, &mut st, eta).unwrap().position
    })
}

fn perturbed(c: &Case, j: usize, h: f64) -> Vec<f64> {
    let mut dv = vec![0.0; c.se.nu()];
    dv[j] = h;
    let mut q = c.q.clone();
    c.se.integrate_position(&c.q, &dv, &mut q);
    q
}

#[test]
fn contour_points_at_nodes_are_the_fe_nodes_material_points() {
    for frame in [FrameLocation::CentreOfMass, FrameLocation::FirstInterface] {
        let mut seed = 3;
        let c = case(frame, &mut seed, 0.005);
        let mut scratch = c.se.new_scratch();
        c.se.update(&c.q, &c.u, &mut scratch).unwrap();
        let e = scratch.get::<SuperelementEval>();
        let (r, rd) = frame_origin(&c, &c.q);
        assert!((r - e.x_j).norm() < 1e-15);
        let s = scratch.contour_source().unwrap();
        let mut st = c.curve.state().unwrap();
        c.curve.update(s, &mut st).unwrap();
        let params = c.curve.interpolator().params().to_vec();
        let n = c.nodes.num_nodes();
        let mut worst: f64 = 0.0;
        let mut deformation: f64 = 0.0;
        for (i, &eta) in params.iter().enumerate() {
            let p = c.curve.point(&r, &rd, s, &mut st, eta).unwrap().position;
            let mut local = c.nodes.node_position(i);
            for k in 0..c.nodes.num_fields() {
                local += c.nodes.node_shape(i, k) * e.q_loc[k];
            }
            let want = e.x_j + e.rj * local;
            worst = worst.max((p - want).norm());
            deformation = deformation.max((local - c.nodes.node_position(i)).norm());
            // interface nodes: the node's absolute position in the coordinates (Pose: x, quat)
            let o = if i == 0 {
                Some(0)
            } else {
                (i == n - 1).then(|| c.se.nq() - 7)
            };
            if let Some(o) = o {
                let x = Vector3::new(c.q[o], c.q[o + 1], c.q[o + 2]);
                let d = (p - x).norm();
                println!("{frame:?}: interface node {i}: |contour - node| = {d:.2e}");
                assert!(d < 1e-12, "{frame:?}: interface node {i}: {p} vs {x}");
            }
        }
        println!("{frame:?}: node points: max |contour - material point| = {worst:.2e}, deformation {deformation:.2e} m");
        assert!(deformation > 1e-3, "the state is deformed");
        assert!(worst < 1e-12, "{frame:?}: {worst:e}");
    }
}

#[test]
fn contour_point_jacobian_equals_central_differences() {
    for frame in [FrameLocation::CentreOfMass, FrameLocation::FirstInterface] {
        let mut seed = 7;
        let c = case(frame, &mut seed, 0.005);
        let nu = c.se.nu();
        let params = c.curve.interpolator().params().to_vec();
        let eta = 0.37 * params[params.len() - 1];
        let (r, rd) = frame_origin(&c, &c.q);
        let (jac, vel) = with_source(&c, &c.q, |s| {
            assert_eq!(s.num_velocities(), nu);
            let mut st = c.curve.state().unwrap();
            c.curve.update(s, &mut st).unwrap();
            let mut jac = Mat::<f64>::zeros(3, nu);
            c.curve
                .jacobian_translation(s, &mut st, eta, jac.as_mut())
                .unwrap();
            (
                jac,
                c.curve.point(&r, &rd, s, &mut st, eta).unwrap().velocity,
            )
        });
        let h = 1e-6;
        let scale = (0..nu)
            .flat_map(|j| (0..3).map(move |i| (i, j)))
            .fold(0.0f64, |m, (i, j)| m.max(jac[(i, j)].abs()));
        let mut worst: f64 = 0.0;
        for j in 0..nu {
            let fd = (point(&c, &perturbed(&c, j, h), eta) - point(&c, &perturbed(&c, j, -h), eta))
                / (2.0 * h);
            for i in 0..3 {
                worst = worst.max((fd[i] - jac[(i, j)]).abs() / scale);
            }
        }
        println!(
            "{frame:?}: J_T vs central differences: max error {worst:.2e} of max |J| {scale:.3}"
        );
        assert!(worst < 1e-7, "{frame:?}: {worst:e}");
        let ju: Vector3<f64> =
            Vector3::from_fn(|i, _| (0..nu).map(|j| jac[(i, j)] * c.u[j]).sum::<f64>());
        let dv = (vel - ju).norm();
        println!("{frame:?}: |v - J u| = {dv:.2e} (|v| = {:.3})", vel.norm());
        assert!(dv < 1e-12 * (1.0 + vel.norm()), "{frame:?}: {vel} vs {ju}");
    }
}

/// Rotation vector of a small rotation `a bᵀ`: the axial vector of its skew part (exact to
/// O(θ³); an angle from the trace loses half the digits at θ ~ 1e-6).
fn rotation_difference(a: &Matrix3<f64>, b: &Matrix3<f64>) -> Vector3<f64> {
    let r = a * b.transpose();
    0.5 * Vector3::new(
        r[(2, 1)] - r[(1, 2)],
        r[(0, 2)] - r[(2, 0)],
        r[(1, 0)] - r[(0, 1)],
    )
}

#[test]
fn frame_rotation_and_field_rows_equal_central_differences() {
    let mut seed = 19;
    let c = case(FrameLocation::CentreOfMass, &mut seed, 0.005);
    let nu = c.se.nu();
    let state = |q: &[f64]| {
        with_source(&c, q, |s| {
            (*s.frame_rotation(), s.field_coordinates().to_vec())
        })
    };
    let (a0, _) = state(&c.q);
    let (mut jpi, mut out_q, mut out_r, mut out_pi) = (
        Mat::<f64>::zeros(3, nu),
        vec![0.0; nu],
        vec![0.0; nu],
        vec![0.0; nu],
    );
    let cvec: Vec<f64> = (0..nu).map(|_| rnd(&mut seed)).collect();
    let v = Vector3::new(0.3, -1.1, 0.6);
    let d = Vector3::new(-0.2, 0.05, 0.4);
    let mut arm = Mat::<f64>::zeros(3, nu);
    with_source(&c, &c.q, |s| {
        s.rotation_jacobian(jpi.as_mut());
        s.add_field_row(&|k| cvec[k], &mut out_q);
        s.add_rotation_row(&v, 2.0, &mut out_r);
        s.add_arm_jacobian(&d, arm.as_mut());
    });
    let h = 1e-6;
    let mut worst = [0.0f64; 4];
    for j in 0..nu {
        let (ap, qp) = state(&perturbed(&c, j, h));
        let (am, qm) = state(&perturbed(&c, j, -h));
        let dpi = rotation_difference(&ap, &am) / (2.0 * h);
        let dq: f64 = (0..nu).map(|k| cvec[k] * (qp[k] - qm[k]) / (2.0 * h)).sum();
        let jcol = Vector3::new(jpi[(0, j)], jpi[(1, j)], jpi[(2, j)]);
        worst[0] = worst[0].max((dpi - jcol).amax());
        worst[1] = worst[1].max((dq - out_q[j]).abs());
        out_pi[j] = 2.0 * (a0.transpose() * jcol).dot(&v);
        worst[2] = worst[2].max((out_r[j] - out_pi[j]).abs());
        let want = -d.cross(&jcol);
        let got = Vector3::new(arm[(0, j)], arm[(1, j)], arm[(2, j)]);
        worst[3] = worst[3].max((got - want).amax());
    }
    println!(
        "J_pi {:.2e}, J_q^T c {:.2e}, rows {:.2e}, arm {:.2e}",
        worst[0], worst[1], worst[2], worst[3]
    );
    assert!(worst[0] < 1e-7 && worst[1] < 1e-6, "{worst:?}");
    assert!(worst[2] < 1e-12 && worst[3] < 1e-12, "{worst:?}");
}
