//! Level lines of a nodal field over a quad mesh (marching squares), chained into polylines.
//!
//! A line crosses an edge whose two nodes lie on either side of the level, where the field,
//! taken linear along the edge, equals it. A quad crossed on all four edges (a saddle) is
//! split by its mean value. Each point of a line is kept as its edge and the fraction along
//! it, so that any other nodal quantity (the initial position, the final one) can be read at
//! the same material points.

use std::collections::HashMap;

/// A point on a mesh edge: nodes `a < b` and the fraction `t` of the way from `a` to `b`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EdgePoint {
    pub a: usize,
    pub b: usize,
    pub t: f64,
}

impl EdgePoint {
    /// The value of a nodal vector field at the point (linear along the edge).
    pub fn at<const N: usize>(&self, field: &[[f64; N]]) -> [f64; N] {
        let (p, q) = (field[self.a], field[self.b]);
        std::array::from_fn(|i| p[i] + self.t * (q[i] - p[i]))
    }
}

/// The lines where `values` (one per node) equals `level` over `quads`, each a polyline of
/// edge points in order; a closed line ends on its first point.
pub fn level_lines(quads: &[[usize; 4]], values: &[f64], level: f64) -> Vec<Vec<EdgePoint>> {
    let above = |n: usize| values[n] > level;
    let crossing = |a: usize, b: usize| {
        let (a, b) = if a < b { (a, b) } else { (b, a) };
        let (va, vb) = (values[a], values[b]);
        EdgePoint {
            a,
            b,
            t: ((level - va) / (vb - va)).clamp(0.0, 1.0),
        }
    };
    // Segments as pairs of edges (the key of an edge: its nodes in order).
    let mut points: HashMap<(usize, usize), EdgePoint> = HashMap::new();
    let mut segments: Vec<[(usize, usize); 2]> = Vec::new();
    for q in quads {
        let cut: Vec<Option<EdgePoint>> = (0..4)
            .map(|i| {
                let (a, b) = (q[i], q[(i + 1) % 4]);
                (above(a) != above(b)).then(|| crossing(a, b))
            })
            .collect();
        let edges: Vec<usize> = (0..4).filter(|&i| cut[i].is_some()).collect();
        let pairs: Vec<(usize, usize)> = match edges.len() {
            2 => vec![(edges[0], edges[1])],
            4 => {
                // A saddle: the corners on the side of the quad's mean value are joined.
                let mean = 0.25 * q.iter().map(|&n| values[n]).sum::<f64>();
                if (mean > level) == above(q[0]) {
                    vec![(0, 1), (2, 3)]
                } else {
                    vec![(3, 0), (1, 2)]
                }
            }
            _ => Vec::new(),
        };
        for (i, j) in pairs {
            let (p, r) = (cut[i].unwrap(), cut[j].unwrap());
            points.insert((p.a, p.b), p);
            points.insert((r.a, r.b), r);
            segments.push([(p.a, p.b), (r.a, r.b)]);
        }
    }
    chain(&segments, &points)
}

/// The segments joined end to end: open lines from their ends first, then the loops.
fn chain(
    segments: &[[(usize, usize); 2]],
    points: &HashMap<(usize, usize), EdgePoint>,
) -> Vec<Vec<EdgePoint>> {
    let mut at: HashMap<(usize, usize), Vec<usize>> = HashMap::new();
    for (s, ends) in segments.iter().enumerate() {
        for e in ends {
            at.entry(*e).or_default().push(s);
        }
    }
    let mut used = vec![false; segments.len()];
    let mut lines = Vec::new();
    // Ends of open lines (an edge with one segment) first, in a fixed order.
    let mut starts: Vec<(usize, usize)> = at
        .iter()
        .filter(|(_, s)| s.len() == 1)
        .map(|(e, _)| *e)
        .collect();
    starts.sort_unstable();
    let mut loop_starts: Vec<(usize, usize)> = segments.iter().map(|s| s[0]).collect();
    loop_starts.sort_unstable();
    for start in starts.into_iter().chain(loop_starts) {
        let mut line = vec![points[&start]];
        let mut here = start;
        while let Some(&s) = at[&here].iter().find(|&&s| !used[s]) {
            used[s] = true;
            let [p, q] = segments[s];
            here = if p == here { q } else { p };
            line.push(points[&here]);
        }
        if line.len() > 1 {
            lines.push(line);
        }
    }
    lines
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An `n × n` grid of quads on [-1, 1]²: its nodes and quads.
    fn grid(n: usize) -> (Vec<[f64; 2]>, Vec<[usize; 4]>) {
        let h = 2.0 / n as f64;
        let nodes = (0..=n)
            .flat_map(|j| (0..=n).map(move |i| [-1.0 + i as f64 * h, -1.0 + j as f64 * h]))
            .collect();
        let id = |i: usize, j: usize| j * (n + 1) + i;
        let quads = (0..n)
            .flat_map(|j| {
                (0..n).map(move |i| [id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)])
            })
            .collect();
        (nodes, quads)
    }

    #[test]
    fn a_circle_is_one_closed_line_at_its_radius() {
        let (nodes, quads) = grid(40);
        let r2: Vec<f64> = nodes.iter().map(|p| p[0] * p[0] + p[1] * p[1]).collect();
        let lines = level_lines(&quads, &r2, 0.25);
        assert_eq!(lines.len(), 1);
        let line = &lines[0];
        assert_eq!(
            line.first(),
            line.last(),
            "a closed line ends where it starts"
        );
        // Linear along the edges, r² = 0.25 is met within h² / 4 / (2 r) of radius 0.5.
        let h = 0.05;
        for p in line {
            let [x, y] = p.at(&nodes);
            let r = (x * x + y * y).sqrt();
            assert!((r - 0.5).abs() < h * h / 4.0, "r = {r}");
        }
        // Around the whole circle: its length, 2π r, to the same order.
        let length: f64 = line
            .windows(2)
            .map(|w| {
                let ([x0, y0], [x1, y1]) = (w[0].at(&nodes), w[1].at(&nodes));
                (x1 - x0).hypot(y1 - y0)
            })
            .sum();
        assert!((length - std::f64::consts::PI).abs() < 0.01, "{length}");
    }

    #[test]
    fn a_linear_field_gives_a_straight_open_line() {
        let (nodes, quads) = grid(7);
        let f: Vec<f64> = nodes.iter().map(|p| 2.0 * p[0] + p[1]).collect();
        let lines = level_lines(&quads, &f, 0.3);
        assert_eq!(lines.len(), 1);
        let line = &lines[0];
        assert_ne!(line.first(), line.last());
        for p in line {
            let [x, y] = p.at(&nodes);
            assert!((2.0 * x + y - 0.3).abs() < 1e-12);
        }
        // From one side of the square to another.
        let ends = [line[0].at(&nodes), line[line.len() - 1].at(&nodes)];
        for [x, y] in ends {
            assert!(x.abs() == 1.0 || y.abs() == 1.0, "end ({x}, {y}) inside");
        }
    }

    #[test]
    fn a_saddle_splits_by_the_mean() {
        // One quad, corners 0 and 2 above: with the mean (0.5) above the level they are
        // joined and the lines cut off corners 1 and 3; with it below, corners 0 and 2.
        let quads = [[0, 1, 2, 3]];
        let cut_off = |level: f64| -> Vec<usize> {
            let mut corners: Vec<usize> = level_lines(&quads, &[1.0, 0.0, 1.0, 0.0], level)
                .iter()
                .map(|l| {
                    let (p, q) = (l[0], l[1]);
                    [p.a, p.b]
                        .into_iter()
                        .find(|n| *n == q.a || *n == q.b)
                        .unwrap()
                })
                .collect();
            corners.sort_unstable();
            corners
        };
        assert_eq!(cut_off(0.4), vec![1, 3]);
        assert_eq!(cut_off(0.6), vec![0, 2]);
        assert!(level_lines(&quads, &[1.0, 1.0, 1.0, 1.0], 0.5).is_empty());
    }
}
