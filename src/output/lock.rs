//! The lock that keeps two runs off the same output: an exclusive advisory lock
//! (`flock`) on `NAME.h5.lock`, taken by rank 0 before anything of the output is created,
//! truncated or reopened, and held until the run ends. It covers every file named after the
//! output (`NAME.h5`, `NAME.h5.partial`, `NAME.ckpt.h5`, the PNG and the XDMF file).
//!
//! The lock file holds the process id of its owner, for the refusal message. It is removed
//! when the run ends (under the lock); a lock left by a run killed outright is not held by
//! anyone (the kernel releases it with the process), so the next run takes it.

use std::fs::{File, OpenOptions, TryLockError};
use std::io::{Read, Seek, Write};
use std::os::unix::fs::MetadataExt;
use std::path::{Path, PathBuf};

/// The lock file of an output (`NAME.h5` -> `NAME.h5.lock`).
pub fn lock_path(output: &Path) -> PathBuf {
    let mut s = output.as_os_str().to_owned();
    s.push(".lock");
    PathBuf::from(s)
}

/// A held lock on an output; released (and its file removed) when dropped.
#[derive(Debug)]
pub struct OutputLock {
    file: File,
    path: PathBuf,
}

/// Why a lock could not be taken.
#[derive(Debug)]
pub enum LockError {
    /// Another process holds it (its process id, when the lock file says).
    Held(Option<u32>),
    /// The lock file could not be created or locked.
    Io(std::io::Error),
}

impl OutputLock {
    /// Take the lock of `output`, without waiting.
    pub fn acquire(output: &Path) -> Result<Self, LockError> {
        let path = lock_path(output);
        // the file may be removed by the run that held it between our open and our lock:
        // then we hold a lock on a file nobody else sees, so try again on the new one
        for _ in 0..8 {
            let mut file = OpenOptions::new()
                .read(true)
                .write(true)
                .create(true)
                .truncate(false)
                .open(&path)
                .map_err(LockError::Io)?;
            match file.try_lock() {
                Ok(()) => {}
                Err(TryLockError::WouldBlock) => {
                    let mut text = String::new();
                    let _ = file.read_to_string(&mut text);
                    return Err(LockError::Held(text.trim().parse().ok()));
                }
                Err(TryLockError::Error(e)) => return Err(LockError::Io(e)),
            }
            let same = match (file.metadata(), std::fs::metadata(&path)) {
                (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
                _ => false,
            };
            if !same {
                continue;
            }
            file.set_len(0)
                .and_then(|_| file.rewind())
                .and_then(|_| write!(file, "{}", std::process::id()))
                .and_then(|_| file.flush())
                .map_err(LockError::Io)?;
            return Ok(OutputLock { file, path });
        }
        Err(LockError::Io(std::io::Error::other(
            "the lock file keeps being replaced by another run",
        )))
    }

    /// The lock file.
    pub fn path(&self) -> &Path {
        &self.path
    }
}

impl Drop for OutputLock {
    fn drop(&mut self) {
        // remove it while still holding the lock, and only if it is still ours
        let ours = match (self.file.metadata(), std::fs::metadata(&self.path)) {
            (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
            _ => false,
        };
        if ours {
            let _ = std::fs::remove_file(&self.path);
        }
        let _ = self.file.unlock();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_second_lock_on_the_same_output_is_refused_until_the_first_is_released() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("a.h5");
        let first = OutputLock::acquire(&out).unwrap();
        assert!(lock_path(&out).exists());
        match OutputLock::acquire(&out) {
            Err(LockError::Held(pid)) => assert_eq!(pid, Some(std::process::id())),
            other => panic!("a second lock was not refused: {other:?}"),
        }
        drop(first);
        assert!(!lock_path(&out).exists(), "the lock file is removed");
        let again = OutputLock::acquire(&out).unwrap();
        assert_eq!(again.path(), lock_path(&out));
    }
}
