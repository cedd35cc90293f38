//! Mode bookkeeping: rigid-body mode recognition, dominant direction and effective modal mass.

use crate::eigen::symmetric_product;
use crate::reduction::ModeLabel;
use crate::system::{sparse_times, FeSystem};
use faer::prelude::Solve;
use faer::{Mat, MatRef};

/// Relative residual below which a mode counts as a rigid-body mode: the M-norm of its part outside
/// the span of the six rigid-body vectors, relative to its M-norm.
pub const RIGID_MODE_TOLERANCE: f64 = 1e-6;

/// Labels of M-normalised modes `x` (independent DOFs of `sys`) with eigenvalues `omega2`.
/// Participation factors `Gamma_d = x^T M r_d` of the six rigid-body vectors `r_d` (through the centre
/// of mass) give the effective mass fractions `Gamma_d^2 / (r_d^T M r_d)`; the dominant direction is the
/// largest of the six fractions. A mode whose part outside span(r) is below [`RIGID_MODE_TOLERANCE`]
/// is labelled `rigid`.
pub fn label_modes(sys: &FeSystem, x: MatRef<'_, f64>, omega2: &[f64]) -> Vec<ModeLabel> {
    let (_, c) = sys.mass_and_center();
    let r = sys.rigid_body_vectors(c);
    let mr = symmetric_product(&sys.m, r.as_ref());
    let rmr = mr.transpose() * &r;
    let mx = symmetric_product(&sys.m, x);
    let gamma = r.transpose() * &mx; // 6 x k
    let names = ["ux", "uy", "uz", "rx", "ry", "rz"];
    let rigid = rigid_mode_flags(rmr.as_ref(), gamma.as_ref(), x, mx.as_ref());
    (0..x.ncols())
        .map(|k| {
            let frac: Vec<f64> = (0..6)
                .map(|d| {
                    if rmr[(d, d)] > 0.0 {
                        gamma[(d, k)].powi(2) / rmr[(d, d)]
                    } else {
                        0.0
                    }
                })
                .collect();
            let dom = (0..6)
                .max_by(|&a, &b| frac[a].total_cmp(&frac[b]))
                .unwrap_or(0);
            let f = omega2[k].max(0.0).sqrt() / (2.0 * std::f64::consts::PI);
            ModeLabel {
                index: k + 1,
                frequency_hz: if rigid[k] { 0.0 } else { f },
                dominant: if rigid[k] {
                    format!("rigid {}", names[dom])
                } else {
                    names[dom].to_string()
                },
                effective_mass_fraction: [frac[0], frac[1], frac[2]],
            }
        })
        .collect()
}

/// For each mode, whether it lies in the span of the rigid-body vectors (M-orthogonal projection).
fn rigid_mode_flags(
    rmr: MatRef<'_, f64>,
    gamma: MatRef<'_, f64>,
    x: MatRef<'_, f64>,
    mx: MatRef<'_, f64>,
) -> Vec<bool> {
    // Components of the projection: a = (R^T M R)^-1 R^T M x; |x - R a|_M^2 = x^T M x - gamma^T a.
    let Ok(llt) = rmr.llt(faer::Side::Lower) else {
        return vec![false; x.ncols()];
    };
    let a = llt.solve(gamma);
    (0..x.ncols())
        .map(|k| {
            let xmx: f64 = (0..x.nrows()).map(|i| x[(i, k)] * mx[(i, k)]).sum();
            let proj: f64 = (0..6).map(|d| gamma[(d, k)] * a[(d, k)]).sum();
            xmx > 0.0 && ((xmx - proj).max(0.0) / xmx).sqrt() < RIGID_MODE_TOLERANCE
        })
        .collect()
}

/// Number of rigid-body modes among the labels.
pub fn count_rigid(labels: &[ModeLabel]) -> usize {
    labels
        .iter()
        .filter(|l| l.dominant.starts_with("rigid"))
        .count()
}

/// Frequencies in Hz of eigenvalues omega^2 (negative round-off clipped to 0).
pub fn frequencies_hz(omega2: &[f64]) -> Vec<f64> {
    omega2
        .iter()
        .map(|&w2| w2.max(0.0).sqrt() / (2.0 * std::f64::consts::PI))
        .collect()
}

/// Dense `Phi^T A Phi` for a sparse `A`.
pub fn project_dense(a: &crate::SparseMatrix, phi: MatRef<'_, f64>) -> Mat<f64> {
    let ap = sparse_times(a, phi);
    let mut out = phi.transpose() * &ap;
    symmetrize(&mut out);
    out
}

/// Replaces `A` by `(A + A^T) / 2`.
pub fn symmetrize(a: &mut Mat<f64>) {
    let n = a.nrows();
    for i in 0..n {
        for j in 0..i {
            let v = 0.5 * (a[(i, j)] + a[(j, i)]);
            a[(i, j)] = v;
            a[(j, i)] = v;
        }
    }
}
