//! The checksum of the text fields of a reduced-body file (format version 2): numeric datasets
//! carry Fletcher-32 checksums, but names, provenance, mode labels and load-pattern names are
//! strings, which HDF5 stores without one. The root attribute `text_sha256` is the SHA-256 (hex)
//! of these strings in a fixed order, each followed by a zero byte:
//!
//! `name`, `units`, `reduction`, `provenance@source`, `provenance@program`, `provenance@notes`,
//! every `modes/label_dominant`, every `geometric/load_pattern` (if the group exists).

use crate::sha256::Sha256;
use flexmbs_fe::geometric::GeometricStiffness;
use flexmbs_fe::reduction::{ReducedBody, ReductionKind};

/// Name of the root attribute holding the digest.
pub(crate) const ATTRIBUTE: &str = "text_sha256";

/// The stored name of a reduction kind (root attribute `reduction`).
pub(crate) fn reduction_name(kind: &ReductionKind) -> &'static str {
    match kind {
        ReductionKind::Modal => "modal",
        ReductionKind::FreeFree => "free_free",
        ReductionKind::CraigBampton { .. } => "craig_bampton",
    }
}

/// SHA-256 (lower-case hex) of the text fields of a body and its optional geometric stiffness,
/// as stored in the root attribute `text_sha256` (module documentation).
pub fn text_sha256(body: &ReducedBody, geometric: Option<&GeometricStiffness>) -> String {
    let mut h = Sha256::default();
    let mut field = |s: &str| {
        h.update(s.as_bytes());
        h.update(&[0]);
    };
    field(&body.name);
    field(body.units.name());
    field(reduction_name(&body.kind));
    field(&body.provenance.source);
    field(&body.provenance.program);
    field(&body.provenance.notes);
    for l in &body.labels {
        field(&l.dominant);
    }
    for &p in geometric.map(|g| g.load_patterns.as_slice()).unwrap_or(&[]) {
        field(&super::geometric::pattern_name(p).unwrap_or_default());
    }
    h.hex()
}
