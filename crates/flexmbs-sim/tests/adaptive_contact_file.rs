//! `solver.adaptive.max_penetration`: a length with its default 1e-6 m, taken by
//! generalized-alpha and moreau; a value <= 0 is an error at the key.

use flexmbs_sim::{compile_model, SimError, SolverConfig};
use std::path::Path;

fn penalty_ball() -> (std::path::PathBuf, String) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/mbs/penalty_ball.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    (path, text)
}

const ADAPTIVE: &str = "adaptive = { rtol = 1e-8, atol = 1e-8, h_max = \"5 ms\" }";

#[test]
fn max_penetration_is_read_with_its_unit_and_default() {
    let (path, text) = penalty_ball();
    assert!(text.contains(ADAPTIVE));
    let cm = compile_model(&text, &path).unwrap();
    let SolverConfig::GenAlpha {
        adaptive: Some(a), ..
    } = cm.solver
    else {
        panic!("{:?}", cm.solver)
    };
    assert_eq!(a.max_penetration, 1e-6);
    let set = text.replace(
        ADAPTIVE,
        "adaptive = { h_max = \"5 ms\", max_penetration = \"0.02 mm\" }",
    );
    let cm = compile_model(&set, &path).unwrap();
    let SolverConfig::GenAlpha {
        adaptive: Some(a), ..
    } = cm.solver
    else {
        panic!("{:?}", cm.solver)
    };
    assert!(
        (a.max_penetration - 2e-5).abs() < 1e-18,
        "{}",
        a.max_penetration
    );
}

#[test]
fn max_penetration_must_be_positive() {
    let (path, text) = penalty_ball();
    let bad = text.replace(ADAPTIVE, "adaptive = { max_penetration = \"-1 mm\" }");
    let err = compile_model(&bad, &path).unwrap_err();
    let msg = err.to_string();
    let SimError::Model { path: p, .. } = &err else {
        panic!("not a model error: {msg}");
    };
    assert_eq!(p, "solver.adaptive.max_penetration", "{msg}");
    assert!(msg.contains("must be > 0"), "{msg}");
}
