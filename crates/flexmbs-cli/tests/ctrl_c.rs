//! Ctrl-C ends a run cleanly: SIGINT to the `flexmbs run` process gives exit code 130 and a
//! readable results file with status `interrupted`. Also: `flexmbs check` on both file kinds.

use crate::common::long_pendulum;
use flexmbs_io::results::{read_results, RunStatus};
use std::path::Path;
use std::process::Command;
use std::time::{Duration, Instant};

#[cfg(unix)]
#[test]
fn sigint_interrupts_run_with_results_kept() {
    interrupt_with("INT");
}

/// `timeout`, container stops and job schedulers send SIGTERM, a closed terminal SIGHUP: both end
/// the run like Ctrl-C (status interrupted, final state written, exit code 130).
#[cfg(unix)]
#[test]
fn sigterm_and_sighup_interrupt_run_with_results_kept() {
    interrupt_with("TERM");
    interrupt_with("HUP");
}

#[cfg(unix)]
fn interrupt_with(signal: &str) {
    let dir = flexmbs_io::test_tools::scratch_dir(&format!("ctrlc-{signal}"));
    let model = dir.join("long.toml");
    std::fs::write(&model, long_pendulum("1000 s", 10)).unwrap();
    let out = dir.join("out");
    let mut child = Command::new(env!("CARGO_BIN_EXE_flexmbs"))
        .args(["--quiet", "run"])
        .arg(&model)
        .arg("-o")
        .arg(&out)
        .spawn()
        .unwrap();
    let results = out.join("results.h5");
    let start = Instant::now();
    while !results.exists() {
        assert!(
            start.elapsed() < Duration::from_secs(60),
            "results.h5 never appeared"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
    std::thread::sleep(Duration::from_millis(500));
    let kill = Command::new("kill")
        .args([&format!("-{signal}"), &child.id().to_string()])
        .status()
        .unwrap();
    assert!(kill.success());
    let status = child.wait().unwrap();
    assert_eq!(
        status.code(),
        Some(130),
        "SIG{signal}: exit status {status:?}"
    );
    let r = read_results(&results).unwrap();
    let RunStatus::Interrupted { t } = r.status else {
        panic!("status {:?}", r.status);
    };
    assert!(t > 0.0 && t < 100000.0);
    assert!(r.time.len() >= 2);
    assert_eq!(*r.time.last().unwrap(), t, "the final state is in the file");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn check_accepts_fe_and_multibody_files() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    for (file, expect) in [
        (
            "examples/mbs/slider_crank.toml",
            "multibody model `slider_crank`",
        ),
        ("examples/mbs/parts/rod.toml", "independent DOFs"),
    ] {
        let o = Command::new(env!("CARGO_BIN_EXE_flexmbs"))
            .args(["--quiet", "check"])
            .arg(root.join(file))
            .output()
            .unwrap();
        let text = String::from_utf8_lossy(&o.stdout);
        assert!(
            o.status.success(),
            "{file}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        assert!(text.contains(expect), "{file}: {text}");
    }
    // a bad multibody file: exit code 1, key path and line in the message
    let dir = flexmbs_io::test_tools::scratch_dir("check");
    let bad = dir.join("bad.toml");
    let text = long_pendulum("1000 s", 10).replace("mass = 1", "mass = \"1 m\"");
    std::fs::write(&bad, text).unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_flexmbs"))
        .arg("check")
        .arg(&bad)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1));
    assert!(
        err.contains("bad.toml:14: at `body[0].mass`") && err.contains("length unit"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// Output into a closed pipe (`flexmbs check ... | head -0`) ends the process by SIGPIPE, as Unix
/// filters do, never with a Rust panic about a broken pipe.
#[cfg(unix)]
#[test]
fn closed_stdout_pipe_ends_quietly() {
    use std::os::unix::process::ExitStatusExt;
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let (reader, writer) = std::io::pipe().unwrap();
    drop(reader); // every write to the pipe now fails with EPIPE
    let o = Command::new(env!("CARGO_BIN_EXE_flexmbs"))
        .args(["--quiet", "check"])
        .arg(root.join("examples/mbs/slider_crank.toml"))
        .stdout(writer)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!err.contains("panicked"), "stderr: {err}");
    assert_eq!(
        o.status.signal(),
        Some(libc::SIGPIPE),
        "status {:?}, stderr: {err}",
        o.status
    );
}
