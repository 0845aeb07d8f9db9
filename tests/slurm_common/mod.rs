//! What the Slurm tests share: reading a sweep's rows.

use std::collections::BTreeMap;
use std::path::Path;

/// The rows of `dir/results.csv`: their count, and each design's max shear and verdict.
pub fn rows(dir: &Path) -> (usize, BTreeMap<String, (String, String)>) {
    let mut r = csv::Reader::from_path(dir.join("results.csv")).unwrap();
    let h = r.headers().unwrap().clone();
    let col = |name: &str| h.iter().position(|c| c == name).unwrap();
    let (d, s, v) = (col("design"), col("max_shear_deg"), col("verdict"));
    let mut n = 0;
    let mut map = BTreeMap::new();
    for rec in r.records() {
        let rec = rec.unwrap();
        n += 1;
        map.insert(rec[d].to_string(), (rec[s].to_string(), rec[v].to_string()));
    }
    (n, map)
}
