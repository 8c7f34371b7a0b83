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

/// Gantry `index`'s handle.
#[pyclass(module = "motioncard", frozen)]
pub struct Gantry {
    pub(crate) gantry: sdk::Gantry,
    pub(crate) card: sdk::Card,
}

/// One slave of a gantry (master's user units).
#[pyclass(module = "motioncard", frozen, get_all)]
pub struct GantrySide {
    /// The slave axis.
    axis: usize,
    /// Its square offset (configured).
    offset: f64,
    /// The offset in force: the skew it was coupled with, the square offset once homed.
    hold: f64,
    /// The skew of the last tick: slave actual − master actual − `hold`.
    skew: f64,
    /// The yaw loop's correction of the last tick (user units/s²).
    correction: f64,
    /// The largest |skew| while coupled since the gantry was formed.
    max_skew: f64,
}

/// A gantry as the card reports it.
#[pyclass(module = "motioncard", frozen, get_all)]
pub struct GantryStatus {
    /// The gantry's number.
    index: usize,
    /// `"coupled"`, `"homing"` or `"squaring"`.
    phase: &'static str,
    /// The master axis.
    master: usize,
    /// The slaves.
    slaves: Vec<Py<GantrySide>>,
    /// The yaw loop's proportional gain, 1/s².
    kp: f64,
    /// The yaw loop's integral gain, 1/s³.
    ki: f64,
    /// The skew beyond which every axis of the gantry stops.
    skew_limit: f64,
    /// `Gantry.home()` squared it.
    squared: bool,
}

pub(crate) fn gantry_status(p: Python<'_>, s: sdk::GantryStatus) -> PyResult<GantryStatus> {
    let slaves = s
        .slaves
        .iter()
        .map(|g| {
            Py::new(
                p,
                GantrySide {
                    axis: g.axis,
                    offset: g.offset,
                    hold: g.hold,
                    skew: g.skew,
                    correction: g.correction,
                    max_skew: g.max_skew,
                },
            )
        })
        .collect::<PyResult<Vec<_>>>()?;
    Ok(GantryStatus {
        index: s.index,
        phase: match s.phase {
            sdk::GantryPhase::Coupled => "coupled",
            sdk::GantryPhase::Homing => "homing",
            sdk::GantryPhase::Squaring => "squaring",
        },
        master: s.master,
        slaves,
        kp: s.kp,
        ki: s.ki,
        skew_limit: s.skew_limit,
        squared: s.squared,
    })
}

#[pymethods]
impl Gantry {
    /// The gantry's number.
    #[getter]
    fn index(&self) -> usize {
        self.gantry.index()
    }

    /// Its status (`GantryStateError` once dissolved).
    fn status(&self, p: Python<'_>) -> PyResult<GantryStatus> {
        gantry_status(p, py(self.gantry.status())?)
    }

    /// The master axis: the handle the gantry is commanded through (moves, jog, halt, power
    /// act on every member; a slave refuses commands of its own: `GantrySlaveError`).
    fn master(&self) -> PyResult<Axis> {
        Ok(Axis {
            axis: py(self.gantry.master())?,
            card: self.card.clone(),
        })
    }

    /// Home the gantry: each side runs its own homing method (home position 0), then each
    /// slave moves to its square offset. Wait on the result (`GantryHoming.wait`).
    fn home(&self, p: Python<'_>) -> PyResult<GantryHoming> {
        Ok(GantryHoming {
            homing: py(p.allow_threads(|| self.gantry.home()))?,
        })
    }

    /// Dissolve the gantry (the master at rest): the slaves hold where they are, in
    /// Standstill, each its own axis again.
    fn dissolve(&self, p: Python<'_>) -> PyResult<()> {
        let g = self.gantry.clone();
        py(p.allow_threads(|| g.dissolve()))
    }

    fn __repr__(&self) -> String {
        format!("<motioncard.Gantry {}>", self.gantry.index())
    }
}

/// A gantry's homing in progress.
#[pyclass(module = "motioncard", frozen)]
pub struct GantryHoming {
    homing: sdk::GantryHoming,
}

#[pymethods]
impl GantryHoming {
    /// The command's seq.
    #[getter]
    fn seq(&self) -> u32 {
        self.homing.seq()
    }

    /// Wait until the bridge is squared: slave 0's skew then (`HomingFailedError` naming
    /// the gantry and the side that failed).
    #[pyo3(signature = (timeout = None))]
    fn wait(&self, p: Python<'_>, timeout: Option<f64>) -> PyResult<f64> {
        crate::wait::wait_sliced(p, timeout, |s| self.homing.wait(s))
    }
}

/// The path-speed output (PSO) as the card ran it at its last tick.
#[pyclass(module = "motioncard", frozen, get_all)]
pub struct PsoStatus {
    /// `"off"` (not configured), `"closed"` (its gate off: the output is 0) or `"on"`.
    state: &'static str,
    /// The group (0 while off).
    group: usize,
    /// The DAC output it drives, or the digital output of its PWM (None while off).
    output: Option<usize>,
    /// The PWM's frequency, Hz (None: a DAC output, or off).
    pwm_hz: Option<f64>,
    /// The digital output whose level gates it (None while off).
    gate: Option<usize>,
    /// The output at rest, V or duty.
    min: f64,
    /// The output at `v_ref` and beyond, V or duty.
    max: f64,
    /// The speed of full output, counts/s (the group's scale is the host's).
    v_ref_counts: f64,
    /// The speed filter's cut-off, Hz.
    filter_hz: f64,
    /// The group's actual tangential speed of the tick, counts/s.
    speed_counts: f64,
    /// The output of the tick: V, or the PWM's duty.
    value: f64,
}

pub(crate) fn pso_status(s: sdk::PsoStatus) -> PsoStatus {
    let (output, pwm_hz) = match s.settings.map(|p| p.output) {
        Some(sdk::PsoOutput::Dac(d)) => (Some(d), None),
        Some(sdk::PsoOutput::Pwm { output, hz }) => (Some(output), Some(hz)),
        None => (None, None),
    };
    let p = s.settings;
    PsoStatus {
        state: match s.state {
            sdk::PsoState::Off => "off",
            sdk::PsoState::Closed => "closed",
            sdk::PsoState::On => "on",
        },
        group: s.group,
        output,
        pwm_hz,
        gate: p.map(|p| p.gate),
        min: p.map_or(0.0, |p| p.min),
        max: p.map_or(0.0, |p| p.max),
        v_ref_counts: p.map_or(0.0, |p| p.v_ref),
        filter_hz: p.map_or(0.0, |p| p.filter_hz),
        speed_counts: s.speed_counts,
        value: s.value,
    }
}

/// The settings of `Group.pso`.
pub(crate) fn pso(
    output: usize,
    pwm_hz: Option<f64>,
    gate: usize,
    min: f64,
    max: f64,
    v_ref: f64,
    filter_hz: f64,
) -> sdk::Pso {
    sdk::Pso {
        output: match pwm_hz {
            Some(hz) => sdk::PsoOutput::Pwm { output, hz },
            None => sdk::PsoOutput::Dac(output),
        },
        gate,
        min,
        max,
        v_ref,
        filter_hz,
    }
}
