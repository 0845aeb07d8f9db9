//! Writing a command's files safely: whole or not at all, and never over what the user gave.
//!
//! - [`write_atomic`] writes through a temporary file in the destination's folder and a
//!   rename: an interrupted or failed write (a full disk, a killed process) leaves the old
//!   file as it was, or no file, never half a file or a 0-byte one.
//! - [`check_outputs`] refuses, before any work, a set of outputs of which one is a file the
//!   command reads (the scene, a measured curve, a tool's STL: compared as files, through
//!   links and relative paths), or an existing file that wovenform did not write in a kind a
//!   person keeps as input (see [`Output::owned_if`]).

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

/// A file a command will write.
#[derive(Clone, Debug)]
pub struct Output {
    pub path: PathBuf,
    /// For kinds a person keeps as input (TOML, CSV, STL): the first bytes every file of this
    /// kind that wovenform writes begins with. An existing file that does not begin so is the
    /// user's, and is not replaced. `None`: any existing file may be replaced (a picture, a
    /// result the command owns).
    pub owned_if: Option<&'static [u8]>,
}

impl Output {
    /// A file any existing version of which may be replaced.
    pub fn replaceable(path: impl Into<PathBuf>) -> Output {
        Output {
            path: path.into(),
            owned_if: None,
        }
    }

    /// A file replaced only when the existing one begins with `head` (wovenform wrote it).
    pub fn owned_if(path: impl Into<PathBuf>, head: &'static [u8]) -> Output {
        Output {
            path: path.into(),
            owned_if: Some(head),
        }
    }
}

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
        "{}: a file of that name is already there and wovenform did not write it; it is not \
         replaced: expected an output folder (--out) without it, or move it away",
        output.display()
    )]
    NotOurs { output: PathBuf },
    #[error("{}: a folder of that name is in the way of the output file", output.display())]
    Folder { output: PathBuf },
}

/// Refuses `outputs` when one of them is one of `inputs`, a folder, or an existing file of a
/// kind a person keeps (see [`Output::owned_if`]) that wovenform did not write.
pub fn check_outputs(outputs: &[Output], inputs: &[Input]) -> Result<(), OverwriteError> {
    for out in outputs {
        if let Some(input) = inputs.iter().find(|i| same_file(&out.path, &i.path)) {
            return Err(OverwriteError::Input {
                output: out.path.clone(),
                input: input.path.clone(),
                what: input.what.clone(),
            });
        }
        if out.path.is_dir() {
            return Err(OverwriteError::Folder {
                output: out.path.clone(),
            });
        }
        if let Some(head) = out.owned_if
            && out.path.exists()
            && !begins_with(&out.path, head)
        {
            return Err(OverwriteError::NotOurs {
                output: out.path.clone(),
            });
        }
    }
    Ok(())
}

/// Whether the file at `path` begins with `head` (false when it cannot be read).
fn begins_with(path: &Path, head: &[u8]) -> bool {
    use std::io::Read as _;
    let Ok(file) = std::fs::File::open(path) else {
        return false;
    };
    let mut first = Vec::with_capacity(head.len());
    file.take(head.len() as u64)
        .read_to_end(&mut first)
        .is_ok_and(|_| first == head)
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
        let e = check_outputs(&[Output::replaceable(&roundabout)], &inputs).unwrap_err();
        assert!(e.to_string().contains("the measured curve"), "{e}");
        #[cfg(unix)]
        {
            let link = dir.path().join("link.csv");
            std::os::unix::fs::symlink(&data, &link).unwrap();
            assert!(check_outputs(&[Output::replaceable(&link)], &inputs).is_err());
        }
        // Another file of the folder may be written.
        let other = Output::replaceable(dir.path().join("bias.png"));
        assert!(check_outputs(&[other], &inputs).is_ok());
    }

    #[test]
    fn a_users_file_of_a_kept_kind_is_replaced_only_when_wovenform_wrote_it() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("fabric.toml");
        let ours = Output::owned_if(&path, b"# The fabric of");
        assert!(check_outputs(std::slice::from_ref(&ours), &[]).is_ok());
        std::fs::write(&path, "[fabric]\na = 0.1\n").unwrap();
        let e = check_outputs(std::slice::from_ref(&ours), &[]).unwrap_err();
        assert!(e.to_string().contains("did not write it"), "{e}");
        std::fs::write(&path, "# The fabric of x\n[fabric]\n").unwrap();
        assert!(check_outputs(&[ours], &[]).is_ok());
        let folder = dir.path().join("maps");
        std::fs::create_dir(&folder).unwrap();
        assert!(check_outputs(&[Output::replaceable(folder)], &[]).is_err());
    }
}
