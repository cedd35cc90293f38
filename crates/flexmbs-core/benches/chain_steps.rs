//! Cost per generalized-alpha step of a chain of N links joined by revolute joints
//! (`tests/chain/mod.rs`: six-mode FFR links, nu = 12 and 5 joint rows per link, or rigid
//! quaternion links, nu = 6), with the dense and the sparse linear-solver backend, and the
//! backend that `LinearSolver::Auto` picks. Full Newton, rho_inf 0.9, h = 1e-3 s, the chain
//! falling from the horizontal under gravity.
//!
//! Run: `cargo bench -p flexmbs-core --bench chain_steps`. Not a test: nothing is asserted.
//! Wall time: the minimum over `CHAIN_BENCH_REPS` (default 3) repetitions of a batch of steps
//! (at least 3 steps and 0.2 s per batch), after 2 warm-up steps.
//! Environment:
//! - `CHAIN_BENCH_N=1,10,100`: restrict the chain lengths;
//! - `CHAIN_BENCH_DENSE_MAX=1000`: largest `nu + nc` run with the dense backend;
//! - `CHAIN_BENCH_LINKS=flexible` (or `rigid`): one series only;
//! - `CHAIN_BENCH_STEPS=5`: exactly this many steps per batch (for instruction counts with
//!   `valgrind --tool=callgrind --collect-atstart=no --toggle-collect='*GenAlpha::step'`).

#[path = "../tests/chain/mod.rs"]
mod chain;

use chain::{chain, Link};
use flexmbs_core::algebra::{LinearSolver, SystemMatrix};
use flexmbs_core::integrator::{GenAlpha, GenAlphaSettings};
use flexmbs_core::Workspace;
use std::time::Instant;

const H: f64 = 1e-3;

fn env_list(name: &str, default: &[usize]) -> Vec<usize> {
    std::env::var(name)
        .ok()
        .map(|s| s.split(',').filter_map(|x| x.trim().parse().ok()).collect())
        .unwrap_or_else(|| default.to_vec())
}

/// (us per step, Newton iterations per step) of `n` links with `choice`.
fn time_steps(n: usize, link: Link, choice: LinearSolver, reps: usize) -> (f64, f64) {
    let fixed = std::env::var("CHAIN_BENCH_STEPS")
        .ok()
        .and_then(|s| s.parse::<usize>().ok());
    let (model, s0) = chain(n, link, None);
    let ga = GenAlpha::new(GenAlphaSettings::default())
        .unwrap()
        .with_step_energy(false);
    let mut ws = Workspace::with_linear_solver(&model, choice);
    let mut s = s0.clone();
    ga.initialize(&model, &mut s, &mut ws).unwrap();
    for _ in 0..2 {
        ga.step(&model, &mut s, &mut ws, H).unwrap();
    }
    let mut best = f64::INFINITY;
    let mut iterations = 0.0;
    for _ in 0..reps {
        let (mut steps, mut its) = (0usize, 0usize);
        let start = Instant::now();
        while match fixed {
            Some(k) => steps < k,
            None => steps < 3 || start.elapsed().as_secs_f64() < 0.2,
        } {
            its += ga.step(&model, &mut s, &mut ws, H).unwrap().iterations;
            steps += 1;
        }
        let per = start.elapsed().as_secs_f64() / steps as f64;
        if per < best {
            best = per;
            iterations = its as f64 / steps as f64;
        }
    }
    (best * 1e6, iterations)
}

fn main() {
    let ns = env_list(
        "CHAIN_BENCH_N",
        &[1, 2, 5, 10, 20, 35, 50, 75, 100, 150, 200],
    );
    let dense_max = env_list("CHAIN_BENCH_DENSE_MAX", &[1000])[0];
    let reps = env_list("CHAIN_BENCH_REPS", &[3])[0];
    let links = match std::env::var("CHAIN_BENCH_LINKS").as_deref() {
        Ok("flexible") => vec![Link::Flexible],
        Ok("rigid") => vec![Link::Rigid],
        _ => vec![Link::Flexible, Link::Rigid],
    };
    println!("| links | N | nu + nc | dense us/step | sparse us/step | sparse/dense | Newton it./step | auto |");
    println!("|---|---|---|---|---|---|---|---|");
    for link in links {
        for &n in &ns {
            let (model, _) = chain(n, link, None);
            let dim = model.nu + model.nc;
            let auto = if SystemMatrix::new(&model, LinearSolver::Auto).is_sparse() {
                "sparse"
            } else {
                "dense"
            };
            let dense = (dim <= dense_max).then(|| time_steps(n, link, LinearSolver::Dense, reps));
            let (sparse, it) = time_steps(n, link, LinearSolver::Sparse, reps);
            let (d, ratio) = match dense {
                Some((d, _)) => (format!("{d:.1}"), format!("{:.2}", sparse / d)),
                None => ("-".into(), "-".into()),
            };
            println!("| {link:?} | {n} | {dim} | {d} | {sparse:.1} | {ratio} | {it:.1} | {auto} |");
        }
    }
}
