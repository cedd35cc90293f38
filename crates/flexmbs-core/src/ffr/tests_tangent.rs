//! The analytic FFR tangent ([`FfrBody::force_tangents`]) against central finite differences
//! of the full force evaluation (the element contract's default tangent).

use super::tests::{body_of, random_data, random_state, rnd};
use super::*;
use crate::element::{finite_difference_tangents, Element, TangentScratch};
use faer::Mat;
use nalgebra::Vector3;

/// max |a - b| / max |b|.
fn rel(a: &Mat<f64>, b: &Mat<f64>) -> f64 {
    let mut d = 0.0_f64;
    let mut m = 0.0_f64;
    for j in 0..a.ncols() {
        for i in 0..a.nrows() {
            d = d.max((a[(i, j)] - b[(i, j)]).abs());
            m = m.max(b[(i, j)].abs());
        }
    }
    d / m
}

/// Analytic and finite-difference tangents of one body at `count` random states.
fn compare(rot: RotationParam, with_damping: bool, seed: u64, count: usize) -> (f64, f64) {
    compare_bodies(rot, with_damping, false, seed, count)
}

/// [`compare`], optionally with random node rotary inertias (symmetric positive definite, of the
/// order of the node masses, so that their terms are not negligible).
fn compare_bodies(
    rot: RotationParam,
    with_damping: bool,
    with_rotary: bool,
    seed: u64,
    count: usize,
) -> (f64, f64) {
    let mut seed = seed;
    let d = random_data(&mut seed, 7, 5, 0.2);
    let mut body = body_of(&d, rot, true);
    if with_damping {
        body.set_rayleigh_damping(0.3, 0.01);
    }
    if with_rotary {
        let inertias: Vec<_> = (0..body.num_nodes())
            .map(|_| {
                let b = nalgebra::Matrix3::from_fn(|_, _| rnd(&mut seed));
                b * b.transpose() + nalgebra::Matrix3::identity() * 0.1
            })
            .collect();
        body.set_rotary_inertia(&inertias).unwrap();
    }
    let fd = FfrElement::new(body.clone()).with_finite_difference_tangent();
    let an = FfrElement::new(body.clone());
    let g = Vector3::new(0.3, -9.81, 1.2);
    let nu = body.nu();
    let (mut worst_q, mut worst_u) = (0.0_f64, 0.0_f64);
    for _ in 0..count {
        let (q, u) = random_state(&mut seed, &body, 0.3);
        let mut ts = TangentScratch::new(&fd);
        let (mut fq, mut fu) = (Mat::zeros(nu, nu), Mat::zeros(nu, nu));
        finite_difference_tangents(&fd, 0.0, &q, &u, &g, fq.as_mut(), fu.as_mut(), &mut ts);
        let (mut aq, mut au) = (Mat::zeros(nu, nu), Mat::zeros(nu, nu));
        let mut e = an.evaluated(&q, &u).unwrap();
        an.force_tangents(0.0, &q, &u, &g, &mut e, aq.as_mut(), au.as_mut(), &mut ts);
        worst_q = worst_q.max(rel(&aq, &fq));
        worst_u = worst_u.max(rel(&au, &fu));
    }
    (worst_q, worst_u)
}

/// Cardan angles with Rayleigh damping and gravity: `dh/dq` to 1e-7 relative (FD truncation
/// O(1e-12), round-off O(1e-10 |h|)), `dh/du` (h quadratic in u: FD exact) to 1e-8.
#[test]
fn cardan_tangent_equals_finite_differences() {
    let (eq, eu) = compare(RotationParam::Cardan, true, 11, 8);
    eprintln!("relative errors dh/dq {eq:e}, dh/du {eu:e}");
    assert!(eq < 1e-7, "dh/dq relative error {eq:e}");
    assert!(eu < 1e-8, "dh/du relative error {eu:e}");
}

/// Node rotary inertia (`ffr/rotary.rs`), Cardan angles with damping and quaternions: the same
/// tolerances (before, bodies with rotary inertia fell back to the finite-difference tangent).
#[test]
fn rotary_inertia_tangent_equals_finite_differences() {
    for (rot, damping, seed) in [
        (RotationParam::Cardan, true, 31),
        (RotationParam::Quaternion, false, 37),
    ] {
        let (eq, eu) = compare_bodies(rot, damping, true, seed, 8);
        eprintln!("{rot:?} with rotary inertia: relative errors dh/dq {eq:e}, dh/du {eu:e}");
        assert!(eq < 1e-7, "dh/dq relative error {eq:e}");
        assert!(eu < 1e-8, "dh/du relative error {eu:e}");
    }
}

/// Quaternion coordinates (tangent along `q ⊕ dv`), undamped.
#[test]
fn quaternion_tangent_equals_finite_differences() {
    let (eq, eu) = compare(RotationParam::Quaternion, false, 23, 8);
    eprintln!("relative errors dh/dq {eq:e}, dh/du {eu:e}");
    assert!(eq < 1e-7, "dh/dq relative error {eq:e}");
    assert!(eu < 1e-8, "dh/du relative error {eu:e}");
}

/// The analytic tangent leaves the evaluated state untouched: forces after a tangent equal the
/// forces before it (bitwise), and a tangent call does not allocate is checked in `no_alloc`.
#[test]
fn tangent_restores_state() {
    let mut seed = 5;
    let d = random_data(&mut seed, 6, 4, 0.2);
    let body = body_of(&d, RotationParam::Cardan, false);
    let (q, u) = random_state(&mut seed, &body, 0.3);
    let mut s = FfrScratch::new(body.nf());
    let mut ts = FfrTangentScratch::new(body.nf());
    body.update(&q, &u, &mut s).unwrap();
    let before = (s.a, s.h, s.hdot_w, s.omega);
    let nu = body.nu();
    let (mut aq, mut au) = (Mat::zeros(nu, nu), Mat::zeros(nu, nu));
    let g = Vector3::zeros();
    body.force_tangents(&q, &u, &g, &mut s, &mut ts, aq.as_mut(), au.as_mut())
        .unwrap();
    assert_eq!(before, (s.a, s.h, s.hdot_w, s.omega));
    let mut wrong = FfrTangentScratch::new(body.nf() + 1);
    assert!(matches!(
        body.force_tangents(&q, &u, &g, &mut s, &mut wrong, aq.as_mut(), au.as_mut()),
        Err(FfrError::DimensionMismatch { .. })
    ));
}

/// The kinematics-only evaluation (`Element::update_kinematics`, used by the local load and
/// constraint-force tangents) gives frame kinematics bitwise equal to the full evaluation, for a
/// mesh-node frame and a point of the floating frame, and fails like it on a singular state.
#[test]
fn kinematics_only_update_is_bitwise_the_full_one() {
    use crate::element::{FrameKinematics, LocalFrame};
    let mut seed = 9;
    let d = random_data(&mut seed, 6, 4, 0.2);
    for rot in [RotationParam::Cardan, RotationParam::Quaternion] {
        let e = FfrElement::new(body_of(&d, rot, false));
        let (mut full, mut kin) = (e.new_scratch(), e.new_scratch());
        let mut node = LocalFrame::at(Vector3::zeros());
        node.mesh_node = Some(3);
        let point = LocalFrame::at(Vector3::new(0.2, -0.1, 0.3));
        for _ in 0..3 {
            let (q, u) = random_state(&mut seed, e.body(), 0.3);
            e.update(&q, &u, &mut full).unwrap();
            e.update_kinematics(&q, &u, &mut kin).unwrap();
            for frame in [&node, &point] {
                let (mut a, mut b) = (FrameKinematics::new(e.nu()), FrameKinematics::new(e.nu()));
                e.frame_kinematics(&q, &u, &mut full, frame, &mut a);
                e.frame_kinematics(&q, &u, &mut kin, frame, &mut b);
                assert_eq!((a.position, a.rotation), (b.position, b.rotation));
                assert_eq!(
                    (a.velocity, a.angular_velocity),
                    (b.velocity, b.angular_velocity)
                );
                assert_eq!((a.bias_acc, a.bias_ang_acc), (b.bias_acc, b.bias_ang_acc));
                assert_eq!((&a.jac_t, &a.jac_r), (&b.jac_t, &b.jac_r));
            }
        }
        let (mut q, u) = random_state(&mut seed, e.body(), 0.3);
        match rot {
            RotationParam::Cardan => q[4] = std::f64::consts::FRAC_PI_2,
            RotationParam::Quaternion => q[3..7].fill(0.0),
        }
        assert!(e.update(&q, &u, &mut full).is_err());
        assert!(e.update_kinematics(&q, &u, &mut kin).is_err());
    }
}
