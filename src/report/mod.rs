//! Reports: charts (PNG), tables (CSV) and the paper's figures reproduced from the law; the
//! maps, VTU file and summary of a drawing run; the report sheet of a design sweep.
pub mod bench;
pub mod bias;
pub mod cantilever;
pub mod canvas;
pub mod contour;
pub mod converge;
pub mod error;
pub mod figure6;
pub mod fit;
pub mod frontier;
pub mod maps;
pub mod mirror;
pub mod newton_trace;
pub mod panels;
pub mod plot;
pub mod sheet;
pub mod summary;
pub mod sweep;
pub mod vtu;

/// `v` with `decimals` decimals, never `-0.0` (a tiny negative rounds to a plain zero).
pub fn fixed(v: f64, decimals: usize) -> String {
    crate::show::Fixed(v, decimals).to_string()
}

/// "s" after a count other than one.
pub fn plural(n: usize) -> &'static str {
    if n == 1 { "" } else { "s" }
}

#[cfg(test)]
mod tests {
    #[test]
    fn fixed_never_prints_minus_zero() {
        assert_eq!(super::fixed(-0.04, 1), "0.0");
        assert_eq!(super::fixed(-0.0, 0), "0");
        assert_eq!(super::fixed(-0.06, 1), "-0.1");
        assert_eq!(super::fixed(6439.23, 1), "6439.2");
        assert_eq!(super::plural(1), "");
        assert_eq!(super::plural(2), "s");
    }
}
