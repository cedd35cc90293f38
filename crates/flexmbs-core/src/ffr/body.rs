//! The FFR body: mass matrix (seed 000 (2.44)-(2.69)), quadratic velocity vector (2.77)-(2.79)
//! (re-derived, see `docs/notation-ffr.md`), stiffness (2.36), damping, generalized forces and
//! accelerations, for Cardan or quaternion rotation coordinates.

use super::{FfrError, FfrInvariants};
use crate::rotation::{
    cardan_g_bar, cardan_g_bar_dot, cardan_matrix, check_cardan, quaternion_e_transpose,
    quaternion_matrix, skew,
};
use faer::MatMut;
use flexmbs_fe::reduction::ReducedBody;
use nalgebra::{DMatrix, DVector, Matrix3, Vector3, Vector4};

pub use crate::rotation::CARDAN_SINGULARITY_TOLERANCE;

/// Rotation coordinates of the floating frame: the same choice as for rigid bodies (Cardan
/// angles x-y-z, seed 000 (2.22), with `theta_dot` (2.26); or a unit quaternion `[w, x, y, z]`
/// with the body-frame angular velocity `omega_bar`).
pub use crate::rigid::RotationParam;

/// Mass properties of the undeformed body, in body-frame axes: what a rigid model of it needs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RigidProperties {
    /// Total mass `I1` (2.47).
    pub mass: f64,
    /// Centre of mass `I_bar / I1` in the body frame.
    pub center_of_mass: Vector3<f64>,
    /// Inertia tensor about the body-frame origin: `tr(I_kl) 1 - I_kl` plus the node rotary
    /// inertia `I_s` if set.
    pub inertia_origin: Matrix3<f64>,
    /// Inertia tensor about the centre of mass (parallel-axis theorem): the tensor
    /// [`crate::RigidBody::new`] takes.
    pub inertia_center: Matrix3<f64>,
}

/// A floating-frame-of-reference body with constant, precomputed inertia invariants.
#[derive(Debug, Clone)]
pub struct FfrBody {
    /// Inertia shape integrals.
    pub invariants: FfrInvariants,
    /// Rotation coordinates.
    pub rotation: RotationParam,
    /// Undeformed node positions u0 (body frame).
    pub u0: Vec<Vector3<f64>>,
    /// Translational modes, 3N x n_f.
    pub modes_t: DMatrix<f64>,
    /// Rotational modes, 3N x n_f (small rotations), if the nodes carry rotations.
    pub modes_r: Option<DMatrix<f64>>,
    /// Modal stiffness k_ff (2.19), the only non-zero block of K (2.36).
    pub k_ff: DMatrix<f64>,
    /// Modal damping matrix d_ff (zero unless set).
    pub d_ff: DMatrix<f64>,
    /// Lumped node rotary inertia terms added to `M` and `Q_v` (none unless set with
    /// [`FfrBody::set_rotary_inertia`]).
    pub rotary: Option<super::RotaryInertia>,
    /// `S_23 - S_32, S_31 - S_13, S_12 - S_21` (2.68), n_f x n_f each.
    pub(super) s_skew: [DMatrix<f64>; 3],
    /// Transposes of `s_skew` (a row of `D_k` as a contiguous column, for `D_k q_f_dot`).
    pub(super) s_skew_t: [DMatrix<f64>; 3],
    /// The nine `S_kl^T` interleaved in the layout of `P` (see `moments.rs`): the deformed
    /// moments are one matrix-vector product `P - Ī = S q_f`.
    pub(super) moments: super::moments::MomentOperator,
    /// Geometric (centrifugal) stiffening, off (`None`) by default (see `stiffening.rs`).
    pub(super) geometric: Option<super::GeometricStiffening>,
    /// Geometric stiffening by node loads and accelerations, off (`None`) by default
    /// (`load_stiffening.rs`).
    pub(super) load_stiffening: Option<super::LoadStiffening>,
}

/// Per-body work buffers and the evaluated state (created once, reused: no allocation at run time).
#[derive(Debug, Clone)]
pub struct FfrScratch {
    /// Rotation matrix A (2.22).
    pub a: Matrix3<f64>,
    /// `H` with `omega_bar = H w` (`G_bar` (2.31) for Cardan, I for quaternions).
    pub h: Matrix3<f64>,
    /// `H_dot w` (`G_bar_dot theta_dot` (2.80); zero for quaternions).
    pub hdot_w: Vector3<f64>,
    /// Body-frame angular velocity omega_bar.
    pub omega: Vector3<f64>,
    /// Modal coordinates q_f.
    pub qf: DVector<f64>,
    /// Modal velocities q_f_dot.
    pub qfd: DVector<f64>,
    /// First moment of the deformed body `S_t = I_bar + S_bar q_f` (2.55).
    pub s_t: Vector3<f64>,
    /// Inertia tensor about the frame origin `Ī_θθ` (2.59).
    pub i_tt: Matrix3<f64>,
    /// `Ī_θf = sum m ũ Φ` (2.67), 3 x n_f.
    pub i_tf: DMatrix<f64>,
    /// `P_kl = sum m ū_k Φ_l = Ī_kl + q_f^T S_kl` (deformed), row 3k+l, 9 x n_f.
    pub p: DMatrix<f64>,
    /// Mass matrix buffer for [`FfrBody::accelerations`], n_u x n_u.
    pub m: DMatrix<f64>,
    /// Force buffer for [`FfrBody::accelerations`], n_u.
    pub rhs: DVector<f64>,
}

impl FfrScratch {
    /// Buffers for a body with `nf` modes.
    pub fn new(nf: usize) -> Self {
        Self {
            a: Matrix3::identity(),
            h: Matrix3::identity(),
            hdot_w: Vector3::zeros(),
            omega: Vector3::zeros(),
            qf: DVector::zeros(nf),
            qfd: DVector::zeros(nf),
            s_t: Vector3::zeros(),
            i_tt: Matrix3::zeros(),
            i_tf: DMatrix::zeros(3, nf),
            p: DMatrix::zeros(9, nf),
            m: DMatrix::zeros(6 + nf, 6 + nf),
            rhs: DVector::zeros(6 + nf),
        }
    }
}

fn copy_modes(m: faer::MatRef<'_, f64>) -> DMatrix<f64> {
    DMatrix::from_fn(m.nrows(), m.ncols(), |i, j| m[(i, j)])
}

impl FfrBody {
    /// Mass, centre of mass and inertia of the undeformed body from the invariants (and the
    /// node rotary inertia, if set): the rigid-body equivalent, e.g. for a rigid twin model
    /// (`RigidBody::new(p.mass, p.inertia_center)` with its frame at `p.center_of_mass`).
    pub fn rigid_properties(&self) -> RigidProperties {
        let inv = &self.invariants;
        let mass = inv.i1;
        let c = inv.i_bar / mass;
        let inertia_origin = Matrix3::identity() * inv.i_kl.trace() - inv.i_kl
            + self.rotary.as_ref().map_or(Matrix3::zeros(), |r| r.i_sum);
        let inertia_center =
            inertia_origin - mass * (Matrix3::identity() * c.norm_squared() - c * c.transpose());
        RigidProperties {
            mass,
            center_of_mass: c,
            inertia_origin,
            inertia_center,
        }
    }

    /// Body from invariants and node data. `modes_t`/`modes_r` are 3N x n_f, `k_ff` n_f x n_f.
    pub fn new(
        invariants: FfrInvariants,
        rotation: RotationParam,
        u0: &[[f64; 3]],
        modes_t: faer::MatRef<'_, f64>,
        modes_r: Option<faer::MatRef<'_, f64>>,
        k_ff: faer::MatRef<'_, f64>,
    ) -> Result<Self, FfrError> {
        let nf = invariants.nf;
        let n = u0.len();
        let check = |what, expected: usize, found: usize| {
            if expected == found {
                Ok(())
            } else {
                Err(FfrError::DimensionMismatch {
                    what,
                    expected,
                    found,
                })
            }
        };
        check("rows of modes_t", 3 * n, modes_t.nrows())?;
        check("columns of modes_t", nf, modes_t.ncols())?;
        if let Some(r) = modes_r {
            check("rows of modes_r", 3 * n, r.nrows())?;
            check("columns of modes_r", nf, r.ncols())?;
        }
        check("rows of k_ff", nf, k_ff.nrows())?;
        check("columns of k_ff", nf, k_ff.ncols())?;
        let inv = &invariants;
        let s_skew = [
            inv.s(1, 2) - inv.s(2, 1),
            inv.s(2, 0) - inv.s(0, 2),
            inv.s(0, 1) - inv.s(1, 0),
        ];
        Ok(Self {
            moments: super::moments::MomentOperator::new(&inv.s_kl, nf),
            rotation,
            u0: u0.iter().map(|x| Vector3::new(x[0], x[1], x[2])).collect(),
            modes_t: copy_modes(modes_t),
            modes_r: modes_r.map(copy_modes),
            k_ff: copy_modes(k_ff),
            d_ff: DMatrix::zeros(nf, nf),
            rotary: None,
            s_skew_t: s_skew.clone().map(|d| d.transpose()),
            s_skew,
            invariants,
            geometric: None,
            load_stiffening: None,
        })
    }

    /// Body of a reduced body with lumped node masses (units as stored: convert with
    /// [`super::reduced_body_to_si`] first).
    pub fn from_reduced(body: &ReducedBody, rotation: RotationParam) -> Result<Self, FfrError> {
        let masses = body
            .node_masses
            .as_ref()
            .ok_or_else(|| FfrError::MissingNodeMasses {
                name: body.name.clone(),
            })?;
        let inv = FfrInvariants::from_lumped(&body.nodes, masses, body.modes_t.as_ref())?;
        Self::new(
            inv,
            rotation,
            &body.nodes,
            body.modes_t.as_ref(),
            body.modes_r.as_ref().map(|m| m.as_ref()),
            body.k_red.as_ref(),
        )
    }

    /// Number of modes n_f.
    pub fn nf(&self) -> usize {
        self.invariants.nf
    }
    /// Number of nodes.
    pub fn num_nodes(&self) -> usize {
        self.u0.len()
    }
    /// Length of q: 3 + (3 or 4) + n_f.
    pub fn nq(&self) -> usize {
        3 + self.rotation.num_coordinates() + self.nf()
    }
    /// Length of u: 6 + n_f.
    pub fn nu(&self) -> usize {
        6 + self.nf()
    }

    /// Adds lumped rotary inertias `node_inertia[j]` (body frame, one per node) to the mass
    /// matrix and the quadratic velocity vector ([`super::RotaryInertia`]); replaces earlier ones.
    /// Damping derived from `m_ff` (Rayleigh, modal ratios) uses the translational `m_ff` only.
    /// For a beam mesh the inertias come from its lumped mass matrix:
    /// `flexmbs_io::full_mass::node_rotary_inertias` (then `rotary_inertias_to_si` for an
    /// SI(mm) body), as `flexmbs run` does. The analytic tangent ([`Self::force_tangents`])
    /// includes the rotary terms.
    pub fn set_rotary_inertia(
        &mut self,
        node_inertia: &[nalgebra::Matrix3<f64>],
    ) -> Result<(), FfrError> {
        self.rotary = Some(super::RotaryInertia::new(self, node_inertia)?);
        Ok(())
    }

    /// Rayleigh damping `d_ff = alpha m_ff + beta k_ff` (modal block only).
    pub fn set_rayleigh_damping(&mut self, alpha: f64, beta: f64) {
        self.d_ff = alpha * &self.invariants.m_ff + beta * &self.k_ff;
    }

    /// Modal damping ratios: `d_ff = diag(2 zeta_i sqrt(k_ii m_ii))`, i.e. `2 zeta_i omega_i` for
    /// mass-normalised modes (`m_ii = 1`, `k_ii = omega_i^2`). Needs diagonal m_ff and k_ff
    /// (relative off-diagonals < 1e-8).
    pub fn set_modal_damping(&mut self, zeta: &[f64]) -> Result<(), FfrError> {
        let nf = self.nf();
        if zeta.len() != nf {
            return Err(FfrError::DimensionMismatch {
                what: "modal damping ratios",
                expected: nf,
                found: zeta.len(),
            });
        }
        for mat in [&self.invariants.m_ff, &self.k_ff] {
            for i in 0..nf {
                for j in 0..nf {
                    let scale = (mat[(i, i)].abs() * mat[(j, j)].abs())
                        .sqrt()
                        .max(f64::MIN_POSITIVE);
                    let relative = mat[(i, j)].abs() / scale;
                    if i != j && relative > 1e-8 {
                        return Err(FfrError::NotDiagonal {
                            row: i,
                            col: j,
                            relative,
                        });
                    }
                }
            }
        }
        self.d_ff = DMatrix::zeros(nf, nf);
        for (i, z) in zeta.iter().enumerate() {
            self.d_ff[(i, i)] = 2.0
                * z
                * (self.k_ff[(i, i)] * self.invariants.m_ff[(i, i)])
                    .max(0.0)
                    .sqrt();
        }
        Ok(())
    }

    /// Evaluates all state-dependent quantities for `(q, u)` into `s`: A, H, omega_bar, H_dot w,
    /// `P_kl`, S_t (2.55), Ī_θθ (2.59)-(2.64), Ī_θf (2.67)-(2.68). Cost O(9 n_f^2), no allocation.
    pub fn update(&self, q: &[f64], u: &[f64], s: &mut FfrScratch) -> Result<(), FfrError> {
        let nf = self.nf();
        let nr = self.rotation.num_coordinates();
        if q.len() != self.nq() {
            return Err(FfrError::DimensionMismatch {
                what: "q",
                expected: self.nq(),
                found: q.len(),
            });
        }
        if u.len() != self.nu() {
            return Err(FfrError::DimensionMismatch {
                what: "u",
                expected: self.nu(),
                found: u.len(),
            });
        }
        if s.qf.len() != nf {
            return Err(FfrError::DimensionMismatch {
                what: "scratch modes",
                expected: nf,
                found: s.qf.len(),
            });
        }
        let w = Vector3::new(u[3], u[4], u[5]);
        match self.rotation {
            RotationParam::Cardan => {
                let th = Vector3::new(q[3], q[4], q[5]);
                check_cardan(&th, CARDAN_SINGULARITY_TOLERANCE)?;
                s.a = cardan_matrix(&th);
                s.h = cardan_g_bar(&th);
                s.hdot_w = cardan_g_bar_dot(&th, &w) * w;
            }
            RotationParam::Quaternion => {
                let p = Vector4::new(q[3], q[4], q[5], q[6]);
                let norm = p.norm();
                if !(norm.is_finite() && norm > 1e-12) {
                    return Err(
                        crate::rotation::RotationError::DegenerateQuaternion { norm }.into(),
                    );
                }
                s.a = quaternion_matrix(&p);
                s.h = Matrix3::identity();
                s.hdot_w = Vector3::zeros();
            }
        }
        s.omega = s.h * w;
        s.qf.copy_from_slice(&q[3 + nr..]);
        s.qfd.copy_from_slice(&u[6..]);
        self.update_moments(s);
        Ok(())
    }

    /// Mass matrix `M(q)` (2.44) written into `out` (n_u x n_u) from the invariants:
    /// `m_RR = I1 I` (2.47), `m_Rw = -A S̃_t H` (2.50), `m_Rf = A S_bar` (2.57),
    /// `m_ww = H^T Ī_θθ H` (2.58), `m_wf = H^T Ī_θf` (2.66), `m_ff` (2.69).
    /// Needs [`Self::update`] first. O(n_f^2).
    pub fn mass_matrix(&self, s: &FfrScratch, mut out: MatMut<'_, f64>) {
        let nf = self.nf();
        let inv = &self.invariants;
        let m_rw = -s.a * skew(&s.s_t) * s.h;
        let m_ww = s.h.transpose() * s.i_tt * s.h;
        for i in 0..3 {
            for j in 0..3 {
                out[(i, j)] = if i == j { inv.i1 } else { 0.0 };
                out[(i, 3 + j)] = m_rw[(i, j)];
                out[(3 + j, i)] = m_rw[(i, j)];
                out[(3 + i, 3 + j)] = m_ww[(i, j)];
            }
            for a in 0..nf {
                let mut rf = 0.0;
                let mut wf = 0.0;
                for k in 0..3 {
                    rf += s.a[(i, k)] * inv.s_bar[(k, a)];
                    wf += s.h[(k, i)] * s.i_tf[(k, a)];
                }
                out[(i, 6 + a)] = rf;
                out[(6 + a, i)] = rf;
                out[(3 + i, 6 + a)] = wf;
                out[(6 + a, 3 + i)] = wf;
            }
        }
        // constant modal block: a vectorized column copy
        out.as_mut()
            .submatrix_mut(6, 6, nf, nf)
            .copy_from(faer::MatRef::from_column_major_slice(
                inv.m_ff.as_slice(),
                nf,
                nf,
            ));
        if let Some(r) = &self.rotary {
            r.add_mass_matrix(s, out);
        }
    }

    /// Quadratic velocity vector `Q_v = -sum_j m_j J_j^T (J_dot_j u)` (equal to (2.77) for Cardan;
    /// corrected (2.79), see `docs/notation-ffr.md`), written into `out` (n_u). With
    /// `ω = omega_bar`, `z = H_dot w`, `N_kl = P_kl q_f_dot`:
    /// - R: `-A [ω×(ω×S_t) + 2 ω×(S_bar q_f_dot) + z×S_t]`
    /// - w: `-H^T [ω×(Ī_θθ ω) + 2 (tr(N) ω - N^T ω) + Ī_θθ z]`
    /// - f: `-[sum_kl ω_k ω_l P_lk^T - |ω|^2 sum_k P_kk^T - 2 sum_k ω_k D_k q_f_dot + Ī_θf^T z]`,
    ///   `D_1 = S_23 - S_32`, ... (cyclic).
    ///
    /// Needs [`Self::update`] first. O(n_f^2).
    pub fn quadratic_velocity(&self, s: &FfrScratch, out: &mut [f64]) {
        let nf = self.nf();
        let (qr, c) = self.quadratic_velocity_frame_terms(s);
        let qw = -(s.h.transpose() * c);
        for i in 0..3 {
            out[i] = qr[i];
            out[3 + i] = qw[i];
        }
        for (a, o) in out[6..6 + nf].iter_mut().enumerate() {
            *o = -self.quadratic_velocity_modal_sum(s, a, |k| {
                // row a of D_k (column a of its stored transpose) times q_f_dot
                let d_row = &self.s_skew_t[k].as_slice()[a * nf..(a + 1) * nf];
                d_row
                    .iter()
                    .zip(s.qfd.as_slice())
                    .fold(0.0, |acc, (d, q)| acc + d * q)
            });
        }
        if let Some(r) = &self.rotary {
            r.add_quadratic_velocity(s, out);
        }
    }

    /// The reference-frame rows of [`Self::quadratic_velocity`]: the translational row
    /// `-A [ω×(ω×S_t) + 2 ω×(S_bar q_f_dot) + z×S_t]` and the rotational bracket
    /// `c = ω×(Ī_θθ ω) + 2 (tr(N) ω - N^T ω) + Ī_θθ z` (the row is `-H^T c`). O(n_f).
    pub(super) fn quadratic_velocity_frame_terms(
        &self,
        s: &FfrScratch,
    ) -> (Vector3<f64>, Vector3<f64>) {
        let inv = &self.invariants;
        let (w, z) = (s.omega, s.hdot_w);
        let mut sqd = Vector3::zeros();
        let mut n = Matrix3::zeros();
        for a in 0..self.nf() {
            for k in 0..3 {
                sqd[k] += inv.s_bar[(k, a)] * s.qfd[a];
                for l in 0..3 {
                    n[(k, l)] += s.p[(3 * k + l, a)] * s.qfd[a];
                }
            }
        }
        let qr = -(s.a * (w.cross(&w.cross(&s.s_t)) + 2.0 * w.cross(&sqd) + z.cross(&s.s_t)));
        let c = w.cross(&(s.i_tt * w)) + 2.0 * (n.trace() * w - n.transpose() * w) + s.i_tt * z;
        (qr, c)
    }

    /// The bracket of modal row `a` of [`Self::quadratic_velocity`],
    /// `sum_kl ω_k ω_l P_lk^T - |ω|^2 sum_k P_kk^T - 2 sum_k ω_k (D_k q_f_dot)_a + Ī_θf^T z`
    /// (the row is its negative), with `(D_k q_f_dot)_a` from `d_qfd(k)`. O(1) besides `d_qfd`.
    pub(super) fn quadratic_velocity_modal_sum(
        &self,
        s: &FfrScratch,
        a: usize,
        d_qfd: impl Fn(usize) -> f64,
    ) -> f64 {
        let (w, z) = (s.omega, s.hdot_w);
        let w2 = w.norm_squared();
        let mut acc = 0.0;
        for k in 0..3 {
            for l in 0..3 {
                acc += w[k] * w[l] * s.p[(3 * l + k, a)];
            }
            acc -= w2 * s.p[(4 * k, a)];
            acc += s.i_tf[(k, a)] * z[k];
            acc -= 2.0 * w[k] * d_qfd(k);
        }
        acc
    }

    /// Adds the elastic and damping forces `-K q - D u` (2.35)-(2.36) (modal block only) to `out`,
    /// plus the geometric stiffening force `-K_geo(omega_bar) q_f` when switched on.
    pub fn add_internal_forces(&self, s: &FfrScratch, out: &mut [f64]) {
        self.add_geometric_stiffening_force(s, out);
        let nf = self.nf();
        for a in 0..nf {
            let mut acc = 0.0;
            for b in 0..nf {
                acc += self.k_ff[(a, b)] * s.qf[b] + self.d_ff[(a, b)] * s.qfd[b];
            }
            out[6 + a] -= acc;
        }
    }

    /// Adds the generalized gravity force `sum_j m_j J_j^T g` to `out`:
    /// `[I1 g, H^T (S_t × A^T g), S_bar^T A^T g]` (exact for lumped and consistent masses).
    pub fn add_gravity_force(&self, s: &FfrScratch, g: &Vector3<f64>, out: &mut [f64]) {
        let gb = s.a.transpose() * g;
        let tw = s.h.transpose() * s.s_t.cross(&gb);
        for i in 0..3 {
            out[i] += self.invariants.i1 * g[i];
            out[3 + i] += tw[i];
        }
        for a in 0..self.nf() {
            let mut acc = 0.0;
            for k in 0..3 {
                acc += self.invariants.s_bar[(k, a)] * gb[k];
            }
            out[6 + a] += acc;
        }
    }

    /// Kinetic energy `1/2 u^T M u` (2.43) of the state evaluated by [`Self::update`] (`M u` by
    /// [`Self::mass_times_vector`] into `s.rhs`; with node rotary inertia `M` assembled in `s.m`;
    /// no allocation).
    pub fn kinetic_energy(&self, s: &mut FfrScratch, u: &[f64]) -> f64 {
        if self.rotary.is_none() {
            // 1/2 u^T (M u) with the O(n_f^2) product instead of the assembled matrix
            let mut mu = std::mem::replace(&mut s.rhs, DVector::zeros(0));
            self.mass_times_vector(s, u, mu.as_mut_slice());
            let e = 0.5 * mu.iter().zip(u).map(|(a, b)| a * b).sum::<f64>();
            s.rhs = mu;
            return e;
        }
        let nu = self.nu();
        let mut m = std::mem::replace(&mut s.m, DMatrix::zeros(0, 0));
        self.mass_matrix(s, faer_view_mut(&mut m));
        let mut e = 0.0;
        for i in 0..nu {
            for j in 0..nu {
                e += 0.5 * u[i] * m[(i, j)] * u[j];
            }
        }
        s.m = m;
        e
    }

    /// Time derivative of the coordinates `q_dot = T(q) u`: `R_dot`, then `theta_dot` (Cardan)
    /// or `p_dot = 1/2 E(p) omega_bar` (quaternion), then `q_f_dot`.
    pub fn coordinate_rates(&self, q: &[f64], u: &[f64], qdot: &mut [f64]) {
        qdot[..3].copy_from_slice(&u[..3]);
        match self.rotation {
            RotationParam::Cardan => {
                qdot[3..6].copy_from_slice(&u[3..6]);
                qdot[6..].copy_from_slice(&u[6..]);
            }
            RotationParam::Quaternion => {
                let p = Vector4::new(q[3], q[4], q[5], q[6]);
                let pd =
                    0.5 * quaternion_e_transpose(&p).transpose() * Vector3::new(u[3], u[4], u[5]);
                qdot[3..7].copy_from_slice(pd.as_slice());
                qdot[7..].copy_from_slice(&u[6..]);
            }
        }
    }

    /// Normalizes the quaternion part of `q` (no-op for Cardan).
    pub fn normalize(&self, q: &mut [f64]) -> Result<(), FfrError> {
        if self.rotation == RotationParam::Quaternion {
            let p = crate::rotation::normalize_quaternion(&Vector4::new(q[3], q[4], q[5], q[6]))?;
            q[3..7].copy_from_slice(p.as_slice());
        }
        Ok(())
    }

    /// Accelerations `u_dot` of the free body: solves `M u_dot = Q_v - K q - D u + Q_g` (2.73)
    /// (gravity `g`, no constraints) by a Cholesky factorization in the scratch buffers.
    pub fn accelerations(
        &self,
        q: &[f64],
        u: &[f64],
        g: &Vector3<f64>,
        s: &mut FfrScratch,
        udot: &mut [f64],
    ) -> Result<(), FfrError> {
        let nu = self.nu();
        if udot.len() != nu {
            return Err(FfrError::DimensionMismatch {
                what: "udot",
                expected: nu,
                found: udot.len(),
            });
        }
        self.update(q, u, s)?;
        let mut m = std::mem::replace(&mut s.m, DMatrix::zeros(0, 0));
        self.mass_matrix(s, faer_view_mut(&mut m));
        self.quadratic_velocity(s, udot);
        self.add_internal_forces(s, udot);
        self.add_gravity_force(s, g, udot);
        let res = crate::linsolve::cholesky_factor(faer_view_mut(&mut m), 1e-14)
            .map(|()| crate::linsolve::cholesky_solve(faer_view_mut(&mut m).as_ref(), udot))
            .map_err(|(pivot, value)| FfrError::NotPositiveDefinite { pivot, value });
        s.m = m;
        res
    }
}

/// `y = A x` for a column-major matrix `A` (faer's SIMD matrix-vector product, sequential).
pub(crate) fn mat_vec(a: &DMatrix<f64>, x: &[f64], y: &mut [f64]) {
    let (r, c) = a.shape();
    let lhs = faer::MatRef::from_column_major_slice(a.as_slice(), r, c);
    let rhs = faer::MatRef::from_column_major_slice(x, c, 1);
    let dst = faer::MatMut::from_column_major_slice_mut(y, r, 1);
    faer::linalg::matmul::matmul(dst, faer::Accum::Replace, lhs, rhs, 1.0, faer::Par::Seq);
}

/// A faer view of a column-major nalgebra matrix (no copy).
pub(crate) fn faer_view_mut(m: &mut DMatrix<f64>) -> MatMut<'_, f64> {
    let (r, c) = m.shape();
    faer::MatMut::from_column_major_slice_mut(m.as_mut_slice(), r, c)
}
