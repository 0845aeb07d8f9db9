//! Throughput measurements for `wovenform bench`: medians of repeated timings, one thread.

use std::hint::black_box;
use std::time::Instant;

use crate::core::element::{self, ElementGeometry, ElementOutput, GAUSS};
use crate::core::law::{CellLaw, CellParams};

/// One measured rate.
#[derive(Clone, Debug)]
pub struct Rate {
    pub name: &'static str,
    /// Median over the repetitions, evaluations per second.
    pub per_second: f64,
    /// All repetitions, evaluations per second.
    pub samples: Vec<f64>,
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(|a, b| a.total_cmp(b));
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

fn measure(name: &'static str, repetitions: usize, mut run: impl FnMut() -> usize) -> Rate {
    run(); // warm-up
    let samples: Vec<f64> = (0..repetitions)
        .map(|_| {
            let t = Instant::now();
            let n = run();
            n as f64 / t.elapsed().as_secs_f64()
        })
        .collect();
    Rate {
        name,
        per_second: median(samples.clone()),
        samples,
    }
}

/// Law evaluations (tensions + tangent) per second, each cell warm-started from its previous
/// state along a loading path, as the solver calls it: strains march in small increments.
pub fn law_rate(repetitions: usize) -> Rate {
    let law = CellLaw::new(CellParams::PAPER_GLASS);
    let cells = 1000;
    let steps = 200;
    measure(
        "law evaluations (with tangent, warm-started)",
        repetitions,
        || {
            let mut states = vec![law.initial_state(); cells];
            for step in 0..steps {
                for (i, s) in states.iter_mut().enumerate() {
                    let k = 1.0 + (i % 7) as f64;
                    let e1 = 2e-5 * step as f64 * (1.0 + 0.001 * i as f64);
                    let r = law.evaluate(black_box([e1, e1 / k]), *s);
                    *s = r.crimp;
                    black_box(r.dt);
                }
            }
            cells * steps
        },
    )
}

/// Element internal force + tangent evaluations per second (2×2 Gauss points, woven law).
pub fn element_rate(repetitions: usize) -> Rate {
    let law = CellLaw::new(CellParams::PAPER_GLASS);
    let x0 = [
        [0.0, 0.0, 0.0],
        [5.0, 0.0, 0.0],
        [5.2, 4.9, 0.0],
        [0.1, 5.0, 0.0],
    ];
    let geo = ElementGeometry::new(
        &x0,
        Some([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]),
        law.p.l0[0] * law.p.l0[1],
    )
    .expect("valid element");
    let n = 20_000;
    let mut out = ElementOutput::default();
    measure("element force + tangent evaluations", repetitions, || {
        let mut crimp = [law.initial_state(); GAUSS];
        for i in 0..n {
            let e = 0.002 + 1e-7 * (i % 100) as f64;
            let x = x0.map(|p| [p[0] * (1.0 + e), p[1] * (1.0 + 0.5 * e), 0.01 * p[0]]);
            element::evaluate(&geo, &law, black_box(&x), &mut crimp, true, &mut out);
            black_box(&out.k);
        }
        n
    })
}
