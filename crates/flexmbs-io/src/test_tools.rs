//! External tools that some tests need: CalculiX (`ccx`) and Python with `h5py`, `numpy` or
//! `vtk`, and a scratch folder per test that goes away with the test process ([`scratch_dir`]).
//! A test whose tool is missing skips: it prints one line `SKIPPED <test>: <reason>` to
//! stderr and returns, so it counts as passed (`cargo test -- --nocapture` or `--show-output`
//! shows the line). With the environment variable [`REQUIRE_TOOLS_ENV`] set to `1` (as `.ci/run`
//! does) a missing tool fails the test instead, so CI cannot pass without running these tests.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::OnceLock;

/// Environment variable that turns a missing tool into a test failure when set to `1`.
pub const REQUIRE_TOOLS_ENV: &str = "FLEXMBS_REQUIRE_TOOLS";

/// True if [`REQUIRE_TOOLS_ENV`] is `1`: tests must not skip for a missing tool.
pub fn tools_required() -> bool {
    std::env::var_os(REQUIRE_TOOLS_ENV).is_some_and(|v| v == "1")
}

/// Reports that `test` cannot run because a tool is missing (`reason`): prints
/// `SKIPPED <test>: <reason>` to stderr, so the caller returns early.
///
/// # Panics
/// When [`tools_required`]: the test fails with the reason instead of skipping.
pub fn skip_for_missing_tool(test: &str, reason: &str) {
    if tools_required() {
        panic!("{test}: {reason} ({REQUIRE_TOOLS_ENV}=1: a missing tool fails the test)");
    }
    eprintln!("SKIPPED {test}: {reason}");
}

/// The `ccx` executable ([`crate::calculix::ccx_available`]), or `None` after
/// [`skip_for_missing_tool`] has reported it missing for `test`.
///
/// # Panics
/// When ccx is missing and [`tools_required`].
pub fn ccx_or_skip(test: &str) -> Option<PathBuf> {
    let ccx = crate::calculix::ccx_available();
    if ccx.is_none() {
        skip_for_missing_tool(
            test,
            "ccx (CalculiX) not found in PATH or $FLEXMBS_CCX (apt-get install calculix-ccx)",
        );
    }
    ccx
}

/// Whether `python3` imports all `modules`; if not, [`skip_for_missing_tool`] reports the
/// reason for `test` (the import error) and the result is false.
///
/// # Panics
/// When a module or python3 is missing and [`tools_required`].
pub fn python_or_skip(test: &str, modules: &[&str]) -> bool {
    let code = modules
        .iter()
        .map(|m| format!("import {m}"))
        .collect::<Vec<_>>()
        .join("; ");
    let reason = match Command::new("python3").args(["-c", &code]).output() {
        Ok(o) if o.status.success() => return true,
        Ok(o) => format!(
            "python3 cannot import {} (pip install {}): {}",
            modules.join(", "),
            modules.join(" "),
            String::from_utf8_lossy(&o.stderr)
                .lines()
                .last()
                .unwrap_or("")
        ),
        Err(e) => format!("python3 not runnable: {e}"),
    };
    skip_for_missing_tool(test, &reason);
    false
}

/// Environment variable that keeps the test processes' scratch folders when set to `1`.
pub const KEEP_TEST_FILES_ENV: &str = "FLEXMBS_KEEP_TEST_FILES";

/// A new empty folder `<temp>/flexmbs-tests-<pid>/<tag>-<n>` for one test's files (`n` counts the
/// folders handed out, so equal tags from tests running at the same time never share a folder).
/// The per-process folder is removed when the test process exits normally, passed or failed
/// (unless [`KEEP_TEST_FILES_ENV`] is `1`): a test run leaves nothing in the temporary directory.
///
/// # Panics
/// When the folder cannot be created (a test helper: the test fails there).
pub fn scratch_dir(tag: &str) -> PathBuf {
    static NEXT: AtomicUsize = AtomicUsize::new(0);
    let n = NEXT.fetch_add(1, Ordering::Relaxed);
    let dir = scratch_root().join(format!("{tag}-{n}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir)
        .unwrap_or_else(|e| panic!("cannot create the scratch folder {}: {e}", dir.display()));
    dir
}

/// The process's scratch root, created (and its removal at exit registered) on first use.
fn scratch_root() -> &'static Path {
    static ROOT: OnceLock<PathBuf> = OnceLock::new();
    ROOT.get_or_init(|| {
        let root = std::env::temp_dir().join(format!("flexmbs-tests-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&root);
        let keep = std::env::var_os(KEEP_TEST_FILES_ENV).is_some_and(|v| v == "1");
        if !keep {
            remove_at_exit();
        }
        root
    })
}

/// Registers [`remove_scratch_root`] with the C library's `atexit`: the test harness ends the
/// process through `exit`, which runs it after the last test.
#[cfg(unix)]
fn remove_at_exit() {
    extern "C" {
        fn atexit(f: extern "C" fn()) -> std::os::raw::c_int;
    }
    // SAFETY: `atexit` is the C library's; the handler is an `extern "C"` function that only
    // calls `remove_dir_all` (errors are returned, not raised) and never calls `exit`.
    unsafe {
        atexit(remove_scratch_root);
    }
}

#[cfg(not(unix))]
fn remove_at_exit() {}

#[cfg(unix)]
extern "C" fn remove_scratch_root() {
    let root = std::env::temp_dir().join(format!("flexmbs-tests-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(root);
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The skip decision follows the environment variable of this process; both outcomes are
    /// exercised in one test (the variable is process-wide, tests run in parallel threads).
    #[test]
    fn a_missing_tool_skips_or_fails_by_the_environment() {
        let missing = "no_such_module_flexmbs_test";
        let before = std::env::var_os(REQUIRE_TOOLS_ENV);
        if before.as_deref().is_some_and(|v| v == "1") {
            let r = std::panic::catch_unwind(|| python_or_skip("probe", &[missing]));
            assert!(
                r.is_err(),
                "a missing module must fail with {REQUIRE_TOOLS_ENV}=1"
            );
        } else {
            assert!(!python_or_skip("probe", &[missing]));
        }
    }

    #[test]
    fn scratch_folders_are_new_empty_and_distinct() {
        let a = scratch_dir("same-tag");
        let b = scratch_dir("same-tag");
        assert_ne!(a, b);
        for d in [&a, &b] {
            assert!(d.is_dir());
            assert_eq!(std::fs::read_dir(d).unwrap().count(), 0);
            assert!(d.starts_with(scratch_root()));
        }
    }
}
