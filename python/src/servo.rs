//! Servo tuning: the PD+ and PID+FF laws (FFPIV is `Axis.configure`), the biquad filters on
//! the servo output (`ServoFilter`), the frequency response (`FreqResponse`, numpy arrays).
use crate::errors::{of_kind, py};
use crate::motion::Axis;
use crate::wait::wait_sliced;
use motioncard_sdk as sdk;
use numpy::{IntoPyArray, PyArray1};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use std::collections::{BTreeMap, HashMap};

type Gains = BTreeMap<&'static str, f64>;

/// A named setting of a block: its name and where it is.
type Field<T> = (&'static str, fn(&mut T) -> &mut f64);

/// The PID+FF gains by name.
const PIDFF: [Field<sdk::PidffSettings>; 8] = [
    ("kp", |s| &mut s.kp),
    ("ki", |s| &mut s.ki),
    ("kd", |s| &mut s.kd),
    ("kvff", |s| &mut s.kvff),
    ("kaff", |s| &mut s.kaff),
    ("friction", |s| &mut s.friction),
    ("friction_deadband", |s| &mut s.friction_deadband),
    ("d_filter_hz", |s| &mut s.d_filter_hz),
];

/// The PD+ gains, drive model and limit by name.
const PDPLUS: [Field<sdk::PdPlusSettings>; 8] = [
    ("kp", |s| &mut s.gains.kp),
    ("kd", |s| &mut s.gains.kd),
    ("kv", |s| &mut s.gains.kv),
    ("ka", |s| &mut s.gains.ka),
    ("kc", |s| &mut s.drive.kc),
    ("tau", |s| &mut s.drive.tau),
    ("ke", |s| &mut s.drive.ke),
    ("umax", |s| &mut s.umax),
];

fn to_map<T>(mut s: T, fields: &[Field<T>]) -> Gains {
    fields.iter().map(|(k, f)| (*k, *f(&mut s))).collect()
}

fn apply<T>(
    s: &mut T,
    fields: &[Field<T>],
    changes: HashMap<String, f64>,
    what: &str,
) -> PyResult<()> {
    for (k, v) in changes {
        let (_, f) = fields
            .iter()
            .find(|(n, _)| *n == k)
            .ok_or_else(|| PyTypeError::new_err(format!("no {what} setting named {k:?}")))?;
        *f(s) = v;
    }
    Ok(())
}

/// The PID+FF gains placed for a drive of `accel_per_volt` (counts/s² per volt) at the
/// crossover `wc` (rad/s), by name: what `Axis.configure_pidff(**gains)` takes.
#[pyfunction]
pub fn pidff_for_drive(accel_per_volt: f64, wc: f64) -> Gains {
    to_map(sdk::PidffSettings::for_drive(accel_per_volt, wc), &PIDFF)
}

/// The PD+ law and drive model of Yeh's die bonder, axis 0 (X) or 1 (Y), in volts, by name:
/// what `Axis.configure_pdplus(**settings)` takes (a card made with `die_bonder=True` axes
/// has that plant).
#[pyfunction]
pub fn die_bonder_pdplus(axis: usize) -> Gains {
    to_map(sdk::die_bonder_pdplus(axis), &PDPLUS)
}

/// The servo law an axis runs.
pub(crate) fn law_name(law: u32) -> &'static str {
    use sdk::proto::raw;
    match law {
        raw::MC_SERVO_PDPLUS => "pdplus",
        raw::MC_SERVO_PIDFF => "pidff",
        _ => "ffpiv",
    }
}

/// A biquad filter on an axis's servo output: make it with `ServoFilter.notch`, `low_pass`,
/// `lead_lag` or `raw`; `Axis.servo_filters()` gives them back with the card's coefficients.
#[pyclass(module = "motioncard", frozen)]
#[derive(Clone, Copy)]
pub struct ServoFilter {
    spec: sdk::BiquadSpec,
    designed: Option<[f64; 5]>,
}

fn filter(spec: sdk::BiquadSpec) -> ServoFilter {
    ServoFilter {
        spec,
        designed: None,
    }
}

#[pymethods]
impl ServoFilter {
    /// A notch at `hz` with damping `damping` (its width) and gain `depth_db` (dB, -120 to 0)
    /// at its centre.
    #[staticmethod]
    fn notch(hz: f64, damping: f64, depth_db: f64) -> Self {
        filter(sdk::BiquadSpec::notch(hz, damping, depth_db))
    }

    /// A second-order low-pass at `hz` with damping `damping`.
    #[staticmethod]
    fn low_pass(hz: f64, damping: f64) -> Self {
        filter(sdk::BiquadSpec::low_pass(hz, damping))
    }

    /// A first-order lead/lag `(1 + s/ω_zero)/(1 + s/ω_pole)`.
    #[staticmethod]
    fn lead_lag(zero_hz: f64, pole_hz: f64) -> Self {
        filter(sdk::BiquadSpec::lead_lag(zero_hz, pole_hz))
    }

    /// The coefficients as given: b0, b1, b2, a1, a2 (a0 = 1).
    #[staticmethod]
    fn raw(b0: f64, b1: f64, b2: f64, a1: f64, a2: f64) -> Self {
        filter(sdk::BiquadSpec::raw([b0, b1, b2, a1, a2]))
    }

    /// `"notch"`, `"low_pass"`, `"lead_lag"` or `"raw"`.
    #[getter]
    fn kind(&self) -> &'static str {
        match self.spec.kind {
            sdk::BiquadKind::Notch => "notch",
            sdk::BiquadKind::LowPass => "low_pass",
            sdk::BiquadKind::LeadLag => "lead_lag",
            sdk::BiquadKind::Raw => "raw",
        }
    }

    /// Notch: the centre; low-pass: the corner; lead/lag: the zero's frequency, Hz.
    #[getter]
    fn freq_hz(&self) -> f64 {
        self.spec.freq_hz
    }

    /// Notch, low-pass: the damping ratio.
    #[getter]
    fn damping(&self) -> f64 {
        self.spec.damping
    }

    /// Notch: the gain at the centre, dB.
    #[getter]
    fn depth_db(&self) -> f64 {
        self.spec.depth_db
    }

    /// Lead/lag: the pole's frequency, Hz.
    #[getter]
    fn freq2_hz(&self) -> f64 {
        self.spec.freq2_hz
    }

    /// The coefficients the card designed at its servo rate (b0, b1, b2, a1, a2; a0 = 1), for
    /// a filter read back with `Axis.servo_filters()`; None for one made here (a raw filter:
    /// its own).
    #[getter]
    fn coeffs(&self) -> Option<(f64, f64, f64, f64, f64)> {
        let c = match (self.designed, self.spec.kind) {
            (Some(c), _) => c,
            (None, sdk::BiquadKind::Raw) => self.spec.coeffs,
            (None, _) => return None,
        };
        Some((c[0], c[1], c[2], c[3], c[4]))
    }

    fn __repr__(&self) -> String {
        let s = &self.spec;
        match s.kind {
            sdk::BiquadKind::Notch => format!(
                "ServoFilter.notch({}, {}, {})",
                s.freq_hz, s.damping, s.depth_db
            ),
            sdk::BiquadKind::LowPass => {
                format!("ServoFilter.low_pass({}, {})", s.freq_hz, s.damping)
            }
            sdk::BiquadKind::LeadLag => {
                format!("ServoFilter.lead_lag({}, {})", s.freq_hz, s.freq2_hz)
            }
            sdk::BiquadKind::Raw => format!("ServoFilter.raw{:?}", s.coeffs),
        }
    }
}

/// A frequency sweep's result. Each response is three numpy arrays: the frequencies (Hz),
/// the gain (dB) and the phase (degrees).
#[pyclass(module = "motioncard", frozen)]
pub struct FreqResponse {
    r: sdk::FreqResponse,
}

type Curve<'py> = (
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
);

fn curve<'py>(p: Python<'py>, b: Vec<sdk::Bode>) -> Curve<'py> {
    let hz: Vec<f64> = b.iter().map(|x| x.hz).collect();
    let db: Vec<f64> = b.iter().map(|x| x.gain_db).collect();
    let deg: Vec<f64> = b.iter().map(|x| x.phase_deg).collect();
    (hz.into_pyarray(p), db.into_pyarray(p), deg.into_pyarray(p))
}

#[pymethods]
impl FreqResponse {
    /// Where the sine entered: `"reference"` or `"output"`.
    #[getter]
    fn mode(&self) -> &'static str {
        match self.r.mode {
            sdk::FreqMode::Reference => "reference",
            sdk::FreqMode::Output => "output",
        }
    }

    /// Every point asked for was measured.
    #[getter]
    fn complete(&self) -> bool {
        self.r.complete
    }

    /// The frequencies measured, Hz.
    #[getter]
    fn frequency<'py>(&self, p: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        let hz: Vec<f64> = self.r.points.iter().map(|x| x.hz).collect();
        hz.into_pyarray(p)
    }

    /// The response of the mode: the closed loop (reference) or the plant (output).
    fn response<'py>(&self, p: Python<'py>) -> Curve<'py> {
        curve(p, self.r.response())
    }

    /// The closed loop `T = X/D`.
    fn closed_loop<'py>(&self, p: Python<'py>) -> Curve<'py> {
        curve(p, self.r.closed_loop())
    }

    /// The plant `P = X/U`, user units per volt.
    fn plant<'py>(&self, p: Python<'py>) -> Curve<'py> {
        curve(p, self.r.plant())
    }

    /// The open loop `L`.
    fn open_loop<'py>(&self, p: Python<'py>) -> Curve<'py> {
        curve(p, self.r.open_loop())
    }

    /// The peaks and dips of the response standing out by at least 3 dB: (Hz, gain dB,
    /// height dB, an anti-resonance) each.
    fn resonances(&self) -> Vec<(f64, f64, f64, bool)> {
        self.r
            .resonances()
            .into_iter()
            .map(|r| (r.hz, r.gain_db, r.height_db, r.anti))
            .collect()
    }

    fn __len__(&self) -> usize {
        self.r.points.len()
    }
}

/// The servo methods of `Axis` (a second `#[pymethods]` block: `multiple-pymethods` is not
/// enabled, so they are plain functions the `Axis` block calls).
impl Axis {
    pub(crate) fn do_servo_law(&self) -> PyResult<&'static str> {
        Ok(law_name(py(self.axis.settings())?.servo_law))
    }

    pub(crate) fn do_configure_pidff(
        &self,
        p: Python<'_>,
        changes: Option<HashMap<String, f64>>,
    ) -> PyResult<()> {
        let mut s = py(self.axis.pidff_settings())?.unwrap_or_default();
        apply(&mut s, &PIDFF, changes.unwrap_or_default(), "PID+FF")?;
        py(p.allow_threads(|| self.axis.configure_pidff(&s)))
    }

    pub(crate) fn do_pidff_settings(&self) -> PyResult<Option<Gains>> {
        Ok(py(self.axis.pidff_settings())?.map(|s| to_map(s, &PIDFF)))
    }

    pub(crate) fn do_configure_pdplus(
        &self,
        p: Python<'_>,
        changes: Option<HashMap<String, f64>>,
    ) -> PyResult<()> {
        let changes = changes.unwrap_or_default();
        let current = py(self.axis.pdplus_settings())?;
        let mut s = match current {
            Some(s) => s,
            None => {
                let missing: Vec<&str> = PDPLUS
                    .iter()
                    .map(|(k, _)| *k)
                    .filter(|k| !changes.contains_key(*k))
                    .collect();
                if !missing.is_empty() {
                    return Err(PyTypeError::new_err(format!(
                        "the axis runs another law: give every PD+ setting (missing {})",
                        missing.join(", ")
                    )));
                }
                sdk::PdPlusSettings::default()
            }
        };
        apply(&mut s, &PDPLUS, changes, "PD+")?;
        py(p.allow_threads(|| self.axis.configure_pdplus(&s)))
    }

    pub(crate) fn do_pdplus_settings(&self) -> PyResult<Option<Gains>> {
        Ok(py(self.axis.pdplus_settings())?.map(|s| to_map(s, &PDPLUS)))
    }

    pub(crate) fn do_set_servo_filter(
        &self,
        p: Python<'_>,
        slot: usize,
        f: &ServoFilter,
    ) -> PyResult<()> {
        let spec = f.spec;
        py(p.allow_threads(|| self.axis.set_servo_filter(slot, &spec)))
    }

    pub(crate) fn do_clear_servo_filter(&self, p: Python<'_>, slot: Option<usize>) -> PyResult<()> {
        py(p.allow_threads(|| match slot {
            Some(k) => self.axis.clear_servo_filter(k),
            None => self.axis.clear_servo_filters(),
        }))
    }

    pub(crate) fn do_servo_filters(&self) -> PyResult<Vec<Option<ServoFilter>>> {
        Ok(py(self.axis.servo_filters())?
            .into_iter()
            .map(|f| {
                f.map(|f| ServoFilter {
                    spec: f.spec,
                    designed: Some(f.coeffs),
                })
            })
            .collect())
    }

    #[allow(clippy::too_many_arguments)]
    pub(crate) fn do_frequency_response(
        &self,
        p: Python<'_>,
        mode: &str,
        from_hz: f64,
        to_hz: f64,
        points: usize,
        amplitude: f64,
        cycles: u32,
        settle_s: f64,
        timeout: Option<f64>,
    ) -> PyResult<FreqResponse> {
        let mode = match mode {
            "reference" => sdk::FreqMode::Reference,
            "output" => sdk::FreqMode::Output,
            other => {
                return Err(PyValueError::new_err(format!(
                    "mode {other:?}: \"reference\" or \"output\""
                )))
            }
        };
        let s = sdk::FreqSweep {
            mode,
            from_hz,
            to_hz,
            points,
            amplitude,
            cycles,
            settle_s,
        };
        let ax = &self.axis;
        let seq = py(p.allow_threads(|| ax.start_frequency_sweep(&s)))?;
        let card = &self.card;
        let sim = card.sim();
        let rate = card.info().servo_rate_hz as f64;
        // in slices (Ctrl-C ends it): a stepped card steps, another one runs on its own
        let r = wait_sliced(p, timeout, |slice| {
            let pr = ax.freq_progress();
            if pr.seq == seq && pr.state != sdk::proto::raw::MC_FREQ_RUNNING {
                return Ok(pr.state);
            }
            match &sim {
                Some(sim) => sim.step(((slice.as_secs_f64() * rate).ceil() as u64).max(1)),
                None => std::thread::sleep(slice),
            }
            Err(sdk::Error::Timeout(slice))
        });
        let state = match r {
            Ok(state) => state,
            Err(e) => {
                let _ = ax.stop_frequency_sweep();
                return Err(e);
            }
        };
        if state != sdk::proto::raw::MC_FREQ_DONE {
            return Err(of_kind(
                sdk::ErrorKind::Aborted,
                format!(
                    "axis {}: the sweep ended early (a stop, or the axis leaving Standstill)",
                    ax.index()
                ),
            ));
        }
        Ok(FreqResponse {
            r: ax.freq_result(),
        })
    }
}
