//! The optional `geometric` group of the reduced-body file: projected geometric stiffness
//! matrices `K_G,i = Φᵀ K_σ,i Φ` of inertial load patterns (unit-load method,
//! [`flexmbs_fe::geometric`]), written by `flexmbs reduce` for bodies with supports and used by
//! `geometric_stiffening = true` in a multibody model (see `docs/formats/reduced-body.md`).
//!
//! Layout: `geometric/load_pattern` (strings `[P]`, names of [`pattern_name`]) and
//! `geometric/stiffness` (f64 `[P, N_f, N_f]`, row-major, matrix `i` for pattern `i`), units of the
//! body per unit pattern coefficient (per (rad/s)² for centrifugal patterns).

use super::h5::{checksummed, hdf5_error, invalid, row_major, Reader};
use super::BodyFileError;
use faer::Mat;
use flexmbs_fe::geometric::{GeometricStiffness, InertialLoad};
use hdf5_pure::{AttrValue, FileBuilder};
use std::path::Path;

/// Load pattern names, `[P]` strings.
pub(crate) const LOAD_PATTERN: &str = "geometric/load_pattern";
/// Projected geometric stiffness matrices, f64 `[P, N_f, N_f]`.
pub(crate) const STIFFNESS: &str = "geometric/stiffness";

/// Relative asymmetry `max |K_ij - K_ji| / max |K_ij|` a stored matrix may have (the writer
/// stores exactly symmetric matrices; the slack admits round-off of other writers).
pub const SYMMETRY_TOLERANCE: f64 = 1e-10;

const AXES: [&str; 3] = ["x", "y", "z"];

/// File name of a load pattern: `centrifugal_xy` (coefficient `ω_x ω_y`), `translation_x`,
/// `angular_acceleration_z`; `None` for an invalid pattern (axis out of range, `a > b`).
pub fn pattern_name(p: InertialLoad) -> Option<String> {
    match p {
        InertialLoad::Centrifugal(a, b) if a <= b && b < 3 => {
            Some(format!("centrifugal_{}{}", AXES[a], AXES[b]))
        }
        InertialLoad::Translation(d) if d < 3 => Some(format!("translation_{}", AXES[d])),
        InertialLoad::AngularAcceleration(d) if d < 3 => {
            Some(format!("angular_acceleration_{}", AXES[d]))
        }
        _ => None,
    }
}

/// The load pattern of a file name (inverse of [`pattern_name`]).
pub fn parse_pattern_name(name: &str) -> Option<InertialLoad> {
    let axis = |s: &str| AXES.iter().position(|a| *a == s);
    if let Some(ab) = name.strip_prefix("centrifugal_") {
        if ab.len() != 2 || !ab.is_ascii() {
            return None;
        }
        let (a, b) = (axis(&ab[..1])?, axis(&ab[1..])?);
        return (a <= b).then_some(InertialLoad::Centrifugal(a, b));
    }
    if let Some(d) = name.strip_prefix("translation_") {
        return axis(d).map(InertialLoad::Translation);
    }
    if let Some(d) = name.strip_prefix("angular_acceleration_") {
        return axis(d).map(InertialLoad::AngularAcceleration);
    }
    None
}

/// Largest relative asymmetry `max |K_ij - K_ji| / max |K_ij|` (0 for a zero matrix).
fn asymmetry(m: &Mat<f64>) -> f64 {
    let n = m.nrows();
    let (mut d, mut s) = (0.0f64, 0.0f64);
    for i in 0..n {
        for j in 0..n {
            d = d.max((m[(i, j)] - m[(j, i)]).abs());
            s = s.max(m[(i, j)].abs());
        }
    }
    if s > 0.0 {
        d / s
    } else {
        0.0
    }
}

/// Checks `g` against a body of `nf` modes: at least one pattern, valid and distinct patterns,
/// one `nf × nf` finite symmetric matrix per pattern. `object` names the place in errors.
pub(crate) fn check(
    path: &Path,
    object: &str,
    g: &GeometricStiffness,
    nf: usize,
) -> Result<(), BodyFileError> {
    let bad = |message: String| invalid(path, object, message);
    if g.load_patterns.is_empty() {
        return Err(bad("no load patterns".into()));
    }
    if g.matrices.len() != g.load_patterns.len() {
        return Err(bad(format!(
            "{} matrices for {} load patterns",
            g.matrices.len(),
            g.load_patterns.len()
        )));
    }
    for (i, (&p, m)) in g.load_patterns.iter().zip(&g.matrices).enumerate() {
        let name = pattern_name(p).ok_or_else(|| bad(format!("invalid load pattern {p:?}")))?;
        if g.load_patterns[..i].contains(&p) {
            return Err(bad(format!("load pattern {name} appears twice")));
        }
        if m.nrows() != nf || m.ncols() != nf {
            return Err(bad(format!(
                "matrix {i} ({name}) is {} x {}, expected N_f x N_f = {nf} x {nf}",
                m.nrows(),
                m.ncols()
            )));
        }
        for c in 0..nf {
            if let Some(r) = (0..nf).find(|&r| !m[(r, c)].is_finite()) {
                return Err(bad(format!(
                    "matrix {i} ({name}) has the non-finite entry {} at ({r}, {c})",
                    m[(r, c)]
                )));
            }
        }
        let a = asymmetry(m);
        if a > SYMMETRY_TOLERANCE {
            return Err(bad(format!(
                "matrix {i} ({name}) is not symmetric: max |K_ij - K_ji| / max |K_ij| = {a:e} \
                 > {SYMMETRY_TOLERANCE:e}"
            )));
        }
    }
    Ok(())
}

/// Adds the `geometric` group for a checked `g`.
pub(crate) fn encode(fb: &mut FileBuilder, g: &GeometricStiffness) {
    let p = g.load_patterns.len() as u64;
    let nf = g.num_modes() as u64;
    let mut grp = fb.create_group("geometric");
    grp.set_attr(
        "method",
        AttrValue::VarLenString("unit_load (Wallrapp/Schwertassek)".into()),
    );
    grp.set_attr("supports", AttrValue::VarLenString("nodes/fixed".into()));
    let names: Vec<String> = g
        .load_patterns
        .iter()
        .map(|&l| pattern_name(l).unwrap_or_default())
        .collect();
    let refs: Vec<&str> = names.iter().map(String::as_str).collect();
    grp.create_dataset("load_pattern").with_vlen_strings(&refs);
    let data: Vec<f64> = g.matrices.iter().flat_map(row_major).collect();
    checksummed(grp.create_dataset("stiffness"), &data, &[p, nf, nf]);
    fb.add_group(grp.finish());
}

/// Reads the `geometric` group of a body with `nf` modes, if the file has one (both datasets or
/// neither), and checks it like the writer does.
pub(crate) fn decode(r: &Reader, nf: usize) -> Result<Option<GeometricStiffness>, BodyFileError> {
    let (names_ds, k_ds) = (r.optional(LOAD_PATTERN)?, r.optional(STIFFNESS)?);
    let (names_ds, k_ds) = match (names_ds, k_ds) {
        (None, None) => return Ok(None),
        (Some(n), Some(k)) => (n, k),
        (n, _) => {
            return Err(BodyFileError::MissingDataset {
                path: r.path.to_path_buf(),
                dataset: if n.is_none() { LOAD_PATTERN } else { STIFFNESS }.to_string(),
            })
        }
    };
    let shape = r.shape(LOAD_PATTERN, &names_ds, &[None], "[P]")?;
    let p = shape[0] as usize;
    let names = names_ds
        .read_string()
        .map_err(|e| hdf5_error(r.path, LOAD_PATTERN, e))?;
    if names.len() != p {
        return Err(invalid(
            r.path,
            LOAD_PATTERN,
            format!("{} strings for shape [{p}]", names.len()),
        ));
    }
    let mut load_patterns = Vec::with_capacity(p);
    for (i, name) in names.iter().enumerate() {
        let p = parse_pattern_name(name).ok_or_else(|| {
            invalid(
                r.path,
                LOAD_PATTERN,
                format!(
                    "entry {i}: unknown load pattern '{name}' (centrifugal_xx .. centrifugal_zz, \
                     translation_x, angular_acceleration_x, ...)"
                ),
            )
        })?;
        if load_patterns.contains(&p) {
            let msg = format!("entry {i}: load pattern '{name}' appears twice");
            return Err(invalid(r.path, LOAD_PATTERN, msg));
        }
        load_patterns.push(p);
    }
    let data = r.f64s(
        STIFFNESS,
        &k_ds,
        &[Some(p as u64), Some(nf as u64), Some(nf as u64)],
        &format!("[P, N_f, N_f] = [{p}, {nf}, {nf}]"),
    )?;
    let matrices = (0..p)
        .map(|i| Mat::from_fn(nf, nf, |a, b| data[(i * nf + a) * nf + b]))
        .collect();
    let g = GeometricStiffness {
        load_patterns,
        matrices,
    };
    check(r.path, STIFFNESS, &g, nf)?;
    Ok(Some(g))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every valid pattern survives name → pattern; invalid ones have no name; near-miss names
    /// are refused.
    #[test]
    fn pattern_names_round_trip() {
        let mut all = InertialLoad::centrifugal();
        all.extend((0..3).map(InertialLoad::Translation));
        all.extend((0..3).map(InertialLoad::AngularAcceleration));
        for p in all {
            let n = pattern_name(p).unwrap();
            assert_eq!(parse_pattern_name(&n), Some(p), "{n}");
        }
        assert_eq!(pattern_name(InertialLoad::Centrifugal(1, 0)), None);
        assert_eq!(pattern_name(InertialLoad::Translation(3)), None);
        for bad in [
            "centrifugal_yx",
            "centrifugal_x",
            "centrifugal_xyz",
            "centrifugal_é",
            "translation_w",
            "CENTRIFUGAL_XX",
            "",
        ] {
            assert_eq!(parse_pattern_name(bad), None, "{bad}");
        }
    }
}
