//! STL files as a user hands them over: binary and ASCII read back what was written, and each
//! kind of bad file is refused with a message that names the file and what is wrong with it.

use crate::common;

use wovenform::core::tools::surface::TriSurface;
use wovenform::core::tools::tessellate::tessellate;
use wovenform::stl::{parse, read_soup, read_surface, to_binary, write_binary};

/// A cube of side 10 mm at the origin: 12 triangles facing out.
fn cube() -> TriSurface {
    let soup = wovenform::core::tools::surface::box_soup([0.0; 3], [10.0; 3]);
    TriSurface::from_soup(&soup).unwrap()
}

/// The cube as ASCII STL, with the stored normals all wrong (they are ignored).
fn cube_ascii() -> String {
    let mut text = String::from("solid cube\n");
    for [a, b, c] in cube().soup() {
        text += "  facet normal 0 0 -1\n    outer loop\n";
        for p in [a, b, c] {
            text += &format!("      vertex {:e} {} {}\n", p[0], p[1], p[2]);
        }
        text += "    endloop\n  endfacet\n";
    }
    text + "endsolid cube\n"
}

use common::{assert_says, stl_refusal as refusal, write_file as file};

#[test]
fn binary_round_trip_keeps_the_surface() {
    let dir = tempfile::tempdir().unwrap();
    let sphere = |p: [f64; 3]| (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt() - 6.0;
    let surface = tessellate(&sphere, [-7.5; 3], [7.5; 3], 1.0);
    let volume = surface.check().unwrap();
    let path = dir.path().join("sphere.stl");
    write_binary(&path, &surface).unwrap();
    let bytes = std::fs::read(&path).unwrap();
    assert_eq!(bytes.len(), 84 + 50 * surface.triangles.len());
    assert!(!bytes.starts_with(b"solid"));
    let back = read_surface(&path).unwrap();
    assert_eq!(back.triangles.len(), surface.triangles.len());
    assert_eq!(back.vertices.len(), surface.vertices.len());
    // Coordinates are stored as f32: 1e-6 mm at most at this size.
    for (ta, tb) in back.soup().iter().zip(&surface.soup()) {
        for (a, b) in ta.iter().zip(tb) {
            assert!((0..3).all(|i| (a[i] - b[i]).abs() < 1e-6), "{a:?} {b:?}");
        }
    }
    let back_volume = back.check().unwrap();
    assert!((back_volume / volume - 1.0).abs() < 1e-6);
    let again = parse(&to_binary(&back)).unwrap();
    assert_eq!(
        again,
        back.soup(),
        "what was read is written as it was read"
    );
}

#[test]
fn ascii_reads_by_the_winding_not_the_stored_normals() {
    let dir = tempfile::tempdir().unwrap();
    let path = file(dir.path(), "cube.stl", cube_ascii().as_bytes());
    let back = read_surface(&path).unwrap();
    assert_eq!(back.triangles.len(), 12);
    assert_eq!(back.vertices.len(), 8);
    assert!((back.check().unwrap() - 1000.0).abs() < 1e-9);
    // Upper-case keywords and Windows line ends read too.
    let shouting = cube_ascii().to_uppercase().replace('\n', "\r\n");
    let path = file(dir.path(), "CUBE.STL", shouting.as_bytes());
    assert_eq!(read_soup(&path).unwrap(), cube().soup());
}

#[test]
fn an_empty_file_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let m = refusal(&file(dir.path(), "empty.stl", b""));
    assert_says(&m, &["empty (0 bytes)"]);
}

#[test]
fn a_truncated_binary_file_is_refused_with_its_sizes() {
    let dir = tempfile::tempdir().unwrap();
    let bytes = to_binary(&cube());
    let m = refusal(&file(dir.path(), "cut.stl", &bytes[..bytes.len() - 30]));
    assert_says(
        &m,
        &[
            "truncated binary STL",
            "12 triangles",
            "84 + 50 × 12 = 684 bytes",
            "only 654 bytes",
        ],
    );
    let mut longer = bytes.clone();
    longer.extend_from_slice(&[7; 20]);
    let m = refusal(&file(dir.path(), "long.stl", &longer));
    assert_says(&m, &["not an STL file", "684 bytes", "704 bytes (20 more)"]);
}

#[test]
fn files_that_are_not_stl_are_named_for_what_they_are() {
    let dir = tempfile::tempdir().unwrap();
    let mut png = b"\x89PNG\r\n\x1a\n\0\0\0\rIHDR".to_vec();
    png.resize(300, 3);
    let m = refusal(&file(dir.path(), "photo.stl", &png));
    assert_says(&m, &["not an STL file", "PNG image"]);
    let toml = "[fabric]\nl0 = [4.76, 4.76]\n";
    let m = refusal(&file(dir.path(), "scene.toml", toml.as_bytes()));
    assert_says(
        &m,
        &["not an STL file", "does not begin with `solid`", "[fabric]"],
    );
    let m = refusal(&file(dir.path(), "tiny.stl", &[1, 2, 3, 0]));
    assert_says(&m, &["not an STL file", "4 bytes", "84-byte header"]);
}

#[test]
fn a_malformed_ascii_line_is_named_by_its_number() {
    let dir = tempfile::tempdir().unwrap();
    let text = cube_ascii();
    // Line 5 is the first triangle's second vertex.
    let bad = text.replacen("vertex 0e0 10 0", "vertex 0e0 ten 0", 1);
    assert_ne!(bad, text);
    let m = refusal(&file(dir.path(), "typo.stl", bad.as_bytes()));
    assert_says(&m, &["line 5:", "`ten` is not a number"]);
    let lines: Vec<&str> = text.lines().collect();
    let missing = [&lines[..5], &lines[6..]].concat().join("\n");
    let m = refusal(&file(dir.path(), "missing.stl", missing.as_bytes()));
    assert_says(&m, &["line 6:", "expected `vertex x y z`, found `endloop`"]);
    let short = lines[..20].join("\n");
    let m = refusal(&file(dir.path(), "short.stl", short.as_bytes()));
    assert_says(&m, &["line 20:", "the file ends here", "truncated"]);
    let nan = text.replacen("vertex 0e0 0 0", "vertex 0e0 nan 0", 1);
    let m = refusal(&file(dir.path(), "nan.stl", nan.as_bytes()));
    assert_says(&m, &["line 4:", "`nan` is not a finite number"]);
}

#[test]
fn enormous_files_are_refused_before_they_are_read() {
    let dir = tempfile::tempdir().unwrap();
    // A sparse file: its size says 600 MB, no disk holds it.
    let path = dir.path().join("huge.stl");
    std::fs::File::create(&path)
        .unwrap()
        .set_len(600_000_000)
        .unwrap();
    let m = refusal(&path);
    assert_says(
        &m,
        &["600000000 bytes", "limit of 500000000 bytes (500 MB)"],
    );
    let mut header = vec![0u8; 80];
    header.extend_from_slice(&6_000_000u32.to_le_bytes());
    let m = refusal(&file(dir.path(), "many.stl", &header));
    assert_says(
        &m,
        &[
            "header says 6000000 triangles",
            "limit of 5000000 (5 million)",
        ],
    );
}

#[test]
fn coordinates_that_are_not_numbers_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let mut bytes = to_binary(&cube());
    // Triangle 3 (from 1), its second corner's y.
    let at = 84 + 50 * 2 + 12 + 12 + 4;
    bytes[at..at + 4].copy_from_slice(&f32::INFINITY.to_le_bytes());
    let m = refusal(&file(dir.path(), "inf.stl", &bytes));
    assert_says(&m, &["triangle 3 (of 12", "not a finite number (inf)"]);
}

#[test]
fn surfaces_that_cannot_be_a_tool_are_refused_with_the_path() {
    let dir = tempfile::tempdir().unwrap();
    let mut open = cube();
    open.triangles.pop();
    let m = refusal(&file(dir.path(), "open.stl", &to_binary(&open)));
    assert_says(&m, &["not a tool's surface", "not closed (not watertight)"]);
    let mut inverted = cube();
    for t in &mut inverted.triangles {
        t.swap(1, 2);
    }
    let m = refusal(&file(dir.path(), "inverted.stl", &to_binary(&inverted)));
    assert_says(&m, &["inside out"]);
    let m = refusal(&dir.path().join("absent.stl"));
    assert_says(&m, &["cannot read the file"]);
    let e = write_binary(&dir.path().join("no/such/dir/punch.stl"), &cube()).unwrap_err();
    assert_says(&e.to_string(), &["punch.stl", "cannot write the file"]);
}
