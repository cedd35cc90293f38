//! The eigenvalue table of a CalculiX `.dat` file (`*FREQUENCY` step):
//!
//! ```text
//!      E I G E N V A L U E   O U T P U T
//!
//!  MODE NO    EIGENVALUE                       FREQUENCY
//!                                      REAL PART            IMAGINARY PART
//!                            (RAD/TIME)      (CYCLES/TIME     (RAD/TIME)
//!
//!       1   0.1105203E+05   0.1051286E+03   0.1673174E+02   0.0000000E+00
//! ```
//!
//! Columns: mode, eigenvalue omega^2, omega [rad/s], f [Hz], imaginary part (older versions
//! omit the last column). Values carry 7 significant digits. Several tables (several steps) are
//! concatenated in file order.

use crate::error::{excerpt, parse_finite, read_text, IoError};
use std::path::Path;

/// One row of the eigenvalue table.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DatMode {
    /// Mode number as printed (1-based within its step).
    pub mode: u32,
    /// Eigenvalue omega^2 [rad^2/s^2].
    pub eigenvalue: f64,
    /// Angular frequency omega [rad/s].
    pub omega: f64,
    /// Frequency f [Hz].
    pub frequency_hz: f64,
    /// Imaginary part of the frequency [rad/s] (0 if not printed).
    pub imaginary: f64,
}

/// Whether a line is the title of an eigenvalue table (letters spaced out by ccx).
fn is_table_title(l: &str) -> bool {
    let squeezed: String = l.chars().filter(|c| !c.is_whitespace()).collect();
    squeezed == "EIGENVALUEOUTPUT"
}

/// Parses all eigenvalue tables of a `.dat` text. Error if there is none, or if a row inside a
/// table is malformed (located by line).
pub fn parse_dat_frequencies(text: &str, file: &Path) -> Result<Vec<DatMode>, IoError> {
    let lines: Vec<&str> = text.lines().collect();
    let mut out = Vec::new();
    let mut tables = 0;
    let mut i = 0;
    while i < lines.len() {
        if !is_table_title(lines[i]) {
            i += 1;
            continue;
        }
        let title = i + 1;
        tables += 1;
        i += 1;
        // Skip the header down to the first row (a line starting with an integer).
        while i < lines.len()
            && lines[i]
                .split_whitespace()
                .next()
                .is_none_or(|t| t.parse::<u32>().is_err())
        {
            i += 1;
        }
        let before = out.len();
        while i < lines.len() && !lines[i].trim().is_empty() {
            out.push(parse_row(lines[i], file, i + 1)?);
            i += 1;
        }
        if out.len() == before {
            return Err(IoError::parse(
                file,
                title,
                "an eigenvalue table with at least one row",
                "none (file truncated?)",
            ));
        }
    }
    if tables == 0 {
        return Err(IoError::inconsistent(
            file,
            "no eigenvalue table ('E I G E N V A L U E   O U T P U T') found",
        ));
    }
    Ok(out)
}

fn parse_row(l: &str, file: &Path, ln: usize) -> Result<DatMode, IoError> {
    let t: Vec<&str> = l.split_whitespace().collect();
    if !(4..=5).contains(&t.len()) {
        return Err(IoError::parse(
            file,
            ln,
            "mode, eigenvalue, omega, f [Hz][, imaginary part]",
            format!("{} fields: {}", t.len(), excerpt(l)),
        ));
    }
    let mode = t[0]
        .parse::<u32>()
        .map_err(|_| IoError::parse(file, ln, "an integer mode number", excerpt(t[0])))?;
    Ok(DatMode {
        mode,
        eigenvalue: parse_finite(t[1], file, ln, "eigenvalue")?,
        omega: parse_finite(t[2], file, ln, "omega")?,
        frequency_hz: parse_finite(t[3], file, ln, "frequency")?,
        imaginary: match t.get(4) {
            Some(s) => parse_finite(s, file, ln, "imaginary part")?,
            None => 0.0,
        },
    })
}

/// Reads the eigenvalue tables of a `.dat` file.
pub fn read_dat_frequencies(path: &Path) -> Result<Vec<DatMode>, IoError> {
    parse_dat_frequencies(&read_text(path)?, path)
}
