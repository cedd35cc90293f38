//! Output targets that are safe to write: a file written by a rename over its path must be absent
//! or a regular file (a symlink, device node, FIFO or folder there is refused, never replaced), and
//! an output folder is locked by the run writing into it.

use std::fs::OpenOptions;
use std::io::Write;
use std::path::{Path, PathBuf};

/// What sits at `path` if it is not a regular file (`None`: absent or a regular file).
pub fn unsafe_target_kind(path: &Path) -> Option<&'static str> {
    let meta = std::fs::symlink_metadata(path).ok()?;
    let t = meta.file_type();
    if t.is_file() {
        return None;
    }
    Some(if t.is_symlink() {
        "a symbolic link"
    } else if t.is_dir() {
        "a folder"
    } else {
        "a device, FIFO or socket"
    })
}

/// Name of the lock file in an output folder.
pub const LOCK_FILE: &str = ".flexmbs-run.lock";

/// A lock on an output folder held by this process; the lock file is removed on drop.
#[derive(Debug)]
pub struct OutputLock {
    path: PathBuf,
}

/// Why an output folder cannot be locked.
#[derive(Debug, thiserror::Error)]
pub enum LockError {
    /// Another live process holds the lock.
    #[error("{} is in use by another flexmbs run (process {pid}); choose another output folder or wait for it", folder.display())]
    InUse {
        /// The output folder.
        folder: PathBuf,
        /// The process writing into it.
        pid: u32,
    },
    /// The lock file cannot be written.
    #[error("{}: cannot create the lock file: {source}", path.display())]
    Io {
        /// The lock file.
        path: PathBuf,
        /// Cause.
        source: std::io::Error,
    },
}

impl OutputLock {
    /// Locks `folder` (which must exist) for this process: creates `folder/.flexmbs-run.lock`
    /// with the process id. A lock of a process that no longer runs (killed with SIGKILL) is taken
    /// over; one of a live process is refused with its id. Liveness is checked through `/proc`
    /// (Linux); where that does not exist, an existing lock is taken over.
    pub fn acquire(folder: &Path) -> Result<Self, LockError> {
        let path = folder.join(LOCK_FILE);
        let io = |source| LockError::Io {
            path: path.clone(),
            source,
        };
        for _ in 0..2 {
            match OpenOptions::new().write(true).create_new(true).open(&path) {
                Ok(mut f) => {
                    write!(f, "{}", std::process::id()).map_err(io)?;
                    return Ok(Self { path });
                }
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {
                    let pid = std::fs::read_to_string(&path)
                        .ok()
                        .and_then(|s| s.trim().parse::<u32>().ok());
                    if let Some(pid) = pid.filter(|p| process_alive(*p)) {
                        return Err(LockError::InUse {
                            folder: folder.to_path_buf(),
                            pid,
                        });
                    }
                    // stale (or unreadable) lock: remove and retry once
                    std::fs::remove_file(&path).map_err(io)?;
                }
                Err(e) => return Err(io(e)),
            }
        }
        Err(io(std::io::Error::other("the lock file reappeared")))
    }
}

impl Drop for OutputLock {
    fn drop(&mut self) {
        let _ = std::fs::remove_file(&self.path);
    }
}

/// `pid` runs (and is not this process, whose stale lock would be its own).
fn process_alive(pid: u32) -> bool {
    pid != std::process::id()
        && Path::new("/proc").is_dir()
        && Path::new(&format!("/proc/{pid}")).exists()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dir(name: &str) -> PathBuf {
        crate::test_tools::scratch_dir(&format!("lock-{name}"))
    }

    #[test]
    fn lock_refuses_a_live_holder_and_takes_over_a_stale_one() {
        let d = dir("live");
        // a live process (a child that sleeps) holds the lock
        let mut child = std::process::Command::new("sleep")
            .arg("5")
            .spawn()
            .unwrap();
        std::fs::write(d.join(LOCK_FILE), child.id().to_string()).unwrap();
        let err = OutputLock::acquire(&d).unwrap_err();
        assert!(
            matches!(err, LockError::InUse { pid, .. } if pid == child.id()),
            "{err}"
        );
        assert!(err.to_string().contains("another flexmbs run"));
        child.kill().unwrap();
        child.wait().unwrap();
        // now stale: taken over, and released on drop
        let lock = OutputLock::acquire(&d).unwrap();
        let held = std::fs::read_to_string(d.join(LOCK_FILE)).unwrap();
        assert_eq!(held, std::process::id().to_string());
        drop(lock);
        assert!(!d.join(LOCK_FILE).exists());
    }

    #[cfg(unix)]
    #[test]
    fn non_regular_targets_are_named() {
        let d = dir("kinds");
        let f = d.join("file");
        std::fs::write(&f, "x").unwrap();
        assert_eq!(unsafe_target_kind(&f), None);
        assert_eq!(unsafe_target_kind(&d.join("absent")), None);
        std::os::unix::fs::symlink(&f, d.join("link")).unwrap();
        assert_eq!(unsafe_target_kind(&d.join("link")), Some("a symbolic link"));
        assert_eq!(unsafe_target_kind(&d), Some("a folder"));
        assert_eq!(
            unsafe_target_kind(Path::new("/dev/null")),
            Some("a device, FIFO or socket")
        );
    }
}
