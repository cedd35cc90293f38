//! A run killed at a random time (kill -9) or stopped by SIGTERM leaves a results file that h5py
//! and `read_results` open: kill -9 leaves status `running` and loses at most one flush interval
//! (the file was last written at most one interval, plus a margin for a loaded machine, before
//! the kill), SIGTERM leaves status `interrupted` with the final state as last row.

use crate::common::long_pendulum;
use flexmbs_io::results::{read_results, RunStatus, DEFAULT_FLUSH_INTERVAL};
use std::path::{Path, PathBuf};
use std::process::{Child, Command};
use std::time::{Duration, Instant, SystemTime};

/// Random delays in `[lo, hi)` seconds from a small linear congruential generator seeded by the
/// clock (the seed is printed, so a failure can be repeated).
fn random_delays(n: usize, lo: f64, hi: f64) -> Vec<f64> {
    let seed = SystemTime::now()
        .duration_since(SystemTime::UNIX_EPOCH)
        .unwrap()
        .as_nanos() as u64;
    eprintln!("random delays: seed {seed}");
    let mut x = seed | 1;
    (0..n)
        .map(|_| {
            x = x
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            lo + (hi - lo) * ((x >> 11) as f64 / (1u64 << 53) as f64)
        })
        .collect()
}

/// Starts `flexmbs run` on the long model in `dir`; returns the child, the results path and
/// the moment the results file appeared.
fn start_run(dir: &Path) -> (Child, PathBuf, Instant) {
    let _ = std::fs::remove_dir_all(dir);
    std::fs::create_dir_all(dir).unwrap();
    let model = dir.join("long.toml");
    std::fs::write(&model, long_pendulum("100000 s", 2)).unwrap();
    let out = dir.join("out");
    let child = Command::new(env!("CARGO_BIN_EXE_flexmbs"))
        .args(["--quiet", "run"])
        .arg(&model)
        .arg("-o")
        .arg(&out)
        .spawn()
        .unwrap();
    let results = out.join("results.h5");
    let start = Instant::now();
    while !results.exists() {
        assert!(start.elapsed() < Duration::from_secs(60), "no results.h5");
        std::thread::sleep(Duration::from_millis(5));
    }
    (child, results, Instant::now())
}

/// h5py opens the file and reads every row dataset; prints `<status> <rows>`.
fn h5py_status_and_rows(path: &Path) -> Option<(String, usize)> {
    if !flexmbs_io::test_tools::python_or_skip("kill_results (h5py)", &["h5py", "numpy"]) {
        return None;
    }
    let code = r#"
import sys, h5py
with h5py.File(sys.argv[1], 'r') as f:
    n = f['time'].shape[0]
    for k in ['q', 'u', 'energy', 'drift', 'step']:
        assert f[k][()].shape[0] >= n, (k, f[k].shape, n)
    print(f.attrs['status'], n)
"#;
    let o = Command::new("python3")
        .args(["-c", code])
        .arg(path)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = String::from_utf8_lossy(&o.stdout).to_string();
    let mut it = text.split_whitespace();
    Some((
        it.next().unwrap().to_string(),
        it.next().unwrap().parse().unwrap(),
    ))
}

#[cfg(unix)]
#[test]
fn kill_9_at_random_times_loses_at_most_one_flush_interval() {
    let margin = Duration::from_millis(1500);
    for (k, delay) in random_delays(4, 0.1, 5.0).into_iter().enumerate() {
        let dir = flexmbs_io::test_tools::scratch_dir(&format!("kill9-{k}"));
        let (mut child, results, appeared) = start_run(&dir);
        std::thread::sleep(Duration::from_secs_f64(delay));
        child.kill().unwrap(); // SIGKILL
        let killed = SystemTime::now();
        let alive = appeared.elapsed();
        child.wait().unwrap();
        let r = read_results(&results).unwrap();
        assert_eq!(r.status, RunStatus::Running, "kill -9 after {delay:.2} s");
        let written = std::fs::metadata(&results).unwrap().modified().unwrap();
        let lost = killed.duration_since(written).unwrap_or_default();
        eprintln!(
            "kill -9 after {alive:?}: {} rows (t = {:?}), last write {lost:?} before the kill",
            r.rows(),
            r.time.last()
        );
        assert!(
            lost <= DEFAULT_FLUSH_INTERVAL + margin,
            "last write {lost:?} before the kill (interval {DEFAULT_FLUSH_INTERVAL:?})"
        );
        if alive > DEFAULT_FLUSH_INTERVAL + margin {
            assert!(r.rows() > 0, "no row after {alive:?}");
        }
        if let Some((status, rows)) = h5py_status_and_rows(&results) {
            assert_eq!((status.as_str(), rows), ("running", r.rows()));
        }
        let _ = std::fs::remove_dir_all(&dir);
    }
}

#[cfg(unix)]
#[test]
fn sigterm_at_random_times_keeps_every_row() {
    for (k, delay) in random_delays(3, 0.1, 3.0).into_iter().enumerate() {
        let dir = flexmbs_io::test_tools::scratch_dir(&format!("term-{k}"));
        let (child, results, _) = start_run(&dir);
        std::thread::sleep(Duration::from_secs_f64(delay));
        let kill = Command::new("kill")
            .args(["-TERM", &child.id().to_string()])
            .status()
            .unwrap();
        assert!(kill.success());
        let status = child.wait_with_output().unwrap().status;
        assert_eq!(status.code(), Some(130), "SIGTERM after {delay:.2} s");
        let r = read_results(&results).unwrap();
        let RunStatus::Interrupted { t } = r.status else {
            panic!("status {:?}", r.status);
        };
        assert_eq!(r.time.last(), Some(&t), "the final state is the last row");
        // every output row up to the interruption: 2 steps of 1 ms per row
        let expected = (t / 0.002).round() as usize;
        assert!(
            r.rows() + 1 >= expected && r.rows() <= expected + 2,
            "{} rows up to t = {t}",
            r.rows()
        );
        if let Some((status, rows)) = h5py_status_and_rows(&results) {
            assert_eq!((status.as_str(), rows), ("interrupted", r.rows()));
        }
        let _ = std::fs::remove_dir_all(&dir);
    }
}
