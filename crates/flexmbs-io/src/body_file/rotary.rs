//! The optional dataset `nodes/rotary_inertia` of the reduced-body file: lumped node rotary
//! inertias of a beam body (3 x 3 per node, body frame, units of the file: mass · length²),
//! written by `flexmbs reduce` for beam meshes and applied by a multibody model through
//! `flexmbs_core::ffr::FfrBody::set_rotary_inertia` (see `docs/formats/reduced-body.md`).
//!
//! Layout: f64 `[N, 3, 3]`, row-major, entry `[j, a, b]` = `I_j[(a, b)]` of node `j`.

use super::h5::{invalid, Reader};
use super::BodyFileError;
use nalgebra::Matrix3;
use std::path::Path;

/// Node rotary inertias, f64 `[N, 3, 3]` (optional).
pub(crate) const ROTARY_INERTIA: &str = "nodes/rotary_inertia";

/// Relative tolerance of the symmetry and positive semi-definiteness checks of a stored node
/// inertia `I_j`: `max |I_ab - I_ba| <= tol · max |I_ab|` and smallest eigenvalue
/// `>= -tol · max |I_ab|` (the tolerance of `FfrBody::set_rotary_inertia`, so that every
/// inertia the reader accepts is accepted by the engine).
pub const ROTARY_INERTIA_TOLERANCE: f64 = 1e-12;

/// Checks the node inertias of a body with `n` nodes: one per node, every entry finite, each
/// symmetric and positive semi-definite to [`ROTARY_INERTIA_TOLERANCE`] relative. `object` names
/// the place in errors.
pub(crate) fn check(
    path: &Path,
    object: &str,
    inertia: &[Matrix3<f64>],
    n: usize,
) -> Result<(), BodyFileError> {
    let bad = |message: String| invalid(path, object, message);
    if inertia.len() != n {
        return Err(bad(format!(
            "{} node inertias for {n} nodes",
            inertia.len()
        )));
    }
    for (j, ij) in inertia.iter().enumerate() {
        if let Some(v) = ij.iter().find(|v| !v.is_finite()) {
            return Err(bad(format!("node {j}: non-finite entry {v}")));
        }
        let scale = ij.abs().max();
        let asym = (ij - ij.transpose()).abs().max();
        if asym > ROTARY_INERTIA_TOLERANCE * scale {
            return Err(bad(format!(
                "node {j}: not symmetric: max |I_ab - I_ba| / max |I_ab| = {:e} > \
                 {ROTARY_INERTIA_TOLERANCE:e}",
                asym / scale
            )));
        }
        let min_eig = ij.symmetric_eigenvalues().min();
        if min_eig < -ROTARY_INERTIA_TOLERANCE * scale {
            return Err(bad(format!(
                "node {j}: not positive semi-definite: smallest eigenvalue {min_eig:e} \
                 (max |I_ab| = {scale:e})"
            )));
        }
    }
    Ok(())
}

/// The row-major `[N, 3, 3]` data of the node inertias.
pub(crate) fn flatten(inertia: &[Matrix3<f64>]) -> Vec<f64> {
    inertia
        .iter()
        .flat_map(|m| (0..3).flat_map(move |a| (0..3).map(move |b| m[(a, b)])))
        .collect()
}

/// Reads `nodes/rotary_inertia` of a body with `n` nodes, if the file has it, and checks it like
/// the writer does.
pub(crate) fn decode(r: &Reader, n: usize) -> Result<Option<Vec<Matrix3<f64>>>, BodyFileError> {
    let Some(d) = r.optional(ROTARY_INERTIA)? else {
        return Ok(None);
    };
    let data = r.f64s(
        ROTARY_INERTIA,
        &d,
        &[Some(n as u64), Some(3), Some(3)],
        "[N, 3, 3]",
    )?;
    let inertia: Vec<Matrix3<f64>> = data
        .chunks_exact(9)
        .map(|c| Matrix3::from_fn(|a, b| c[3 * a + b]))
        .collect();
    check(r.path, ROTARY_INERTIA, &inertia, n)?;
    Ok(Some(inertia))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `flatten` is row-major per node (`[j, a, b]`), and the check names the first bad node:
    /// non-finite, asymmetric beyond 1e-12 relative, an eigenvalue below -1e-12 relative; a
    /// symmetric PSD matrix with round-off asymmetry of 1e-14 and a zero matrix pass.
    #[test]
    fn flatten_order_and_checks() {
        let m = Matrix3::new(1.0, 2.0, 3.0, 2.0, 5.0, 6.0, 3.0, 6.0, 9.0);
        let d = flatten(&[Matrix3::zeros(), m]);
        assert_eq!(&d[9..], &[1.0, 2.0, 3.0, 2.0, 5.0, 6.0, 3.0, 6.0, 9.0]);
        let p = Path::new("x.fmb.h5");
        let good = Matrix3::new(2.0, 0.5, 0.0, 0.5 + 1e-14, 1.0, 0.0, 0.0, 0.0, 0.0);
        assert!(check(p, ROTARY_INERTIA, &[Matrix3::zeros(), good], 2).is_ok());
        assert!(check(p, ROTARY_INERTIA, &[good], 2)
            .unwrap_err()
            .to_string()
            .contains("1 node inertias for 2 nodes"));
        let mut nan = good;
        nan[(2, 1)] = f64::NAN;
        let mut asym = good;
        asym[(0, 2)] = 1e-9;
        let neg = Matrix3::from_diagonal(&nalgebra::Vector3::new(1.0, -1e-6, 1.0));
        for (bad, text) in [
            (nan, "node 1: non-finite entry NaN"),
            (asym, "node 1: not symmetric"),
            (neg, "node 1: not positive semi-definite"),
        ] {
            let e = check(p, ROTARY_INERTIA, &[good, bad], 2).unwrap_err();
            let s = e.to_string();
            assert!(s.contains(text) && s.contains(ROTARY_INERTIA), "{s}");
        }
    }
}
