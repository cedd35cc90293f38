//! The full-FE reference of `point_mass_on_beam` (`point_mass_on_beam_full_fe`): unit tests of the
//! reference itself, and the step and mode studies behind the README's tables (ignored: minutes).

use flexmbs_validate::point_mass_on_beam::reduce_beam_with;
use flexmbs_validate::point_mass_on_beam_convergence::{mode_study, step_study};
use std::path::Path;

fn log(s: &str) {
    println!("{s}");
}

/// The step study (h = 1e-5, 5e-6, 2.5e-6 s; hex20 face weights), 0.1 s. About 25 min.
#[test]
#[ignore]
fn full_fe_step_study() {
    let t_end = std::env::var("PMB_T_END").ok().and_then(|s| s.parse().ok()).unwrap_or(0.1);
    let rows = step_study(1e-5, t_end, &log).unwrap();
    println!("{}", rows.join("\n"));
}

/// The mode study (10 ... 200 modes, FFR S4 and the reference's integrator on the modal basis,
/// h = 1e-5 s, 0.1 s); writes `node_full_fe` and `mass_full_fe` plots into the case's folder.
#[test]
#[ignore]
fn full_fe_mode_study() {
    let t_end = std::env::var("PMB_T_END").ok().and_then(|s| s.parse().ok()).unwrap_or(0.1);
    let beam = reduce_beam_with(200).unwrap();
    let out = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../validation/point_mass_on_beam");
    let rows = mode_study(&beam, &[10, 20, 40, 60, 100, 200], 1e-5, t_end, &out, &log).unwrap();
    println!("{}", rows.join("\n"));
}
