//! Values of swept keys as the sweep shows them: in tables and ids, as TOML literals, with
//! their units; and the hash that names designs.

/// 64-bit FNV-1a, as 16 hex digits: stable across platforms and Rust versions.
pub fn fnv_hex(text: &str) -> String {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in text.bytes() {
        h ^= b as u64;
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    format!("{h:016x}")
}

/// A value as written in tables and ids: `5`, `7.5`, `true`, `full`, `[5, 4]`.
pub fn show_value(v: &toml::Value) -> String {
    match v {
        // As every number a person reads: `1e-300`, not 300 zeros (and read back the same).
        toml::Value::Float(f) => crate::show::Num(*f).to_string(),
        toml::Value::Integer(i) => format!("{i}"),
        toml::Value::Boolean(b) => format!("{b}"),
        toml::Value::String(s) => s.clone(),
        toml::Value::Array(a) => {
            let parts: Vec<String> = a.iter().map(show_value).collect();
            format!("[{}]", parts.join(", "))
        }
        other => other.to_string(),
    }
}

/// The value in a TOML literal (for `--set`-style overrides).
pub(super) fn toml_literal(v: &toml::Value) -> String {
    match v {
        toml::Value::Float(f) if f.fract() == 0.0 && f.abs() < 1e15 => format!("{f:.1}"),
        // As every number a person reads: `1e-300`, not 300 zeros (and read back the same).
        toml::Value::Float(f) => crate::show::Num(*f).to_string(),
        other => other.to_string(),
    }
}

pub fn as_number(v: &toml::Value) -> Option<f64> {
    match v {
        toml::Value::Float(f) => Some(*f),
        toml::Value::Integer(i) => Some(*i as f64),
        _ => None,
    }
}

/// The unit written after a key's values, e.g. ` mm`.
pub fn unit_of(key: &str) -> &'static str {
    match key {
        "tools.kind" => "",
        k if k.starts_with("tools.") => " mm",
        "process.stroke" | "mesh.element_size" | "blank.size" => " mm",
        "process.holder_pressure" => " MPa",
        "process.holder_force" => " kN",
        "fabric.locking_angle_deg" | "fabric.yarn_angle_deg" => "°",
        "fabric.break_tension_n" | "fabric.c" | "fabric.compressive_stiffness" => " N",
        "fabric.l0" | "fabric.e0" | "fabric.a" | "fabric.wrinkle_limit_mm" => " mm",
        "fabric.b" => " 1/N",
        "fabric.bending_rigidity" => " N·mm",
        "fabric.shear_moment" => " N·mm/mm²",
        "fabric.areal_mass" => " g/m²",
        "numerics.trigger_pa" => " Pa",
        _ => "",
    }
}
