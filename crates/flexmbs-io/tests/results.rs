//! Results file, CSV, plots and animation: round trips, error paths, crash behaviour.

use crate::body_file_support;
use crate::results_support;

use body_file_support::temp_dir;
use flexmbs_fe::mesh::ElementKind;
use flexmbs_fe::reduction::Cell;
use flexmbs_io::results::{
    plot_series, read_results, write_csv, AnimationBody, AnimationWriter, ResultsError,
    ResultsLayout, ResultsWriter, RunStatus, MAX_PENDING_BYTES,
};
use results_support::{layout, rows, same_bits, OwnedRow};
use std::path::Path;
use std::time::Duration;

/// Writes `rows` and finishes with `status`.
fn write(path: &Path, l: &ResultsLayout, rows: &[OwnedRow], status: &RunStatus) {
    let mut w =
        ResultsWriter::create(path, l.clone(), &[("case", "unit test"), ("seed", "7")]).unwrap();
    for r in rows {
        w.push(&r.view()).unwrap();
    }
    assert_eq!(w.rows(), rows.len());
    assert_eq!(w.finish(status).unwrap(), path);
}

/// Every dataset reads back bit for bit, including special values, for full, empty and
/// zero-width layouts and zero rows.
#[test]
fn round_trip_is_bit_exact() {
    let dir = temp_dir("results-rt");
    let cases = [
        (layout(7, 6, 3, true), 50),
        (layout(7, 6, 3, true), 0),
        (layout(0, 0, 0, false), 0),
        (layout(0, 0, 0, false), 4),
        (layout(5, 5, 0, false), 3),
        (layout(2, 2, 1, true), 1),
    ];
    for (k, (l, n)) in cases.into_iter().enumerate() {
        let path = dir.join(format!("case{k}.h5"));
        let mut data = rows(&l, n, 11 + k as u64);
        if let Some(r) = data.get_mut(1) {
            // Special values survive too.
            r.energy = [-0.0, f64::NAN, f64::INFINITY, f64::MIN_POSITIVE / 4.0];
            if let Some(q) = r.q.first_mut() {
                *q = f64::NEG_INFINITY;
            }
        }
        write(&path, &l, &data, &RunStatus::Completed);
        let res = read_results(&path).unwrap();
        assert_eq!(res.layout, l, "case {k}");
        assert_eq!(res.status, RunStatus::Completed);
        assert_eq!(res.rows(), n);
        assert_eq!(res.time.len(), n);
        for (i, r) in data.iter().enumerate() {
            assert!(
                same_bits(&res.row(i).unwrap(), &r.view()),
                "case {k} row {i}"
            );
        }
        assert!(res.row(n).is_none());
        assert_eq!(res.attribute("case"), Some("unit test"));
        assert_eq!(res.attribute("seed"), Some("7"));
        assert_eq!(res.attributes().len(), 2);
    }
}

/// Every status variant round-trips, with its time and message.
#[test]
fn every_status_round_trips() {
    let dir = temp_dir("results-status");
    let l = layout(3, 3, 1, true);
    let data = rows(&l, 5, 3);
    let statuses = [
        RunStatus::Running,
        RunStatus::Completed,
        RunStatus::Interrupted { t: 0.0035 },
        RunStatus::Failed {
            t: 0.004,
            message: "Newton did not converge: residual 3.2e-2 > 1e-8 (ν = 0.3)".into(),
        },
        RunStatus::Failed {
            t: 0.0,
            message: String::new(),
        },
    ];
    for (k, s) in statuses.iter().enumerate() {
        let path = dir.join(format!("s{k}.h5"));
        write(&path, &l, &data, s);
        assert_eq!(&read_results(&path).unwrap().status, s);
    }
}

/// A slice of the wrong length is an error naming the field; the row is not stored.
#[test]
fn wrong_row_lengths_are_errors() {
    let dir = temp_dir("results-len");
    let l = layout(4, 3, 2, true);
    let path = dir.join("r.h5");
    let mut w = ResultsWriter::create(&path, l.clone(), &[]).unwrap();
    let good = rows(&l, 1, 5).remove(0);
    let mut bad = Vec::new();
    for field in ["q", "u", "lambda", "signals"] {
        let mut r = good.clone();
        match field {
            "q" => r.q.push(1.0),
            "u" => {
                r.u.pop();
            }
            "lambda" => r.lambda.clear(),
            _ => r.signals.push(0.0),
        }
        bad.push((field, r));
    }
    for (field, r) in &bad {
        match w.push(&r.view()) {
            Err(ResultsError::RowLength { field: f, .. }) => assert_eq!(f, *field),
            other => panic!("{field}: expected RowLength, got {other:?}"),
        }
    }
    assert_eq!(w.rows(), 0);
    w.push(&good.view()).unwrap();
    assert_eq!(w.rows(), 1);
    let msg = w.push(&bad[0].1.view()).unwrap_err().to_string();
    assert!(msg.contains("'q' has 5 values, the layout has 4"), "{msg}");
}

/// Invalid layouts and reserved attribute names are refused before anything is written.
#[test]
fn invalid_layout_and_attributes_are_errors() {
    let dir = temp_dir("results-layout");
    let path = dir.join("r.h5");
    let mut l = layout(1, 1, 0, true);
    l.signals[1].name = "tip.position".into();
    assert!(matches!(
        ResultsWriter::create(&path, l, &[]),
        Err(ResultsError::InvalidLayout { .. })
    ));
    let mut l = layout(1, 1, 0, true);
    l.signals[0].name = "a/b".into();
    assert!(ResultsWriter::create(&path, l, &[]).is_err());
    let mut l = layout(1, 1, 0, true);
    l.signals[0].components.clear();
    assert!(ResultsWriter::create(&path, l, &[]).is_err());
    for attrs in [&[("status", "x")][..], &[("a", "1"), ("a", "2")][..]] {
        assert!(matches!(
            ResultsWriter::create(&path, layout(1, 1, 0, false), attrs),
            Err(ResultsError::BadUserAttribute { .. })
        ));
    }
    assert!(!path.exists());
}

/// A writer dropped without `finish` (as in a crash) leaves the rows of its last write, readable,
/// with status "running"; rows pushed after it are lost, no temporary file is left behind.
#[test]
fn crashed_run_leaves_readable_file() {
    let dir = temp_dir("results-crash");
    let path = dir.join("crash.h5");
    let l = layout(6, 6, 2, true);
    let data = rows(&l, 8, 9);
    let mut w = ResultsWriter::create(&path, l.clone(), &[]).unwrap();
    w.set_flush_interval(Duration::from_secs(3600));
    for r in &data[..5] {
        w.push(&r.view()).unwrap();
    }
    w.flush().unwrap();
    for r in &data[5..] {
        w.push(&r.view()).unwrap();
    }
    drop(w);
    let res = read_results(&path).unwrap();
    assert_eq!(res.status, RunStatus::Running);
    assert_eq!(res.rows(), 5);
    for (i, r) in data[..5].iter().enumerate() {
        assert!(same_bits(&res.row(i).unwrap(), &r.view()));
    }
    let leftovers: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .filter(|n| n != "crash.h5")
        .collect();
    assert!(leftovers.is_empty(), "{leftovers:?}");
}

/// `push` does not write before the flush interval has passed: with a one-hour interval the file
/// still holds the empty file of `create` after 1000 rows; with a zero interval every push writes
/// until the interval has been raised to ten times the measured write time.
#[test]
fn push_respects_flush_interval() {
    let dir = temp_dir("results-interval");
    let path = dir.join("r.h5");
    let l = layout(10, 10, 2, true);
    let data = rows(&l, 1000, 1);
    let mut w = ResultsWriter::create(&path, l.clone(), &[]).unwrap();
    w.set_flush_interval(Duration::from_secs(3600));
    for r in &data {
        w.push(&r.view()).unwrap();
    }
    assert_eq!(w.write_statistics().0, 1);
    assert_eq!(read_results(&path).unwrap().rows(), 0);

    let path2 = dir.join("r2.h5");
    let mut w = ResultsWriter::create(&path2, l, &[]).unwrap();
    w.set_flush_interval(Duration::ZERO);
    w.push(&data[0].view()).unwrap();
    w.wait_for_writer().unwrap();
    let (writes, spent) = w.write_statistics();
    assert_eq!(writes, 2);
    assert!(spent > Duration::ZERO && w.flush_interval() > Duration::ZERO);
    assert_eq!(read_results(&path2).unwrap().rows(), 1);
}

/// The writer's memory is bounded: with a one-hour flush interval, the pending rows are handed to
/// the writing thread as soon as they hold `MAX_PENDING_BYTES`, so the file (read while the writer
/// is alive, after the batch in flight is written) holds all but fewer than that many bytes.
#[test]
fn pending_rows_are_flushed_at_the_byte_limit() {
    let dir = temp_dir("results-bytes");
    let path = dir.join("r.h5");
    let l = layout(200, 200, 20, true);
    let data = rows(&l, 64, 3);
    let mut w = ResultsWriter::create(&path, l, &[]).unwrap();
    w.set_flush_interval(Duration::from_secs(3600));
    // time, q, u, lambda, energy, drift, step and 4 signal values per row
    let row_bytes = 8 * (1 + 200 + 200 + 20 + 4 + 2 + 3 + 4);
    let per_flush = MAX_PENDING_BYTES.div_ceil(row_bytes);
    let n = 2 * per_flush + 7;
    for i in 0..n {
        let mut r = data[i % data.len()].view();
        r.t = i as f64;
        w.push(&r).unwrap();
    }
    w.wait_for_writer().unwrap();
    let res = read_results(&path).unwrap();
    assert_eq!(res.status, RunStatus::Running);
    assert_eq!(res.rows(), 2 * per_flush);
    assert_eq!(res.time[per_flush], per_flush as f64);
    assert_eq!(
        w.write_statistics().0,
        3,
        "create and two flushes at the byte limit"
    );
    assert_eq!(w.rows(), n);
    w.finish(&RunStatus::Completed).unwrap();
    let res = read_results(&path).unwrap();
    assert_eq!(res.rows(), n);
    assert!(same_bits(&res.row(n - 1).unwrap(), &{
        let mut r = data[(n - 1) % data.len()].view();
        r.t = (n - 1) as f64;
        r
    }));
}

/// Truncated, corrupted, foreign and missing files give errors, never panics; a flipped bit in
/// the coordinate data is caught by the Fletcher-32 checksum.
#[test]
fn damaged_files_are_errors() {
    let dir = temp_dir("results-damaged");
    let path = dir.join("good.h5");
    let l = layout(8, 8, 2, true);
    let mut data = rows(&l, 40, 2);
    let marker = f64::from_bits(0x4009_21FB_5444_2D18 ^ 0x5A5A_5A5A); // distinctive bit pattern
    data[20].q[3] = marker;
    write(&path, &l, &data, &RunStatus::Completed);
    let bytes = std::fs::read(&path).unwrap();
    let bad = dir.join("bad.h5");

    for len in [0, 7, 100, bytes.len() / 2, bytes.len() - 1] {
        std::fs::write(&bad, &bytes[..len]).unwrap();
        assert!(read_results(&bad).is_err(), "truncated to {len} bytes");
    }
    // Flip one byte at 300 positions spread over the file: never a panic.
    for k in 0..300 {
        let mut b = bytes.clone();
        let i = k * bytes.len() / 300;
        b[i] ^= 0x5A;
        std::fs::write(&bad, &b).unwrap();
        let _ = read_results(&bad);
    }
    let needle = marker.to_le_bytes();
    let at = bytes
        .windows(8)
        .position(|w| w == needle)
        .expect("marker stored raw");
    let mut b = bytes.clone();
    b[at + 2] ^= 0x01;
    std::fs::write(&bad, &b).unwrap();
    let err = read_results(&bad).unwrap_err();
    assert!(matches!(err, ResultsError::Hdf5 { .. }), "{err}");

    std::fs::write(&bad, b"t,q\n0,1\n").unwrap();
    assert!(matches!(read_results(&bad), Err(ResultsError::Hdf5 { .. })));
    assert!(matches!(
        read_results(&dir.join("missing.h5")),
        Err(ResultsError::Io { .. })
    ));

    let mut fb = hdf5_pure::FileBuilder::new();
    fb.set_attr("format", hdf5_pure::AttrValue::VarLenString("other".into()));
    std::fs::write(&bad, fb.finish().unwrap()).unwrap();
    let err = read_results(&bad).unwrap_err();
    assert!(matches!(err, ResultsError::NotAResultsFile { .. }), "{err}");
    assert!(err.to_string().contains("'other'"));
}

/// Series names, values (including the energy total) and the unknown-name error.
#[test]
fn series_by_name() {
    let dir = temp_dir("results-series");
    let path = dir.join("r.h5");
    let l = layout(2, 1, 1, true);
    let data = rows(&l, 6, 4);
    write(&path, &l, &data, &RunStatus::Completed);
    let res = read_results(&path).unwrap();
    let expected = [
        "q/rod.q0",
        "q/rod.q1",
        "u/rod.u0",
        "lambda/pin.row0",
        "energy/kinetic",
        "energy/gravity",
        "energy/elastic",
        "energy/springs",
        "energy/total",
        "drift/position",
        "drift/velocity",
        "step/h",
        "step/iterations",
        "step/residual",
        "tip.position.x",
        "tip.position.y",
        "tip.position.z",
        "crank.angle.phi",
    ];
    assert_eq!(res.series_names(), expected);
    for name in expected {
        assert_eq!(res.series(name).unwrap().len(), 6, "{name}");
    }
    let col = |f: &dyn Fn(&OwnedRow) -> f64| data.iter().map(f).collect::<Vec<f64>>();
    assert_eq!(res.series("q/rod.q1").unwrap(), col(&|r| r.q[1]));
    assert_eq!(
        res.series("lambda/pin.row0").unwrap(),
        col(&|r| r.lambda[0])
    );
    assert_eq!(res.series("drift/velocity").unwrap(), col(&|r| r.drift[1]));
    assert_eq!(res.series("step/iterations").unwrap(), col(&|r| r.step[1]));
    assert_eq!(
        res.series("tip.position.z").unwrap(),
        col(&|r| r.signals[2])
    );
    assert_eq!(
        res.series("crank.angle.phi").unwrap(),
        col(&|r| r.signals[3])
    );
    let total = col(&|r| r.energy.iter().sum());
    assert_eq!(res.series("energy/total").unwrap(), total);

    match res.series("tip.positon.z") {
        Err(e @ ResultsError::UnknownSeries { .. }) => {
            let msg = e.to_string();
            assert!(msg.contains("'tip.positon.z'"), "{msg}");
            assert!(msg.contains("tip.position.z"), "{msg}");
            assert!(!msg.contains("crank.angle.phi"), "{msg}");
        }
        other => panic!("expected UnknownSeries, got {other:?}"),
    }
    match res.series("energy/totl") {
        Err(ResultsError::UnknownSeries { close, .. }) => assert_eq!(close[0], "energy/total"),
        other => panic!("expected UnknownSeries, got {other:?}"),
    }
}

/// CSV text is exact: header, shortest round-trip numbers, one line per row; unknown names fail.
#[test]
fn csv_content_is_exact() {
    let dir = temp_dir("results-csv");
    let path = dir.join("r.h5");
    let l = layout(2, 1, 0, true);
    let mut data = rows(&l, 3, 4);
    for (i, r) in data.iter_mut().enumerate() {
        r.t = 0.5 * i as f64;
        r.q = vec![i as f64 + 0.25, -1e-12];
        r.energy = [1.5, 2.0, 0.0, f64::NAN];
        r.signals = vec![0.1, 0.2, 0.3, 3.0 * i as f64];
    }
    write(&path, &l, &data, &RunStatus::Completed);
    let res = read_results(&path).unwrap();
    let csv = dir.join("out.csv");
    write_csv(
        &res,
        &[
            "q/rod.q0",
            "q/rod.q1",
            "energy/total",
            "tip.position.y",
            "crank.angle.phi",
        ],
        &csv,
    )
    .unwrap();
    assert_eq!(
        std::fs::read_to_string(&csv).unwrap(),
        "t,q/rod.q0,q/rod.q1,energy/total,tip.position.y,crank.angle.phi\n\
         0.0,0.25,-1e-12,NaN,0.2,0.0\n\
         0.5,1.25,-1e-12,NaN,0.2,3.0\n\
         1.0,2.25,-1e-12,NaN,0.2,6.0\n"
    );
    write_csv(&res, &[], &csv).unwrap();
    let text = std::fs::read_to_string(&csv).unwrap();
    let header: Vec<&str> = text.lines().next().unwrap().split(',').collect();
    assert_eq!(header.len(), 1 + res.series_names().len());
    assert_eq!(text.lines().count(), 4);
    for line in text.lines().skip(1) {
        let values: Vec<f64> = line.split(',').map(|v| v.parse().unwrap()).collect();
        assert_eq!(values.len(), header.len());
        let i = (values[0] / 0.5).round() as usize;
        assert_eq!(values[1..3], res.row(i).unwrap().q[..]);
    }
    assert!(matches!(
        write_csv(&res, &["q/nope"], &csv),
        Err(ResultsError::UnknownSeries { .. })
    ));
}

/// PNG and SVG plots of several series are written; other extensions and empty lists are errors.
#[test]
fn plots_are_written() {
    let dir = temp_dir("results-plot");
    let path = dir.join("r.h5");
    let l = layout(2, 2, 1, true);
    write(&path, &l, &rows(&l, 30, 8), &RunStatus::Completed);
    let res = read_results(&path).unwrap();
    let names = ["tip.position.x", "tip.position.y", "tip.position.z"];
    let png = dir.join("tip.png");
    plot_series(&res, &names, &png).unwrap();
    let bytes = std::fs::read(&png).unwrap();
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
    let svg = dir.join("energy.SVG");
    plot_series(&res, &["energy/kinetic", "energy/total", "q/rod.q0"], &svg).unwrap();
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(text.contains("<svg"));
    assert!(text.contains("energy/total"));
    for bad in ["plot.pdf", "plot"] {
        assert!(matches!(
            plot_series(&res, &names, &dir.join(bad)),
            Err(ResultsError::UnsupportedPlotFormat { .. })
        ));
    }
    assert!(matches!(
        plot_series(&res, &[], &png),
        Err(ResultsError::NoSeries { .. })
    ));
    assert!(matches!(
        plot_series(&res, &["tip.position.w"], &png),
        Err(ResultsError::UnknownSeries { .. })
    ));
}

/// Two bodies (a hexahedron and a two-beam line) animated over three frames.
pub fn animation_bodies() -> Vec<AnimationBody> {
    let hex: Vec<[f64; 3]> = (0..8)
        .map(|i| {
            let (x, y, z) = (
                (i % 4 == 1 || i % 4 == 2) as u8,
                (i % 4 >= 2) as u8,
                (i >= 4) as u8,
            );
            [x as f64, y as f64, z as f64]
        })
        .collect();
    vec![
        AnimationBody {
            name: "block".into(),
            reference_points: hex,
            cells: vec![Cell {
                kind: ElementKind::Hex8,
                nodes: (0..8).collect(),
            }],
        },
        AnimationBody {
            name: "rod".into(),
            reference_points: vec![[2.0, 0.0, 0.0], [3.0, 0.0, 0.0], [4.0, 0.0, 0.0]],
            cells: vec![
                Cell {
                    kind: ElementKind::Beam2,
                    nodes: vec![0, 1],
                },
                Cell {
                    kind: ElementKind::Beam2,
                    nodes: vec![1, 2],
                },
            ],
        },
    ]
}

/// Positions of frame `k`: the block translated by (0, 0, 0.1 k), the rod rotated about z by
/// 0.2 k around its first point.
pub fn animation_positions(bodies: &[AnimationBody], k: usize) -> Vec<Vec<[f64; 3]>> {
    let a = 0.2 * k as f64;
    let block = bodies[0]
        .reference_points
        .iter()
        .map(|p| [p[0], p[1], p[2] + 0.1 * k as f64])
        .collect();
    let rod = bodies[1]
        .reference_points
        .iter()
        .map(|p| {
            let (dx, dy) = (p[0] - 2.0, p[1]);
            [
                2.0 + a.cos() * dx - a.sin() * dy,
                a.sin() * dx + a.cos() * dy,
                p[2],
            ]
        })
        .collect();
    vec![block, rod]
}

/// With the default interval the .pvd is written after the first frame, then lags (cost linear in
/// the frame count) until `flush` or drop; a new writer of the same name removes the old frames
/// (and nothing else) from the frames folder.
#[test]
fn animation_pvd_throttled_flushed_and_old_frames_removed() {
    let dir = temp_dir("results-anim-throttle");
    let bodies = animation_bodies();
    let frame = |w: &mut AnimationWriter, k: usize| {
        let pos = animation_positions(&bodies, k);
        let refs: Vec<&[[f64; 3]]> = pos.iter().map(Vec::as_slice).collect();
        w.write_frame(0.01 * k as f64, &refs).unwrap();
    };
    let listed = |w: &AnimationWriter| {
        std::fs::read_to_string(w.pvd_path())
            .unwrap()
            .matches("<DataSet ")
            .count()
    };
    let mut w = AnimationWriter::create(&dir, "run", bodies.clone()).unwrap();
    assert_eq!(w.pvd_interval(), std::time::Duration::from_secs(1));
    for k in 0..5 {
        frame(&mut w, k);
    }
    assert_eq!(
        listed(&w),
        1,
        "only the first frame is listed within the interval"
    );
    w.flush().unwrap();
    assert_eq!(listed(&w), 5);
    frame(&mut w, 5);
    frame(&mut w, 6);
    let pvd = w.pvd_path();
    drop(w);
    let text = std::fs::read_to_string(&pvd).unwrap();
    assert_eq!(text.matches("<DataSet ").count(), 7, "drop writes the rest");
    // a second run of the same name: old frame files go, a user's file stays
    std::fs::write(dir.join("run_frames/notes.txt"), "keep").unwrap();
    let mut w2 = AnimationWriter::create(&dir, "run", bodies.clone()).unwrap();
    frame(&mut w2, 0);
    w2.flush().unwrap();
    let mut files: Vec<String> = std::fs::read_dir(dir.join("run_frames"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    files.sort();
    assert_eq!(files, ["notes.txt", "run_000000.vtu"]);
    assert_eq!(listed(&w2), 1);
}

/// The .pvd lists every frame with its time and a relative file name after every frame; the
/// frames have all points, and bad input is refused.
#[test]
fn animation_writes_frames_and_collection() {
    let dir = temp_dir("results-anim");
    let bodies = animation_bodies();
    let mut w = AnimationWriter::create(&dir, "run", bodies.clone())
        .unwrap()
        .with_pvd_interval(std::time::Duration::ZERO);
    assert_eq!(w.pvd_path(), dir.join("run.pvd"));
    for k in 0..3 {
        let pos = animation_positions(&bodies, k);
        let refs: Vec<&[[f64; 3]]> = pos.iter().map(Vec::as_slice).collect();
        w.write_frame(0.05 * k as f64, &refs).unwrap();
        assert_eq!(w.frames(), k + 1);
        let pvd = std::fs::read_to_string(w.pvd_path()).unwrap();
        assert_eq!(pvd.matches("<DataSet ").count(), k + 1);
    }
    let pvd = std::fs::read_to_string(w.pvd_path()).unwrap();
    for (k, t) in ["0", "0.05", "0.1"].iter().enumerate() {
        let entry =
            format!("timestep=\"{t}\" group=\"\" part=\"0\" file=\"run_frames/run_{k:06}.vtu\"");
        assert!(pvd.contains(&entry), "{entry} in\n{pvd}");
    }
    let vtu = std::fs::read_to_string(dir.join("run_frames/run_000002.vtu")).unwrap();
    assert!(
        vtu.contains("NumberOfPoints=\"11\" NumberOfCells=\"3\""),
        "{vtu}"
    );
    assert!(vtu.contains("Name=\"displacement\" NumberOfComponents=\"3\""));
    assert!(vtu.contains("Name=\"body\" NumberOfComponents=\"1\""));

    let pos = animation_positions(&bodies, 3);
    let refs: Vec<&[[f64; 3]]> = pos.iter().map(Vec::as_slice).collect();
    for (t, r) in [(0.1, &refs[..]), (f64::NAN, &refs[..]), (0.2, &refs[..1])] {
        assert!(matches!(
            w.write_frame(t, r),
            Err(ResultsError::InvalidAnimation { .. })
        ));
    }
    let short = [&pos[0][..], &pos[1][..2]];
    assert!(w.write_frame(0.2, &short).is_err());
    assert_eq!(w.frames(), 3);

    let mut broken = animation_bodies();
    broken[1].cells[1].nodes = vec![1, 3];
    assert!(matches!(
        AnimationWriter::create(&dir, "b", broken),
        Err(ResultsError::InvalidAnimation { .. })
    ));
    assert!(AnimationWriter::create(&dir, "a/b", animation_bodies()).is_err());
}

/// A file of format version 1 (fixed-size `[n, k]` datasets, written by the previous writer and
/// kept in `tests/data/results_v1.h5`) still reads bit for bit.
#[test]
fn format_version_1_files_still_read() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/results_v1.h5");
    let l = layout(3, 3, 1, true);
    let data = rows(&l, 5, 42);
    let res = read_results(&path).unwrap();
    assert_eq!(res.layout, l);
    assert_eq!(res.status, RunStatus::Completed);
    assert_eq!(res.rows(), 5);
    assert_eq!(res.attribute("case"), Some("format version 1 fixture"));
    for (i, r) in data.iter().enumerate() {
        assert!(same_bits(&res.row(i).unwrap(), &r.view()), "row {i}");
    }
}
