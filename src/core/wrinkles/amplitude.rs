//! The wrinkle amplitude: out-of-plane waviness of the fabric that the tools do not explain.
//!
//! A node is *anchored* where a tool gives it its shape: on the punch, on the die's radius or
//! wall, or pressed between die and holder. What the tools explain of the free fabric between
//! them is taken from two smooth surfaces spanned over the anchored nodes (`Spanned`): a
//! uniform net (harmonic: never beyond its anchors, flat where they are flat) and a plate
//! (each yarn line a cubic spline through its anchors: it keeps the curvature the anchors give,
//! a cylinder, a saddle, a dome, the curved wall between a punch and a die, and overshoots where
//! they turn sharply, as from a punch's nose radius to its flat top). A free node lying between
//! the two is explained; one beyond both on the same side *deviates* by its distance from the
//! nearer, measured along its own surface normal (so a yarn sliding in the fabric's plane does
//! not count). Neither surface can follow a wave shorter than the span between anchors: both
//! are flat between two clamps, and under a flange crest whose troughs rest on the die.
//!
//! Along every yarn line (a grid line), the free nodes between two anchors form a *span* (a
//! span that reaches the blank's edge ends at its last node); a span's amplitude is the
//! peak-to-valley of its deviations, its anchored ends counting 0: a bulge between two clamps
//! counts its height, a wave its crest-to-trough depth. Each node takes the larger amplitude of
//! its two spans (warp and weft); an anchored node, 0.
//!
//! A free part of the blank with too few anchors to hold the surfaces (none, or all on one
//! line) has no unique reference: the conjugate gradients start from the positions, so what
//! they cannot fix stays where it is and shows no deviation there.

use crate::core::membrane::mesh::Mesh;
use crate::core::vec3::{cross, dot, sub};

/// The wrinkle field of a deformed yarn-grid blank.
#[derive(Clone, Debug, PartialEq)]
pub struct Wrinkles {
    /// The amplitude of the spans through each node, mm (0 at anchored nodes).
    pub per_node_mm: Vec<f64>,
    /// The largest amplitude, mm, and the node farthest from its span's chord there.
    pub max_mm: f64,
    pub at_node: usize,
}

/// Each node's surface normal (not normalised): the sum of its elements' normals, each the
/// cross product of the element's diagonals (twice its area).
fn nodal_normals(mesh: &Mesh, x: &[[f64; 3]]) -> Vec<[f64; 3]> {
    let mut n = vec![[0.0; 3]; x.len()];
    for q in &mesh.quads {
        let c = cross(sub(x[q[2]], x[q[0]]), sub(x[q[3]], x[q[1]]));
        for &i in q {
            for m in 0..3 {
                n[i][m] += c[m];
            }
        }
    }
    n
}

/// The warp and weft lines of an `[n1, n2]` grid, each its nodes in order.
fn grid_lines([n1, n2]: [usize; 2]) -> Vec<Vec<usize>> {
    let id = |i: usize, j: usize| j * (n1 + 1) + i;
    let warp = (0..=n2).map(|j| (0..=n1).map(|i| id(i, j)).collect::<Vec<_>>());
    let weft = (0..=n1).map(|i| (0..=n2).map(|j| id(i, j)).collect::<Vec<_>>());
    warp.chain(weft).collect()
}

/// The smooth surfaces spanned over the anchors.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Spanned {
    /// A uniform net: the least sum of squared edge lengths, each free node at the mean of its
    /// grid neighbours (harmonic). Never beyond its anchors' range; flat where they are.
    Net,
    /// A plate: the least sum of squared second differences along the yarns, each line a cubic
    /// spline through its anchors. Keeps the curvature its anchors give (where they come two
    /// rows deep, as a tool's contact does: every quadratic surface), and overshoots past a
    /// kink in them.
    Plate,
}

/// `out = Aᵀ A u` for the surface's operator `A` (edge differences or second differences
/// along `lines`), zero at the anchors.
fn apply(kind: Spanned, lines: &[Vec<usize>], anchored: &[bool], u: &[f64], out: &mut [f64]) {
    out.iter_mut().for_each(|v| *v = 0.0);
    for line in lines {
        match kind {
            Spanned::Net => {
                for w in line.windows(2) {
                    let d = u[w[1]] - u[w[0]];
                    out[w[0]] -= d;
                    out[w[1]] += d;
                }
            }
            Spanned::Plate => {
                for w in line.windows(3) {
                    let d = u[w[0]] - 2.0 * u[w[1]] + u[w[2]];
                    out[w[0]] += d;
                    out[w[1]] -= 2.0 * d;
                    out[w[2]] += d;
                }
            }
        }
    }
    for (o, a) in out.iter_mut().zip(anchored) {
        if *a {
            *o = 0.0;
        }
    }
}

/// The surface `kind` through the anchored nodes: the free nodes' positions that make its
/// energy least, by conjugate gradients from the positions themselves to a relative residual
/// of 1e-10 (or 20,000 iterations).
fn reference(
    kind: Spanned,
    lines: &[Vec<usize>],
    x: &[[f64; 3]],
    anchored: &[bool],
) -> Vec<[f64; 3]> {
    let mut reference = x.to_vec();
    for m in 0..3 {
        let mut u: Vec<f64> = x.iter().map(|p| p[m]).collect();
        let operator = |v: &[f64], out: &mut [f64]| apply(kind, lines, anchored, v, out);
        crate::core::sparse::conjugate::relax_free(operator, &mut u, 1e-10, 0.0, 20_000);
        for (r, ui) in reference.iter_mut().zip(u) {
            r[m] = ui;
        }
    }
    reference
}

/// The peak-to-valley of a span's deviations (0 counted, as an anchored end), and the index
/// of the largest |deviation|.
fn peak_to_valley(dev: &[f64]) -> (usize, f64) {
    let (mut lo, mut hi, mut far, mut far_d) = (0.0f64, 0.0f64, 0, -1.0f64);
    for (k, &d) in dev.iter().enumerate() {
        lo = lo.min(d);
        hi = hi.max(d);
        if d.abs() > far_d {
            (far, far_d) = (k, d.abs());
        }
    }
    (far, hi - lo)
}

/// Each node's deviation from what the anchors explain, along its surface normal, mm: its
/// distance from the nearer of the two surfaces spanned over them (`Spanned`) when it lies
/// beyond both on the same side, else 0 (between them it is explained); 0 at the anchored
/// nodes. `lines` are the mesh's yarn lines, each its nodes in order.
pub fn deviations_along(
    mesh: &Mesh,
    lines: &[Vec<usize>],
    x: &[[f64; 3]],
    anchored: &[bool],
) -> Vec<f64> {
    let (signed, _) = signed_distances(mesh, lines, x, anchored);
    signed.iter().map(|d| unexplained(d)).collect()
}

/// The deviation left by signed distances from references: 0 when the node lies between two
/// of them (they disagree in sign), else the nearest.
fn unexplained(d: &[f64]) -> f64 {
    let (lo, hi) = d
        .iter()
        .fold((f64::MAX, f64::MIN), |(l, h), &v| (l.min(v), h.max(v)));
    if lo <= 0.0 && hi >= 0.0 {
        0.0
    } else if hi < 0.0 {
        hi
    } else {
        lo
    }
}

/// Each node's signed distances (along its unit normal, mm) from the net and the plate, and
/// its unit normal; anchored nodes and nodes without a normal get `[0, 0]`.
fn signed_distances(
    mesh: &Mesh,
    lines: &[Vec<usize>],
    x: &[[f64; 3]],
    anchored: &[bool],
) -> (Vec<Vec<f64>>, Vec<[f64; 3]>) {
    let normals = nodal_normals(mesh, x);
    let net = reference(Spanned::Net, lines, x, anchored);
    let plate = reference(Spanned::Plate, lines, x, anchored);
    let mut units = vec![[0.0; 3]; x.len()];
    let signed = (0..x.len())
        .map(|i| {
            let n = normals[i];
            let len = dot(n, n).sqrt();
            if anchored[i] || len == 0.0 {
                return vec![0.0, 0.0];
            }
            units[i] = [n[0] / len, n[1] / len, n[2] / len];
            vec![
                dot(sub(x[i], net[i]), units[i]),
                dot(sub(x[i], plate[i]), units[i]),
            ]
        })
        .collect();
    (signed, units)
}

/// The deviations along a span anchored at both ends with its chord as a third reference (a
/// free yarn bridging straight between two tools is explained by it: the double dome's saddle),
/// else with the net and the plate alone.
fn span_deviations(
    span: &[usize],
    x: &[[f64; 3]],
    anchored: &[bool],
    signed: &[Vec<f64>],
    units: &[[f64; 3]],
) -> Vec<f64> {
    let (first, last) = (span[0], span[span.len() - 1]);
    if !(anchored[first] && anchored[last]) {
        return span.iter().map(|&i| unexplained(&signed[i])).collect();
    }
    let n = (span.len() - 1) as f64;
    span.iter()
        .enumerate()
        .map(|(k, &i)| {
            if anchored[i] {
                return 0.0;
            }
            let t = k as f64 / n;
            let on_chord = [0, 1, 2].map(|m| x[first][m] + t * (x[last][m] - x[first][m]));
            let chord = dot(sub(x[i], on_chord), units[i]);
            unexplained(&[signed[i][0], signed[i][1], chord])
        })
        .collect()
}

/// The wrinkle field of a yarn-grid blank at positions `x`, `anchored` saying which nodes a
/// tool holds. `None` for a mesh that is not a yarn grid.
pub fn wrinkles(mesh: &Mesh, x: &[[f64; 3]], anchored: &[bool]) -> Option<Wrinkles> {
    Some(wrinkles_along(mesh, &grid_lines(mesh.grid?), x, anchored))
}

/// What a drawing's tools and loads explain of its free fabric beyond the two surfaces.
#[derive(Clone, Copy, Debug)]
pub struct Explained<'a> {
    /// Each anchored node's facet sag on its tool, mm: on a tool of curvature `κ` the fabric
    /// between two nodes `h` apart sags from their chord by `h²κ/8`, which surfaces sampled at
    /// the nodes cannot resolve, so a span's peak-to-valley up to the larger sag at its two
    /// ends is the mesh's facets on a curved tool, not a wrinkle (0 on flat tools and clamps).
    pub sag_mm: &'a [f64],
    /// Each node taut: stretched in every direction of the fabric's plane by all its elements.
    /// A taut membrane cannot wrinkle (tension field theory: a wrinkle needs a compressed or
    /// slack direction), so a taut free node takes the shape its tools and loads give it, and
    /// its deviation is explained (a wall bridging between tools, pulled tight).
    pub taut: &'a [bool],
}

/// [`wrinkles`] with what the tools explain (`explained`) taken off, and each span held at
/// both ends by tools also measured from its chord. `None` for a mesh that is not a yarn grid.
pub fn wrinkles_resolved(
    mesh: &Mesh,
    x: &[[f64; 3]],
    anchored: &[bool],
    explained: Explained,
) -> Option<Wrinkles> {
    let lines = grid_lines(mesh.grid?);
    Some(field_of(mesh, &lines, x, anchored, Some(explained)))
}

/// [`wrinkles`] on a mesh whose yarn lines are `lines` (each its nodes in order).
pub fn wrinkles_along(
    mesh: &Mesh,
    lines: &[Vec<usize>],
    x: &[[f64; 3]],
    anchored: &[bool],
) -> Wrinkles {
    field_of(mesh, lines, x, anchored, None)
}

fn field_of(
    mesh: &Mesh,
    lines: &[Vec<usize>],
    x: &[[f64; 3]],
    anchored: &[bool],
    explained: Option<Explained>,
) -> Wrinkles {
    let (signed, units) = signed_distances(mesh, lines, x, anchored);
    let mut field = Wrinkles {
        per_node_mm: vec![0.0; x.len()],
        max_mm: 0.0,
        at_node: 0,
    };
    for line in lines {
        for span in spans(line, anchored) {
            // A drawing's spans also take their chord as a reference (`span_deviations`).
            let local: Vec<f64> = match explained {
                Some(e) => span_deviations(span, x, anchored, &signed, &units)
                    .into_iter()
                    .zip(span)
                    .map(|(d, &i)| if e.taut[i] { 0.0 } else { d })
                    .collect(),
                None => span.iter().map(|&i| unexplained(&signed[i])).collect(),
            };
            let (k, amp) = peak_to_valley(&local);
            let far = span[k];
            let sag = explained.map_or(0.0, |e| {
                let ends = [span[0], span[span.len() - 1]];
                ends.iter()
                    .filter(|&&i| anchored[i])
                    .map(|&i| e.sag_mm[i])
                    .fold(0.0, f64::max)
            });
            let amp = (amp - sag).max(0.0);
            for &i in span {
                if !anchored[i] {
                    field.per_node_mm[i] = field.per_node_mm[i].max(amp);
                }
            }
            if amp > field.max_mm {
                (field.max_mm, field.at_node) = (amp, far);
            }
        }
    }
    field
}

/// The spans of a line: each run of free nodes with the anchors that bound it (a run at the
/// line's end stops at the end node).
fn spans<'a>(line: &'a [usize], anchored: &[bool]) -> Vec<&'a [usize]> {
    let mut out = Vec::new();
    let mut k = 0;
    while k < line.len() {
        if anchored[line[k]] {
            k += 1;
            continue;
        }
        let start = k.saturating_sub(1);
        let mut end = k;
        while end < line.len() && !anchored[line[end]] {
            end += 1;
        }
        let stop = end.min(line.len() - 1);
        if stop > start {
            out.push(&line[start..=stop]);
        }
        k = end;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::FRAC_PI_2;

    fn strip(n: usize) -> Mesh {
        Mesh::yarn_grid(
            [0.0, 0.0],
            [100.0, 10.0],
            [n, 2],
            std::f64::consts::FRAC_PI_2,
        )
    }

    fn ends_anchored(mesh: &Mesh) -> Vec<bool> {
        mesh.nodes
            .iter()
            .map(|p| p[0] < 1e-9 || p[0] > 100.0 - 1e-9)
            .collect()
    }

    #[test]
    fn a_flat_or_tilted_plane_has_no_wrinkle() {
        let mesh = strip(20);
        let anchored = ends_anchored(&mesh);
        let tilted: Vec<[f64; 3]> = mesh
            .nodes
            .iter()
            .map(|p| [p[0], p[1], 0.3 * p[0] - 0.2 * p[1]])
            .collect();
        for x in [&mesh.nodes, &tilted] {
            let w = wrinkles(&mesh, x, &anchored).unwrap();
            assert!(w.max_mm < 1e-12, "{}", w.max_mm);
        }
    }

    #[test]
    fn a_span_loses_the_facet_sag_of_its_ends_and_no_more() {
        let mesh = strip(50);
        // The whole border held, so that every span, warp and weft, ends on anchors.
        let anchored: Vec<bool> = mesh
            .nodes
            .iter()
            .map(|p| p[0] < 1e-9 || p[0] > 100.0 - 1e-9 || p[1] < 1e-9 || p[1] > 10.0 - 1e-9)
            .collect();
        let pi = std::f64::consts::PI;
        let bulge: Vec<[f64; 3]> = mesh
            .nodes
            .iter()
            .map(|p| {
                [
                    p[0],
                    p[1],
                    3.0 * (pi * p[0] / 100.0).sin() * (pi * p[1] / 10.0).sin(),
                ]
            })
            .collect();
        let plain = wrinkles(&mesh, &bulge, &anchored).unwrap().max_mm;
        assert!((plain - 3.0).abs() < 0.01, "{plain}");
        // Flat clamps: no sag, the plain figure; anchors on a tool that sags 0.5 mm, 0.5 less;
        // a sag above the figure, nothing.
        for (sag_end, want) in [(0.0, plain), (0.5, plain - 0.5), (4.0, 0.0)] {
            let sag: Vec<f64> = anchored
                .iter()
                .map(|&a| if a { sag_end } else { 0.0 })
                .collect();
            let taut = vec![false; mesh.nodes.len()];
            let explained = Explained {
                sag_mm: &sag,
                taut: &taut,
            };
            let w = wrinkles_resolved(&mesh, &bulge, &anchored, explained).unwrap();
            assert!(
                (w.max_mm - want).abs() < 1e-12,
                "{sag_end}: {} against {want}",
                w.max_mm
            );
        }
    }

    #[test]
    fn a_taut_span_is_explained_and_a_slack_part_keeps_its_figure() {
        let mesh = strip(50);
        let anchored = ends_anchored(&mesh);
        let tau = std::f64::consts::TAU;
        // Two waves of depth 2 mm along the strip.
        let waves: Vec<[f64; 3]> = mesh
            .nodes
            .iter()
            .map(|p| [p[0], p[1], (2.0 * tau * p[0] / 100.0).sin()])
            .collect();
        let sag = vec![0.0; mesh.nodes.len()];
        let figure = |taut: &[bool]| {
            let explained = Explained { sag_mm: &sag, taut };
            wrinkles_resolved(&mesh, &waves, &anchored, explained)
                .unwrap()
                .max_mm
        };
        let slack = figure(&vec![false; mesh.nodes.len()]);
        assert!((slack - 2.0).abs() < 0.02, "{slack}");
        assert_eq!(figure(&vec![true; mesh.nodes.len()]), 0.0);
        // Taut over the first wave only: the second keeps its depth.
        let half: Vec<bool> = mesh.nodes.iter().map(|p| p[0] < 50.0).collect();
        let kept = figure(&half);
        assert!((kept - 2.0).abs() < 0.05, "{kept}");
    }

    #[test]
    fn a_clamped_bulge_counts_its_height_and_a_wave_its_depth() {
        let mesh = strip(50);
        let anchored = ends_anchored(&mesh);
        let tau = std::f64::consts::TAU;
        let shape = |f: &dyn Fn(f64) -> f64| -> Vec<[f64; 3]> {
            mesh.nodes.iter().map(|p| [p[0], p[1], f(p[0])]).collect()
        };
        // The Euler strip's first mode, A (1 − cos 2πx/L)/2: height A.
        let bulge = shape(&|x| 0.5 * 3.0 * (1.0 - (tau * x / 100.0).cos()));
        let w = wrinkles(&mesh, &bulge, &anchored).unwrap();
        assert!((w.max_mm - 3.0).abs() < 0.03, "{}", w.max_mm);
        assert!((mesh.nodes[w.at_node][0] - 50.0).abs() < 1e-9);
        // A full sine wave of amplitude a: crest to trough 2a; and three waves.
        for waves in [1.0, 3.0] {
            let wave = shape(&|x| 1.5 * (waves * tau * x / 100.0).sin());
            let w = wrinkles(&mesh, &wave, &anchored).unwrap();
            assert!((w.max_mm - 3.0).abs() < 0.03, "{waves}: {}", w.max_mm);
        }
        // Anchored nodes carry none.
        assert_eq!(w.per_node_mm[0], 0.0);
    }

    /// A 60 × 60 mm blank in 2 mm elements, anchored on its two outer rings of nodes (a
    /// tool's contact is more than one node deep: it gives the slope too).
    fn square() -> (Mesh, Vec<bool>) {
        let mesh = Mesh::yarn_grid([-30.0, -30.0], [60.0, 60.0], [30, 30], FRAC_PI_2);
        let anchored = mesh
            .nodes
            .iter()
            .map(|p| p[0].abs() > 27.99 || p[1].abs() > 27.99)
            .collect();
        (mesh, anchored)
    }

    #[test]
    fn a_saddle_spanned_between_its_anchors_is_no_wrinkle() {
        // z = (x² − y²)/60: 15 mm high and deep at the corners, curved both ways.
        let (mesh, anchored) = square();
        let saddle = |p: &[f64; 3]| (p[0] * p[0] - p[1] * p[1]) / 60.0;
        let x: Vec<[f64; 3]> = mesh.nodes.iter().map(|p| [p[0], p[1], saddle(p)]).collect();
        let w = wrinkles(&mesh, &x, &anchored).unwrap();
        assert!(w.max_mm < 1e-6, "{}", w.max_mm);
        // A wave on it, 12 mm long, fading to nothing at the anchors: its depth along the
        // middle line, as the nodes sample it (the saddle's slope there is under 0.2).
        let tau = std::f64::consts::TAU;
        let fade = |v: f64| (1.0 - (v / 28.0).powi(2)).max(0.0);
        let wave = |p: &[f64; 3]| 0.25 * (tau * p[0] / 12.0).sin() * fade(p[0]) * fade(p[1]);
        let x: Vec<[f64; 3]> = mesh
            .nodes
            .iter()
            .map(|p| [p[0], p[1], saddle(p) + wave(p)])
            .collect();
        let w = wrinkles(&mesh, &x, &anchored).unwrap();
        let line: Vec<f64> = (0..=30)
            .map(|i| wave(&[-30.0 + 2.0 * i as f64, 0.0, 0.0]))
            .collect();
        let sampled =
            line.iter().fold(0.0f64, |a, &b| a.max(b)) - line.iter().fold(0.0f64, |a, &b| a.min(b));
        assert!(
            (w.max_mm / sampled - 1.0).abs() < 0.05,
            "{} against {sampled}",
            w.max_mm
        );
    }

    #[test]
    fn a_cylinder_or_a_dome_spanned_between_anchors_is_no_wrinkle() {
        // Curved one way (z = x²/120) and both ways (a paraboloid, 15 mm deep): the splines
        // spanned over the anchored rings reproduce them, as they would not a wave.
        let (mesh, anchored) = square();
        for f in [
            (|p: &[f64; 3]| p[0] * p[0] / 120.0) as fn(&[f64; 3]) -> f64,
            |p: &[f64; 3]| (p[0] * p[0] + p[1] * p[1]) / 120.0,
        ] {
            let x: Vec<[f64; 3]> = mesh.nodes.iter().map(|p| [p[0], p[1], f(p)]).collect();
            let w = wrinkles(&mesh, &x, &anchored).unwrap();
            assert!(w.max_mm < 0.01, "{}", w.max_mm);
        }
    }

    #[test]
    fn a_curve_in_the_fabric_plane_is_no_wrinkle() {
        // The strip bent in its own plane (an arc in x-y): the normal is z, the arc's
        // deviation from its chord lies in the plane.
        let mesh = strip(40);
        let anchored = ends_anchored(&mesh);
        let x: Vec<[f64; 3]> = mesh
            .nodes
            .iter()
            .map(|p| {
                let th = p[0] / 200.0;
                let r = 200.0 - p[1];
                [r * th.sin(), 200.0 - r * th.cos(), 0.0]
            })
            .collect();
        let w = wrinkles(&mesh, &x, &anchored).unwrap();
        assert!(w.max_mm < 1e-12, "{}", w.max_mm);
    }

    #[test]
    fn spans_run_between_anchors_and_to_the_edge() {
        let line = [0, 1, 2, 3, 4, 5, 6];
        let anchored = [false, true, false, false, true, true, false];
        let s = spans(&line, &anchored);
        assert_eq!(s, vec![&line[0..=1], &line[1..=4], &line[5..=6]]);
    }
}
