//! Names and enum values for Python: the members of the register map's code enums.
use pyo3::prelude::*;

/// A name in `UPPER_SNAKE_CASE` from a Rust variant's `CamelCase` (`DiscreteMotion` →
/// `DISCRETE_MOTION`, `URequest` → `U_REQUEST`, `Ain0` → `AIN0`).
pub(crate) fn upper_snake(name: &str) -> String {
    let mut out = String::new();
    for (i, c) in name.chars().enumerate() {
        if c.is_ascii_uppercase() && i > 0 {
            out.push('_');
        }
        out.push(c.to_ascii_uppercase());
    }
    out
}

/// The members of an enum for Python: `(NAME, value)` in the enum's order.
pub(crate) fn members<E: std::fmt::Debug + Copy>(
    all: &[E],
    value: impl Fn(E) -> i64,
) -> Vec<(String, i64)> {
    all.iter()
        .map(|&e| (upper_snake(&format!("{e:?}")), value(e)))
        .collect()
}

/// An instance of the package's enum `name` (`motioncard.AxisState` ...) of value `v`.
pub(crate) fn py_enum<'py>(py: Python<'py>, name: &str, v: i64) -> PyResult<Bound<'py, PyAny>> {
    py.import("motioncard")?.getattr(name)?.call1((v,))
}
