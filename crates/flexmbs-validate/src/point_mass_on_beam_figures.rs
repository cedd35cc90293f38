//! The seed's figures of `point_mass_on_beam` redrawn (seed 000 §5.2, Figs. 5.6-5.12): the
//! contour comparison (setups A and B), the coefficient of restitution (setup B), the four
//! configurations S1-S4 with several mode counts (setup B), and the final velocity and CPU time
//! against the number of modes (setup B, Fig. 5.10). No ABAQUS curves: the seed's reference
//! results are not available (the full-FE comparison of this case is in
//! [`crate::point_mass_on_beam_convergence`]).

use crate::point_mass_on_beam::{simulate, Beam, Config, Run};
use crate::ValidationResult;
use anyhow::Result;
use flexmbs_io::plot::{LinePlot, Series, Style};
use std::path::Path;

/// The four configurations of the seed (§5.2): set-valued (Newton impact) or penalty
/// (k = 1e7 N/m), with step-size control or a fixed step of 1e-5 s.
pub const CONFIGURATIONS: [(&str, bool, bool); 4] = [
    ("S1", true, false),
    ("S2", true, true),
    ("S3", false, false),
    ("S4", false, true),
];

/// Mode counts of the setup-B sweep (seed Fig. 5.10).
pub const MODE_COUNTS: [usize; 7] = [10, 20, 30, 40, 60, 80, 100];

/// The configuration `name` of setup B (z0 = 40 mm) with `modes`, from `base` (C_R = 0).
fn setup_b(base: &Config, set_valued: bool, fixed: bool, modes: usize) -> Config {
    Config {
        modes,
        z0: 0.040,
        restitution: if set_valued { Some(0.0) } else { None },
        step: if fixed { Some(1e-5) } else { None },
        ..*base
    }
}

fn line(name: String, points: &[(f64, f64)], scale: f64) -> Series {
    Series {
        name,
        points: points.iter().map(|&(t, v)| (t, scale * v)).collect(),
        style: Style::Line,
    }
}

/// Writes `name`.png and .svg.
fn write(out: &Path, name: &str, title: &str, x: &str, y: &str, series: Vec<Series>) -> Result<()> {
    let plot = LinePlot {
        title: title.into(),
        x_label: x.into(),
        y_label: y.into(),
        series,
        log_x: false,
        log_y: false,
    };
    plot.write(&out.join(format!("{name}.png")))?;
    plot.write(&out.join(format!("{name}.svg")))?;
    Ok(())
}

/// Setup B: S1-S4 for every mode count of [`MODE_COUNTS`]; records `v_y_final_B_<S>_modes<n>`
/// and `cpu_thread_s_B_<S>_modes<n>`, draws Figs. 5.9-5.11.
pub fn setup_b_sweep(
    out: &Path,
    beam: &Beam,
    base: &Config,
    res: &mut ValidationResult,
    log: &dyn Fn(&str),
) -> Result<()> {
    let mut runs: Vec<(&str, usize, Run)> = Vec::new();
    for (name, set_valued, fixed) in CONFIGURATIONS {
        for n in MODE_COUNTS {
            let r = simulate(beam, &setup_b(base, set_valued, fixed, n))?;
            log(&format!(
                "B {name} {n} modes: v_y_final {:.5} m/s, y_min {:.6} m, {} steps, {:.2} s on CPU",
                r.v_y_final, r.y_min, r.steps, r.cpu_thread
            ));
            res.record(&format!("v_y_final_B_{name}_modes{n}"), r.v_y_final);
            res.record(&format!("cpu_thread_s_B_{name}_modes{n}"), r.cpu_thread);
            res.record(&format!("steps_B_{name}_modes{n}"), r.steps as f64);
            runs.push((name, n, r));
        }
    }
    let per_config = |f: &dyn Fn(&Run) -> f64| -> Vec<Series> {
        CONFIGURATIONS
            .iter()
            .map(|(name, ..)| Series {
                name: (*name).into(),
                points: runs
                    .iter()
                    .filter(|(c, ..)| c == name)
                    .map(|(_, n, r)| (*n as f64, f(r)))
                    .collect(),
                style: Style::LinePoints,
            })
            .collect()
    };
    let title = "Point mass on beam, setup B, C_R = 0 (S1, S2)";
    write(
        out,
        "B_final_velocity",
        &format!("{title}: final velocity vs modes (seed Fig. 5.10a)"),
        "modes",
        "v_y(0.1 s) [m/s]",
        per_config(&|r| r.v_y_final),
    )?;
    write(
        out,
        "B_cpu",
        &format!("{title}: CPU time for 0.1 s vs modes (seed Fig. 5.10b)"),
        "modes",
        "CPU [s]",
        per_config(&|r| r.cpu_thread),
    )?;
    let pick = |modes: &[usize], configs: &[&str], f: &dyn Fn(&Run) -> &[(f64, f64)], s: f64| {
        runs.iter()
            .filter(|(c, n, _)| configs.contains(c) && modes.contains(n))
            .map(|(c, n, r)| line(format!("{c}, {n} modes"), f(r), s))
            .collect::<Vec<_>>()
    };
    let all = ["S1", "S2", "S3", "S4"];
    write(
        out,
        "B_configs_y",
        &format!("{title}: height of the mass (seed Fig. 5.9)"),
        "t [s]",
        "y [mm]",
        pick(&[20, 100], &all, &|r| &r.y, 1e3),
    )?;
    write(
        out,
        "B_configs_v",
        &format!("{title}: velocity of the mass (seed Fig. 5.9)"),
        "t [s]",
        "v_y [m/s]",
        pick(&[20, 100], &all, &|r| &r.v_y, 1.0),
    )?;
    write(
        out,
        "B_modes_v",
        &format!("{title}: S1, velocity of the mass vs modes (seed Fig. 5.11)"),
        "t [s]",
        "v_y [m/s]",
        pick(&[10, 20, 40, 100], &["S1"], &|r| &r.v_y, 1.0),
    )?;
    Ok(())
}

/// Figs. 5.6/5.7: height and velocity of the mass with the 2D neutral contour and the
/// FlexibleBand, setups A and B (`runs`: label and run).
pub fn contour_figures(out: &Path, runs: &[(String, Run)]) -> Result<()> {
    let title = "Point mass on beam, S2, C_R = 0, 20 modes: 2D contour vs FlexibleBand";
    write(
        out,
        "contour_y",
        &format!("{title} (seed Figs. 5.6, 5.7)"),
        "t [s]",
        "y [mm]",
        runs.iter()
            .map(|(l, r)| line(l.clone(), &r.y, 1e3))
            .collect(),
    )?;
    write(
        out,
        "contour_v",
        &format!("{title} (seed Figs. 5.6, 5.7)"),
        "t [s]",
        "v_y [m/s]",
        runs.iter()
            .map(|(l, r)| line(l.clone(), &r.v_y, 1.0))
            .collect(),
    )
}

/// Fig. 5.8 (setup B) and Fig. 5.12 (setup A): velocity of the mass for C_R = 0, 0.7, 1
/// (`runs`: label and run).
pub fn restitution_figure(
    out: &Path,
    name: &str,
    title: &str,
    runs: &[(String, Run)],
) -> Result<()> {
    write(
        out,
        name,
        title,
        "t [s]",
        "v_y [m/s]",
        runs.iter()
            .map(|(l, r)| line(l.clone(), &r.v_y, 1.0))
            .collect(),
    )
}
