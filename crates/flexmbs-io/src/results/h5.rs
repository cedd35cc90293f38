//! HDF5 layout of the results file, version 2 (see `docs/formats/results.md`); version 1 is
//! still read.
//!
//! Matrices are stored row-major (C order, as HDF5 and NumPy expect), one row per output time:
//! version 2 as one-dimensional extensible datasets whose elements are rows (`float64[k]`),
//! version 1 as `[n, k]` float64 datasets. Row datasets are chunked along the time axis with a
//! Fletcher-32 checksum per chunk, so that a damaged file is detected when read, not silently used.

use super::{
    Columns, ResultsError, ResultsLayout, RunStatus, SignalSpec, DRIFT_COLUMNS, ENERGY_COLUMNS,
    FORMAT_NAME, FORMAT_VERSION, RESERVED_ATTRIBUTES, STEP_COLUMNS,
};
use hdf5_pure::{
    make_f64_type, AttrValue, DType, Dataset, File, FileBuilder, FormatError, MaxExtent,
};
use std::collections::HashMap;
use std::path::Path;

/// Target number of f64 values per chunk (64 KiB): chunks of 1 MiB made the final write of a
/// 350 MB file about twice slower (each chunk buffer a fresh, kernel-zeroed mapping).
const CHUNK_VALUES: u64 = 8_192;

fn hdf5_error(path: &Path, object: &str, e: impl std::fmt::Display) -> ResultsError {
    ResultsError::Hdf5 {
        path: path.to_path_buf(),
        object: object.to_string(),
        message: e.to_string(),
    }
}

/// An empty float matrix of `cols` columns (or vector when `cols` is `None`) that grows along
/// the rows (format version 2): a one-dimensional dataset with an unlimited dimension whose
/// elements are rows (HDF5 array datatype `float64[cols]`; `hdf5-pure` appends in place to
/// one-dimensional datasets only), chunked along it with a Fletcher-32 checksum. NumPy reads it
/// as an `[n, cols]` float64 array. A matrix without columns cannot be chunked; it is an empty
/// `[0, 0]` dataset until the writer finishes.
fn extensible(b: &mut hdf5_pure::DatasetBuilder, cols: Option<usize>) {
    let width = cols.unwrap_or(1) as u64;
    if width == 0 {
        b.with_f64_data(&[]).with_shape(&[0, 0]);
        return;
    }
    let rows = (CHUNK_VALUES / width).max(1);
    match cols {
        Some(c) => b.with_array_data(make_f64_type(), &[c as u32], Vec::new(), 0),
        None => b.with_f64_data(&[]),
    };
    b.with_shape(&[0])
        .with_maxshape(&[MaxExtent::Unlimited])
        .with_chunks(&[rows])
        .with_fletcher32();
}

fn strings(v: &[&str]) -> AttrValue {
    AttrValue::VarLenStringArray(v.iter().map(|s| s.to_string()).collect())
}

/// Stages an empty results file with status `running` whose row datasets grow by in-place
/// appends (format version 2; see [`super::stream`]).
pub(crate) fn build_extensible(
    layout: &ResultsLayout,
    attributes: &[(String, String)],
) -> FileBuilder {
    let mut fb = FileBuilder::new();
    fb.set_attr("format", AttrValue::VarLenString(FORMAT_NAME.into()));
    fb.set_attr("format_version", AttrValue::I64(FORMAT_VERSION));
    fb.set_attr("model", AttrValue::VarLenString(layout.model.clone()));
    fb.set_attr("status", AttrValue::VarLenString("running".into()));
    fb.set_attr("status_time", AttrValue::F64(f64::NAN));
    fb.set_attr("status_message", AttrValue::VarLenString(String::new()));
    for (k, v) in attributes {
        fb.set_attr(k, AttrValue::VarLenString(v.clone()));
    }

    extensible(fb.create_dataset("time"), None);
    for (name, w) in [
        ("q", layout.coordinates.len()),
        ("u", layout.velocities.len()),
        ("lambda", layout.multipliers.len()),
    ] {
        extensible(fb.create_dataset(name), Some(w));
    }
    let fixed: [(&str, &[&str]); 3] = [
        ("energy", &ENERGY_COLUMNS),
        ("drift", &DRIFT_COLUMNS),
        ("step", &STEP_COLUMNS),
    ];
    for (name, cols) in fixed {
        let d = fb.create_dataset(name);
        extensible(d, Some(cols.len()));
        d.set_attr("columns", strings(cols));
    }
    for (name, list) in [
        ("coordinates", &layout.coordinates),
        ("velocities", &layout.velocities),
        ("multipliers", &layout.multipliers),
    ] {
        let v: Vec<&str> = list.iter().map(String::as_str).collect();
        fb.create_dataset(name).with_vlen_strings(&v);
    }

    let mut g = fb.create_group("signals");
    let names: Vec<&str> = layout.signals.iter().map(|s| s.name.as_str()).collect();
    g.set_attr("names", strings(&names));
    for s in &layout.signals {
        let d = g.create_dataset(&s.name);
        extensible(d, Some(s.components.len()));
        d.set_attr("unit", AttrValue::VarLenString(s.unit.clone()));
        let comps: Vec<&str> = s.components.iter().map(String::as_str).collect();
        d.set_attr("components", strings(&comps));
    }
    fb.add_group(g.finish());
    fb
}

/// Streams a results file to a temporary sibling of `path` (no whole-file buffer in memory) and
/// renames it over `path`, so that readers only ever see the old or the new complete file.
pub(crate) fn write_atomically(path: &Path, fb: FileBuilder) -> Result<(), ResultsError> {
    if let Some(kind) = crate::output_safety::unsafe_target_kind(path) {
        return Err(ResultsError::UnsafeTarget {
            path: path.to_path_buf(),
            kind,
        });
    }
    let tmp = super::temporary_sibling(path);
    let result = std::fs::File::create(&tmp)
        .map_err(hdf5_pure::Error::Io)
        .and_then(|f| fb.finish_to(f));
    if let Err(e) = result {
        let _ = std::fs::remove_file(&tmp);
        return Err(match e {
            hdf5_pure::Error::Io(source) => ResultsError::Io { path: tmp, source },
            e => hdf5_error(path, "/", e),
        });
    }
    std::fs::rename(&tmp, path).map_err(|source| {
        let _ = std::fs::remove_file(&tmp);
        ResultsError::Io {
            path: path.to_path_buf(),
            source,
        }
    })
}

/// What [`decode`] returns.
pub(crate) struct Decoded {
    pub layout: ResultsLayout,
    pub status: RunStatus,
    pub attributes: Vec<(String, String)>,
    pub columns: Columns,
}

/// Reader of one file: keeps the path for error messages.
struct Reader<'a> {
    path: &'a Path,
    file: File,
    /// Size of the file in bytes: no dataset of ours can hold more (no compression is written),
    /// so a larger shape is a corrupted header, refused before any allocation.
    file_len: u64,
}

impl Reader<'_> {
    fn dataset(&self, name: &str) -> Result<Dataset, ResultsError> {
        match self.file.dataset(name) {
            Ok(d) => Ok(d),
            Err(hdf5_pure::Error::Format(FormatError::PathNotFound(_))) => {
                Err(ResultsError::MissingDataset {
                    path: self.path.to_path_buf(),
                    dataset: name.to_string(),
                })
            }
            Err(e) => Err(hdf5_error(self.path, name, e)),
        }
    }

    fn wrong(&self, name: &str, expected: String, found: String) -> ResultsError {
        ResultsError::WrongShape {
            path: self.path.to_path_buf(),
            dataset: name.to_string(),
            expected,
            found,
        }
    }

    /// A float64 dataset `[rows, cols]` (or `[rows]` when `cols` is `None`), flattened row-major.
    /// A matrix may hold more rows than `rows` (a run killed during a flush appends `time` last):
    /// only the first `rows` are returned. A matrix without columns may have any row count.
    fn matrix(
        &self,
        name: &str,
        rows: usize,
        cols: Option<usize>,
    ) -> Result<Vec<f64>, ResultsError> {
        let d = self.dataset(name)?;
        let shape = d.shape().map_err(|e| hdf5_error(self.path, name, e))?;
        // version 1: `[n, cols]` float64; version 2: `[n]` of rows `float64[cols]`
        let dtype = d.dtype().map_err(|e| hdf5_error(self.path, name, e))?;
        let rows_of = |c: usize| match dtype {
            DType::Array(ref base, ref dims) => {
                **base == DType::F64 && dims.as_slice() == [c as u32]
            }
            _ => false,
        };
        let (fits, is_rows) = match (cols, shape.as_slice()) {
            (None, &[n]) => (n == rows as u64 && dtype == DType::F64, false),
            (Some(c), &[n, w]) => (
                dtype == DType::F64 && w == c as u64 && (n >= rows as u64 || c == 0),
                false,
            ),
            (Some(c), &[n]) => (rows_of(c) && n >= rows as u64, true),
            _ => (false, false),
        };
        if !fits {
            let expected = match cols {
                Some(c) => format!("f64 shape [{rows} (or more), {c}]"),
                None => format!("f64 shape [{rows}]"),
            };
            return Err(self.wrong(name, expected, format!("{dtype} shape {shape:?}")));
        }
        let width = if is_rows { cols.unwrap_or(1) as u64 } else { 1 };
        let count = shape
            .iter()
            .try_fold(width, |a, &b| a.checked_mul(b))
            .filter(|&c| c.checked_mul(8).is_some_and(|b| b <= self.file_len));
        let wanted = rows as u64 * cols.unwrap_or(1) as u64;
        match count {
            _ if wanted == 0 => return Ok(Vec::new()),
            Some(_) => {}
            None => {
                return Err(self.wrong(
                    name,
                    format!("at most {} bytes of data (the file size)", self.file_len),
                    format!("shape {shape:?}"),
                ))
            }
        }
        let mut v = if is_rows {
            let bytes = d.read_raw().map_err(|e| hdf5_error(self.path, name, e))?;
            bytes
                .chunks_exact(8)
                .map(|b| f64::from_le_bytes([b[0], b[1], b[2], b[3], b[4], b[5], b[6], b[7]]))
                .collect()
        } else {
            d.read_f64().map_err(|e| hdf5_error(self.path, name, e))?
        };
        let total = width * shape.iter().product::<u64>();
        if v.len() as u64 != total {
            return Err(self.wrong(
                name,
                format!("{total} values"),
                format!("{} values", v.len()),
            ));
        }
        v.truncate(wanted as usize);
        Ok(v)
    }

    /// A one-dimensional string dataset.
    fn names(&self, name: &str) -> Result<Vec<String>, ResultsError> {
        let d = self.dataset(name)?;
        let shape = d.shape().map_err(|e| hdf5_error(self.path, name, e))?;
        if shape.len() != 1 {
            return Err(self.wrong(name, "shape [*]".into(), format!("shape {shape:?}")));
        }
        if shape[0] == 0 {
            return Ok(Vec::new());
        }
        // A variable-length string takes at least 16 bytes of heap reference in the file.
        if shape[0].saturating_mul(16) > self.file_len {
            return Err(self.wrong(
                name,
                format!("at most {} strings (the file size)", self.file_len / 16),
                format!("shape {shape:?}"),
            ));
        }
        let v = d
            .read_string()
            .map_err(|e| hdf5_error(self.path, name, e))?;
        if v.len() as u64 != shape[0] {
            return Err(self.wrong(
                name,
                format!("{} strings", shape[0]),
                format!("{} strings", v.len()),
            ));
        }
        Ok(v)
    }

    fn bad_attr(&self, object: &str, name: &str, expected: &str) -> ResultsError {
        let sep = if object.ends_with('/') { "" } else { "/" };
        ResultsError::BadAttribute {
            path: self.path.to_path_buf(),
            attribute: format!("{object}{sep}@{name}"),
            expected: expected.to_string(),
        }
    }
}

fn attr_str(
    r: &Reader,
    a: &HashMap<String, AttrValue>,
    object: &str,
    name: &str,
) -> Result<String, ResultsError> {
    a.get(name)
        .and_then(|v| v.as_str())
        .map(str::to_string)
        .ok_or_else(|| r.bad_attr(object, name, "string"))
}

fn attr_strings(
    r: &Reader,
    a: &HashMap<String, AttrValue>,
    object: &str,
    name: &str,
) -> Result<Vec<String>, ResultsError> {
    a.get(name)
        .and_then(|v| v.as_strings())
        .map(<[String]>::to_vec)
        .ok_or_else(|| r.bad_attr(object, name, "string array"))
}

/// Parses the bytes of a results file.
pub(crate) fn decode(path: &Path, bytes: Vec<u8>) -> Result<Decoded, ResultsError> {
    let file_len = bytes.len() as u64;
    let file = File::from_bytes(bytes).map_err(|e| hdf5_error(path, "/", e))?;
    let r = Reader {
        path,
        file,
        file_len,
    };
    let root = r
        .file
        .root()
        .attrs()
        .map_err(|e| hdf5_error(path, "/", e))?;
    match root.get("format").and_then(|v| v.as_str()) {
        Some(FORMAT_NAME) => {}
        Some(other) => {
            return Err(ResultsError::NotAResultsFile {
                path: path.to_path_buf(),
                reason: format!("root attribute format = '{other}', expected '{FORMAT_NAME}'"),
            })
        }
        None => {
            return Err(ResultsError::NotAResultsFile {
                path: path.to_path_buf(),
                reason: "no string root attribute 'format'".into(),
            })
        }
    }
    let version = root
        .get("format_version")
        .and_then(|v| v.as_i64())
        .ok_or_else(|| r.bad_attr("/", "format_version", "integer"))?;
    if !(1..=FORMAT_VERSION).contains(&version) {
        return Err(ResultsError::UnsupportedVersion {
            path: path.to_path_buf(),
            found: version,
            supported: FORMAT_VERSION,
        });
    }
    let model = attr_str(&r, &root, "/", "model")?;
    let status = read_status(&r, &root)?;
    let mut attributes: Vec<(String, String)> = root
        .iter()
        .filter(|(k, _)| !RESERVED_ATTRIBUTES.contains(&k.as_str()))
        .filter_map(|(k, v)| v.as_str().map(|s| (k.clone(), s.to_string())))
        .collect();
    attributes.sort();

    let coordinates = r.names("coordinates")?;
    let velocities = r.names("velocities")?;
    let multipliers = r.names("multipliers")?;

    let d = r.dataset("time")?;
    let shape = d.shape().map_err(|e| hdf5_error(path, "time", e))?;
    if shape.len() != 1 {
        return Err(r.wrong("time", "shape [n]".into(), format!("shape {shape:?}")));
    }
    let n = shape[0] as usize;
    let time = r.matrix("time", n, None)?;
    let q = r.matrix("q", n, Some(coordinates.len()))?;
    let u = r.matrix("u", n, Some(velocities.len()))?;
    let lambda = r.matrix("lambda", n, Some(multipliers.len()))?;
    let energy = r.matrix("energy", n, Some(ENERGY_COLUMNS.len()))?;
    let drift = r.matrix("drift", n, Some(DRIFT_COLUMNS.len()))?;
    let step = r.matrix("step", n, Some(STEP_COLUMNS.len()))?;

    let group = r.file.group("signals").map_err(|e| match e {
        hdf5_pure::Error::Format(FormatError::PathNotFound(_)) => ResultsError::MissingDataset {
            path: path.to_path_buf(),
            dataset: "signals".into(),
        },
        e => hdf5_error(path, "signals", e),
    })?;
    let gattrs = group.attrs().map_err(|e| hdf5_error(path, "signals", e))?;
    let names = attr_strings(&r, &gattrs, "/signals", "names")?;
    let mut signals = Vec::with_capacity(names.len());
    let mut blocks = Vec::with_capacity(names.len());
    for name in names {
        let full = format!("signals/{name}");
        let d = r.dataset(&full)?;
        let a = d.attrs().map_err(|e| hdf5_error(path, &full, e))?;
        let unit = attr_str(&r, &a, &full, "unit")?;
        let components = attr_strings(&r, &a, &full, "components")?;
        blocks.push(r.matrix(&full, n, Some(components.len()))?);
        signals.push(SignalSpec {
            name,
            unit,
            components,
        });
    }
    let layout = ResultsLayout {
        model,
        coordinates,
        velocities,
        multipliers,
        signals,
    };
    layout.check(path)?;
    let width = layout.signal_width();
    let mut concatenated = Vec::with_capacity(n * width);
    for i in 0..n {
        for (s, b) in layout.signals.iter().zip(&blocks) {
            let k = s.components.len();
            concatenated.extend_from_slice(&b[i * k..(i + 1) * k]);
        }
    }
    Ok(Decoded {
        layout,
        status,
        attributes,
        columns: Columns {
            time,
            q,
            u,
            lambda,
            energy,
            drift,
            step,
            signals: concatenated,
        },
    })
}

fn read_status(r: &Reader, root: &HashMap<String, AttrValue>) -> Result<RunStatus, ResultsError> {
    let name = attr_str(r, root, "/", "status")?;
    let time = || {
        root.get("status_time")
            .and_then(|v| v.as_f64())
            .ok_or_else(|| r.bad_attr("/", "status_time", "float"))
    };
    match name.as_str() {
        "running" => Ok(RunStatus::Running),
        "completed" => Ok(RunStatus::Completed),
        "interrupted" => Ok(RunStatus::Interrupted { t: time()? }),
        "failed" => Ok(RunStatus::Failed {
            t: time()?,
            message: attr_str(r, root, "/", "status_message")?,
        }),
        _ => Err(r.bad_attr(
            "/",
            "status",
            "'running', 'completed', 'interrupted' or 'failed'",
        )),
    }
}
