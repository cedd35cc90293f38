//! Time per Moreau step of `sliding_balls` (the validation case's model, `simulate` of
//! `flexmbs_validate::sliding_balls`): the ball from mid-span, Moreau with step-size control, the
//! beam with 10 ... 100 modes. The beam is reduced once (100 modes); the times are the integration
//! only.
//!
//! Run: `cargo bench -p flexmbs-validate --bench sliding_balls`. Not a test: nothing is asserted.
//! Environment:
//! - `SB_BENCH_MODES=20,100`: the mode counts (default 100);
//! - `SB_BENCH_T_END=0.02`: the end time (default 0.05 s; e.g. under callgrind: `valgrind
//!   --tool=callgrind --collect-atstart=no --toggle-collect='*MoreauSscStepper*step*'`);
//! - `SB_BENCH_CACHE=dir`: keep the reduced beam in `dir` (`beam.h5`, the reduced-body file, and
//!   `mass.bin`, the consistent mass matrix) and read it from there in later runs;
//! - `SB_BENCH_DUMP=dir`: write the sampled signals of every run (`modes<n>.csv`: t, ball x, ball
//!   y, tip y, relative energy change, all digits) to compare trajectories between builds.

#[path = "support/beam_cache.rs"]
mod beam_cache;

use beam_cache::{cached_beam, env_list};
use flexmbs_validate::sliding_balls::{reduce_beam, simulate, Config, Run};
use std::io::Write;
use std::time::Instant;

fn dump(dir: &str, name: &str, r: &Run) {
    std::fs::create_dir_all(dir).expect("dump dir");
    let mut f = std::fs::File::create(format!("{dir}/{name}.csv")).expect("dump file");
    for ((b, tip), e) in r.ball.iter().zip(&r.tip).zip(&r.energy) {
        writeln!(
            f,
            "{:.17e},{:.17e},{:.17e},{:.17e},{:.17e}",
            b.0, b.1, b.2, tip.1, e.1
        )
        .expect("write");
    }
}

fn main() {
    let t0 = Instant::now();
    let beam = cached_beam("SB_BENCH_CACHE", reduce_beam);
    println!("beam reduced in {:.1} s", t0.elapsed().as_secs_f64());
    let t_end = std::env::var("SB_BENCH_T_END")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(0.05);
    let dump_dir = std::env::var("SB_BENCH_DUMP").ok();
    for n in env_list("SB_BENCH_MODES", &[100]) {
        let c = Config {
            modes: n,
            x0: 0.75,
            vx0: 0.01,
            t_end,
            degree: 3,
        };
        let r = simulate(&beam, &c).expect("run");
        println!(
            "modes {n:3}, {t_end} s: {:.3} s (on CPU {:.3} s), {} steps, {:.1} us per step on CPU, \
             {} sweeps, energy dev {:.3e}, x_end {:.12}",
            r.cpu,
            r.cpu_thread,
            r.steps,
            1e6 * r.cpu_thread / r.steps.max(1) as f64,
            r.sweeps,
            r.energy_deviation,
            r.x_end
        );
        if let Some(d) = &dump_dir {
            dump(d, &format!("modes{n}"), &r);
        }
    }
}
