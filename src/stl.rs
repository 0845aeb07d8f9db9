//! STL files: a tool's surface read from ASCII or binary STL, and written as binary STL.
//!
//! Binary STL: an 80-byte header, a little-endian `u32` triangle count, then 50 bytes per
//! triangle (normal and three corners as 12 `f32`, a 2-byte attribute). ASCII STL:
//! `solid NAME`, then per triangle `facet normal nx ny nz`, `outer loop`, three
//! `vertex x y z`, `endloop`, `endfacet`, and `endsolid NAME` (keywords in any case).
//!
//! The facet normals stored in a file are ignored: a triangle's corners wind counter-clockwise
//! seen from outside the tool's material, and that winding alone says which way it faces
//! (many writers store zero or stale normals). Units are mm.
//!
//! What a file cannot be is refused with an [`StlError`] that names the file and the problem
//! in words: not a regular file (a named pipe, a device such as `/dev/zero`, a directory: not
//! read at all), empty, too large (see [`MAX_BYTES`], enforced while reading too, and
//! [`MAX_TRIANGLES`]) or too large for the machine's memory, not an STL at all (and what it
//! is when known), truncated, an ASCII STL spoilt by a byte that is not text (its offset and
//! line), a malformed ASCII line (with its number), coordinates that are not finite numbers,
//! and a surface that cannot bound a tool ([`TriSurface::check`]).

use std::io::Read;
use std::path::{Path, PathBuf};

use crate::core::tools::surface::{SurfaceError, TriSurface};

/// The largest STL file read, bytes (500 MB).
pub const MAX_BYTES: u64 = 500_000_000;
/// The most triangles read from one file.
pub const MAX_TRIANGLES: u64 = 5_000_000;

/// A triangle as three corners, mm.
pub type Triangle = [[f64; 3]; 3];

/// Why an STL file cannot be read or written, naming the file.
#[derive(Debug, thiserror::Error)]
#[error("{}: {problem}", path.display())]
pub struct StlError {
    pub path: PathBuf,
    pub problem: StlProblem,
}

/// What is wrong with an STL file.
#[derive(Debug, thiserror::Error)]
pub enum StlProblem {
    #[error("cannot read the file: {0}")]
    Read(std::io::Error),
    #[error("it is {0}; expected a regular file holding an STL")]
    NotAFile(&'static str),
    #[error("cannot write the file: {0}")]
    Write(std::io::Error),
    #[error("the file is empty (0 bytes); an STL file holds triangles")]
    Empty,
    #[error(
        "the file is {bytes} bytes, over the limit of {limit} bytes (500 MB) for a tool's STL; \
         coarsen the mesh"
    )]
    TooLarge { bytes: u64, limit: u64 },
    #[error(
        "its size was reported as {reported} bytes, but it holds more than the limit of \
         {limit} bytes for a tool's STL (is it growing, or not a plain file?)"
    )]
    GrewTooLarge { reported: u64, limit: u64 },
    #[error(
        "reading and checking its {triangles} triangles would need about {need}, but a run may \
         use at most {limit} on this machine (80 % of what is available); coarsen the mesh"
    )]
    OverMemory {
        triangles: u64,
        need: String,
        limit: String,
    },
    #[error(
        "its header says {count} triangles, over the limit of {limit} (5 million) for a tool's \
         STL; coarsen the mesh"
    )]
    TooManyTriangles { count: u64, limit: u64 },
    #[error(
        "it holds more than {limit} triangles (5 million), the limit for a tool's STL; coarsen \
         the mesh"
    )]
    TooManyAsciiTriangles { limit: u64 },
    #[error(
        "truncated binary STL: its header says {count} triangles, which take \
         84 + 50 × {count} = {expected} bytes, but the file holds only {actual} bytes"
    )]
    Truncated {
        count: u64,
        expected: u64,
        actual: u64,
    },
    #[error("not an STL file: {0}")]
    NotStl(String),
    #[error("line {line}: {what}")]
    AsciiLine { line: usize, what: String },
    #[error(
        "it begins with `solid` as an ASCII STL does, but byte {offset} (counting from 0; \
         line {line}{where_}) is 0x{byte:02x}, which is not text, so it is not an ASCII STL; \
         nor is it a binary STL ({binary}). Remove the stray byte, or export the file again",
        where_ = if *last { ", the file's last byte" } else { "" }
    )]
    AsciiNotText {
        offset: usize,
        line: usize,
        byte: u8,
        last: bool,
        binary: String,
    },
    #[error(
        "triangle {triangle} (of {count}, counting from 1) has a coordinate that is not a \
         finite number ({value})"
    )]
    NotFinite {
        triangle: usize,
        count: usize,
        value: f64,
    },
    #[error("not a tool's surface: {0}")]
    Surface(SurfaceError),
}

/// Reads an STL file (ASCII or binary) as a closed tool surface: its corners welded and the
/// surface checked (closed, manifold, facing out; see [`TriSurface::check`]).
pub fn read_surface(path: &Path) -> Result<TriSurface, StlError> {
    let at = |problem| StlError {
        path: path.to_path_buf(),
        problem,
    };
    let soup = read_soup(path)?;
    let surface = TriSurface::from_soup(&soup).map_err(|e| at(StlProblem::Surface(e)))?;
    surface.check().map_err(|e| at(StlProblem::Surface(e)))?;
    Ok(surface)
}

/// Reads the triangles of an STL file (ASCII or binary), as they are stored.
pub fn read_soup(path: &Path) -> Result<Vec<Triangle>, StlError> {
    let at = |problem| StlError {
        path: path.to_path_buf(),
        problem,
    };
    let mut file = open_regular(path).map_err(at)?;
    let bytes = file.metadata().map_err(|e| at(StlProblem::Read(e)))?.len();
    if bytes > MAX_BYTES {
        return Err(at(StlProblem::TooLarge {
            bytes,
            limit: MAX_BYTES,
        }));
    }
    // The header first, so that a binary file's count is refused before the rest is read.
    let mut head = Vec::with_capacity(84);
    (&mut file)
        .take(84)
        .read_to_end(&mut head)
        .map_err(|e| at(StlProblem::Read(e)))?;
    check_head(&head).map_err(at)?;
    check_memory(&head, bytes).map_err(at)?;
    let all = read_bounded(&mut file, head, bytes, MAX_BYTES).map_err(at)?;
    parse(&all).map_err(at)
}

/// Opens `path` for reading when it is a regular file (after following links): a named pipe
/// would block until someone writes to it, a device such as `/dev/zero` never ends, and a
/// directory or a socket holds no file to read.
fn open_regular(path: &Path) -> Result<std::fs::File, StlProblem> {
    let meta = std::fs::metadata(path).map_err(StlProblem::Read)?;
    not_special(&meta)?;
    let mut options = std::fs::OpenOptions::new();
    options.read(true);
    // Should the path become a pipe between the look and the opening, the opening must not
    // wait for a writer (the check below then refuses it).
    #[cfg(unix)]
    std::os::unix::fs::OpenOptionsExt::custom_flags(&mut options, libc::O_NONBLOCK);
    let file = options.open(path).map_err(StlProblem::Read)?;
    not_special(&file.metadata().map_err(StlProblem::Read)?)?;
    Ok(file)
}

/// Refuses what is not a regular file, naming what it is.
fn not_special(meta: &std::fs::Metadata) -> Result<(), StlProblem> {
    let kind = meta.file_type();
    if kind.is_file() {
        return Ok(());
    }
    if kind.is_dir() {
        return Err(StlProblem::NotAFile(
            "a directory (name the STL file in it)",
        ));
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        let what = if kind.is_fifo() {
            "a named pipe (FIFO), whose reading waits for a writer and may never end"
        } else if kind.is_char_device() {
            "a character device (such as /dev/zero), whose reading may never end"
        } else if kind.is_block_device() {
            "a block device (a disk), not a file"
        } else if kind.is_socket() {
            "a socket, not a file"
        } else {
            "a special file"
        };
        return Err(StlProblem::NotAFile(what));
    }
    #[allow(unreachable_code)]
    Err(StlProblem::NotAFile("a special file"))
}

/// The rest of the file after `head`, at most `limit` bytes in all whatever its size was
/// reported as (`reported`): a file that grows, or one whose size the system does not know,
/// is not read without end.
fn read_bounded(
    file: &mut impl Read,
    head: Vec<u8>,
    reported: u64,
    limit: u64,
) -> Result<Vec<u8>, StlProblem> {
    let mut all = head;
    all.reserve(reported.min(limit).saturating_sub(all.len() as u64) as usize);
    let room = (limit + 1).saturating_sub(all.len() as u64);
    file.take(room)
        .read_to_end(&mut all)
        .map_err(StlProblem::Read)?;
    if all.len() as u64 > limit {
        return Err(StlProblem::GrewTooLarge { reported, limit });
    }
    Ok(all)
}

/// About how many bytes reading, welding and checking one triangle takes at most (the file's
/// 50 bytes, the soup's 72, the welded surface, the hierarchy of the crossing test).
const BYTES_PER_TRIANGLE: f64 = 600.0;

/// Refuses a file whose triangles would not fit in the memory a run may take, before they are
/// read: a binary file's count is in its header; an ASCII facet takes 60 bytes or more.
fn check_memory(head: &[u8], bytes: u64) -> Result<(), StlProblem> {
    let triangles = if head.len() == 84 && !is_text(head) && !may_be_text(head) {
        binary_count(head)
    } else {
        bytes / 60
    };
    let need = bytes as f64 + triangles as f64 * BYTES_PER_TRIANGLE;
    let budget = crate::machine::memory_budget_bytes();
    if need > budget {
        return Err(StlProblem::OverMemory {
            triangles,
            need: crate::show::show_bytes(need),
            limit: crate::show::show_bytes(budget),
        });
    }
    Ok(())
}

/// Refuses what the first 84 bytes already show: an empty file, a known other format, a
/// binary count over the limit.
fn check_head(head: &[u8]) -> Result<(), StlProblem> {
    if head.is_empty() {
        return Err(StlProblem::Empty);
    }
    if let Some(kind) = other_format(head) {
        return Err(StlProblem::NotStl(format!("it is {kind}")));
    }
    if head.len() == 84 && !is_text(head) && !may_be_text(head) {
        let count = binary_count(head);
        if count > MAX_TRIANGLES {
            return Err(StlProblem::TooManyTriangles {
                count,
                limit: MAX_TRIANGLES,
            });
        }
    }
    Ok(())
}

/// The triangles of an STL file's bytes (ASCII or binary).
pub fn parse(bytes: &[u8]) -> Result<Vec<Triangle>, StlProblem> {
    if bytes.is_empty() {
        return Err(StlProblem::Empty);
    }
    if let Some(kind) = other_format(bytes) {
        return Err(StlProblem::NotStl(format!("it is {kind}")));
    }
    if is_text(bytes) {
        let text = String::from_utf8_lossy(bytes);
        // A byte-order mark (some Windows editors write one) is not part of the text.
        let text = text.strip_prefix('\u{feff}').unwrap_or(&text);
        let first = text.lines().find(|l| !l.trim().is_empty()).unwrap_or("");
        let starts_solid = first
            .split_whitespace()
            .next()
            .is_some_and(|w| w.eq_ignore_ascii_case("solid"));
        if !starts_solid {
            return Err(StlProblem::NotStl(format!(
                "it is a text file that does not begin with `solid` as an ASCII STL does \
                 (it begins `{}`)",
                excerpt(first)
            )));
        }
        return parse_ascii(text);
    }
    if let Some(not_binary) = binary_misfit(bytes) {
        if starts_with_solid(bytes) {
            return Err(ascii_not_text(bytes, not_binary));
        }
        if is_utf16(bytes) {
            return Err(StlProblem::NotStl(
                "it is UTF-16 text (\"Unicode\" in some editors); save the ASCII STL as UTF-8 \
                 or plain ASCII"
                    .into(),
            ));
        }
    }
    parse_binary(bytes)
}

/// Whether bytes that are not all text may still be text spoilt by a stray byte (they begin
/// with `solid`) or text in UTF-16: [`parse`] tells, by the whole file, rather than a binary
/// header's count read from them.
fn may_be_text(head: &[u8]) -> bool {
    starts_with_solid(head) || is_utf16(head)
}

/// Whether the bytes begin with a UTF-16 byte-order mark.
fn is_utf16(bytes: &[u8]) -> bool {
    bytes.starts_with(b"\xff\xfe") || bytes.starts_with(b"\xfe\xff")
}

/// Whether the bytes begin with `solid` (any case, after blanks and a byte-order mark), as an
/// ASCII STL does (and some binary files' headers).
fn starts_with_solid(bytes: &[u8]) -> bool {
    let bytes = bytes.strip_prefix(b"\xef\xbb\xbf").unwrap_or(bytes);
    let start = bytes.iter().position(|b| !b.is_ascii_whitespace());
    start.is_some_and(|i| bytes[i..].len() >= 5 && bytes[i..i + 5].eq_ignore_ascii_case(b"solid"))
}

/// Why the bytes are not a binary STL, if they are not: too short, or a size other than the
/// 84 + 50 × count bytes its header says.
fn binary_misfit(bytes: &[u8]) -> Option<String> {
    let actual = bytes.len() as u64;
    if actual < 84 {
        return Some(format!("{actual} bytes, shorter than its 84-byte header"));
    }
    let count = binary_count(bytes);
    let expected = 84 + 50 * count;
    (actual != expected).then(|| {
        format!(
            "read as one, its header would say {count} triangles, which take 84 + 50 × {count} = \
             {expected} bytes, but the file holds {actual}"
        )
    })
}

/// An ASCII STL spoilt by a byte that is not text: where the byte is.
fn ascii_not_text(bytes: &[u8], binary: String) -> StlProblem {
    let offset = bytes.iter().position(|&b| !is_text(&[b])).unwrap_or(0);
    let line = 1 + bytes[..offset].iter().filter(|&&b| b == b'\n').count();
    StlProblem::AsciiNotText {
        offset,
        line,
        byte: bytes[offset],
        last: offset + 1 == bytes.len(),
        binary,
    }
}

/// A few formats a tool file is mistaken for, by their first bytes.
fn other_format(bytes: &[u8]) -> Option<&'static str> {
    let signatures: [(&[u8], &str); 6] = [
        (b"\x89PNG\r\n\x1a\n", "a PNG image"),
        (b"\xff\xd8\xff", "a JPEG image"),
        (b"%PDF", "a PDF document"),
        (
            b"PK\x03\x04",
            "a ZIP archive (a 3MF file is one: export STL instead)",
        ),
        (b"\x1f\x8b", "gzip-compressed (uncompress it first)"),
        (b"ISO-10303-21", "a STEP file (export STL instead)"),
    ];
    signatures
        .iter()
        .find(|(magic, _)| bytes.starts_with(magic))
        .map(|(_, kind)| *kind)
}

/// Whether the bytes look like text: no NUL and no control character but tab, line feed,
/// form feed and carriage return (a binary STL's floats and count hold such bytes).
fn is_text(bytes: &[u8]) -> bool {
    bytes
        .iter()
        .all(|&b| b >= 0x20 || matches!(b, b'\t' | b'\n' | b'\r' | 0x0c))
}

fn binary_count(bytes: &[u8]) -> u64 {
    u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as u64
}

/// The first 60 characters of a line, for a message.
fn excerpt(line: &str) -> String {
    let line = line.trim();
    if line.chars().count() > 60 {
        format!("{}…", line.chars().take(60).collect::<String>())
    } else {
        line.to_string()
    }
}

fn parse_binary(bytes: &[u8]) -> Result<Vec<Triangle>, StlProblem> {
    let actual = bytes.len() as u64;
    if actual < 84 {
        return Err(StlProblem::NotStl(format!(
            "it is {actual} bytes of binary data, shorter than a binary STL's 84-byte header \
             and triangle count, and not an ASCII STL"
        )));
    }
    let count = binary_count(bytes);
    if count > MAX_TRIANGLES {
        return Err(StlProblem::TooManyTriangles {
            count,
            limit: MAX_TRIANGLES,
        });
    }
    let expected = 84 + 50 * count;
    if actual < expected {
        return Err(StlProblem::Truncated {
            count,
            expected,
            actual,
        });
    }
    if actual > expected {
        return Err(StlProblem::NotStl(format!(
            "as a binary STL its header says {count} triangles, which take 84 + 50 × {count} = \
             {expected} bytes, but the file holds {actual} bytes ({} more)",
            actual - expected
        )));
    }
    let f32_at =
        |at: usize| f32::from_le_bytes([bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]]);
    let count = count as usize;
    let mut soup = Vec::with_capacity(count);
    for t in 0..count {
        // Skip the stored normal (12 bytes): the winding says which way a triangle faces.
        let base = 84 + 50 * t + 12;
        let tri: Triangle =
            std::array::from_fn(|c| std::array::from_fn(|i| f32_at(base + 12 * c + 4 * i) as f64));
        if let Some(&value) = tri.iter().flatten().find(|v| !v.is_finite()) {
            return Err(StlProblem::NotFinite {
                triangle: t + 1,
                count,
                value,
            });
        }
        soup.push(tri);
    }
    Ok(soup)
}

/// What an ASCII STL expects next.
#[derive(Clone, Copy, PartialEq)]
enum Expect {
    Solid,
    FacetOrEnd,
    OuterLoop,
    Vertex(usize),
    EndLoop,
    EndFacet,
}

impl Expect {
    fn describe(self) -> &'static str {
        match self {
            Expect::Solid => "`solid NAME`",
            Expect::FacetOrEnd => "`facet normal nx ny nz` or `endsolid`",
            Expect::OuterLoop => "`outer loop`",
            Expect::Vertex(_) => "`vertex x y z`",
            Expect::EndLoop => "`endloop`",
            Expect::EndFacet => "`endfacet`",
        }
    }
}

fn parse_ascii(text: &str) -> Result<Vec<Triangle>, StlProblem> {
    let mut soup = Vec::new();
    let mut expect = Expect::Solid;
    let mut corners = [[0.0; 3]; 3];
    let mut solids = 0;
    let mut last_line = 0;
    for (index, line) in text.lines().enumerate() {
        let number = index + 1;
        let words: Vec<&str> = line.split_whitespace().collect();
        let Some(first) = words.first() else {
            continue;
        };
        last_line = number;
        let is = |word: &str| first.eq_ignore_ascii_case(word);
        let wrong = || StlProblem::AsciiLine {
            line: number,
            what: format!("expected {}, found `{}`", expect.describe(), excerpt(line)),
        };
        expect = match expect {
            Expect::Solid if is("solid") => {
                solids += 1;
                Expect::FacetOrEnd
            }
            Expect::FacetOrEnd if is("endsolid") => Expect::Solid,
            // The stored normal is not read: the winding says which way the triangle faces.
            Expect::FacetOrEnd if is("facet") => Expect::OuterLoop,
            Expect::OuterLoop
                if words.len() == 2 && is("outer") && words[1].eq_ignore_ascii_case("loop") =>
            {
                Expect::Vertex(0)
            }
            Expect::Vertex(k) if is("vertex") && words.len() == 4 => {
                corners[k] = vertex(&words[1..], number)?;
                if k < 2 {
                    Expect::Vertex(k + 1)
                } else {
                    Expect::EndLoop
                }
            }
            Expect::EndLoop if is("endloop") && words.len() == 1 => Expect::EndFacet,
            Expect::EndFacet if is("endfacet") && words.len() == 1 => {
                soup.push(corners);
                if soup.len() as u64 > MAX_TRIANGLES {
                    return Err(StlProblem::TooManyAsciiTriangles {
                        limit: MAX_TRIANGLES,
                    });
                }
                Expect::FacetOrEnd
            }
            _ => return Err(wrong()),
        };
    }
    if expect != Expect::Solid || solids == 0 {
        return Err(StlProblem::AsciiLine {
            line: last_line,
            what: format!(
                "the file ends here, where {} was expected (is it truncated?)",
                expect.describe()
            ),
        });
    }
    Ok(soup)
}

/// The three coordinates of a `vertex` line.
fn vertex(words: &[&str], line: usize) -> Result<[f64; 3], StlProblem> {
    let mut p = [0.0; 3];
    for (i, word) in words.iter().enumerate() {
        let value: f64 = word.parse().map_err(|_| StlProblem::AsciiLine {
            line,
            what: format!("`{}` is not a number", excerpt(word)),
        })?;
        if !value.is_finite() {
            return Err(StlProblem::AsciiLine {
                line,
                what: format!("the coordinate `{word}` is not a finite number"),
            });
        }
        p[i] = value;
    }
    Ok(p)
}

/// The surface as binary STL bytes: each triangle's normal from its winding (unit length,
/// zero for a degenerate triangle), coordinates as `f32`.
pub fn to_binary(surface: &TriSurface) -> Vec<u8> {
    let mut out = Vec::with_capacity(84 + 50 * surface.triangles.len());
    // The header must not begin with `solid`, which would say ASCII to some readers.
    let mut header = [b' '; 80];
    let text = b"binary STL written by wovenform; mm; counter-clockwise seen from outside";
    header[..text.len()].copy_from_slice(text);
    out.extend_from_slice(&header);
    out.extend_from_slice(&(surface.triangles.len() as u32).to_le_bytes());
    for t in 0..surface.triangles.len() {
        let [a, b, c] = surface.corners(t);
        let (u, v) = (
            [0, 1, 2].map(|i| b[i] - a[i]),
            [0, 1, 2].map(|i| c[i] - a[i]),
        );
        let n = [
            u[1] * v[2] - u[2] * v[1],
            u[2] * v[0] - u[0] * v[2],
            u[0] * v[1] - u[1] * v[0],
        ];
        let l = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
        let n = if l > 0.0 { n.map(|x| x / l) } else { [0.0; 3] };
        for x in n.iter().chain(a.iter()).chain(b.iter()).chain(c.iter()) {
            out.extend_from_slice(&(*x as f32).to_le_bytes());
        }
        out.extend_from_slice(&[0, 0]);
    }
    out
}

/// Writes the surface as binary STL (see [`to_binary`]), whole.
pub fn write_binary(path: &Path, surface: &TriSurface) -> Result<(), StlError> {
    // Whole or not at all: a full disk leaves no half a tool.
    crate::files::write_atomic(path, &to_binary(surface)).map_err(|e| StlError {
        path: path.to_path_buf(),
        problem: StlProblem::Write(e),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_endless_reader_is_read_up_to_the_limit_only() {
        // What /proc files and growing files are: a reported size that is not what comes.
        let mut endless = std::io::repeat(b'x');
        let e = read_bounded(&mut endless, b"solid".to_vec(), 0, 1000).unwrap_err();
        assert!(
            matches!(
                e,
                StlProblem::GrewTooLarge {
                    reported: 0,
                    limit: 1000
                }
            ),
            "{e}"
        );
        let mut short = std::io::Cursor::new(vec![b'y'; 995]);
        let all = read_bounded(&mut short, b"solid".to_vec(), 0, 1000).unwrap();
        assert_eq!(all.len(), 1000);
    }
}
