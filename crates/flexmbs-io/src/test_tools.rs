//! External tools that some tests need: CalculiX (`ccx`) and Python with `h5py`, `numpy` or
//! `vtk`. A test whose tool is missing skips: it prints one line `SKIPPED <test>: <reason>` to
//! stderr and returns, so it counts as passed (`cargo test -- --nocapture` or `--show-output`
//! shows the line). With the environment variable [`REQUIRE_TOOLS_ENV`] set to `1` (as `.ci/run`
//! does) a missing tool fails the test instead, so CI cannot pass without running these tests.

use std::path::PathBuf;
use std::process::Command;

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
}
