//! The optional `stress` group of the reduced-body file: modal stress fields (nodal stress of
//! every basis vector, [`flexmbs_fe::stress::ModalStress`]), written by `flexmbs reduce` and used
//! by a multibody model to recover stresses linearly, `sigma = sum_k S_k q_k` (see
//! `docs/formats/reduced-body.md`).
//!
//! Layout: `stress/modal` f64 `[6 N, N_f]` (row `6 i + c` = component `c` of node `i`, as
//! `modes/translation` with 6 rows per node; units of the body: force / length²) and
//! `stress/node_kind` u8 `[N]` (0 no element, 1 solid: Cauchy stress xx, yy, zz, xy, yz, zx in
//! body axes; 2 beam: section stresses `N/A, M_y c_z/I_y, -M_z c_y/I_z, T c_t/J, V_y/A, V_z/A`),
//! its attribute `names` naming the codes.

use super::h5::{checksummed, invalid, row_major, Reader};
use super::BodyFileError;
use faer::Mat;
use flexmbs_fe::stress::{ModalStress, NodeStressKind};
use hdf5_pure::{AttrValue, FileBuilder};
use std::path::Path;

/// Modal stress fields, f64 `[6 N, N_f]`.
pub(crate) const MODAL: &str = "stress/modal";
/// Node stress kinds, u8 `[N]`.
pub(crate) const NODE_KIND: &str = "stress/node_kind";

const KIND_NAMES: [&str; 3] = ["none", "solid", "beam"];

/// Checks `s` against a body of `n` nodes and `nf` modes: one kind per node, `6 n x nf` finite
/// fields, zero rows at nodes of kind none.
pub(crate) fn check(
    path: &Path,
    s: &ModalStress,
    n: usize,
    nf: usize,
) -> Result<(), BodyFileError> {
    if s.kinds.len() != n {
        let msg = format!("{} node kinds for {n} nodes", s.kinds.len());
        return Err(invalid(path, NODE_KIND, msg));
    }
    if s.fields.nrows() != 6 * n || s.fields.ncols() != nf {
        let msg = format!(
            "is {} x {}, expected 6 N x N_f = {} x {nf}",
            s.fields.nrows(),
            s.fields.ncols(),
            6 * n
        );
        return Err(invalid(path, MODAL, msg));
    }
    for c in 0..nf {
        if let Some(r) = (0..6 * n).find(|&r| !s.fields[(r, c)].is_finite()) {
            let msg = format!("non-finite entry {} at ({r}, {c})", s.fields[(r, c)]);
            return Err(invalid(path, MODAL, msg));
        }
    }
    Ok(())
}

/// Adds the `stress` group for a checked `s`.
pub(crate) fn encode(fb: &mut FileBuilder, s: &ModalStress) {
    let (n, nf) = (s.num_nodes() as u64, s.num_modes() as u64);
    let mut grp = fb.create_group("stress");
    grp.set_attr(
        "method",
        AttrValue::VarLenString(
            "linear recovery: nodal stress of each basis vector (solids: D B at the element \
             nodes, averaged; beams: end-force section stresses, averaged)"
                .into(),
        ),
    );
    checksummed(
        grp.create_dataset("modal"),
        &row_major(&s.fields),
        &[6 * n, nf],
    );
    let codes: Vec<u8> = s.kinds.iter().map(|&k| k as u8).collect();
    let names: Vec<String> = KIND_NAMES.iter().map(|s| s.to_string()).collect();
    grp.create_dataset("node_kind")
        .with_u8_data(&codes)
        .set_attr("names", AttrValue::VarLenStringArray(names));
    fb.add_group(grp.finish());
}

/// Reads the `stress` group of a body with `n` nodes and `nf` modes, if the file has one (both
/// datasets or neither), and checks it like the writer does.
pub(crate) fn decode(
    r: &Reader,
    n: usize,
    nf: usize,
) -> Result<Option<ModalStress>, BodyFileError> {
    let (modal, kind) = match (r.optional(MODAL)?, r.optional(NODE_KIND)?) {
        (None, None) => return Ok(None),
        (Some(m), Some(k)) => (m, k),
        (m, _) => {
            return Err(BodyFileError::MissingDataset {
                path: r.path.to_path_buf(),
                dataset: if m.is_none() { MODAL } else { NODE_KIND }.to_string(),
            })
        }
    };
    let codes = r.u64s(NODE_KIND, &kind, &[Some(n as u64)], "[N]")?;
    let kinds = codes
        .iter()
        .enumerate()
        .map(|(i, &c)| {
            u8::try_from(c)
                .ok()
                .and_then(NodeStressKind::from_code)
                .ok_or_else(|| {
                    invalid(
                        r.path,
                        NODE_KIND,
                        format!("node {i}: unknown kind code {c} (0 none, 1 solid, 2 beam)"),
                    )
                })
        })
        .collect::<Result<Vec<_>, _>>()?;
    let what = format!("[6 N, N_f] = [{}, {nf}]", 6 * n);
    let data = r.f64s(MODAL, &modal, &[Some(6 * n as u64), Some(nf as u64)], &what)?;
    let fields = Mat::from_fn(6 * n, nf, |a, b| data[a * nf + b]);
    let s = ModalStress { kinds, fields };
    check(r.path, &s, n, nf)?;
    Ok(Some(s))
}
