//! `flexmbs`: the command-line front end. Thin by design: it parses arguments, shows progress and
//! prints tables; all work is done by the library crates.

mod file_kind;
mod progress;
mod run_cmd;

use anyhow::{bail, Context, Result};
use clap::{Parser, Subcommand};
use flexmbs_fe::reduction::ReducedBody;
use flexmbs_io::body_file::BodyFile;
use flexmbs_io::model::read_fe_model;
use flexmbs_io::model_check::FeModelSource;
use flexmbs_reduce::pipeline::{prepare, run_modal, run_reduction, PreparedBody};
use std::path::{Path, PathBuf};

/// flexmbs: flexible multibody dynamics with FE-based flexible bodies.
#[derive(Parser)]
#[command(name = "flexmbs", version, about, long_about = None, propagate_version = true)]
struct Cli {
    /// Suppress progress bars.
    #[arg(long, short, global = true)]
    quiet: bool,
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Modal analysis of an FE body: prints the frequency table.
    Modal {
        /// Model file (TOML) describing the FE body.
        model: PathBuf,
        /// Number of elastic modes (default: `reduction.modes` of the model).
        #[arg(long, short = 'n')]
        modes: Option<usize>,
        /// Print JSON instead of a table.
        #[arg(long)]
        json: bool,
    },
    /// Reduces an FE body (modal or Craig-Bampton) and writes the reduced-body file. A body with
    /// fixed nodes also gets its six centrifugal geometric stiffness matrices (for
    /// `geometric_stiffening = true` in a multibody model).
    Reduce {
        /// Model file (TOML).
        model: PathBuf,
        /// Output reduced-body file (`.fmb.h5`).
        #[arg(long, short)]
        output: PathBuf,
        /// Do not compute and store the geometric stiffness.
        #[arg(long)]
        no_geometric: bool,
    },
    /// Writes mode shapes for ParaView: modes.vtu (every mode as a point field) and
    /// modes_animation.pvd (the first 10 modes animated).
    ExportVtk {
        /// Model file (TOML) or reduced-body file (`.h5`).
        input: PathBuf,
        /// Output folder.
        #[arg(long, short, default_value = "modes_vtk")]
        output: PathBuf,
        /// Largest displayed displacement as a fraction of the body size.
        #[arg(long, default_value_t = 0.1)]
        scale: f64,
    },
    /// Writes the body's mesh as a CalculiX deck (nodes, elements, node sets, materials).
    ExportInp {
        /// Model file (TOML).
        model: PathBuf,
        /// Output deck (`.inp`).
        #[arg(long, short)]
        output: PathBuf,
    },
    /// Checks a model file without running it: an FE body file (parses, meshes, applies boundary
    /// conditions) or a multibody model file (a file with a `[model]` table: compiles it, which
    /// also reduces its FE bodies).
    Check {
        /// Model file (TOML).
        model: PathBuf,
    },
    /// Runs a multibody model file: results.h5, ParaView animation, CSV and plots.
    /// Exit code 0 completed, 1 failed, 130 interrupted (Ctrl-C; a second Ctrl-C aborts).
    Run {
        /// Multibody model file (TOML).
        model: PathBuf,
        /// Output folder (default out/<model file stem>).
        #[arg(long, short)]
        output: Option<PathBuf>,
    },
    /// Plots series of a results file (PNG or SVG by extension) or exports them as CSV.
    Plot {
        /// Results file (results.h5).
        results: PathBuf,
        /// Series names (see --list), e.g. `tip.position.z`, `energy/total`.
        series: Vec<String>,
        /// Output image (default plot.png).
        #[arg(long, short)]
        output: Option<PathBuf>,
        /// Also write the series (or every series if none is given) as CSV.
        #[arg(long)]
        csv: Option<PathBuf>,
        /// List the series names.
        #[arg(long)]
        list: bool,
    },
    /// Runs validation cases and writes validation/<case>/result.json.
    Validate {
        /// Case name (see `--list`).
        case: Option<String>,
        /// Run all cases.
        #[arg(long)]
        all: bool,
        /// List the cases.
        #[arg(long)]
        list: bool,
        /// Folder holding validation/<case>/ (default: ./validation).
        #[arg(long, default_value = "validation")]
        dir: PathBuf,
    },
    /// The main job on embedded models: modal analysis and reduction of a steel cantilever and its
    /// time simulation as an FFR body under a tip force step (CSV, plots, reduced-body file, ParaView
    /// animations), then the flexible slider-crank multibody model and a point mass bouncing on a
    /// soft beam's NURBS face (contact on a flexible body) run end to end like `flexmbs run`
    /// (results.h5, plots, animations in <output>/slider_crank/ and <output>/point_mass_on_beam/).
    Demo {
        /// Output folder.
        #[arg(long, short, default_value = "out/demo")]
        output: PathBuf,
    },
}

fn main() {
    restore_default_sigpipe();
    // large matrices and Lanczos blocks go back to the system when freed (peak memory)
    flexmbs_fe::memory::fix_mmap_threshold();
    let cli = Cli::parse();
    match run(cli) {
        Ok(0) => {}
        Ok(code) => std::process::exit(code),
        Err(e) => {
            eprintln!("error: {}", error_chain(&e));
            std::process::exit(1);
        }
    }
}

/// The error and its causes joined by ": ", leaving out causes whose text the message already
/// contains (our error types print their source themselves; `{:#}` would repeat it).
fn error_chain(e: &anyhow::Error) -> String {
    let mut out = e.to_string();
    for cause in e.chain().skip(1) {
        let c = cause.to_string();
        if !out.contains(&c) {
            out.push_str(": ");
            out.push_str(&c);
        }
    }
    out
}

/// Restores the default action of SIGPIPE (terminate quietly), as every Unix filter does. The Rust
/// runtime ignores SIGPIPE, so `flexmbs plot ... --list | head -1` would otherwise end in a panic
/// of `println!` on the closed pipe. Files being written are unaffected (results files are written
/// by atomic rename, so the last complete one stays readable).
fn restore_default_sigpipe() {
    #[cfg(unix)]
    // SAFETY: called first thing in `main`, before any thread exists; `signal` with `SIG_DFL`
    // only resets the disposition of one signal.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
}

/// Runs a command; returns the exit code.
fn run(cli: Cli) -> Result<i32> {
    let quiet = cli.quiet;
    match cli.command {
        Command::Run { model, output } => run_cmd::cmd_run(&model, output, quiet),
        Command::Plot {
            results,
            series,
            output,
            csv,
            list,
        } => run_cmd::cmd_plot(&results, &series, output, csv, list).map(|_| 0),
        other => run_other(other, quiet).map(|_| 0),
    }
}

fn run_other(command: Command, quiet: bool) -> Result<()> {
    match command {
        Command::Run { .. } | Command::Plot { .. } => {
            bail!("internal: `run`/`plot` are dispatched in run()")
        }
        Command::Modal { model, modes, json } => cmd_modal(&model, modes, json, quiet),
        Command::Reduce {
            model,
            output,
            no_geometric,
        } => {
            let f = reduce_model_file(&model, quiet, !no_geometric)?;
            create_parent_folder(&output)?;
            f.write(&output)
                .with_context(|| format!("writing {}", output.display()))?;
            let kg = match (&f.geometric, no_geometric) {
                (Some(g), _) => format!(
                    ", geometric stiffness of {} load patterns",
                    g.matrices.len()
                ),
                (None, true) => String::new(),
                (None, false) => ", no geometric stiffness (no fixed nodes)".into(),
            };
            let rot = if f.rotary_inertia.is_some() {
                ", beam node rotary inertias"
            } else {
                ""
            };
            let stress = if f.stress.is_some() {
                ", modal stress fields"
            } else {
                ""
            };
            println!(
                "wrote {} ({} nodes, {} modes{kg}{rot}{stress})",
                output.display(),
                f.body.num_nodes(),
                f.body.num_modes()
            );
            Ok(())
        }
        Command::ExportVtk {
            input,
            output,
            scale,
        } => {
            let body = if input.extension().is_some_and(|e| e == "toml") {
                reduce_model(&input, quiet)?
            } else {
                flexmbs_io::body_file::read_body(&input)
                    .with_context(|| format!("reading {}", input.display()))?
            };
            let files = flexmbs_io::vtk::write_mode_shapes(&output, &body, scale)?;
            println!(
                "wrote {} files to {} (open the .pvd in ParaView)",
                files.len(),
                output.display()
            );
            Ok(())
        }
        Command::ExportInp { model, output } => {
            let src = FeModelSource::read(&model)?;
            let base = model.parent().unwrap_or(Path::new("."));
            let mesh = flexmbs_reduce::pipeline::build_mesh(&src.model.body, base)
                .map_err(|e| src.locate(e))?;
            let text = flexmbs_io::inp_writer::mesh_to_inp(&mesh).map_err(anyhow::Error::msg)?;
            if let Some(kind) = flexmbs_io::output_safety::unsafe_target_kind(&output) {
                bail!(
                    "{} is {kind}, not a regular file: refusing to write the deck there",
                    output.display()
                );
            }
            create_parent_folder(&output)?;
            std::fs::write(&output, text)
                .with_context(|| format!("writing {}", output.display()))?;
            println!(
                "wrote {} ({} nodes, {} elements)",
                output.display(),
                mesh.num_nodes(),
                mesh.elements.len()
            );
            Ok(())
        }
        Command::Check { model } => {
            file_kind::expect_model_file(&model, "check", false)?;
            let text = flexmbs_io::source_file::read_to_string(&model)
                .with_context(|| format!("reading {}", model.display()))?;
            if flexmbs_sim::is_multibody_model(&text) {
                return run_cmd::check_multibody(&model);
            }
            let (body, _) = load(&model, quiet)?;
            println!(
                "{}: OK: {} nodes, {} elements, {} independent DOFs, {} fixed nodes, {} rigid interfaces",
                model.display(),
                body.mesh.num_nodes(),
                body.mesh.elements.len(),
                body.system.len(),
                body.bc.fixed.len(),
                body.bc.rigid.len()
            );
            Ok(())
        }
        Command::Validate {
            case,
            all,
            list,
            dir,
        } => {
            let cases = flexmbs_validate::cases();
            if list {
                for c in &cases {
                    println!("{:28} {}", c.name, c.description);
                }
                return Ok(());
            }
            let selected: Vec<_> = match (case, all) {
                (Some(name), false) => {
                    let c = cases.into_iter().find(|c| c.name == name);
                    vec![c.with_context(|| format!("no validation case '{name}' (try --list)"))?]
                }
                (None, true) => cases,
                _ => bail!("give a case name or --all (list them with --list)"),
            };
            let mut failed = Vec::new();
            let mut known = Vec::new();
            for c in selected {
                let out = dir.join(c.name);
                std::fs::create_dir_all(&out)?;
                eprintln!("validation case {} ...", c.name);
                let r =
                    (c.run)(&out, quiet).with_context(|| format!("validation case {}", c.name))?;
                r.write(&out.join("result.json"))?;
                println!("{}", r.summary());
                let unexpected = r.unexpected_failures();
                if !unexpected.is_empty() {
                    failed.push(format!("{} ({})", c.name, unexpected.join(", ")));
                } else if !r.pass {
                    known.push(format!("{} ({})", c.name, r.failed_checks.join(", ")));
                }
            }
            if !known.is_empty() {
                println!(
                    "known disagreements with the reference (reported as FAIL; the case README has the analysis): {}",
                    known.join(", ")
                );
            }
            if !failed.is_empty() {
                bail!("validation failed: {}", failed.join(", "));
            }
            Ok(())
        }
        Command::Demo { output } => demo::run(&output, quiet),
    }
}

mod demo;
mod demo_sim;

/// Reads an FE body file and prepares the body; errors name the file, line and key path.
fn load(model: &Path, quiet: bool) -> Result<(PreparedBody, FeModelSource)> {
    let src = FeModelSource::read(model)?;
    let base = model.parent().unwrap_or(Path::new("."));
    let mut p = progress::Progress::new(quiet);
    let body = prepare(&src.model.body, base, &mut |s| p.stage(s)).map_err(|e| src.locate(e));
    p.finish();
    Ok((body?, src))
}

/// Creates the folder of the output file `path` if it does not exist (`reduce -o out/arm.fmb.h5`
/// into a new folder).
fn create_parent_folder(path: &Path) -> Result<()> {
    match path.parent() {
        Some(dir) if !dir.as_os_str().is_empty() && !dir.exists() => std::fs::create_dir_all(dir)
            .with_context(|| format!("creating the output folder {}", dir.display())),
        _ => Ok(()),
    }
}

fn reduce_model(model: &Path, quiet: bool) -> Result<ReducedBody> {
    reduce_model_file(model, quiet, false).map(|f| f.body)
}

/// The reduced body of an FE model file and, if `geometric` and the body has fixed nodes, its
/// centrifugal geometric stiffness (`flexmbs_reduce::geometric`, as a multibody model computes it
/// from the FE model), and for a beam mesh its lumped node rotary inertias
/// (`flexmbs_reduce::full_mass::beam_node_rotary_inertias`, as a multibody model computes them),
/// and its modal stress fields (`flexmbs_reduce::stress`). Seed folders have no FE model and get
/// none of these.
fn reduce_model_file(model: &Path, quiet: bool, geometric: bool) -> Result<BodyFile> {
    let spec = read_fe_model(model)?.body;
    let base = model.parent().unwrap_or(Path::new("."));
    if let flexmbs_io::model::MeshSpec::Seed { dir } = &spec.mesh {
        let dir = flexmbs_reduce::pipeline::resolve(base, dir);
        let body = flexmbs_io::seed_body::read_seed_body(&dir, &spec.name, spec.units)?;
        return Ok(BodyFile::plain(body));
    }
    let src = FeModelSource::read(model)?;
    let mut p = progress::Progress::new(quiet);
    let prepared =
        flexmbs_reduce::body_file::prepare_for_body_file(&src.model.body, base, &mut |s| {
            p.stage(s)
        })
        .map_err(|e| src.locate(e));
    let (prepared, full_mass) = match prepared {
        Ok(x) => x,
        Err(e) => {
            p.finish();
            return Err(e.into());
        }
    };
    let spec = &src.model.body;
    let r = run_reduction(spec, &prepared, &mut |s| p.stage(s)).map_err(|e| src.locate(e));
    let body = match r {
        Ok(b) => b,
        Err(e) => {
            p.finish();
            return Err(e.into());
        }
    };
    let built = flexmbs_reduce::body_file::body_file_of(
        spec,
        &prepared,
        full_mass.as_ref(),
        body,
        geometric,
        &mut |s| p.stage(s),
    );
    p.finish();
    let (file, no_stress) = built?;
    // a body whose elements cannot give stresses is still written, without them
    if let Some(e) = no_stress {
        eprintln!(
            "warning: no modal stress fields written (no stress output from this file): {}",
            src.locate(e)
        );
    }
    Ok(file)
}

fn cmd_modal(model: &Path, modes: Option<usize>, json: bool, quiet: bool) -> Result<()> {
    let (body, src) = load(model, quiet)?;
    let spec = &src.model.body;
    let n = modes.unwrap_or(spec.reduction.modes);
    let mut p = progress::Progress::new(quiet);
    let modal = run_modal(spec, &body, n, &mut |s| p.stage(s)).map_err(|e| src.locate(e));
    p.finish();
    let modal = modal?;
    let rows = flexmbs_reduce::report::modal_rows(&modal);
    if json {
        println!(
            "{}",
            serde_json::to_string_pretty(&flexmbs_reduce::report::modal_json(
                &spec.name, &body, &modal
            ))?
        );
    } else {
        println!(
            "{}: {} nodes, {} elements, {} independent DOFs, {} rigid-body modes",
            spec.name,
            body.mesh.num_nodes(),
            body.mesh.elements.len(),
            body.system.len(),
            modal.n_rigid
        );
        print!("{}", flexmbs_reduce::report::modal_table(&rows));
    }
    Ok(())
}
