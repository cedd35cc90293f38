//! `sliding_balls` setup B (100 modes) over the seed's full 5 s against the geometrically
//! nonlinear reference. Not in CI: the 100-mode run takes 12.5 times the steps of the 0.5 s run
//! (153 240 steps, 124 s on CPU in the dev build, 2026-11-25; 375 s wall on this loaded 2-core
//! machine); the reference (40 elements, h = 0.125 ms) about 20 s on CPU. Run with
//! `cargo test -p flexmbs-validate --test integration sliding_balls_full:: -- --ignored --nocapture`
//! (`SLIDING_BALLS_SERIES_DIR=dir` also writes the series for `compare_series.py`).

use flexmbs_validate::sliding_balls::{
    differences_to_reference, reduce_beam, simulate, write_reference_series, write_series, Config,
};
use flexmbs_validate::sliding_balls_reference as reference;

/// Setup B to 5 s: the laws of the CI run (energy within 5e-3, constraint at round-off, the
/// ball planar) and the agreement with the reference: RMS differences of the ball's height and
/// of the tip deflection below 10 % of the reference's RMS. The bound is the beam models'
/// difference (hex20 solid vs Euler-Bernoulli line), not nonlinearity (rotations stay below
/// 3.2e-4 rad), set from the 5 s runs of 10/20/40 modes (7.0e-2 / 7.5e-2, 7.3e-2 / 7.4e-2,
/// 7.7e-2 / 7.8e-2) before this one was run; matching the reference's first frequency to the
/// solid's does not reduce them (README). Measured (2026-11-25): 7.73e-2 / 7.76e-2.
#[test]
#[ignore = "setup B (100 modes) to 5 s: about 2.5 min of CPU (dev build), not part of CI"]
fn setup_b_to_five_seconds_against_the_reference() {
    let beam = reduce_beam().unwrap();
    let config = Config {
        modes: 100,
        x0: 0.75,
        vx0: 0.01,
        t_end: 5.0,
        degree: 3,
    };
    let run = simulate(&beam, &config).unwrap();
    let h = 1.25e-4;
    let reference = reference::simulate(40, 1.0, h, 5.0, h, 0.75, 0.01, -0.002).unwrap();
    let [dy, dtip, dx] = differences_to_reference(&run, &reference);
    // `SLIDING_BALLS_SERIES_DIR=dir`: the series for `compare_series.py` (as the case writes them)
    if let Some(dir) = std::env::var_os("SLIDING_BALLS_SERIES_DIR") {
        let dir = std::path::Path::new(&dir);
        std::fs::create_dir_all(dir).unwrap();
        write_series(&dir.join("series_modes100.csv"), &run).unwrap();
        write_reference_series(&dir.join("series_reference.csv"), &reference).unwrap();
    }
    println!(
        "100 modes, 5 s: {} steps, {:.0} s ({:.0} s on CPU); energy dev {:.2e}; drift {:.1e}; \
         z dev {:.1e}; acc max/rms {:.3}/{:.3}; ball y {dy:.3e}, tip y {dtip:.3e}, ball x {dx:.2e} m",
        run.steps,
        run.cpu,
        run.cpu_thread,
        run.energy_deviation,
        run.drift,
        run.z_dev,
        run.acc_max,
        run.acc_rms
    );
    assert!(run.energy_deviation < 5e-3 && run.drift < 1e-9 && run.z_dev < 1e-5);
    assert!(dy < 0.1 && dtip < 0.1, "{dy} {dtip}");
    assert!(dx < 1e-5, "{dx}");
}
