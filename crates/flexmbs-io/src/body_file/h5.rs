//! HDF5 layout of the reduced-body file, version 1 (see `docs/formats/reduced-body.md`).
//!
//! Matrices are stored row-major (C order, as HDF5 and NumPy expect) with their mathematical
//! shape: `modes/translation` is `[3 N, N_f]` exactly as [`ReducedBody::modes_t`].

use super::{BodyFile, BodyFileError, FORMAT_NAME, FORMAT_VERSION};
use faer::Mat;
use flexmbs_fe::geometric::GeometricStiffness;
use flexmbs_fe::mesh::ElementKind;
use flexmbs_fe::reduction::{Cell, ModeLabel, Provenance, ReducedBody, ReductionKind};
use flexmbs_fe::UnitSystem;
use hdf5_pure::{AttrValue, DType, Dataset, File, FileBuilder, FormatError};
use std::path::Path;

/// Dataset paths of layout version 1.
pub(crate) mod ds {
    /// Node positions, f64 `[N, 3]`.
    pub const POSITION: &str = "nodes/position";
    /// Node labels, u64 `[N]`.
    pub const ID: &str = "nodes/id";
    /// Lumped node masses, f64 `[N]` (optional).
    pub const MASS: &str = "nodes/mass";
    /// Interface node indices (0-based), u64 `[n]`.
    pub const INTERFACE: &str = "nodes/interface";
    /// Fixed node indices (0-based), u64 `[n]`.
    pub const FIXED: &str = "nodes/fixed";
    /// Translational mode shapes, f64 `[3 N, N_f]`.
    pub const TRANSLATION: &str = "modes/translation";
    /// Rotational mode shapes, f64 `[3 N, N_f]` (optional).
    pub const ROTATION: &str = "modes/rotation";
    /// Frequencies in Hz, f64 `[N_f]`.
    pub const FREQUENCY: &str = "modes/frequency_hz";
    /// Label index (1-based), u64 `[N_f]`.
    pub const LABEL_INDEX: &str = "modes/label_index";
    /// Label frequency in Hz (NaN for static modes), f64 `[N_f]`.
    pub const LABEL_FREQUENCY: &str = "modes/label_frequency_hz";
    /// Label dominant motion, variable-length UTF-8 strings `[N_f]`.
    pub const LABEL_DOMINANT: &str = "modes/label_dominant";
    /// Effective mass fractions, f64 `[N_f, 3]`.
    pub const EFFECTIVE_MASS: &str = "modes/effective_mass_fraction";
    /// Reduced stiffness, f64 `[N_f, N_f]`.
    pub const STIFFNESS: &str = "reduced/stiffness";
    /// Reduced mass, f64 `[N_f, N_f]`.
    pub const MASS_RED: &str = "reduced/mass";
    /// Cell kind codes (index into the attribute `names`), u8 `[N_c]`.
    pub const CELL_KIND: &str = "cells/kind";
    /// Cell offsets into the connectivity, u64 `[N_c + 1]`.
    pub const CELL_OFFSETS: &str = "cells/offsets";
    /// Cell connectivity (0-based node indices, Abaqus order), u64 `[sum]`.
    pub const CELL_CONNECTIVITY: &str = "cells/connectivity";
}

/// Element kinds in the order of their `cells/kind` code; also the attribute `cells/kind@names`.
const KIND_NAMES: [(ElementKind, &str); 6] = [
    (ElementKind::Hex8, "Hex8"),
    (ElementKind::Hex8I, "Hex8I"),
    (ElementKind::Hex20, "Hex20"),
    (ElementKind::Hex20R, "Hex20R"),
    (ElementKind::Tet10, "Tet10"),
    (ElementKind::Beam2, "Beam2"),
];

pub(super) fn invalid(path: &Path, object: &str, message: String) -> BodyFileError {
    BodyFileError::Invalid {
        path: path.to_path_buf(),
        object: object.to_string(),
        message,
    }
}

pub(super) fn hdf5_error(path: &Path, object: &str, e: impl std::fmt::Display) -> BodyFileError {
    BodyFileError::Hdf5 {
        path: path.to_path_buf(),
        object: object.to_string(),
        message: e.to_string(),
    }
}

/// Consistency of a body: the invariants the file layout and a multibody model rely on.
pub(crate) fn check_body(path: &Path, b: &ReducedBody) -> Result<(), BodyFileError> {
    let n = b.num_nodes();
    let nf = b.num_modes();
    let rows = |name: &str, m: &Mat<f64>, r: usize, c: usize| {
        if m.nrows() != r || m.ncols() != c {
            Err(invalid(
                path,
                name,
                format!("is {} x {}, expected {r} x {c}", m.nrows(), m.ncols()),
            ))
        } else {
            Ok(())
        }
    };
    if b.node_ids.len() != n {
        return Err(invalid(
            path,
            ds::ID,
            format!("{} labels for {n} nodes", b.node_ids.len()),
        ));
    }
    if let Some(m) = &b.node_masses {
        if m.len() != n {
            return Err(invalid(
                path,
                ds::MASS,
                format!("{} masses for {n} nodes", m.len()),
            ));
        }
    }
    rows(ds::TRANSLATION, &b.modes_t, 3 * n, nf)?;
    if let Some(r) = &b.modes_r {
        rows(ds::ROTATION, r, 3 * n, nf)?;
    }
    rows(ds::STIFFNESS, &b.k_red, nf, nf)?;
    rows(ds::MASS_RED, &b.m_red, nf, nf)?;
    if b.frequencies_hz.len() != nf {
        return Err(invalid(
            path,
            ds::FREQUENCY,
            format!("{} frequencies for {nf} modes", b.frequencies_hz.len()),
        ));
    }
    if b.labels.len() != nf {
        return Err(invalid(
            path,
            ds::LABEL_INDEX,
            format!("{} labels for {nf} modes", b.labels.len()),
        ));
    }
    for (name, set) in [
        (ds::INTERFACE, &b.interface_nodes),
        (ds::FIXED, &b.fixed_nodes),
    ] {
        if let Some(&i) = set.iter().find(|&&i| i >= n) {
            return Err(invalid(
                path,
                name,
                format!("node index {i} out of range (N = {n})"),
            ));
        }
    }
    for (ci, c) in b.cells.iter().enumerate() {
        if c.nodes.len() != c.kind.num_nodes() {
            let msg = format!(
                "cell {ci} ({:?}) has {} nodes, expected {}",
                c.kind,
                c.nodes.len(),
                c.kind.num_nodes()
            );
            return Err(invalid(path, ds::CELL_CONNECTIVITY, msg));
        }
        if let Some(&i) = c.nodes.iter().find(|&&i| i >= n) {
            return Err(invalid(
                path,
                ds::CELL_CONNECTIVITY,
                format!("cell {ci}: node index {i} out of range (N = {n})"),
            ));
        }
    }
    Ok(())
}

/// Row-major copy of a matrix.
pub(super) fn row_major(m: &Mat<f64>) -> Vec<f64> {
    let mut v = Vec::with_capacity(m.nrows() * m.ncols());
    for r in 0..m.nrows() {
        for c in 0..m.ncols() {
            v.push(m[(r, c)]);
        }
    }
    v
}

fn as_u64(v: &[usize]) -> Vec<u64> {
    v.iter().map(|&i| i as u64).collect()
}

fn kind_code(kind: ElementKind) -> u8 {
    KIND_NAMES.iter().position(|(k, _)| *k == kind).unwrap_or(0) as u8
}

/// Rows per chunk of a checksummed float dataset: about 1 MiB per chunk at 50 columns.
const CHUNK_ROWS: u64 = 2048;

/// Stores a float array of the given shape (row-major data) chunked along its first axis with a
/// Fletcher-32 checksum per chunk (HDF5 filter 3), so that a damaged file is detected when read,
/// not silently used.
pub(super) fn checksummed(b: &mut hdf5_pure::DatasetBuilder, data: &[f64], shape: &[u64]) {
    b.with_f64_data(data).with_shape(shape);
    if !data.is_empty() {
        let mut chunk = shape.to_vec();
        chunk[0] = chunk[0].min(CHUNK_ROWS);
        b.with_chunks(&chunk).with_fletcher32();
    }
}

/// Entries per chunk of a checksummed index vector (256 KiB). Chunk dimensions stay below
/// 65 536: for larger ones the writer encodes the dimension in more bytes than libhdf5
/// computes, and h5py then refuses to open the dataset.
const INDEX_CHUNK: u64 = 32_768;

/// Stores an index vector chunked with a Fletcher-32 checksum (as [`checksummed`]).
fn checksummed_u64(b: &mut hdf5_pure::DatasetBuilder, data: &[u64]) {
    b.with_u64_data(data);
    if !data.is_empty() {
        b.with_chunks(&[(data.len() as u64).min(INDEX_CHUNK)])
            .with_fletcher32();
    }
}

/// Serializes a checked body into the bytes of an HDF5 file.
pub(crate) fn encode_body(
    path: &Path,
    b: &ReducedBody,
    geometric: Option<&GeometricStiffness>,
    rotary_inertia: Option<&[nalgebra::Matrix3<f64>]>,
    optional: super::Optional<'_>,
) -> Result<Vec<u8>, BodyFileError> {
    let n = b.num_nodes() as u64;
    let nf = b.num_modes() as u64;
    let mut fb = FileBuilder::new();
    fb.set_attr("format", AttrValue::VarLenString(FORMAT_NAME.into()));
    fb.set_attr("format_version", AttrValue::I64(FORMAT_VERSION));
    fb.set_attr("name", AttrValue::VarLenString(b.name.clone()));
    fb.set_attr("units", AttrValue::VarLenString(b.units.name().into()));
    let internal = match b.kind {
        ReductionKind::CraigBampton { internal_modes } => internal_modes as i64,
        _ => 0,
    };
    let kind = super::text_digest::reduction_name(&b.kind);
    fb.set_attr("reduction", AttrValue::VarLenString(kind.into()));
    fb.set_attr(
        super::text_digest::ATTRIBUTE,
        AttrValue::VarLenString(super::text_sha256(b, geometric)),
    );
    fb.set_attr("internal_modes", AttrValue::I64(internal));
    fb.set_attr("num_nodes", AttrValue::I64(n as i64));
    fb.set_attr("num_modes", AttrValue::I64(nf as i64));

    let mut prov = fb.create_group("provenance");
    prov.set_attr(
        "source",
        AttrValue::VarLenString(b.provenance.source.clone()),
    );
    prov.set_attr(
        "program",
        AttrValue::VarLenString(b.provenance.program.clone()),
    );
    prov.set_attr("notes", AttrValue::VarLenString(b.provenance.notes.clone()));
    fb.add_group(prov.finish());

    let mut nodes = fb.create_group("nodes");
    let pos: Vec<f64> = b.nodes.iter().flatten().copied().collect();
    checksummed(nodes.create_dataset("position"), &pos, &[n, 3]);
    checksummed_u64(nodes.create_dataset("id"), &b.node_ids);
    if let Some(m) = &b.node_masses {
        checksummed(nodes.create_dataset("mass"), m, &[n]);
    }
    checksummed_u64(
        nodes.create_dataset("interface"),
        &as_u64(&b.interface_nodes),
    );
    checksummed_u64(nodes.create_dataset("fixed"), &as_u64(&b.fixed_nodes));
    if let Some(r) = rotary_inertia {
        let data = super::rotary::flatten(r);
        checksummed(nodes.create_dataset("rotary_inertia"), &data, &[n, 3, 3]);
    }
    fb.add_group(nodes.finish());

    let mut modes = fb.create_group("modes");
    checksummed(
        modes.create_dataset("translation"),
        &row_major(&b.modes_t),
        &[3 * n, nf],
    );
    if let Some(r) = &b.modes_r {
        checksummed(
            modes.create_dataset("rotation"),
            &row_major(r),
            &[3 * n, nf],
        );
    }
    checksummed(
        modes.create_dataset("frequency_hz"),
        &b.frequencies_hz,
        &[nf],
    );
    let idx: Vec<u64> = b.labels.iter().map(|l| l.index as u64).collect();
    checksummed_u64(modes.create_dataset("label_index"), &idx);
    let lf: Vec<f64> = b.labels.iter().map(|l| l.frequency_hz).collect();
    checksummed(modes.create_dataset("label_frequency_hz"), &lf, &[nf]);
    let dom: Vec<&str> = b.labels.iter().map(|l| l.dominant.as_str()).collect();
    modes
        .create_dataset("label_dominant")
        .with_vlen_strings(&dom);
    let emf: Vec<f64> = b
        .labels
        .iter()
        .flat_map(|l| l.effective_mass_fraction)
        .collect();
    checksummed(
        modes.create_dataset("effective_mass_fraction"),
        &emf,
        &[nf, 3],
    );
    fb.add_group(modes.finish());

    let mut red = fb.create_group("reduced");
    checksummed(
        red.create_dataset("stiffness"),
        &row_major(&b.k_red),
        &[nf, nf],
    );
    checksummed(red.create_dataset("mass"), &row_major(&b.m_red), &[nf, nf]);
    fb.add_group(red.finish());

    let mut cells = fb.create_group("cells");
    let codes: Vec<u8> = b.cells.iter().map(|c| kind_code(c.kind)).collect();
    let names: Vec<String> = KIND_NAMES.iter().map(|(_, s)| s.to_string()).collect();
    cells
        .create_dataset("kind")
        .with_u8_data(&codes)
        .set_attr("names", AttrValue::VarLenStringArray(names));
    let mut offsets = Vec::with_capacity(b.cells.len() + 1);
    offsets.push(0u64);
    let mut conn = Vec::new();
    for c in &b.cells {
        conn.extend(c.nodes.iter().map(|&i| i as u64));
        offsets.push(conn.len() as u64);
    }
    checksummed_u64(cells.create_dataset("offsets"), &offsets);
    checksummed_u64(cells.create_dataset("connectivity"), &conn);
    fb.add_group(cells.finish());

    if let Some(g) = geometric {
        super::geometric::encode(&mut fb, g);
    }
    if let Some(s) = optional.stress {
        super::stress::encode(&mut fb, s);
    }
    if let Some(g) = optional.inertia_gram {
        super::inertia::encode(&mut fb, g);
    }

    fb.finish().map_err(|e| hdf5_error(path, "/", e))
}

/// Reader of one file: keeps the path for error messages.
pub(super) struct Reader<'a> {
    pub(super) path: &'a Path,
    file: File,
}

impl Reader<'_> {
    /// The dataset at `name`, or `None` if nothing is there.
    pub(super) fn optional(&self, name: &str) -> Result<Option<Dataset>, BodyFileError> {
        match self.file.dataset(name) {
            Ok(d) => Ok(Some(d)),
            Err(hdf5_pure::Error::Format(FormatError::PathNotFound(_))) => Ok(None),
            Err(e) => Err(hdf5_error(self.path, name, e)),
        }
    }

    pub(super) fn required(&self, name: &str) -> Result<Dataset, BodyFileError> {
        self.optional(name)?
            .ok_or_else(|| BodyFileError::MissingDataset {
                path: self.path.to_path_buf(),
                dataset: name.to_string(),
            })
    }

    /// Checks the shape of a dataset against `expected` (`None` = any extent).
    pub(super) fn shape(
        &self,
        name: &str,
        d: &Dataset,
        expected: &[Option<u64>],
        what: &str,
    ) -> Result<Vec<u64>, BodyFileError> {
        let shape = d.shape().map_err(|e| hdf5_error(self.path, name, e))?;
        let ok = shape.len() == expected.len()
            && shape
                .iter()
                .zip(expected)
                .all(|(s, e)| e.is_none_or(|e| *s == e));
        if !ok {
            let exp: Vec<String> = expected
                .iter()
                .map(|e| e.map_or("*".to_string(), |v| v.to_string()))
                .collect();
            return Err(BodyFileError::WrongShape {
                path: self.path.to_path_buf(),
                dataset: name.to_string(),
                expected: format!("{what} = [{}]", exp.join(", ")),
                found: shape,
            });
        }
        Ok(shape)
    }

    fn dtype(&self, name: &str, d: &Dataset) -> Result<DType, BodyFileError> {
        d.dtype().map_err(|e| hdf5_error(self.path, name, e))
    }

    fn wrong_type(&self, name: &str, expected: &str, found: DType) -> BodyFileError {
        BodyFileError::WrongType {
            path: self.path.to_path_buf(),
            dataset: name.to_string(),
            expected: expected.to_string(),
            found: found.to_string(),
        }
    }

    /// A float64 dataset of the given shape, flattened row-major.
    pub(super) fn f64s(
        &self,
        name: &str,
        d: &Dataset,
        expected: &[Option<u64>],
        what: &str,
    ) -> Result<Vec<f64>, BodyFileError> {
        self.shape(name, d, expected, what)?;
        match self.dtype(name, d)? {
            DType::F64 => d.read_f64().map_err(|e| hdf5_error(self.path, name, e)),
            other => Err(self.wrong_type(name, "f64", other)),
        }
    }

    /// A non-negative integer dataset (any integer width; h5py writes int64 by default).
    pub(super) fn u64s(
        &self,
        name: &str,
        d: &Dataset,
        expected: &[Option<u64>],
        what: &str,
    ) -> Result<Vec<u64>, BodyFileError> {
        self.shape(name, d, expected, what)?;
        match self.dtype(name, d)? {
            DType::U8 | DType::U16 | DType::U32 | DType::U64 => {
                d.read_u64().map_err(|e| hdf5_error(self.path, name, e))
            }
            DType::I8 | DType::I16 | DType::I32 | DType::I64 => {
                let v = d.read_i64().map_err(|e| hdf5_error(self.path, name, e))?;
                if let Some(bad) = v.iter().find(|&&x| x < 0) {
                    return Err(invalid(self.path, name, format!("negative value {bad}")));
                }
                Ok(v.into_iter().map(|x| x as u64).collect())
            }
            other => Err(self.wrong_type(name, "unsigned integer", other)),
        }
    }

    /// Indices `< n` as usize.
    fn indices(
        &self,
        name: &str,
        expected: &[Option<u64>],
        what: &str,
        n: usize,
    ) -> Result<Vec<usize>, BodyFileError> {
        let d = self.required(name)?;
        let v = self.u64s(name, &d, expected, what)?;
        if let Some(bad) = v.iter().find(|&&i| i >= n as u64) {
            return Err(invalid(
                self.path,
                name,
                format!("index {bad} out of range (N = {n})"),
            ));
        }
        Ok(v.into_iter().map(|i| i as usize).collect())
    }

    fn matrix(
        &self,
        name: &str,
        d: &Dataset,
        rows: usize,
        cols: usize,
        what: &str,
    ) -> Result<Mat<f64>, BodyFileError> {
        let v = self.f64s(name, d, &[Some(rows as u64), Some(cols as u64)], what)?;
        Ok(Mat::from_fn(rows, cols, |r, c| v[r * cols + c]))
    }

    fn attrs(
        &self,
        group: &str,
    ) -> Result<std::collections::HashMap<String, AttrValue>, BodyFileError> {
        let g = if group == "/" {
            self.file.root()
        } else {
            self.file
                .group(group)
                .map_err(|e| hdf5_error(self.path, group, e))?
        };
        g.attrs().map_err(|e| hdf5_error(self.path, group, e))
    }

    fn bad_attr(&self, group: &str, name: &str, expected: &str) -> BodyFileError {
        let sep = if group.ends_with('/') { "" } else { "/" };
        BodyFileError::BadAttribute {
            path: self.path.to_path_buf(),
            attribute: format!("{group}{sep}@{name}"),
            expected: expected.to_string(),
        }
    }
}

fn attr_str(
    r: &Reader,
    a: &std::collections::HashMap<String, AttrValue>,
    group: &str,
    name: &str,
) -> Result<String, BodyFileError> {
    a.get(name)
        .and_then(|v| v.as_str())
        .map(str::to_string)
        .ok_or_else(|| r.bad_attr(group, name, "string"))
}

fn attr_int(
    r: &Reader,
    a: &std::collections::HashMap<String, AttrValue>,
    group: &str,
    name: &str,
) -> Result<i64, BodyFileError> {
    a.get(name)
        .and_then(|v| v.as_i64())
        .ok_or_else(|| r.bad_attr(group, name, "integer"))
}

/// Parses the bytes of a reduced-body file.
pub(crate) fn decode_body(path: &Path, bytes: Vec<u8>) -> Result<BodyFile, BodyFileError> {
    let file = File::from_bytes(bytes).map_err(|e| hdf5_error(path, "/", e))?;
    let r = Reader { path, file };
    let root = r.attrs("/")?;
    match root.get("format").and_then(|v| v.as_str()) {
        Some(FORMAT_NAME) => {}
        Some(other) => {
            return Err(BodyFileError::NotABodyFile {
                path: path.to_path_buf(),
                reason: format!("root attribute format = '{other}', expected '{FORMAT_NAME}'"),
            })
        }
        None => {
            return Err(BodyFileError::NotABodyFile {
                path: path.to_path_buf(),
                reason: "no string root attribute 'format'".into(),
            })
        }
    }
    let version = attr_int(&r, &root, "/", "format_version")?;
    if !(1..=FORMAT_VERSION).contains(&version) {
        return Err(BodyFileError::UnsupportedVersion {
            path: path.to_path_buf(),
            found: version,
            supported: FORMAT_VERSION,
        });
    }
    let name = attr_str(&r, &root, "/", "name")?;
    let units = match attr_str(&r, &root, "/", "units")?.as_str() {
        "SI" => UnitSystem::Si,
        "SI(mm)" => UnitSystem::SiMm,
        _ => return Err(r.bad_attr("/", "units", "'SI' or 'SI(mm)'")),
    };
    let kind = match attr_str(&r, &root, "/", "reduction")?.as_str() {
        "modal" => ReductionKind::Modal,
        "free_free" => ReductionKind::FreeFree,
        "craig_bampton" => {
            let m = attr_int(&r, &root, "/", "internal_modes")?;
            let internal_modes = usize::try_from(m)
                .map_err(|_| r.bad_attr("/", "internal_modes", "integer >= 0"))?;
            ReductionKind::CraigBampton { internal_modes }
        }
        _ => return Err(r.bad_attr("/", "reduction", "'modal', 'free_free' or 'craig_bampton'")),
    };
    let prov = r.attrs("provenance")?;
    let provenance = Provenance {
        source: attr_str(&r, &prov, "/provenance", "source")?,
        program: attr_str(&r, &prov, "/provenance", "program")?,
        notes: attr_str(&r, &prov, "/provenance", "notes")?,
    };

    // Nodes: N is fixed by nodes/position.
    let d = r.required(ds::POSITION)?;
    let pos = r.f64s(ds::POSITION, &d, &[None, Some(3)], "[N, 3]")?;
    let nodes: Vec<[f64; 3]> = pos.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
    let n = nodes.len();
    let nn = Some(n as u64);
    let d = r.required(ds::ID)?;
    let node_ids = r.u64s(ds::ID, &d, &[nn], &format!("[N] = [{n}]"))?;
    let node_masses = match r.optional(ds::MASS)? {
        Some(d) => Some(r.f64s(ds::MASS, &d, &[nn], &format!("[N] = [{n}]"))?),
        None => None,
    };
    let interface_nodes = r.indices(ds::INTERFACE, &[None], "[*]", n)?;
    let fixed_nodes = r.indices(ds::FIXED, &[None], "[*]", n)?;

    // Modes: N_f is fixed by modes/translation.
    let d = r.required(ds::TRANSLATION)?;
    let shape = r.shape(
        ds::TRANSLATION,
        &d,
        &[Some(3 * n as u64), None],
        &format!("[3 N, N_f] = [{}, *]", 3 * n),
    )?;
    let nf = shape[1] as usize;
    let mn = format!("[3 N, N_f] = [{}, {nf}]", 3 * n);
    let modes_t = r.matrix(ds::TRANSLATION, &d, 3 * n, nf, &mn)?;
    let modes_r = match r.optional(ds::ROTATION)? {
        Some(d) => Some(r.matrix(ds::ROTATION, &d, 3 * n, nf, &mn)?),
        None => None,
    };
    let f1 = [Some(nf as u64)];
    let w1 = format!("[N_f] = [{nf}]");
    let frequencies_hz = r.f64s(ds::FREQUENCY, &r.required(ds::FREQUENCY)?, &f1, &w1)?;
    let index = r.u64s(ds::LABEL_INDEX, &r.required(ds::LABEL_INDEX)?, &f1, &w1)?;
    let lf = r.f64s(
        ds::LABEL_FREQUENCY,
        &r.required(ds::LABEL_FREQUENCY)?,
        &f1,
        &w1,
    )?;
    let d = r.required(ds::LABEL_DOMINANT)?;
    r.shape(ds::LABEL_DOMINANT, &d, &f1, &w1)?;
    let dominant = d
        .read_string()
        .map_err(|e| hdf5_error(path, ds::LABEL_DOMINANT, e))?;
    let d = r.required(ds::EFFECTIVE_MASS)?;
    let emf = r.f64s(
        ds::EFFECTIVE_MASS,
        &d,
        &[Some(nf as u64), Some(3)],
        &format!("[N_f, 3] = [{nf}, 3]"),
    )?;
    let labels = (0..nf)
        .map(|k| ModeLabel {
            index: index[k] as usize,
            frequency_hz: lf[k],
            dominant: dominant[k].clone(),
            effective_mass_fraction: [emf[3 * k], emf[3 * k + 1], emf[3 * k + 2]],
        })
        .collect();
    let wq = format!("[N_f, N_f] = [{nf}, {nf}]");
    let k_red = r.matrix(ds::STIFFNESS, &r.required(ds::STIFFNESS)?, nf, nf, &wq)?;
    let m_red = r.matrix(ds::MASS_RED, &r.required(ds::MASS_RED)?, nf, nf, &wq)?;

    let cells = read_cells(&r, n)?;
    let body = ReducedBody {
        name,
        units,
        nodes,
        node_ids,
        node_masses,
        modes_t,
        modes_r,
        k_red,
        m_red,
        frequencies_hz,
        labels,
        interface_nodes,
        fixed_nodes,
        kind,
        cells,
        provenance,
    };
    check_body(path, &body)?;
    super::consistency::check_physics(path, &body)?;
    let geometric = super::geometric::decode(&r, nf)?;
    if version >= 2 {
        check_text_digest(&r, &root, &body, geometric.as_ref())?;
    }
    let rotary_inertia = super::rotary::decode(&r, n)?;
    let stress = super::stress::decode(&r, n, nf)?;
    let inertia_gram = super::inertia::decode(&r, &body)?;
    Ok(BodyFile {
        body,
        geometric,
        rotary_inertia,
        stress,
        inertia_gram,
    })
}

/// Compares the root attribute `text_sha256` (format version 2) with the digest of the decoded
/// text fields.
fn check_text_digest(
    r: &Reader,
    root: &std::collections::HashMap<String, AttrValue>,
    body: &ReducedBody,
    geometric: Option<&GeometricStiffness>,
) -> Result<(), BodyFileError> {
    let stored = attr_str(r, root, "/", super::text_digest::ATTRIBUTE)?;
    let computed = super::text_sha256(body, geometric);
    if stored != computed {
        let msg = format!(
            "the text fields (name, units, reduction, provenance, mode labels, load-pattern names) \
             do not match their checksum (stored {stored}, computed {computed}): the file was \
             altered after it was written"
        );
        return Err(invalid(r.path, "/@text_sha256", msg));
    }
    Ok(())
}

/// Cells from `cells/kind`, `cells/offsets` and `cells/connectivity`.
fn read_cells(r: &Reader, n: usize) -> Result<Vec<Cell>, BodyFileError> {
    let d = r.required(ds::CELL_KIND)?;
    let codes = r.u64s(ds::CELL_KIND, &d, &[None], "[N_c]")?;
    let nc = codes.len();
    let offsets = r.indices(
        ds::CELL_OFFSETS,
        &[Some(nc as u64 + 1)],
        &format!("[N_c + 1] = [{}]", nc + 1),
        usize::MAX,
    )?;
    let conn = r.indices(ds::CELL_CONNECTIVITY, &[None], "[*]", n)?;
    // The attribute `names` maps codes to kinds; the writer's table is the default.
    let attrs = d
        .attrs()
        .map_err(|e| hdf5_error(r.path, ds::CELL_KIND, e))?;
    let names: Vec<String> = match attrs.get("names") {
        Some(v) => v
            .as_strings()
            .ok_or_else(|| r.bad_attr(ds::CELL_KIND, "names", "string array"))?
            .to_vec(),
        None => KIND_NAMES.iter().map(|(_, s)| s.to_string()).collect(),
    };
    let mut table = Vec::with_capacity(names.len());
    for name in &names {
        let kind = KIND_NAMES.iter().find(|(_, s)| s == name).map(|(k, _)| *k);
        table.push(kind.ok_or_else(|| {
            invalid(
                r.path,
                ds::CELL_KIND,
                format!("unknown element kind name '{name}'"),
            )
        })?);
    }
    let mut cells = Vec::with_capacity(nc);
    for (ci, &code) in codes.iter().enumerate() {
        let kind = *table.get(code as usize).ok_or_else(|| {
            invalid(
                r.path,
                ds::CELL_KIND,
                format!("cell {ci}: kind code {code} not in {names:?}"),
            )
        })?;
        let (a, b) = (offsets[ci], offsets[ci + 1]);
        if a > b || b > conn.len() {
            return Err(invalid(
                r.path,
                ds::CELL_OFFSETS,
                format!("cell {ci}: offsets {a}..{b} not increasing within the connectivity of length {}", conn.len()),
            ));
        }
        cells.push(Cell {
            kind,
            nodes: conn[a..b].to_vec(),
        });
    }
    if offsets.first().is_some_and(|&o| o != 0) || offsets.last().is_some_and(|&o| o != conn.len())
    {
        return Err(invalid(
            r.path,
            ds::CELL_OFFSETS,
            format!("must start at 0 and end at {}", conn.len()),
        ));
    }
    Ok(cells)
}
