//! A seed 4-file folder as a [`ReducedBody`]: the seed's lumped masses and modes are kept, the
//! reduced matrices are `k_ff = Phi^T K Phi` and `m_ff = Phi^T diag(m) Phi`.

use crate::seed::{read_seed_dir, SeedBody};
use crate::IoError;
use flexmbs_fe::eigen::dense_generalized;
use flexmbs_fe::modes::frequencies_hz;
use flexmbs_fe::reduction::{ModeLabel, Provenance, ReducedBody, ReductionKind};
use flexmbs_fe::UnitSystem;
use std::path::Path;

/// Reads a seed folder as a reduced body named `name` in `units`.
pub fn read_seed_body(dir: &Path, name: &str, units: UnitSystem) -> Result<ReducedBody, IoError> {
    let seed = read_seed_dir(dir)?;
    seed_to_body(&seed, dir, name, units)
}

/// Converts a parsed seed body. The frequencies are those of the reduced pair (k_ff, m_ff).
pub fn seed_to_body(
    seed: &SeedBody,
    dir: &Path,
    name: &str,
    units: UnitSystem,
) -> Result<ReducedBody, IoError> {
    let k = seed.k_ff();
    let m = seed.m_ff();
    let bad = |what: String| IoError::Inconsistent {
        file: dir.into(),
        what,
    };
    let (w2, _) = dense_generalized(k.as_ref(), m.as_ref())
        .map_err(|e| bad(format!("reduced matrices: {e}")))?;
    let n = seed.num_nodes();
    let fixed_nodes = (0..n)
        .filter(|&i| {
            (0..seed.num_modes()).all(|c| (0..3).all(|d| seed.modes[(3 * i + d, c)] == 0.0))
        })
        .collect();
    let labels = (0..seed.num_modes())
        .map(|i| ModeLabel {
            index: i + 1,
            frequency_hz: f64::NAN,
            dominant: "seed mode".into(),
            effective_mass_fraction: [0.0; 3],
        })
        .collect();
    Ok(ReducedBody {
        name: name.to_string(),
        units,
        nodes: seed.u0.clone(),
        node_ids: (1..=n as u64).collect(),
        node_masses: Some(seed.masses.clone()),
        modes_t: seed.modes.clone(),
        modes_r: None,
        k_red: k,
        m_red: m,
        frequencies_hz: frequencies_hz(&w2),
        labels,
        interface_nodes: Vec::new(),
        fixed_nodes,
        kind: ReductionKind::Modal,
        cells: Vec::new(),
        provenance: Provenance {
            source: format!("seed 4-file folder {}", dir.display()),
            program: format!("flexmbs {}", env!("CARGO_PKG_VERSION")),
            notes: "k_ff = Phi^T K Phi, m_ff = Phi^T diag(m) Phi".into(),
        },
    })
}
