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

use flexmbs_validate::sliding_balls::{reduce_beam, simulate, Beam, Config, Run};
use std::io::{Read, Write};
use std::path::Path;
use std::time::Instant;

fn env_list(name: &str, default: &[usize]) -> Vec<usize> {
    match std::env::var(name) {
        Ok(s) => s.split(',').filter_map(|x| x.trim().parse().ok()).collect(),
        Err(_) => default.to_vec(),
    }
}

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

/// The consistent mass matrix as `n`, `nnz`, column pointers, row indices, values (u64/f64 LE).
fn write_mass(path: &Path, m: &flexmbs_fe::SparseMatrix) {
    let mut f = std::fs::File::create(path).expect("mass file");
    let (ptr, idx, val) = (m.col_ptr(), m.row_idx(), m.val());
    let mut put = |x: u64| f.write_all(&x.to_le_bytes()).expect("write");
    put(m.nrows() as u64);
    put(val.len() as u64);
    ptr.iter().chain(idx).for_each(|&x| put(x as u64));
    for x in val {
        f.write_all(&x.to_le_bytes()).expect("write");
    }
}

fn read_mass(path: &Path) -> flexmbs_fe::SparseMatrix {
    let mut bytes = vec![];
    std::fs::File::open(path)
        .expect("mass file")
        .read_to_end(&mut bytes)
        .expect("read");
    let word = |i: usize| u64::from_le_bytes(bytes[8 * i..8 * i + 8].try_into().unwrap());
    let (n, nnz) = (word(0) as usize, word(1) as usize);
    let ptr: Vec<usize> = (0..=n).map(|i| word(2 + i) as usize).collect();
    let idx: Vec<usize> = (0..nnz).map(|i| word(3 + n + i) as usize).collect();
    let val: Vec<f64> = (0..nnz)
        .map(|i| f64::from_bits(word(3 + n + nnz + i)))
        .collect();
    let sym = faer::sparse::SymbolicSparseColMat::new_checked(n, n, ptr, None, idx);
    faer::sparse::SparseColMat::new(sym, val)
}

/// The reduced beam, from the cache directory `SB_BENCH_CACHE` if it holds one.
fn beam() -> Beam {
    let Ok(dir) = std::env::var("SB_BENCH_CACHE") else {
        return reduce_beam().expect("beam");
    };
    let dir = Path::new(&dir);
    let (body, mass) = (dir.join("beam.h5"), dir.join("mass.bin"));
    if body.exists() && mass.exists() {
        return Beam {
            reduced: flexmbs_io::body_file::read_body(&body).expect("cached beam"),
            mass: read_mass(&mass),
        };
    }
    let beam = reduce_beam().expect("beam");
    std::fs::create_dir_all(dir).expect("cache dir");
    flexmbs_io::body_file::write_body(&body, &beam.reduced).expect("write beam");
    write_mass(&mass, &beam.mass);
    beam
}

fn main() {
    let t0 = Instant::now();
    let beam = beam();
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
