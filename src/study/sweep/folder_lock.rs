//! The output folder's lock, `DIR/sweep.pid`: held while a sweep (or a merge) writes into the
//! folder, so that two of them (two `--resume`s of one folder, say) never write there at once.
//!
//! The file holds the pid of the process that has it and an advisory lock of the system on it
//! (`flock`, which the system lets go when the process ends, however it ends). It is removed
//! when the sweep ends, on an error too. A file left by a process that was killed is not
//! locked any more: it is taken over, with a note. Where the file system has no such locks, a
//! file whose pid is running (`/proc/PID`) keeps the folder.

use std::fs;
use std::io::{Read as _, Seek as _, Write as _};
use std::path::{Path, PathBuf};

use super::SweepError;
use super::folder_error::StoreError;

/// The lock file's name in the output folder.
pub const LOCK_FILE: &str = "sweep.pid";

/// The folder's lock, while it is held; dropping it removes the file and lets the lock go.
#[derive(Debug)]
pub struct FolderLock {
    path: PathBuf,
    _file: fs::File,
}

impl Drop for FolderLock {
    fn drop(&mut self) {
        let _ = fs::remove_file(&self.path);
    }
}

impl FolderLock {
    /// Claims `dir` as wovenform's output folder ([`crate::files::claim_folder`]: a folder
    /// of the user's is refused) and takes its lock; with a note when the lock of a process
    /// that no longer runs was taken over. A folder held by a running sweep: bad input.
    pub fn take(dir: &Path) -> Result<(FolderLock, Option<String>), SweepError> {
        crate::files::claim_folder(dir).map_err(|e| SweepError::BadInput(e.to_string()))?;
        let path = dir.join(LOCK_FILE);
        // The holder may remove the file between our open and our lock: then lock the new one.
        for _ in 0..8 {
            let mut file = fs::OpenOptions::new()
                .read(true)
                .write(true)
                .create(true)
                .truncate(false)
                .open(&path)
                .map_err(|e| SweepError::Folder(StoreError::io(&path, "write")(e)))?;
            let mut held_by = String::new();
            let _ = file.read_to_string(&mut held_by);
            let held_by = held_by.trim().to_string();
            let locked = match file.try_lock() {
                Ok(()) => true,
                Err(fs::TryLockError::WouldBlock) => false,
                // No locks on this file system: the pid in the file decides.
                Err(fs::TryLockError::Error(_)) => !running(&held_by),
            };
            if !locked {
                return Err(in_use(dir, &path, &held_by));
            }
            if !same_file(&file, &path) {
                continue;
            }
            let note = (!held_by.is_empty()).then(|| {
                format!(
                    "{}: took over the lock of pid {held_by}, which is no longer running",
                    path.display()
                )
            });
            let written = file
                .set_len(0)
                .and_then(|_| file.rewind())
                .and_then(|_| writeln!(file, "{}", std::process::id()));
            written.map_err(|e| SweepError::Folder(StoreError::io(&path, "write")(e)))?;
            return Ok((FolderLock { path, _file: file }, note));
        }
        Err(in_use(dir, &path, "unknown"))
    }
}

fn in_use(dir: &Path, path: &Path, pid: &str) -> SweepError {
    SweepError::BadInput(format!(
        "{}: another sweep is writing into this folder (pid {pid}, its lock {}): wait for it to end, or choose another --out",
        dir.display(),
        path.display()
    ))
}

/// A process of that pid runs (Linux: `/proc/PID` exists).
fn running(pid: &str) -> bool {
    pid.parse::<u32>()
        .is_ok_and(|p| Path::new("/proc").join(p.to_string()).exists())
}

/// The open file is still the one at `path` (not removed, nor replaced, since it was opened).
fn same_file(file: &fs::File, path: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt as _;
        match (file.metadata(), fs::metadata(path)) {
            (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
            _ => false,
        }
    }
    #[cfg(not(unix))]
    {
        let _ = file;
        path.exists()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_held_folder_is_refused_and_a_stale_lock_taken_over() {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path().join("out");
        let (lock, note) = FolderLock::take(&dir).unwrap();
        assert_eq!(note, None);
        let pid = std::process::id().to_string();
        let text = fs::read_to_string(dir.join(LOCK_FILE)).unwrap();
        assert_eq!(text.trim(), pid);
        let e = FolderLock::take(&dir).unwrap_err();
        assert!(e.is_bad_input());
        let e = e.to_string();
        assert!(
            e.contains(&dir.display().to_string()) && e.contains(&pid),
            "{e}"
        );
        drop(lock);
        assert!(!dir.join(LOCK_FILE).exists(), "removed when let go");
        // A file left by a killed process: not locked, taken over.
        fs::write(dir.join(LOCK_FILE), "4000000000\n").unwrap();
        let (_lock, note) = FolderLock::take(&dir).unwrap();
        assert!(note.unwrap().contains("pid 4000000000"));
        assert!(!running("4000000000") && running(&pid));
    }
}
