//! Lumped rotary inertia of the nodes of an FFR body (beyond seed 000, whose lumped formulation
//! carries translational node masses only: a beam body with torsion modes then has a singular
//! modal mass, because torsion moves no node).
//!
//! Node `j` carries a constant rotary inertia `I_j` (3 x 3, body frame). Its angular velocity is
//! `A (omega_bar + Phi_r,j q_f_dot)` (small elastic rotations; the change of `I_j` by the elastic
//! rotation is neglected, consistent with the linear modal kinematics), so with the rotation
//! Jacobian `J_R,j = [0, A H, A Phi_r,j]` ((2.72) extended by the rotational modes, linearized:
//! the node frames of joints use the exact `A J_l(theta) Phi_r,j`, see `kinematics.rs`)
//!
//! `T_r = 1/2 sum_j u^T J_R,j^T A I_j A^T J_R,j u`,
//!
//! and the mass matrix gains the constant-invariant terms
//! `M_ww += H^T I_s H`, `M_wf += H^T C`, `M_ff += D` with
//! `I_s = sum_j I_j`, `C = sum_j I_j Phi_r,j` (3 x n_f), `D = sum_j Phi_r,j^T I_j Phi_r,j`.
//! Lagrange's equations (Hamel's for quaternions) give the quadratic velocity terms, with
//! `omega = omega_bar`, `z = H_dot w`:
//! `Q_v,w += -H^T [omega x (I_s omega + C q_f_dot) + I_s z]`, `Q_v,f += -C^T z`.

use super::{FfrBody, FfrError, FfrScratch};
use faer::MatMut;
use nalgebra::{DMatrix, Matrix3, Vector3};

/// The rotary-inertia invariants of an FFR body (computed once).
#[derive(Debug, Clone, PartialEq)]
pub struct RotaryInertia {
    /// Sum of the node inertias `I_s = sum_j I_j` (body frame).
    pub i_sum: Matrix3<f64>,
    /// `C = sum_j I_j Phi_r,j`, 3 x n_f.
    pub c: DMatrix<f64>,
    /// `D = sum_j Phi_r,j^T I_j Phi_r,j`, n_f x n_f (the modal mass contribution).
    pub d: DMatrix<f64>,
}

impl RotaryInertia {
    /// Invariants of node inertias `node_inertia[j]` (one per node of `body`, symmetric,
    /// positive semi-definite, body frame) with the body's rotational modes (zero contribution
    /// to `C`, `D` without them).
    pub fn new(body: &FfrBody, node_inertia: &[Matrix3<f64>]) -> Result<Self, FfrError> {
        let n = body.num_nodes();
        let nf = body.nf();
        if node_inertia.len() != n {
            return Err(FfrError::DimensionMismatch {
                what: "node rotary inertias",
                expected: n,
                found: node_inertia.len(),
            });
        }
        let mut i_sum = Matrix3::zeros();
        let mut c = DMatrix::zeros(3, nf);
        let mut d = DMatrix::zeros(nf, nf);
        for (node, ij) in node_inertia.iter().enumerate() {
            check_inertia(node, ij)?;
            i_sum += ij;
            let Some(mr) = &body.modes_r else { continue };
            let phi = mr.rows(3 * node, 3);
            let ip = ij * phi;
            c += &ip;
            d += phi.transpose() * ip;
        }
        Ok(Self {
            i_sum,
            c,
            d: 0.5 * (&d + d.transpose()),
        })
    }

    /// Adds the rotary-inertia terms `H^T I_s H`, `H^T C`, `D` to the mass matrix `out`
    /// (n_u x n_u, after [`FfrBody::mass_matrix`]). Needs [`FfrBody::update`] first.
    pub fn add_mass_matrix(&self, s: &FfrScratch, mut out: MatMut<'_, f64>) {
        let nf = self.c.ncols();
        let m_ww = s.h.transpose() * self.i_sum * s.h;
        for i in 0..3 {
            for j in 0..3 {
                out[(3 + i, 3 + j)] += m_ww[(i, j)];
            }
            for a in 0..nf {
                let mut wf = 0.0;
                for k in 0..3 {
                    wf += s.h[(k, i)] * self.c[(k, a)];
                }
                out[(3 + i, 6 + a)] += wf;
                out[(6 + a, 3 + i)] += wf;
            }
        }
        for a in 0..nf {
            for b in 0..nf {
                out[(6 + a, 6 + b)] += self.d[(a, b)];
            }
        }
    }

    /// Adds the rotary-inertia quadratic velocity terms
    /// `-H^T [omega x (I_s omega + C q_f_dot) + I_s z]` and `-C^T z` to `out` (n_u, after
    /// [`FfrBody::quadratic_velocity`]). Needs [`FfrBody::update`] first.
    pub fn add_quadratic_velocity(&self, s: &FfrScratch, out: &mut [f64]) {
        let nf = self.c.ncols();
        let w = s.omega;
        let z = s.hdot_w;
        let mut l = self.i_sum * w;
        for a in 0..nf {
            for k in 0..3 {
                l[k] += self.c[(k, a)] * s.qfd[a];
            }
        }
        let qw = -(s.h.transpose() * (w.cross(&l) + self.i_sum * z));
        for i in 0..3 {
            out[3 + i] += qw[i];
        }
        for a in 0..nf {
            let mut acc = 0.0;
            for k in 0..3 {
                acc += self.c[(k, a)] * z[k];
            }
            out[6 + a] -= acc;
        }
    }
}

/// Checks that a node inertia is finite, symmetric (1e-12 relative) and positive semi-definite.
fn check_inertia(node: usize, ij: &Matrix3<f64>) -> Result<(), FfrError> {
    if ij.iter().any(|v| !v.is_finite()) {
        return Err(FfrError::NonFinite {
            what: "node rotary inertia",
        });
    }
    let scale = ij.abs().max();
    let asym = (ij - ij.transpose()).abs().max();
    let min_eig = ij.symmetric_eigenvalues().min();
    if asym > 1e-12 * scale || min_eig < -1e-12 * scale {
        return Err(FfrError::InvalidMass {
            node,
            mass: if asym > 1e-12 * scale {
                f64::NAN
            } else {
                min_eig
            },
        });
    }
    Ok(())
}

/// Rotary inertia of node rotations about the body axes for a diagonal node inertia
/// `diag(jx, jy, jz)` (convenience for beam nodes whose axes are the body axes).
pub fn diagonal_inertia(j: Vector3<f64>) -> Matrix3<f64> {
    Matrix3::from_diagonal(&j)
}

#[cfg(test)]
mod tests {
    use super::super::body::faer_view_mut;
    use super::super::tests::{advance, body_of, random_data, random_state, rnd};
    use super::*;
    use crate::ffr::RotationParam;
    use nalgebra::DVector;

    fn random_inertias(seed: &mut u64, n: usize) -> Vec<Matrix3<f64>> {
        (0..n)
            .map(|_| {
                let b = Matrix3::from_fn(|_, _| rnd(seed));
                b * b.transpose() + Matrix3::identity() * 0.1
            })
            .collect()
    }

    /// The rotary part alone of `M(q)` and `Q_v(q, u)`.
    fn rotary_parts(
        b: &FfrBody,
        r: &RotaryInertia,
        q: &[f64],
        u: &[f64],
    ) -> (DMatrix<f64>, DVector<f64>) {
        let mut s = FfrScratch::new(b.nf());
        b.update(q, u, &mut s).unwrap();
        let mut m = DMatrix::zeros(b.nu(), b.nu());
        r.add_mass_matrix(&s, faer_view_mut(&mut m));
        let mut qv = DVector::zeros(b.nu());
        r.add_quadratic_velocity(&s, qv.as_mut_slice());
        (m, qv)
    }

    /// The linearized node angular-velocity Jacobian `[0, A H, A Phi_r,j]` of this model (the
    /// node-frame Jacobian of `kinematics.rs` is the exact `A J_l(theta) Phi_r,j`; the rotary
    /// inertia keeps the linear modal kinematics, see the module doc).
    fn linear_rotation_jacobian(b: &FfrBody, j: usize, s: &FfrScratch) -> DMatrix<f64> {
        let mr = b.modes_r.as_ref().unwrap();
        let mut jr = DMatrix::zeros(3, b.nu());
        jr.view_mut((0, 3), (3, 3)).copy_from(&(s.a * s.h));
        let phi = mr.rows(3 * j, 3);
        jr.view_mut((0, 6), (3, b.nf())).copy_from(&(s.a * phi));
        jr
    }

    /// The rotary mass terms equal the brute-force `sum_j J_R,j^T (A I_j A^T) J_R,j` with the
    /// linearized rotation Jacobians (2.72) at random states, Cardan and quaternions, to 1e-12.
    #[test]
    fn rotary_mass_equals_node_sum() {
        let mut seed = 3;
        for rot in [RotationParam::Cardan, RotationParam::Quaternion] {
            for _ in 0..5 {
                let d = random_data(&mut seed, 6, 4, 0.3);
                let b = body_of(&d, rot, true);
                let inertias = random_inertias(&mut seed, 6);
                let r = RotaryInertia::new(&b, &inertias).unwrap();
                let (q, u) = random_state(&mut seed, &b, 0.5);
                let mut s = FfrScratch::new(b.nf());
                b.update(&q, &u, &mut s).unwrap();
                let mut brute = DMatrix::zeros(b.nu(), b.nu());
                for (j, ij) in inertias.iter().enumerate() {
                    let jr = linear_rotation_jacobian(&b, j, &s);
                    let ig = s.a * ij * s.a.transpose();
                    brute += jr.transpose() * ig * &jr;
                }
                let (m, _) = rotary_parts(&b, &r, &q, &u);
                let e = (&m - &brute).abs().max() / brute.abs().max();
                assert!(e < 1e-12, "{rot:?}: {e:e}");
            }
        }
    }

    /// The rotary quadratic velocity terms equal Lagrange's form `-M_dot u + 1/2 d(u^T M u)/dq`
    /// (Cardan) or Hamel's form with `-omega x p_omega` (quaternions) of the rotary mass matrix,
    /// by central differences, to 1e-6 relative.
    #[test]
    fn rotary_quadratic_velocity_equals_lagrange_and_hamel_forms() {
        let mut seed = 9;
        for rot in [RotationParam::Cardan, RotationParam::Quaternion] {
            for _ in 0..5 {
                let d = random_data(&mut seed, 5, 3, 0.3);
                let b = body_of(&d, rot, true);
                let r = RotaryInertia::new(&b, &random_inertias(&mut seed, 5)).unwrap();
                let (q, u) = random_state(&mut seed, &b, 0.5);
                let uv = DVector::from_column_slice(&u);
                let m_at = |q: &[f64]| rotary_parts(&b, &r, q, &u).0;
                let h = 1e-6;
                let mdot =
                    (m_at(&advance(&b, &q, &u, h)) - m_at(&advance(&b, &q, &u, -h))) / (2.0 * h);
                let mut lag = -mdot * &uv;
                for i in 0..b.nu() {
                    let mut e = vec![0.0; b.nu()];
                    e[i] = 1.0;
                    let tp = 0.5 * uv.dot(&(m_at(&advance(&b, &q, &e, h)) * &uv));
                    let tm = 0.5 * uv.dot(&(m_at(&advance(&b, &q, &e, -h)) * &uv));
                    lag[i] += (tp - tm) / (2.0 * h);
                }
                let (m, qv) = rotary_parts(&b, &r, &q, &u);
                if rot == RotationParam::Quaternion {
                    let p = &m * &uv;
                    let w = Vector3::new(u[3], u[4], u[5]);
                    let hamel = w.cross(&Vector3::new(p[3], p[4], p[5]));
                    for k in 0..3 {
                        lag[3 + k] -= hamel[k];
                    }
                }
                let e = (&qv - &lag).norm() / lag.norm();
                assert!(e < 1e-6, "{rot:?}: relative error {e:e}");
            }
        }
    }

    /// Energy `1/2 u^T M u + 1/2 q_f^T K q_f` and angular momentum about the origin
    /// `sum_j m_j r_j x v_j + A (I_s omega + C q_f_dot)` (1e-8 relative) of a free, spinning body
    /// with rotary inertia (set through [`FfrBody::set_rotary_inertia`]), integrated with RK4
    /// (1000 steps of 1e-3 s), Cardan and quaternions: validates the wiring of M and Q_v.
    #[test]
    fn free_flight_with_rotary_inertia_conserves_energy_and_momentum() {
        for rot in [RotationParam::Cardan, RotationParam::Quaternion] {
            let mut seed = 21;
            let d = random_data(&mut seed, 5, 2, 0.3);
            let mut b = body_of(&d, rot, true);
            b.set_rotary_inertia(&random_inertias(&mut seed, 5))
                .unwrap();
            let r = b.rotary.clone().unwrap();
            let mut q = match rot {
                RotationParam::Cardan => vec![0.1, -0.2, 0.3, 0.2, 0.3, -0.1],
                RotationParam::Quaternion => vec![0.1, -0.2, 0.3, 0.9, 0.1, 0.3, -0.2],
            };
            q.extend([0.05, -0.03]);
            b.normalize(&mut q).unwrap();
            let mut u = vec![0.3, -0.1, 0.2, 1.5, -2.0, 1.0, 0.2, -0.1];
            let mut s = FfrScratch::new(b.nf());
            let g = Vector3::zeros();
            let invariants = |q: &[f64], u: &[f64], s: &mut FfrScratch| {
                b.update(q, u, s).unwrap();
                let e = b.kinetic_energy(s, u) + 0.5 * s.qf.dot(&(&b.k_ff * &s.qf));
                let mut l = s.a * (r.i_sum * s.omega + &r.c * &s.qfd);
                for (j, m) in d.masses.iter().enumerate() {
                    let k = b.node_kinematics(j, q, u, s).unwrap();
                    l += *m * k.r.cross(&k.v);
                }
                (e, l)
            };
            let (e0, l0) = invariants(&q, &u, &mut s);
            let (nq, nu, dt) = (b.nq(), b.nu(), 1e-3);
            for _ in 0..1000 {
                let mut kq = vec![vec![0.0; nq]; 4];
                let mut ku = vec![vec![0.0; nu]; 4];
                for stage in 0..4 {
                    let c = [0.0, 0.5, 0.5, 1.0][stage] * dt;
                    let (qt, ut): (Vec<f64>, Vec<f64>) = if stage == 0 {
                        (q.clone(), u.clone())
                    } else {
                        (
                            q.iter()
                                .zip(&kq[stage - 1])
                                .map(|(a, k)| a + c * k)
                                .collect(),
                            u.iter()
                                .zip(&ku[stage - 1])
                                .map(|(a, k)| a + c * k)
                                .collect(),
                        )
                    };
                    b.coordinate_rates(&qt, &ut, &mut kq[stage]);
                    b.accelerations(&qt, &ut, &g, &mut s, &mut ku[stage])
                        .unwrap();
                }
                for i in 0..nq {
                    q[i] += dt / 6.0 * (kq[0][i] + 2.0 * kq[1][i] + 2.0 * kq[2][i] + kq[3][i]);
                }
                for i in 0..nu {
                    u[i] += dt / 6.0 * (ku[0][i] + 2.0 * ku[1][i] + 2.0 * ku[2][i] + ku[3][i]);
                }
            }
            let (e1, l1) = invariants(&q, &u, &mut s);
            let (de, dl) = ((e1 - e0).abs() / e0, (l1 - l0).norm() / l0.norm());
            eprintln!("{rot:?}: rel. drift energy {de:e}, angular momentum {dl:e}");
            assert!(de < 1e-8 && dl < 1e-8, "{rot:?}: {de:e} {dl:e}");
            assert!((q[nq - 2] - 0.05).abs() > 1e-3);
        }
    }

    /// A torsion-only body (translational modes zero, rotational modes about x): the lumped
    /// translational modal mass is singular, the rotary term makes it `sum_j jx_j phi_j^2`; bad
    /// inertias are rejected.
    #[test]
    fn torsion_mode_gets_modal_mass() {
        let mut seed = 5;
        let mut d = random_data(&mut seed, 4, 1, 0.3);
        d.modes_t = faer::Mat::zeros(12, 1);
        d.modes_r = faer::Mat::from_fn(12, 1, |i, _| if i % 3 == 0 { (i / 3) as f64 } else { 0.0 });
        let b = body_of(&d, RotationParam::Cardan, true);
        assert_eq!(b.invariants.m_ff[(0, 0)], 0.0);
        let jx = [0.5, 1.0, 2.0, 4.0];
        let inertias: Vec<_> = jx
            .iter()
            .map(|&j| diagonal_inertia(Vector3::new(j, 3.0, 3.0)))
            .collect();
        let r = RotaryInertia::new(&b, &inertias).unwrap();
        let expected: f64 = jx.iter().enumerate().map(|(k, j)| j * (k * k) as f64).sum();
        assert!((r.d[(0, 0)] - expected).abs() < 1e-14 * expected);
        let mut bad = inertias.clone();
        bad[2][(0, 1)] = 0.5;
        assert!(matches!(
            RotaryInertia::new(&b, &bad),
            Err(FfrError::InvalidMass { node: 2, .. })
        ));
        bad[2] = diagonal_inertia(Vector3::new(-1.0, 1.0, 1.0));
        assert!(RotaryInertia::new(&b, &bad).is_err());
        assert!(RotaryInertia::new(&b, &inertias[..3]).is_err());
    }
}
