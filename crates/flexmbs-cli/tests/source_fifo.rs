//! A model file or body source that is a FIFO (named pipe) is refused at once with a message
//! naming it, instead of hanging while waiting for a writer (created with `mkfifo`).

#![cfg(unix)]

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// Runs `flexmbs <args>`; kills it and fails if it has not ended within 20 s (a hang).
fn flexmbs_within_20_s(args: &[&str], file: &Path) -> (Option<i32>, String) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_flexmbs"))
        .args(args)
        .arg(file)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let start = Instant::now();
    loop {
        if let Some(status) = child.try_wait().unwrap() {
            let mut err = String::new();
            std::io::Read::read_to_string(child.stderr.as_mut().unwrap(), &mut err).unwrap();
            return (status.code(), err);
        }
        if start.elapsed() > Duration::from_secs(20) {
            child.kill().unwrap();
            panic!("flexmbs {args:?} {} hangs", file.display());
        }
        std::thread::sleep(Duration::from_millis(20));
    }
}

fn mkfifo(path: &Path) -> bool {
    match Command::new("mkfifo").arg(path).status() {
        Ok(s) if s.success() => true,
        _ => {
            flexmbs_io::test_tools::skip_for_missing_tool("source_fifo", "mkfifo not available");
            false
        }
    }
}

#[test]
fn fifo_model_and_body_source_are_refused() {
    let dir = flexmbs_io::test_tools::scratch_dir("fifo");
    let model = dir.join("model.toml");
    if !mkfifo(&model) {
        return;
    }
    for args in [&["check"][..], &["run"][..]] {
        let (code, err) = flexmbs_within_20_s(args, &model);
        assert_eq!(code, Some(1), "{args:?}: {err}");
        assert!(
            err.contains("model.toml") && err.contains("FIFO"),
            "{args:?}: {err}"
        );
    }
    // a regular model file whose ffr body source is a FIFO
    let body = dir.join("body.h5");
    assert!(mkfifo(&body));
    let text = format!(
        "[model]\nname = \"m\"\n\n[solver]\ntype = \"generalized-alpha\"\nh = \"1 ms\"\n\
         t_end = \"0.01 s\"\n\n[[body]]\nname = \"beam\"\ntype = \"ffr\"\nsource = \"{}\"\n",
        body.display()
    );
    let model2 = dir.join("model2.toml");
    std::fs::write(&model2, text).unwrap();
    let (code, err) = flexmbs_within_20_s(&["check"], &model2);
    assert_eq!(code, Some(1), "{err}");
    assert!(err.contains("body.h5") && err.contains("FIFO"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}
