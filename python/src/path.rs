//! A path's control beyond streaming: each segment's buffer mode (PLCopen, `Aborting` too)
//! and transition, the chord fitter's tolerance (`Segment.with_buffer`, `with_transition`,
//! `fit_within`), outputs along the path (`PathOutput`), and what `Group.path_push`,
//! `path_pause` and `path_resume` take.
use crate::group::Segment;
use motioncard_sdk as sdk;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// The buffer modes by their Python names, in `PathBuffer`'s order.
const BUFFERS: [(&str, sdk::PathBuffer); 6] = [
    ("aborting", sdk::PathBuffer::Aborting),
    ("buffered", sdk::PathBuffer::Buffered),
    ("blending_low", sdk::PathBuffer::BlendingLow),
    ("blending_previous", sdk::PathBuffer::BlendingPrevious),
    ("blending_next", sdk::PathBuffer::BlendingNext),
    ("blending_high", sdk::PathBuffer::BlendingHigh),
];

pub(crate) fn buffer(name: &str) -> PyResult<sdk::PathBuffer> {
    BUFFERS
        .iter()
        .find(|(n, _)| *n == name)
        .map(|(_, b)| *b)
        .ok_or_else(|| {
            let names: Vec<_> = BUFFERS.iter().map(|(n, _)| *n).collect();
            PyValueError::new_err(format!("buffer mode {name:?}: one of {names:?}"))
        })
}

pub(crate) fn buffer_name(b: sdk::PathBuffer) -> &'static str {
    BUFFERS
        .iter()
        .find(|(_, x)| *x == b)
        .map(|(n, _)| *n)
        .unwrap_or("?")
}

pub(crate) fn transition(kind: &str, distance: f64) -> PyResult<sdk::Transition> {
    Ok(match kind {
        "none" => sdk::Transition::None,
        "max_deviation" => sdk::Transition::MaxDeviation(distance),
        "corner_distance" => sdk::Transition::CornerDistance(distance),
        "time_shift" => sdk::Transition::TimeShift(distance),
        other => {
            return Err(PyValueError::new_err(format!(
                "transition {other:?}: \"none\", \"max_deviation\", \"corner_distance\" or \
                 \"time_shift\""
            )))
        }
    })
}

pub(crate) fn transition_pair(t: sdk::Transition) -> (&'static str, f64) {
    match t {
        sdk::Transition::None => ("none", 0.0),
        sdk::Transition::MaxDeviation(d) => ("max_deviation", d),
        sdk::Transition::CornerDistance(d) => ("corner_distance", d),
        sdk::Transition::TimeShift(d) => ("time_shift", d),
    }
}

/// Where an output action fires in the next motion segment: "start", "end" or a distance.
#[derive(FromPyObject)]
pub(crate) enum AtArg {
    Name(String),
    Distance(f64),
}

/// Set (`on`) or clear digital output `output` at a point of the next motion segment queued
/// after it: `at` "start" (as it starts), "end" (as it ends) or a distance along it (first
/// group axis's units). An item of `Group.stream_path` and `Group.path_push`.
#[pyclass(module = "motioncard", frozen)]
#[derive(Clone)]
pub struct PathOutput {
    pub(crate) output: u8,
    pub(crate) on: bool,
    pub(crate) at: sdk::OutputAt,
}

#[pymethods]
impl PathOutput {
    #[new]
    #[pyo3(signature = (output, on, at = AtArg::Name("start".into())))]
    fn new(output: u8, on: bool, at: AtArg) -> PyResult<Self> {
        let at = match at {
            AtArg::Name(n) if n == "start" => sdk::OutputAt::Start,
            AtArg::Name(n) if n == "end" => sdk::OutputAt::End,
            AtArg::Distance(d) => sdk::OutputAt::Distance(d),
            AtArg::Name(n) => {
                return Err(PyValueError::new_err(format!(
                    "at {n:?}: \"start\", \"end\" or a distance"
                )))
            }
        };
        Ok(PathOutput { output, on, at })
    }

    /// The output's number.
    #[getter]
    fn output(&self) -> u8 {
        self.output
    }

    /// Set, else clear.
    #[getter]
    fn on(&self) -> bool {
        self.on
    }

    /// "start", "end" or the distance.
    #[getter]
    fn at(&self, p: Python<'_>) -> PyResult<PyObject> {
        Ok(match self.at {
            sdk::OutputAt::Start => "start".into_pyobject(p)?.into_any().unbind(),
            sdk::OutputAt::End => "end".into_pyobject(p)?.into_any().unbind(),
            sdk::OutputAt::Distance(d) => d.into_pyobject(p)?.into_any().unbind(),
        })
    }

    fn __repr__(&self) -> String {
        let at = match self.at {
            sdk::OutputAt::Start => "\"start\"".to_string(),
            sdk::OutputAt::End => "\"end\"".to_string(),
            sdk::OutputAt::Distance(d) => d.to_string(),
        };
        let on = if self.on { "True" } else { "False" };
        format!("PathOutput({}, {on}, at={at})", self.output)
    }
}

/// An item of a path: a segment or an output action.
#[derive(FromPyObject)]
pub(crate) enum ItemArg {
    Segment(Segment),
    Output(PathOutput),
}

impl From<ItemArg> for sdk::PathItem {
    fn from(i: ItemArg) -> Self {
        match i {
            ItemArg::Segment(s) => sdk::PathItem::Segment(s.segment),
            ItemArg::Output(o) => sdk::PathItem::Output {
                output: o.output,
                on: o.on,
                at: o.at,
            },
        }
    }
}
