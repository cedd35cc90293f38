//! Steps per second of one FFR body on the rotating-beam model, for 6 ... 100 modes: a solid
//! aluminium tube (outer radius 10 mm, wall 1 mm, L = 1 m; 99 x 1 x 20 hex8i ring sectors, 4000
//! nodes, 11 880 free DOFs, clamped at x = 0 for the modal analysis), hinged at x = 0 and driven at
//! 100 rad/s about z by a prescribed revolute joint, started in rigid spin with an initial velocity
//! 0.05 of the first two (bending) modal coordinates. Generalized-alpha rho_inf 0.9, h = 1e-4 s,
//! 2000 steps (t_end = 0.2 s).
//!
//! Run: `cargo bench -p flexmbs-validate --bench ffr_steps`. Not a test: nothing is asserted.
//! Environment:
//! - `FFR_BENCH_FD=1`: also time the finite-difference tangent (the state before the analytic one);
//! - `FFR_BENCH_EXPORT=dir`: write the 100-mode reduced data (`nodes.npy`, `masses.npy`,
//!   `modes.npy`, `kff.npy`) and the tip responses `tip_flexmbs_<n>_{full,modified}.csv` (full / modified Newton) for
//!   `benches/exudyn/ffr_exudyn.py`;
//! - `FFR_BENCH_IMPORT=dir`: skip the FE model and the modal analysis and use the reduced data an
//!   earlier `FFR_BENCH_EXPORT=dir` run wrote (the first n modes and the leading n x n block of
//!   k_ff): seconds instead of minutes under valgrind;
//! - `FFR_BENCH_MODES=6,12`: restrict the mode counts;
//! - `FFR_BENCH_NEWTON=modified` (or `full`): run only that Newton variant (for profiling with
//!   `valgrind --tool=callgrind --collect-atstart=no --toggle-collect='*GenAlpha*integrate*'`);
//! - `FFR_BENCH_LOAD=1`: add a follower tip force (1 N along the tip node frame's y axis) at the
//!   tip node (x = L, y = R, z = 0): the cost of one load's tangent;
//! - `FFR_BENCH_STEPS=200`: fewer steps (e.g. under callgrind; default 2000).

use flexmbs_core::ffr::{FfrBody, FfrElement, FfrInvariants, RotationParam};
use flexmbs_core::integrator::{GenAlpha, GenAlphaSettings, NewtonSettings};
use flexmbs_core::{
    Joint, Load, LoadCoordinates, ModelSpec, PrescribedMotion, TimeFunction, Workspace,
};
use flexmbs_fe::constraint::BoundaryConditions;
use flexmbs_fe::eigen::EigenOptions;
use flexmbs_fe::element::MassKind;
use flexmbs_fe::reduction::{modal_analysis, reduce_modal, Provenance, ReducedBody};
use flexmbs_fe::system::FeSystem;
use flexmbs_fe::{Material, UnitSystem};
use nalgebra::{Matrix3, Vector3};
use std::io::Write;
use std::time::Instant;

const H: f64 = 1e-4;
const STEPS: usize = 2000;
const OMEGA: f64 = 100.0;
const QF_DOT0: f64 = 0.05;

/// Writes a little-endian f64 array as a NumPy `.npy` file (C order).
fn write_npy(path: &std::path::Path, shape: &[usize], data: &[f64]) {
    let shape_s = match shape {
        [n] => format!("({n},)"),
        _ => format!(
            "({})",
            shape
                .iter()
                .map(|s| s.to_string())
                .collect::<Vec<_>>()
                .join(", ")
        ),
    };
    let mut header = format!("{{'descr': '<f8', 'fortran_order': False, 'shape': {shape_s}, }}");
    while (10 + header.len() + 1) % 64 != 0 {
        header.push(' ');
    }
    header.push('\n');
    let mut f = std::fs::File::create(path).expect("npy file");
    f.write_all(b"\x93NUMPY\x01\x00").unwrap();
    f.write_all(&(header.len() as u16).to_le_bytes()).unwrap();
    f.write_all(header.as_bytes()).unwrap();
    for x in data {
        f.write_all(&x.to_le_bytes()).unwrap();
    }
}

fn export(dir: &std::path::Path, body: &ReducedBody) {
    std::fs::create_dir_all(dir).expect("export dir");
    let n = body.nodes.len();
    let nf = body.modes_t.ncols();
    let nodes: Vec<f64> = body.nodes.iter().flatten().copied().collect();
    write_npy(&dir.join("nodes.npy"), &[n, 3], &nodes);
    write_npy(
        &dir.join("masses.npy"),
        &[n],
        body.node_masses.as_ref().expect("lumped masses"),
    );
    let modes: Vec<f64> = (0..3 * n)
        .flat_map(|i| (0..nf).map(move |j| body.modes_t[(i, j)]))
        .collect();
    write_npy(&dir.join("modes.npy"), &[3 * n, nf], &modes);
    let k: Vec<f64> = (0..nf)
        .flat_map(|i| (0..nf).map(move |j| body.k_red[(i, j)]))
        .collect();
    write_npy(&dir.join("kff.npy"), &[nf, nf], &k);
}

/// The tip node: its index, undeformed position, the y row of its modes, and whether a tip force
/// is applied there.
#[derive(Clone, Copy)]
struct Tip<'a> {
    node: usize,
    position: Vector3<f64>,
    phi: &'a [f64],
    load: bool,
}

/// One timed run; returns (wall seconds of the stepping, mean Newton iterations per step, tip
/// deflection series every 10 steps).
fn run(
    ffr: FfrBody,
    tip: Tip<'_>,
    fd: bool,
    modified: bool,
    steps: usize,
) -> (f64, f64, Vec<(f64, f64)>) {
    let nf = ffr.nf();
    let element = if fd {
        FfrElement::new(ffr).with_finite_difference_tangent()
    } else {
        FfrElement::new(ffr)
    };
    let mut spec = ModelSpec::new();
    let b = spec.add_body("tube", element);
    let g = spec.add_ground_frame("hinge", Vector3::zeros(), Matrix3::identity());
    let f = spec.add_frame("hinge", b, Vector3::zeros(), Matrix3::identity());
    if tip.load {
        let tf = spec.add_node_frame("tip", b, tip.node, tip.position);
        spec.add_load(Load::Force {
            frame: tf,
            vector: Vector3::new(0.0, 1.0, 0.0),
            time: TimeFunction::Constant(1.0),
            coordinates: LoadCoordinates::Frame,
        });
    }
    spec.add_joint(Joint::revolute("drive", g, f).with_prescribed(
        PrescribedMotion::RevoluteRate {
            initial_angle: 0.0,
            rate: TimeFunction::Constant(OMEGA),
        },
    ));
    let model = spec.compile().expect("model");
    let mut s = model.initial_state();
    model.set_body_velocity(&mut s, b, Vector3::zeros(), Vector3::new(0.0, 0.0, OMEGA));
    for u in &mut model.body_u_mut(b, &mut s.u)[6..6 + 2.min(nf)] {
        *u = QF_DOT0;
    }
    let mut ws = Workspace::new(&model);
    let settings = GenAlphaSettings {
        rho_inf: 0.9,
        newton: NewtonSettings {
            modified,
            ..NewtonSettings::default()
        },
    };
    // energies are not evaluated per step (as in the `flexmbs run` driver, which computes them at
    // output rows only; Exudyn does not compute them either)
    let ga = GenAlpha::new(settings)
        .expect("integrator")
        .with_step_energy(false);
    ga.initialize(&model, &mut s, &mut ws).expect("init");
    let mut series = Vec::with_capacity(steps / 10 + 1);
    let (mut k, mut iterations) = (0usize, 0usize);
    let t0 = Instant::now();
    ga.integrate(&model, &mut s, &mut ws, H, steps as f64 * H, |st, stats| {
        k += 1;
        iterations += stats.iterations;
        if k.is_multiple_of(10) {
            let qf = &model.body_q(b, &st.q)[6..];
            series.push((st.t, tip.phi.iter().zip(qf).map(|(p, q)| p * q).sum()));
        }
    })
    .expect("run");
    let wall = t0.elapsed().as_secs_f64();
    (wall, iterations as f64 / k.max(1) as f64, series)
}

/// Reads a little-endian f64 `.npy` file written by [`write_npy`]: (shape, data in C order).
fn read_npy(path: &std::path::Path) -> (Vec<usize>, Vec<f64>) {
    let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let hlen = u16::from_le_bytes([bytes[8], bytes[9]]) as usize;
    let header = std::str::from_utf8(&bytes[10..10 + hlen]).expect("npy header");
    assert!(
        header.contains("'<f8'") && header.contains("False"),
        "{header}"
    );
    let shape_s = &header[header.find("'shape': (").expect("shape") + 10..];
    let shape: Vec<usize> = shape_s[..shape_s.find(')').expect("shape end")]
        .split(',')
        .filter_map(|x| x.trim().parse().ok())
        .collect();
    let data = bytes[10 + hlen..]
        .chunks_exact(8)
        .map(|c| f64::from_le_bytes(c.try_into().expect("8 bytes")))
        .collect();
    (shape, data)
}

/// Index of the tip node (x = L, y = R, z = 0).
fn tip_node(nodes: &[[f64; 3]]) -> usize {
    let d = |x: &[f64; 3]| (x[0] - 1.0).powi(2) + (x[1] - 0.01).powi(2) + x[2].powi(2);
    (0..nodes.len())
        .min_by(|&a, &b| d(&nodes[a]).total_cmp(&d(&nodes[b])))
        .expect("nodes")
}

/// The tube's FE model and its 100 clamped modes.
struct FeModel {
    mesh: flexmbs_fe::mesh::Mesh,
    sys: FeSystem,
    modal: flexmbs_fe::reduction::ModalResult,
}

/// Where the reduced bodies come from: the FE model, or data exported by an earlier run.
enum Source {
    Fe(Box<FeModel>),
    Imported {
        nodes: Vec<[f64; 3]>,
        masses: Vec<f64>,
        /// 3N x 100, C order.
        modes: (usize, Vec<f64>),
        /// 100 x 100, C order.
        kff: (usize, Vec<f64>),
    },
}

impl Source {
    fn import(dir: &std::path::Path) -> Self {
        let (_, n) = read_npy(&dir.join("nodes.npy"));
        let (_, masses) = read_npy(&dir.join("masses.npy"));
        let (ms, modes) = read_npy(&dir.join("modes.npy"));
        let (ks, kff) = read_npy(&dir.join("kff.npy"));
        Source::Imported {
            nodes: n.chunks_exact(3).map(|x| [x[0], x[1], x[2]]).collect(),
            masses,
            modes: (ms[1], modes),
            kff: (ks[1], kff),
        }
    }

    /// FFR body with `n` modes, the tip node, its position and the tip y row of its modes.
    fn body(&self, n: usize) -> (FfrBody, usize, Vector3<f64>, Vec<f64>) {
        match self {
            Source::Fe(fe) => {
                let body = reduce_modal(
                    &fe.mesh,
                    &fe.sys,
                    &fe.modal,
                    n,
                    "tube",
                    Provenance::default(),
                )
                .expect("reduce");
                let tip = tip_node(&body.nodes);
                let phi = (0..n).map(|a| body.modes_t[(3 * tip + 1, a)]).collect();
                let ffr = FfrBody::from_reduced(&body, RotationParam::Cardan).expect("ffr");
                (ffr, tip, Vector3::from(body.nodes[tip]), phi)
            }
            Source::Imported {
                nodes,
                masses,
                modes,
                kff,
            } => {
                let modes_t =
                    faer::Mat::from_fn(3 * nodes.len(), n, |i, j| modes.1[i * modes.0 + j]);
                let k = faer::Mat::from_fn(n, n, |i, j| kff.1[i * kff.0 + j]);
                let inv = FfrInvariants::from_lumped(nodes, masses, modes_t.as_ref()).expect("inv");
                let tip = tip_node(nodes);
                let phi = (0..n).map(|a| modes_t[(3 * tip + 1, a)]).collect();
                let ffr = FfrBody::new(
                    inv,
                    RotationParam::Cardan,
                    nodes,
                    modes_t.as_ref(),
                    None,
                    k.as_ref(),
                )
                .expect("ffr");
                (ffr, tip, Vector3::from(nodes[tip]), phi)
            }
        }
    }
}

/// Meshes the tube and computes its first 100 clamped modes; returns the source and the times
/// (mesh + assembly, modal analysis).
fn fe_source() -> (Source, f64, f64) {
    let start = Instant::now();
    let material = Material {
        e: 70e9,
        nu: 0.3,
        rho: 2700.0,
    };
    let mesh = flexmbs_fe::mesh::tube::tube_mesh(
        1.0,
        0.01,
        0.009,
        [99, 1, 20],
        flexmbs_fe::ElementKind::Hex8I,
        material,
        UnitSystem::Si,
    )
    .expect("mesh");
    let bc = BoundaryConditions {
        fixed: mesh.node_set("xmin").expect("set").to_vec(),
        rigid: vec![],
    };
    let sys = FeSystem::assemble(&mesh, &bc, MassKind::Lumped, &mut |_, _| {}).expect("assembly");
    let t_mesh = start.elapsed().as_secs_f64();
    // clamped model: K is positive definite, so the shift 0 lies below the spectrum (the automatic
    // negative shift is far from it and converges slowly for the many double tube modes); the
    // default residual tolerance 1e-9 is not reached for all 100 modes within the iteration
    // limit (stalls near 5e-8), hence 1e-6
    let opts = EigenOptions {
        shift: Some(0.0),
        tol: 1e-6,
        ..EigenOptions::default()
    };
    let modal = modal_analysis(&sys, 100, &opts, &mut |_| {}).expect("modes");
    let t_modal = start.elapsed().as_secs_f64() - t_mesh;
    println!(
        "FE model: {} nodes, {} free DOFs; mesh + assembly {t_mesh:.2} s, modal analysis (100 modes) {t_modal:.2} s",
        mesh.num_nodes(),
        sys.len(),
    );
    (
        Source::Fe(Box::new(FeModel { mesh, sys, modal })),
        t_mesh,
        t_modal,
    )
}

fn main() {
    let export_dir = std::env::var_os("FFR_BENCH_EXPORT").map(std::path::PathBuf::from);
    let (source, t_mesh, t_modal) = match std::env::var_os("FFR_BENCH_IMPORT") {
        Some(dir) => (Source::import(std::path::Path::new(&dir)), 0.0, 0.0),
        None => fe_source(),
    };
    let with_fd = std::env::var("FFR_BENCH_FD").is_ok_and(|v| v == "1");
    let with_load = std::env::var("FFR_BENCH_LOAD").is_ok_and(|v| v == "1");
    let counts: Vec<usize> = std::env::var("FFR_BENCH_MODES")
        .map(|v| v.split(',').filter_map(|x| x.trim().parse().ok()).collect())
        .unwrap_or_else(|_| vec![6, 12, 24, 50, 100]);
    if let (Some(dir), Source::Fe(fe)) = (&export_dir, &source) {
        let body = reduce_modal(
            &fe.mesh,
            &fe.sys,
            &fe.modal,
            100,
            "tube",
            Provenance::default(),
        )
        .expect("reduce");
        export(dir, &body);
        println!(
            "exported reduced data to {} (tip node {})",
            dir.display(),
            tip_node(&body.nodes)
        );
    }
    println!(
        "| modes | tangent | Newton | steps | iterations/step | wall [s] | steps/s | us/step | whole process [s] | tip y at 0.2 s [mm] |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|");
    for n in counts {
        let t_set = Instant::now();
        let (ffr, tip_index, tip_position, phi_tip) = source.body(n);
        let tip = Tip {
            node: tip_index,
            position: tip_position,
            phi: &phi_tip,
            load: with_load,
        };
        let setup = t_set.elapsed().as_secs_f64();
        let steps = std::env::var("FFR_BENCH_STEPS")
            .ok()
            .and_then(|v| v.parse().ok())
            .unwrap_or(STEPS);
        let mut variants = vec![(false, false, steps), (false, true, steps)];
        match std::env::var("FFR_BENCH_NEWTON").as_deref() {
            Ok("modified") => variants.retain(|v| v.1),
            Ok("full") => variants.retain(|v| !v.1),
            _ => {}
        }
        if with_fd {
            let fd_steps = match n {
                0..=12 => 1000,
                13..=24 => 200,
                25..=50 => 40,
                _ => 10,
            };
            variants.push((true, false, fd_steps));
        }
        for (fd, modified, steps) in variants {
            let (wall, iters, series) = run(ffr.clone(), tip, fd, modified, steps);
            let whole = t_mesh + t_modal + setup + wall * STEPS as f64 / steps as f64;
            let last = series.last().map_or(f64::NAN, |x| x.1);
            println!(
                "| {n} | {} | {} | {steps} | {iters:.2} | {wall:.3} | {:.0} | {:.1} | {whole:.2} | {} |",
                if fd { "finite differences" } else { "analytic" },
                if modified { "modified" } else { "full" },
                steps as f64 / wall,
                1e6 * wall / steps as f64,
                if steps == STEPS {
                    format!("{:.6}", 1e3 * last)
                } else {
                    "-".into()
                },
            );
            if let (Some(dir), false) = (&export_dir, fd) {
                let kind = if modified { "modified" } else { "full" };
                let mut f = std::fs::File::create(dir.join(format!("tip_flexmbs_{n}_{kind}.csv")))
                    .expect("csv");
                writeln!(f, "t,tip_y").unwrap();
                for (t, y) in &series {
                    writeln!(f, "{t:.6},{y:.12e}").unwrap();
                }
            }
        }
    }
}
