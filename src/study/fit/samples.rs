//! The measured curves a fit reads: a CSV with a header naming the columns
//! `eps1,eps2,t11_n,t22_n` (any order, other columns ignored; the header `wovenform law
//! --curves` writes), the fabric strains along warp and weft and the measured tensions per yarn
//! (N). Blank lines and `#` comments are skipped. Read with the `csv` crate (RFC 4180 quoting).

use std::path::Path;

/// The strains the law is used for: `[min, max]` on each of ε11, ε22.
pub const STRAIN_RANGE: [f64; 2] = [-0.05, 0.10];

/// One measured point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample {
    /// `[ε11, ε22]`.
    pub eps: [f64; 2],
    /// Measured `[T11, T22]`, N per yarn.
    pub t: [f64; 2],
    /// Line in the file (1-based).
    pub line: usize,
}

const COLUMNS: [&str; 4] = ["eps1", "eps2", "t11_n", "t22_n"];

/// Reads a data CSV; errors name the file, the line and the column.
pub fn read_samples(path: &Path) -> Result<Vec<Sample>, String> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| format!("{}: cannot read the data file: {e}", path.display()))?;
    parse_samples(&text, &path.display().to_string())
}

/// The position of each of [`COLUMNS`] in the header.
fn column_index(header: &csv::StringRecord, line: u64, origin: &str) -> Result<[usize; 4], String> {
    let expected = "expected a header line naming the columns eps1,eps2,t11_n,t22_n (strains; tensions per yarn, N)";
    let shown: Vec<&str> = header.iter().collect();
    let shown = shown.join(",");
    let mut index = [0usize; 4];
    for (c, col) in COLUMNS.iter().enumerate() {
        let found: Vec<usize> = (0..header.len()).filter(|&i| &header[i] == *col).collect();
        index[c] = match found[..] {
            [i] => i,
            [] => {
                return Err(format!(
                    "{origin}: line {line}: the header `{shown}` has no column {col}: {expected}"
                ));
            }
            _ => {
                return Err(format!(
                    "{origin}: line {line}: the header names column {col} more than once"
                ));
            }
        };
    }
    Ok(index)
}

/// One line as a CSV record (RFC 4180 quoting; fields trimmed).
fn record(line: &str) -> Result<csv::StringRecord, csv::Error> {
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(false)
        .trim(csv::Trim::All)
        .from_reader(line.as_bytes());
    reader
        .records()
        .next()
        .unwrap_or_else(|| Ok(csv::StringRecord::new()))
}

/// Parses data CSV text; `origin` names it in errors. A record per line (no line breaks
/// inside a field), so that errors give the file's line numbers.
pub fn parse_samples(text: &str, origin: &str) -> Result<Vec<Sample>, String> {
    let mut lines = text
        .lines()
        .enumerate()
        .map(|(i, l)| (i as u64 + 1, l.trim()))
        .filter(|(_, l)| !l.is_empty() && !l.starts_with('#'))
        .map(|(n, l)| (n, record(l).map_err(|e| format!("{origin}: line {n}: {e}"))));
    let (header_line, header) = lines.next().ok_or_else(|| {
        format!("{origin}: the file is empty: expected a header line naming the columns eps1,eps2,t11_n,t22_n")
    })?;
    let header = header?;
    let index = column_index(&header, header_line, origin)?;
    let mut samples = Vec::new();
    for (n, record) in lines {
        let record = record?;
        if record.len() != header.len() {
            return Err(format!(
                "{origin}: line {n}: expected {} comma-separated fields as in the header, found {}",
                header.len(),
                record.len()
            ));
        }
        let mut v = [0.0; 4];
        for c in 0..4 {
            let field = &record[index[c]];
            let x: f64 = field
                .parse()
                .ok()
                .filter(|x: &f64| x.is_finite())
                .ok_or_else(|| {
                    format!(
                        "{origin}: line {n}, column {}: `{field}` is not a finite number",
                        COLUMNS[c]
                    )
                })?;
            if c < 2 && !(STRAIN_RANGE[0]..=STRAIN_RANGE[1]).contains(&x) {
                return Err(format!(
                    "{origin}: line {n}, column {}: {x} is outside the law's strain range [{}, {}]",
                    COLUMNS[c], STRAIN_RANGE[0], STRAIN_RANGE[1]
                ));
            }
            v[c] = x;
        }
        samples.push(Sample {
            eps: [v[0], v[1]],
            t: [v[2], v[3]],
            line: n as usize,
        });
    }
    if samples.is_empty() {
        return Err(format!("{origin}: no data rows after the header"));
    }
    Ok(samples)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn header_and_numbers_are_checked_by_line_and_column() {
        let e = parse_samples("eps1,eps2,t11_n\n0,0,0\n", "d.csv").unwrap_err();
        assert!(
            e.starts_with("d.csv: line 1:") && e.contains("t22_n"),
            "{e}"
        );
        let e = parse_samples("eps1,eps2,t11_n,t22_n\n0.001,0,x,0\n", "d.csv").unwrap_err();
        assert!(e.starts_with("d.csv: line 2, column t11_n: `x`"), "{e}");
        let e = parse_samples("t22_n,t11_n,eps2,eps1\n# c\n\n1,2,0,0.5\n", "d.csv").unwrap_err();
        assert!(e.starts_with("d.csv: line 4, column eps1"), "{e}");
        let s = parse_samples("t22_n,t11_n,eps2,eps1\n1,2,0.001,0.002\n", "d.csv").unwrap();
        assert_eq!(s[0].eps, [0.002, 0.001]);
        assert_eq!(s[0].t, [2.0, 1.0]);
    }

    #[test]
    fn quoted_fields_and_what_law_curves_writes_are_read() {
        let s = parse_samples(
            "\"eps1\",eps2,t11_n,t22_n,note\n0.001,0,\"1.5\",0,\"a, b\"\n",
            "d.csv",
        )
        .unwrap();
        assert_eq!(s[0].t, [1.5, 0.0]);
        let law = "k,eps1,eps2,t11_n,t22_n\n1,0.002,0.002,0.5,0.5\n";
        assert_eq!(
            parse_samples(law, "figure6.csv").unwrap()[0].eps,
            [0.002, 0.002]
        );
    }
}
