//! Exact kinematics of FFR node frames (beam nodes with rotational modes) at deformed states:
//! the node frame `F = A exp(skew(Phi_r q_f))` is orthonormal, and the Jacobians `J_T`, `J_R` and
//! the bias accelerations of `Element::frame_kinematics` equal central finite differences taken
//! with the element's own position update `q ⊕ dv` (`Element::integrate_position`).

use faer::Mat;
use flexmbs_core::ffr::{FfrBody, FfrElement, FfrInvariants, RotationParam};
use flexmbs_core::rotation::{rotation_vector_matrix, unskew};
use flexmbs_core::{Element, FrameKinematics, LocalFrame};
use nalgebra::{DVector, Matrix3, Vector3};

fn rnd(seed: &mut u64) -> f64 {
    *seed = seed
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    ((*seed >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
}

const NODES: usize = 5;
const NF: usize = 3;
/// The node whose frame is checked.
const NODE: usize = 3;

/// A lumped body with random translational and rotational modes (3 modes, 5 nodes).
fn element(seed: &mut u64, rot: RotationParam) -> FfrElement {
    let u0: Vec<[f64; 3]> = (0..NODES)
        .map(|i| [0.25 * i as f64, 0.1 * rnd(seed), 0.05 * rnd(seed)])
        .collect();
    let masses: Vec<f64> = (0..NODES).map(|_| 1.0 + 0.5 * rnd(seed)).collect();
    let modes_t = Mat::from_fn(3 * NODES, NF, |_, _| 0.3 * rnd(seed));
    let modes_r = Mat::from_fn(3 * NODES, NF, |_, _| rnd(seed));
    let k = Mat::from_fn(NF, NF, |i, j| if i == j { 100.0 } else { 0.0 });
    let inv = FfrInvariants::from_lumped(&u0, &masses, modes_t.as_ref()).unwrap();
    let body = FfrBody::new(
        inv,
        rot,
        &u0,
        modes_t.as_ref(),
        Some(modes_r.as_ref()),
        k.as_ref(),
    )
    .unwrap();
    FfrElement::new(body)
}

/// A deformed state whose elastic rotation `|Phi_r q_f|` at [`NODE`] is `angle`, with a general
/// pose and random velocities.
fn deformed_state(seed: &mut u64, e: &FfrElement, angle: f64) -> (Vec<f64>, Vec<f64>) {
    let (mut q, mut u) = (vec![0.0; e.nq()], vec![0.0; e.nu()]);
    e.reference_coordinates(&mut q, &mut u);
    let pose = rotation_vector_matrix(&Vector3::new(0.4, -0.9, 0.7));
    e.set_pose(&mut q, &Vector3::new(0.3, -0.2, 0.5), &pose);
    let qf: DVector<f64> = DVector::from_fn(NF, |_, _| rnd(seed));
    let mr = e.body().modes_r.as_ref().unwrap();
    let th = mr.rows(3 * NODE, 3) * &qf;
    let qf = qf * (angle / th.norm());
    let nq = q.len();
    q[nq - NF..].copy_from_slice(qf.as_slice());
    for x in u.iter_mut() {
        *x = 2.0 * rnd(seed);
    }
    (q, u)
}

fn frame() -> LocalFrame {
    LocalFrame {
        position: Vector3::zeros(),
        rotation: rotation_vector_matrix(&Vector3::new(0.2, 0.1, -0.3)),
        mesh_node: Some(NODE),
    }
}

fn kin(e: &FfrElement, q: &[f64], u: &[f64]) -> FrameKinematics {
    let mut out = FrameKinematics::new(e.nu());
    let mut s = e.evaluated(q, u).unwrap();
    e.frame_kinematics(q, u, &mut s, &frame(), &mut out);
    out
}

/// `q ⊕ h dv` with the element's own position update.
fn step(e: &FfrElement, q: &[f64], dv: &[f64], h: f64) -> Vec<f64> {
    let dv: Vec<f64> = dv.iter().map(|x| h * x).collect();
    let mut out = vec![0.0; q.len()];
    e.integrate_position(q, &dv, &mut out);
    out
}

fn column(m: &Mat<f64>, j: usize) -> Vector3<f64> {
    Vector3::new(m[(0, j)], m[(1, j)], m[(2, j)])
}

fn times(m: &Mat<f64>, u: &[f64]) -> Vector3<f64> {
    (0..u.len()).map(|j| column(m, j) * u[j]).sum()
}

const PARAMS: [RotationParam; 2] = [RotationParam::Cardan, RotationParam::Quaternion];
const ANGLES: [f64; 4] = [1e-4, 0.1, 0.2, 0.3];

/// `F^T F = I` and `det F = 1` to 1e-14 at elastic node rotations up to 0.3 rad.
#[test]
fn node_frame_rotation_is_orthonormal() {
    let mut seed = 1;
    for rot in PARAMS {
        let e = element(&mut seed, rot);
        for angle in ANGLES {
            let (q, u) = deformed_state(&mut seed, &e, angle);
            let f = kin(&e, &q, &u).rotation;
            let err = (f.transpose() * f - Matrix3::identity()).abs().max();
            assert!(err < 1e-14, "{rot:?}, {angle} rad: |F^T F - I| = {err:e}");
            assert!((f.determinant() - 1.0).abs() < 1e-14);
        }
    }
}

/// Column j of `J_T` and `J_R` equals the central difference of the position and of the
/// rotation (`unskew((F(q ⊕ eps e_j) - F(q ⊕ -eps e_j)) F^T)/(2 eps)`) to 1e-7, and
/// `v = J_T u`, `omega = J_R u` to 1e-13 relative, at deformed states.
#[test]
fn node_frame_jacobians_equal_finite_differences() {
    let mut seed = 2;
    let eps = 1e-6;
    for rot in PARAMS {
        let e = element(&mut seed, rot);
        for angle in ANGLES {
            let (q, u) = deformed_state(&mut seed, &e, angle);
            let k = kin(&e, &q, &u);
            for j in 0..e.nu() {
                let mut ej = vec![0.0; e.nu()];
                ej[j] = 1.0;
                let kp = kin(&e, &step(&e, &q, &ej, eps), &u);
                let km = kin(&e, &step(&e, &q, &ej, -eps), &u);
                let jt_fd = (kp.position - km.position) / (2.0 * eps);
                let jr_fd =
                    unskew(&((kp.rotation - km.rotation) * k.rotation.transpose())) / (2.0 * eps);
                let et = (jt_fd - column(&k.jac_t, j)).norm();
                let er = (jr_fd - column(&k.jac_r, j)).norm();
                assert!(et < 1e-7, "{rot:?}, {angle} rad, J_T column {j}: {et:e}");
                assert!(er < 1e-7, "{rot:?}, {angle} rad, J_R column {j}: {er:e}");
            }
            let v = times(&k.jac_t, &u);
            let w = times(&k.jac_r, &u);
            assert!((k.velocity - v).norm() < 1e-13 * v.norm());
            assert!((k.angular_velocity - w).norm() < 1e-13 * w.norm());
        }
    }
}

/// The bias accelerations `J_dot u` equal central differences of `J(q(t)) u` along the motion
/// `q(t) = q ⊕ t u` (fixed `u`) to 1e-6, at deformed states.
#[test]
fn node_frame_bias_equals_finite_differences() {
    let mut seed = 3;
    let h = 1e-6;
    for rot in PARAMS {
        let e = element(&mut seed, rot);
        for angle in ANGLES {
            let (q, u) = deformed_state(&mut seed, &e, angle);
            let k = kin(&e, &q, &u);
            let kp = kin(&e, &step(&e, &q, &u, h), &u);
            let km = kin(&e, &step(&e, &q, &u, -h), &u);
            let at = (times(&kp.jac_t, &u) - times(&km.jac_t, &u)) / (2.0 * h);
            let ar = (times(&kp.jac_r, &u) - times(&km.jac_r, &u)) / (2.0 * h);
            let et = (at - k.bias_acc).norm();
            let er = (ar - k.bias_ang_acc).norm();
            assert!(et < 1e-6, "{rot:?}, {angle} rad, translation bias: {et:e}");
            assert!(er < 1e-6, "{rot:?}, {angle} rad, rotation bias: {er:e}");
        }
    }
}

/// `floating_frame_is_material`: true without modes, with a fixed node carrying rotations (zero
/// translational and rotational rows) or three non-collinear fixed solid nodes; false for
/// free-free modes, a fixed node whose rotations move, or collinear fixed solid nodes.
#[test]
fn floating_frame_is_material_only_when_clamped() {
    let mut seed = 4;
    let u0: Vec<[f64; 3]> = (0..NODES)
        .map(|i| [0.25 * i as f64, 0.1 * (i % 2) as f64, 0.0])
        .collect();
    let masses = vec![1.0; NODES];
    let body = |zero_t: &[usize], zero_r: &[usize], with_r: bool, nf: usize, seed: &mut u64| {
        let modes_t = Mat::from_fn(3 * NODES, nf, |i, _| {
            if zero_t.contains(&(i / 3)) {
                0.0
            } else {
                rnd(seed)
            }
        });
        let modes_r = Mat::from_fn(3 * NODES, nf, |i, _| {
            if zero_r.contains(&(i / 3)) {
                0.0
            } else {
                rnd(seed)
            }
        });
        let k = Mat::from_fn(nf, nf, |i, j| if i == j { 1.0 } else { 0.0 });
        let inv = FfrInvariants::from_lumped(&u0, &masses, modes_t.as_ref()).unwrap();
        let mr = with_r.then_some(modes_r.as_ref());
        FfrBody::new(
            inv,
            RotationParam::Quaternion,
            &u0,
            modes_t.as_ref(),
            mr,
            k.as_ref(),
        )
        .unwrap()
    };
    let s = &mut seed;
    assert!(body(&[], &[], true, 0, s).floating_frame_is_material());
    assert!(!body(&[], &[], true, NF, s).floating_frame_is_material());
    assert!(body(&[0], &[0], true, NF, s).floating_frame_is_material());
    assert!(body(&[0], &[0], true, NF, s).node_is_fixed(0));
    assert!(!body(&[0], &[], true, NF, s).floating_frame_is_material());
    assert!(!body(&[0], &[], false, NF, s).floating_frame_is_material());
    // nodes 0, 2, 4 lie on the x axis (collinear); 0, 1, 2 span a plane
    assert!(!body(&[0, 2, 4], &[], false, NF, s).floating_frame_is_material());
    assert!(body(&[0, 1, 2], &[], false, NF, s).floating_frame_is_material());
}
