//! Writing a command's files safely: whole or not at all, and never over what the user gave.
//!
//! - [`write_atomic`] writes through a temporary file in the destination's folder and a
//!   rename: an interrupted or failed write (a full disk, a killed process) leaves the old
//!   file as it was, or no file, never half a file or a 0-byte one.
//! - [`claim_folder`] makes a folder wovenform's before any work: a new or empty one is
//!   marked with [`FOLDER_MARKER`]; one that holds files and no marker is the user's, and
//!   nothing is written there. One rule for every file of every command.
//! - [`check_outputs`] refuses, before any work, a set of outputs of which one is a file the
//!   command reads (the scene, a measured curve, a tool's STL: compared as files, through
//!   links and relative paths), and keeps those inputs from any later write of the process.

use std::io::Write as _;
use std::path::{Path, PathBuf};

/// The largest text file read as an input (a scene, a sweep, a measured curve), bytes.
pub const MAX_TEXT_BYTES: u64 = 64_000_000;

/// Reads a text input: a regular file (a named pipe, a device, a socket or a folder is refused
/// before it is opened, so nothing blocks), at most `max_bytes` long (enforced while reading,
/// whatever size the file reports), in UTF-8.
pub fn read_text(path: &Path, max_bytes: u64) -> std::io::Result<String> {
    use std::io::Read as _;
    let bytes = read_regular(path, max_bytes)?;
    let mut text = String::new();
    bytes.as_slice().read_to_string(&mut text)?;
    Ok(text)
}

/// The bytes of a regular file of at most `max_bytes` (see [`read_text`]).
pub fn read_regular(path: &Path, max_bytes: u64) -> std::io::Result<Vec<u8>> {
    use std::io::Read as _;
    let kind = std::fs::metadata(path)?.file_type();
    if !kind.is_file() {
        return Err(std::io::Error::other(format!(
            "it is {}, not a regular file: expected a file",
            kind_name(&kind)
        )));
    }
    let mut bytes = Vec::new();
    std::fs::File::open(path)?
        .take(max_bytes + 1)
        .read_to_end(&mut bytes)?;
    if bytes.len() as u64 > max_bytes {
        return Err(std::io::Error::other(format!(
            "it holds more than {max_bytes} bytes, the limit for this input: expected a smaller file"
        )));
    }
    Ok(bytes)
}

fn kind_name(kind: &std::fs::FileType) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if kind.is_fifo() {
            return "a named pipe (FIFO)";
        }
        if kind.is_char_device() || kind.is_block_device() {
            return "a device";
        }
        if kind.is_socket() {
            return "a socket";
        }
    }
    if kind.is_dir() {
        "a folder"
    } else {
        "not a regular file"
    }
}

/// Writes `bytes` to `path` whole: through a temporary file in the same folder, flushed to
/// disk, then renamed over `path`.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    write_atomic_with(path, |file| file.write_all(bytes))
}

/// Writes `path` whole with `fill`, which writes the contents into the temporary file: when
/// `fill` or the flush fails, `path` is left as it was and the temporary file is removed.
pub fn write_atomic_with(
    path: &Path,
    fill: impl FnOnce(&mut std::fs::File) -> std::io::Result<()>,
) -> std::io::Result<()> {
    if let Some(input) = protected_at(path) {
        return Err(std::io::Error::other(format!(
            "it is {} {}, which this command reads: not overwritten",
            input.what,
            input.path.display()
        )));
    }
    let dir = path.parent().filter(|d| !d.as_os_str().is_empty());
    let mut tmp = tempfile::NamedTempFile::new_in(dir.unwrap_or(Path::new(".")))?;
    fill(tmp.as_file_mut())?;
    tmp.as_file_mut().flush()?;
    // The temporary file is made private (0600); the file written is as any other the user
    // makes: 0666 less the umask.
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        let mode = 0o666 & !umask();
        tmp.as_file()
            .set_permissions(std::fs::Permissions::from_mode(mode))?;
    }
    tmp.as_file().sync_all()?;
    tmp.persist(path).map_err(|e| e.error)?;
    Ok(())
}

/// This process's umask, read from `/proc/self/status` (changing it to read it would race
/// with the threads that write files); 022 where it cannot be read.
#[cfg(unix)]
fn umask() -> u32 {
    static UMASK: std::sync::OnceLock<u32> = std::sync::OnceLock::new();
    *UMASK.get_or_init(|| {
        let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
        status
            .lines()
            .find_map(|l| l.strip_prefix("Umask:"))
            .and_then(|v| u32::from_str_radix(v.trim(), 8).ok())
            .unwrap_or(0o022)
    })
}

/// Whether `a` and `b` are the same file (same device and inode on Unix, the same canonical
/// path elsewhere); false when either does not exist.
pub fn same_file(a: &Path, b: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        match (std::fs::metadata(a), std::fs::metadata(b)) {
            (Ok(x), Ok(y)) => x.dev() == y.dev() && x.ino() == y.ino(),
            _ => false,
        }
    }
    #[cfg(not(unix))]
    {
        match (a.canonicalize(), b.canonicalize()) {
            (Ok(x), Ok(y)) => x == y,
            _ => false,
        }
    }
}

/// A file a command reads, and what it is to the user (for the message).
#[derive(Clone, Debug)]
pub struct Input {
    pub path: PathBuf,
    pub what: String,
}

impl Input {
    pub fn new(path: impl Into<PathBuf>, what: impl Into<String>) -> Input {
        Input {
            path: path.into(),
            what: what.into(),
        }
    }
}

/// The file that marks a folder as wovenform's output folder: written into a folder when a
/// command first writes there (a new or empty one). Files in a marked folder may be replaced
/// by a later command; a folder that holds anything else is not written into at all.
pub const FOLDER_MARKER: &str = ".wovenform";

const MARKER_TEXT: &str = "This folder holds what wovenform wrote: a later wovenform command may \
     replace its files. wovenform writes into no folder that holds other files and lacks this \
     one.\n";

/// Why a command's outputs were refused before it did any work.
#[derive(Debug, thiserror::Error)]
pub enum OverwriteError {
    #[error(
        "{}: writing there would overwrite {what} {}, which this command reads: it is not \
         overwritten; expected an output folder (--out) that holds none of the inputs",
        output.display(),
        input.display()
    )]
    Input {
        output: PathBuf,
        input: PathBuf,
        what: String,
    },
    #[error(
        "{}: the folder holds {}, which wovenform did not write (the folder has no \
         {FOLDER_MARKER} file): nothing is written there; expected a new or empty output folder \
         (--out), or one a wovenform command wrote",
        folder.display(),
        file.display()
    )]
    NotOurs { folder: PathBuf, file: PathBuf },
    #[error("{}: a folder of that name is in the way of the output file", output.display())]
    Folder { output: PathBuf },
    #[error("{}: not a folder: expected an output folder (--out) to write into", path.display())]
    NotAFolder { path: PathBuf },
    #[error("{}: cannot {action}: {source}", path.display())]
    Io {
        path: PathBuf,
        action: &'static str,
        #[source]
        source: std::io::Error,
    },
}

/// Refuses `outputs` (files a command will write) when one of them is one of `inputs` or a
/// folder. The inputs are also kept from being replaced by any later write of this process
/// ([`write_atomic`] refuses them), so that an output a command did not list cannot
/// overwrite them either.
pub fn check_outputs(outputs: &[PathBuf], inputs: &[Input]) -> Result<(), OverwriteError> {
    protect(inputs);
    for out in outputs {
        if let Some(input) = inputs.iter().find(|i| same_file(out, &i.path)) {
            return Err(OverwriteError::Input {
                output: out.clone(),
                input: input.path.clone(),
                what: input.what.clone(),
            });
        }
        if out.is_dir() {
            return Err(OverwriteError::Folder {
                output: out.clone(),
            });
        }
    }
    Ok(())
}

/// Makes `dir` a folder wovenform may write into, or says why not: a new folder is created
/// and marked ([`FOLDER_MARKER`]), as is an empty one; a marked folder is taken as it is, and
/// so is an output folder of an earlier version (its `sweep.lock` written by wovenform), which
/// is marked now. A folder holding anything else is refused, naming one of its files.
pub fn claim_folder(dir: &Path) -> Result<(), OverwriteError> {
    let io = |action: &'static str| {
        let path = dir.to_path_buf();
        move |source| OverwriteError::Io {
            path,
            action,
            source,
        }
    };
    if dir.exists() && !dir.is_dir() {
        return Err(OverwriteError::NotAFolder {
            path: dir.to_path_buf(),
        });
    }
    std::fs::create_dir_all(dir).map_err(io("create the output folder"))?;
    let marker = dir.join(FOLDER_MARKER);
    if marker.is_file() {
        return Ok(());
    }
    let first = std::fs::read_dir(dir)
        .map_err(io("read the output folder"))?
        .filter_map(Result::ok)
        .map(|e| e.file_name())
        .min();
    if let Some(name) = first.filter(|_| !earlier_output_folder(dir)) {
        return Err(OverwriteError::NotOurs {
            folder: dir.to_path_buf(),
            file: dir.join(name),
        });
    }
    write_atomic(&marker, MARKER_TEXT.as_bytes()).map_err(io("write into the output folder"))
}

/// Whether `dir` may be written into without refusal: it does not exist, is empty, or is
/// marked (see [`claim_folder`]); nothing is created.
pub fn folder_is_free(dir: &Path) -> bool {
    if !dir.exists() {
        return true;
    }
    dir.is_dir()
        && (dir.join(FOLDER_MARKER).is_file()
            || earlier_output_folder(dir)
            || std::fs::read_dir(dir).is_ok_and(|mut e| e.next().is_none()))
}

/// An output folder of a version before the marker: its `sweep.lock` says wovenform wrote it.
fn earlier_output_folder(dir: &Path) -> bool {
    let Ok(text) = read_text(&dir.join("sweep.lock"), 1 << 20) else {
        return false;
    };
    serde_json::from_str::<serde_json::Value>(&text)
        .is_ok_and(|v| v.get("program").and_then(|p| p.as_str()) == Some("wovenform"))
}

/// The inputs of this process's command, kept from being replaced.
static PROTECTED: std::sync::Mutex<Vec<Input>> = std::sync::Mutex::new(Vec::new());

fn protect(inputs: &[Input]) {
    let mut kept = PROTECTED.lock().unwrap_or_else(|e| e.into_inner());
    kept.extend(inputs.iter().cloned());
}

/// The protected input at `path`, if it is one.
fn protected_at(path: &Path) -> Option<Input> {
    let kept = PROTECTED.lock().unwrap_or_else(|e| e.into_inner());
    kept.iter().find(|i| same_file(path, &i.path)).cloned()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn special_files_are_refused_and_long_ones_cut_while_reading() {
        let e = read_text(Path::new("/dev/zero"), 1000).unwrap_err();
        assert!(e.to_string().contains("a device"), "{e}");
        let dir = tempfile::tempdir().unwrap();
        let e = read_text(dir.path(), 1000).unwrap_err();
        assert!(e.to_string().contains("a folder"), "{e}");
        let path = dir.path().join("a.toml");
        std::fs::write(&path, "x".repeat(1001)).unwrap();
        assert!(
            read_text(&path, 1000)
                .unwrap_err()
                .to_string()
                .contains("1000 bytes")
        );
        assert_eq!(read_text(&path, 1001).unwrap().len(), 1001);
    }

    #[test]
    fn a_failed_write_leaves_the_old_file_and_no_temporary_one() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("shear.png");
        std::fs::write(&path, b"old picture").unwrap();
        // The disk fills half-way through the new picture.
        let full = std::io::Error::from_raw_os_error(28);
        let e = write_atomic_with(&path, |f| {
            f.write_all(b"half a ne")?;
            Err(full)
        })
        .unwrap_err();
        assert_eq!(e.raw_os_error(), Some(28));
        assert_eq!(std::fs::read(&path).unwrap(), b"old picture");
        let left: Vec<_> = std::fs::read_dir(dir.path()).unwrap().collect();
        assert_eq!(left.len(), 1, "the temporary file is removed");
        write_atomic(&path, b"new").unwrap();
        assert_eq!(std::fs::read(&path).unwrap(), b"new");
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            let mode = std::fs::metadata(&path).unwrap().permissions().mode() & 0o777;
            assert_eq!(mode, 0o666 & !umask(), "as a file the user makes");
        }
    }

    #[test]
    fn an_input_reached_through_another_path_or_a_link_is_not_overwritten() {
        let dir = tempfile::tempdir().unwrap();
        let data = dir.path().join("bias.csv");
        std::fs::write(&data, "displacement_mm,force_n\n").unwrap();
        let inputs = [Input::new(&data, "the measured curve")];
        let roundabout = dir.path().join(".").join("bias.csv");
        let e = check_outputs(std::slice::from_ref(&roundabout), &inputs).unwrap_err();
        assert!(e.to_string().contains("the measured curve"), "{e}");
        #[cfg(unix)]
        {
            let link = dir.path().join("link.csv");
            std::os::unix::fs::symlink(&data, &link).unwrap();
            assert!(check_outputs(&[link], &inputs).is_err());
        }
        // Another file of the folder may be written; the input, by no later write.
        assert!(check_outputs(&[dir.path().join("bias.png")], &inputs).is_ok());
        let e = write_atomic(&roundabout, b"x").unwrap_err();
        assert!(e.to_string().contains("the measured curve"), "{e}");
        assert_eq!(std::fs::read(&data).unwrap(), b"displacement_mm,force_n\n");
        let folder = dir.path().join("maps");
        std::fs::create_dir(&folder).unwrap();
        assert!(check_outputs(&[folder], &[]).is_err());
    }

    #[test]
    fn a_folder_is_written_into_when_new_empty_or_marked_and_never_when_it_holds_other_files() {
        let tmp = tempfile::tempdir().unwrap();
        let new = tmp.path().join("a/b");
        claim_folder(&new).unwrap();
        assert!(new.join(FOLDER_MARKER).is_file());
        claim_folder(&new).unwrap();
        std::fs::write(new.join("shear.png"), "ours").unwrap();
        claim_folder(&new).unwrap();
        // A folder of the user's: refused, naming a file, nothing written.
        let mine = tmp.path().join("mine");
        std::fs::create_dir(&mine).unwrap();
        std::fs::write(mine.join("frontier.csv"), "x\n").unwrap();
        assert!(!folder_is_free(&mine));
        let e = claim_folder(&mine).unwrap_err().to_string();
        assert!(
            e.contains("frontier.csv") && e.contains(FOLDER_MARKER),
            "{e}"
        );
        assert_eq!(std::fs::read_dir(&mine).unwrap().count(), 1);
        // An empty one is taken and marked; a file in the way is no folder.
        let empty = tmp.path().join("empty");
        std::fs::create_dir(&empty).unwrap();
        assert!(folder_is_free(&empty));
        claim_folder(&empty).unwrap();
        assert!(empty.join(FOLDER_MARKER).is_file());
        let e = claim_folder(&mine.join("frontier.csv")).unwrap_err();
        assert!(e.to_string().contains("not a folder"), "{e}");
        // A sweep folder of an earlier version: its lock says so.
        let old = tmp.path().join("old");
        std::fs::create_dir(&old).unwrap();
        std::fs::write(old.join("results.csv"), "r\n").unwrap();
        std::fs::write(old.join("sweep.lock"), "{\"program\": \"wovenform\"}").unwrap();
        claim_folder(&old).unwrap();
        assert!(old.join(FOLDER_MARKER).is_file());
    }
}
