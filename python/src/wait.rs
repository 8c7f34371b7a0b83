//! The one way a call waits: without the GIL, in slices, looking for signals between them.
use crate::errors::Error;
use pyo3::prelude::*;
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
