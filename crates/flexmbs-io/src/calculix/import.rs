//! Importing a CalculiX model's stiffness and mass matrices: run `ccx` with
//! `*FREQUENCY, SOLVER=MATRIXSTORAGE` on the deck's model data and renumber the exported equations
//! (`node.direction` in `.dof`) into flexmbs's node-by-node DOF numbering.

use super::run::inline_includes;
use super::{read_ccx_matrices, run_ccx, CcxMatrices};
use crate::IoError;
use faer::sparse::Triplet;
use flexmbs_fe::assembly::{entries, Assembled, DofMap};
use flexmbs_fe::{Mesh, SparseMatrix};
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

static RUN: AtomicUsize = AtomicUsize::new(0);

/// The model-data part of a deck (everything before the first `*STEP`, includes inlined) followed by
/// a matrix-export step.
pub fn matrix_export_deck_text(deck: &Path) -> Result<String, IoError> {
    let text = crate::source_file::read_to_string(deck).map_err(|source| IoError::Io {
        file: deck.into(),
        source,
    })?;
    let text = inline_includes(&text, deck)?;
    let mut model = String::with_capacity(text.len() + 100);
    for line in text.lines() {
        if line.trim_start().to_ascii_uppercase().starts_with("*STEP") {
            break;
        }
        model.push_str(line);
        model.push('\n');
    }
    model.push_str("*STEP\n*FREQUENCY, SOLVER=MATRIXSTORAGE\n*END STEP\n");
    Ok(model)
}

/// Runs ccx on `deck` (model data only, with a matrix-export step) in a fresh temporary folder and
/// returns K and M renumbered for `mesh` (the same deck read by [`super::read_inp`]). DOFs removed by
/// the deck's `*BOUNDARY` stay as empty rows: their nodes must be fixed.
pub fn import_matrices(deck: &Path, mesh: &Mesh) -> Result<Assembled, IoError> {
    let text = matrix_export_deck_text(deck)?;
    let dir = std::env::temp_dir().join(format!(
        "flexmbs-ccx-{}-{}",
        std::process::id(),
        RUN.fetch_add(1, Ordering::Relaxed)
    ));
    std::fs::create_dir_all(&dir).map_err(|source| IoError::Io {
        file: dir.clone(),
        source,
    })?;
    let job_deck: PathBuf = dir.join("export.inp");
    std::fs::write(&job_deck, text).map_err(|source| IoError::Io {
        file: job_deck.clone(),
        source,
    })?;
    let run = run_ccx(&job_deck, &dir)?;
    let ccx = read_ccx_matrices(&run.job)?;
    let out = renumber(&ccx, mesh, &run.file("dof"));
    let _ = std::fs::remove_dir_all(&dir);
    out
}

/// Renumbers exported matrices into the DOF numbering of `mesh` (`DofMap::from_counts(mesh.node_dofs())`).
pub fn renumber(ccx: &CcxMatrices, mesh: &Mesh, dof_file: &Path) -> Result<Assembled, IoError> {
    let dofs = DofMap::from_counts(mesh.node_dofs());
    let index: HashMap<u64, usize> = mesh
        .node_ids
        .iter()
        .enumerate()
        .map(|(i, &id)| (id, i))
        .collect();
    let mut map = Vec::with_capacity(ccx.dofs.len());
    for (eq, &(label, dir)) in ccx.dofs.iter().enumerate() {
        let node = *index.get(&label).ok_or_else(|| IoError::Invalid {
            file: dof_file.into(),
            line: eq + 1,
            what: format!(
                "node {label} is not in the mesh (element-internal nodes such as those of C3D8I are not supported: use C3D8, C3D20, C3D20R or C3D10)"
            ),
        })?;
        let d = dofs.dof(node, usize::from(dir).saturating_sub(1)).ok_or_else(|| IoError::Invalid {
            file: dof_file.into(),
            line: eq + 1,
            what: format!("node {label} direction {dir} has no DOF in the mesh (node used by no element?)"),
        })?;
        map.push(d);
    }
    let permute = |a: &SparseMatrix| -> Result<SparseMatrix, IoError> {
        let t: Vec<_> = entries(a)
            .map(|(i, j, v)| Triplet::new(map[i], map[j], v))
            .collect();
        flexmbs_fe::assembly::sparse_from_triplets(dofs.len, &t).map_err(|e| {
            IoError::Inconsistent {
                file: dof_file.into(),
                what: e.to_string(),
            }
        })
    };
    Ok(Assembled {
        k: permute(&ccx.k)?,
        m: permute(&ccx.m)?,
        dofs,
    })
}
