//! The machine's axis features: pitch-error and backlash compensation tables, the handwheel
//! (an auxiliary encoder jogs an axis).
use crate::errors::py;
use crate::motion::{Axis, Motion};
use motioncard_sdk as sdk;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// An axis's pitch-error and backlash compensation, user units and seconds: the points
/// `(position, correction)` (or `(position, forward, reverse)`: a bidirectional table),
/// positions strictly increasing; the backlash (+backlash/2 moving forward, -backlash/2 in
/// reverse), the bound on every correction, the ramp that takes up each jump of it.
#[pyclass(module = "motioncard", frozen)]
#[derive(Clone)]
pub struct Compensation {
    pub(crate) comp: sdk::Compensation,
}

#[pymethods]
impl Compensation {
    #[new]
    #[pyo3(signature = (points, *, backlash = 0.0, bound, ramp_velocity = 1_000.0, ramp_acceleration = 1e6))]
    fn new(
        points: Vec<Vec<f64>>,
        backlash: f64,
        bound: f64,
        ramp_velocity: f64,
        ramp_acceleration: f64,
    ) -> PyResult<Self> {
        let mut bidirectional = false;
        let mut pts = Vec::with_capacity(points.len());
        for p in points {
            pts.push(match p[..] {
                [position, c] => sdk::CompPoint::new(position, c),
                [position, forward, reverse] => {
                    bidirectional = true;
                    sdk::CompPoint {
                        position,
                        forward,
                        reverse,
                    }
                }
                _ => {
                    return Err(PyValueError::new_err(format!(
                    "a point is (position, correction) or (position, forward, reverse), not {p:?}"
                )))
                }
            });
        }
        Ok(Compensation {
            comp: sdk::Compensation {
                points: pts,
                bidirectional,
                backlash,
                bound,
                ramp_velocity,
                ramp_acceleration,
            },
        })
    }

    /// The points, (position, forward, reverse) each.
    #[getter]
    fn points(&self) -> Vec<(f64, f64, f64)> {
        self.comp
            .points
            .iter()
            .map(|p| (p.position, p.forward, p.reverse))
            .collect()
    }

    /// The points give a correction per direction.
    #[getter]
    fn bidirectional(&self) -> bool {
        self.comp.bidirectional
    }

    /// Backlash.
    #[getter]
    fn backlash(&self) -> f64 {
        self.comp.backlash
    }

    /// The largest |correction ± backlash/2|.
    #[getter]
    fn bound(&self) -> f64 {
        self.comp.bound
    }

    /// The ramp's velocity.
    #[getter]
    fn ramp_velocity(&self) -> f64 {
        self.comp.ramp_velocity
    }

    /// The ramp's acceleration.
    #[getter]
    fn ramp_acceleration(&self) -> f64 {
        self.comp.ramp_acceleration
    }

    fn __repr__(&self) -> String {
        format!(
            "Compensation({} points, backlash={}, bound={})",
            self.comp.points.len(),
            self.comp.backlash,
            self.comp.bound
        )
    }
}

/// The compensation and handwheel methods of `Axis` (plain functions its `#[pymethods]`
/// block calls).
impl Axis {
    pub(crate) fn do_set_compensation(&self, p: Python<'_>, c: &Compensation) -> PyResult<()> {
        py(p.allow_threads(|| self.axis.set_compensation(&c.comp)))
    }

    pub(crate) fn do_clear_compensation(&self, p: Python<'_>) -> PyResult<()> {
        py(p.allow_threads(|| self.axis.clear_compensation()))
    }

    pub(crate) fn do_compensation(&self, p: Python<'_>) -> PyResult<Option<Compensation>> {
        let c = py(p.allow_threads(|| self.axis.compensation()))?;
        Ok(c.map(|comp| Compensation { comp }))
    }

    pub(crate) fn do_handwheel(
        &self,
        p: Python<'_>,
        input: usize,
        ratio: i32,
        detent: u32,
    ) -> PyResult<Motion> {
        let wheel = sdk::Handwheel::new(input).ratio(ratio).detent(detent);
        let m = py(p.allow_threads(|| self.axis.handwheel(&wheel)))?;
        Ok(Motion {
            motion: m,
            axis: self.axis.index(),
        })
    }

    pub(crate) fn do_handwheel_off(&self, p: Python<'_>) -> PyResult<()> {
        py(p.allow_threads(|| self.axis.handwheel_off()))
    }
}
