//! Simulation results: the HDF5 results file, its reader, CSV export, plots and the ParaView
//! animation of a run.
//!
//! A run writes one results file with a [`ResultsWriter`]: every output row (time, coordinates,
//! velocities, multipliers, energies, constraint drift, step statistics and the requested signals)
//! is kept in memory and the whole file is rewritten atomically (temporary sibling + rename) at
//! most every flush interval, so a crashed or killed run always leaves a complete, readable file
//! whose root attribute `status` is `"running"`. [`ResultsWriter::finish`] writes the final file
//! with the run's [`RunStatus`]. The layout is documented in `docs/formats/results.md`.
//!
//! [`read_results`] reads such a file (finished or not) into [`Results`], whose columns are
//! addressed by series names (`"q/rod.R_x"`, `"energy/total"`, `"tip.position.z"`, ...) for
//! [`write_csv`] and [`plot_series`]. [`AnimationWriter`] writes one `.vtu` per output frame and a
//! `.pvd` collection for ParaView.

mod animation;
mod animation_parts;
mod export;
mod flusher;
mod h5;
mod stream;
mod writer;

pub use animation::{AnimationBody, AnimationWriter};
pub use animation_parts::{AnimationPart, VTK_LINE, VTK_QUAD, VTK_VERTEX};
pub use export::{plot_series, write_csv};
pub use writer::{ResultsWriter, DEFAULT_FLUSH_INTERVAL, MAX_PENDING_BYTES};

use std::path::{Path, PathBuf};
use thiserror::Error;

/// Value of the root attribute `format` that marks a flexmbs results file.
pub const FORMAT_NAME: &str = "flexmbs-results";

/// Version of the on-disk layout written by [`ResultsWriter`]; [`read_results`] reads this
/// version and every older one (1: fixed-size datasets; 2: extensible datasets grown by in-place
/// appends, which may hold more rows than `time` after a killed run).
pub const FORMAT_VERSION: i64 = 2;

/// Column names of the `energy` dataset (order of `flexmbs_core::system::Energy`).
pub const ENERGY_COLUMNS: [&str; 4] = ["kinetic", "gravity", "elastic", "springs"];

/// Column names of the `drift` dataset: max |g| and max |G u + g_t|.
pub const DRIFT_COLUMNS: [&str; 2] = ["position", "velocity"];

/// Column names of the `step` dataset: step size, Newton iterations, final residual.
pub const STEP_COLUMNS: [&str; 3] = ["h", "iterations", "residual"];

/// Root attribute names written by flexmbs itself; user attributes may not use them.
pub const RESERVED_ATTRIBUTES: [&str; 6] = [
    "format",
    "format_version",
    "model",
    "status",
    "status_time",
    "status_message",
];

/// One requested output signal with its components, e.g. `tip.position` in `m` with components
/// `x`, `y`, `z`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SignalSpec {
    /// Signal name (non-empty, no `/`), unique within a layout.
    pub name: String,
    /// Unit of all components, e.g. `m` (may be empty).
    pub unit: String,
    /// Component names (at least one, unique within the signal).
    pub components: Vec<String>,
}

/// What one output row contains: the names of every column of a results file.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct ResultsLayout {
    /// Model name.
    pub model: String,
    /// Names of the `nq` generalized coordinates, e.g. `rod.R_x`, `rod.q_f3`.
    pub coordinates: Vec<String>,
    /// Names of the `nu` velocities.
    pub velocities: Vec<String>,
    /// Names of the `nc` Lagrange multipliers, e.g. `pin.row2`.
    pub multipliers: Vec<String>,
    /// Requested output signals (frame positions and velocities, node displacements, ...).
    pub signals: Vec<SignalSpec>,
}

impl ResultsLayout {
    /// Total number of signal components (the length of [`ResultsRow::signals`]).
    pub fn signal_width(&self) -> usize {
        self.signals.iter().map(|s| s.components.len()).sum()
    }

    /// Checks that the layout can be stored and addressed: signal names non-empty, free of `/`
    /// and unique, every signal with at least one component, component names unique.
    pub fn check(&self, path: &Path) -> Result<(), ResultsError> {
        let bad = |message: String| ResultsError::InvalidLayout {
            path: path.to_path_buf(),
            message,
        };
        let mut seen = std::collections::HashSet::new();
        for s in &self.signals {
            if s.name.is_empty() || s.name.contains('/') || s.name == "." || s.name == ".." {
                return Err(bad(format!(
                    "signal name {:?} must be non-empty and contain no '/'",
                    s.name
                )));
            }
            if !seen.insert(s.name.as_str()) {
                return Err(bad(format!("signal '{}' appears twice", s.name)));
            }
            if s.components.is_empty() {
                return Err(bad(format!("signal '{}' has no components", s.name)));
            }
            let mut comps = std::collections::HashSet::new();
            for c in &s.components {
                if !comps.insert(c.as_str()) {
                    return Err(bad(format!(
                        "signal '{}' has component '{c}' twice",
                        s.name
                    )));
                }
            }
        }
        Ok(())
    }
}

/// One output row handed to [`ResultsWriter::push`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ResultsRow<'a> {
    /// Time.
    pub t: f64,
    /// Generalized coordinates, `nq` values in layout order.
    pub q: &'a [f64],
    /// Velocities, `nu` values.
    pub u: &'a [f64],
    /// Lagrange multipliers, `nc` values.
    pub lambda: &'a [f64],
    /// Kinetic, gravity, elastic and spring energy (`flexmbs_core::system::Energy` order).
    pub energy: [f64; 4],
    /// Constraint drift: max |g| and max |G u + g_t|.
    pub drift: [f64; 2],
    /// Step statistics: step size h, Newton iterations, final residual.
    pub step: [f64; 3],
    /// All signal components concatenated in layout order.
    pub signals: &'a [f64],
}

/// How a run ended (or that it has not ended yet).
#[derive(Debug, Clone, PartialEq)]
pub enum RunStatus {
    /// The run is still going, or was killed before it could record an end.
    Running,
    /// The run reached its end time.
    Completed,
    /// The run was stopped on request at time `t`.
    Interrupted {
        /// Time reached.
        t: f64,
    },
    /// The run failed at time `t`.
    Failed {
        /// Time of the failure.
        t: f64,
        /// What went wrong.
        message: String,
    },
}

impl RunStatus {
    /// The value of the root attribute `status`.
    pub fn name(&self) -> &'static str {
        match self {
            RunStatus::Running => "running",
            RunStatus::Completed => "completed",
            RunStatus::Interrupted { .. } => "interrupted",
            RunStatus::Failed { .. } => "failed",
        }
    }
}

/// Errors of writing, reading and exporting results. Every variant names the file.
#[derive(Debug, Error)]
pub enum ResultsError {
    /// The output path holds something that is not a regular file (a symlink, device, FIFO or
    /// folder): it is not replaced.
    #[error("{path}: is {kind}; refusing to replace it (choose another output path)")]
    UnsafeTarget {
        /// The path.
        path: PathBuf,
        /// What is there.
        kind: &'static str,
    },
    /// The file could not be read or written at the operating-system level.
    #[error("{path}: {source}")]
    Io {
        /// File concerned.
        path: PathBuf,
        /// Underlying error.
        source: std::io::Error,
    },
    /// The HDF5 layer rejected the file (not HDF5, truncated, corrupted) or an object in it.
    #[error("{path}: HDF5 error at '{object}': {message}")]
    Hdf5 {
        /// File concerned.
        path: PathBuf,
        /// HDF5 object (dataset, group or `/`) being accessed.
        object: String,
        /// Message of the HDF5 layer.
        message: String,
    },
    /// The file is HDF5 but not a flexmbs results file.
    #[error("{path}: not a flexmbs results file ({reason})")]
    NotAResultsFile {
        /// File concerned.
        path: PathBuf,
        /// What was found instead.
        reason: String,
    },
    /// The file was written with a layout version this program does not read.
    #[error(
        "{path}: unsupported format_version {found} (this program reads versions 1 to {supported})"
    )]
    UnsupportedVersion {
        /// File concerned.
        path: PathBuf,
        /// Version found in the file.
        found: i64,
        /// Version this program reads.
        supported: i64,
    },
    /// A required dataset or group is missing.
    #[error("{path}: missing dataset '{dataset}'")]
    MissingDataset {
        /// File concerned.
        path: PathBuf,
        /// Full dataset path inside the file.
        dataset: String,
    },
    /// A required attribute is missing or has the wrong type or value.
    #[error("{path}: missing or ill-typed attribute '{attribute}' ({expected} expected)")]
    BadAttribute {
        /// File concerned.
        path: PathBuf,
        /// Object path and attribute name, e.g. `/@status`.
        attribute: String,
        /// Expected type or value.
        expected: String,
    },
    /// A dataset has a shape or element type inconsistent with the rest of the file.
    #[error("{path}: dataset '{dataset}' is {found}, expected {expected}")]
    WrongShape {
        /// File concerned.
        path: PathBuf,
        /// Full dataset path inside the file.
        dataset: String,
        /// Expected shape or type, e.g. `f64 [n, nq] = [*, 12]`.
        expected: String,
        /// Shape or type found.
        found: String,
    },
    /// The layout handed to the writer cannot be stored (duplicate or ill-formed names).
    #[error("{path}: invalid results layout: {message}")]
    InvalidLayout {
        /// File concerned.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
    /// A user attribute has a reserved name or appears twice.
    #[error("{path}: attribute '{name}' is reserved or given twice")]
    BadUserAttribute {
        /// File concerned.
        path: PathBuf,
        /// Attribute name.
        name: String,
    },
    /// A row handed to [`ResultsWriter::push`] has a slice of the wrong length.
    #[error("{path}: row at t = {t}: '{field}' has {found} values, the layout has {expected}")]
    RowLength {
        /// File concerned.
        path: PathBuf,
        /// Time of the row.
        t: f64,
        /// Row field: `q`, `u`, `lambda` or `signals`.
        field: &'static str,
        /// Length given.
        found: usize,
        /// Length of the layout.
        expected: usize,
    },
    /// No series of this name; `close` lists the most similar names.
    #[error("{path}: unknown series '{name}'{}", close_hint(.close))]
    UnknownSeries {
        /// Results file concerned.
        path: PathBuf,
        /// Name asked for.
        name: String,
        /// Most similar existing names (may be empty).
        close: Vec<String>,
    },
    /// No series was named for a plot.
    #[error(
        "{path}: no series to plot (name at least one; `flexmbs plot RESULTS --list` lists them)"
    )]
    NoSeries {
        /// Plot file asked for.
        path: PathBuf,
    },
    /// A plot file name has an extension other than `.png` or `.svg`.
    #[error("{path}: cannot plot to '.{extension}' (use a .png or .svg file name)")]
    UnsupportedPlotFormat {
        /// Plot file asked for.
        path: PathBuf,
        /// Extension found (empty if none).
        extension: String,
    },
    /// The plot could not be drawn (nothing finite to plot, backend failure).
    #[error(transparent)]
    Plot(#[from] crate::plot::PlotError),
    /// A VTK file of the animation could not be written.
    #[error(transparent)]
    Vtk(#[from] crate::vtk::VtkError),
    /// The data handed to the animation writer are inconsistent.
    #[error("{path}: invalid animation data: {message}")]
    InvalidAnimation {
        /// Animation file (`.pvd`) concerned.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
}

fn close_hint(close: &[String]) -> String {
    if close.is_empty() {
        " (`flexmbs plot RESULTS --list` lists the series)".into()
    } else {
        format!("; did you mean {}?", close.join(", "))
    }
}

/// The columns of a results file held in memory, row-major.
#[derive(Debug, Clone, Default, PartialEq)]
pub(crate) struct Columns {
    /// Times, `n`.
    pub time: Vec<f64>,
    /// `n x nq`.
    pub q: Vec<f64>,
    /// `n x nu`.
    pub u: Vec<f64>,
    /// `n x nc`.
    pub lambda: Vec<f64>,
    /// `n x 4`.
    pub energy: Vec<f64>,
    /// `n x 2`.
    pub drift: Vec<f64>,
    /// `n x 3`.
    pub step: Vec<f64>,
    /// `n x (sum of signal components)`, signals concatenated in layout order.
    pub signals: Vec<f64>,
}

impl Columns {
    fn rows(&self) -> usize {
        self.time.len()
    }

    /// Appends the rows of `other`.
    fn append(&mut self, other: &Columns) {
        self.time.extend_from_slice(&other.time);
        self.q.extend_from_slice(&other.q);
        self.u.extend_from_slice(&other.u);
        self.lambda.extend_from_slice(&other.lambda);
        self.energy.extend_from_slice(&other.energy);
        self.drift.extend_from_slice(&other.drift);
        self.step.extend_from_slice(&other.step);
        self.signals.extend_from_slice(&other.signals);
    }

    /// Empties every column, keeping the allocations.
    fn clear(&mut self) {
        for v in [
            &mut self.time,
            &mut self.q,
            &mut self.u,
            &mut self.lambda,
            &mut self.energy,
            &mut self.drift,
            &mut self.step,
            &mut self.signals,
        ] {
            v.clear();
        }
    }
}

/// The content of a results file, as read by [`read_results`].
#[derive(Debug, Clone, PartialEq)]
pub struct Results {
    /// Names of every column.
    pub layout: ResultsLayout,
    /// How the run ended (`Running` for a run that was killed or is still going).
    pub status: RunStatus,
    /// Output times, one per row.
    pub time: Vec<f64>,
    path: PathBuf,
    attributes: Vec<(String, String)>,
    columns: Columns,
}

/// Reads a results file written by [`ResultsWriter`], also one of a run that is still going,
/// was interrupted, failed or was killed (status `running`). Never panics on a damaged file.
pub fn read_results(path: &Path) -> Result<Results, ResultsError> {
    let bytes = crate::source_file::read(path).map_err(|source| ResultsError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    decode_results(path, bytes)
}

/// Decodes the bytes of a results file; `path` only labels errors. A panic of the HDF5 layer on
/// malformed input is caught and reported as [`ResultsError::Hdf5`].
pub fn decode_results(path: &Path, bytes: Vec<u8>) -> Result<Results, ResultsError> {
    let outcome =
        std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| h5::decode(path, bytes)));
    let decoded = match outcome {
        Ok(result) => result?,
        Err(payload) => {
            let message = payload
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| payload.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown panic".to_string());
            return Err(ResultsError::Hdf5 {
                path: path.to_path_buf(),
                object: "/".into(),
                message: format!("corrupted file (HDF5 decoder panicked: {message})"),
            });
        }
    };
    let h5::Decoded {
        layout,
        status,
        attributes,
        mut columns,
    } = decoded;
    Ok(Results {
        layout,
        status,
        time: std::mem::take(&mut columns.time),
        path: path.to_path_buf(),
        attributes,
        columns,
    })
}

/// Fixed columns of a results file: (series prefix, column names) in file order.
const FIXED_GROUPS: [(&str, &[&str]); 3] = [
    ("energy", &ENERGY_COLUMNS),
    ("drift", &DRIFT_COLUMNS),
    ("step", &STEP_COLUMNS),
];

impl Results {
    /// Number of output rows.
    pub fn rows(&self) -> usize {
        self.time.len()
    }

    /// The file this was read from.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// User attributes of the file (root string attributes other than the reserved ones), sorted
    /// by name.
    pub fn attributes(&self) -> &[(String, String)] {
        &self.attributes
    }

    /// The value of user attribute `name`.
    pub fn attribute(&self, name: &str) -> Option<&str> {
        self.attributes
            .iter()
            .find(|(k, _)| k == name)
            .map(|(_, v)| v.as_str())
    }

    /// Row `i` as written (`None` past the end).
    pub fn row(&self, i: usize) -> Option<ResultsRow<'_>> {
        if i >= self.rows() {
            return None;
        }
        let l = &self.layout;
        let c = &self.columns;
        fn slice(v: &[f64], i: usize, w: usize) -> &[f64] {
            &v[i * w..(i + 1) * w]
        }
        let e = slice(&c.energy, i, 4);
        let d = slice(&c.drift, i, 2);
        let s = slice(&c.step, i, 3);
        Some(ResultsRow {
            t: self.time[i],
            q: slice(&c.q, i, l.coordinates.len()),
            u: slice(&c.u, i, l.velocities.len()),
            lambda: slice(&c.lambda, i, l.multipliers.len()),
            energy: [e[0], e[1], e[2], e[3]],
            drift: [d[0], d[1]],
            step: [s[0], s[1], s[2]],
            signals: slice(&c.signals, i, l.signal_width()),
        })
    }

    /// Every plottable series name: `q/<coordinate>`, `u/<velocity>`, `lambda/<multiplier>`,
    /// `energy/kinetic|gravity|elastic|springs|total`, `drift/position|velocity`,
    /// `step/h|iterations|residual` and `<signal>.<component>` (e.g. `tip.position.z`).
    pub fn series_names(&self) -> Vec<String> {
        let l = &self.layout;
        let mut names = Vec::new();
        for (prefix, list) in [
            ("q", &l.coordinates),
            ("u", &l.velocities),
            ("lambda", &l.multipliers),
        ] {
            names.extend(list.iter().map(|n| format!("{prefix}/{n}")));
        }
        for (prefix, cols) in FIXED_GROUPS {
            names.extend(cols.iter().map(|c| format!("{prefix}/{c}")));
            if prefix == "energy" {
                names.push("energy/total".into());
            }
        }
        for s in &l.signals {
            names.extend(s.components.iter().map(|c| format!("{}.{c}", s.name)));
        }
        names
    }

    /// The values of series `name` (see [`Results::series_names`]), one per row. An unknown name
    /// is an error listing the closest existing names.
    pub fn series(&self, name: &str) -> Result<Vec<f64>, ResultsError> {
        let n = self.rows();
        let column = |data: &[f64], width: usize, j: usize| -> Vec<f64> {
            (0..n).map(|i| data[i * width + j]).collect()
        };
        let l = &self.layout;
        let c = &self.columns;
        if let Some((prefix, rest)) = name.split_once('/') {
            let lists: [(&str, &Vec<String>, &Vec<f64>); 3] = [
                ("q", &l.coordinates, &c.q),
                ("u", &l.velocities, &c.u),
                ("lambda", &l.multipliers, &c.lambda),
            ];
            for (p, list, data) in lists {
                if p == prefix {
                    if let Some(j) = list.iter().position(|x| x == rest) {
                        return Ok(column(data, list.len(), j));
                    }
                }
            }
            let fixed: [&Vec<f64>; 3] = [&c.energy, &c.drift, &c.step];
            for ((p, cols), data) in FIXED_GROUPS.iter().zip(fixed) {
                if *p == prefix {
                    if let Some(j) = cols.iter().position(|x| *x == rest) {
                        return Ok(column(data, cols.len(), j));
                    }
                }
            }
            if name == "energy/total" {
                return Ok((0..n)
                    .map(|i| c.energy[4 * i..4 * i + 4].iter().sum())
                    .collect());
            }
        }
        let width = l.signal_width();
        let mut offset = 0;
        for s in &l.signals {
            let component = name
                .strip_prefix(s.name.as_str())
                .and_then(|rest| rest.strip_prefix('.'));
            if let Some(k) = component.and_then(|comp| s.components.iter().position(|x| x == comp))
            {
                return Ok(column(&c.signals, width, offset + k));
            }
            offset += s.components.len();
        }
        Err(ResultsError::UnknownSeries {
            path: self.path.clone(),
            name: name.to_string(),
            close: close_names(name, &self.series_names()),
        })
    }
}

/// Up to five names most similar to `name`: small edit distance (case-insensitive) or sharing
/// the part after the last `/` or `.`.
fn close_names(name: &str, names: &[String]) -> Vec<String> {
    let lower = name.to_lowercase();
    let tail = |s: &str| -> String {
        s.rsplit(['/', '.'])
            .next()
            .unwrap_or(s)
            .to_lowercase()
            .to_string()
    };
    let name_tail = tail(name);
    let limit = (name.chars().count() / 3).max(2);
    let mut scored: Vec<(usize, &String)> = names
        .iter()
        .filter_map(|n| {
            let d = edit_distance(&lower, &n.to_lowercase());
            let related = d <= limit
                || (!name_tail.is_empty() && tail(n) == name_tail)
                || n.to_lowercase().contains(&lower);
            related.then_some((d, n))
        })
        .collect();
    scored.sort();
    scored.into_iter().take(5).map(|(_, n)| n.clone()).collect()
}

/// Levenshtein distance in characters.
fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut prev: Vec<usize> = (0..=b.len()).collect();
    let mut cur = vec![0; b.len() + 1];
    for (i, ca) in a.chars().enumerate() {
        cur[0] = i + 1;
        for (j, &cb) in b.iter().enumerate() {
            let sub = prev[j] + usize::from(ca != cb);
            cur[j + 1] = sub.min(prev[j + 1] + 1).min(cur[j] + 1);
        }
        std::mem::swap(&mut prev, &mut cur);
    }
    prev[b.len()]
}

/// `dir/.name.tmp-<pid>-<k>`: a temporary file next to `path` (same file system, so the rename
/// that replaces `path` by it is atomic).
pub(crate) fn temporary_sibling(path: &Path) -> PathBuf {
    static COUNTER: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
    let k = COUNTER.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "results".into());
    path.with_file_name(format!(".{name}.tmp-{}-{k}", std::process::id()))
}

#[cfg(test)]
mod tests {
    use super::{close_names, edit_distance};

    #[test]
    fn edit_distance_known_values() {
        assert_eq!(edit_distance("kitten", "sitting"), 3);
        assert_eq!(edit_distance("", "abc"), 3);
        assert_eq!(edit_distance("flaw", "lawn"), 2);
        assert_eq!(edit_distance("same", "same"), 0);
    }

    #[test]
    fn close_names_prefers_small_distance() {
        let names: Vec<String> = ["q/rod.R_x", "q/rod.R_y", "u/rod.R_x", "energy/total"]
            .iter()
            .map(|s| s.to_string())
            .collect();
        let c = close_names("q/rod.Rx", &names);
        assert_eq!(c[0], "q/rod.R_x");
        assert!(c.contains(&"q/rod.R_y".to_string()));
        assert!(!c.contains(&"energy/total".to_string()));
    }
}
