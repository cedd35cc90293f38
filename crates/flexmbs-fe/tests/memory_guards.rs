//! Memory guards refuse, with the estimate and the memory available, instead of allocating:
//! the sparse factor (estimate from the symbolic analysis, reported before the numeric work and
//! equal to the factor then computed), the dense eigen path (above a stated size or the memory),
//! the assembly (before meshing for a structured box, before allocating in `assemble`).
//! Small limits are injected per thread (`with_memory_limit`); nothing large is allocated.

use faer::sparse::Triplet;
use flexmbs_fe::assembly::{assemble, assembly_bytes, sparse_from_triplets};
use flexmbs_fe::constraint::BoundaryConditions;
use flexmbs_fe::eigen::{lowest_modes, EigenEvent, EigenMethod, EigenOptions, SparseCholesky};
use flexmbs_fe::element::MassKind;
use flexmbs_fe::memory::{with_memory_limit, DENSE_MAX_DIM};
use flexmbs_fe::mesh::generate::box_mesh;
use flexmbs_fe::system::FeSystem;
use flexmbs_fe::{ElementKind, FeError, Material, Mesh, UnitSystem};

fn bar(n: [usize; 3]) -> Result<Mesh, FeError> {
    box_mesh(
        [1.0, 0.1, 0.1],
        n,
        ElementKind::Hex20,
        Material::steel(),
        UnitSystem::Si,
    )
}

fn clamped(mesh: &Mesh) -> FeSystem {
    let bc = BoundaryConditions {
        fixed: mesh.nodes_on_plane(0, 0.0, 1e-9),
        rigid: vec![],
    };
    FeSystem::assemble(mesh, &bc, MassKind::Lumped, &mut |_, _| {}).unwrap()
}

fn refused(e: FeError) -> (u64, u64) {
    match e {
        FeError::MemoryRefused {
            estimate,
            available,
            ..
        } => (estimate, available),
        other => panic!("expected a memory refusal, got {other}"),
    }
}

/// The factor estimate reported before the numeric work equals the factor computed (entries of
/// L) and bounds its values (8 bytes each); a limit below it refuses with both numbers.
#[test]
fn sparse_factor_is_estimated_then_refused_below_the_estimate() {
    let sys = clamped(&bar([8, 2, 2]).unwrap());
    let mut reported = None;
    let chol = SparseCholesky::factor_observed(&sys.k, &mut |nnz_l, bytes| {
        reported = Some((nnz_l, bytes))
    })
    .unwrap();
    let (nnz_l, bytes) = reported.unwrap();
    assert_eq!(nnz_l, chol.nnz_l());
    assert!(nnz_l >= sys.k.nrows() && bytes >= 8 * nnz_l as u64);
    let err = with_memory_limit(bytes - 1, || SparseCholesky::factor(&sys.k)).unwrap_err();
    let text = err.to_string();
    assert_eq!(refused(err), (bytes, bytes - 1));
    assert!(text.contains("sparse Cholesky factor") && text.contains("FLEXMBS_MEMORY_LIMIT"));
    assert!(with_memory_limit(bytes, || SparseCholesky::factor(&sys.k)).is_ok());

    // the Lanczos path reports the estimate as an event and passes the refusal on unchanged
    let opts = EigenOptions {
        n_modes: 4,
        method: EigenMethod::Lanczos,
        ..EigenOptions::default()
    };
    let mut events = Vec::new();
    let err = with_memory_limit(1000, || {
        lowest_modes(&sys.k, &sys.m, &opts, &mut |e| events.push(e))
    })
    .unwrap_err();
    refused(err);
    assert!(events
        .iter()
        .any(|e| matches!(e, EigenEvent::FactorEstimate { .. })));
}

/// The dense path: refused above DENSE_MAX_DIM whatever the memory (checked on a diagonal
/// problem, nothing dense is built), and below it when n^2 entries exceed the limit.
#[test]
fn dense_eigen_path_is_refused_above_its_size() {
    let n = DENSE_MAX_DIM + 1;
    let diag: Vec<_> = (0..n).map(|i| Triplet::new(i, i, 1.0 + i as f64)).collect();
    let k = sparse_from_triplets(n, &diag).unwrap();
    let m = sparse_from_triplets(
        n,
        &(0..n).map(|i| Triplet::new(i, i, 1.0)).collect::<Vec<_>>(),
    )
    .unwrap();
    let opts = EigenOptions {
        n_modes: 2,
        method: EigenMethod::Dense,
        ..EigenOptions::default()
    };
    let e = lowest_modes(&k, &m, &opts, &mut |_| {})
        .unwrap_err()
        .to_string();
    assert!(e.contains("limited to 20000 unknowns"), "{e}");

    let sys = clamped(&bar([4, 1, 1]).unwrap());
    let n = sys.k.nrows() as u64;
    let err = with_memory_limit(8 * n * n, || {
        lowest_modes(&sys.k, &sys.m, &opts, &mut |_| {})
    })
    .unwrap_err();
    assert_eq!(refused(err), (48 * n * n, 8 * n * n));
}

/// Assembly: a structured box is refused before meshing (estimate: 2106 matrix entries of 42
/// bytes per hex20 cell: the node-adjacency pattern, the values of K and M, marks, compacted
/// rows), and `assemble` refuses a mesh before allocating its matrices (the [4, 2, 2] hex20 box:
/// 141 nodes whose adjacency pattern has 42 741 entries, counted by hand from the grid).
#[test]
fn assembly_is_refused_before_allocation() {
    let limit = 1 << 20;
    let err = with_memory_limit(limit, || bar([20, 4, 4])).unwrap_err();
    assert_eq!(refused(err), (20 * 4 * 4 * 2106 * 42, limit));
    assert_eq!(assembly_bytes(1), 42);

    let mesh = bar([4, 2, 2]).unwrap();
    let err = with_memory_limit(100_000, || {
        assemble(&mesh, MassKind::Consistent, &[], &mut |_, _| {})
    })
    .unwrap_err();
    assert_eq!(refused(err), (42_741 * 42, 100_000));
}
