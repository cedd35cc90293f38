//! Corpus of bad multibody model files (`tests/bad_models/*.toml`): `flexmbs check` must refuse
//! each with a located error (file, line, key path) and the expected message, and `flexmbs run`
//! must refuse it the same way before it writes anything: exit code 1, never a panic (exit 101),
//! never a `results.h5` left behind. Each corpus file starts with two header lines:
//! `# expect-key: <key path>` and `# expect: <substring of the message>`.
//!
//! FE body files (`tests/bad_models/fe/*.toml`, same headers) that are mechanisms (zero-energy
//! modes: hourglass modes, disconnected parts) are refused the same way by `modal` and `reduce`
//! (which writes no file); `check` of an FE body file meshes it and finds disconnected parts, but
//! runs no eigen analysis.
//!
//! Plus the case that needs a generated file: a reduced-body file (`.fmb.h5`) without modes.

use std::path::{Path, PathBuf};
use std::process::Command;

fn corpus_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/bad_models")
}

/// A fresh scratch folder for this test process.
fn scratch(name: &str) -> PathBuf {
    flexmbs_io::test_tools::scratch_dir(&format!("bad_{name}"))
}

/// Exit code and stderr of `flexmbs -q <command> <model> [-o <out>]` (`-o` for run and reduce).
fn flexmbs(command: &str, model: &Path, out: &Path) -> (Option<i32>, String) {
    let mut c = Command::new(env!("CARGO_BIN_EXE_flexmbs"));
    c.arg("-q").arg(command).arg(model);
    if command == "run" || command == "reduce" {
        c.arg("-o").arg(out);
    }
    let o = c.output().unwrap();
    (
        o.status.code(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

/// The value of the header line `# <tag>: value` of a corpus file.
fn header<'a>(text: &'a str, tag: &str, name: &str) -> &'a str {
    let prefix = format!("# {tag}: ");
    text.lines()
        .find_map(|l| l.strip_prefix(&prefix))
        .unwrap_or_else(|| panic!("{name}: no `{prefix}` header line"))
        .trim()
}

/// Asserts that `check` and `run` both refuse `model` with a located error at `key` (after the
/// file name and a line number) containing `needle`, without a panic, and that `run` wrote no
/// results file.
fn assert_refused(model: &Path, key: &str, needle: &str, out: &Path) {
    assert_refused_by(&["check", "run"], model, key, needle, out);
    assert!(
        !out.join("results.h5").exists(),
        "run {} wrote a results file although the model is refused",
        model.display()
    );
}

/// Asserts that each of `commands` refuses `model` with a located error at `key` (after the file
/// name and a line number) containing `needle`, with exit code 1 and without a panic.
fn assert_refused_by(commands: &[&str], model: &Path, key: &str, needle: &str, out: &Path) {
    let name = model.file_name().unwrap().to_str().unwrap();
    for &command in commands {
        let (code, err) = flexmbs(command, model, out);
        let what = format!("{command} {name}: exit {code:?}, stderr:\n{err}");
        assert_eq!(code, Some(1), "{what}");
        assert!(!err.contains("panicked"), "{what}");
        let located = format!("at `{key}`: ");
        let at = err
            .find(&located)
            .unwrap_or_else(|| panic!("{what}\n(no `{located}`)"));
        // `<file>:<line>: at `key`` with a line >= 1 right before the key path
        let before = err[..at].trim_end_matches(' ');
        let (file_part, line) = before
            .trim_end_matches(':')
            .rsplit_once(':')
            .unwrap_or_else(|| panic!("{what}\n(no line before the key path)"));
        assert!(line.parse::<usize>().is_ok_and(|l| l >= 1), "{what}");
        assert!(file_part.ends_with(name), "{what}");
        assert!(err[at..].contains(needle), "{what}\n(lacks `{needle}`)");
    }
}

#[test]
fn check_and_run_refuse_every_bad_model_with_a_located_error() {
    let mut files: Vec<PathBuf> = std::fs::read_dir(corpus_dir())
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    files.sort();
    assert!(files.len() >= 18, "corpus shrank: {} files", files.len());
    let out = scratch("corpus");
    for model in &files {
        let text = std::fs::read_to_string(model).unwrap();
        let name = model.file_name().unwrap().to_str().unwrap();
        let key = header(&text, "expect-key", name);
        let needle = header(&text, "expect", name);
        let out = out.join(model.file_stem().unwrap());
        assert_refused(model, key, needle, &out);
        println!("{name}: refused at `{key}`");
    }
}

#[test]
fn modal_and_reduce_refuse_mechanisms_with_the_cause_named() {
    let dir = corpus_dir().join("fe");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    assert_eq!(files.len(), 3);
    let out = scratch("fe");
    for model in &files {
        let text = std::fs::read_to_string(model).unwrap();
        let name = model.file_name().unwrap().to_str().unwrap();
        let key = header(&text, "expect-key", name);
        let needle = header(&text, "expect", name);
        let body_file = out.join(format!("{name}.fmb.h5"));
        assert_refused_by(&["modal", "reduce"], model, key, needle, &body_file);
        assert!(!body_file.exists(), "reduce {name} wrote {body_file:?}");
        println!("{name}: refused at `{key}`");
    }
    // `check` meshes the body: it finds the disconnected parts (no eigen analysis)
    let two = dir.join("two_boxes.toml");
    assert_refused_by(&["check"], &two, "body.mesh", "parts not connected", &out);
}

/// A free-free solid body (hex8), so that the FFR mass product without rotary inertias runs.
const BAR: &str = r#"
[body]
name = "bar"
[body.mesh]
type = "box"
size = [0.2, 0.02, 0.02]
divisions = [4, 1, 1]
element = "hex8"
material = { e = 210e9, nu = 0.3, rho = 7850.0 }
[body.reduction]
modes = 2
"#;

const MODEL_WITH_BODY_FILE: &str = r#"
[model]
name = "no_modes"

[solver]
type = "generalized-alpha"
h = "1 ms"
t_end = "0.01 s"

[[body]]
name = "bar"
type = "ffr"
source = "bar.fmb.h5"
"#;

#[test]
fn check_and_run_refuse_a_body_file_without_modes() {
    let d = scratch("body_file");
    std::fs::write(d.join("bar.toml"), BAR).unwrap();
    let mut body = flexmbs_sim::bodies::load_reduced(
        Path::new("bar.toml"),
        &d,
        "bar",
        flexmbs_fe::UnitSystem::Si,
    )
    .unwrap();
    assert_eq!(body.num_modes(), 2);
    let n3 = body.modes_t.nrows();
    body.modes_t = faer::Mat::zeros(n3, 0);
    body.modes_r = body.modes_r.map(|m| faer::Mat::zeros(m.nrows(), 0));
    body.k_red = faer::Mat::zeros(0, 0);
    body.m_red = faer::Mat::zeros(0, 0);
    body.frequencies_hz.clear();
    body.labels.clear();
    flexmbs_io::body_file::write_body(&d.join("bar.fmb.h5"), &body).unwrap();
    let model = d.join("no_modes.toml");
    std::fs::write(&model, MODEL_WITH_BODY_FILE).unwrap();
    assert_refused(
        &model,
        "body[0].source",
        "the body has no modes",
        &d.join("out"),
    );
}
