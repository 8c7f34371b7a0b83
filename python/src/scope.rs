//! The scope: a one-shot capture as numpy arrays, one per channel, and the time.
use crate::errors::py;
use crate::names::upper_snake;
use motioncard_sdk as sdk;
use numpy::PyArray1;
use pyo3::exceptions::{PyIndexError, PyValueError};
use pyo3::prelude::*;
use std::sync::Mutex;
use std::time::Duration;

/// The card's scope: records up to `SCOPE_CHANNELS` signals every `divider` servo ticks.
#[pyclass(module = "motioncard", frozen)]
pub struct Scope {
    card: sdk::Card,
}

impl Scope {
    pub(crate) fn new(card: &sdk::Card) -> Self {
        Scope { card: card.clone() }
    }
}

/// A signal given as `motioncard.Signal` (an int) or its name (`"cmd_pos"`, `"CMD_POS"`).
fn signal(obj: &Bound<'_, PyAny>) -> PyResult<sdk::Signal> {
    if let Ok(name) = obj.extract::<String>() {
        let want = name.to_ascii_uppercase();
        return sdk::Signal::ALL
            .iter()
            .copied()
            .find(|s| upper_snake(&format!("{s:?}")) == want)
            .ok_or_else(|| PyValueError::new_err(format!("no signal named {name:?}")));
    }
    let v: u32 = obj.extract()?;
    sdk::Signal::from_raw(v).ok_or_else(|| PyValueError::new_err(format!("no signal {v}")))
}

fn edge(name: &str) -> PyResult<sdk::Edge> {
    match name {
        "rising" => Ok(sdk::Edge::Rising),
        "falling" => Ok(sdk::Edge::Falling),
        "either" => Ok(sdk::Edge::Either),
        _ => Err(PyValueError::new_err(format!(
            "edge {name:?}: \"rising\", \"falling\" or \"either\""
        ))),
    }
}

#[pymethods]
impl Scope {
    /// Configure, arm and run a one-shot capture of `channels` (pairs of a signal and the
    /// axis, group or 0 for the card's signals) for `samples` samples after the trigger
    /// (`pre_trigger` more before it), one every `divider` ticks. `trigger`: "immediate",
    /// "command" (call `scope.trigger()` from `while_armed`), "fault", "level" (channel
    /// `trigger_channel` crossing `level` on `edge`) or "input" (digital input
    /// `trigger_input` on `edge`). `while_armed`, if given, is called once the scope is armed
    /// (start the motion to capture there). `timeout` bounds the whole capture (emulated
    /// time on a stepped card, which is stepped meanwhile).
    #[pyo3(signature = (channels, samples, *, divider = 1, pre_trigger = 0, trigger = "immediate", trigger_channel = 0, level = 0.0, trigger_input = 0, edge = "rising", timeout = 10.0, while_armed = None))]
    #[allow(clippy::too_many_arguments)]
    fn capture(
        &self,
        p: Python<'_>,
        channels: Vec<(Bound<'_, PyAny>, u16)>,
        samples: u32,
        divider: u32,
        pre_trigger: u32,
        trigger: &str,
        trigger_channel: usize,
        level: f64,
        trigger_input: usize,
        edge: &str,
        timeout: f64,
        while_armed: Option<PyObject>,
    ) -> PyResult<Capture> {
        let sources = channels
            .iter()
            .map(|(s, index)| {
                Ok(sdk::Source {
                    signal: signal(s)?,
                    index: *index,
                })
            })
            .collect::<PyResult<Vec<_>>>()?;
        let mut settings = sdk::ScopeSettings::new(&sources, samples);
        settings.divider = divider;
        settings.pre_trigger = pre_trigger;
        settings.trigger = match trigger {
            "immediate" => sdk::ScopeTrigger::Immediate,
            "command" => sdk::ScopeTrigger::Command,
            "fault" => sdk::ScopeTrigger::Fault,
            "level" => sdk::ScopeTrigger::Level {
                channel: trigger_channel,
                level,
                edge: self::edge(edge)?,
            },
            "input" => sdk::ScopeTrigger::Input {
                input: trigger_input,
                edge: self::edge(edge)?,
            },
            other => {
                return Err(PyValueError::new_err(format!(
                "trigger {other:?}: \"immediate\", \"command\", \"fault\", \"level\" or \"input\""
            )))
            }
        };
        let timeout = Duration::try_from_secs_f64(timeout)
            .map_err(|e| PyValueError::new_err(format!("timeout {timeout}: {e}")))?;
        let scope = self.card.scope();
        let rate = self.card.info().servo_rate_hz.max(1) as f64;
        // the callback's own exception, raised again once the capture has ended
        let failed: Mutex<Option<PyErr>> = Mutex::new(None);
        let r = p.allow_threads(|| {
            scope.capture(&settings, timeout, |_| match &while_armed {
                None => Ok(()),
                Some(f) => Python::with_gil(|p| match f.call0(p) {
                    Ok(_) => Ok(()),
                    Err(e) => {
                        *failed.lock().unwrap_or_else(|e| e.into_inner()) = Some(e);
                        Err(sdk::Error::Cancelled)
                    }
                }),
            })
        });
        if let Some(e) = failed.into_inner().unwrap_or_else(|e| e.into_inner()) {
            return Err(e);
        }
        let c = py(r)?;
        let n = c.channels;
        let ticks: Vec<u64> = c.samples.iter().map(|s| s.tick).collect();
        let time: Vec<f64> = c
            .samples
            .iter()
            .map(|s| (s.tick as f64 - c.trigger_tick as f64) / rate)
            .collect();
        let values: Vec<Vec<f64>> = (0..n)
            .map(|k| c.samples.iter().map(|s| s.value[k]).collect())
            .collect();
        Ok(Capture {
            names: sources
                .iter()
                .map(|s| {
                    (
                        upper_snake(&format!("{:?}", s.signal)).to_lowercase(),
                        s.index,
                    )
                })
                .collect(),
            ticks,
            time,
            values,
            trigger_tick: c.trigger_tick,
            lost: c.lost,
        })
    }

    /// Trigger a capture armed with the "command" trigger.
    fn trigger(&self, p: Python<'_>) -> PyResult<()> {
        let scope = self.card.scope();
        py(p.allow_threads(|| scope.trigger()))
    }
}

/// A finished capture: `time` (s from the trigger), `ticks`, and one array per channel
/// (`capture[k]`, `capture.channels`), in the card's units (counts, volts, words as their
/// value). `matplotlib.pyplot.plot(c.time, c[0])` plots channel 0.
#[pyclass(module = "motioncard", frozen)]
pub struct Capture {
    names: Vec<(String, u16)>,
    ticks: Vec<u64>,
    time: Vec<f64>,
    values: Vec<Vec<f64>>,
    /// The tick of the trigger.
    #[pyo3(get)]
    trigger_tick: u64,
    /// Samples lost (the ring overran).
    #[pyo3(get)]
    lost: u64,
}

#[pymethods]
impl Capture {
    /// Seconds from the trigger, one per sample.
    #[getter]
    fn time<'py>(&self, p: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(p, &self.time)
    }

    /// The servo tick of each sample.
    #[getter]
    fn ticks<'py>(&self, p: Python<'py>) -> Bound<'py, PyArray1<u64>> {
        PyArray1::from_slice(p, &self.ticks)
    }

    /// One array per channel.
    #[getter]
    fn channels<'py>(&self, p: Python<'py>) -> Vec<Bound<'py, PyArray1<f64>>> {
        self.values
            .iter()
            .map(|v| PyArray1::from_slice(p, v))
            .collect()
    }

    /// The channels' sources: (signal name, axis or group).
    #[getter]
    fn sources(&self) -> Vec<(String, u16)> {
        self.names.clone()
    }

    fn __getitem__<'py>(&self, p: Python<'py>, k: isize) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let n = self.values.len() as isize;
        let i = if k < 0 { k + n } else { k };
        if i < 0 || i >= n {
            return Err(PyIndexError::new_err(format!("channel {k} of {n}")));
        }
        Ok(PyArray1::from_slice(p, &self.values[i as usize]))
    }

    /// The channels' arrays in order.
    fn __iter__<'py>(&self, p: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        pyo3::types::PyList::new(p, self.channels(p))?
            .into_any()
            .try_iter()
            .map(|i| i.into_any())
    }

    /// The number of channels.
    fn __len__(&self) -> usize {
        self.values.len()
    }

    fn __repr__(&self) -> String {
        format!("Capture({} samples of {:?})", self.time.len(), self.names)
    }
}
