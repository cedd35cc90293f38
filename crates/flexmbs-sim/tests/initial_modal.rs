//! Initial modal coordinates and velocities of an FFR body (`modal_coordinates`,
//! `modal_velocities`): a clamped steel cantilever released from a deformed or moving first mode
//! vibrates freely in that mode. References: the mass-normalised first cantilever mode has the tip
//! value `2 / sqrt(m)` (any uniform clamped-free beam: `φ(L) = 2` for `∫φ² = L`), and
//! `f_1 = 1.8751² / (2π) sqrt(E I / (ρ A L⁴))` (Euler-Bernoulli).

use crate::common;

use flexmbs_io::results::read_results;
use flexmbs_sim::run::{run_model, RunOptions};
use flexmbs_sim::{compile_model, SimError};
use std::path::{Path, PathBuf};

const E: f64 = 210e9;
const RHO: f64 = 7850.0;
const B: f64 = 0.02;

fn part() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/mbs/parts/cantilever_beam.toml")
}

fn model(extra_body: &str, solver: &str) -> String {
    format!(
        r#"
[model]
name = "released_cantilever"
[solver]
{solver}
[[body]]
name = "beam"
type = "ffr"
source = "{}"
{extra_body}
[[frame]]
name = "wall"
body = "ground"
[[frame]]
name = "tip"
body = "beam"
nearest = [1.0, 0.0, 0.0]
[[joint]]
name = "clamp"
type = "fixed"
a = "wall"
b = "beam"
[output]
signals = ["tip.deformation"]
"#,
        part().display()
    )
}

fn first_frequency() -> f64 {
    let (a, i) = (B * B, B.powi(4) / 12.0);
    1.8751f64.powi(2) / (2.0 * std::f64::consts::PI) * (E * i / (RHO * a)).sqrt()
}

/// Tip deflection magnitude `|d(t)|` with sign along `d(0)` (or along the largest sample).
fn run_tip(extra: &str, t_end: f64, h: f64, tag: &str) -> (Vec<f64>, Vec<f64>) {
    let solver = format!("type = \"generalized-alpha\"\nrho_inf = 1.0\nh = {h}\nt_end = {t_end}");
    let text = model(extra, &solver);
    let cm = compile_model(
        &text,
        &common::work_dir("initial-modal", tag).join("m.toml"),
    )
    .unwrap();
    let out = common::work_dir("initial-modal", &format!("{tag}-out"));
    run_model(&cm, &RunOptions::new(&out), &mut |_| {}).unwrap();
    let r = read_results(&out.join("results.h5")).unwrap();
    let d: Vec<[f64; 3]> = {
        let s = |c: &str| r.series(&format!("tip.deformation.{c}")).unwrap();
        let (x, y, z) = (s("x"), s("y"), s("z"));
        (0..r.time.len()).map(|k| [x[k], y[k], z[k]]).collect()
    };
    let dir = *d.iter().max_by(|a, b| norm(a).total_cmp(&norm(b))).unwrap();
    let n = norm(&dir);
    let w = d
        .iter()
        .map(|v| (v[0] * dir[0] + v[1] * dir[1] + v[2] * dir[2]) / n)
        .collect();
    (r.time.clone(), w)
}

fn norm(v: &[f64; 3]) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

fn at(time: &[f64], w: &[f64], t: f64) -> f64 {
    let k = time.iter().position(|&x| x >= t - 1e-12).unwrap();
    w[k]
}

#[test]
fn released_from_a_deformed_first_mode_vibrates_in_it() {
    let a = 1e-3;
    let f1 = first_frequency();
    let period = 1.0 / f1;
    let h = period / 400.0;
    let extra = format!("modal_coordinates = [{a}, 0, 0, 0, 0, 0, 0, 0]");
    let (time, w) = run_tip(&extra, 1.01 * period, h, "q");
    let tip_value = 2.0 / (RHO * B * B).sqrt();
    // the setting itself: d(0) = φ_1(L) a (20 elements, lumped mass: 2e-3)
    assert!(
        (w[0].abs() / (tip_value * a) - 1.0).abs() < 2e-3,
        "{} vs {}",
        w[0],
        tip_value * a
    );
    // free vibration in mode 1: d(T/2) = -d(0), d(T) = d(0) (FE f_1 within 1e-3 of the analytic)
    let half = at(&time, &w, 0.5 * period);
    let full = at(&time, &w, period);
    assert!(
        (half / w[0] + 1.0).abs() < 1e-3,
        "d(T/2)/d(0) = {}",
        half / w[0]
    );
    assert!(
        (full / w[0] - 1.0).abs() < 1e-3,
        "d(T)/d(0) = {}",
        full / w[0]
    );
}

#[test]
fn released_with_a_first_mode_velocity_swings_out_to_v_over_omega() {
    let v = 0.1;
    let f1 = first_frequency();
    let omega = 2.0 * std::f64::consts::PI * f1;
    let period = 1.0 / f1;
    let extra = format!("modal_velocities = [{v}, 0, 0, 0, 0, 0, 0, 0]");
    let (time, w) = run_tip(&extra, 0.3 * period, period / 400.0, "u");
    assert_eq!(w[0], 0.0);
    let peak = at(&time, &w, 0.25 * period).abs();
    let expected = 2.0 / (RHO * B * B).sqrt() * v / omega;
    assert!((peak / expected - 1.0).abs() < 3e-3, "{peak} vs {expected}");
}

fn error_of(extra: &str, solver: &str) -> String {
    let text = model(extra, solver);
    match compile_model(
        &text,
        &common::work_dir("initial-modal", "bad").join("m.toml"),
    ) {
        Err(e @ SimError::Model { .. }) => e.to_string(),
        Err(e) => panic!("expected a located model error, got {e}"),
        Ok(_) => panic!("accepted: {extra}"),
    }
}

#[test]
fn bad_modal_initial_conditions_are_located() {
    let ga = "type = \"generalized-alpha\"\nh = 1e-4\nt_end = 1e-3";
    let e = error_of("modal_coordinates = [1e-3, 0]", ga);
    assert!(
        e.contains("body[0].modal_coordinates") && e.contains("keeps 8 modes"),
        "{e}"
    );
    let e = error_of("modal_velocities = [0, 0, 0, 0, 0, 0, 0, nan]", ga);
    assert!(
        e.contains("body[0].modal_velocities") && e.contains("not a finite"),
        "{e}"
    );
    let st = "type = \"generalized-alpha\"\nh = 1e-4\nt_end = 1e-3\ninitial = \"static\"";
    let e = error_of("modal_coordinates = [0, 0, 0, 0, 0, 0, 0, 0]", st);
    assert!(
        e.contains("body[0].modal_coordinates") && e.contains("static"),
        "{e}"
    );
}

#[test]
fn rigid_body_has_no_modal_coordinates() {
    let text = r#"
[model]
name = "m"
[solver]
type = "generalized-alpha"
h = 1e-3
t_end = 1e-2
[[body]]
name = "block"
type = "rigid"
mass = 1.0
inertia = [1, 1, 1]
modal_coordinates = [1.0]
"#;
    let e = compile_model(text, Path::new("/tmp/m.toml"))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("body[0].modal_coordinates") && e.contains("only ffr"),
        "{e}"
    );
}
