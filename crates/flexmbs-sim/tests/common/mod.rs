//! Fixtures shared by the integration tests of `flexmbs-sim`.
#![allow(dead_code)] // each test binary uses a subset

use std::path::PathBuf;

/// An empty scratch folder for one test ([`flexmbs_io::test_tools::scratch_dir`]).
pub fn work_dir(group: &str, name: &str) -> PathBuf {
    flexmbs_io::test_tools::scratch_dir(&format!("sim-{group}-{name}"))
}

/// FE model file of a steel shaft 1 m x 20 mm x 20 mm, 10 Euler-Bernoulli beam elements (lumped
/// mass), clamped at x = 0, 12 modes: 4 bending pairs, then torsion (mode 9), in SI.
pub const SHAFT: &str = r#"
[body]
name = "shaft"
[body.mesh]
type = "beam"
start = [0.0, 0.0, 0.0]
end = [1.0, 0.0, 0.0]
elements = 10
section = { shape = "rectangle", width = 0.02, height = 0.02 }
material = { e = 210e9, nu = 0.3, rho = 7850.0 }
[body.boundary]
fixed = [{ nearest = [0.0, 0.0, 0.0] }]
[body.reduction]
method = "modal"
modes = 12
"#;

/// A clamped hex20 beam 0.2 x 0.04 x 0.04 m (10 x 2 x 2 elements, 6 modes, consistent mass),
/// written as `beam.toml` by the contact and guide model tests; its axis y = z = 0.02 is a line
/// of element edges (21 nodes).
pub const CONTACT_BEAM: &str = r#"
[body]
name = "beam"
units = "SI"
[body.mesh]
type = "box"
size = [0.2, 0.04, 0.04]
divisions = [10, 2, 2]
element = "hex20"
material = { e = 50e6, nu = 0.3, rho = 920.0 }
[body.boundary]
fixed = ["xmin"]
[body.reduction]
method = "modal"
modes = 6
mass = "consistent"
"#;
