//! The `q_f`-dependent moments of the deformed body (seed 000 (2.55)-(2.68)) in one pass over
//! plain slices: `P_kl`, `S_t`, `Ī_θθ`, `Ī_θf`.
//!
//! The O(9 n_f^2) part is `P_kl - Ī_kl = S_kl^T q_f` for the nine `(k, l)`. [`MomentOperator`]
//! stores the nine `S_kl^T` interleaved in the layout of [`super::FfrScratch::p`] (row `9 a + kl`
//! of a `9 n_f x n_f` column-major matrix holds row `a` of `S_kl^T`), so the product lands in `P`
//! directly as `n_f` contiguous multiply-adds of length `9 n_f`; the `O(n_f)` rest (`S_t`, `u_kl`,
//! `Ī_θf`) is fused into one loop over the modes. (faer's SIMD matrix-vector product beat a plain
//! loop from 6 modes on, measured with callgrind on the `ffr_steps` bench.)

use super::{FfrBody, FfrScratch};
use nalgebra::{DMatrix, Matrix3};

/// The nine `S_kl^T` interleaved: `9 n_f x n_f`, column-major, entry `(9 a + 3 k + l, b)` =
/// `S_kl[b, a]`.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct MomentOperator {
    nf: usize,
    op: DMatrix<f64>,
}

impl MomentOperator {
    /// From the nine `S_kl` (`s_kl[3 k + l]`, `n_f x n_f` each).
    pub(super) fn new(s_kl: &[DMatrix<f64>], nf: usize) -> Self {
        let op = DMatrix::from_fn(9 * nf, nf, |row, b| {
            let (a, kl) = (row / 9, row % 9);
            s_kl[kl][(b, a)]
        });
        Self { nf, op }
    }

    /// `y = op x` (`y`: `9 n_f`, in the layout of `P`), faer's SIMD matrix-vector product.
    pub(super) fn apply(&self, x: &[f64], y: &mut [f64]) {
        debug_assert_eq!(y.len(), 9 * self.nf);
        super::body::mat_vec(&self.op, x, y);
    }
}

impl FfrBody {
    /// `P_kl = Ī_kl + S_kl^T q_f`, `S_t = I_bar + S_bar q_f` (2.55), `Ī_θθ = tr(u) I - u` with
    /// `u_kl = sym(I_kl + Σ_a (Ī_lk,a + P_kl,a) q_f,a)` (2.59)-(2.64), `Ī_θf` rows
    /// `P_23 - P_32, P_31 - P_13, P_12 - P_21` (2.67)-(2.68), from `s.qf`. O(9 n_f^2), no
    /// allocation.
    pub(super) fn update_moments(&self, s: &mut FfrScratch) {
        let nf = self.nf();
        let inv = &self.invariants;
        let FfrScratch {
            qf,
            p,
            s_t,
            i_tt,
            i_tf,
            ..
        } = s;
        let (qf, p) = (qf.as_slice(), p.as_mut_slice());
        self.moments.apply(qf, p);
        let ikb = inv.i_kl_bar.as_slice();
        let s_bar = inv.s_bar.as_slice();
        let i_tf = i_tf.as_mut_slice();
        let mut st = [inv.i_bar[0], inv.i_bar[1], inv.i_bar[2]];
        let mut u: [[f64; 3]; 3] =
            std::array::from_fn(|k| std::array::from_fn(|l| inv.i_kl[(k, l)]));
        for a in 0..nf {
            let x = qf[a];
            let (pa, ika) = (&mut p[9 * a..9 * a + 9], &ikb[9 * a..9 * a + 9]);
            for (pv, ik) in pa.iter_mut().zip(ika) {
                *pv += ik;
            }
            for k in 0..3 {
                st[k] += s_bar[3 * a + k] * x;
                for l in 0..3 {
                    u[k][l] += (ika[3 * l + k] + pa[3 * k + l]) * x;
                }
            }
            i_tf[3 * a] = pa[5] - pa[7];
            i_tf[3 * a + 1] = pa[6] - pa[2];
            i_tf[3 * a + 2] = pa[1] - pa[3];
        }
        *s_t = st.into();
        let ukl = Matrix3::from_fn(|k, l| u[k][l]);
        let ukl = 0.5 * (ukl + ukl.transpose());
        *i_tt = Matrix3::identity() * ukl.trace() - ukl;
    }
}
