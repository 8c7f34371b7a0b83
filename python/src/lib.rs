//! `motioncard._motioncard`: the SDK (`motioncard_sdk`) for Python. The package `motioncard`
//! (python/motioncard/__init__.py) re-exports it and adds what is plain Python: the enums
//! built from the lists exported here, the asyncio helpers.
//!
//! Every call that waits releases the GIL and waits in slices of at most [`SLICE`], checking
//! for signals between them, so Ctrl-C ends a wait with `KeyboardInterrupt`.
use pyo3::prelude::*;

mod card;
mod errors;
mod group;
mod io;
mod motion;
mod scope;

use errors::Error;
use std::time::Duration;

/// The longest a wait runs without looking for a signal (emulated time on a stepped card).
pub(crate) const SLICE: Duration = Duration::from_millis(50);

/// Run `f` without the GIL in slices of at most [`SLICE`] until it gives something other
/// than a timeout or `timeout` (seconds; `None`: no end) has passed; signals are checked
/// between slices (a `KeyboardInterrupt` ends the wait).
pub(crate) fn wait_sliced<T: Send>(
    py: Python<'_>,
    timeout: Option<f64>,
    mut f: impl FnMut(Duration) -> motioncard_sdk::Result<T> + Send,
) -> PyResult<T> {
    let total = match timeout {
        None => None,
        Some(t) if t.is_finite() && t >= 0.0 => Some(Duration::from_secs_f64(t)),
        Some(t) => {
            return Err(pyo3::exceptions::PyValueError::new_err(format!(
                "timeout {t}: not a finite number of seconds >= 0"
            )))
        }
    };
    let mut left = total;
    loop {
        py.check_signals()?;
        let slice = left.map_or(SLICE, |l| l.min(SLICE));
        match py.allow_threads(|| f(slice)) {
            Ok(t) => return Ok(t),
            Err(e) if e.kind() == motioncard_sdk::ErrorKind::Timeout => {
                if let Some(l) = left.as_mut() {
                    if *l <= slice {
                        return Err(Error::from(motioncard_sdk::Error::Timeout(
                            total.unwrap_or_default(),
                        ))
                        .into());
                    }
                    *l -= slice;
                }
            }
            Err(e) => return Err(Error::from(e).into()),
        }
    }
}

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
fn members<E: std::fmt::Debug + Copy>(all: &[E], value: impl Fn(E) -> i64) -> Vec<(String, i64)> {
    all.iter()
        .map(|&e| (upper_snake(&format!("{e:?}")), value(e)))
        .collect()
}

/// An instance of the package's enum `name` (`motioncard.AxisState` ...) of value `v`.
pub(crate) fn py_enum<'py>(py: Python<'py>, name: &str, v: i64) -> PyResult<Bound<'py, PyAny>> {
    py.import("motioncard")?.getattr(name)?.call1((v,))
}

#[pymodule]
fn _motioncard(m: &Bound<'_, PyModule>) -> PyResult<()> {
    use motioncard_sdk as sdk;
    let py = m.py();
    errors::register(m)?;
    m.add(
        "AXIS_STATES",
        members(sdk::AxisState::ALL, |e| e as u32 as i64),
    )?;
    m.add(
        "GROUP_STATES",
        members(sdk::GroupState::ALL, |e| e as u32 as i64),
    )?;
    m.add(
        "EVENT_KINDS",
        members(sdk::EventKind::ALL, |e| e as u16 as i64),
    )?;
    m.add("SIGNALS", members(sdk::Signal::ALL, |e| e as u32 as i64))?;
    m.add(
        "STOP_CATEGORIES",
        members(sdk::StopCategory::ALL, |e| e as u32 as i64),
    )?;
    m.add("SCOPE_CHANNELS", sdk::SCOPE_CHANNELS)?;
    m.add("INPUTS", sdk::INPUTS)?;
    m.add_class::<card::Card>()?;
    m.add_class::<card::CardInfo>()?;
    m.add_class::<card::Sim>()?;
    m.add_class::<card::Event>()?;
    m.add_class::<card::Events>()?;
    m.add_class::<card::SafetyStatus>()?;
    m.add_class::<motion::Axis>()?;
    m.add_class::<motion::MoveLimits>()?;
    m.add_class::<motion::Motion>()?;
    m.add_class::<motion::Status>()?;
    m.add_class::<group::Group>()?;
    m.add_class::<group::GroupMotion>()?;
    m.add_class::<group::GroupStatus>()?;
    m.add_class::<group::PathLimits>()?;
    m.add_class::<group::Segment>()?;
    m.add_class::<io::Compare>()?;
    m.add_class::<io::Probe>()?;
    m.add_class::<scope::Scope>()?;
    m.add_class::<scope::Capture>()?;
    let _ = py;
    Ok(())
}
