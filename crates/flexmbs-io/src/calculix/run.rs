//! Running CalculiX (`ccx`): finding the executable, running a deck in a work directory and
//! checking both its exit status and its `*ERROR` messages (ccx 2.20 exits non-zero on input
//! errors but prints the reason only on standard output).

use super::Keyword;
use crate::error::{read_text, write_text, IoError};
use std::path::{Path, PathBuf};
use std::process::Command;

/// Environment variable naming the ccx executable, overriding the search in `PATH`.
pub const CCX_ENV: &str = "FLEXMBS_CCX";

/// A finished, successful ccx run.
#[derive(Debug, Clone)]
pub struct CcxRun {
    /// Directory the job ran in.
    pub workdir: PathBuf,
    /// Job path without extension (`workdir/<deck stem>`).
    pub job: PathBuf,
    /// Standard output and error of ccx.
    pub output: String,
    /// Files the job produced (`job.*` except the deck), sorted.
    pub files: Vec<PathBuf>,
}

impl CcxRun {
    /// Path of the produced file with extension `ext` (`"sti"`, `"frd"`, ...); it may not exist.
    pub fn file(&self, ext: &str) -> PathBuf {
        let mut s = self.job.as_os_str().to_owned();
        s.push(".");
        s.push(ext);
        PathBuf::from(s)
    }
}

/// The ccx executable: `$FLEXMBS_CCX` if set and existing, else `ccx` found in `PATH`.
pub fn ccx_available() -> Option<PathBuf> {
    if let Some(p) = std::env::var_os(CCX_ENV).map(PathBuf::from) {
        if p.is_file() {
            return Some(p);
        }
    }
    let path = std::env::var_os("PATH")?;
    std::env::split_paths(&path)
        .map(|d| d.join("ccx"))
        .find(|p| p.is_file())
}

/// A deck that includes the mesh deck `mesh_inp` and exports its free (or `*BOUNDARY`-reduced)
/// stiffness and mass matrices with `*FREQUENCY, SOLVER=MATRIXSTORAGE` (`.sti`, `.mas`, `.dof`).
pub fn matrix_export_deck(mesh_inp: &Path) -> String {
    format!(
        "** flexmbs: matrix export of {0}\n*INCLUDE, INPUT={0}\n*STEP\n*FREQUENCY, SOLVER=MATRIXSTORAGE\n*END STEP\n",
        mesh_inp.display()
    )
}

/// Returns the deck text with every `*INCLUDE, INPUT=` replaced by the included file's text
/// (recursively, paths relative to the including file), so a deck can run in any directory.
pub fn inline_includes(text: &str, file: &Path) -> Result<String, IoError> {
    fn go(text: &str, file: &Path, depth: usize, out: &mut String) -> Result<(), IoError> {
        for (i, l) in text.lines().enumerate() {
            match Keyword::parse(l).filter(|k| k.name == "INCLUDE") {
                Some(kw) => {
                    let input = kw.param("INPUT").ok_or_else(|| {
                        IoError::parse(file, i + 1, "*INCLUDE, INPUT=<file>", l.trim().to_string())
                    })?;
                    if depth >= 16 {
                        return Err(IoError::invalid(
                            file,
                            i + 1,
                            "*INCLUDE nested deeper than 16",
                        ));
                    }
                    let p = Path::new(input);
                    let p = if p.is_absolute() {
                        p.to_path_buf()
                    } else {
                        file.parent().unwrap_or(Path::new("")).join(p)
                    };
                    out.push_str(&format!("** included from {}\n", p.display()));
                    go(&read_text(&p)?, &p, depth + 1, out)?;
                }
                None => {
                    out.push_str(l);
                    out.push('\n');
                }
            }
        }
        Ok(())
    }
    let mut out = String::new();
    go(text, file, 0, &mut out)?;
    Ok(out)
}

/// Runs ccx on `deck` inside `workdir` (created if absent). The deck is written there with its
/// `*INCLUDE`s inlined, as `<deck stem>.inp`; ccx runs with `OMP_NUM_THREADS=2`. Fails with
/// [`IoError::CcxMissing`] without ccx, and with [`IoError::CcxFailed`] on a non-zero exit status
/// or an `*ERROR` in the output.
pub fn run_ccx(deck: &Path, workdir: &Path) -> Result<CcxRun, IoError> {
    let ccx = ccx_available().ok_or(IoError::CcxMissing)?;
    let stem = deck
        .file_stem()
        .and_then(|s| s.to_str())
        .filter(|s| !s.is_empty() && !s.contains(char::is_whitespace))
        .ok_or_else(|| {
            IoError::inconsistent(
                deck,
                "deck name must be a non-empty file name without spaces",
            )
        })?
        .to_string();
    let text = inline_includes(&read_text(deck)?, deck)?;
    std::fs::create_dir_all(workdir).map_err(|source| IoError::Io {
        file: workdir.to_path_buf(),
        source,
    })?;
    let job = workdir.join(&stem);
    let run = CcxRun {
        workdir: workdir.to_path_buf(),
        job: job.clone(),
        output: String::new(),
        files: Vec::new(),
    };
    let inp = run.file("inp");
    // Remove outputs of an earlier run of the same job so `files` lists only fresh ones.
    for f in produced(workdir, &stem) {
        let _ = std::fs::remove_file(f);
    }
    write_text(&inp, &text)?;
    let out = Command::new(&ccx)
        .arg("-i")
        .arg(&stem)
        .current_dir(workdir)
        .env("OMP_NUM_THREADS", "2")
        .output()
        .map_err(|source| IoError::Io {
            file: ccx.clone(),
            source,
        })?;
    let output = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    let errors: Vec<&str> = {
        let lines: Vec<&str> = output.lines().collect();
        let mut e = Vec::new();
        for (i, l) in lines.iter().enumerate() {
            if l.contains("*ERROR") {
                e.push(l.trim());
                if let Some(n) = lines.get(i + 1).filter(|n| !n.trim().is_empty()) {
                    e.push(n.trim());
                }
            }
        }
        e
    };
    if !out.status.success() || !errors.is_empty() {
        let message = if errors.is_empty() {
            output
                .lines()
                .rev()
                .take(10)
                .collect::<Vec<_>>()
                .into_iter()
                .rev()
                .collect::<Vec<_>>()
                .join("\n")
        } else {
            errors.join("\n")
        };
        return Err(IoError::CcxFailed {
            deck: deck.to_path_buf(),
            status: out.status.code(),
            message,
        });
    }
    Ok(CcxRun {
        output,
        files: produced(workdir, &stem),
        ..run
    })
}

/// Files `stem.*` in `dir` other than the deck `stem.inp`, sorted.
fn produced(dir: &Path, stem: &str) -> Vec<PathBuf> {
    let prefix = format!("{stem}.");
    let mut v: Vec<PathBuf> = std::fs::read_dir(dir)
        .map(|rd| {
            rd.filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| {
                    p.file_name()
                        .and_then(|n| n.to_str())
                        .is_some_and(|n| n.starts_with(&prefix) && n != format!("{stem}.inp"))
                })
                .collect()
        })
        .unwrap_or_default();
    v.sort();
    v
}
