//! The outputs of `wovenform converge`: each rung's error against its wall time, log-log (PNG
//! and text), the table and the CSV.

use std::fmt::Write as _;

use crate::accuracy::Accuracy;
use crate::report::plot::{Colour, LegendAt, LineChart, Series};
use crate::study::converge::{FIGURES, Ladder};

/// Error of the maximum shear (°) and of the punch force (%) against wall time (s), for the
/// mesh ladder and the step ladder. Rungs with no error to show (the reference itself) are
/// left out of the logarithmic axes.
pub fn chart(mesh: &Ladder, steps: &Ladder) -> LineChart {
    let mut chart = LineChart::new(
        "Error against run time (one core)",
        "wall time (s)",
        "error: max shear (°), punch force (%)",
    )
    .log_log();
    chart.legend_at = LegendAt::UpperRight;
    let points = |ladder: &Ladder, k: usize| -> Vec<(f64, f64)> {
        ladder
            .rungs
            .iter()
            .enumerate()
            .filter(|(_, r)| r.converged)
            .map(|(i, r)| (r.wall_s, ladder.error(i, k)))
            .filter(|p| p.0 > 0.0 && p.1 > 0.0)
            .collect()
    };
    for (ladder, name, colour) in [
        (mesh, "mesh ladder", Colour::nth(0)),
        (steps, "step ladder", Colour::nth(1)),
    ] {
        let (shear, force) = (points(ladder, 0), points(ladder, 1));
        chart.push(Series::line(
            format!("{name}: max shear (°)"),
            shear.clone(),
            colour,
        ));
        chart.push(Series::markers("", shear, colour));
        chart.push(Series::dashed(
            format!("{name}: punch force (%)"),
            force.clone(),
            colour,
        ));
        chart.push(Series::crosses("", force, colour));
    }
    chart
}

/// The same errors as a text chart (log-log), for a terminal or a README: `S`/`F` the mesh
/// ladder's max shear (°) and punch force (%), `s`/`f` the step ladder's; `*` where marks meet.
/// Axes span whole decades around the points.
pub fn text_chart(mesh: &Ladder, steps: &Ladder, width: usize, height: usize) -> String {
    let mut points: Vec<(f64, f64, char)> = Vec::new();
    for (ladder, marks) in [(mesh, ['S', 'F']), (steps, ['s', 'f'])] {
        for (i, r) in ladder.rungs.iter().enumerate() {
            for (k, mark) in marks.iter().enumerate() {
                let e = ladder.error(i, k);
                if r.converged && r.wall_s > 0.0 && e > 0.0 {
                    points.push((r.wall_s, e, *mark));
                }
            }
        }
    }
    text_scatter(&points, width, height, "wall time (s)", "error")
}

/// A log-log scatter of `(x, y, mark)` on a `width × height` grid of characters, with decade
/// ticks on both axes.
fn text_scatter(
    points: &[(f64, f64, char)],
    width: usize,
    height: usize,
    x_label: &str,
    y_label: &str,
) -> String {
    if points.is_empty() {
        return String::from("(no errors to chart)\n");
    }
    let decades = |f: fn(&(f64, f64, char)) -> f64| {
        let lo = points.iter().map(f).fold(f64::INFINITY, f64::min);
        let hi = points.iter().map(f).fold(0.0, f64::max);
        let (lo, hi) = (lo.log10().floor(), hi.log10().ceil());
        (lo, if hi > lo { hi } else { lo + 1.0 })
    };
    let (x0, x1) = decades(|p| p.0);
    let (y0, y1) = decades(|p| p.1);
    let (w, h) = (width.max(10), height.max(4));
    let column = |x: f64| (((x.log10() - x0) / (x1 - x0)) * (w - 1) as f64).round() as usize;
    let row = |y: f64| (((y1 - y.log10()) / (y1 - y0)) * (h - 1) as f64).round() as usize;
    let mut grid = vec![vec![' '; w]; h];
    for &(x, y, mark) in points {
        let (c, r) = (column(x).min(w - 1), row(y).min(h - 1));
        grid[r][c] = if grid[r][c] == ' ' || grid[r][c] == mark {
            mark
        } else {
            '*'
        };
    }
    let label = |e: f64| format!("1e{}", e as i64);
    let mut out = format!("{y_label}\n");
    for (r, line) in grid.iter().enumerate() {
        // A tick where a whole decade falls on this row.
        let e = y1 - (r as f64) * (y1 - y0) / (h - 1) as f64;
        let tick = if (e - e.round()).abs() < 0.5 * (y1 - y0) / (h - 1) as f64 {
            label(e.round())
        } else {
            String::new()
        };
        out.push_str(&format!(
            "{tick:>6} |{}\n",
            line.iter().collect::<String>().trim_end()
        ));
    }
    out.push_str(&format!("{:>6} +{}\n", "", "-".repeat(w)));
    let mut axis = vec![' '; w + 14];
    for e in (x0 as i64)..=(x1 as i64) {
        let c = column(10f64.powi(e as i32));
        for (j, ch) in label(e as f64).chars().enumerate() {
            if let Some(slot) = axis.get_mut(8 + c + j) {
                *slot = ch;
            }
        }
    }
    out.push_str(axis.iter().collect::<String>().trim_end());
    out.push_str(&format!("\n{:>width$}\n", x_label, width = w + 8));
    out
}

/// The rows of both ladders as CSV: each rung's figures and their error bounds against its
/// ladder's reference (distance to it plus its uncertainty).
pub fn csv(mesh: &Ladder, steps: &Ladder) -> String {
    let mut w = csv::Writer::from_writer(Vec::new());
    let header = [
        "ladder",
        "element_size_mm",
        "max_step",
        "dofs",
        "steps",
        "newton_iterations",
        "wall_s",
        "converged",
        "max_shear_deg",
        "punch_force_n",
        "draw_in_mm",
        "max_tension_n",
        "err_max_shear_deg",
        "err_punch_force_pct",
        "err_draw_in_mm",
        "err_max_tension_pct",
    ];
    w.write_record(header).expect("writing to memory");
    for ladder in [mesh, steps] {
        for (i, r) in ladder.rungs.iter().enumerate() {
            let e = errors(ladder, i);
            let f = r.figures;
            w.write_record([
                r.ladder.to_string(),
                r.element_size_mm.to_string(),
                r.max_step.to_string(),
                r.dofs.to_string(),
                r.steps.to_string(),
                r.newton_iterations.to_string(),
                format!("{:.3}", r.wall_s),
                r.converged.to_string(),
                format!("{:.4}", f[0]),
                format!("{:.2}", f[1]),
                format!("{:.4}", f[2]),
                format!("{:.2}", f[3]),
                format!("{:.4}", e[0]),
                format!("{:.3}", e[1]),
                format!("{:.4}", e[2]),
                format!("{:.3}", e[3]),
            ])
            .expect("writing to memory");
        }
    }
    String::from_utf8(w.into_inner().expect("writing to memory")).expect("UTF-8")
}

fn errors(ladder: &Ladder, i: usize) -> Vec<f64> {
    (0..FIGURES.len()).map(|k| ladder.error(i, k)).collect()
}

/// The table `converge` prints: both ladders' rungs with units, each ladder's reference, and
/// the accuracy levels' errors where the mesh ladder has their element sizes.
pub fn table(mesh: &Ladder, steps: &Ladder) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "{:<6} {:>7} {:>6} {:>6} {:>5} {:>6} {:>8}  {:>9} {:>8} {:>8} {:>8}   error ≤ {:>7} {:>7} {:>7} {:>7}",
        "ladder",
        "h mm",
        "Δλ",
        "dofs",
        "steps",
        "Newton",
        "wall s",
        "shear °",
        "force N",
        "draw mm",
        "T N",
        "shear °",
        "force %",
        "draw mm",
        "T %"
    );
    for ladder in [mesh, steps] {
        for (i, r) in ladder.rungs.iter().enumerate() {
            let e = errors(ladder, i);
            let f = r.figures;
            let _ = writeln!(
                out,
                "{:<6} {:>7} {:>6.4} {:>6} {:>5} {:>6} {:>8.2}  {:>9.3} {:>8.1} {:>8.3} {:>8.1}           {:>7.3} {:>7.2} {:>7.3} {:>7.2}{}",
                r.ladder,
                r.element_size_mm,
                r.max_step,
                r.dofs,
                r.steps,
                r.newton_iterations,
                r.wall_s,
                f[0],
                f[1],
                f[2],
                f[3],
                e[0],
                e[1],
                e[2],
                e[3],
                if r.converged {
                    ""
                } else {
                    "  (did not converge)"
                }
            );
        }
        let refs: Vec<String> = FIGURES
            .iter()
            .zip(&ladder.reference)
            .map(|(name, r)| match r.order {
                Some(p) => format!(
                    "{name} {:.4} ± {:.4} (Richardson, order {p:.2})",
                    r.value, r.uncertainty
                ),
                None => format!(
                    "{name} {:.4} ± {:.4} (the finest rung; ± the spread of the rungs before it)",
                    r.value, r.uncertainty
                ),
            })
            .collect();
        let _ = writeln!(
            out,
            "reference of the {} ladder: {}",
            ladder.rungs[0].ladder,
            refs.join("; ")
        );
    }
    write_levels(&mut out, mesh);
    out
}

/// The accuracy levels' errors, where the mesh ladder has their element sizes.
fn write_levels(out: &mut String, mesh: &Ladder) {
    for level in Accuracy::ALL {
        if let Some(i) = mesh
            .rungs
            .iter()
            .position(|r| (r.element_size_mm - level.element_size_mm()).abs() < 1e-9)
        {
            let _ = writeln!(
                out,
                "{level} ({} mm): max shear error ≤ {:.2}°, punch force error ≤ {:.2} %, {:.2} s on one core",
                level.element_size_mm(),
                mesh.error(i, 0),
                mesh.error(i, 1),
                mesh.rungs[i].wall_s
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn marks_sit_at_their_logarithms() {
        // x over [1e-1, 1e1] on 21 columns: 1 s is column 10; y over [1e-2, 1e0] on 5 rows:
        // 0.1 is row 2, 1 row 0, 0.01 row 4.
        let chart = text_scatter(
            &[(1.0, 0.1, 'S'), (0.1, 1.0, 'F'), (10.0, 0.01, 'f')],
            21,
            5,
            "x",
            "y",
        );
        let rows: Vec<&str> = chart.lines().skip(1).take(5).collect();
        assert_eq!(rows[0], "   1e0 |F", "{chart}");
        assert_eq!(rows[2], "  1e-1 |          S", "{chart}");
        assert_eq!(rows[4], "  1e-2 |                    f", "{chart}");
        // Two different marks in one cell become `*`.
        let chart = text_scatter(&[(1.0, 1.0, 'S'), (1.0, 1.0, 's')], 11, 4, "x", "y");
        assert!(chart.contains('*'), "{chart}");
    }
}
