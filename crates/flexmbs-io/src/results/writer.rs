//! [`ResultsWriter`]: collects output rows and keeps a complete results file on disk.

use super::{h5, Columns, ResultsError, ResultsLayout, ResultsRow, RunStatus, RESERVED_ATTRIBUTES};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// Default wall-clock time between two rewrites of the results file.
pub const DEFAULT_FLUSH_INTERVAL: Duration = Duration::from_secs(2);

/// The flush interval is raised to this multiple of the duration of the last write, so that
/// writing takes at most about 1 / (1 + 10) of the run's wall time.
const INTERVAL_PER_WRITE_TIME: u32 = 10;

/// Writer of a results file.
///
/// hdf5-pure writes whole files only, so the writer keeps every row in memory and rewrites the
/// file atomically (temporary sibling + rename): at [`ResultsWriter::create`] (empty), from
/// [`ResultsWriter::push`] when the flush interval has passed since the last write, on
/// [`ResultsWriter::flush`] and on [`ResultsWriter::finish`]. The file on disk is therefore always
/// complete and readable; a run that crashes or is killed leaves the rows of the last write with
/// status `running`. Dropping the writer without `finish` writes nothing more (as in a crash).
#[derive(Debug)]
pub struct ResultsWriter {
    path: PathBuf,
    layout: ResultsLayout,
    attributes: Vec<(String, String)>,
    columns: Columns,
    interval: Duration,
    last_write: Instant,
    write_time: Duration,
    writes: usize,
}

impl ResultsWriter {
    /// Writes a valid (empty) file at once; `attributes` are stored as root string attributes
    /// (their names may not be one of [`RESERVED_ATTRIBUTES`] nor repeat).
    pub fn create(
        path: &Path,
        layout: ResultsLayout,
        attributes: &[(&str, &str)],
    ) -> Result<Self, ResultsError> {
        layout.check(path)?;
        let mut attrs: Vec<(String, String)> = Vec::with_capacity(attributes.len());
        for &(k, v) in attributes {
            if k.is_empty() || RESERVED_ATTRIBUTES.contains(&k) || attrs.iter().any(|(a, _)| a == k)
            {
                return Err(ResultsError::BadUserAttribute {
                    path: path.to_path_buf(),
                    name: k.to_string(),
                });
            }
            attrs.push((k.to_string(), v.to_string()));
        }
        let mut w = ResultsWriter {
            path: path.to_path_buf(),
            layout,
            attributes: attrs,
            columns: Columns::default(),
            interval: DEFAULT_FLUSH_INTERVAL,
            last_write: Instant::now(),
            write_time: Duration::ZERO,
            writes: 0,
        };
        w.write(&RunStatus::Running)?;
        Ok(w)
    }

    /// Appends one output row (checks every slice length against the layout -> error, never
    /// panic). Rewrites the file atomically when the wall time since the last write exceeds the
    /// flush interval (default [`DEFAULT_FLUSH_INTERVAL`], raised automatically to ten times the
    /// duration of the last write so that writing stays below ~10 % of the run time), so a
    /// crashed or killed run leaves a readable file.
    pub fn push(&mut self, row: &ResultsRow) -> Result<(), ResultsError> {
        let l = &self.layout;
        let checks: [(&'static str, usize, usize); 4] = [
            ("q", row.q.len(), l.coordinates.len()),
            ("u", row.u.len(), l.velocities.len()),
            ("lambda", row.lambda.len(), l.multipliers.len()),
            ("signals", row.signals.len(), l.signal_width()),
        ];
        for (field, found, expected) in checks {
            if found != expected {
                return Err(ResultsError::RowLength {
                    path: self.path.clone(),
                    t: row.t,
                    field,
                    found,
                    expected,
                });
            }
        }
        let c = &mut self.columns;
        c.time.push(row.t);
        c.q.extend_from_slice(row.q);
        c.u.extend_from_slice(row.u);
        c.lambda.extend_from_slice(row.lambda);
        c.energy.extend_from_slice(&row.energy);
        c.drift.extend_from_slice(&row.drift);
        c.step.extend_from_slice(&row.step);
        c.signals.extend_from_slice(row.signals);
        if self.last_write.elapsed() >= self.interval {
            self.write(&RunStatus::Running)?;
        }
        Ok(())
    }

    /// Writes the file now (status `running`).
    pub fn flush(&mut self) -> Result<(), ResultsError> {
        self.write(&RunStatus::Running)
    }

    /// Final write with `status`; returns the path of the file.
    pub fn finish(mut self, status: &RunStatus) -> Result<PathBuf, ResultsError> {
        self.write(status)?;
        Ok(self.path)
    }

    /// Number of rows pushed so far.
    pub fn rows(&self) -> usize {
        self.columns.rows()
    }

    /// The file written.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The layout of the rows.
    pub fn layout(&self) -> &ResultsLayout {
        &self.layout
    }

    /// Sets the minimum wall time between two writes from [`ResultsWriter::push`] (it is still
    /// raised automatically after slow writes).
    pub fn set_flush_interval(&mut self, interval: Duration) {
        self.interval = interval;
    }

    /// The current minimum wall time between two writes from [`ResultsWriter::push`].
    pub fn flush_interval(&self) -> Duration {
        self.interval
    }

    /// Number of file writes so far and the total wall time spent in them.
    pub fn write_statistics(&self) -> (usize, Duration) {
        (self.writes, self.write_time)
    }

    fn write(&mut self, status: &RunStatus) -> Result<(), ResultsError> {
        let start = Instant::now();
        let fb = h5::build(&self.layout, &self.attributes, status, &self.columns);
        h5::write_atomically(&self.path, fb)?;
        let took = start.elapsed();
        self.write_time += took;
        self.writes += 1;
        self.interval = self.interval.max(took * INTERVAL_PER_WRITE_TIME);
        self.last_write = Instant::now();
        Ok(())
    }
}
