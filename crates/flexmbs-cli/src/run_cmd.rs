//! `flexmbs run`, `flexmbs plot` and the multibody part of `flexmbs check`: thin wrappers around
//! `flexmbs_sim` with a progress bar, Ctrl-C handling and a summary.

use anyhow::Result;
use flexmbs_io::results::{plot_series, read_results, write_csv, RunStatus};
use flexmbs_sim::run::{run_model, Progress, RunError, RunOptions, RunSummary};
use flexmbs_sim::{CompiledModel, SolverConfig};
use indicatif::{ProgressBar, ProgressStyle};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Arc;
use std::time::Instant;

/// Exit code of an interrupted run (128 + SIGINT).
pub const EXIT_INTERRUPTED: i32 = 130;

/// Installs the handler of Ctrl-C (SIGINT) and of SIGTERM and SIGHUP (`timeout`, container stops,
/// job schedulers, a closed terminal): the first signal sets `stop` (the run finishes its step and
/// writes its results with status interrupted), the second aborts at once.
fn install_ctrl_c(stop: Arc<AtomicBool>) {
    let count = AtomicUsize::new(0);
    let res = ctrlc::set_handler(move || {
        if count.fetch_add(1, Ordering::SeqCst) == 0 {
            stop.store(true, Ordering::SeqCst);
            eprintln!("\ninterrupt: finishing the current step and writing results (interrupt again to abort)");
        } else {
            std::process::exit(EXIT_INTERRUPTED);
        }
    });
    if let Err(e) = res {
        eprintln!("warning: cannot install the Ctrl-C handler: {e}");
    }
}

/// `flexmbs run`: returns the process exit code (0 completed, 1 failed, 130 interrupted).
pub fn cmd_run(model: &Path, out: Option<PathBuf>, quiet: bool) -> Result<i32> {
    crate::file_kind::expect_model_file(model, "run", true)?;
    let cm = flexmbs_sim::load_model(model)?;
    print_warnings(&cm);
    let out = out.unwrap_or_else(|| {
        let stem = model
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "run".into());
        Path::new("out").join(stem)
    });
    let opts = RunOptions::new(&out);
    install_ctrl_c(opts.stop.clone());
    run_compiled(&cm, &opts, quiet)
}

/// Runs a compiled model with a progress bar and prints the summary; returns the exit code.
pub fn run_compiled(cm: &CompiledModel, opts: &RunOptions, quiet: bool) -> Result<i32> {
    let statics = matches!(cm.solver, SolverConfig::Statics { .. });
    if !quiet {
        eprintln!(
            "{}: {}, {}, {}; output to {}",
            cm.name,
            count(cm.bodies.len(), "body", "bodies"),
            count(cm.model.nq, "coordinate", "coordinates"),
            count(cm.model.nc, "constraint row", "constraint rows"),
            opts.out_dir.display()
        );
    }
    let bar = if quiet {
        ProgressBar::hidden()
    } else {
        ProgressBar::new(1000)
    };
    bar.set_style(
        ProgressStyle::with_template("{bar:30.cyan/blue} {msg} ETA {eta}")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    let start = Instant::now();
    let mut last = Instant::now();
    let mut on_progress = |p: &Progress| {
        if last.elapsed().as_millis() < 100 {
            return;
        }
        last = Instant::now();
        let rate = p.steps as f64 / start.elapsed().as_secs_f64().max(1e-9);
        if p.t_end > 0.0 {
            bar.set_position((1000.0 * p.t / p.t_end).clamp(0.0, 1000.0) as u64);
        }
        bar.set_message(if statics {
            format!(
                "load factor {:.3}, {} increments, {} Newton iterations",
                p.t, p.steps, p.newton_iterations
            )
        } else {
            let rejected = if p.rejected > 0 {
                format!(" ({} rejected, h = {:.3e} s)", p.rejected, p.h)
            } else {
                String::new()
            };
            format!(
                "t = {:.4e} / {:.4e} s, {} steps{rejected}, {:.0} steps/s",
                p.t, p.t_end, p.steps, rate
            )
        });
    };
    let result = run_model(cm, opts, &mut on_progress);
    bar.finish_and_clear();
    match result {
        Ok(summary) => {
            let work = match cm.solver {
                SolverConfig::Dopri5 { .. } => "stage evaluations",
                SolverConfig::Moreau { .. } => "contact-solver sweeps",
                _ => "Newton iterations",
            };
            let contacts = !cm.model.contacts.is_empty();
            print_summary(&summary, statics, work, contacts);
            for w in &summary.warnings {
                eprintln!("warning: {w}");
            }
            Ok(match summary.status {
                RunStatus::Interrupted { .. } => EXIT_INTERRUPTED,
                _ => 0,
            })
        }
        Err(e @ RunError::Solver { .. }) => {
            eprintln!("error: {e}");
            if let RunError::Solver { cause, .. } = &e {
                eprintln!("hint: {}", cause.hint(&cm.solver));
            }
            Ok(1)
        }
        Err(e) => Err(e.into()),
    }
}

/// The run's summary; `work` names what `newton_iterations` counts for the solver; with
/// `contacts` the energy balance says that it contains what the contacts dissipate (not
/// metered as work).
fn print_summary(s: &RunSummary, statics: bool, work: &str, contacts: bool) {
    if statics {
        println!(
            "statics completed: full load in {} load increments, {} Newton iterations, wall time {:.2} s",
            s.steps,
            s.newton_iterations,
            s.wall_time.as_secs_f64()
        );
        println!(
            "  constraint residual max |g| {:.3e}; one output row per increment (time column = load factor)",
            s.position_drift
        );
        println!("  {} output rows; files:", s.rows);
        for f in &s.files {
            println!("    {}", f.display());
        }
        return;
    }
    let status = match &s.status {
        RunStatus::Completed => format!("completed at t = {:.6e} s", s.t),
        RunStatus::Interrupted { t } => format!("interrupted at t = {t:.6e} s"),
        RunStatus::Failed { t, message } => format!("failed at t = {t:.6e} s: {message}"),
        RunStatus::Running => format!("running, t = {:.6e} s", s.t),
    };
    println!("run {status}");
    println!(
        "  steps {} (rejected {}), {} {}, wall time {:.2} s ({:.0} steps/s)",
        s.steps,
        s.rejected,
        work,
        s.newton_iterations,
        s.wall_time.as_secs_f64(),
        s.steps as f64 / s.wall_time.as_secs_f64().max(1e-9)
    );
    println!(
        "  energy: initial {:.6e} J, work W {:.6e} J (loads {:.6e} J, dampers {:.6e} J, drives {:.6e} J{}), largest balance error |E - W - E0| {:.3e} J{}; constraint drift: max |g| {:.3e}, max |g_dot| {:.3e}",
        s.energy_initial,
        s.external_work,
        s.work.loads,
        s.work.dampers,
        s.work.drives,
        s.work
            .stiffening
            .map_or(String::new(), |w| format!(", geometric stiffening {w:.6e} J")),
        s.energy_drift,
        if contacts {
            " (includes the energy the contacts dissipate: impacts with restitution < 1, friction, contact damping)"
        } else {
            ""
        },
        s.position_drift,
        s.velocity_drift
    );
    println!("  {} output rows; files:", s.rows);
    for f in &s.files {
        println!("    {}", f.display());
    }
}

/// `flexmbs check` of a multibody model file.
pub fn check_multibody(model: &Path) -> Result<()> {
    let cm = flexmbs_sim::load_model(model)?;
    print_warnings(&cm);
    println!(
        "{}: OK: multibody model `{}`: {}, {}, {} ({}), {}, {}, {}; solver {}",
        model.display(),
        cm.name,
        count(cm.bodies.len(), "body", "bodies"),
        count(cm.model.frames.len(), "frame", "frames"),
        count(cm.model.joints.len(), "joint", "joints"),
        count(cm.model.nc, "constraint row", "constraint rows"),
        count(cm.model.loads.len(), "load", "loads"),
        count(cm.model.nq, "coordinate", "coordinates"),
        count(cm.signals.len(), "signal", "signals"),
        describe_solver(&cm.solver)
    );
    Ok(())
}

/// Prints the model's warnings to stderr, one per line.
fn print_warnings(cm: &CompiledModel) {
    for w in &cm.warnings {
        eprintln!("warning: {w}");
    }
}

/// `n` with the singular or plural noun.
pub fn count(n: usize, one: &str, many: &str) -> String {
    format!("{n} {}", if n == 1 { one } else { many })
}

/// One line describing the solver settings, in model-file terms.
pub fn describe_solver(solver: &SolverConfig) -> String {
    match solver {
        SolverConfig::GenAlpha {
            settings,
            h,
            t_end,
            adaptive,
        } => {
            let newton = if settings.newton.modified {
                "modified Newton"
            } else {
                "full Newton"
            };
            match adaptive {
                None => format!(
                    "generalized-alpha, rho_inf {}, h {h:e} s, t_end {t_end} s, {newton}",
                    settings.rho_inf
                ),
                Some(a) => format!(
                    "generalized-alpha adaptive, rho_inf {}, h in [{:e}, {:e}] s, rtol {:e}, atol {:e}, t_end {t_end} s, {newton}",
                    settings.rho_inf, a.h_min, a.h_max, a.rtol, a.atol
                ),
            }
        }
        SolverConfig::Dopri5 { settings, t_end } => format!(
            "dopri5, rtol {:e}, atol {:e}, h_max {:e} s, t_end {t_end} s",
            settings.rtol, settings.atol, settings.h_max
        ),
        SolverConfig::Statics { settings } => format!(
            "statics, {}",
            count(settings.load_steps, "load step", "load steps")
        ),
        SolverConfig::Moreau { h, t_end, adaptive } => match adaptive {
            None => format!("moreau, h {h:e} s, t_end {t_end} s"),
            Some(a) => format!(
                "moreau adaptive, h in [{:e}, {:e}] s, rtol {:e}, atol {:e}, t_end {t_end} s",
                a.h_min, a.h_max, a.rtol, a.atol
            ),
        },
    }
}

/// `flexmbs plot`.
pub fn cmd_plot(
    results: &Path,
    series: &[String],
    output: Option<PathBuf>,
    csv: Option<PathBuf>,
    list: bool,
) -> Result<()> {
    let r = read_results(results).map_err(|e| crate::file_kind::not_a_results_file(results, &e))?;
    if list {
        for n in r.series_names() {
            println!("{n}");
        }
        return Ok(());
    }
    let names: Vec<&str> = series.iter().map(|s| s.as_str()).collect();
    if names.is_empty() && csv.is_none() {
        anyhow::bail!(
            "nothing to do: give the series to plot (e.g. `flexmbs plot {} energy/total`), or --csv FILE; `--list` lists the series",
            results.display()
        );
    }
    if let Some(c) = csv {
        write_csv(&r, &names, &c)?;
        println!("wrote {}", c.display());
    }
    if !names.is_empty() {
        let out = output.unwrap_or_else(|| PathBuf::from("plot.png"));
        plot_series(&r, &names, &out)?;
        println!("wrote {}", out.display());
    } else if output.is_some() {
        anyhow::bail!("give at least one series to plot (list them with --list)");
    }
    Ok(())
}
