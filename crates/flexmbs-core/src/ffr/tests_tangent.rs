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
        let mut ts = TangentScratch::new(body.nq(), nu);
        let (mut fq, mut fu) = (Mat::zeros(nu, nu), Mat::zeros(nu, nu));
        finite_difference_tangents(&fd, 0.0, &q, &u, &g, fq.as_mut(), fu.as_mut(), &mut ts);
        let (mut aq, mut au) = (Mat::zeros(nu, nu), Mat::zeros(nu, nu));
        an.force_tangents(0.0, &q, &u, &g, aq.as_mut(), au.as_mut(), &mut ts);
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

/// The moment cache is transparent: `update_cached` leaves the scratch bitwise equal to `update`,
/// on a miss (new `q_f`) and on a hit (same `q_f`, new rotation and velocities).
#[test]
fn update_cache_is_bitwise_transparent() {
    let mut seed = 9;
    let d = random_data(&mut seed, 6, 4, 0.2);
    for rot in [RotationParam::Cardan, RotationParam::Quaternion] {
        let body = body_of(&d, rot, false);
        let mut cache = MomentCache::new(body.nf());
        let (mut sc, mut sr) = (FfrScratch::new(body.nf()), FfrScratch::new(body.nf()));
        let (q1, u1) = random_state(&mut seed, &body, 0.3);
        let (mut q2, u2) = random_state(&mut seed, &body, 0.3);
        let nr = rot.num_coordinates();
        q2[3 + nr..].copy_from_slice(&q1[3 + nr..]); // same deformation, new pose
        for (q, u) in [(&q1, &u1), (&q2, &u2), (&q1, &u2)] {
            body.update_cached(q, u, &mut sc, &mut cache).unwrap();
            body.update(q, u, &mut sr).unwrap();
            assert_eq!(
                (sc.a, sc.h, sc.hdot_w, sc.omega),
                (sr.a, sr.h, sr.hdot_w, sr.omega)
            );
            assert_eq!((&sc.qf, &sc.qfd, &sc.p), (&sr.qf, &sr.qfd, &sr.p));
            assert_eq!((sc.s_t, sc.i_tt, &sc.i_tf), (sr.s_t, sr.i_tt, &sr.i_tf));
        }
    }
}
