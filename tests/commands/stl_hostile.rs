//! Tool files as a hostile (or unlucky) user hands them over: what is not a file, an ASCII STL
//! spoilt by one byte, and surfaces that are closed and consistently wound but still no tool
//! (passing through themselves, one solid inside another, a triangle with no area). Each is
//! refused with a message naming the file and saying what it is, without hanging.

use crate::common;

use std::path::Path;
use std::time::Instant;

use wovenform::core::tools::intersect::self_intersection;
use wovenform::core::tools::surface::TriSurface;
use wovenform::core::tools::tessellate::tessellate;
use wovenform::stl::{read_soup, read_surface, to_binary};

type Soup = Vec<[[f64; 3]; 3]>;

/// An axis-aligned box's 12 triangles, facing out (inwards when `!outward`).
fn cuboid(lo: [f64; 3], hi: [f64; 3], outward: bool) -> Soup {
    let soup = wovenform::core::tools::surface::box_soup(lo, hi).into_iter();
    soup.map(|t| if outward { t } else { [t[0], t[2], t[1]] })
        .collect()
}

/// The soup as binary STL bytes, triangles as given (not welded).
fn binary(soup: &Soup) -> Vec<u8> {
    let mut out = vec![b' '; 80];
    out.extend((soup.len() as u32).to_le_bytes());
    for t in soup {
        out.extend([0u8; 12]);
        for p in t {
            for x in p {
                out.extend((*x as f32).to_le_bytes());
            }
        }
        out.extend([0, 0]);
    }
    out
}

fn ascii(soup: &Soup) -> String {
    let mut text = String::from("solid part\n");
    for t in soup {
        text += "  facet normal 0 0 0\n    outer loop\n";
        for p in t {
            text += &format!("      vertex {} {} {}\n", p[0], p[1], p[2]);
        }
        text += "    endloop\n  endfacet\n";
    }
    text + "endsolid part\n"
}

use common::{assert_says, stl_refusal as refusal, write_file as file};

#[test]
fn what_is_not_a_regular_file_is_refused_without_reading_it() {
    let dir = tempfile::tempdir().unwrap();
    let fifo = dir.path().join("punch.stl");
    let c = std::ffi::CString::new(fifo.to_str().unwrap()).unwrap();
    assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o644) }, 0);
    let m = refusal(&fifo);
    assert_says(&m, &["named pipe (FIFO)", "expected a regular file"]);
    let m = refusal(Path::new("/dev/zero"));
    assert_says(&m, &["character device", "expected a regular file"]);
    let m = refusal(dir.path());
    assert_says(&m, &["a directory"]);
    // A link to itself: the system says so.
    let link = dir.path().join("loop.stl");
    std::os::unix::fs::symlink(&link, &link).unwrap();
    let m = refusal(&link);
    assert_says(&m, &["cannot read the file"]);
}

#[test]
fn an_ascii_stl_with_a_stray_byte_is_named_for_what_it_is() {
    let dir = tempfile::tempdir().unwrap();
    let text = ascii(&cuboid([0.0; 3], [10.0; 3], true));
    let lines = text.lines().count();
    for stray in [0u8, 1, 0x7] {
        let mut bytes = text.clone().into_bytes();
        bytes.push(stray);
        let m = refusal(&file(dir.path(), "trailing.stl", &bytes));
        assert_says(
            &m,
            &[
                "begins with `solid` as an ASCII STL does",
                &format!("byte {} ", text.len()),
                &format!("line {}, the file's last byte", lines + 1),
                &format!("0x{stray:02x}"),
            ],
        );
        assert!(!m.contains("coarsen"), "{m}");
    }
    // Within the first 84 bytes (where a binary file's count would be), and further on.
    for at in [20, 300] {
        let mut bytes = text.clone().into_bytes();
        bytes.insert(at, 0);
        let line = 1 + text[..at].matches('\n').count();
        let m = refusal(&file(dir.path(), "inner.stl", &bytes));
        assert_says(&m, &[&format!("byte {at} "), &format!("line {line})")]);
        assert!(!m.contains("coarsen"), "{m}");
    }
    // A byte-order mark is not a stray byte; UTF-16 is named.
    let bom = [b"\xef\xbb\xbf".as_slice(), text.as_bytes()].concat();
    let read = read_soup(&file(dir.path(), "bom.stl", &bom)).unwrap();
    assert_eq!(read.len(), 12);
    let utf16: Vec<u8> = [0xff, 0xfe]
        .into_iter()
        .chain(text.encode_utf16().flat_map(|u| u.to_le_bytes()))
        .collect();
    let m = refusal(&file(dir.path(), "wide.stl", &utf16));
    assert_says(&m, &["UTF-16"]);
    // A binary STL whose header begins with `solid` (some exporters write one) still reads.
    let mut bytes = binary(&cuboid([0.0; 3], [10.0; 3], true));
    bytes[..12].copy_from_slice(b"solid binary");
    let read = read_soup(&file(dir.path(), "solid_binary.stl", &bytes)).unwrap();
    assert_eq!(read.len(), 12);
}

#[test]
fn a_surface_through_itself_is_refused_with_where() {
    let dir = tempfile::tempdir().unwrap();
    // Two closed boxes overlapping in [5, 10] × [5, 10] × [0, 10], sharing their bottom plane.
    let mut two = cuboid([0.0; 3], [10.0; 3], true);
    two.extend(cuboid([5.0, 5.0, 0.0], [15.0, 15.0, 10.0], true));
    let m = refusal(&file(dir.path(), "two.stl", &binary(&two)));
    assert_says(&m, &["passes through itself", "cross near ("]);
    let at: Vec<f64> = m
        .split("cross near (")
        .nth(1)
        .unwrap()
        .split(')')
        .next()
        .unwrap()
        .split(", ")
        .map(|v| v.parse().unwrap())
        .collect();
    // Where the boxes' surfaces meet: within both boxes (closed).
    assert!(
        (0..2).all(|i| (5.0..=10.0).contains(&at[i])) && (0.0..=10.0).contains(&at[2]),
        "{at:?}"
    );
    // A cube with a corner pushed down through its bottom face.
    let pushed: Soup = cuboid([0.0; 3], [10.0; 3], true)
        .into_iter()
        .map(|t| t.map(|p| if p == [10.0; 3] { [4.0, 4.0, -5.0] } else { p }))
        .collect();
    let m = refusal(&file(dir.path(), "pushed.stl", &binary(&pushed)));
    assert_says(&m, &["passes through itself"]);
    // A solid inside another (no face crossing): the material is enclosed twice.
    let mut nested = cuboid([0.0; 3], [10.0; 3], true);
    nested.extend(cuboid([2.0; 3], [8.0; 3], true));
    let m = refusal(&file(dir.path(), "nested.stl", &binary(&nested)));
    assert_says(&m, &["encloses material twice", "inside another solid"]);
    // The same inner box facing inwards is a cavity: a hollow tool, accepted.
    let mut hollow = cuboid([0.0; 3], [10.0; 3], true);
    hollow.extend(cuboid([2.0; 3], [8.0; 3], false));
    let s = read_surface(&file(dir.path(), "hollow.stl", &binary(&hollow))).unwrap();
    assert!((s.volume_mm3() - (1000.0 - 216.0)).abs() < 1e-9);
    // Two boxes apart: two solids, one tool.
    let mut apart = cuboid([0.0; 3], [10.0; 3], true);
    apart.extend(cuboid([20.0; 3], [30.0; 3], true));
    read_surface(&file(dir.path(), "apart.stl", &binary(&apart))).unwrap();
}

#[test]
fn a_triangle_with_no_area_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    // A cube whose top triangle over the edge (0,0,10)–(10,0,10) is split at that edge's
    // middle m, and a needle (0,0,10) (10,0,10) m closes the gap: closed, wound one way, with
    // one triangle whose corners lie in a line.
    let mut soup = cuboid([0.0; 3], [10.0; 3], true);
    let (a, b, c, m) = (
        [0.0, 0.0, 10.0],
        [10.0, 0.0, 10.0],
        [10.0, 10.0, 10.0],
        [5.0, 0.0, 10.0],
    );
    let top = soup.iter().position(|t| *t == [a, b, c]).unwrap();
    soup[top] = [a, m, c];
    soup.extend([[m, b, c], [a, b, m]]);
    let m = refusal(&file(dir.path(), "needle.stl", &binary(&soup)));
    assert_says(&m, &["three corners in a line", "(5.000, 0.000, 10.000)"]);
}

#[test]
fn the_crossing_test_takes_well_under_a_second_per_100k_triangles() {
    // A sphere of radius 50 mm on a 1 mm grid: about 100 000 triangles.
    let sphere = |p: [f64; 3]| (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt() - 50.0;
    let s: TriSurface = tessellate(&sphere, [-52.0; 3], [52.0; 3], 1.0);
    let n = s.triangles.len();
    assert!((70_000..200_000).contains(&n), "{n} triangles");
    let start = Instant::now();
    assert_eq!(self_intersection(&s), None);
    let took = start.elapsed().as_secs_f64();
    eprintln!("crossing test: {n} triangles in {took:.3} s");
    // Generous (a shared, loaded machine): the point is that it is not quadratic.
    assert!(
        took < 10.0 * n as f64 / 100_000.0,
        "{took} s for {n} triangles"
    );
    // And the whole check of the binary file as read, with its path in no message.
    let dir = tempfile::tempdir().unwrap();
    let path = file(dir.path(), "sphere.stl", &to_binary(&s));
    read_surface(&path).unwrap();
}
