//! Cost of the results writer: pushing 10^5 rows of a 200-coordinate model (file writes, finish,
//! read back), and the adaptive flush interval of a run computing 20 us per row. Printed, not
//! asserted. Run: `cargo bench -p flexmbs-io --bench results_push`.

#[path = "../tests/results_support/mod.rs"]
mod results_support;

use flexmbs_io::results::{read_results, ResultsWriter, RunStatus};
use results_support::{layout, rows};
use std::time::Duration;

fn main() {
    let dir = std::env::temp_dir().join(format!("flexmbs-results-bench-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("big.h5");
    let l = layout(200, 200, 20, true);
    let data = rows(&l, 64, 3);
    let mut w = ResultsWriter::create(&path, l, &[]).unwrap();
    let start = std::time::Instant::now();
    for i in 0..100_000 {
        let mut r = data[i % data.len()].view();
        r.t = i as f64 * 1e-4;
        w.push(&r).unwrap();
    }
    let pushed = start.elapsed();
    let (writes, spent) = w.write_statistics();
    let t = std::time::Instant::now();
    w.finish(&RunStatus::Completed).unwrap();
    let finish = t.elapsed();
    let size = std::fs::metadata(&path).unwrap().len();
    let t = std::time::Instant::now();
    let res = read_results(&path).unwrap();
    let read = t.elapsed();
    assert_eq!(res.rows(), 100_000);
    println!(
        "push 1e5 rows: {pushed:?} (of which {writes} file writes {spent:?}); finish {finish:?}; \
         file {:.1} MB; read {read:?}",
        size as f64 / 1e6
    );

    // A run that computes 20 us per row and starts with a zero flush interval: the interval adapts
    // so that writing stays a small fraction of the wall time.
    let path = dir.join("adaptive.h5");
    let mut w = ResultsWriter::create(&path, layout(200, 200, 20, true), &[]).unwrap();
    w.set_flush_interval(Duration::ZERO);
    let start = std::time::Instant::now();
    for i in 0..100_000 {
        let spin = std::time::Instant::now();
        while spin.elapsed() < Duration::from_micros(20) {}
        let mut r = data[i % data.len()].view();
        r.t = i as f64 * 1e-4;
        w.push(&r).unwrap();
    }
    let total = start.elapsed();
    let (writes, spent) = w.write_statistics();
    println!(
        "adaptive: {total:?} wall, {writes} writes taking {spent:?} ({:.1} %), final interval {:?}",
        100.0 * spent.as_secs_f64() / total.as_secs_f64(),
        w.flush_interval()
    );
    let _ = std::fs::remove_dir_all(&dir);
}
