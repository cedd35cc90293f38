//! CPU time of `point_mass_on_beam` (the validation case's model, `simulate` of
//! `flexmbs_validate::point_mass_on_beam`) over 0.1 s: setup A, C_R = 0, S2 (Moreau, h = 1e-5 s)
//! for 10 ... 100 modes, then at 20 modes S1 (step-size control, C_R = 0 and 1) and S3 (penalty,
//! step-size control), and the contour comparison (S2, 0.05 s, 2D neutral contour vs
//! FlexibleBand). The beam is reduced once (100 modes); the times are the integration only.
//!
//! Run: `cargo bench -p flexmbs-validate --bench point_mass_on_beam`. Not a test: nothing is
//! asserted. Environment:
//! - `PMB_BENCH_MODES=10,100`: restrict the mode counts of the S2 sweep;
//! - `PMB_BENCH_ONLY_S2=1`: skip the S1/S3 and contour runs;
//! - `PMB_BENCH_LAWS=1`: also S1 (C_R = 0), S3 and S4 for every mode count of the sweep (seed
//!   Table 5.4), with the average step of the step-size-controlled runs;
//! - `PMB_BENCH_T_END=0.02`: a shorter end time (e.g. under callgrind: `valgrind
//!   --tool=callgrind --collect-atstart=no --toggle-collect='*MoreauStepper*advance*'`);
//! - `PMB_BENCH_REPEAT=3`: run every configuration this many times and report the run with the
//!   least time on CPU;
//! - `PMB_BENCH_CACHE=dir`: keep the reduced beam in `dir` (`beam.h5`, the reduced-body file,
//!   and `mass.bin`, the consistent mass matrix) and read it from there in later runs (seconds
//!   instead of minutes under valgrind);
//! - `PMB_BENCH_DUMP=dir`: write the signals of every S2 run (`s2_<modes>.csv`: t, y of the
//!   mass, its y velocity, the probe node's y displacement, relative energy change) to compare
//!   trajectories between builds; likewise `s1_cr0.csv`, `s1_cr1.csv`, `s3.csv` of the S1/S3 runs.

#[path = "support/beam_cache.rs"]
mod beam_cache;

use beam_cache::{cached_beam, env_list};
use flexmbs_validate::point_mass_on_beam::{reduce_beam, simulate, Config, Run};
use std::io::Write;
use std::time::Instant;

fn env_f64(name: &str, default: f64) -> f64 {
    std::env::var(name)
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(default)
}

fn dump(dir: &str, name: &str, r: &Run) {
    std::fs::create_dir_all(dir).expect("dump dir");
    let mut f = std::fs::File::create(format!("{dir}/{name}.csv")).expect("dump file");
    for (i, &(t, y)) in r.y.iter().enumerate() {
        writeln!(
            f,
            "{t:.17e},{y:.17e},{:.17e},{:.17e},{:.17e}",
            r.v_y[i].1, r.node[i].1, r.energy[i].1
        )
        .expect("write");
    }
}

fn main() {
    let t0 = Instant::now();
    let beam = cached_beam("PMB_BENCH_CACHE", reduce_beam);
    println!("beam reduced in {:.1} s", t0.elapsed().as_secs_f64());
    let t_end = env_f64("PMB_BENCH_T_END", 0.1);
    let repeat = env_list("PMB_BENCH_REPEAT", &[1])[0].max(1);
    let dump_dir = std::env::var("PMB_BENCH_DUMP").ok();
    let base = Config {
        modes: 20,
        z0: 0.025,
        restitution: Some(0.0),
        step: Some(1e-5),
        band: false,
        t_end,
    };
    let best = |c: &Config| {
        let mut best: Option<Run> = None;
        for _ in 0..repeat {
            let r = simulate(&beam, c).expect("run");
            if best.as_ref().is_none_or(|b| r.cpu_thread < b.cpu_thread) {
                best = Some(r);
            }
        }
        best.expect("one run")
    };
    for n in env_list("PMB_BENCH_MODES", &[10, 20, 30, 40, 60, 80, 100]) {
        let r = best(&Config { modes: n, ..base });
        println!(
            "S2 modes {n:3}: {:.3} s (on CPU {:.3} s), {} steps, v_y_final {:.6}, y_min {:.7}",
            r.cpu, r.cpu_thread, r.steps, r.v_y_final, r.y_min
        );
        if let Some(d) = &dump_dir {
            dump(d, &format!("s2_{n}"), &r);
        }
    }
    if std::env::var("PMB_BENCH_LAWS").is_ok() {
        laws_by_modes(&base, &best);
    }
    if std::env::var("PMB_BENCH_ONLY_S2").is_ok() {
        return;
    }
    for (name, file, restitution) in [
        ("S1 C_R=0", "s1_cr0", Some(0.0)),
        ("S1 C_R=1", "s1_cr1", Some(1.0)),
        ("S3", "s3", None),
    ] {
        let c = Config {
            restitution,
            step: None,
            ..base
        };
        let r = best(&c);
        println!(
            "{name} 20 modes: {:.3} s (on CPU {:.3} s), {} steps",
            r.cpu, r.cpu_thread, r.steps
        );
        if let Some(d) = &dump_dir {
            dump(d, file, &r);
        }
    }
    for band in [false, true] {
        let c = Config {
            band,
            t_end: 0.05,
            ..base
        };
        let r = best(&c);
        let what = if band { "band" } else { "surface" };
        println!(
            "contour {what} (S2, 0.05 s, 20 modes): {:.3} s (on CPU {:.3} s)",
            r.cpu, r.cpu_thread
        );
    }
}

/// S1 (C_R = 0), S3 and S4 for every mode count of the sweep: time on CPU and, for the
/// step-size-controlled runs, the number of steps and the average step.
fn laws_by_modes(base: &Config, best: &dyn Fn(&Config) -> Run) {
    for n in env_list("PMB_BENCH_MODES", &[10, 20, 30, 40, 60, 80, 100]) {
        for (name, restitution, step) in [
            ("S1", Some(0.0), None),
            ("S3", None, None),
            ("S4", None, Some(1e-5)),
        ] {
            let c = Config {
                modes: n,
                restitution,
                step,
                ..*base
            };
            let r = best(&c);
            println!(
                "{name} modes {n:3}: {:.3} s (on CPU {:.3} s), {} steps, average step {:.3e} s, v_y_final {:.6}, y_min {:.7}",
                r.cpu,
                r.cpu_thread,
                r.steps,
                c.t_end / r.steps as f64,
                r.v_y_final,
                r.y_min
            );
        }
    }
}
