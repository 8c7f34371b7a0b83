//! `motioncard.replay` and its `ReplayReport`: an API trace (`Card.open(..., trace=...)`,
//! `MOTIONCARD_TRACE`) run again on a stepped emulated card.
use crate::errors::py;
use motioncard_sdk as sdk;
use pyo3::prelude::*;

/// What `motioncard.replay` found.
#[pyclass(module = "motioncard", frozen, get_all)]
pub struct ReplayReport {
    /// The register-map layout the trace was recorded with, (major, minor).
    layout: (u16, u16),
    /// The axes of the card it was recorded on.
    axes: usize,
    /// Its servo rate, Hz.
    servo_rate_hz: u32,
    /// The URI it was opened with.
    uri: String,
    /// Commands sent again.
    commands: usize,
    /// Recorded events compared with the replaying card's.
    events: usize,
    /// The first difference: (the trace's line, what differs); None: the card answered as
    /// recorded.
    difference: Option<(usize, String)>,
}

#[pymethods]
impl ReplayReport {
    fn __repr__(&self) -> String {
        format!(
            "ReplayReport(uri={:?}, axes={}, servo_rate_hz={}, commands={}, events={}, \
             difference={:?})",
            self.uri, self.axes, self.servo_rate_hz, self.commands, self.events, self.difference
        )
    }
}

/// Run the API trace at `path` on a stepped emulated card with its axes and servo rate:
/// every block write and command at the tick the recorded card served it, every recorded
/// event compared with the card's (kind, axis, command, code, tick, value). Returns the
/// report, with the first difference if any. A file that cannot be read or is not a trace:
/// `IoError`, `BadConfigError`; a trace of another layout: `VersionMismatchError`.
#[pyfunction]
pub(crate) fn replay(p: Python<'_>, path: std::path::PathBuf) -> PyResult<ReplayReport> {
    let r = py(p.allow_threads(|| sdk::replay(&path)))?;
    Ok(ReplayReport {
        layout: r.header.layout,
        axes: r.header.axes,
        servo_rate_hz: r.header.servo_rate_hz,
        uri: r.header.uri,
        commands: r.commands,
        events: r.events,
        difference: r.difference,
    })
}
