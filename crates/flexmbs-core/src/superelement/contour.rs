//! The superelement as a [`NeutralContourSource`] (`docs/engine.md`, "Neutral contours"): the
//! recovered floating frame `(x_j, R_j)`, field coordinates the local coordinates `q_loc`, and a
//! material point `x = x_j + R_j ū`, `ū = X_0 + Φ q_loc` (`Φ`: the translational rows of the
//! Craig-Bampton basis at the point). Its variation (seed 001 (3.17), (3.18)):
//!
//! ```text
//!     δx = δx_j + δπ_j × R_j ū + R_j Φ δq_loc,
//!     δx_j = R_j Z_t P δv,   δπ_j = R_j Z_r P δv,   δq_loc = Λ (P − Φ_rig Z P) δv
//! ```
//!
//! so `J_T = R_j [Z_t P + (Z_r P) × ū − (Φ Λ Φ_rig) Z P + Φ Λ P]`, formed block by block (`P`
//! has one 3 x 3 block per interface node, `Λ` one per interface rotation) in O(n) per point
//! once `Z P` is known. [`Superelement`]'s `update` prepares `Z P`, `ω̄ = Z_r P u` and
//! `q̇_loc` for this.

use super::eval::SuperelementEval;
use super::{BeamSegmentSpec, Superelement, SuperelementData};
use crate::contour_source::{NeutralContourSource, NodeTable};
use crate::rotation::skew;
use faer::MatMut;
use nalgebra::{DMatrix, Matrix3, Vector3};

impl Superelement {
    /// `Z P`, `ω̄` and `q̇_loc = Λ (P u − Φ_rig Z P u)` of the evaluated state for the contour
    /// source (allocation-free).
    /// Without velocities (`u` of another length) the rates are zero.
    pub(super) fn contour_kinematics(&self, e: &mut SuperelementEval, u: &[f64]) {
        self.frame_variation(e);
        if u.len() != self.n() {
            e.omega_bar = Vector3::zeros();
            e.qd_loc.fill(0.0);
            return;
        }
        let zp = &e.work.zp;
        let a: [f64; 6] =
            std::array::from_fn(|r| (0..self.n()).map(|j| zp[(r, j)] * u[j]).sum::<f64>());
        e.omega_bar = Vector3::new(a[3], a[4], a[5]);
        for i in 0..self.n() {
            let pu: f64 = (0..self.n()).map(|j| e.p[(i, j)] * u[j]).sum();
            let rig: f64 = (0..6).map(|c| e.phi_rig[(i, c)] * a[c]).sum();
            e.qd_loc[i] = pu - rig;
        }
        for (k, l) in e.lam.iter().enumerate() {
            let v = l * e.qd_loc.fixed_rows::<3>(6 * k + 3);
            e.qd_loc.fixed_rows_mut::<3>(6 * k + 3).copy_from(&v);
        }
    }
}

impl SuperelementEval {
    /// Column `j` of `Z P`: `(a_t, a_r)`.
    fn zp_col(&self, j: usize) -> (Vector3<f64>, Vector3<f64>) {
        let zp = &self.work.zp;
        (
            Vector3::new(zp[(0, j)], zp[(1, j)], zp[(2, j)]),
            Vector3::new(zp[(3, j)], zp[(4, j)], zp[(5, j)]),
        )
    }

    /// The blocks `Φ_t,k`, `Φ_r,k Λ_k` of `C = Φ Λ` for interface `k`.
    fn c_blocks(&self, phi: &[Vector3<f64>], k: usize) -> (Matrix3<f64>, Matrix3<f64>) {
        let ct = Matrix3::from_columns(&[phi[6 * k], phi[6 * k + 1], phi[6 * k + 2]]);
        let cr = Matrix3::from_columns(&[phi[6 * k + 3], phi[6 * k + 4], phi[6 * k + 5]]);
        (ct, cr * self.lam[k])
    }
}

impl NeutralContourSource for SuperelementEval {
    fn frame_rotation(&self) -> &Matrix3<f64> {
        &self.rj
    }
    fn frame_angular_velocity(&self) -> &Vector3<f64> {
        &self.omega_bar
    }
    fn field_coordinates(&self) -> &[f64] {
        self.q_loc.as_slice()
    }
    fn field_velocities(&self) -> &[f64] {
        self.qd_loc.as_slice()
    }
    fn num_velocities(&self) -> usize {
        self.q_loc.len()
    }

    fn point_jacobian(&self, u: &Vector3<f64>, phi: &[Vector3<f64>], mut jt: MatMut<'_, f64>) {
        let (n, ni) = (self.q_loc.len(), self.node_x.len());
        // C Φ_rig = [Σ C_t,k, Σ (C_r,k − C_t,k r_k~)]
        let (mut cr_t, mut cr_r) = (Matrix3::zeros(), Matrix3::zeros());
        for k in 0..ni {
            let (ct, cr) = self.c_blocks(phi, k);
            cr_t += ct;
            cr_r += cr - ct * skew(&self.r[k]);
        }
        for j in 0..n {
            let (at, ar) = self.zp_col(j);
            let col = at + ar.cross(u) - cr_t * at - cr_r * ar;
            for i in 0..3 {
                jt[(i, j)] = col[i];
            }
        }
        // + C P: one block per interface node, identity for the internal modes
        let rjt = self.rj.transpose();
        let mut add = |j: usize, v: Vector3<f64>| {
            for i in 0..3 {
                jt[(i, j)] += v[i];
            }
        };
        for k in 0..ni {
            let (ct, cr) = self.c_blocks(phi, k);
            let (bt, br) = (ct * rjt, cr * (rjt * self.node_r[k]));
            for m in 0..3 {
                add(self.vel_index[6 * k + m], bt.column(m).into_owned());
                add(self.vel_index[6 * k + 3 + m], br.column(m).into_owned());
            }
        }
        for (i, p) in phi.iter().enumerate().take(n).skip(6 * ni) {
            add(self.vel_index[i], *p);
        }
        for j in 0..n {
            let v = self.rj * Vector3::new(jt[(0, j)], jt[(1, j)], jt[(2, j)]);
            for i in 0..3 {
                jt[(i, j)] = v[i];
            }
        }
    }

    fn add_arm_jacobian(&self, d: &Vector3<f64>, mut jac: MatMut<'_, f64>) {
        for j in 0..self.q_loc.len() {
            let w = self.rj * self.zp_col(j).1;
            let v = w.cross(d);
            for i in 0..3 {
                jac[(i, j)] += v[i];
            }
        }
    }

    fn rotation_jacobian(&self, mut jac: MatMut<'_, f64>) {
        for j in 0..self.q_loc.len() {
            let w = self.rj * self.zp_col(j).1;
            for i in 0..3 {
                jac[(i, j)] = w[i];
            }
        }
    }

    fn add_rotation_row(&self, v: &Vector3<f64>, scale: f64, out: &mut [f64]) {
        for (j, o) in out.iter_mut().enumerate().take(self.q_loc.len()) {
            *o += scale * self.zp_col(j).1.dot(v);
        }
    }

    /// `(J_qᵀ c)_j = ((Λᵀ c)ᵀ P)_j − ((Λᵀ c)ᵀ Φ_rig) (Z P)_j`.
    fn add_field_row(&self, c: &dyn Fn(usize) -> f64, out: &mut [f64]) {
        let (n, ni) = (self.q_loc.len(), self.node_x.len());
        let rjt = self.rj.transpose();
        let block = |k: usize| {
            let ct = Vector3::new(c(6 * k), c(6 * k + 1), c(6 * k + 2));
            let cr = Vector3::new(c(6 * k + 3), c(6 * k + 4), c(6 * k + 5));
            (ct, self.lam[k].transpose() * cr)
        };
        let (mut g_t, mut g_r) = (Vector3::zeros(), Vector3::zeros());
        for k in 0..ni {
            let (ct, cr) = block(k);
            g_t += ct;
            g_r += self.r[k].cross(&ct) + cr;
        }
        for (j, o) in out.iter_mut().enumerate().take(n) {
            let (at, ar) = self.zp_col(j);
            *o -= g_t.dot(&at) + g_r.dot(&ar);
        }
        for k in 0..ni {
            let (ct, cr) = block(k);
            let (pt, pr) = (
                rjt.transpose() * ct,
                (rjt * self.node_r[k]).transpose() * cr,
            );
            for m in 0..3 {
                out[self.vel_index[6 * k + m]] += pt[m];
                out[self.vel_index[6 * k + 3 + m]] += pr[m];
            }
        }
        for i in 6 * ni..n {
            out[self.vel_index[i]] += c(i);
        }
    }
}

/// The FE nodes of a beam segment ([`super::beam_segment_with_interfaces`]: its data `data`
/// and basis `v`, 6 DOF per node, node `i` at `x = i L / n_e`) as contour nodes of its
/// superelement: positions in the floating frame and the translational rows of `v`.
pub fn beam_segment_contour_nodes(
    spec: &BeamSegmentSpec,
    data: &SuperelementData,
    v: &DMatrix<f64>,
) -> NodeTable {
    let ne = super::even_elements(spec);
    // the undeformed centre of mass is the midpoint: it fixes the frame origin along the axis
    let origin = 0.5 * spec.length - data.centre_of_mass.x;
    let positions = (0..=ne)
        .map(|i| Vector3::new(spec.length * i as f64 / ne as f64 - origin, 0.0, 0.0))
        .collect::<Vec<_>>();
    fe_contour_nodes(positions, v, 6)
}

/// Contour nodes from FE node positions (floating-frame axes) and a basis `v` with `dofs` rows
/// per node, the first three the translations (columns: the superelement's local coordinates).
pub fn fe_contour_nodes(positions: Vec<Vector3<f64>>, v: &DMatrix<f64>, dofs: usize) -> NodeTable {
    let n = positions.len();
    let shapes = DMatrix::from_fn(3 * n, v.ncols(), |r, c| v[(dofs * (r / 3) + r % 3, c)]);
    NodeTable {
        positions,
        shapes,
        velocities: v.ncols(),
    }
}
