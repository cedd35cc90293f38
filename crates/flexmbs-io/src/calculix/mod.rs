//! CalculiX (`ccx`) as FE front end: Abaqus-format decks, the `*FREQUENCY, SOLVER=MATRIXSTORAGE`
//! matrix export (`.sti`, `.mas`, `.dof`), the `.dat` frequency table, the ASCII `.frd` result
//! file and running `ccx` itself. Formats as verified in `reference/calculix.md`.

pub mod dat;
pub mod frd;
pub mod import;
pub mod inp;
pub mod matrices;
pub mod run;

pub use dat::{parse_dat_frequencies, read_dat_frequencies, DatMode};
pub use frd::{parse_frd, read_frd, FrdElement, FrdMode, FrdResult};
pub use import::{import_matrices, matrix_export_deck_text, renumber};
pub use inp::{parse_inp, parse_inp_with, read_inp, Boundary, InpModel};
pub use matrices::{parse_ccx_dofs, parse_ccx_matrix, read_ccx_matrices, CcxMatrices};
pub use run::{ccx_available, matrix_export_deck, run_ccx, CcxRun};

/// A keyword line of an Abaqus deck: `*NAME, KEY=VALUE, FLAG`.
#[derive(Debug, Clone)]
pub(crate) struct Keyword {
    /// Upper-case name with single inner spaces (`SOLID SECTION`).
    pub name: String,
    /// Parameters: upper-case key, value as written (trimmed), `None` for a flag.
    pub params: Vec<(String, Option<String>)>,
}

impl Keyword {
    /// Parses a line starting with a single `*`; `None` for comment lines (`**`) and non-keywords.
    pub fn parse(line: &str) -> Option<Self> {
        let l = line.trim_start();
        let rest = l.strip_prefix('*')?;
        if rest.starts_with('*') {
            return None;
        }
        let mut parts = rest.split(',');
        let name = parts
            .next()
            .unwrap_or("")
            .split_whitespace()
            .collect::<Vec<_>>()
            .join(" ")
            .to_uppercase();
        let params = parts
            .filter(|p| !p.trim().is_empty())
            .map(|p| match p.split_once('=') {
                Some((k, v)) => (
                    k.trim().to_uppercase(),
                    Some(v.trim().trim_matches('"').to_string()),
                ),
                None => (p.trim().to_uppercase(), None),
            })
            .collect();
        Some(Self { name, params })
    }

    /// Value of parameter `key` (upper case), if given with a value.
    pub fn param(&self, key: &str) -> Option<&str> {
        self.params
            .iter()
            .find(|(k, _)| k == key)
            .and_then(|(_, v)| v.as_deref())
    }

    /// Whether the flag (or parameter) `key` is present.
    pub fn has(&self, key: &str) -> bool {
        self.params.iter().any(|(k, _)| k == key)
    }
}

/// Whether a deck line is a comment (`**`) or blank.
pub(crate) fn is_comment_or_blank(line: &str) -> bool {
    let l = line.trim();
    l.is_empty() || l.starts_with("**")
}
