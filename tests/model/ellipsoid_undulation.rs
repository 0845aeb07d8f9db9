//! The paper's second example: the ellipsoidal punch drawn with and without the undulation
//! variations (Figure 12b, c). The paper finds the two final shapes "not very large" apart
//! because the fabric is rather flat; here both runs must converge, and the largest distance
//! between the two shapes (same mesh, node by node) and the difference in maximum shear are
//! measured and bounded.

use std::path::Path;

use wovenform::core::drawing;
use wovenform::scene::{Override, Scene};

#[test]
fn ellipsoid_with_and_without_undulation() {
    let preset = Path::new(env!("CARGO_MANIFEST_DIR")).join("presets/paper-ellipsoid.toml");
    let woven = Scene::load(Some(&preset), &[]).unwrap().to_problem();
    let off: Override = "fabric.undulation=false".parse().unwrap();
    let linear = Scene::load(Some(&preset), &[off]).unwrap().to_problem();
    assert!(woven.fabric.undulation && !linear.fabric.undulation);
    let a = drawing::solve(&woven, &mut |_| {});
    let b = drawing::solve(&linear, &mut |_| {});
    assert!(a.converged, "{:?}", a.failure);
    assert!(b.converged, "{:?}", b.failure);
    let distance = a
        .positions
        .iter()
        .zip(&b.positions)
        .map(|(p, q)| {
            ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)).sqrt()
        })
        .fold(0.0, f64::max);
    let (sa, sb) = (a.max_shear().1, b.max_shear().1);
    println!(
        "ellipsoid: largest distance between the shapes {distance:.3} mm (stroke {} mm); max shear \
         {sa:.2}° with undulation, {sb:.2}° without (difference {:.2}°); max tension {:.1} N vs {:.1} N; \
         {} and {} Newton iterations",
        woven.stroke_mm,
        sa - sb,
        a.max_tension_n(),
        b.max_tension_n(),
        a.stats.newton_iterations,
        b.stats.newton_iterations
    );
    // "Not very large": well under the element size, and the shear within a couple of degrees.
    assert!(
        distance < 0.5 * woven.element_size_mm,
        "shapes {distance} mm apart"
    );
    assert!((sa - sb).abs() < 2.0);
}
