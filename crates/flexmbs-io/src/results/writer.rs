//! [`ResultsWriter`]: appends output rows to a results file that is readable at any time.

use super::flusher::Flusher;
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
/// The appends of `push` run on a thread of the writer (`results-writer`), so the pushing thread
/// only hands over a buffer; it waits only when the previous batch is still being written and
/// the pending rows have reached [`MAX_PENDING_BYTES`] (memory: two batches at most).
/// The file on disk is readable at any time; a run that crashes or is killed leaves the rows
/// of the last flush with status `running`. Dropping the writer without `finish` writes nothing
/// more (as in a crash).
#[derive(Debug)]
pub struct ResultsWriter {
    path: PathBuf,
    layout: ResultsLayout,
    /// The thread appending to the file (`None` once finished).
    flusher: Option<Flusher>,
    /// Rows pushed since the last batch handed to the thread.
    pending: Columns,
    /// The buffer of the batch before (cleared), reused for the next one.
    spare: Columns,
    /// Rows handed to the thread (pushed before `pending`).
    flushed: usize,
    /// Wall time the pushing thread waited for the writing thread.
    waited: Duration,
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
        let flusher = Flusher::start(path, file, layout.signal_width())?;
        Ok(ResultsWriter {
            path: path.to_path_buf(),
            layout,
            flusher: Some(flusher),
            pending: Columns::default(),
            spare: Columns::default(),
            flushed: 0,
            waited: Duration::ZERO,
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
        let full = pending_bytes >= MAX_PENDING_BYTES;
        if full || self.last_write.elapsed() >= self.interval {
            // the interval alone does not wait for a batch still being written
            let idle = self.flusher.as_mut().is_none_or(Flusher::ready);
            if full || idle {
                self.dispatch()?;
            }
        }
        Ok(())
    }

    /// Appends the pending rows to the file now and waits until they are written (status stays
    /// `running`).
    pub fn flush(&mut self) -> Result<(), ResultsError> {
        self.dispatch()?;
        self.wait_for_writer()
    }

    /// Waits until the batch being written (if any) is in the file; reports its error.
    pub fn wait_for_writer(&mut self) -> Result<(), ResultsError> {
        let start = Instant::now();
        let Some(flusher) = self.flusher.as_mut() else {
            return Ok(());
        };
        let Some(done) = flusher.wait()? else {
            return Ok(());
        };
        self.waited += start.elapsed();
        self.write_time += done.took;
        self.writes += 1;
        self.interval = self.interval.max(done.took * INTERVAL_PER_WRITE_TIME);
        let mut rows = done.rows;
        match done.result {
            Ok(()) => {
                rows.clear();
                self.spare = rows;
                Ok(())
            }
            Err(e) => {
                // the rows go out again with the next batch; no dataset gets one twice
                rows.append(&self.pending);
                self.pending = rows;
                self.flushed = done.first;
                Err(e)
            }
        }
    }

    /// Flushes the pending rows and writes the final `status`; returns the path of the file.
    pub fn finish(mut self, status: &RunStatus) -> Result<PathBuf, ResultsError> {
        self.flush()?;
        let rows = self.rows();
        if let Some(f) = self.flusher.take() {
            f.finish(status, self.last_time, rows)?;
        }
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

    /// Number of file writes so far and the total wall time spent in them (on the writing
    /// thread; a batch still being written is not counted yet).
    pub fn write_statistics(&self) -> (usize, Duration) {
        (self.writes, self.write_time)
    }

    /// Wall time the pushing thread has waited for the writing thread (the cost of the results
    /// file to the run, apart from copying the rows).
    pub fn waiting_time(&self) -> Duration {
        self.waited
    }

    /// Hands the pending rows to the writing thread (after waiting for the batch before).
    fn dispatch(&mut self) -> Result<(), ResultsError> {
        self.wait_for_writer()?;
        self.last_write = Instant::now();
        if self.pending.rows() == 0 {
            return Ok(());
        }
        let Some(flusher) = self.flusher.as_mut() else {
            return Ok(());
        };
        let rows = std::mem::replace(&mut self.pending, std::mem::take(&mut self.spare));
        let n = rows.rows();
        flusher.send(rows, self.flushed)?;
        self.flushed += n;
        Ok(())
    }
}
