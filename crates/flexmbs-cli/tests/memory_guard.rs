//! `flexmbs check` on a `[1000, 70, 70]` hex20r box (under the 5 M cell limit, about 847 GB of
//! assembly) is refused within seconds, naming the estimate and the memory available,
//! instead of running for minutes and aborting; `FLEXMBS_MEMORY_LIMIT` sets the memory available.

use std::path::Path;
use std::process::Command;
use std::time::{Duration, Instant};

fn model_with_divisions(dir: &Path, divisions: &str) -> std::path::PathBuf {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let text = std::fs::read_to_string(root.join("examples/cantilever_modal.toml")).unwrap();
    let text = text.replace(
        "divisions = [40, 2, 2]",
        &format!("divisions = {divisions}"),
    );
    assert!(text.contains(divisions));
    let path = dir.join(format!("box{}.toml", divisions.len()));
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn huge_box_is_refused_within_seconds_at_check() {
    let dir = flexmbs_io::test_tools::scratch_dir("memguard");
    let model = model_with_divisions(&dir, "[1000, 70, 70]");
    let start = Instant::now();
    let o = Command::new(env!("CARGO_BIN_EXE_flexmbs"))
        .arg("check")
        .arg(&model)
        .env("FLEXMBS_MEMORY_LIMIT", "64G")
        .output()
        .unwrap();
    let took = start.elapsed();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(took < Duration::from_secs(10), "took {took:?}");
    // 4.9e6 elements x 2106 matrix entries x 42 bytes (pattern, K, M, marks, compacted rows)
    assert!(
        err.contains("4900000 hex elements")
            && err.contains("433.41 GB")
            && err.contains("68.72 GB available (FLEXMBS_MEMORY_LIMIT)"),
        "{err}"
    );

    // the override also refuses a small model when set below its need
    let small = model_with_divisions(&dir, "[40, 4, 4]");
    let o = Command::new(env!("CARGO_BIN_EXE_flexmbs"))
        .arg("modal")
        .arg(&small)
        .env("FLEXMBS_MEMORY_LIMIT", "20M")
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(
        err.contains("would need about") && err.contains("21.0 MB available"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
