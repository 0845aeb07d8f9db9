//! The peak of a field over a neighbourhood of stated size: the largest area-weighted mean of
//! |value| over the elements whose initial centres lie within a radius of an element's initial
//! centre. With the radius of one woven cell this is the peak at the scale the model describes
//! (the cell's law is a homogenised one), and unlike the largest element value it does not
//! depend on how finely a corner happens to be meshed.

use std::collections::HashMap;

use super::result::DrawingResult;

/// An element's centre (or one of its mirror images) and the element.
type Image = ([f64; 2], usize);

impl DrawingResult {
    /// The largest mean of `|values|` (one per element) over a disc of `radius_mm` around an
    /// element's initial centre, weighted by the elements' initial areas, and that element.
    /// When a quarter was solved its mirror images (about x = 0 and y = 0) are counted, so an
    /// element by a symmetry plane sees the whole disc. `(0, 0.0)` for an empty field.
    pub fn neighbourhood_peak(&self, values: &[f64], radius_mm: f64) -> (usize, f64) {
        self.neighbourhood_peaks(&[values], radius_mm)[0]
    }

    /// [`DrawingResult::neighbourhood_peak`] of several fields, with one neighbour search.
    pub fn neighbourhood_peaks(&self, fields: &[&[f64]], radius_mm: f64) -> Vec<(usize, f64)> {
        let m = &self.mesh;
        let (centres, areas): (Vec<[f64; 2]>, Vec<f64>) = m
            .quads
            .iter()
            .map(|q| {
                let x = q.map(|n| m.nodes[n]);
                let c = [
                    0.25 * (x[0][0] + x[1][0] + x[2][0] + x[3][0]),
                    0.25 * (x[0][1] + x[1][1] + x[2][1] + x[3][1]),
                ];
                (c, initial_area(&x))
            })
            .unzip();
        let mirrors: &[[f64; 2]] = if self.quarter {
            &[[1.0, 1.0], [-1.0, 1.0], [1.0, -1.0], [-1.0, -1.0]]
        } else {
            &[[1.0, 1.0]]
        };
        let r = radius_mm.max(1e-9);
        let cell = |p: [f64; 2]| ((p[0] / r).floor() as i64, (p[1] / r).floor() as i64);
        // Every image of every element, bucketed by squares of side r.
        let mut buckets: HashMap<(i64, i64), Vec<Image>> = HashMap::new();
        for (e, c) in centres.iter().enumerate() {
            for s in mirrors {
                let p = [s[0] * c[0], s[1] * c[1]];
                buckets.entry(cell(p)).or_default().push((p, e));
            }
        }
        let mut best = vec![(0, 0.0); fields.len()];
        let mut sums = vec![0.0; fields.len()];
        for (e, c) in centres.iter().enumerate() {
            let (i, j) = cell(*c);
            let mut weight = 0.0;
            sums.fill(0.0);
            for di in -1..=1 {
                for dj in -1..=1 {
                    for (p, f) in buckets.get(&(i + di, j + dj)).into_iter().flatten() {
                        let d = [p[0] - c[0], p[1] - c[1]];
                        if d[0] * d[0] + d[1] * d[1] <= r * r {
                            weight += areas[*f];
                            for (sum, values) in sums.iter_mut().zip(fields) {
                                *sum += areas[*f] * values[*f].abs();
                            }
                        }
                    }
                }
            }
            for (b, sum) in best.iter_mut().zip(&sums) {
                if weight > 0.0 && sum / weight > b.1 {
                    *b = (e, sum / weight);
                }
            }
        }
        best
    }
}

/// Area of a quad in the plane of its first three nodes' projection (the blank starts flat).
fn initial_area(x: &[[f64; 3]; 4]) -> f64 {
    let d1 = [x[2][0] - x[0][0], x[2][1] - x[0][1]];
    let d2 = [x[3][0] - x[1][0], x[3][1] - x[1][1]];
    0.5 * (d1[0] * d2[1] - d1[1] * d2[0]).abs()
}

#[cfg(test)]
mod tests {
    use crate::core::drawing::result::DrawingResult;
    use crate::core::membrane::mesh::Mesh;

    fn result(mesh: Mesh, quarter: bool) -> DrawingResult {
        DrawingResult {
            converged: true,
            ..DrawingResult::at_rest(mesh, quarter, 1.0, 4.76)
        }
    }

    #[test]
    fn a_uniform_field_peaks_at_its_value_and_one_hot_element_is_averaged_away() {
        // 20 × 20 elements of 1 mm: a uniform field's neighbourhood mean is the field.
        let mesh = Mesh::yarn_grid(
            [0.0, 0.0],
            [20.0, 20.0],
            [20, 20],
            std::f64::consts::FRAC_PI_2,
        );
        let r = result(mesh, false);
        let n = r.mesh.quads.len();
        let (_, peak) = r.neighbourhood_peak(&vec![7.0; n], 2.5);
        assert!((peak - 7.0).abs() < 1e-12);
        // One element at 100, the rest 0: within a disc of radius 2.5 mm around an inner
        // centre lie the centres (i, j) with i² + j² ≤ 6.25: 21 elements of equal area, so
        // the peak is 100/21 (a closed form), at the hot element or a neighbour.
        let mut v = vec![0.0; n];
        v[10 * 20 + 10] = 100.0;
        let (_, peak) = r.neighbourhood_peak(&v, 2.5);
        assert!((peak - 100.0 / 21.0).abs() < 1e-12, "{peak}");
    }

    #[test]
    fn a_quarter_counts_its_mirror_images() {
        // The corner element of a quarter (centre (0.5, 0.5)) with radius 1.2 mm sees its own
        // three images (distance 1, 1, √2 > 1.2: two of them) and its two neighbours: 5 equal
        // areas, the corner hot at 50 → its images carry the 50 too: (3·50)/5.
        let mesh = Mesh::yarn_grid(
            [0.0, 0.0],
            [10.0, 10.0],
            [10, 10],
            std::f64::consts::FRAC_PI_2,
        );
        let r = result(mesh, true);
        let mut v = vec![0.0; r.mesh.quads.len()];
        v[0] = 50.0;
        let (e, peak) = r.neighbourhood_peak(&v, 1.2);
        assert_eq!(e, 0);
        assert!((peak - 150.0 / 5.0).abs() < 1e-12, "{peak}");
    }
}
