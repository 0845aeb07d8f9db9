//! Numbers and sizes as a person reads them in a message: plain data to text, used by every
//! layer that words an error (the machine's memory, the scene's bounds, the summary).

use std::fmt;

const GIB: f64 = 1024.0 * 1024.0 * 1024.0;

/// A number as a person reads it in a message: `1e308` rather than 309 digits, `1e-9` rather
/// than nine zeros, never `-0`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Num(pub f64);

impl fmt::Display for Num {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let v = self.0 + 0.0; // -0.0 + 0.0 is 0.0
        if v != 0.0 && v.is_finite() && !(1e-4..1e6).contains(&v.abs()) {
            write!(f, "{v:e}")
        } else {
            write!(f, "{v}")
        }
    }
}

/// A figure to `decimals` places, as `{:.decimals$}` prints it, unless it is too large to read
/// in fixed digits (|v| ≥ 1e9: `1.23e300`, not 301 digits); never `-0.0`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fixed(pub f64, pub usize);

impl fmt::Display for Fixed {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (v, d) = (self.0 + 0.0, self.1);
        if v.is_finite() && v.abs() >= 1e9 {
            return write!(f, "{v:.2e}");
        }
        let text = format!("{v:.d$}");
        match text.strip_prefix('-') {
            Some(rest) if rest.chars().all(|c| c == '0' || c == '.') => f.write_str(rest),
            _ => f.write_str(&text),
        }
    }
}

/// Bytes as a person reads them: `712 MiB`, `21.3 GiB`, `2.1e4 TiB`.
pub fn show_bytes(bytes: f64) -> String {
    let units = [
        ("TiB", GIB * 1024.0),
        ("GiB", GIB),
        ("MiB", 1024.0 * 1024.0),
    ];
    for (name, size) in units {
        if bytes >= size {
            let v = bytes / size;
            return if v >= 1e4 {
                format!("{v:.1e} {name}")
            } else if v >= 100.0 {
                format!("{v:.0} {name}")
            } else {
                format!("{v:.1} {name}")
            };
        }
    }
    format!("{:.0} KiB", bytes / 1024.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bytes_read_as_a_person_reads_them() {
        assert_eq!(show_bytes(712.0 * 1024.0 * 1024.0), "712 MiB");
        assert_eq!(show_bytes(21.3 * GIB), "21.3 GiB");
        assert_eq!(show_bytes(2.1e4 * 1024.0 * GIB), "2.1e4 TiB");
    }

    #[test]
    fn numbers_read_short_and_never_as_minus_zero() {
        assert_eq!(Num(1e308).to_string(), "1e308");
        assert_eq!(Num(1e-9).to_string(), "1e-9");
        assert_eq!(Num(-0.0).to_string(), "0");
        assert_eq!(Num(2.5).to_string(), "2.5");
        assert_eq!(Fixed(1e300, 1).to_string(), "1.00e300");
        assert_eq!(Fixed(-0.001, 1).to_string(), "0.0");
        assert_eq!(Fixed(12.345, 2).to_string(), "12.35");
    }
}
