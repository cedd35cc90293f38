//! The results file on disk while a run writes it (format version 2): every row dataset is
//! chunked and extensible along the time axis, and new rows are appended in place, so the cost
//! of a flush is proportional to the rows it adds and the writer holds only the rows not yet
//! flushed (see `docs/formats/results.md`, "Writing while the run goes on").
//!
//! Order of a flush: every row dataset first, `time` last. `hdf5-pure` makes each append
//! crash-atomic (against this process dying; the file is synced when closed), so a run killed
//! in the middle of a flush leaves datasets that hold at least as many rows as `time`; the reader
//! takes the length of `time` as the number of rows.

use super::{h5, Columns, ResultsError, ResultsLayout, RunStatus};
use hdf5_pure::{AttrValue, File, FileAccessProperties, FileLocking, SyncPolicy};
use std::path::{Path, PathBuf};

/// One extensible row dataset: its path in the file, its width and the rows it holds.
#[derive(Debug)]
struct RowDataset {
    name: String,
    width: usize,
    /// Rows in the file (counted from the start of the run).
    written: usize,
}

/// An open results file whose row datasets grow by in-place appends.
#[derive(Debug)]
pub(crate) struct AppendFile {
    path: PathBuf,
    file: File,
    /// Row datasets in flush order (`time` last).
    datasets: Vec<RowDataset>,
    /// Signal offset of each `signals/<name>` dataset within a row of [`Columns::signals`].
    signal_offsets: Vec<usize>,
    /// Reused buffer of one signal's columns during a flush.
    scratch: Vec<f64>,
    /// Reused buffer of the little-endian bytes of one dataset's new rows.
    bytes: Vec<u8>,
}

fn edit_error(path: &Path, object: &str, e: hdf5_pure::Error) -> ResultsError {
    match e {
        hdf5_pure::Error::Io(source) => ResultsError::Io {
            path: path.to_path_buf(),
            source,
        },
        e => ResultsError::Hdf5 {
            path: path.to_path_buf(),
            object: object.to_string(),
            message: e.to_string(),
        },
    }
}

impl AppendFile {
    /// Writes an empty results file (status `running`) atomically and opens it for appending.
    pub(crate) fn create(
        path: &Path,
        layout: &ResultsLayout,
        attributes: &[(String, String)],
    ) -> Result<Self, ResultsError> {
        let fb = h5::build_extensible(layout, attributes);
        h5::write_atomically(path, fb)?;
        // No OS lock: the output folder is locked by the run, and a reader (h5py, `flexmbs
        // plot`) may open the file while the run goes on. No fsync per append: an append
        // reaches the operating system at once, so a killed process loses nothing written.
        let props = FileAccessProperties::new()
            .with_locking(FileLocking::Disabled)
            .with_sync_policy(SyncPolicy::OnClose);
        let file = File::open_rw_with_options(path, props).map_err(|e| edit_error(path, "/", e))?;
        let mut datasets = Vec::new();
        let fixed: [(&str, usize); 6] = [
            ("q", layout.coordinates.len()),
            ("u", layout.velocities.len()),
            ("lambda", layout.multipliers.len()),
            ("energy", super::ENERGY_COLUMNS.len()),
            ("drift", super::DRIFT_COLUMNS.len()),
            ("step", super::STEP_COLUMNS.len()),
        ];
        for (name, width) in fixed {
            datasets.push((name.to_string(), width));
        }
        let mut signal_offsets = Vec::with_capacity(layout.signals.len());
        let mut offset = 0;
        for s in &layout.signals {
            datasets.push((format!("signals/{}", s.name), s.components.len()));
            signal_offsets.push(offset);
            offset += s.components.len();
        }
        datasets.push(("time".to_string(), 1));
        Ok(AppendFile {
            path: path.to_path_buf(),
            file,
            datasets: datasets
                .into_iter()
                .map(|(name, width)| RowDataset {
                    name,
                    width,
                    written: 0,
                })
                .collect(),
            signal_offsets,
            scratch: Vec::new(),
            bytes: Vec::new(),
        })
    }

    /// Appends the rows `first .. first + pending.rows()` (`first` = rows flushed before) to
    /// every dataset that does not hold them yet, `time` last. A dataset that failed in an
    /// earlier flush is completed here, none gets a row twice.
    pub(crate) fn append(
        &mut self,
        pending: &Columns,
        first: usize,
        signal_width: usize,
    ) -> Result<(), ResultsError> {
        let m = pending.time.len();
        let nfixed = 6;
        for i in 0..self.datasets.len() {
            let d = &self.datasets[i];
            let skip = d.written.saturating_sub(first).min(m);
            if skip == m || d.width == 0 {
                continue;
            }
            let (w, name) = (d.width, d.name.clone());
            let data: &[f64] = match i {
                0 => &pending.q,
                1 => &pending.u,
                2 => &pending.lambda,
                3 => &pending.energy,
                4 => &pending.drift,
                5 => &pending.step,
                i if i + 1 == self.datasets.len() => &pending.time,
                i => {
                    let off = self.signal_offsets[i - nfixed];
                    self.scratch.clear();
                    for r in skip..m {
                        let row = &pending.signals[r * signal_width..(r + 1) * signal_width];
                        self.scratch.extend_from_slice(&row[off..off + w]);
                    }
                    &self.scratch
                }
            };
            let data = if (nfixed..self.datasets.len() - 1).contains(&i) {
                data
            } else {
                &data[skip * w..m * w]
            };
            let mut ds = self
                .file
                .dataset(&name)
                .map_err(|e| edit_error(&self.path, &name, e))?;
            self.bytes.clear();
            self.bytes.reserve(8 * data.len());
            for x in data {
                self.bytes.extend_from_slice(&x.to_le_bytes());
            }
            ds.append_raw(&self.bytes)
                .map_err(|e| edit_error(&self.path, &name, e))?;
            self.datasets[i].written = first + m;
        }
        Ok(())
    }

    /// Writes the final status (root attributes `status`, `status_time`, `status_message`),
    /// gives the datasets without columns their row count (shape `[n, 0]`) and closes the file
    /// (one commit and one fsync).
    pub(crate) fn finish(
        self,
        status: &RunStatus,
        last_time: f64,
        rows: usize,
    ) -> Result<(), ResultsError> {
        let (status_time, message) = match status {
            RunStatus::Running | RunStatus::Completed => (last_time, String::new()),
            RunStatus::Interrupted { t } => (*t, String::new()),
            RunStatus::Failed { t, message } => (*t, message.clone()),
        };
        let root = self.file.root();
        let err = |e| edit_error(&self.path, "/", e);
        root.set_attr("status", AttrValue::VarLenString(status.name().into()))
            .map_err(err)?;
        root.set_attr("status_time", AttrValue::F64(status_time))
            .map_err(err)?;
        root.set_attr("status_message", AttrValue::VarLenString(message))
            .map_err(err)?;
        for d in self.datasets.iter().filter(|d| d.width == 0 && rows > 0) {
            root.delete(&d.name).map_err(err)?;
            root.create_dataset(&d.name, |b| {
                b.with_f64_data(&[]).with_shape(&[rows as u64, 0]);
            })
            .map_err(err)?;
        }
        drop(root);
        self.file.close().map_err(err)
    }
}
