//! The measured curves a fit reads: a CSV with a header naming the columns
//! `eps1,eps2,t11_n,t22_n` (any order, other columns ignored; the header `wovenform law
//! --curves` writes), the fabric strains along warp and weft and the measured tensions per yarn
//! (N). Blank lines and `#` comments are skipped. Read with the `csv` crate, a record per line
//! (quoted fields, but no line break inside one), so that errors give the file's line numbers.

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

/// The columns of measured curves: strains along warp and weft, tensions per yarn (N). The
/// CSV that `law --curves` writes has them too (after its path number `k`).
pub const COLUMNS: [&str; 4] = ["eps1", "eps2", "t11_n", "t22_n"];

const EXPECTED: &str = "expected a header line naming the columns eps1,eps2,t11_n,t22_n (strains; tensions per yarn, N)";

/// What is wrong with a data file, and where: `origin` names the file.
#[derive(Debug, thiserror::Error)]
#[error("{origin}: {problem}")]
pub struct SamplesError {
    pub origin: String,
    pub problem: Problem,
}

/// What is wrong with a data file.
#[derive(Debug, thiserror::Error)]
pub enum Problem {
    #[error("cannot read the data file: {0}")]
    Unreadable(#[source] std::io::Error),
    #[error("the file is empty: {EXPECTED}")]
    Empty,
    #[error("line {line}: {message}")]
    Csv { line: u64, message: String },
    #[error("line {line}: the header `{header}` has no column {column}: {EXPECTED}")]
    MissingColumn {
        line: u64,
        header: String,
        column: &'static str,
    },
    #[error("line {line}: the header names column {column} more than once")]
    RepeatedColumn { line: u64, column: &'static str },
    #[error(
        "line {line}: expected {expected} comma-separated fields as in the header, found {found}"
    )]
    FieldCount {
        line: u64,
        expected: usize,
        found: usize,
    },
    #[error("line {line}, column {column}: `{field}` is not a finite number")]
    NotANumber {
        line: u64,
        column: &'static str,
        field: String,
    },
    #[error("line {line}, column {column}: {value} is outside the law's strain range [{}, {}]", STRAIN_RANGE[0], STRAIN_RANGE[1])]
    OutOfRange {
        line: u64,
        column: &'static str,
        value: f64,
    },
    #[error("no data rows after the header")]
    NoRows,
}

/// Reads a data CSV; errors name the file, the line and the column.
pub fn read_samples(path: &Path) -> Result<Vec<Sample>, SamplesError> {
    let origin = path.display().to_string();
    let text =
        crate::files::read_text(path, crate::files::MAX_TEXT_BYTES).map_err(|e| SamplesError {
            origin: origin.clone(),
            problem: Problem::Unreadable(e),
        })?;
    parse_samples(&text, &origin)
}

/// The position of each of [`COLUMNS`] in the header.
fn column_index(header: &csv::StringRecord, line: u64) -> Result<[usize; 4], Problem> {
    let mut index = [0usize; 4];
    for (c, column) in COLUMNS.iter().copied().enumerate() {
        let found: Vec<usize> = (0..header.len())
            .filter(|&i| &header[i] == column)
            .collect();
        index[c] = match found[..] {
            [i] => i,
            [] => {
                let names: Vec<&str> = header.iter().collect();
                return Err(Problem::MissingColumn {
                    line,
                    header: names.join(","),
                    column,
                });
            }
            _ => return Err(Problem::RepeatedColumn { line, column }),
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
pub fn parse_samples(text: &str, origin: &str) -> Result<Vec<Sample>, SamplesError> {
    samples_of(text).map_err(|problem| SamplesError {
        origin: origin.to_string(),
        problem,
    })
}

fn samples_of(text: &str) -> Result<Vec<Sample>, Problem> {
    // A byte-order mark (as spreadsheets write) is not part of the first line.
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut lines = text
        .lines()
        .enumerate()
        .map(|(i, l)| (i as u64 + 1, l.trim()))
        .filter(|(_, l)| !l.is_empty() && !l.starts_with('#'))
        .map(|(line, l)| {
            let r = record(l).map_err(|e| Problem::Csv {
                line,
                message: e.to_string(),
            });
            (line, r)
        });
    let (header_line, header) = lines.next().ok_or(Problem::Empty)?;
    let header = header?;
    let index = column_index(&header, header_line)?;
    let mut samples = Vec::new();
    for (line, record) in lines {
        let record = record?;
        if record.len() != header.len() {
            return Err(Problem::FieldCount {
                line,
                expected: header.len(),
                found: record.len(),
            });
        }
        let mut v = [0.0; 4];
        for (c, column) in COLUMNS.iter().copied().enumerate() {
            let field = &record[index[c]];
            let x: f64 = field
                .parse()
                .ok()
                .filter(|x: &f64| x.is_finite())
                .ok_or_else(|| Problem::NotANumber {
                    line,
                    column,
                    field: field.to_string(),
                })?;
            if c < 2 && !(STRAIN_RANGE[0]..=STRAIN_RANGE[1]).contains(&x) {
                return Err(Problem::OutOfRange {
                    line,
                    column,
                    value: x,
                });
            }
            v[c] = x;
        }
        samples.push(Sample {
            eps: [v[0], v[1]],
            t: [v[2], v[3]],
            line: line as usize,
        });
    }
    if samples.is_empty() {
        return Err(Problem::NoRows);
    }
    Ok(samples)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn header_and_numbers_are_checked_by_line_and_column() {
        let e = parse_samples("eps1,eps2,t11_n\n0,0,0\n", "d.csv")
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("d.csv: line 1:") && e.contains("t22_n"),
            "{e}"
        );
        let e = parse_samples("eps1,eps2,t11_n,t22_n\n0.001,0,x,0\n", "d.csv")
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("d.csv: line 2, column t11_n: `x`"), "{e}");
        let e = parse_samples("t22_n,t11_n,eps2,eps1\n# c\n\n1,2,0,0.5\n", "d.csv")
            .unwrap_err()
            .to_string();
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
        let bom = "\u{feff}# measured\neps1,eps2,t11_n,t22_n\n0.001,0,1,2\n";
        assert_eq!(parse_samples(bom, "d.csv").unwrap()[0].t, [1.0, 2.0]);
        let law = "k,eps1,eps2,t11_n,t22_n\n1,0.002,0.002,0.5,0.5\n";
        assert_eq!(
            parse_samples(law, "figure6.csv").unwrap()[0].eps,
            [0.002, 0.002]
        );
    }
}
