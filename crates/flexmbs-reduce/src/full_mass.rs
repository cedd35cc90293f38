//! A reduced body together with the full mass matrix of its FE model, for FFR bodies with
//! consistent-mass invariants (seed 000 §6.2 outlook): CalculiX exports only consistent mass
//! matrices (`reference/calculix.md`), so a body imported with `matrices = "ccx"` carries no
//! lumped node masses and needs the full mass instead.

use crate::pipeline::{prepare_keeping_mass, run_reduction, PipelineError, PreparedBody, Stage};
use faer::sparse::Triplet;
use flexmbs_fe::assembly::Assembled;
use flexmbs_fe::reduction::ReducedBody;
use flexmbs_fe::Mesh;
use flexmbs_fe::SparseMatrix;
use flexmbs_io::calculix::{matrix_export_deck_text, read_ccx_matrices, renumber, run_ccx};
use flexmbs_io::model::FeBodySpec;
use flexmbs_io::IoError;
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};

/// A reduced body and the mass matrix of its FE model over the three translations of each of the
/// body's nodes (3N x 3N, node order of `body.nodes`, the body's units; rows of nodes without
/// translational DOFs, such as rigid-interface nodes, are zero).
#[derive(Debug, Clone)]
pub struct ReducedWithMass {
    /// The reduced body (as [`run_reduction`] builds it).
    pub body: ReducedBody,
    /// Full translational mass matrix `M` (consistent for CalculiX imports and
    /// `mass = "consistent"`, diagonal for lumped built-in masses).
    pub mass: SparseMatrix,
}

/// [`crate::pipeline::prepare`] that also returns the full translational mass matrix over the
/// nodes of the constrained system (`system.map.nodes`, which are the nodes of the reduced body).
/// CalculiX decks are exported without their `*BOUNDARY` cards ([`import_free_matrices`]) so that
/// the fixed nodes keep their mass; they are fixed by flexmbs as in [`crate::pipeline::prepare`].
pub fn prepare_with_mass(
    spec: &FeBodySpec,
    base: &Path,
    progress: &mut dyn FnMut(Stage),
) -> Result<(PreparedBody, SparseMatrix), PipelineError> {
    let (body, m) = prepare_keeping_mass(spec, base, true, progress)?;
    let mass = translational_mass(&m, &body.mesh.node_dofs(), body.system.map.nodes.len())
        .map_err(|message| PipelineError::Model {
            path: "body.mesh".into(),
            message,
        })?;
    Ok((body, mass))
}

/// Builds the body of `spec` (mesh, matrices, reduction) and returns the reduced body with its
/// full translational mass matrix.
pub fn reduce_with_mass(
    spec: &FeBodySpec,
    base: &Path,
    progress: &mut dyn FnMut(Stage),
) -> Result<ReducedWithMass, PipelineError> {
    let (prepared, mass) = prepare_with_mass(spec, base, progress)?;
    let body = run_reduction(spec, &prepared, progress)?;
    Ok(ReducedWithMass { body, mass })
}

/// `deck` text with its `*BOUNDARY` blocks (keyword line and data lines) removed.
pub fn strip_boundary_cards(deck: &str) -> String {
    let mut out = String::with_capacity(deck.len());
    let mut skipping = false;
    for line in deck.lines() {
        let t = line.trim_start();
        if t.starts_with('*') && !t.starts_with("**") {
            let name: String = t[1..]
                .split(',')
                .next()
                .unwrap_or("")
                .split_whitespace()
                .collect::<Vec<_>>()
                .join(" ")
                .to_ascii_uppercase();
            skipping = name == "BOUNDARY";
        }
        if !skipping {
            out.push_str(line);
            out.push('\n');
        }
    }
    out
}

/// Like [`flexmbs_io::calculix::import_matrices`], but the exported model is free (the deck's
/// `*BOUNDARY` cards removed): K and M over all DOFs of `mesh`, including those of nodes the deck
/// fixes (`reference/calculix.md`: deleting the fixed DOFs from the free export gives the
/// constrained export bit-identically).
pub fn import_free_matrices(deck: &Path, mesh: &Mesh) -> Result<Assembled, IoError> {
    let text = strip_boundary_cards(&matrix_export_deck_text(deck)?);
    static RUN: AtomicUsize = AtomicUsize::new(0);
    let dir = std::env::temp_dir().join(format!(
        "flexmbs-ccx-free-{}-{}",
        std::process::id(),
        RUN.fetch_add(1, Ordering::Relaxed)
    ));
    std::fs::create_dir_all(&dir).map_err(|source| IoError::Io {
        file: dir.clone(),
        source,
    })?;
    let job_deck = dir.join("export.inp");
    let result = std::fs::write(&job_deck, text)
        .map_err(|source| IoError::Io {
            file: job_deck.clone(),
            source,
        })
        .and_then(|_| run_ccx(&job_deck, &dir))
        .and_then(|run| {
            let ccx = read_ccx_matrices(&run.job)?;
            renumber(&ccx, mesh, &run.file("dof"))
        });
    let _ = std::fs::remove_dir_all(&dir);
    result
}

/// The translational block of a mass matrix numbered node by node with `dofs_per_node[j]` DOFs at
/// node `j` (translations first: 3 for solid nodes, 6 for beam nodes, 0 for unused nodes), as a
/// 3N x 3N matrix over `n_nodes >= dofs_per_node.len()` nodes (nodes beyond the list get zero
/// rows). Rotational DOFs are dropped. Errors (as a message) on inconsistent sizes.
pub fn translational_mass(
    m: &SparseMatrix,
    dofs_per_node: &[usize],
    n_nodes: usize,
) -> Result<SparseMatrix, String> {
    let total: usize = dofs_per_node.iter().sum();
    if m.nrows() != total || m.ncols() != total {
        return Err(format!(
            "mass matrix is {} x {}, but the nodes have {total} DOFs",
            m.nrows(),
            m.ncols()
        ));
    }
    if n_nodes < dofs_per_node.len() {
        return Err(format!(
            "{n_nodes} body nodes for {} mesh nodes",
            dofs_per_node.len()
        ));
    }
    // equation -> translational row 3 j + d (None for rotations)
    let mut map = vec![None; total];
    let mut first = 0;
    for (j, &c) in dofs_per_node.iter().enumerate() {
        for d in 0..c.min(3) {
            map[first + d] = Some(3 * j + d);
        }
        first += c;
    }
    let sym = m.symbolic();
    let mut trip = Vec::with_capacity(m.val().len());
    for (c, tc) in map.iter().enumerate() {
        let Some(tc) = *tc else { continue };
        for idx in sym.col_range(c) {
            if let Some(tr) = map[sym.row_idx()[idx]] {
                trip.push(Triplet::new(tr, tc, m.val()[idx]));
            }
        }
    }
    SparseMatrix::try_new_from_triplets(3 * n_nodes, 3 * n_nodes, &trip)
        .map_err(|e| format!("translational mass matrix: {e:?}"))
}

/// The rotational 3 x 3 diagonal block of each node of a mass matrix numbered node by node
/// (`dofs_per_node[j]` DOFs at node `j`, rotations in DOFs 3..6 of 6-DOF nodes): the lumped node
/// rotary inertias of beam meshes (global axes = body axes), for
/// `flexmbs_core::ffr::FfrBody::set_rotary_inertia`. Nodes with fewer than 6 DOFs and nodes beyond
/// the list (up to `n_nodes`) get zero. Errors (as a message) on inconsistent sizes. Coupling
/// between translations and rotations (consistent beam masses) is not represented.
pub fn node_rotary_inertias(
    m: &SparseMatrix,
    dofs_per_node: &[usize],
    n_nodes: usize,
) -> Result<Vec<nalgebra::Matrix3<f64>>, String> {
    let total: usize = dofs_per_node.iter().sum();
    if m.nrows() != total || m.ncols() != total || n_nodes < dofs_per_node.len() {
        return Err(format!(
            "mass matrix {} x {}, {total} DOFs, {n_nodes} body nodes for {} mesh nodes",
            m.nrows(),
            m.ncols(),
            dofs_per_node.len()
        ));
    }
    // equation -> (node, rotation axis)
    let mut map = vec![None; total];
    let mut first = 0;
    for (j, &c) in dofs_per_node.iter().enumerate() {
        if c >= 6 {
            for d in 0..3 {
                map[first + 3 + d] = Some((j, d));
            }
        }
        first += c;
    }
    let mut out = vec![nalgebra::Matrix3::zeros(); n_nodes];
    for (r, c, v) in flexmbs_fe::assembly::entries(m) {
        if let (Some((i, a)), Some((j, b))) = (map[r], map[c]) {
            if i == j {
                out[i][(a, b)] += v;
            }
        }
    }
    Ok(out)
}

/// Lumped node rotary inertias of a beam mesh, in the mesh's units, one per body node
/// (`n_nodes >= mesh.num_nodes()`, extra nodes get zero): [`node_rotary_inertias`] of the **lumped** mass
/// matrix of `mesh` (torsion `rho I_p L/2`, bending `rho A L^3/78 + rho I L/2` per element end,
/// `flexmbs_fe::element::beam`), whatever mass the body was reduced with. `None` for meshes
/// without rotational DOFs (solid meshes). This is what `flexmbs reduce` stores in the
/// reduced-body file (`nodes/rotary_inertia`) and what a multibody model applies to an FE-source
/// beam body, so both give the same body. Errors as text.
pub fn beam_node_rotary_inertias(
    mesh: &Mesh,
    n_nodes: usize,
) -> Result<Option<Vec<nalgebra::Matrix3<f64>>>, String> {
    let dofs = mesh.node_dofs();
    if !dofs.iter().any(|&c| c >= 6) {
        return Ok(None);
    }
    let lumped = flexmbs_fe::assembly::assemble(
        mesh,
        flexmbs_fe::element::MassKind::Lumped,
        &[],
        &mut |_, _| {},
    )
    .map_err(|e| format!("lumped beam mass for the node rotary inertias: {e}"))?;
    node_rotary_inertias(&lumped.m, &dofs, n_nodes).map(Some)
}

/// Node rotary inertias converted from `units` to SI (`mass_to_si * length_to_si^2`).
pub fn rotary_inertias_to_si(
    inertias: &[nalgebra::Matrix3<f64>],
    units: flexmbs_fe::UnitSystem,
) -> Vec<nalgebra::Matrix3<f64>> {
    let f = units.mass_to_si() * units.length_to_si().powi(2);
    inertias.iter().map(|i| i * f).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dense(t: &SparseMatrix) -> nalgebra::DMatrix<f64> {
        let mut d = nalgebra::DMatrix::zeros(t.nrows(), t.ncols());
        for (r, c, v) in flexmbs_fe::assembly::entries(t) {
            d[(r, c)] += v;
        }
        d
    }

    /// Keeps the translational entries of a mixed 3/6-DOF matrix in node order, pads extra nodes
    /// with zero rows, rejects a wrong size.
    #[test]
    fn boundary_cards_are_stripped() {
        let deck = "*NODE\n1, 0, 0, 0\n** comment\n*Boundary\nFIX, 1, 3\n2, 1\n*MATERIAL, NAME=S\n*STEP\n*FREQUENCY, SOLVER=MATRIXSTORAGE\n";
        assert_eq!(
            strip_boundary_cards(deck),
            "*NODE\n1, 0, 0, 0\n** comment\n*MATERIAL, NAME=S\n*STEP\n*FREQUENCY, SOLVER=MATRIXSTORAGE\n"
        );
    }

    #[test]
    fn translational_block_of_mixed_dofs() {
        // node 0: 3 DOFs (eq 0..3), node 1: 6 DOFs (eq 3..9); value encodes (row, col)
        let trip: Vec<_> = (0..9)
            .flat_map(|r| (0..9).map(move |c| Triplet::new(r, c, (10 * r + c) as f64)))
            .collect();
        let m = SparseMatrix::try_new_from_triplets(9, 9, &trip).unwrap();
        let d = dense(&translational_mass(&m, &[3, 6], 3).unwrap());
        assert_eq!(d.shape(), (9, 9));
        let expected = nalgebra::DMatrix::from_fn(9, 9, |a, b| {
            if a < 6 && b < 6 {
                (10 * a + b) as f64
            } else {
                0.0
            }
        });
        assert_eq!(d, expected);
        assert!(translational_mass(&m, &[3, 3], 2).is_err());
        assert!(translational_mass(&m, &[3, 6], 1).is_err());
    }

    /// A beam mesh (6 DOFs per node): the translational block of the built-in consistent mass has
    /// the total mass rho A L in each direction (1e-12), i.e. the rotational DOFs were dropped.
    #[test]
    fn beam_translational_mass_sums_to_total_mass() {
        use flexmbs_fe::element::MassKind;
        use flexmbs_fe::mesh::generate::beam_line;
        use flexmbs_fe::mesh::{BeamSection, BeamTheory};
        let mat = flexmbs_fe::Material::new(210e9, 0.3, 7850.0).unwrap();
        let sec = BeamSection::rectangle(0.02, 0.01);
        let mesh = beam_line(
            [0.0; 3],
            [1.0, 0.0, 0.0],
            5,
            sec,
            BeamTheory::EulerBernoulli,
            [0.0, 1.0, 0.0],
            mat,
            flexmbs_fe::UnitSystem::Si,
        )
        .unwrap();
        let a = flexmbs_fe::assembly::assemble(&mesh, MassKind::Consistent, &[], &mut |_, _| {})
            .unwrap();
        let t = translational_mass(&a.m, &mesh.node_dofs(), mesh.num_nodes()).unwrap();
        let d = dense(&t);
        let mass = 7850.0 * 0.02 * 0.01;
        for dir in 0..3 {
            let s: f64 = (0..mesh.num_nodes())
                .flat_map(|i| (0..mesh.num_nodes()).map(move |j| (i, j)))
                .map(|(i, j)| d[(3 * i + dir, 3 * j + dir)])
                .sum();
            assert!((s - mass).abs() < 1e-12 * mass, "dir {dir}: {s} vs {mass}");
        }
    }
}
