//! Geometric (centrifugal) stiffening of an FFR body (unit-load method, Wallrapp/Schwertassek):
//! the modal stiffness of a body spinning with body-frame angular velocity `ω̄` is
//! `k_ff + K_geo(ω̄)`, `K_geo = Σ_{a<=b} ω̄_a ω̄_b K_G,ab`, with the projected geometric stiffness
//! matrices `K_G,ab` of the six centrifugal load patterns computed by the FE front end
//! ([`flexmbs_fe::geometric::geometric_stiffness`]). The generalized elastic force gains
//! `-K_geo(ω̄) q_f`; `ω̄ = H(θ) w` makes it depend on `u` and, for Cardan angles, on `θ`.
//!
//! Switchable: an [`FfrBody`] has no stiffening unless built with
//! [`FfrBody::with_geometric_stiffening`]. A linear FFR body without it shows spin softening
//! (`-Ω² m_ff` from the quadratic velocity vector); stiffening restores the Southwell behaviour.

use super::{FfrBody, FfrError, FfrScratch, RotationParam};
use crate::rotation::cardan_g_bar_dot;
use faer::MatMut;
use flexmbs_fe::geometric::{GeometricStiffness, InertialLoad};
use nalgebra::{DMatrix, Vector3};

/// The centrifugal geometric stiffness carried by an FFR body: pattern axes `(a, b)`, `a <= b`,
/// and `K_G,ab` (n_f × n_f, SI, per (rad/s)²).
#[derive(Debug, Clone, PartialEq)]
pub struct GeometricStiffening {
    /// Axes `(a, b)` of each pattern (coefficient `ω̄_a ω̄_b`).
    pub axes: Vec<(usize, usize)>,
    /// `K_G,ab`, same order as `axes`.
    pub matrices: Vec<DMatrix<f64>>,
}

impl GeometricStiffening {
    /// Takes the centrifugal patterns of `g` (`n_f` modes expected). Translational and
    /// angular-acceleration patterns are not supported by the engine (their coefficients would
    /// be accelerations, unknown when forces are evaluated) and are rejected.
    pub fn from_fe(g: &GeometricStiffness, nf: usize) -> Result<Self, FfrError> {
        let mut axes = Vec::new();
        let mut matrices = Vec::new();
        for (p, m) in g.load_patterns.iter().zip(&g.matrices) {
            match *p {
                InertialLoad::Centrifugal(a, b) if a <= b && b < 3 => {
                    for (what, found) in [
                        ("rows of a geometric stiffness matrix", m.nrows()),
                        ("columns of a geometric stiffness matrix", m.ncols()),
                    ] {
                        if found != nf {
                            return Err(FfrError::DimensionMismatch {
                                what,
                                expected: nf,
                                found,
                            });
                        }
                    }
                    if (0..nf).any(|i| (0..nf).any(|j| !m[(i, j)].is_finite())) {
                        return Err(FfrError::NonFinite {
                            what: "geometric stiffness matrix",
                        });
                    }
                    axes.push((a, b));
                    matrices.push(DMatrix::from_fn(nf, nf, |i, j| m[(i, j)]));
                }
                other => {
                    return Err(FfrError::UnsupportedLoadPattern {
                        pattern: format!("{other:?}"),
                    })
                }
            }
        }
        if g.load_patterns.len() != g.matrices.len() {
            return Err(FfrError::DimensionMismatch {
                what: "geometric stiffness matrices per load pattern",
                expected: g.load_patterns.len(),
                found: g.matrices.len(),
            });
        }
        Ok(Self { axes, matrices })
    }
}

/// `∂(ω_a ω_b)/∂ω · d` for a direction `d`.
fn coefficient_derivative(a: usize, b: usize, w: &Vector3<f64>, d: &Vector3<f64>) -> f64 {
    w[b] * d[a] + w[a] * d[b]
}

impl FfrBody {
    /// The body with geometric (centrifugal) stiffening switched on (off by default). `g` must
    /// be in SI (like the body) and contain only centrifugal patterns for this body's `n_f`.
    pub fn with_geometric_stiffening(mut self, g: &GeometricStiffness) -> Result<Self, FfrError> {
        self.geometric = Some(GeometricStiffening::from_fe(g, self.nf())?);
        Ok(self)
    }

    /// The geometric stiffening data, if switched on.
    pub fn geometric_stiffening(&self) -> Option<&GeometricStiffening> {
        self.geometric.as_ref()
    }

    /// `K_geo(ω̄) = Σ ω̄_a ω̄_b K_G,ab` (allocates; zero matrix without stiffening).
    pub fn geometric_stiffness_matrix(&self, omega_bar: &Vector3<f64>) -> DMatrix<f64> {
        let nf = self.nf();
        let mut k = DMatrix::zeros(nf, nf);
        if let Some(g) = &self.geometric {
            for (&(a, b), m) in g.axes.iter().zip(&g.matrices) {
                k += omega_bar[a] * omega_bar[b] * m;
            }
        }
        k
    }

    /// Adds `-K_geo(ω̄) q_f` to the modal part of `out` (no-op without stiffening). Needs
    /// [`FfrBody::update`] first. O(6 n_f²), no allocation.
    pub fn add_geometric_stiffening_force(&self, s: &FfrScratch, out: &mut [f64]) {
        let Some(g) = &self.geometric else {
            return;
        };
        let nf = self.nf();
        let w = s.omega;
        for (&(a, b), m) in g.axes.iter().zip(&g.matrices) {
            let c = w[a] * w[b];
            if c == 0.0 {
                continue;
            }
            for i in 0..nf {
                let mut acc = 0.0;
                for j in 0..nf {
                    acc += m[(i, j)] * s.qf[j];
                }
                out[6 + i] -= c * acc;
            }
        }
    }

    /// Adds the exact tangent of `-K_geo(ω̄) q_f` to `dh_dq` (along `q ⊕ dv`, `n_u × n_u`) and
    /// `dh_du` (`n_u × n_u`); no-op without stiffening. Needs [`FfrBody::update`] for `(q, u)`
    /// first. Rows `6..`:
    /// - `∂/∂q_f = -K_geo(ω̄)`;
    /// - `∂/∂w_j = -Σ_ab ∂(ω̄_a ω̄_b)/∂ω̄ · H e_j  K_G,ab q_f` (`ω̄ = H w`);
    /// - Cardan: `∂/∂θ_j = -Σ_ab ∂(ω̄_a ω̄_b)/∂ω̄ · (∂H/∂θ_j w) K_G,ab q_f`; quaternions: 0
    ///   (`ω̄ = w` does not depend on `q`).
    ///
    /// O(6 n_f² + 36 n_f), no allocation.
    pub fn add_geometric_stiffening_tangent(
        &self,
        q: &[f64],
        u: &[f64],
        s: &FfrScratch,
        mut dh_dq: MatMut<'_, f64>,
        mut dh_du: MatMut<'_, f64>,
    ) {
        let Some(g) = &self.geometric else {
            return;
        };
        let nf = self.nf();
        let w = s.omega;
        let wu = Vector3::new(u[3], u[4], u[5]);
        // d omega_bar / d theta_j = (dH/dtheta_j) w = G_bar_dot(theta, e_j) w (Cardan)
        let mut dw_dth = [Vector3::zeros(); 3];
        if self.rotation == RotationParam::Cardan {
            let th = Vector3::new(q[3], q[4], q[5]);
            for (j, d) in dw_dth.iter_mut().enumerate() {
                let mut e = Vector3::zeros();
                e[j] = 1.0;
                *d = cardan_g_bar_dot(&th, &e) * wu;
            }
        }
        for (&(a, b), m) in g.axes.iter().zip(&g.matrices) {
            let c = w[a] * w[b];
            let dc_dw: [f64; 3] =
                std::array::from_fn(|j| coefficient_derivative(a, b, &w, &s.h.column(j).into()));
            let dc_dth: [f64; 3] =
                std::array::from_fn(|j| coefficient_derivative(a, b, &w, &dw_dth[j]));
            for i in 0..nf {
                let mut kq = 0.0;
                for j in 0..nf {
                    kq += m[(i, j)] * s.qf[j];
                    dh_dq[(6 + i, 6 + j)] -= c * m[(i, j)];
                }
                for j in 0..3 {
                    dh_du[(6 + i, 3 + j)] -= dc_dw[j] * kq;
                    dh_dq[(6 + i, 3 + j)] -= dc_dth[j] * kq;
                }
            }
        }
    }
}
