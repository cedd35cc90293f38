//! Physical consistency of a reduced body, checked when a body file is written and read: what a
//! multibody model silently relies on and a damaged, hand-edited or foreign file may violate.
//!
//! * every number finite;
//! * `K_red` and `M_red` symmetric ([`MATRIX_SYMMETRY_TOLERANCE`] relative);
//! * `M_red` positive definite and `K_red` positive semidefinite (eigenvalues of the pair
//!   `(K_red, M_red)` not below `−`[`NULL_SPACE_TOLERANCE`]` · λ_max`);
//! * the rigid null space: a modal or free-free body (an FFR basis, whose rigid motion is carried
//!   by the floating frame) has none; a Craig-Bampton body at most six rigid modes;
//! * the stored frequencies are those of the pair `(K_red, M_red)`
//!   ([`FREQUENCY_TOLERANCE`] relative in `ω²`);
//! * lumped node masses consistent with `M_red`: `Σ_i m_i |φ_ik|²` summed over the modes (the
//!   translational part of `Φᵀ M Φ` for a lumped mass) may not exceed `trace M_red`, and equals it
//!   for a body without rotational mode shapes (relative [`NODE_MASS_TOLERANCE`]).

use super::h5::ds;
use super::h5::invalid;
use super::BodyFileError;
use faer::Mat;
use flexmbs_fe::eigen::dense_generalized;
use flexmbs_fe::reduction::{ReducedBody, ReductionKind};
use std::path::Path;

/// Largest `max |A_ij − A_ji| / max |A_ij|` accepted for `K_red` and `M_red`.
pub const MATRIX_SYMMETRY_TOLERANCE: f64 = 1e-9;

/// Eigenvalues of `(K_red, M_red)` with `|λ| ≤ NULL_SPACE_TOLERANCE · λ_max` are rigid-body
/// (zero-energy) modes; below `−NULL_SPACE_TOLERANCE · λ_max` the stiffness is indefinite.
pub const NULL_SPACE_TOLERANCE: f64 = 1e-9;

/// Largest `|λ_stored − λ| / max(λ, NULL_SPACE_TOLERANCE · λ_max)` accepted between the stored
/// frequencies (as `λ = (2π f)²`, both sorted) and the eigenvalues of `(K_red, M_red)`.
pub const FREQUENCY_TOLERANCE: f64 = 1e-6;

/// Relative tolerance of the node-mass identity `Σ_i m_i |φ_ik|² = trace M_red`.
pub const NODE_MASS_TOLERANCE: f64 = 1e-6;

/// Checks the physical consistency of `b` (module documentation); the error names the dataset.
pub(crate) fn check_physics(path: &Path, b: &ReducedBody) -> Result<(), BodyFileError> {
    check_finite(path, b)?;
    for (name, m) in [(ds::STIFFNESS, &b.k_red), (ds::MASS_RED, &b.m_red)] {
        check_symmetric(path, name, m)?;
    }
    check_spectrum(path, b)?;
    check_node_masses(path, b)
}

fn check_finite(path: &Path, b: &ReducedBody) -> Result<(), BodyFileError> {
    let mats = [
        (ds::TRANSLATION, Some(&b.modes_t)),
        (ds::ROTATION, b.modes_r.as_ref()),
        (ds::STIFFNESS, Some(&b.k_red)),
        (ds::MASS_RED, Some(&b.m_red)),
    ];
    for (name, m) in mats {
        if let Some(m) = m {
            if let Some((i, j)) = first_non_finite(m) {
                let msg = format!("entry [{i}, {j}] is {}", m[(i, j)]);
                return Err(invalid(path, name, msg));
            }
        }
    }
    let vectors = [
        (
            ds::POSITION,
            b.nodes.iter().flatten().copied().collect::<Vec<_>>(),
        ),
        (ds::FREQUENCY, b.frequencies_hz.clone()),
        (ds::MASS, b.node_masses.clone().unwrap_or_default()),
    ];
    for (name, v) in vectors {
        if let Some(i) = v.iter().position(|x| !x.is_finite()) {
            return Err(invalid(path, name, format!("value {i} is {}", v[i])));
        }
    }
    if let Some(i) = b.frequencies_hz.iter().position(|&f| f < 0.0) {
        let msg = format!("frequency {i} is negative ({} Hz)", b.frequencies_hz[i]);
        return Err(invalid(path, ds::FREQUENCY, msg));
    }
    match &b.node_masses {
        Some(m) if m.iter().any(|&x| x < 0.0) => {
            let i = m.iter().position(|&x| x < 0.0).unwrap_or(0);
            let msg = format!("node {i} has a negative mass ({})", m[i]);
            Err(invalid(path, ds::MASS, msg))
        }
        _ => Ok(()),
    }
}

fn first_non_finite(m: &Mat<f64>) -> Option<(usize, usize)> {
    (0..m.ncols())
        .flat_map(|j| (0..m.nrows()).map(move |i| (i, j)))
        .find(|&(i, j)| !m[(i, j)].is_finite())
}

fn check_symmetric(path: &Path, name: &str, m: &Mat<f64>) -> Result<(), BodyFileError> {
    let scale = m.norm_max();
    let n = m.nrows();
    let mut worst = (0.0, 0, 0);
    for j in 0..n {
        for i in 0..j {
            let d = (m[(i, j)] - m[(j, i)]).abs();
            if d > worst.0 {
                worst = (d, i, j);
            }
        }
    }
    let (d, i, j) = worst;
    if d > MATRIX_SYMMETRY_TOLERANCE * scale {
        let msg = format!(
            "is not symmetric: [{i}, {j}] = {:e} but [{j}, {i}] = {:e} (max |A_ij - A_ji| / max |A_ij| = \
             {:.1e} > {MATRIX_SYMMETRY_TOLERANCE:e})",
            m[(i, j)],
            m[(j, i)],
            d / scale
        );
        return Err(invalid(path, name, msg));
    }
    Ok(())
}

/// Definiteness, rigid null space and stored frequencies from the eigenvalues of the pair.
fn check_spectrum(path: &Path, b: &ReducedBody) -> Result<(), BodyFileError> {
    let nf = b.num_modes();
    if nf == 0 {
        return Ok(());
    }
    if b.m_red.llt(faer::Side::Lower).is_err() {
        let msg = "is not positive definite (a mass matrix must be: negative or zero kinetic \
                   energy for some motion)"
            .to_string();
        return Err(invalid(path, ds::MASS_RED, msg));
    }
    let (mut lambda, _) = dense_generalized(b.k_red.as_ref(), b.m_red.as_ref())
        .map_err(|e| invalid(path, ds::STIFFNESS, e.to_string()))?;
    lambda.sort_by(f64::total_cmp);
    let lmax = lambda[nf - 1].abs().max(f64::MIN_POSITIVE);
    let floor = NULL_SPACE_TOLERANCE * lmax;
    if lambda[0] < -floor {
        let msg = format!(
            "is indefinite: the pair (K_red, M_red) has the eigenvalue omega^2 = {:.3e} < 0 \
             (largest {lmax:.3e})",
            lambda[0]
        );
        return Err(invalid(path, ds::STIFFNESS, msg));
    }
    check_null_space(path, b, lambda.iter().filter(|l| l.abs() <= floor).count())?;
    check_frequencies(path, b, &lambda, floor)
}

fn check_null_space(path: &Path, b: &ReducedBody, rigid: usize) -> Result<(), BodyFileError> {
    let (allowed, why) = match b.kind {
        ReductionKind::Modal | ReductionKind::FreeFree => (
            0,
            "a modal or free-free basis must not contain rigid-body modes (the floating frame \
             carries the rigid motion)",
        ),
        ReductionKind::CraigBampton { .. } => (6, "a body has at most six rigid-body modes"),
    };
    if rigid > allowed {
        let msg = format!(
            "has {rigid} zero-energy modes (eigenvalues of (K_red, M_red) within \
             {NULL_SPACE_TOLERANCE:e} of the largest); {why}"
        );
        return Err(invalid(path, ds::STIFFNESS, msg));
    }
    Ok(())
}

fn check_frequencies(
    path: &Path,
    b: &ReducedBody,
    lambda: &[f64],
    floor: f64,
) -> Result<(), BodyFileError> {
    let two_pi = 2.0 * std::f64::consts::PI;
    let mut stored: Vec<f64> = b
        .frequencies_hz
        .iter()
        .map(|f| (two_pi * f).powi(2))
        .collect();
    stored.sort_by(f64::total_cmp);
    for (k, (&s, &l)) in stored.iter().zip(lambda).enumerate() {
        let l = l.max(0.0);
        if (s - l).abs() > FREQUENCY_TOLERANCE * l.max(floor) {
            let msg = format!(
                "frequency {k} (in ascending order) is {:.9e} Hz, but the pair (K_red, M_red) gives \
                 {:.9e} Hz: the frequencies and the reduced matrices do not belong together",
                s.sqrt() / two_pi,
                l.sqrt() / two_pi
            );
            return Err(invalid(path, ds::FREQUENCY, msg));
        }
    }
    Ok(())
}

/// `Σ_i m_i |φ_ik|²` over the modes against `trace M_red`.
fn check_node_masses(path: &Path, b: &ReducedBody) -> Result<(), BodyFileError> {
    let Some(masses) = &b.node_masses else {
        return Ok(());
    };
    let nf = b.num_modes();
    let trace: f64 = (0..nf).map(|k| b.m_red[(k, k)]).sum();
    let lumped: f64 = (0..nf)
        .map(|k| {
            masses
                .iter()
                .enumerate()
                .map(|(i, m)| {
                    m * (0..3)
                        .map(|d| b.modes_t[(3 * i + d, k)].powi(2))
                        .sum::<f64>()
                })
                .sum::<f64>()
        })
        .sum();
    let tol = NODE_MASS_TOLERANCE * trace.abs();
    let exact = b.modes_r.is_none();
    if lumped > trace + tol || (exact && lumped < trace - tol) {
        let msg = format!(
            "the node masses do not match the reduced mass: sum_i m_i |phi_ik|^2 over the modes = {lumped:.9e}, \
             trace(M_red) = {trace:.9e} (ratio {:.6}; expected {})",
            lumped / trace,
            if exact { "1" } else { "at most 1" }
        );
        return Err(invalid(path, ds::MASS, msg));
    }
    Ok(())
}
