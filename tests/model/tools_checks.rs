#![allow(clippy::needless_range_loop)]
//! The rigid tools against closed forms (distances to faces, spheres and tori of known radius)
//! and finite differences (normal = gradient of the distance, continuity of the normal).

use crate::analytic;
use crate::common;
use common::Lcg;
use wovenform::core::tools::Tool;

fn tools() -> Vec<(&'static str, Tool)> {
    vec![
        (
            "box punch r>rp",
            Tool::box_punch([60.0, 60.0], 10.0, 6.0, -3.0),
        ),
        (
            "box punch r<rp",
            Tool::box_punch([60.0, 60.0], 5.0, 6.0, -3.0),
        ),
        (
            "box punch r<<rp",
            Tool::box_punch([60.0, 50.0], 10.0, 15.0, 0.0),
        ),
        ("box die", Tool::box_die([60.0, 60.0], 5.0, 1.5, 5.0)),
        (
            "ellipsoid punch",
            Tool::EllipsoidPunch {
                axes: [40.0, 25.0, 20.0],
                tip: -2.0,
            },
        ),
        (
            "sphere punch",
            Tool::EllipsoidPunch {
                axes: [30.0; 3],
                tip: 0.0,
            },
        ),
        ("elliptic die", Tool::elliptic_die([40.0, 25.0], 1.5, 5.0)),
        (
            "elliptic die, tall",
            Tool::elliptic_die([20.0, 35.0], 1.5, 5.0),
        ),
        ("circular die", Tool::elliptic_die([30.0, 30.0], 1.5, 5.0)),
    ]
}

#[test]
fn normal_is_the_unit_gradient_of_the_distance() {
    let mut g = Lcg(1);
    for (name, tool) in tools() {
        let mut checked = 0;
        for _ in 0..4000 {
            let p = [
                g.range(-50.0, 50.0),
                g.range(-50.0, 50.0),
                g.range(-25.0, 10.0),
            ];
            let d = tool.distance(p);
            if d.d.abs() > 3.0 {
                continue;
            }
            // The normal is exactly the gradient of the distance field; the field is an exact
            // distance (|∇d| = 1) except in the variable-radius corner blend of a punch whose
            // nose radius exceeds its corner radius.
            // In the blend the corner radius changes with height, so the field is a smooth
            // implicit surface rather than an exact distance: |∇d| stays within 20 % of 1.
            let n2: f64 = d.n.iter().map(|v| v * v).sum();
            let blended = name.contains("r<");
            let ok = if blended {
                (0.64..=1.44).contains(&n2)
            } else {
                (n2 - 1.0).abs() < 1e-9
            };
            assert!(ok, "{name}: |n|² = {n2} at {p:?}");
            let h = 1e-6;
            let mut fd = [0.0; 3];
            for m in 0..3 {
                let mut pp = p;
                let mut pm = p;
                pp[m] += h;
                pm[m] -= h;
                fd[m] = (tool.distance(pp).d - tool.distance(pm).d) / (2.0 * h);
            }
            let err = (0..3).map(|m| (fd[m] - d.n[m]).abs()).fold(0.0, f64::max);
            assert!(
                err < 1e-5,
                "{name}: gradient {fd:?} vs normal {:?} at {p:?}",
                d.n
            );
            checked += 1;
        }
        assert!(
            checked > 100,
            "{name}: only {checked} points near the surface"
        );
    }
}

#[test]
fn normal_is_continuous_near_the_surface() {
    // C1: the normal changes by O(step) between close points, everywhere near the surface.
    let mut g = Lcg(2);
    for (name, tool) in tools() {
        for _ in 0..20000 {
            let p = [
                g.range(-50.0, 50.0),
                g.range(-50.0, 50.0),
                g.range(-25.0, 10.0),
            ];
            let d = tool.distance(p);
            if d.d.abs() > 1.0 {
                continue;
            }
            let q = [
                p[0] + g.range(-1e-4, 1e-4),
                p[1] + g.range(-1e-4, 1e-4),
                p[2] + g.range(-1e-4, 1e-4),
            ];
            let e = tool.distance(q);
            let jump = (0..3).map(|m| (d.n[m] - e.n[m]).abs()).fold(0.0, f64::max);
            assert!(
                jump < 1e-2,
                "{name}: normal jumps by {jump} between {p:?} and {q:?}"
            );
        }
    }
}

#[test]
fn normal_is_continuous_across_the_corner_diagonal_and_the_arc_centre() {
    // Where creases would hide: the diagonal through the plan corner and the corner arc's
    // centre, on the nose, for punches with r < rp and r > rp.
    for (name, tool) in tools()
        .into_iter()
        .filter(|(n, _)| n.starts_with("box punch"))
    {
        for k in 0..2000 {
            let depth = -3.0 + 20.0 * k as f64 / 2000.0;
            for along in [15.0, 17.5, 20.0, 22.0, 24.0, 25.0, 26.0, 28.0, 30.0, 32.0] {
                let p = [along + 1e-7, along - 1e-7, depth];
                let q = [along - 1e-7, along + 1e-7, depth];
                let (a, b) = (tool.distance(p), tool.distance(q));
                if a.d.abs() > 2.0 {
                    continue;
                }
                let jump = (0..3).map(|m| (a.n[m] - b.n[m]).abs()).fold(0.0, f64::max);
                assert!(
                    jump < 1e-4,
                    "{name}: normal jumps by {jump} across the diagonal at {p:?}"
                );
            }
        }
    }
}

#[test]
fn closed_form_distances() {
    let punch = Tool::box_punch([60.0, 60.0], 10.0, 6.0, -3.0);
    // Below the flat nose: the distance to the plane z = −3.
    let d = punch.distance([0.0, 0.0, -5.0]);
    assert!((d.d - 2.0).abs() < 1e-12 && (d.n[2] + 1.0).abs() < 1e-12);
    // Beside a side wall, above the nose: distance to the plane x = 30.
    let d = punch.distance([32.0, 0.0, 20.0]);
    assert!((d.d - 2.0).abs() < 1e-12 && (d.n[0] - 1.0).abs() < 1e-12);
    // On the nose torus along the x axis: centre line at x = 24, z = 3; radius 6.
    let t = std::f64::consts::FRAC_PI_4;
    let p = [24.0 + 8.0 * t.cos(), 0.0, 3.0 - 8.0 * t.sin()];
    assert!((punch.distance(p).d - 2.0).abs() < 1e-12);
    // Plan corner of the side wall: radius 10 about (20, 20).
    let p = [20.0 + 12.0 * t.cos(), 20.0 + 12.0 * t.sin(), 30.0];
    assert!((punch.distance(p).d - 2.0).abs() < 1e-12);
    // Die: on the face, on the entry torus, in the opening wall.
    let die = Tool::box_die([60.0, 60.0], 5.0, 1.5, 5.0);
    assert!((die.distance([60.0, 0.0, 1.0]).d - 1.0).abs() < 1e-12);
    let p = [31.5 + 5.0 - 7.0 * t.cos(), 0.0, -5.0 + 7.0 * t.sin()];
    assert!(
        (die.distance(p).d - 2.0).abs() < 1e-12,
        "{}",
        die.distance(p).d
    );
    assert!((die.distance([30.0, 0.0, -20.0]).d - 1.5).abs() < 1e-12);
    // Sphere of radius 30 with its lowest point at z = 0.
    let sphere = Tool::EllipsoidPunch {
        axes: [30.0; 3],
        tip: 0.0,
    };
    let p = [10.0, -20.0, 30.0 - 5.0];
    let exact = analytic::sphere_distance([0.0, 0.0, 30.0], 30.0, p);
    assert!((sphere.distance(p).d - exact).abs() < 1e-9);
    // Ellipsoid: on an axis the distance is the gap to the vertex.
    let ell = Tool::EllipsoidPunch {
        axes: [40.0, 25.0, 20.0],
        tip: 0.0,
    };
    assert!((ell.distance([0.0, 0.0, -3.0]).d - 3.0).abs() < 1e-9);
    assert!((ell.distance([45.0, 0.0, 20.0]).d - 5.0).abs() < 1e-9);
}

#[test]
fn curvature_of_the_nose_and_the_sphere() {
    // On a sphere of radius R, ∂n/∂x at the surface = (I − n nᵀ)/R.
    let sphere = Tool::EllipsoidPunch {
        axes: [30.0; 3],
        tip: 0.0,
    };
    let h = sphere.curvature([0.0, 0.0, 0.0], 1.0);
    let k_sphere = analytic::circle_curvature(30.0);
    assert!((h[0][0] - k_sphere).abs() < 1e-6 && (h[1][1] - k_sphere).abs() < 1e-6);
    assert!(h[2][2].abs() < 1e-6);
    // On the nose torus at its lowest-outward point along x, the profile curvature is 1/rp.
    let punch = Tool::box_punch([60.0, 60.0], 10.0, 6.0, 0.0);
    let t = std::f64::consts::FRAC_PI_4;
    let p = [24.0 + 6.0 * t.cos(), 0.0, 6.0 - 6.0 * t.sin()];
    let h = punch.curvature(p, 1.0);
    // Profile direction in the x–z plane, tangent to the circle.
    let tdir = [t.sin(), 0.0, t.cos()];
    let k: f64 = (0..3)
        .map(|i| (0..3).map(|j| tdir[i] * h[i][j] * tdir[j]).sum::<f64>())
        .sum();
    assert!(
        (k - analytic::circle_curvature(6.0)).abs() < 1e-5,
        "profile curvature {k}"
    );
    // The largest principal curvature: 1/R on the sphere, 1/rp on the nose (its hoop
    // curvature is smaller), 0 on the flat top.
    let largest = sphere.largest_curvature([0.0, 0.0, 0.0], 1.0);
    assert!(
        (largest - analytic::circle_curvature(30.0)).abs() < 1e-6,
        "{largest}"
    );
    let largest = punch.largest_curvature(p, 1.0);
    assert!(
        (largest - analytic::circle_curvature(6.0)).abs() < 1e-5,
        "{largest}"
    );
    assert_eq!(punch.largest_curvature([0.0, 0.0, 0.0], 1.0), 0.0);
}

#[test]
fn elliptic_opening_distance_against_the_nearest_of_many_points() {
    // The die's elliptic opening (semi-axes 40 × 25, offset 1.5): its plan distance at a point
    // is the distance to the nearest of 400,000 points on the ellipse (to within their spacing),
    // less the offset; inside the evolute on the major axis the nearest point leaves the axis.
    let (a, b, offset) = (40.0, 25.0, 1.5);
    let die = Tool::elliptic_die([a, b], offset, 5.0);
    let samples: Vec<[f64; 2]> = (0..400_000)
        .map(|i| {
            let t = std::f64::consts::TAU * i as f64 / 400_000.0;
            [a * t.cos(), b * t.sin()]
        })
        .collect();
    let mut g = Lcg(7);
    let mut points: Vec<[f64; 2]> = (0..300)
        .map(|_| [g.range(-60.0, 60.0), g.range(-45.0, 45.0)])
        .collect();
    points.extend([
        [5.0, 0.0],
        [0.0, 3.0],
        [0.0, 0.0],
        [-30.0, 0.0],
        [0.0, -40.0],
    ]);
    for p in points {
        let nearest = samples
            .iter()
            .map(|s| ((p[0] - s[0]).powi(2) + (p[1] - s[1]).powi(2)).sqrt())
            .fold(f64::INFINITY, f64::min);
        let inside = (p[0] / a).powi(2) + (p[1] / b).powi(2) < 1.0;
        let expected = if inside { -nearest } else { nearest } - offset;
        let (d, _, _) = die.opening_distance(p[0], p[1]).unwrap();
        assert!((d - expected).abs() < 1e-6, "at {p:?}: {d} vs {expected}");
    }
}
