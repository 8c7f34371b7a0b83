//! Position compare and touch probes of an axis.
use crate::errors::py;
use crate::wait::wait_sliced;
use motioncard_sdk as sdk;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

fn direction(name: &str) -> PyResult<sdk::Direction> {
    match name {
        "positive" => Ok(sdk::Direction::Positive),
        "negative" => Ok(sdk::Direction::Negative),
        "either" => Ok(sdk::Direction::Either),
        _ => Err(PyValueError::new_err(format!(
            "direction {name:?}: \"positive\", \"negative\" or \"either\""
        ))),
    }
}

/// A position-compare channel: pulses an output when its axis passes positions.
#[pyclass(module = "motioncard", frozen)]
pub struct Compare {
    pub(crate) compare: sdk::CompareChannel,
}

#[pymethods]
impl Compare {
    /// The channel number.
    #[getter]
    fn channel(&self) -> usize {
        self.compare.channel()
    }

    /// Pulse `output` for `pulse_us` µs when the axis passes `position` going `direction`
    /// ("positive", "negative", "either").
    #[pyo3(signature = (output, pulse_us, position, direction = "either"))]
    fn arm_single(
        &self,
        p: Python<'_>,
        output: u32,
        pulse_us: u32,
        position: f64,
        direction: &str,
    ) -> PyResult<()> {
        let d = self::direction(direction)?;
        py(p.allow_threads(|| self.compare.arm_single(output, pulse_us, position, d)))
    }

    /// Pulse at `count` positions from `start`, `pitch` apart, going `direction`.
    #[pyo3(signature = (output, pulse_us, start, pitch, count, direction = "positive"))]
    #[allow(clippy::too_many_arguments)]
    fn arm_series(
        &self,
        p: Python<'_>,
        output: u32,
        pulse_us: u32,
        start: f64,
        pitch: f64,
        count: u32,
        direction: &str,
    ) -> PyResult<()> {
        let d = self::direction(direction)?;
        py(p.allow_threads(|| {
            self.compare
                .arm_series(output, pulse_us, start, pitch, count, d)
        }))
    }

    /// A rotary axis: pulse at every crossing of `position` (a place on the turn, in
    /// `[0, modulo)`) going `direction` ("either": both ways), on every turn, until
    /// `disarm()`. A linear axis, or a place off the turn: `CompareTurnError`.
    #[pyo3(signature = (output, pulse_us, position, direction = "either"))]
    fn arm_single_each_turn(
        &self,
        p: Python<'_>,
        output: u32,
        pulse_us: u32,
        position: f64,
        direction: &str,
    ) -> PyResult<()> {
        let d = self::direction(direction)?;
        py(p.allow_threads(|| {
            self.compare
                .arm_single_each_turn(output, pulse_us, position, d)
        }))
    }

    /// A rotary axis: the series of `arm_series` on every turn, endless until `disarm()`:
    /// `count` places from `start` (in `[0, modulo)`), `pitch` apart going `direction`,
    /// wrapped into the turn, with `count * pitch <= modulo`; `count` 0 is a whole turn of
    /// pitches. Each place fires at every crossing going `direction`. A linear axis, or a
    /// series that does not fit the turn: `CompareTurnError`.
    #[pyo3(signature = (output, pulse_us, start, pitch, count = 0, direction = "positive"))]
    #[allow(clippy::too_many_arguments)]
    fn arm_series_each_turn(
        &self,
        p: Python<'_>,
        output: u32,
        pulse_us: u32,
        start: f64,
        pitch: f64,
        count: u32,
        direction: &str,
    ) -> PyResult<()> {
        let d = self::direction(direction)?;
        py(p.allow_threads(|| {
            self.compare
                .arm_series_each_turn(output, pulse_us, start, pitch, count, d)
        }))
    }

    /// Fire at the positions of the channel's table in order (queued with `push`, before or
    /// after), the axis moving `direction` ("positive" or "negative"); an
    /// `EventKind.COMPARE` event (code: low water) when the queue falls to `low_water` (0:
    /// none). The table stays queued from one arm to the next until `disarm()`.
    #[pyo3(signature = (output, pulse_us, *, low_water = 0, direction = "positive"))]
    fn arm_table(
        &self,
        p: Python<'_>,
        output: u32,
        pulse_us: u32,
        low_water: u32,
        direction: &str,
    ) -> PyResult<()> {
        let d = self::direction(direction)?;
        py(p.allow_threads(|| self.compare.arm_table(output, pulse_us, low_water, d)))
    }

    /// Queue `positions` (strictly monotonic going `direction`) in the channel's table, in
    /// entries of up to 12, all or nothing per entry (a full table: `CompareFullError`, the
    /// entries before it staying queued). The room left.
    #[pyo3(signature = (positions, direction = "positive"))]
    fn push(&self, p: Python<'_>, positions: Vec<f64>, direction: &str) -> PyResult<usize> {
        let d = self::direction(direction)?;
        py(p.allow_threads(|| self.compare.push(d, &positions)))
    }

    /// Free room in the channel's table.
    fn room(&self) -> PyResult<usize> {
        py(self.compare.room())
    }

    /// The channel's state: "idle", "armed" or "done".
    fn state(&self) -> PyResult<&'static str> {
        Ok(match py(self.compare.status())?.state {
            sdk::IoState::Idle => "idle",
            sdk::IoState::Armed => "armed",
            sdk::IoState::Done => "done",
        })
    }

    /// Disarm the channel.
    fn disarm(&self, p: Python<'_>) -> PyResult<()> {
        py(p.allow_threads(|| self.compare.disarm()))
    }

    /// (pulses fired, positions missed, positions pending, last position fired).
    fn status(&self) -> PyResult<(u32, u32, u32, f64)> {
        let s = py(self.compare.status())?;
        Ok((s.fires, s.missed, s.pending, s.last_fired))
    }
}

/// A touch probe: latches its axis's position on an input's edge (or the encoder index).
#[pyclass(module = "motioncard", frozen)]
pub struct Probe {
    pub(crate) probe: sdk::TouchProbe,
}

#[pymethods]
impl Probe {
    /// Arm on digital input `input` (None: the encoder's index), on its rising and/or
    /// falling edge; `continuous`: every edge, else the first; `window`: only captures
    /// between these positions.
    #[pyo3(signature = (input, *, rising = true, falling = false, continuous = false, window = None))]
    fn arm(
        &self,
        p: Python<'_>,
        input: Option<u32>,
        rising: bool,
        falling: bool,
        continuous: bool,
        window: Option<(f64, f64)>,
    ) -> PyResult<()> {
        let mut t = match input {
            Some(i) => sdk::ProbeTrigger::rising(i),
            None => sdk::ProbeTrigger::index(),
        };
        t.rising = rising;
        t.falling = falling;
        t.continuous = continuous;
        t.window = window;
        py(p.allow_threads(|| self.probe.arm(&t)))
    }

    /// Disarm.
    fn abort(&self, p: Python<'_>) -> PyResult<()> {
        py(p.allow_threads(|| self.probe.abort()))
    }

    /// The positions captured since the arm (the last 8 at most).
    fn positions(&self) -> PyResult<Vec<f64>> {
        Ok(py(self.probe.status())?.positions)
    }

    /// Wait for capture `n` (1, 2, ... since the arm) and give its position.
    #[pyo3(signature = (n = 1, timeout = None))]
    fn wait_capture(&self, p: Python<'_>, n: u32, timeout: Option<f64>) -> PyResult<f64> {
        wait_sliced(p, timeout, |s| self.probe.wait_capture(n, s))
    }
}

/// An analog input as the card sampled it at its last tick (`Card.analog_input_status`).
#[pyclass(module = "motioncard", frozen, get_all)]
pub struct AnalogInput {
    /// The ADC's sample, V (a multiple of the ADC's step, 20 V / 65536).
    sample: f64,
    /// The filtered value, V.
    value: f64,
    /// Above the threshold.
    above: bool,
    /// The filter's cut-off, Hz (0: none).
    cutoff_hz: f64,
    /// The threshold, V.
    threshold: f64,
    /// The hysteresis, V.
    hysteresis: f64,
    /// An event going above.
    rise_event: bool,
    /// An event going below again.
    fall_event: bool,
}

impl From<sdk::AnalogInput> for AnalogInput {
    fn from(a: sdk::AnalogInput) -> Self {
        AnalogInput {
            sample: a.sample,
            value: a.value,
            above: a.above,
            cutoff_hz: a.settings.cutoff_hz,
            threshold: a.settings.threshold,
            hysteresis: a.settings.hysteresis,
            rise_event: a.settings.rise_event,
            fall_event: a.settings.fall_event,
        }
    }
}

#[pymethods]
impl AnalogInput {
    fn __repr__(&self) -> String {
        format!(
            "AnalogInput(sample={}, value={}, above={}, cutoff_hz={}, threshold={}, \
             hysteresis={}, rise_event={}, fall_event={})",
            self.sample,
            self.value,
            self.above,
            self.cutoff_hz,
            self.threshold,
            self.hysteresis,
            self.rise_event,
            self.fall_event
        )
    }
}
