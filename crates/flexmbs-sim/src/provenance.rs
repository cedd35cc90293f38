//! What a results file records so that its run can be reproduced from it alone: the model text
//! (root attribute `model_text`) and the SHA-256 of every body source the model file names
//! (root attribute `source_sha256`, in the format of `sha256sum`, so `sha256sum -c` checks it).

use crate::compile::{parse_model_file, CompiledModel};
use flexmbs_io::sha256::sha256_file;
use std::path::{Path, PathBuf};

/// The body source files of a compiled model: each `body.source` resolved against the model
/// file's folder, in model order without repeats; a seed folder contributes each regular file in
/// it (sorted by name).
pub fn source_files(cm: &CompiledModel) -> Vec<PathBuf> {
    let Ok(mf) = parse_model_file(&cm.text, &cm.file) else {
        return Vec::new();
    };
    let base = cm.file.parent().unwrap_or(Path::new("."));
    let mut files: Vec<PathBuf> = Vec::new();
    for source in mf.body.iter().filter_map(|b| b.source.as_ref()) {
        let path = flexmbs_reduce::pipeline::resolve(base, source);
        let found = if path.is_dir() {
            let mut inside: Vec<PathBuf> = std::fs::read_dir(&path)
                .map(|d| {
                    d.filter_map(Result::ok)
                        .map(|e| e.path())
                        .filter(|p| p.is_file())
                        .collect()
                })
                .unwrap_or_default();
            inside.sort();
            inside
        } else {
            vec![path]
        };
        for f in found {
            if !files.contains(&f) {
                files.push(f);
            }
        }
    }
    files
}

/// `sha256sum` lines (`<64 hex digits>  <path>`) of `files`; a file that cannot be read gets
/// the line `unreadable  <path>: <error>`.
pub fn sha256_lines(files: &[PathBuf]) -> String {
    let mut out = String::new();
    for f in files {
        match sha256_file(f) {
            Ok(hex) => out.push_str(&format!("{hex}  {}\n", f.display())),
            Err(e) => out.push_str(&format!("unreadable  {}: {e}\n", f.display())),
        }
    }
    out
}
