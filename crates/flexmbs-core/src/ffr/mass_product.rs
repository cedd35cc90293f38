//! The product `M(q) v` of the FFR mass matrix (seed 000 (2.44)-(2.69)) with a vector, without
//! assembling `M`: O(n_f^2) for the constant modal block plus O(n_f) for the coupling blocks,
//! instead of writing all `(6 + n_f)^2` entries and multiplying.

use super::{FfrBody, FfrScratch};
use crate::rotation::skew;
use nalgebra::Vector3;

impl FfrBody {
    /// `out = M v` with the blocks of [`FfrBody::mass_matrix`] (translational terms; node rotary
    /// inertia is not included): with `v = [v_R, v_w, v_f]`,
    /// - `out_R = I1 v_R + m_Rw v_w + A (S_bar v_f)`, `m_Rw = -A S̃_t H` (2.50), (2.57);
    /// - `out_w = m_Rw^T v_R + H^T Ī_θθ H v_w + H^T (Ī_θf v_f)` (2.58), (2.66);
    /// - `out_f = S_bar^T (A^T v_R) + Ī_θf^T (H v_w) + m_ff v_f` (2.69).
    ///
    /// Needs [`Self::update`] first (the `q` part). No allocation.
    pub fn mass_times_vector(&self, s: &FfrScratch, v: &[f64], out: &mut [f64]) {
        let nf = self.nf();
        let inv = &self.invariants;
        let (v_r, v_w) = (
            Vector3::new(v[0], v[1], v[2]),
            Vector3::new(v[3], v[4], v[5]),
        );
        let v_f = &v[6..6 + nf];
        let (s_bar, i_tf) = (inv.s_bar.as_slice(), s.i_tf.as_slice());
        // S_bar v_f and Ī_θf v_f (3 x n_f, columns contiguous)
        let (mut sv, mut iv) = (Vector3::zeros(), Vector3::zeros());
        for (a, x) in v_f.iter().enumerate() {
            for k in 0..3 {
                sv[k] += s_bar[3 * a + k] * x;
                iv[k] += i_tf[3 * a + k] * x;
            }
        }
        let m_rw = -s.a * skew(&s.s_t) * s.h;
        let out_r = inv.i1 * v_r + m_rw * v_w + s.a * sv;
        let out_w = m_rw.transpose() * v_r + s.h.transpose() * (s.i_tt * (s.h * v_w) + iv);
        out[..3].copy_from_slice(out_r.as_slice());
        out[3..6].copy_from_slice(out_w.as_slice());
        let (at_v, h_v) = (s.a.transpose() * v_r, s.h * v_w);
        let out_f = &mut out[6..6 + nf];
        for (a, o) in out_f.iter_mut().enumerate() {
            let mut acc = 0.0;
            for k in 0..3 {
                acc += s_bar[3 * a + k] * at_v[k] + i_tf[3 * a + k] * h_v[k];
            }
            *o = acc;
        }
        // m_ff v_f column by column (contiguous columns; none without modes)
        for (col, x) in inv.m_ff.as_slice().chunks_exact(nf.max(1)).zip(v_f) {
            for (o, m) in out_f.iter_mut().zip(col) {
                *o += m * x;
            }
        }
    }
}
