//! [`ResultsWriter`]: appends output rows to a results file that is readable at any time.

use super::stream::AppendFile;
use super::{Columns, ResultsError, ResultsLayout, ResultsRow, RunStatus, RESERVED_ATTRIBUTES};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// Default wall-clock time between two flushes of the results file.
pub const DEFAULT_FLUSH_INTERVAL: Duration = Duration::from_secs(2);

/// The flush interval is raised to this multiple of the duration of the last flush, so that
/// writing takes at most about 1 / (1 + 10) of the run's wall time.
const INTERVAL_PER_WRITE_TIME: u32 = 10;

/// Rows not yet flushed are flushed when they hold this many bytes, whatever the interval:
/// the writer's memory is bounded by this, not by the length of the run.
pub const MAX_PENDING_BYTES: usize = 8 << 20;

/// Writer of a results file.
///
/// The file (format version 2) is created at once, empty and valid, with chunked datasets that
/// grow along the time axis. The writer keeps only the rows pushed since the last flush and
/// appends them in place to the file (no rewrite): from [`ResultsWriter::push`] when the flush
/// interval has passed since the last flush or the pending rows reach [`MAX_PENDING_BYTES`], on
/// [`ResultsWriter::flush`] and on [`ResultsWriter::finish`], which also writes the final status.
/// The file on disk is readable at any time; a run that crashes or is killed leaves the rows
/// of the last flush with status `running`. Dropping the writer without `finish` writes nothing
/// more (as in a crash).
#[derive(Debug)]
pub struct ResultsWriter {
    path: PathBuf,
    layout: ResultsLayout,
    file: AppendFile,
    /// Rows pushed since the last complete flush.
    pending: Columns,
    /// Rows in the file (pushed before `pending`).
    flushed: usize,
    last_time: f64,
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
        let start = Instant::now();
        let file = AppendFile::create(path, &layout, &attrs)?;
        Ok(ResultsWriter {
            path: path.to_path_buf(),
            layout,
            file,
            pending: Columns::default(),
            flushed: 0,
            last_time: f64::NAN,
            interval: DEFAULT_FLUSH_INTERVAL,
            last_write: Instant::now(),
            write_time: start.elapsed(),
            writes: 1,
        })
    }

    /// Appends one output row (checks every slice length against the layout -> error, never
    /// panic). Flushes the pending rows to the file when the wall time since the last flush
    /// exceeds the flush interval (default [`DEFAULT_FLUSH_INTERVAL`], raised automatically to ten
    /// times the duration of the last flush so that writing stays below ~10 % of the run time) or
    /// when they reach [`MAX_PENDING_BYTES`], so a crashed or killed run leaves a readable file.
    /// If that flush fails, the rows are kept (the next successful flush writes them, no row
    /// twice) and the error is returned.
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
        let c = &mut self.pending;
        c.time.push(row.t);
        c.q.extend_from_slice(row.q);
        c.u.extend_from_slice(row.u);
        c.lambda.extend_from_slice(row.lambda);
        c.energy.extend_from_slice(&row.energy);
        c.drift.extend_from_slice(&row.drift);
        c.step.extend_from_slice(&row.step);
        c.signals.extend_from_slice(row.signals);
        self.last_time = row.t;
        let values = [
            &c.time, &c.q, &c.u, &c.lambda, &c.energy, &c.drift, &c.step, &c.signals,
        ]
        .iter()
        .map(|v| v.len())
        .sum::<usize>();
        let pending_bytes = 8 * values;
        if pending_bytes >= MAX_PENDING_BYTES || self.last_write.elapsed() >= self.interval {
            self.write()?;
        }
        Ok(())
    }

    /// Appends the pending rows to the file now (status stays `running`).
    pub fn flush(&mut self) -> Result<(), ResultsError> {
        self.write()
    }

    /// Flushes the pending rows and writes the final `status`; returns the path of the file.
    pub fn finish(mut self, status: &RunStatus) -> Result<PathBuf, ResultsError> {
        self.write()?;
        let rows = self.rows();
        self.file.finish(status, self.last_time, rows)?;
        Ok(self.path)
    }

    /// Number of rows pushed so far.
    pub fn rows(&self) -> usize {
        self.flushed + self.pending.rows()
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

    fn write(&mut self) -> Result<(), ResultsError> {
        let start = Instant::now();
        let width = self.layout.signal_width();
        self.file.append(&self.pending, self.flushed, width)?;
        self.flushed += self.pending.rows();
        self.pending.clear();
        let took = start.elapsed();
        self.write_time += took;
        self.writes += 1;
        self.interval = self.interval.max(took * INTERVAL_PER_WRITE_TIME);
        self.last_write = Instant::now();
        Ok(())
    }
}
