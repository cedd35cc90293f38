//! Brute-force cross-checks of the FFR body against sums over nodes and finite differences.

use super::body::faer_view_mut;
use super::*;
use crate::rotation::{normalize_quaternion, skew};
use nalgebra::{DMatrix, DVector, Matrix3, Vector3, Vector4};

pub(super) fn rnd(seed: &mut u64) -> f64 {
    *seed = seed
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    ((*seed >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
}

/// Random test body data: node positions, masses, translational and rotational modes, stiffness.
pub(super) struct Data {
    pub(super) u0: Vec<[f64; 3]>,
    pub(super) masses: Vec<f64>,
    pub(super) modes_t: faer::Mat<f64>,
    pub(super) modes_r: faer::Mat<f64>,
    pub(super) k: faer::Mat<f64>,
}

pub(super) fn random_data(seed: &mut u64, n: usize, nf: usize, mode_scale: f64) -> Data {
    let u0 = (0..n)
        .map(|_| [rnd(seed), 0.5 * rnd(seed) + 0.2, 0.3 * rnd(seed) - 0.1])
        .collect();
    let masses = (0..n).map(|_| 1.25 + 0.75 * rnd(seed)).collect();
    let modes_t = faer::Mat::from_fn(3 * n, nf, |_, _| mode_scale * rnd(seed));
    let modes_r = faer::Mat::from_fn(3 * n, nf, |_, _| mode_scale * rnd(seed));
    let k = faer::Mat::from_fn(
        nf,
        nf,
        |i, j| if i == j { 50.0 * (i + 1) as f64 } else { 0.0 },
    );
    Data {
        u0,
        masses,
        modes_t,
        modes_r,
        k,
    }
}

pub(super) fn body_of(d: &Data, rot: RotationParam, with_r: bool) -> FfrBody {
    let inv = FfrInvariants::from_lumped(&d.u0, &d.masses, d.modes_t.as_ref()).unwrap();
    let mr = if with_r {
        Some(d.modes_r.as_ref())
    } else {
        None
    };
    FfrBody::new(inv, rot, &d.u0, d.modes_t.as_ref(), mr, d.k.as_ref()).unwrap()
}

pub(super) fn random_state(seed: &mut u64, b: &FfrBody, qf_scale: f64) -> (Vec<f64>, Vec<f64>) {
    let nf = b.nf();
    let mut q = vec![rnd(seed), rnd(seed), rnd(seed)];
    match b.rotation {
        RotationParam::Cardan => q.extend([rnd(seed) * 3.0, rnd(seed) * 1.3, rnd(seed) * 3.0]),
        RotationParam::Quaternion => {
            let p = normalize_quaternion(&Vector4::new(rnd(seed), rnd(seed), rnd(seed), rnd(seed)))
                .unwrap();
            q.extend(p.iter());
        }
    }
    q.extend((0..nf).map(|_| qf_scale * rnd(seed)));
    let u = (0..6 + nf).map(|_| 2.0 * rnd(seed)).collect();
    (q, u)
}

/// `q + h T(q) u` (one explicit step along the motion).
pub(super) fn advance(b: &FfrBody, q: &[f64], u: &[f64], h: f64) -> Vec<f64> {
    let mut qd = vec![0.0; q.len()];
    b.coordinate_rates(q, u, &mut qd);
    q.iter().zip(&qd).map(|(a, d)| a + h * d).collect()
}

pub(super) fn mass_matrix(b: &FfrBody, q: &[f64], u: &[f64]) -> DMatrix<f64> {
    let mut s = FfrScratch::new(b.nf());
    b.update(q, u, &mut s).unwrap();
    let mut m = DMatrix::zeros(b.nu(), b.nu());
    b.mass_matrix(&s, faer_view_mut(&mut m));
    m
}

pub(super) fn jt(b: &FfrBody, j: usize, q: &[f64], u: &[f64]) -> DMatrix<f64> {
    let mut s = FfrScratch::new(b.nf());
    b.update(q, u, &mut s).unwrap();
    let mut m = DMatrix::zeros(3, b.nu());
    b.node_jacobian_translation(j, &s, faer_view_mut(&mut m))
        .unwrap();
    m
}

pub(super) fn node_pos(b: &FfrBody, j: usize, q: &[f64]) -> Vector3<f64> {
    let mut s = FfrScratch::new(b.nf());
    let u = vec![0.0; b.nu()];
    b.update(q, &u, &mut s).unwrap();
    b.node_kinematics(j, q, &u, &s).unwrap().r
}

pub(super) fn qv(b: &FfrBody, q: &[f64], u: &[f64]) -> DVector<f64> {
    let mut s = FfrScratch::new(b.nf());
    b.update(q, u, &mut s).unwrap();
    let mut out = DVector::zeros(b.nu());
    b.quadratic_velocity(&s, out.as_mut_slice());
    out
}

fn rel(a: &DMatrix<f64>, b: &DMatrix<f64>) -> f64 {
    (a - b).abs().max() / b.abs().max().max(1e-300)
}

const PARAMS: [RotationParam; 2] = [RotationParam::Cardan, RotationParam::Quaternion];

/// J_T (2.70) equals finite differences of the node position along `q_dot = T(q) e_i` (1e-7),
/// and M from the invariants equals sum_j m_j J_j^T J_j (2.40)-(2.44) to 1e-12 relative.
#[test]
fn mass_matrix_equals_node_sum() {
    let mut seed = 11;
    for rot in PARAMS {
        for trial in 0..10 {
            let d = random_data(&mut seed, 7, 4, 0.3);
            let b = body_of(&d, rot, false);
            let (q, u) = random_state(&mut seed, &b, 0.5);
            let mut brute = DMatrix::zeros(b.nu(), b.nu());
            for j in 0..b.num_nodes() {
                let jj = jt(&b, j, &q, &u);
                brute += d.masses[j] * jj.transpose() * &jj;
                if trial < 2 {
                    let h = 1e-6;
                    for i in 0..b.nu() {
                        let mut e = vec![0.0; b.nu()];
                        e[i] = 1.0;
                        let fd = (node_pos(&b, j, &advance(&b, &q, &e, h))
                            - node_pos(&b, j, &advance(&b, &q, &e, -h)))
                            / (2.0 * h);
                        assert!(
                            (fd - jj.column(i)).norm() < 1e-7,
                            "J_T column {i}: {}",
                            (fd - jj.column(i)).norm()
                        );
                    }
                }
            }
            let m = mass_matrix(&b, &q, &u);
            let e = rel(&m, &brute);
            assert!(e < 1e-12, "{rot:?}: M relative error {e:e}");
        }
    }
}

/// Q_v equals -sum_j m_j J_j^T (J_dot_j u) with J_dot_j u by central differences of J_j along the
/// motion (1e-6 relative); the analytic bias `J_dot_T u` of the node kinematics agrees (1e-6).
#[test]
fn quadratic_velocity_equals_node_sum_of_jacobian_derivatives() {
    let mut seed = 5;
    for rot in PARAMS {
        for _ in 0..5 {
            let d = random_data(&mut seed, 6, 3, 0.3);
            let b = body_of(&d, rot, false);
            let (q, u) = random_state(&mut seed, &b, 0.5);
            let uv = DVector::from_column_slice(&u);
            let h = 1e-5;
            let (qp, qm) = (advance(&b, &q, &u, h), advance(&b, &q, &u, -h));
            let mut s = FfrScratch::new(b.nf());
            b.update(&q, &u, &mut s).unwrap();
            let mut brute = DVector::zeros(b.nu());
            for j in 0..b.num_nodes() {
                let jdot_u = (jt(&b, j, &qp, &u) - jt(&b, j, &qm, &u)) / (2.0 * h) * &uv;
                brute -= d.masses[j] * jt(&b, j, &q, &u).transpose() * &jdot_u;
                let bias = b.node_kinematics(j, &q, &u, &s).unwrap().a_bias;
                assert!((bias - &jdot_u).norm() < 1e-6 * jdot_u.norm().max(1.0));
            }
            let e = (qv(&b, &q, &u) - &brute).norm() / brute.norm();
            assert!(e < 1e-6, "{rot:?}: Q_v relative error {e:e}");
        }
    }
}

/// Cardan (holonomic): Q_v = -M_dot u + 1/2 d(u^T M u)/dq (2.77), both by central differences
/// (1e-6 relative). Quaternion (omega_bar are quasi-velocities): Hamel's form
/// Q_v = -M_dot u + T(q)^T dT*/dq - [0; ω̄ × dT*/dω̄; 0].
#[test]
fn quadratic_velocity_equals_lagrange_and_hamel_forms() {
    let mut seed = 17;
    for rot in PARAMS {
        for _ in 0..5 {
            let d = random_data(&mut seed, 6, 3, 0.3);
            let b = body_of(&d, rot, false);
            let (q, u) = random_state(&mut seed, &b, 0.5);
            let uv = DVector::from_column_slice(&u);
            let h = 1e-6;
            let mdot = (mass_matrix(&b, &advance(&b, &q, &u, h), &u)
                - mass_matrix(&b, &advance(&b, &q, &u, -h), &u))
                / (2.0 * h);
            let mut lag = -mdot * &uv;
            // gradient of T* = 1/2 u^T M u along the directions T(q) e_i
            for i in 0..b.nu() {
                let mut e = vec![0.0; b.nu()];
                e[i] = 1.0;
                let tp = 0.5 * uv.dot(&(mass_matrix(&b, &advance(&b, &q, &e, h), &u) * &uv));
                let tm = 0.5 * uv.dot(&(mass_matrix(&b, &advance(&b, &q, &e, -h), &u) * &uv));
                lag[i] += (tp - tm) / (2.0 * h);
            }
            if rot == RotationParam::Quaternion {
                let p = mass_matrix(&b, &q, &u) * &uv;
                let w = Vector3::new(u[3], u[4], u[5]);
                let hamel = w.cross(&Vector3::new(p[3], p[4], p[5]));
                for k in 0..3 {
                    lag[3 + k] -= hamel[k];
                }
            }
            let e = (qv(&b, &q, &u) - &lag).norm() / lag.norm();
            assert!(e < 1e-6, "{rot:?}: relative error {e:e}");
        }
    }
}

/// Zero modes: M is the rigid-body mass matrix [m I, -A S̃ H; ., H^T J_O H] with J_O the inertia
/// about the frame origin (parallel-axis sum), and Q_v = [-A (ω×(ω×S) + Ḣw×S), -H^T(ω×J_O ω + J_O Ḣw)]
/// (gyroscopic ω × J ω), to 1e-12.
#[test]
fn rigid_body_limit() {
    let mut seed = 23;
    for rot in PARAMS {
        let d = random_data(&mut seed, 5, 0, 0.0);
        let b = body_of(&d, rot, false);
        let (q, u) = random_state(&mut seed, &b, 0.0);
        let mass: f64 = d.masses.iter().sum();
        let mut first = Vector3::zeros();
        let mut j_c = Matrix3::zeros(); // inertia about the centre of mass, then parallel axis
        for (x, m) in d.u0.iter().zip(&d.masses) {
            first += *m * Vector3::from(*x);
        }
        let c = first / mass;
        for (x, m) in d.u0.iter().zip(&d.masses) {
            let r = Vector3::from(*x) - c;
            j_c += *m * (r.norm_squared() * Matrix3::identity() - r * r.transpose());
        }
        let j_o = j_c + mass * (c.norm_squared() * Matrix3::identity() - c * c.transpose());
        let p = b.rigid_properties();
        assert!((p.mass - mass).abs() <= 1e-14 * mass);
        assert!((p.center_of_mass - c).norm() <= 1e-14 * c.norm().max(1.0));
        assert!((p.inertia_origin - j_o).norm() <= 1e-12 * j_o.norm());
        assert!((p.inertia_center - j_c).norm() <= 1e-12 * j_o.norm());
        let mut s = FfrScratch::new(0);
        b.update(&q, &u, &mut s).unwrap();
        let mut expected = DMatrix::zeros(6, 6);
        expected
            .view_mut((0, 0), (3, 3))
            .copy_from(&(mass * Matrix3::identity()));
        let m_rw = -s.a * skew(&first) * s.h;
        expected.view_mut((0, 3), (3, 3)).copy_from(&m_rw);
        expected
            .view_mut((3, 0), (3, 3))
            .copy_from(&m_rw.transpose());
        expected
            .view_mut((3, 3), (3, 3))
            .copy_from(&(s.h.transpose() * j_o * s.h));
        let m = mass_matrix(&b, &q, &u);
        assert!(rel(&m, &expected) < 1e-12, "{}", rel(&m, &expected));
        let w = s.omega;
        let qr = -(s.a * (w.cross(&w.cross(&first)) + s.hdot_w.cross(&first)));
        let qw = -(s.h.transpose() * (w.cross(&(j_o * w)) + j_o * s.hdot_w));
        let got = qv(&b, &q, &u);
        let exp = DVector::from_iterator(6, qr.iter().chain(qw.iter()).copied());
        assert!(
            (&got - &exp).norm() <= 1e-12 * exp.norm(),
            "{}",
            (&got - &exp).norm()
        );
        if rot == RotationParam::Quaternion {
            // Euler: -ω × J_O ω in the body frame
            assert!(
                (Vector3::new(got[3], got[4], got[5]) + w.cross(&(j_o * w))).norm()
                    <= 1e-12 * got.norm()
            );
        }
    }
}

/// 1/2 u^T M u equals sum_j 1/2 m_j |r_dot_j|^2 with r_dot_j from central differences of the
/// node positions (1e-7 relative).
#[test]
fn kinetic_energy_equals_node_sum() {
    let mut seed = 31;
    for rot in PARAMS {
        let d = random_data(&mut seed, 8, 4, 0.3);
        let b = body_of(&d, rot, false);
        let (q, u) = random_state(&mut seed, &b, 0.5);
        let h = 1e-5;
        let (qp, qm) = (advance(&b, &q, &u, h), advance(&b, &q, &u, -h));
        let mut brute = 0.0;
        for j in 0..b.num_nodes() {
            let v = (node_pos(&b, j, &qp) - node_pos(&b, j, &qm)) / (2.0 * h);
            brute += 0.5 * d.masses[j] * v.norm_squared();
        }
        let mut s = FfrScratch::new(b.nf());
        b.update(&q, &u, &mut s).unwrap();
        let t = b.kinetic_energy(&mut s, &u);
        assert!(
            ((t - brute) / brute).abs() < 1e-7,
            "{rot:?}: {t} vs {brute}"
        );
    }
}

/// With a diagonal M (3 equal entries per node) the consistent constructor reproduces the lumped
/// invariants to 1e-13; a direction-coupled M is rejected.
#[test]
fn consistent_with_diagonal_mass_equals_lumped() {
    let mut seed = 41;
    let d = random_data(&mut seed, 9, 5, 0.3);
    let n = d.u0.len();
    let trip: Vec<_> = (0..3 * n)
        .map(|i| faer::sparse::Triplet::new(i, i, d.masses[i / 3]))
        .collect();
    let m = flexmbs_fe::SparseMatrix::try_new_from_triplets(3 * n, 3 * n, &trip).unwrap();
    let a = FfrInvariants::from_lumped(&d.u0, &d.masses, d.modes_t.as_ref()).unwrap();
    let c = FfrInvariants::from_consistent(&d.u0, &m, d.modes_t.as_ref()).unwrap();
    assert!(
        a.max_abs_difference(&c) < 1e-13,
        "{:e}",
        a.max_abs_difference(&c)
    );
    let mut trip2 = trip.clone();
    trip2.push(faer::sparse::Triplet::new(0, 1, 0.1));
    let m2 = flexmbs_fe::SparseMatrix::try_new_from_triplets(3 * n, 3 * n, &trip2).unwrap();
    assert!(matches!(
        FfrInvariants::from_consistent(&d.u0, &m2, d.modes_t.as_ref()),
        Err(FfrError::NonIsotropicMass { row: 0, col: 1, .. })
    ));
}

/// Consistent mass of one linear tetrahedron (rho V / 20 (1 + δ_ij) I_3): mass, first and second
/// moments equal the exact volume integrals (second moment: m/20 (sum_a x_a x_a^T + s s^T),
/// s = sum of the vertices) to 1e-14; with linear "modes" Φ = x_k e_l, S_bar is the exact moment.
#[test]
fn consistent_tetrahedron_exact_moments() {
    let x = [
        [0.1, 0.2, 0.0],
        [1.3, 0.1, 0.2],
        [0.2, 0.9, 0.1],
        [0.3, 0.4, 1.1],
    ];
    let xv: Vec<Vector3<f64>> = x.iter().map(|p| Vector3::from(*p)).collect();
    let vol = (xv[1] - xv[0])
        .cross(&(xv[2] - xv[0]))
        .dot(&(xv[3] - xv[0]))
        / 6.0;
    let rho = 7.8;
    let mass = rho * vol;
    let mut trip = Vec::new();
    for i in 0..4 {
        for j in 0..4 {
            let v = mass / 20.0 * if i == j { 2.0 } else { 1.0 };
            for d in 0..3 {
                trip.push(faer::sparse::Triplet::new(3 * i + d, 3 * j + d, v));
            }
        }
    }
    let m = flexmbs_fe::SparseMatrix::try_new_from_triplets(12, 12, &trip).unwrap();
    // one mode: Φ(x) = x_1 e_2 (linear field, exactly interpolated)
    let modes = faer::Mat::from_fn(12, 1, |r, _| if r % 3 == 1 { x[r / 3][0] } else { 0.0 });
    let inv = FfrInvariants::from_consistent(&x, &m, modes.as_ref()).unwrap();
    let s: Vector3<f64> = xv.iter().sum();
    let second = mass / 20.0
        * (xv.iter().map(|p| p * p.transpose()).sum::<Matrix3<f64>>() + s * s.transpose());
    assert!((inv.i1 - mass).abs() < 1e-14 * mass);
    assert!((inv.i_bar - mass * s / 4.0).norm() < 1e-14 * mass);
    assert!((inv.i_kl - second).abs().max() < 1e-14 * mass);
    // S_bar row 2 = ∫ρ x_1 dV, I_kl_bar(k, l=2) = ∫ρ x_k x_1 dV, S_22 = ∫ρ x_1^2 dV
    assert!((inv.s_bar[(1, 0)] - mass * s[0] / 4.0).abs() < 1e-14 * mass);
    assert!(inv.s_bar[(0, 0)].abs() < 1e-15 && inv.s_bar[(2, 0)].abs() < 1e-15);
    for k in 0..3 {
        assert!((inv.i_kl_bar[(3 * k + 1, 0)] - second[(k, 0)]).abs() < 1e-14 * mass);
    }
    assert!((inv.s(1, 1)[(0, 0)] - second[(0, 0)]).abs() < 1e-14 * mass);
    assert!((inv.m_ff[(0, 0)] - second[(0, 0)]).abs() < 1e-14 * mass);
}

/// `node_deformation` is `Φ^p q_f`: with the body frame at rest at the origin (identity rotation)
/// a node's global position is `u0 + u_f` (2.8), to 1e-14; a bad node or length is an error.
#[test]
fn node_deformation_is_modal_displacement() {
    let mut seed = 41;
    let d = random_data(&mut seed, 6, 3, 0.2);
    let b = body_of(&d, RotationParam::Quaternion, false);
    let q_f = [0.01, -0.02, 0.005];
    let mut q = vec![0.0; b.nq()];
    q[3] = 1.0; // identity quaternion
    q[7..].copy_from_slice(&q_f);
    let u = vec![0.0; b.nu()];
    let mut s = FfrScratch::new(3);
    b.update(&q, &u, &mut s).unwrap();
    for node in 0..b.num_nodes() {
        let uf = b.node_deformation(node, &q_f).unwrap();
        let k = b.node_kinematics(node, &q, &u, &s).unwrap();
        let expected = k.r - Vector3::from(d.u0[node]);
        assert!(
            (uf - expected).norm() < 1e-14,
            "node {node}: {uf:?} vs {expected:?}"
        );
    }
    assert!(b.node_deformation(99, &q_f).is_err());
    assert!(b.node_deformation(0, &q_f[..2]).is_err());
}

/// `mass_times_vector` (no assembled M) equals the assembled `mass_matrix` times `v` to round-off
/// (1e-13 relative), for both rotation parametrizations and deformed states.
#[test]
fn mass_times_vector_equals_assembled_product() {
    let mut seed = 17;
    for rot in PARAMS {
        for _ in 0..5 {
            let d = random_data(&mut seed, 7, 4, 0.3);
            let b = body_of(&d, rot, false);
            let (q, u) = random_state(&mut seed, &b, 0.5);
            let v: Vec<f64> = (0..b.nu()).map(|_| rnd(&mut seed)).collect();
            let dense = mass_matrix(&b, &q, &u) * DVector::from_column_slice(&v);
            let mut s = FfrScratch::new(b.nf());
            b.update(&q, &u, &mut s).unwrap();
            let mut out = vec![f64::NAN; b.nu()];
            b.mass_times_vector(&s, &v, &mut out);
            let e = (DVector::from_column_slice(&out) - &dense).norm() / dense.norm();
            assert!(e < 1e-13, "{rot:?}: relative difference {e:e}");
        }
    }
}
