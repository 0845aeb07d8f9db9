//! The distance a mesh tool gives the fabric, checked against answers from outside the code:
//! a sphere's and a plane's distance in closed form, finite differences of the interpolant,
//! and an analytic die's own flange (`d_open − rm`).
//!
//! ```text
//!   sphere R = 12 mm, tessellated at 0.5 mm     die of the paper's box, tessellated at 1 mm
//!        .-"""-.                                 ───────╮        ╭───────  face z = 0
//!       /   ·   \   d = |p| − R                          │ opening│
//!       \       /                                        ╰────────╯
//!        '-...-'
//! ```

use wovenform::core::drawing::DrawingProblem;
use wovenform::core::tools::capped::tool_surfaces;
use wovenform::core::tools::mesh_tool::{Limits, MeshTool, Role};
use wovenform::core::tools::nearest::ExactDistance;
use wovenform::core::tools::sampled::SampledDistance;
use wovenform::core::tools::surface::TriSurface;
use wovenform::core::tools::tessellate::tessellate;

const R: f64 = 12.0;

fn sphere(spacing: f64) -> TriSurface {
    let field = |p: [f64; 3]| (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt() - R;
    let s = tessellate(&field, [-R - 3.0; 3], [R + 3.0; 3], spacing);
    s.check().unwrap();
    s
}

/// Points spread around the sphere at distances −2 … 2 mm from it (a fixed sequence).
fn points_near_sphere(n: usize) -> Vec<[f64; 3]> {
    (0..n)
        .map(|i| {
            let u = (i as f64 * 0.618_033_988_75).fract();
            let v = (i as f64 * 0.414_213_562_37).fract();
            let w = (i as f64 * 0.732_050_807_57).fract();
            let (theta, z) = (std::f64::consts::TAU * u, 2.0 * v - 1.0);
            let r = (1.0 - z * z).sqrt();
            let radius = R + 4.0 * (w - 0.5);
            [
                radius * r * theta.cos(),
                radius * r * theta.sin(),
                radius * z,
            ]
        })
        .collect()
}

#[test]
fn the_exact_distance_is_the_spheres_within_its_chords_with_the_right_sign() {
    let s = sphere(0.5);
    let exact = ExactDistance::new(&s);
    // Chords of 0.5 mm cells (edges up to ~0.9 mm) sag by at most e²/(8R) ≈ 0.01 mm.
    for p in points_near_sphere(2000) {
        let want = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt() - R;
        let got = exact.query(p);
        assert!((got.d - want).abs() < 0.012, "{p:?}: {} vs {want}", got.d);
        if want.abs() > 0.02 {
            assert_eq!(got.d > 0.0, want > 0.0, "{p:?}");
        }
    }
}

#[test]
fn the_sampled_distance_is_smooth_and_its_derivatives_are_its_own() {
    let s = sphere(0.5);
    let sampled = SampledDistance::new(&s, 0.5, 1.0, 3.0);
    let h = 1e-5;
    for p in points_near_sphere(300) {
        let e = sampled.evaluate(p, true);
        let want = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt() - R;
        if want.abs() > 0.9 {
            // Beyond the band a bound may answer: it never exceeds the distance.
            assert!(e.d.abs() <= want.abs() + 0.02, "{p:?}: {} vs {want}", e.d);
            continue;
        }
        assert!((e.d - want).abs() < 0.015, "{p:?}: {} vs {want}", e.d);
        // The normal is the sphere's within a degree.
        let r = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
        let cos = (0..3).map(|a| e.n[a] * p[a] / r).sum::<f64>();
        let len = (0..3).map(|a| e.n[a] * e.n[a]).sum::<f64>().sqrt();
        assert!(cos / len > 1f64.to_radians().cos(), "{p:?}: {:?}", e.n);
        // Gradient and Hessian against central differences of the interpolant itself.
        let hess = e.hessian.unwrap();
        for a in 0..3 {
            let (mut pp, mut pm) = (p, p);
            pp[a] += h;
            pm[a] -= h;
            let (ep, em) = (sampled.evaluate(pp, true), sampled.evaluate(pm, true));
            let fd = (ep.d - em.d) / (2.0 * h);
            assert!((fd - e.n[a]).abs() < 1e-6, "{p:?} ∂{a}: {fd} vs {}", e.n[a]);
            for (b, row) in hess.iter().enumerate() {
                let fd = (ep.n[b] - em.n[b]) / (2.0 * h);
                // The Hessian jumps across cell faces (the interpolant is C1): skip a
                // difference that straddles one.
                let tol = 1e-4 * (1.0 + row[a].abs());
                if (fd - row[a]).abs() > tol {
                    let g = [p[a] / 0.5 - h / 0.5, p[a] / 0.5 + h / 0.5];
                    assert!(
                        g[0].floor() != g[1].floor(),
                        "{p:?} H{a}{b}: {fd} vs {}",
                        hess[b][a]
                    );
                }
            }
        }
    }
}

#[test]
fn the_gradient_is_continuous_across_the_lattice_cells() {
    let s = sphere(0.5);
    let sampled = SampledDistance::new(&s, 0.5, 1.0, 3.0);
    let (o, h) = (sampled.lattice_origin(), sampled.spacing());
    let (mut worst, mut value_jump, mut hessian_jump): (f64, f64, f64) = (0.0, 0.0, 0.0);
    let mut crossings = 0;
    for k in 0..120 {
        let y = -3.0 + 0.05 * k as f64;
        let z = 0.17;
        let x = (R * R - y * y - z * z).sqrt();
        // The lattice planes x = o + j·h on either side of the surface point.
        for j in [-1.0, 0.0, 1.0, 2.0] {
            let xa = o[0] + ((x - o[0]) / h).floor() * h + j * h;
            let eps = 1e-9;
            let (l, r) = (
                sampled.evaluate([xa - eps, y, z], true),
                sampled.evaluate([xa + eps, y, z], true),
            );
            if l.d.abs() > 0.9 {
                continue;
            }
            crossings += 1;
            value_jump = value_jump.max((l.d - r.d).abs());
            for a in 0..3 {
                worst = worst.max((l.n[a] - r.n[a]).abs());
                for b in 0..3 {
                    hessian_jump = hessian_jump
                        .max((l.hessian.unwrap()[a][b] - r.hessian.unwrap()[a][b]).abs());
                }
            }
        }
    }
    assert!(crossings > 200, "{crossings}");
    assert!(
        value_jump < 1e-8 && worst < 1e-6,
        "jumps: value {value_jump}, gradient {worst}"
    );
    // The curvature does jump (C1, not C2): the test sees cell faces.
    assert!(hessian_jump > 1e-4, "{hessian_jump}");
}

#[test]
fn a_flat_face_has_its_planes_distance_and_no_curvature() {
    let p = DrawingProblem::paper_box(10.0, 15.0, 10.0);
    let (_, die) = tool_surfaces(&p.tooling, p.blank_mm, p.stroke_mm, 1.0);
    let die = MeshTool::new(Role::Die, "die.stl", &die, 0.5, 1.0).unwrap();
    for (x, y) in [(60.0, 0.0), (70.0, 70.0), (-55.0, 20.0), (0.0, -80.0)] {
        for z in [-0.3, -0.01, 0.0, 0.02, 0.6] {
            let e = die.distance.evaluate([x, y, z], true);
            assert!((e.d - z).abs() < 1e-9, "({x}, {y}, {z}): {}", e.d);
            assert!((e.n[2] - 1.0).abs() < 1e-9 && e.n[0].abs() < 1e-9);
            assert!(e.hessian.unwrap().iter().flatten().all(|v| v.abs() < 1e-9));
        }
    }
}

#[test]
fn the_flange_starts_where_the_analytic_dies_entry_radius_ends() {
    let p = DrawingProblem::paper_box(10.0, 15.0, 10.0);
    let (_, die_surface) = tool_surfaces(&p.tooling, p.blank_mm, p.stroke_mm, 1.0);
    let mesh_die = MeshTool::new(Role::Die, "die.stl", &die_surface, 0.5, 1.0).unwrap();
    let flange = mesh_die.flange.as_ref().unwrap();
    let (_, die) = p.tooling.tools();
    for k in 0..400 {
        let t = k as f64 / 400.0 * std::f64::consts::TAU;
        for r in [30.0, 40.0, 45.0, 60.0] {
            let (x, y) = (r * t.cos(), r * t.sin());
            let (d_open, _, rm) = die.opening_distance(x, y).unwrap();
            let want = d_open - rm;
            if want.abs() > 4.0 {
                continue;
            }
            let (got, _) = flange.distance(x, y);
            // The face's edge is found to a tessellation cell (1 mm) and a plan cell.
            assert!(
                (got - want).abs() < 1.0,
                "({x:.1}, {y:.1}): {got} vs {want}"
            );
        }
    }
    let half = mesh_die.flange.as_ref().unwrap().opening_half();
    let want = p.tooling.opening_half()[0] + 10.0;
    assert!((half[0] - want).abs() < 1.0, "{half:?} vs {want}");
}

#[test]
fn tables_kept_where_the_fabric_reaches_change_no_value_there() {
    // The paper box's die (a 210 mm plate, its face from 41.5 mm off the centre) kept only
    // within 70 mm of the centre in plan and 10 mm of its face: the same distance and flange
    // where kept, the exact distance elsewhere.
    let p = DrawingProblem::paper_box(10.0, 15.0, 10.0);
    let (_, surface) = tool_surfaces(&p.tooling, p.blank_mm, p.stroke_mm, 1.0);
    let whole = MeshTool::new(Role::Die, "die.stl", &surface, 0.5, 1.0).unwrap();
    let reach = ([-70.0, -70.0, -10.0], [70.0, 70.0, 10.0]);
    let limits = Limits {
        reach,
        budget_bytes: f64::INFINITY,
    };
    let kept = MeshTool::within(Role::Die, "die.stl", &surface, 0.5, 1.0, &limits).unwrap();
    let exact = ExactDistance::new(&surface);
    let (mut inside, mut off) = (0, 0);
    for i in 0..4000 {
        let f = |k: f64| (i as f64 * k).fract();
        let q = [
            180.0 * f(0.618_033_988_75) - 90.0,
            180.0 * f(0.414_213_562_37) - 90.0,
            30.0 * f(0.732_050_807_57) - 20.0,
        ];
        let (a, b) = (
            whole.distance.evaluate(q, true),
            kept.distance.evaluate(q, true),
        );
        if (0..3).all(|k| q[k] > reach.0[k] && q[k] < reach.1[k]) {
            inside += 1;
            assert_eq!(a.d.to_bits(), b.d.to_bits(), "{q:?}");
            assert_eq!(a.n, b.n, "{q:?}");
        } else if (0..3).any(|k| q[k] < reach.0[k] - 6.0 || q[k] > reach.1[k] + 6.0) && q[2] < 0.0 {
            // Off the kept lattice (a page, 4 mm, and a stencil beyond the reach), within the
            // tool's box (x and y within its ±105 mm plate): the exact distance (to rounding:
            // another hierarchy may pick another of several nearest triangles).
            off += 1;
            assert!((b.d - exact.query(q).d).abs() < 1e-9, "{q:?}");
        }
        let (fa, fb) = (
            whole.flange.as_ref().unwrap(),
            kept.flange.as_ref().unwrap(),
        );
        // Within 10 mm of the face's edge (where the holder's grip fades in) and that edge
        // within the raster kept: the same flange.
        if q[0].abs() < 60.0 && q[1].abs() < 60.0 && fa.distance(q[0], q[1]).0.abs() < 10.0 {
            assert_eq!(fa.distance(q[0], q[1]), fb.distance(q[0], q[1]), "{q:?}");
        }
    }
    assert!(inside > 300 && off > 300, "{inside} {off}");
    // A budget smaller than the tables: refused before they are made, naming the sizes.
    let tight = Limits {
        reach,
        budget_bytes: 1e5,
    };
    let e = MeshTool::within(Role::Die, "die.stl", &surface, 0.5, 1.0, &tight).unwrap_err();
    assert!(e.to_string().contains("over the 1.000e5 bytes"), "{e}");
}
