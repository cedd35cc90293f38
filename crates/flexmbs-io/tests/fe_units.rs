//! Unit strings in FE body model files: converted to the body's unit system (SI or SI(mm)); plain
//! numbers stay in it; a unit of the wrong dimension is a located error.

use flexmbs_io::model::{parse_fe_model, MeshSpec, NodeSelector, SectionSpec};
use std::path::Path;

fn beam(units: &str, width: &str, e: &str, rho: &str, end: &str) -> String {
    format!(
        r#"
[body]
name = "b"
{units}
[body.mesh]
type = "beam"
start = [0, 0, 0]
end = [{end}, 0, 0]
elements = 4
section = {{ shape = "rectangle", width = {width}, height = {width} }}
material = {{ e = {e}, nu = 0.3, rho = {rho} }}
[body.boundary]
fixed = [{{ nearest = [0, "0 mm", 0] }}]
"#
    )
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-15 * b.abs().max(1e-300)
}

fn beam_values(text: &str) -> (f64, f64, f64, f64) {
    let m = parse_fe_model(text, Path::new("b.toml")).unwrap();
    match m.body.mesh {
        MeshSpec::Beam {
            end,
            section: SectionSpec::Rectangle { width, .. },
            material,
            ..
        } => (end[0], width, material.e, material.rho),
        other => panic!("{other:?}"),
    }
}

#[test]
fn unit_strings_convert_to_si() {
    let (l, w, e, rho) = beam_values(&beam(
        "",
        "\"20 mm\"",
        "\"210 GPa\"",
        "\"7.85 g/cm^3\"",
        "\"100 cm\"",
    ));
    assert!(
        close(l, 1.0) && close(w, 0.02) && close(e, 210e9) && close(rho, 7850.0),
        "{l} {w} {e} {rho}"
    );
    // plain numbers are SI as before
    let (l, w, e, rho) = beam_values(&beam("", "0.02", "210e9", "7850.0", "1.0"));
    assert_eq!((l, w, e, rho), (1.0, 0.02, 210e9, 7850.0));
}

#[test]
fn unit_strings_convert_to_si_mm() {
    let units = "units = \"SI(mm)\"";
    let (l, w, e, rho) = beam_values(&beam(
        units,
        "\"2 cm\"",
        "\"210 GPa\"",
        "\"7850 kg/m^3\"",
        "\"1 m\"",
    ));
    assert!(close(l, 1000.0) && close(w, 20.0), "{l} {w}");
    assert!(close(e, 210_000.0) && close(rho, 7.85e-9), "{e} {rho}");
    // plain numbers are in the body's units (mm, MPa, t/mm^3)
    let (l, w, e, rho) = beam_values(&beam(units, "20", "210000", "7.85e-9", "1000"));
    assert_eq!((l, w, e, rho), (1000.0, 20.0, 210000.0, 7.85e-9));
    let m = parse_fe_model(
        &beam(units, "20", "2.1e5", "7.85e-9", "\"0.5 m\""),
        Path::new("b.toml"),
    )
    .unwrap();
    assert!(matches!(
        m.body.boundary.fixed[0],
        NodeSelector::Nearest {
            nearest: [0.0, 0.0, 0.0]
        }
    ));
}

#[test]
fn unit_of_the_wrong_dimension_is_located() {
    let text = beam("", "\"5 kg\"", "210e9", "7850.0", "1.0");
    let e = parse_fe_model(&text, Path::new("b.toml"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("b.toml:10") && e.contains("section"), "{e}");
    assert!(e.contains("mass unit") && e.contains("length"), "{e}");
    let text = beam("", "0.02", "\"210 kN\"", "7850.0", "1.0");
    let e = parse_fe_model(&text, Path::new("b.toml"))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("material") && e.contains("force unit") && e.contains("GPa"),
        "{e}"
    );
    let text =
        beam("", "0.02", "210e9", "7850.0", "1.0").replace("[0, \"0 mm\", 0]", "[0, \"0 s\", 0]");
    let e = parse_fe_model(&text, Path::new("b.toml"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("b.toml:13") && e.contains("time unit"), "{e}");
}
