//! The seed's 4-file body format (seed 000 sec. 4.2.1, Listings 4.1-4.5).
//!
//! A body is a folder with
//! - `u0.dat`: undeformed position of each of the `Nn` lumped nodes, 3 whitespace-separated
//!   numbers per line (Listing 4.1);
//! - `modeShapeMatrix.dat`: `3 Nn` rows x `Nf` columns, row `3 i - 3 + d` holds DOF `d` of node
//!   `i` (1-based); fixed nodes have zero rows (Listing 4.2);
//! - `mij.dat`: one lumped mass per node (Listing 4.3);
//! - `stiffnessMatrix.dat`: lines `a,b, c,d, e`, value `e` at row `3 a - 3 + b` and column
//!   `3 c - 3 + d` (1-based) of the full `3 Nn x 3 Nn` FE stiffness (Listings 4.4-4.5).
//!
//! `%` starts a comment running to the end of the line; blank lines are ignored.
//!
//! Stiffness storage policy: the seed writes the full symmetric matrix. The reader accepts full
//! storage and also files holding only one triangle: for every off-diagonal pair, if only one of
//! `K_ij`, `K_ji` is present it is mirrored; if both are present they must agree to a relative
//! 1e-9 (of the larger magnitude, with an absolute floor of 1e-14 x the largest entry), and their
//! mean is used. A position given twice is an error (not summed): a stiffness file is a list of
//! entries, not an element-by-element assembly, so a repeated entry signals a broken export.

use crate::error::{excerpt, fmt_exact, parse_finite, read_text, write_text, IoError};
use faer::sparse::Triplet;
use faer::Mat;
use flexmbs_fe::SparseMatrix;
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::Path;

/// Degrees of freedom per node in the seed format (3 translations).
pub const SEED_NDOF: usize = 3;

/// File names of the seed format, in the order u0, modes, masses, stiffness.
pub const SEED_FILES: [&str; 4] = [
    "u0.dat",
    "modeShapeMatrix.dat",
    "mij.dat",
    "stiffnessMatrix.dat",
];

/// Relative tolerance between `K_ij` and `K_ji` when both are stored.
pub const SYMMETRY_TOL: f64 = 1e-9;

/// A flexible body in the seed's 4-file format.
#[derive(Debug, Clone)]
pub struct SeedBody {
    /// Undeformed node positions (`u0.dat`).
    pub u0: Vec<[f64; 3]>,
    /// Mode-shape matrix Phi, `3 Nn x Nf` (`modeShapeMatrix.dat`).
    pub modes: Mat<f64>,
    /// Lumped node masses (`mij.dat`).
    pub masses: Vec<f64>,
    /// Full FE stiffness K, `3 Nn x 3 Nn`, symmetric, full storage (`stiffnessMatrix.dat`).
    pub stiffness: SparseMatrix,
}

/// Iterates over the non-empty, comment-stripped lines of `text` with their 1-based numbers.
fn data_lines(text: &str) -> impl Iterator<Item = (usize, &str)> {
    text.lines().enumerate().filter_map(|(i, l)| {
        let l = l.split('%').next().unwrap_or("").trim();
        (!l.is_empty()).then_some((i + 1, l))
    })
}

/// Parses `u0.dat`: one line `x y z` per node (Listing 4.1).
pub fn parse_u0(text: &str, file: &Path) -> Result<Vec<[f64; 3]>, IoError> {
    let mut out = Vec::new();
    for (ln, l) in data_lines(text) {
        let toks: Vec<&str> = l.split_whitespace().collect();
        if toks.len() != 3 {
            return Err(IoError::parse(
                file,
                ln,
                "3 numbers (x y z)",
                format!("{}: {}", toks.len(), excerpt(l)),
            ));
        }
        let mut x = [0.0; 3];
        for (k, t) in toks.iter().enumerate() {
            x[k] = parse_finite(t, file, ln, ["x", "y", "z"][k])?;
        }
        out.push(x);
    }
    if out.is_empty() {
        return Err(IoError::inconsistent(
            file,
            "no nodes (file has no data lines)",
        ));
    }
    Ok(out)
}

/// Parses `modeShapeMatrix.dat`: every line one DOF, every column one mode (Listing 4.2).
/// All lines must have the same number of columns; the row count is checked against the node
/// count by [`SeedBody::new`].
pub fn parse_mode_shapes(text: &str, file: &Path) -> Result<Mat<f64>, IoError> {
    let mut rows: Vec<Vec<f64>> = Vec::new();
    let mut ncols = None;
    for (ln, l) in data_lines(text) {
        let toks: Vec<&str> = l.split_whitespace().collect();
        let nf = *ncols.get_or_insert(toks.len());
        if toks.len() != nf {
            return Err(IoError::parse(
                file,
                ln,
                format!("{nf} mode-shape values (as on the first data line)"),
                format!("{}: {}", toks.len(), excerpt(l)),
            ));
        }
        let row = toks
            .iter()
            .map(|t| parse_finite(t, file, ln, "mode-shape value"))
            .collect::<Result<Vec<_>, _>>()?;
        rows.push(row);
    }
    let nf = ncols.ok_or_else(|| {
        IoError::inconsistent(file, "no mode-shape rows (file has no data lines)")
    })?;
    Ok(Mat::from_fn(rows.len(), nf, |i, j| rows[i][j]))
}

/// Parses `mij.dat`: one positive lumped mass per line (Listing 4.3).
pub fn parse_masses(text: &str, file: &Path) -> Result<Vec<f64>, IoError> {
    let mut out = Vec::new();
    for (ln, l) in data_lines(text) {
        let toks: Vec<&str> = l.split_whitespace().collect();
        if toks.len() != 1 {
            return Err(IoError::parse(
                file,
                ln,
                "1 number (node mass)",
                format!("{}: {}", toks.len(), excerpt(l)),
            ));
        }
        let m = parse_finite(toks[0], file, ln, "node mass")?;
        if m <= 0.0 {
            return Err(IoError::parse(
                file,
                ln,
                "a positive node mass",
                excerpt(toks[0]),
            ));
        }
        out.push(m);
    }
    if out.is_empty() {
        return Err(IoError::inconsistent(
            file,
            "no masses (file has no data lines)",
        ));
    }
    Ok(out)
}

/// Parses one 1-based integer index of a stiffness line and checks `1 <= v <= max`.
fn parse_index(
    tok: &str,
    file: &Path,
    ln: usize,
    what: &str,
    max: usize,
) -> Result<usize, IoError> {
    let v: usize = tok
        .trim()
        .parse()
        .map_err(|_| IoError::parse(file, ln, format!("an integer {what}"), excerpt(tok)))?;
    if v == 0 || v > max {
        return Err(IoError::invalid(
            file,
            ln,
            format!("{what} {v} out of range 1..={max}"),
        ));
    }
    Ok(v)
}

/// Parses `stiffnessMatrix.dat` (Listings 4.4-4.5) of a body with `n_nodes` nodes into the full
/// symmetric `3 n_nodes x 3 n_nodes` matrix. See the module documentation for the symmetry and
/// duplicate policy.
pub fn parse_stiffness(text: &str, file: &Path, n_nodes: usize) -> Result<SparseMatrix, IoError> {
    let n = SEED_NDOF * n_nodes;
    // (row, col) -> (value, line)
    let mut entries: BTreeMap<(usize, usize), (f64, usize)> = BTreeMap::new();
    for (ln, l) in data_lines(text) {
        let toks: Vec<&str> = l.split(',').collect();
        if toks.len() != 5 {
            return Err(IoError::parse(
                file,
                ln,
                "5 comma-separated fields (a,b, c,d, e)",
                format!("{}: {}", toks.len(), excerpt(l)),
            ));
        }
        let a = parse_index(toks[0], file, ln, "row node a", n_nodes)?;
        let b = parse_index(toks[1], file, ln, "row DOF b", SEED_NDOF)?;
        let c = parse_index(toks[2], file, ln, "column node c", n_nodes)?;
        let d = parse_index(toks[3], file, ln, "column DOF d", SEED_NDOF)?;
        let e = parse_finite(toks[4], file, ln, "stiffness value e")?;
        let (r, col) = (SEED_NDOF * (a - 1) + b - 1, SEED_NDOF * (c - 1) + d - 1);
        if let Some((_, first)) = entries.insert((r, col), (e, ln)) {
            return Err(IoError::invalid(
                file,
                ln,
                format!("duplicate entry {a},{b}, {c},{d} (first given on line {first})"),
            ));
        }
    }
    if entries.is_empty() {
        return Err(IoError::inconsistent(
            file,
            "no stiffness entries (file has no data lines)",
        ));
    }
    let kmax = entries.values().fold(0.0f64, |m, (v, _)| m.max(v.abs()));
    let mut trip = Vec::with_capacity(2 * entries.len());
    for (&(r, c), &(v, ln)) in &entries {
        if r == c {
            trip.push(Triplet::new(r, c, v));
            continue;
        }
        match entries.get(&(c, r)) {
            None => {
                trip.push(Triplet::new(r, c, v));
                trip.push(Triplet::new(c, r, v));
            }
            Some(&(w, ln2)) => {
                if r > c {
                    continue; // handled with its partner from the upper triangle
                }
                let tol = SYMMETRY_TOL * v.abs().max(w.abs()) + 1e-14 * kmax;
                if (v - w).abs() > tol {
                    return Err(IoError::invalid(
                        file,
                        ln2.max(ln),
                        format!(
                            "stiffness not symmetric: K({},{}) = {v:e} (line {ln}) but K({},{}) = {w:e} (line {ln2})",
                            r + 1,
                            c + 1,
                            c + 1,
                            r + 1
                        ),
                    ));
                }
                let mean = if v == w { v } else { 0.5 * (v + w) };
                trip.push(Triplet::new(r, c, mean));
                trip.push(Triplet::new(c, r, mean));
            }
        }
    }
    SparseMatrix::try_new_from_triplets(n, n, &trip)
        .map_err(|e| IoError::inconsistent(file, format!("cannot build sparse stiffness: {e:?}")))
}

impl SeedBody {
    /// Assembles a body from its parts and checks that they agree: `3 Nn` mode rows, `Nn` masses,
    /// a `3 Nn x 3 Nn` stiffness. `dir` only serves the error messages.
    pub fn new(
        u0: Vec<[f64; 3]>,
        modes: Mat<f64>,
        masses: Vec<f64>,
        stiffness: SparseMatrix,
        dir: &Path,
    ) -> Result<Self, IoError> {
        let nn = u0.len();
        if modes.nrows() != SEED_NDOF * nn {
            return Err(IoError::inconsistent(
                &dir.join(SEED_FILES[1]),
                format!(
                    "{} mode-shape rows, but {} nodes in u0.dat need 3 x {} = {}",
                    modes.nrows(),
                    nn,
                    nn,
                    3 * nn
                ),
            ));
        }
        if masses.len() != nn {
            return Err(IoError::inconsistent(
                &dir.join(SEED_FILES[2]),
                format!("{} masses, but u0.dat has {} nodes", masses.len(), nn),
            ));
        }
        if let Some(m) = masses.iter().find(|m| !(m.is_finite() && **m > 0.0)) {
            return Err(IoError::inconsistent(
                &dir.join(SEED_FILES[2]),
                format!("node mass {m} is not positive"),
            ));
        }
        if stiffness.nrows() != SEED_NDOF * nn || stiffness.ncols() != SEED_NDOF * nn {
            return Err(IoError::inconsistent(
                &dir.join(SEED_FILES[3]),
                format!(
                    "stiffness is {} x {}, expected {} x {}",
                    stiffness.nrows(),
                    stiffness.ncols(),
                    3 * nn,
                    3 * nn
                ),
            ));
        }
        Ok(Self {
            u0,
            modes,
            masses,
            stiffness,
        })
    }

    /// Number of nodes `Nn`.
    pub fn num_nodes(&self) -> usize {
        self.u0.len()
    }

    /// Number of modes `Nf`.
    pub fn num_modes(&self) -> usize {
        self.modes.ncols()
    }

    /// Reduced stiffness `k_ff = Phi^T K Phi` (`Nf x Nf`).
    pub fn k_ff(&self) -> Mat<f64> {
        let phi = &self.modes;
        let k = &self.stiffness;
        let kphi = crate::calculix::matrices::sparse_times_dense(k, phi);
        phi.transpose() * &kphi
    }

    /// Reduced lumped mass `m_ff = Phi^T diag(m_i I3) Phi` (`Nf x Nf`).
    pub fn m_ff(&self) -> Mat<f64> {
        let phi = &self.modes;
        let nf = phi.ncols();
        Mat::from_fn(nf, nf, |a, b| {
            (0..phi.nrows())
                .map(|r| self.masses[r / SEED_NDOF] * phi[(r, a)] * phi[(r, b)])
                .sum()
        })
    }
}

/// Reads a seed body folder (`u0.dat`, `modeShapeMatrix.dat`, `mij.dat`, `stiffnessMatrix.dat`).
pub fn read_seed_dir(dir: &Path) -> Result<SeedBody, IoError> {
    let p: Vec<_> = SEED_FILES.iter().map(|f| dir.join(f)).collect();
    let u0 = parse_u0(&read_text(&p[0])?, &p[0])?;
    let modes = parse_mode_shapes(&read_text(&p[1])?, &p[1])?;
    let masses = parse_masses(&read_text(&p[2])?, &p[2])?;
    let k = parse_stiffness(&read_text(&p[3])?, &p[3], u0.len())?;
    SeedBody::new(u0, modes, masses, k, dir)
}

/// Formats `u0.dat` exactly like Listing 4.1 (tab-separated, `% node: i`).
pub fn format_u0(u0: &[[f64; 3]]) -> String {
    let mut s = String::new();
    for (i, x) in u0.iter().enumerate() {
        let _ = writeln!(
            s,
            "{}\t{}\t{}\t% node: {}",
            fmt_exact(x[0]),
            fmt_exact(x[1]),
            fmt_exact(x[2]),
            i + 1
        );
    }
    s
}

/// Formats `modeShapeMatrix.dat` exactly like Listing 4.2 (`% node: i, DOF: d`).
pub fn format_mode_shapes(modes: &Mat<f64>) -> String {
    let mut s = String::new();
    for r in 0..modes.nrows() {
        for c in 0..modes.ncols() {
            s.push_str(&fmt_exact(modes[(r, c)]));
            s.push('\t');
        }
        let _ = writeln!(
            s,
            "% node: {}, DOF: {}",
            r / SEED_NDOF + 1,
            r % SEED_NDOF + 1
        );
    }
    s
}

/// Formats `mij.dat` exactly like Listing 4.3.
pub fn format_masses(masses: &[f64]) -> String {
    let mut s = String::new();
    for (i, m) in masses.iter().enumerate() {
        let _ = writeln!(s, "{}\t% node: {}", fmt_exact(*m), i + 1);
    }
    s
}

/// Formats `stiffnessMatrix.dat` like Listing 4.5: every stored entry of the full matrix as
/// `a,b, c,d, e`, column by column, with 17 significant digits (bit-identical on reading).
pub fn format_stiffness(k: &SparseMatrix) -> String {
    let mut s = String::new();
    let (cp, ri, vals) = (k.col_ptr(), k.row_idx(), k.val());
    for j in 0..k.ncols() {
        for p in cp[j]..cp[j + 1] {
            let i = ri[p];
            let _ = writeln!(
                s,
                "{},{}, {},{}, {}",
                i / SEED_NDOF + 1,
                i % SEED_NDOF + 1,
                j / SEED_NDOF + 1,
                j % SEED_NDOF + 1,
                fmt_exact(vals[p])
            );
        }
    }
    s
}

/// Writes a seed body folder (created if absent) in exactly the layout of Listings 4.1-4.5.
pub fn write_seed_dir(dir: &Path, body: &SeedBody) -> Result<(), IoError> {
    std::fs::create_dir_all(dir).map_err(|source| IoError::Io {
        file: dir.to_path_buf(),
        source,
    })?;
    write_text(&dir.join(SEED_FILES[0]), &format_u0(&body.u0))?;
    write_text(&dir.join(SEED_FILES[1]), &format_mode_shapes(&body.modes))?;
    write_text(&dir.join(SEED_FILES[2]), &format_masses(&body.masses))?;
    write_text(&dir.join(SEED_FILES[3]), &format_stiffness(&body.stiffness))
}
