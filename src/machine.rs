//! What the machine the program runs on allows: the memory a run may take.

/// The memory one run may take, bytes: 80 % of what the system reported available
/// (`MemAvailable` in `/proc/meminfo`) when first asked, or of 10 GiB where it does not say.
/// Read once per process: every scene's validation asks (each keystroke in the explorer, each
/// design of a sweep).
pub fn memory_budget_bytes() -> f64 {
    static BUDGET: std::sync::OnceLock<f64> = std::sync::OnceLock::new();
    *BUDGET.get_or_init(|| {
        let available = std::fs::read_to_string("/proc/meminfo")
            .ok()
            .and_then(|text| {
                text.lines()
                    .find(|l| l.starts_with("MemAvailable:"))
                    .and_then(|l| l.split_whitespace().nth(1))
                    .and_then(|kb| kb.parse::<f64>().ok())
            })
            .map(|kb| kb * 1024.0);
        0.8 * available.unwrap_or(10.0 * GIB)
    })
}

const GIB: f64 = 1024.0 * 1024.0 * 1024.0;

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
        assert!(memory_budget_bytes() > 0.0);
    }
}
