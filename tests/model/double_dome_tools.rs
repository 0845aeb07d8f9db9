//! The double-dome tools committed in `presets/double-dome/` (binary STL) are what the
//! generator (`wovenform::core::tools::double_dome`) makes now. To write them anew:
//!
//! ```text
//! WOVENFORM_WRITE_TOOLS=1 cargo test --release --test model double_dome_tools::
//! ```
//!
//! Spacings: both at 1 mm (the punch about 2 MB; the die's plate of 250 × 190 × 35 mm takes
//! 254 192 triangles, 12.7 MB). The die was at 1.5 mm (5.6 MB) before: its entry radius's
//! first facet then turned 14° from the face, the smoothed normal at the face's edge leaned
//! 3.6°, and at `fine` (1.25 mm elements, a row of nodes on that edge) the first step did
//! not converge; at 1 mm it does.

use std::path::Path;

use wovenform::core::tools::double_dome::DoubleDome;
use wovenform::stl::{read_surface, write_binary};

const PUNCH_SPACING_MM: f64 = 1.0;
const DIE_SPACING_MM: f64 = 1.0;
const MAX_FILE_BYTES: u64 = 13_000_000;

#[test]
fn the_committed_double_dome_tools_are_what_the_generator_makes() {
    let dd = DoubleDome::STANDARD;
    let (punch, die) = dd.surfaces(&DoubleDome::STANDARD_CAPS, PUNCH_SPACING_MM, DIE_SPACING_MM);
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("presets/double-dome");
    let write = std::env::var("WOVENFORM_WRITE_TOOLS").as_deref() == Ok("1");
    for (name, surface) in [("punch", &punch), ("die", &die)] {
        surface
            .check()
            .unwrap_or_else(|e| panic!("the generated {name}: {e}"));
        let path = dir.join(format!("{name}.stl"));
        if write {
            std::fs::create_dir_all(&dir).unwrap();
            write_binary(&path, surface).unwrap();
            eprintln!(
                "wrote {} ({} triangles)",
                path.display(),
                surface.triangles.len()
            );
        }
        let read = read_surface(&path)
            .unwrap_or_else(|e| panic!("{e} (write it with WOVENFORM_WRITE_TOOLS=1)"));
        let bytes = std::fs::metadata(&path).unwrap().len();
        assert!(bytes < MAX_FILE_BYTES, "{name}.stl is {bytes} bytes");
        assert_eq!(
            read.triangles.len(),
            surface.triangles.len(),
            "{name}: the committed file differs from the generator \
             (write it anew with WOVENFORM_WRITE_TOOLS=1)"
        );
        assert_eq!(read.vertices.len(), surface.vertices.len(), "{name}");
        // The file stores f32: the generated corners rounded to f32 are the file's.
        for (t, (a, b)) in read.soup().iter().zip(surface.soup()).enumerate() {
            for (p, q) in a.iter().zip(b) {
                for i in 0..3 {
                    let want = q[i] as f32 as f64;
                    assert!(
                        (p[i] - want).abs() <= 1e-9,
                        "{name}: triangle {t}: {p:?} against {q:?}"
                    );
                }
            }
        }
    }
    // In the drawing's frame: the punch's lowest points and the die's face at z = 0.
    let (lo, hi) = punch.bounds();
    assert!(lo[2].abs() < 1e-6, "the punch's lowest z {}", lo[2]);
    assert!((hi[2] - 35.0).abs() < 1e-9);
    let (lo, hi) = die.bounds();
    assert!(hi[2].abs() < 1e-9, "the die's highest z {}", hi[2]);
    assert!((lo[2] + 35.0).abs() < 1e-9);
}
