//! The safety configuration: each axis's limits, following error and stop ramp
//! (`SafetySettings`, `Axis.configure_safety`), the card-wide settings (the e-stop input's
//! stop category, the longest stop time, the watchdog timeout: `CardSafetySettings`), and
//! how an axis's last stop went (`Axis.stop_reason`, `Axis.stop_info`).
use crate::errors::{of_kind, py};
use crate::names::py_enum;
use motioncard_sdk as sdk;
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// A stop category by its value (0, 1 or 2), else `BadCategoryError`.
pub(crate) fn stop_category(c: u32) -> PyResult<sdk::StopCategory> {
    sdk::StopCategory::from_raw(c).ok_or_else(|| {
        of_kind(
            sdk::ErrorKind::BadCategory,
            format!("stop category {c}: 0, 1 or 2"),
        )
    })
}

/// A duration in seconds, else `ValueError`.
pub(crate) fn seconds(what: &str, s: f64) -> PyResult<std::time::Duration> {
    std::time::Duration::try_from_secs_f64(s)
        .map_err(|e| PyValueError::new_err(format!("{what} {s}: {e}")))
}

/// An axis's safety configuration, in user units (see `Axis.set_scale`). Made with keyword
/// arguments (those not given: the card's defaults, in counts), read from the card with
/// `Axis.safety_settings()`; `replace(**changes)` is a copy with some changed.
#[pyclass(module = "motioncard", frozen)]
#[derive(Clone)]
pub struct SafetySettings {
    pub(crate) s: sdk::SafetySettings,
}

impl SafetySettings {
    fn changed(&self, changes: Option<&Bound<'_, PyDict>>) -> PyResult<SafetySettings> {
        let mut s = self.s;
        let Some(changes) = changes else {
            return Ok(SafetySettings { s });
        };
        for (k, v) in changes.iter() {
            let k: String = k.extract()?;
            match k.as_str() {
                "soft_limits" => s.soft_limits = v.extract()?,
                "hard_limits" => s.hard_limits = v.extract()?,
                "amp_alarm" => s.amp_alarm = v.extract()?,
                "encoder_checks" => s.encoder_checks = v.extract()?,
                "limit_stop" => s.limit_stop = stop_category(v.extract()?)?,
                "ferror" => s.ferror = v.extract()?,
                "min_ferror" => s.min_ferror = v.extract()?,
                "max_velocity" => s.max_velocity = v.extract()?,
                "stop_deceleration" => s.stop_deceleration = v.extract()?,
                "stop_jerk" => s.stop_jerk = v.extract()?,
                "encoder_max_velocity" => s.encoder_max_velocity = v.extract()?,
                other => {
                    return Err(PyTypeError::new_err(format!(
                        "no safety setting named {other:?}"
                    )))
                }
            }
        }
        Ok(SafetySettings { s })
    }
}

#[pymethods]
impl SafetySettings {
    /// `soft_limits` (negative, positive) or None, `hard_limits`, `amp_alarm`,
    /// `encoder_checks` (bool), `limit_stop` (the stop category a limit makes), `ferror`
    /// (the following-error limit at `max_velocity`), `min_ferror` (at rest),
    /// `max_velocity`, `stop_deceleration` and `stop_jerk` (of category 1 and 2 stops),
    /// `encoder_max_velocity`.
    #[new]
    #[pyo3(signature = (**settings))]
    fn new(settings: Option<&Bound<'_, PyDict>>) -> PyResult<Self> {
        SafetySettings {
            s: sdk::SafetySettings::default(),
        }
        .changed(settings)
    }

    /// A copy with the settings named changed (as the constructor's keywords).
    #[pyo3(signature = (**changes))]
    fn replace(&self, changes: Option<&Bound<'_, PyDict>>) -> PyResult<Self> {
        self.changed(changes)
    }

    /// Soft limits (negative, positive), or None.
    #[getter]
    fn soft_limits(&self) -> Option<(f64, f64)> {
        self.s.soft_limits
    }
    /// Honour the limit switch inputs.
    #[getter]
    fn hard_limits(&self) -> bool {
        self.s.hard_limits
    }
    /// Honour the amplifier alarm input.
    #[getter]
    fn amp_alarm(&self) -> bool {
        self.s.amp_alarm
    }
    /// Honour encoder loss and jumps.
    #[getter]
    fn encoder_checks(&self) -> bool {
        self.s.encoder_checks
    }
    /// The stop a hard or soft limit makes (`motioncard.StopCategory`).
    #[getter]
    fn limit_stop<'py>(&self, p: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        py_enum(p, "StopCategory", self.s.limit_stop as i64)
    }
    /// Following-error limit at `max_velocity`.
    #[getter]
    fn ferror(&self) -> f64 {
        self.s.ferror
    }
    /// Following-error limit at rest.
    #[getter]
    fn min_ferror(&self) -> f64 {
        self.s.min_ferror
    }
    /// The velocity `ferror` applies at.
    #[getter]
    fn max_velocity(&self) -> f64 {
        self.s.max_velocity
    }
    /// Deceleration of category 1 and 2 stops.
    #[getter]
    fn stop_deceleration(&self) -> f64 {
        self.s.stop_deceleration
    }
    /// Jerk of those stops.
    #[getter]
    fn stop_jerk(&self) -> f64 {
        self.s.stop_jerk
    }
    /// Fastest possible encoder velocity: a larger change in one tick is a fault.
    #[getter]
    fn encoder_max_velocity(&self) -> f64 {
        self.s.encoder_max_velocity
    }

    fn __eq__(&self, other: &Self) -> bool {
        self.s == other.s
    }

    fn __repr__(&self) -> String {
        let s = &self.s;
        let b = |v: bool| if v { "True" } else { "False" };
        let limits = match s.soft_limits {
            Some((n, p)) => format!("({n}, {p})"),
            None => "None".into(),
        };
        format!(
            "SafetySettings(soft_limits={:?}, hard_limits={}, amp_alarm={}, encoder_checks={}, \
             limit_stop={}, ferror={}, min_ferror={}, max_velocity={}, stop_deceleration={}, \
             stop_jerk={}, encoder_max_velocity={})",
            limits,
            b(s.hard_limits),
            b(s.amp_alarm),
            b(s.encoder_checks),
            s.limit_stop as u32,
            s.ferror,
            s.min_ferror,
            s.max_velocity,
            s.stop_deceleration,
            s.stop_jerk,
            s.encoder_max_velocity
        )
    }
}

/// The card-wide safety settings as the card holds them.
#[pyclass(module = "motioncard", frozen)]
pub struct CardSafetySettings {
    s: sdk::CardSafetySettings,
}

impl From<sdk::CardSafetySettings> for CardSafetySettings {
    fn from(s: sdk::CardSafetySettings) -> Self {
        CardSafetySettings { s }
    }
}

#[pymethods]
impl CardSafetySettings {
    /// The host watchdog's timeout, s.
    #[getter]
    fn watchdog_timeout(&self) -> f64 {
        self.s.watchdog_timeout_us as f64 / 1e6
    }
    /// The stop the e-stop input makes (`motioncard.StopCategory`).
    #[getter]
    fn estop_input_category<'py>(&self, p: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        py_enum(p, "StopCategory", self.s.estop_input_category as i64)
    }
    /// The longest any stop may take, s.
    #[getter]
    fn max_stop_time(&self) -> f64 {
        self.s.max_stop_time_us as f64 / 1e6
    }

    fn __repr__(&self) -> String {
        format!(
            "CardSafetySettings(watchdog_timeout={}, estop_input_category={}, max_stop_time={})",
            self.watchdog_timeout(),
            self.s.estop_input_category,
            self.max_stop_time()
        )
    }
}

/// How an axis's last safety stop went, measured by the card.
#[pyclass(module = "motioncard", frozen)]
pub struct StopInfo {
    reason: u32,
    /// Servo tick at which the last safety stop began (0: none since boot).
    #[pyo3(get)]
    stop_tick: u64,
    /// Servo tick at which the axis came to rest after it (None while still stopping).
    #[pyo3(get)]
    rest_tick: Option<u64>,
    /// The planned duration of the stop's deceleration ramp, s (0 for category 0).
    #[pyo3(get)]
    ramp_time: f64,
}

impl From<sdk::StopInfo> for StopInfo {
    fn from(i: sdk::StopInfo) -> Self {
        StopInfo {
            reason: i.reason as u32,
            stop_tick: i.stop_tick,
            rest_tick: i.rest_tick,
            ramp_time: i.ramp_time.as_secs_f64(),
        }
    }
}

#[pymethods]
impl StopInfo {
    /// Why the last motion ended (`motioncard.StopReason`).
    #[getter]
    fn reason<'py>(&self, p: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        py_enum(p, "StopReason", self.reason as i64)
    }

    fn __repr__(&self) -> String {
        format!(
            "StopInfo(reason={}, stop_tick={}, rest_tick={:?}, ramp_time={})",
            self.reason, self.stop_tick, self.rest_tick, self.ramp_time
        )
    }
}

/// `Axis.stop_reason()`: why the axis's last motion ended.
pub(crate) fn stop_reason<'py>(p: Python<'py>, axis: &sdk::Axis) -> PyResult<Bound<'py, PyAny>> {
    let r = py(axis.stop_reason())?;
    py_enum(p, "StopReason", r as u32 as i64)
}
