//! Cost of the results writer. Printed, not asserted. Run: `cargo bench -p flexmbs-io --bench
//! results_push` (or `cargo test -p flexmbs-io --bench results_push` for the dev profile).
//!
//! 1. Memory of a long run: peak RSS (VmHWM) after 10^5 and 10^6 rows of a 50-column layout
//!    (first, so that nothing else has raised the peak yet).
//! 2. Pushing 10^5 rows of a 420-column model (nq = nu = 200, nc = 20, 4 signal components):
//!    time of the pushes, the flushes among them, the finish, reading back.
//! 3. A run computing 20 us per row with the default flush interval and with a zero initial
//!    interval (adaptive): share of the wall time spent flushing.

#[path = "../tests/results_support/mod.rs"]
mod results_support;

use flexmbs_io::results::{read_results, ResultsWriter, RunStatus};
use results_support::{layout, rows};
use std::time::{Duration, Instant};

/// Peak resident set size of this process in MiB (`VmHWM` of /proc/self/status).
fn peak_rss_mib() -> f64 {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    status
        .lines()
        .find_map(|l| l.strip_prefix("VmHWM:"))
        .and_then(|v| v.split_whitespace().next()?.parse::<f64>().ok())
        .map_or(f64::NAN, |kb| kb / 1024.0)
}

fn memory_of_a_long_run(dir: &std::path::Path) {
    let path = dir.join("long.h5");
    let l = layout(20, 20, 2, true);
    let data = rows(&l, 64, 5);
    println!(
        "memory: peak RSS before the writer {:.1} MiB",
        peak_rss_mib()
    );
    let mut w = ResultsWriter::create(&path, l, &[]).unwrap();
    let start = Instant::now();
    for i in 0..1_000_000 {
        let mut r = data[i % data.len()].view();
        r.t = i as f64 * 1e-4;
        w.push(&r).unwrap();
        if i + 1 == 100_000 || i + 1 == 1_000_000 {
            println!(
                "memory: {} rows pushed in {:?}, peak RSS {:.1} MiB, file {:.1} MB",
                i + 1,
                start.elapsed(),
                peak_rss_mib(),
                std::fs::metadata(&path).unwrap().len() as f64 / 1e6
            );
        }
    }
    w.finish(&RunStatus::Completed).unwrap();
    println!("memory: after finish, peak RSS {:.1} MiB", peak_rss_mib());
    let _ = std::fs::remove_file(&path);
}

fn main() {
    let dir = std::env::temp_dir().join(format!("flexmbs-results-bench-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    memory_of_a_long_run(&dir);

    let path = dir.join("big.h5");
    let l = layout(200, 200, 20, true);
    let data = rows(&l, 64, 3);
    let mut w = ResultsWriter::create(&path, l, &[]).unwrap();
    let start = Instant::now();
    for i in 0..100_000 {
        let mut r = data[i % data.len()].view();
        r.t = i as f64 * 1e-4;
        w.push(&r).unwrap();
    }
    let pushed = start.elapsed();
    let (writes, spent) = w.write_statistics();
    let t = Instant::now();
    w.finish(&RunStatus::Completed).unwrap();
    let finish = t.elapsed();
    let size = std::fs::metadata(&path).unwrap().len();
    let t = Instant::now();
    let res = read_results(&path).unwrap();
    let read = t.elapsed();
    assert_eq!(res.rows(), 100_000);
    drop(res);
    let _ = std::fs::remove_file(&path);
    println!(
        "push 1e5 rows: {pushed:?} (of which {writes} file writes {spent:?}); finish {finish:?}; \
         file {:.1} MB; read {read:?}",
        size as f64 / 1e6
    );

    // A run that computes 20 us per row: the default interval, then a zero initial interval
    // that adapts so that writing stays a small fraction of the wall time.
    for initial in [None, Some(Duration::ZERO)] {
        let path = dir.join("paced.h5");
        let mut w = ResultsWriter::create(&path, layout(200, 200, 20, true), &[]).unwrap();
        let (created, create_time) = w.write_statistics();
        if let Some(i) = initial {
            w.set_flush_interval(i);
        }
        let start = Instant::now();
        for i in 0..100_000 {
            let spin = Instant::now();
            while spin.elapsed() < Duration::from_micros(20) {}
            let mut r = data[i % data.len()].view();
            r.t = i as f64 * 1e-4;
            w.push(&r).unwrap();
        }
        let t = Instant::now();
        let interval = w.flush_interval();
        let waited = w.waiting_time();
        w.wait_for_writer().unwrap();
        let (writes, spent) = w.write_statistics();
        w.finish(&RunStatus::Completed).unwrap();
        let total = start.elapsed();
        let cost = waited + t.elapsed();
        println!(
            "20 us per row, initial interval {:?}: {total:?} wall; the run waited {cost:?} \
             ({:.1} %) for the writer (incl. finish); {} flushes took {:?} on the writing \
             thread; final interval {interval:?}",
            initial.unwrap_or(flexmbs_io::results::DEFAULT_FLUSH_INTERVAL),
            100.0 * cost.as_secs_f64() / total.as_secs_f64(),
            writes - created,
            spent - create_time,
        );
        let _ = std::fs::remove_file(&path);
    }
    let _ = std::fs::remove_dir_all(&dir);
}
