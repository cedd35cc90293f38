//! The thread that appends rows to the results file, so that the run's thread only hands over a
//! buffer: at most one batch of rows is in flight while the next one fills (double buffering).

use super::stream::AppendFile;
use super::{Columns, ResultsError, RunStatus};
use std::path::{Path, PathBuf};
use std::sync::mpsc::{channel, Receiver, Sender, TryRecvError};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

enum Job {
    Append {
        rows: Columns,
        first: usize,
    },
    Finish {
        status: RunStatus,
        last_time: f64,
        rows: usize,
    },
}

/// A batch of rows the thread has handled.
#[derive(Debug)]
pub(crate) struct Appended {
    /// The rows (returned for reuse, or to be sent again after an error).
    pub rows: Columns,
    /// Index of the first of them in the run.
    pub first: usize,
    /// Time the append took.
    pub took: Duration,
    /// Its outcome.
    pub result: Result<(), ResultsError>,
}

enum Reply {
    Appended(Box<Appended>),
    Finished(Result<(), ResultsError>),
}

/// Handle of the appending thread.
pub(crate) struct Flusher {
    path: PathBuf,
    jobs: Sender<Job>,
    replies: Receiver<Reply>,
    /// A batch was sent and its reply not yet taken.
    busy: bool,
    /// A reply received by [`Flusher::ready`] and not yet taken.
    ready: Option<Appended>,
    handle: Option<JoinHandle<()>>,
}

impl std::fmt::Debug for Flusher {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Flusher")
            .field("path", &self.path)
            .field("busy", &self.busy)
            .finish()
    }
}

fn gone(path: &Path) -> ResultsError {
    ResultsError::Hdf5 {
        path: path.to_path_buf(),
        object: "/".into(),
        message: "the thread writing the results file has ended unexpectedly".into(),
    }
}

/// The body of the appending thread: appends batches until asked to finish.
fn serve(mut file: AppendFile, signal_width: usize, jobs: Receiver<Job>, replies: Sender<Reply>) {
    for job in jobs {
        match job {
            Job::Append { rows, first } => {
                let start = Instant::now();
                let result = file.append(&rows, first, signal_width);
                let reply = Appended {
                    rows,
                    first,
                    took: start.elapsed(),
                    result,
                };
                if replies.send(Reply::Appended(Box::new(reply))).is_err() {
                    return;
                }
            }
            Job::Finish {
                status,
                last_time,
                rows,
            } => {
                let _ = replies.send(Reply::Finished(file.finish(&status, last_time, rows)));
                return;
            }
        }
    }
}

impl Flusher {
    /// Starts the thread that owns `file`.
    pub(crate) fn start(
        path: &Path,
        file: AppendFile,
        signal_width: usize,
    ) -> Result<Self, ResultsError> {
        let (jobs, job_rx) = channel::<Job>();
        let (reply_tx, replies) = channel::<Reply>();
        let handle = std::thread::Builder::new()
            .name("results-writer".into())
            .spawn(move || serve(file, signal_width, job_rx, reply_tx))
            .map_err(|source| ResultsError::Io {
                path: path.to_path_buf(),
                source,
            })?;
        Ok(Flusher {
            path: path.to_path_buf(),
            jobs,
            replies,
            busy: false,
            ready: None,
            handle: Some(handle),
        })
    }

    /// True if no batch is in flight (its reply may still be waiting to be taken).
    pub(crate) fn ready(&mut self) -> bool {
        if !self.busy || self.ready.is_some() {
            return true;
        }
        match self.replies.try_recv() {
            Ok(Reply::Appended(a)) => {
                self.ready = Some(*a);
                true
            }
            Ok(Reply::Finished(_)) | Err(TryRecvError::Empty) => false,
            Err(TryRecvError::Disconnected) => true,
        }
    }

    /// Hands `rows` (rows `first ..` of the run) to the thread. Call [`Flusher::wait`] first.
    pub(crate) fn send(&mut self, rows: Columns, first: usize) -> Result<(), ResultsError> {
        debug_assert!(!self.busy);
        self.jobs
            .send(Job::Append { rows, first })
            .map_err(|_| gone(&self.path))?;
        self.busy = true;
        Ok(())
    }

    /// Waits for the batch in flight; `None` when there is none.
    pub(crate) fn wait(&mut self) -> Result<Option<Appended>, ResultsError> {
        if !self.busy {
            return Ok(None);
        }
        self.busy = false;
        if let Some(a) = self.ready.take() {
            return Ok(Some(a));
        }
        match self.replies.recv() {
            Ok(Reply::Appended(a)) => Ok(Some(*a)),
            _ => Err(gone(&self.path)),
        }
    }

    /// Writes the final status and closes the file (after [`Flusher::wait`]); joins the thread.
    pub(crate) fn finish(
        mut self,
        status: &RunStatus,
        last_time: f64,
        rows: usize,
    ) -> Result<(), ResultsError> {
        self.jobs
            .send(Job::Finish {
                status: status.clone(),
                last_time,
                rows,
            })
            .map_err(|_| gone(&self.path))?;
        let result = match self.replies.recv() {
            Ok(Reply::Finished(r)) => r,
            _ => Err(gone(&self.path)),
        };
        if let Some(h) = self.handle.take() {
            let _ = h.join();
        }
        result
    }
}
