//! The CalculiX-export variant of `complex_beam_frequencies`: the built-in complex-beam mesh is
//! written as a CalculiX deck, `ccx` exports its stiffness and (consistent) mass matrices
//! (`matrices = "ccx"` in the FE model file), flexmbs reduces them to 30 constrained modes and
//! builds the FFR body with consistent-mass invariants from the full ccx mass matrix. The
//! reference is CalculiX's own `*FREQUENCY` analysis of the same deck (`.dat` eigenvalue table).

use crate::complex_beam_frequencies::MODEL;
use anyhow::{bail, Context, Result};
use flexmbs_core::ffr::{
    consistent_mass_to_si, reduced_body_to_si, FfrBody, FfrInvariants, RotationParam,
};
use flexmbs_fe::reduction::ReducedBody;
use flexmbs_fe::SparseMatrix;
use flexmbs_io::calculix::{read_dat_frequencies, run_ccx};
use flexmbs_io::model::parse_fe_model;
use flexmbs_reduce::full_mass::reduce_with_mass;
use flexmbs_reduce::pipeline::build_mesh;
use std::path::{Path, PathBuf};

/// Deck of the mesh written by flexmbs (nodes, elements, node sets, material).
pub const MESH_DECK: &str = "complex_beam_mesh.inp";

/// FE model file of the CalculiX variant: the mesh deck with K and M from `ccx`, clamped on the
/// node set `XMIN` (written by `inp_writer` from the mesh's `xmin`), 30 modes.
pub const CCX_MODEL: &str = r#"
[body]
name = "complex_beam_ccx"
units = "SI(mm)"

[body.mesh]
type = "calculix"
deck = "complex_beam_mesh.inp"
matrices = "ccx"

[body.boundary]
fixed = ["XMIN"]

[body.reduction]
method = "modal"
modes = 30
mass = "consistent"
"#;

/// The CalculiX `*FREQUENCY` deck of the same mesh, clamped on `XMIN`, `n` modes.
pub fn frequency_deck(n: usize) -> String {
    format!(
        "** flexmbs: complex beam, modal analysis by CalculiX\n*INCLUDE, INPUT={MESH_DECK}\n*BOUNDARY\nXMIN, 1, 3\n*STEP\n*FREQUENCY\n{n}\n*END STEP\n"
    )
}

/// The CalculiX variant's data, in SI.
#[derive(Debug, Clone)]
pub struct CcxBody {
    /// Reduced body (30 modes) of the ccx matrices, in SI.
    pub body: ReducedBody,
    /// Full ccx mass matrix over the translations of all nodes, in SI (kg).
    pub mass: SparseMatrix,
    /// Frequencies [Hz] of CalculiX's `*FREQUENCY` run (`.dat`, 7 significant digits).
    pub dat_hz: Vec<f64>,
    /// Largest deviation of the ccx mass matrix from block isotropy (`M_ij = m_ij I_3`),
    /// relative to its largest entry.
    pub isotropy_deviation: f64,
}

/// A fresh temporary work folder, removed on drop.
struct WorkDir(PathBuf);

impl Drop for WorkDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// Writes the built-in mesh as a deck, imports K and M through `ccx` (model-file route), reduces
/// to 30 modes and runs CalculiX's modal analysis of the same deck (`n_dat` modes).
/// `log` receives stage messages.
pub fn ccx_body(n_dat: usize, log: &mut dyn FnMut(&str)) -> Result<CcxBody> {
    let work = WorkDir(std::env::temp_dir().join(format!(
        "flexmbs-complex-beam-ccx-{}-{:?}",
        std::process::id(),
        std::thread::current().id()
    )));
    let dir = &work.0;
    std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    let spec = parse_fe_model(MODEL, Path::new("examples/complex_beam.toml"))?.body;
    let mesh = build_mesh(&spec, Path::new("."))?;
    let deck = flexmbs_io::inp_writer::mesh_to_inp(&mesh).map_err(anyhow::Error::msg)?;
    std::fs::write(dir.join(MESH_DECK), deck)?;
    log(&format!(
        "wrote the built-in mesh as {MESH_DECK} ({} nodes)",
        mesh.num_nodes()
    ));
    let ccx_spec = parse_fe_model(CCX_MODEL, &dir.join("complex_beam_ccx.toml"))?.body;
    let r = reduce_with_mass(&ccx_spec, dir, &mut |_| {}).context("ccx matrix import")?;
    log(&format!(
        "ccx matrices imported and reduced ({} modes)",
        r.body.num_modes()
    ));
    let isotropy_deviation = isotropy_deviation(&r.mass);
    let freq_deck = dir.join("complex_beam_freq.inp");
    std::fs::write(&freq_deck, frequency_deck(n_dat))?;
    let run = run_ccx(&freq_deck, dir).context("ccx *FREQUENCY run")?;
    let dat_hz: Vec<f64> = read_dat_frequencies(&run.file("dat"))?
        .iter()
        .map(|m| m.frequency_hz)
        .collect();
    if dat_hz.len() < n_dat {
        bail!(
            "ccx printed {} frequencies, {n_dat} requested",
            dat_hz.len()
        );
    }
    log("ccx *FREQUENCY run done");
    Ok(CcxBody {
        mass: consistent_mass_to_si(&r.mass, r.body.units),
        body: reduced_body_to_si(&r.body),
        dat_hz,
        isotropy_deviation,
    })
}

/// Largest deviation of `m` (3N x 3N, node order) from block isotropy: the larger of the
/// direction-coupling entries and the spread of the three diagonal-direction entries of each node
/// block, relative to the largest entry.
pub fn isotropy_deviation(m: &SparseMatrix) -> f64 {
    use std::collections::HashMap;
    let mut blocks: HashMap<(usize, usize), [f64; 3]> = HashMap::new();
    let (mut max_abs, mut dev) = (0.0f64, 0.0f64);
    let sym = m.symbolic();
    for c in 0..m.ncols() {
        for idx in sym.col_range(c) {
            let (r, v) = (sym.row_idx()[idx], m.val()[idx]);
            max_abs = max_abs.max(v.abs());
            if r % 3 == c % 3 {
                blocks.entry((r / 3, c / 3)).or_insert([0.0; 3])[r % 3] += v;
            } else {
                dev = dev.max(v.abs());
            }
        }
    }
    for d in blocks.values() {
        let mean = (d[0] + d[1] + d[2]) / 3.0;
        for x in d {
            dev = dev.max((x - mean).abs());
        }
    }
    dev / max_abs
}

/// The FFR body of the CalculiX variant (consistent-mass invariants, Cardan angles) and the
/// largest deviation of its `m_ff` from the FE projection `Phi^T M Phi` (`m_red`).
pub fn ffr_body(c: &CcxBody) -> Result<(FfrBody, f64)> {
    let ffr = FfrBody::from_reduced_consistent(&c.body, &c.mass, RotationParam::Cardan)?;
    let inv: &FfrInvariants = &ffr.invariants;
    let n = c.body.num_modes();
    let mut dev = 0.0f64;
    for i in 0..n {
        for j in 0..n {
            dev = dev.max((inv.m_ff[(i, j)] - c.body.m_red[(i, j)]).abs());
        }
    }
    Ok((ffr, dev))
}
