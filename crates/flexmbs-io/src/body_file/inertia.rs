//! The optional dataset `inertia/gram` of the reduced-body file: the Gram matrix `G = f^T m f` of
//! the scalar node fields `f = [1, x_1, x_2, x_3, Phi_1, Phi_2, Phi_3]` under the consistent FE
//! mass (`flexmbs_core::ffr::FfrInvariants::consistent_gram`). It holds every inertia shape
//! integral of the FFR body (mass, first and second moments, `S_bar`, `S_kl`, `m_ff`; seed 000
//! (2.47)-(2.69)), so a body reduced from a consistent mass matrix (a CalculiX deck, or a built-in
//! solid mesh with `mass = "consistent"`) runs from its `.fmb.h5` file with `inertia =
//! "consistent"`, without the FE model (see `docs/formats/reduced-body.md`).
//!
//! Layout: f64 `[4 + 3 N_f, 4 + 3 N_f]`, row-major, rows and columns in the order `1, x_1, x_2,
//! x_3`, then the `N_f` modes of the x components, of the y and of the z components; units of the
//! file (entry `(i, j)` in mass · `s_i s_j` with `s = [1, length, length, length, mode, ...]`).

use super::h5::{checksummed, invalid, Reader};
use super::BodyFileError;
use flexmbs_fe::reduction::ReducedBody;
use hdf5_pure::FileBuilder;
use nalgebra::DMatrix;
use std::path::Path;

/// Consistent-mass Gram matrix, f64 `[4 + 3 N_f, 4 + 3 N_f]` (optional).
pub(crate) const GRAM: &str = "inertia/gram";

/// Relative tolerance of the checks of a stored Gram matrix: symmetry `max |G_ij - G_ji| <= tol ·
/// max |G_ij|`, and the modal mass it implies, `m_ff = S_11 + S_22 + S_33`, equal to the stored
/// reduced mass `reduced/mass` (`Phi^T M Phi` of the same mass matrix) to `tol · max |M_red|`.
pub const GRAM_TOLERANCE: f64 = 1e-8;

/// Checks the Gram matrix `g` of `body`: `(4 + 3 N_f)` square, finite, symmetric, a positive
/// total mass `G[0, 0]`, and its modal block consistent with `body.m_red` (all to
/// [`GRAM_TOLERANCE`]).
pub(crate) fn check(
    path: &Path,
    g: &DMatrix<f64>,
    body: &ReducedBody,
) -> Result<(), BodyFileError> {
    let bad = |message: String| invalid(path, GRAM, message);
    let nf = body.num_modes();
    let size = 4 + 3 * nf;
    if g.nrows() != size || g.ncols() != size {
        return Err(bad(format!(
            "is {} x {}, expected (4 + 3 N_f) = {size} square",
            g.nrows(),
            g.ncols()
        )));
    }
    if let Some(v) = g.iter().find(|v| !v.is_finite()) {
        return Err(bad(format!("non-finite entry {v}")));
    }
    let scale = g.abs().max();
    let asym = (g - g.transpose()).abs().max();
    if asym > GRAM_TOLERANCE * scale {
        return Err(bad(format!(
            "not symmetric: max |G_ij - G_ji| / max |G_ij| = {:e} > {GRAM_TOLERANCE:e}",
            asym / scale
        )));
    }
    if g[(0, 0)] <= 0.0 {
        return Err(bad(format!(
            "total mass G[0, 0] = {} is not positive",
            g[(0, 0)]
        )));
    }
    let m_red = &body.m_red;
    let m_scale = (0..nf)
        .flat_map(|i| (0..nf).map(move |j| (i, j)))
        .map(|(i, j)| m_red[(i, j)].abs())
        .fold(0.0, f64::max);
    for i in 0..nf {
        for j in 0..nf {
            let m_ff: f64 = (0..3).map(|k| g[(4 + k * nf + i, 4 + k * nf + j)]).sum();
            let d = (m_ff - m_red[(i, j)]).abs();
            if d > GRAM_TOLERANCE * m_scale {
                return Err(bad(format!(
                    "its modal mass m_ff = S_11 + S_22 + S_33 differs from reduced/mass at \
                     ({i}, {j}): {m_ff:e} vs {:e} (the matrix is not of this body's mass)",
                    m_red[(i, j)]
                )));
            }
        }
    }
    Ok(())
}

/// Adds the `inertia` group with the checked Gram matrix `g`.
pub(crate) fn encode(fb: &mut FileBuilder, g: &DMatrix<f64>) {
    let n = g.nrows() as u64;
    let data: Vec<f64> = (0..g.nrows())
        .flat_map(|i| (0..g.ncols()).map(move |j| g[(i, j)]))
        .collect();
    let mut grp = fb.create_group("inertia");
    checksummed(grp.create_dataset("gram"), &data, &[n, n]);
    fb.add_group(grp.finish());
}

/// Reads `inertia/gram` of `body`, if the file has it, and checks it like the writer does.
pub(crate) fn decode(
    r: &Reader,
    body: &ReducedBody,
) -> Result<Option<DMatrix<f64>>, BodyFileError> {
    let Some(d) = r.optional(GRAM)? else {
        return Ok(None);
    };
    let size = 4 + 3 * body.num_modes();
    let s = Some(size as u64);
    let what = format!("[4 + 3 N_f, 4 + 3 N_f] = [{size}, {size}]");
    let data = r.f64s(GRAM, &d, &[s, s], &what)?;
    let g = DMatrix::from_fn(size, size, |i, j| data[i * size + j]);
    check(r.path, &g, body)?;
    Ok(Some(g))
}
