//! The main job (`flexmbs demo`): the embedded cantilever model, analysed and reduced end to end.

use crate::progress::Progress;
use anyhow::{Context, Result};
use flexmbs_io::model::parse_fe_model;
use flexmbs_io::plot::{LinePlot, Series, Style};
use flexmbs_reduce::pipeline::{prepare, run_modal, run_reduction};
use std::path::Path;

/// The embedded default model.
pub const DEFAULT_MODEL: &str = include_str!("../../../examples/cantilever_modal.toml");
/// The embedded multibody model: the flexible slider-crank.
pub const SLIDER_CRANK: &str = include_str!("../../../examples/mbs/slider_crank.toml");
/// Its FE rod (referenced as `parts/rod.toml`).
pub const SLIDER_CRANK_ROD: &str = include_str!("../../../examples/mbs/parts/rod.toml");

/// The embedded contact model: a point mass bouncing on a soft flexible beam (NURBS contour on
/// the FFR body's face, Newton impact, Moreau time-stepping).
pub const POINT_MASS_ON_BEAM: &str = include_str!("../../../examples/mbs/point_mass_on_beam.toml");
/// Its FE beam (referenced as `parts/soft_beam.toml`).
pub const SOFT_BEAM: &str = include_str!("../../../examples/mbs/parts/soft_beam.toml");

/// Writes an embedded multibody model `name` (`model` text, `parts`: file name under `parts/`
/// and text) into `out/<name>/` and runs it through the same path as `flexmbs run` (results.h5,
/// CSV, plots, ParaView animation).
fn run_embedded(
    out: &Path,
    name: &str,
    model: &str,
    parts: &[(&str, &str)],
    quiet: bool,
) -> Result<()> {
    let dir = out.join(name);
    std::fs::create_dir_all(dir.join("parts"))?;
    let file = dir.join(format!("{name}.toml"));
    std::fs::write(&file, model)?;
    for (part, text) in parts {
        std::fs::write(dir.join("parts").join(part), text)?;
    }
    let cm = flexmbs_sim::load_model(&file)?;
    let opts = flexmbs_sim::run::RunOptions::new(&dir);
    match crate::run_cmd::run_compiled(&cm, &opts, quiet)? {
        0 => Ok(()),
        code => anyhow::bail!("{name} run ended with exit code {code}"),
    }
}

/// Runs the demo, writing everything into `out`.
pub fn run(out: &Path, quiet: bool) -> Result<()> {
    std::fs::create_dir_all(out).with_context(|| format!("creating {}", out.display()))?;
    let spec = parse_fe_model(DEFAULT_MODEL, Path::new("<embedded cantilever_modal.toml>"))?.body;
    let mut p = Progress::new(quiet);
    let body = prepare(&spec, Path::new("."), &mut |s| p.stage(s))?;
    let modal = run_modal(&spec, &body, spec.reduction.modes, &mut |s| p.stage(s))?;
    let reduced = run_reduction(&spec, &body, &mut |s| p.stage(s))?;
    // the clamped cantilever also gets its centrifugal geometric stiffness, as `flexmbs reduce`
    p.stage(flexmbs_reduce::pipeline::Stage::Started(
        "geometric stiffness (unit-load method)".into(),
    ));
    let mass = flexmbs_reduce::geometric::system_mass_kind(&spec.mesh, spec.reduction.mass);
    let kg = flexmbs_reduce::geometric::centrifugal_geometric_stiffness(&body, mass, &reduced);
    p.finish();
    let kg = kg.context("geometric stiffness")?;

    let rows = flexmbs_reduce::report::modal_rows(&modal);
    print!("{}", flexmbs_reduce::report::modal_table(&rows));
    std::fs::write(
        out.join("frequencies.csv"),
        flexmbs_reduce::report::modal_csv(&rows),
    )?;
    let body_path = out.join("cantilever.h5");
    let rotary_inertia =
        flexmbs_reduce::full_mass::beam_node_rotary_inertias(&body.mesh, reduced.num_nodes())
            .map_err(anyhow::Error::msg)?;
    flexmbs_io::body_file::BodyFile {
        body: reduced.clone(),
        geometric: kg,
        rotary_inertia,
        stress: Some(flexmbs_reduce::stress::modal_stress_fields(
            &spec, &body, &reduced,
        )?),
        inertia_gram: None,
    }
    .write(&body_path)?;
    let vtk_dir = out.join("modes");
    let files = flexmbs_io::vtk::write_mode_shapes(&vtk_dir, &reduced, 0.1)?;

    // Bending frequencies against Euler-Bernoulli: f_n = (beta_n L)^2 / (2 pi L^2) sqrt(EI / rho A).
    let c =
        (210e9 * 0.02f64.powi(4) / 12.0 / (7850.0 * 4e-4)).sqrt() / (2.0 * std::f64::consts::PI);
    let betas = [1.875104, 4.694091, 7.854757, 10.995541, 14.137168];
    let eb: Vec<(f64, f64)> = betas
        .iter()
        .enumerate()
        .map(|(i, b)| ((i + 1) as f64, b * b * c))
        .collect();
    let mut fe_bend = Vec::new();
    for l in modal
        .labels
        .iter()
        .filter(|l| matches!(l.dominant.as_str(), "uy" | "uz" | "ry" | "rz"))
    {
        fe_bend.push(l.frequency_hz);
    }
    let pairs: Vec<(f64, f64)> = fe_bend
        .chunks(2)
        .take(betas.len())
        .enumerate()
        .map(|(i, p)| ((i + 1) as f64, p[0]))
        .collect();
    LinePlot {
        title: "Cantilever bending frequencies: hex20r 40x2x2 vs Euler-Bernoulli".into(),
        x_label: "bending mode pair".into(),
        y_label: "frequency [Hz]".into(),
        series: vec![
            Series {
                name: "Euler-Bernoulli".into(),
                points: eb,
                style: Style::Line,
            },
            Series {
                name: "flexmbs hex20r".into(),
                points: pairs,
                style: Style::Points,
            },
        ],
        log_x: false,
        log_y: true,
    }
    .write(&out.join("frequencies.png"))?;
    crate::demo_sim::run(out, &reduced, quiet)?;
    println!("\nflexible slider-crank (examples/mbs/slider_crank.toml):");
    let rod = [("rod.toml", SLIDER_CRANK_ROD)];
    run_embedded(out, "slider_crank", SLIDER_CRANK, &rod, quiet)?;
    println!(
        "\ncontact on a flexible body: a point mass bouncing on a soft beam's NURBS face \
         (examples/mbs/point_mass_on_beam.toml):"
    );
    let beam = [("soft_beam.toml", SOFT_BEAM)];
    run_embedded(out, "point_mass_on_beam", POINT_MASS_ON_BEAM, &beam, quiet)?;
    println!(
        "\nwrote {0}/slider_crank/ (results.h5, slider_crank.pvd, plots), {0}/point_mass_on_beam/ (results.h5, point_mass_on_beam.pvd with the contact points and the deformed contour, plots), {0}/tip.csv, {0}/tip.png, {0}/animation/cantilever.pvd (ParaView), {0}/frequencies.csv, {0}/frequencies.png, {1} and {2} ParaView files in {3} (open modes_animation.pvd)",
        out.display(),
        body_path.display(),
        files.len(),
        vtk_dir.display()
    );
    Ok(())
}
