//! `Axis`, `MoveLimits`, `Motion` and `Status`.
use crate::errors::py;
use crate::names::py_enum;
use crate::wait::wait_sliced;
use motioncard_sdk as sdk;
use pyo3::prelude::*;

/// Limits of a point-to-point move, in user units: velocity, acceleration and jerk, with a
/// different deceleration, deceleration jerk, or four phase jerks by keyword.
#[pyclass(module = "motioncard", frozen)]
#[derive(Clone, Copy)]
pub struct MoveLimits {
    pub(crate) limits: sdk::MoveLimits,
}

#[pymethods]
impl MoveLimits {
    #[new]
    #[pyo3(signature = (velocity, acceleration, jerk, *, deceleration = None, decel_jerk = None, jerks = None))]
    fn new(
        velocity: f64,
        acceleration: f64,
        jerk: f64,
        deceleration: Option<f64>,
        decel_jerk: Option<f64>,
        jerks: Option<[f64; 4]>,
    ) -> Self {
        let mut l = sdk::MoveLimits::new(velocity, acceleration, jerk);
        if let Some(d) = deceleration {
            l = l.deceleration(d);
        }
        if let Some(j) = decel_jerk {
            l = l.decel_jerk(j);
        }
        if let Some(j) = jerks {
            l.jerk = j;
        }
        MoveLimits { limits: l }
    }

    /// Maximum velocity.
    #[getter]
    fn velocity(&self) -> f64 {
        self.limits.velocity
    }

    /// Maximum acceleration.
    #[getter]
    fn acceleration(&self) -> f64 {
        self.limits.acceleration
    }

    /// Maximum deceleration.
    #[getter]
    fn deceleration(&self) -> f64 {
        self.limits.deceleration
    }

    /// Jerks of the seven-segment phases 1, 3 (acceleration), 5 and 7 (deceleration).
    #[getter]
    fn jerks(&self) -> (f64, f64, f64, f64) {
        let j = self.limits.jerk;
        (j[0], j[1], j[2], j[3])
    }

    fn __repr__(&self) -> String {
        let l = &self.limits;
        format!(
            "MoveLimits({}, {}, {}, deceleration={}, jerks={:?})",
            l.velocity, l.acceleration, l.jerk[0], l.deceleration, l.jerk
        )
    }
}

/// One axis of a card.
#[pyclass(module = "motioncard", frozen)]
pub struct Axis {
    pub(crate) axis: sdk::Axis,
    /// Its card (the stepping of a stepped card, its servo rate).
    pub(crate) card: sdk::Card,
}

fn started(m: sdk::Result<sdk::Motion>, axis: usize) -> PyResult<Motion> {
    Ok(Motion {
        motion: py(m)?,
        axis,
    })
}

/// The settings `Axis.settings` and `Axis.configure` name.
type Field = fn(&mut sdk::AxisSettings) -> &mut f64;
const SETTINGS: [(&str, Field); 13] = [
    ("kp", |c| &mut c.ffpiv.kp),
    ("ki", |c| &mut c.ffpiv.ki),
    ("kv", |c| &mut c.ffpiv.kv),
    ("kvff", |c| &mut c.ffpiv.kvff),
    ("kaff", |c| &mut c.ffpiv.kaff),
    ("vel_filter_hz", |c| &mut c.ffpiv.vel_filter_hz),
    ("dac_limit_v", |c| &mut c.dac_limit_v),
    ("in_pos_window", |c| &mut c.in_pos_window),
    ("in_vel_window", |c| &mut c.in_vel_window),
    ("settle_time", |c| &mut c.settle_time),
    ("jog_max_vel", |c| &mut c.jog_max_vel),
    ("jog_accel", |c| &mut c.jog_accel),
    ("jog_jerk", |c| &mut c.jog_jerk),
];

impl Axis {
    fn move_with(
        &self,
        p: Python<'_>,
        kind: sdk::MoveKind,
        value: f64,
        limits: MoveLimits,
        buffered: bool,
        direction: sdk::MoveDirection,
    ) -> PyResult<Motion> {
        let mode = if buffered {
            sdk::BufferMode::Buffered
        } else {
            sdk::BufferMode::Aborting
        };
        started(
            p.allow_threads(|| {
                self.axis
                    .move_with_dir(kind, value, &limits.limits, mode, direction)
            }),
            self.axis.index(),
        )
    }
}

/// A move's direction on a modulo axis by its Python name.
fn direction(name: &str) -> PyResult<sdk::MoveDirection> {
    Ok(match name {
        "shortest" => sdk::MoveDirection::Shortest,
        "positive" => sdk::MoveDirection::Positive,
        "negative" => sdk::MoveDirection::Negative,
        "current" => sdk::MoveDirection::Current,
        other => {
            return Err(pyo3::exceptions::PyValueError::new_err(format!(
                "direction {other:?}: \"shortest\", \"positive\", \"negative\" or \"current\""
            )))
        }
    })
}

#[pymethods]
impl Axis {
    /// The axis's number on the card.
    #[getter]
    fn index(&self) -> usize {
        self.axis.index()
    }

    /// Power on: Disabled → Standstill.
    fn enable(&self, p: Python<'_>) -> PyResult<()> {
        py(p.allow_threads(|| self.axis.enable()))
    }

    /// Power off.
    fn disable(&self, p: Python<'_>) -> PyResult<()> {
        py(p.allow_threads(|| self.axis.disable()))
    }

    /// Encoder counts per user unit (positions, velocities and limits are in user units).
    fn set_scale(&self, p: Python<'_>, counts_per_unit: f64) -> PyResult<()> {
        py(p.allow_threads(|| self.axis.set_scale(counts_per_unit)))
    }

    /// The counts per user unit.
    #[getter]
    fn scale(&self) -> f64 {
        self.axis.scale_factor()
    }

    /// Make it a rotary axis whose position wraps every `period` user units.
    fn set_modulo(&self, p: Python<'_>, period: f64) -> PyResult<()> {
        py(p.allow_threads(|| self.axis.set_modulo(period)))
    }

    /// A linear axis again.
    fn clear_modulo(&self, p: Python<'_>) -> PyResult<()> {
        py(p.allow_threads(|| self.axis.clear_modulo()))
    }

    /// The modulo period (0: a linear axis).
    fn modulo(&self) -> PyResult<f64> {
        py(self.axis.modulo())
    }

    /// Move to `target` within `limits`; `buffered`: after the motion in progress ends
    /// (PLCopen Buffered), else at once from the current state (Aborting). On a modulo axis
    /// (`set_modulo`) `target` is in [0, period) and `direction` (PLCopen `MC_Direction`)
    /// names the way round: `"shortest"`, `"positive"`, `"negative"` or `"current"` (the way
    /// it moves, or last moved); a linear axis takes `"shortest"` only (`ModuloMoveError`).
    #[pyo3(signature = (target, limits, *, buffered = false, direction = "shortest"))]
    fn move_absolute(
        &self,
        p: Python<'_>,
        target: f64,
        limits: MoveLimits,
        buffered: bool,
        direction: &str,
    ) -> PyResult<Motion> {
        let d = self::direction(direction)?;
        self.move_with(p, sdk::MoveKind::Absolute, target, limits, buffered, d)
    }

    /// Move by `distance` within `limits`; `buffered` as `move_absolute`.
    #[pyo3(signature = (distance, limits, *, buffered = false))]
    fn move_relative(
        &self,
        p: Python<'_>,
        distance: f64,
        limits: MoveLimits,
        buffered: bool,
    ) -> PyResult<Motion> {
        self.move_with(
            p,
            sdk::MoveKind::Relative,
            distance,
            limits,
            buffered,
            Default::default(),
        )
    }

    /// MC_MoveAdditive: `distance` more than the target of the motion in progress.
    #[pyo3(signature = (distance, limits, *, buffered = false))]
    fn move_additive(
        &self,
        p: Python<'_>,
        distance: f64,
        limits: MoveLimits,
        buffered: bool,
    ) -> PyResult<Motion> {
        self.move_with(
            p,
            sdk::MoveKind::Additive,
            distance,
            limits,
            buffered,
            Default::default(),
        )
    }

    /// The servo gains, windows and jog limits (FFPIV; counts, seconds, volts) by name:
    /// `kp`, `ki`, `kv`, `kvff`, `kaff`, `vel_filter_hz`, `dac_limit_v`, `in_pos_window`,
    /// `in_vel_window`, `settle_time`, `jog_max_vel`, `jog_accel`, `jog_jerk`.
    fn settings(&self) -> PyResult<std::collections::BTreeMap<&'static str, f64>> {
        let mut c = py(self.axis.settings())?;
        Ok(SETTINGS.iter().map(|(k, f)| (*k, *f(&mut c))).collect())
    }

    /// Change some of `settings()` (the others stay) and have the card check and apply
    /// them: `axis.configure(kp=120.0, in_pos_window=2.0)`.
    #[pyo3(signature = (**changes))]
    fn configure(
        &self,
        p: Python<'_>,
        changes: Option<std::collections::HashMap<String, f64>>,
    ) -> PyResult<()> {
        let mut c = py(self.axis.settings())?;
        for (k, v) in changes.unwrap_or_default() {
            let (_, field) = SETTINGS.iter().find(|(n, _)| *n == k).ok_or_else(|| {
                pyo3::exceptions::PyTypeError::new_err(format!("no axis setting named {k:?}"))
            })?;
            *field(&mut c) = v;
        }
        py(p.allow_threads(|| self.axis.configure(&c)))
    }

    /// Run at the signed `velocity`, reached within `acceleration` (and `deceleration`,
    /// default the acceleration) and `jerk`; end it with `halt` or `stop`. The motion is
    /// never done, only aborted; `Motion.wait_in_velocity` waits for the velocity.
    #[pyo3(signature = (velocity, acceleration, jerk, *, deceleration = None))]
    fn move_velocity(
        &self,
        p: Python<'_>,
        velocity: f64,
        acceleration: f64,
        jerk: f64,
        deceleration: Option<f64>,
    ) -> PyResult<Motion> {
        let mut l = sdk::VelocityLimits::new(acceleration, jerk);
        if let Some(d) = deceleration {
            l.deceleration = d;
        }
        started(
            p.allow_threads(|| self.axis.move_velocity(velocity, &l)),
            self.axis.index(),
        )
    }

    /// Jog at the signed `velocity` with the axis's jog limits; `jog_release` ends it.
    fn jog(&self, p: Python<'_>, velocity: f64) -> PyResult<Motion> {
        started(
            p.allow_threads(|| self.axis.jog(velocity)),
            self.axis.index(),
        )
    }

    /// Release the jog button: halt at the jog deceleration.
    fn jog_release(&self, p: Python<'_>) -> PyResult<Motion> {
        started(
            p.allow_threads(|| self.axis.jog_release()),
            self.axis.index(),
        )
    }

    /// MC_Halt: decelerate within the limits to Standstill.
    fn halt(&self, p: Python<'_>, deceleration: f64, jerk: f64) -> PyResult<Motion> {
        started(
            p.allow_threads(|| self.axis.halt(deceleration, jerk)),
            self.axis.index(),
        )
    }

    /// MC_Stop: decelerate and stay in Stopping until `release_stop`.
    fn stop(&self, p: Python<'_>, deceleration: f64, jerk: f64) -> PyResult<Motion> {
        started(
            p.allow_threads(|| self.axis.stop(deceleration, jerk)),
            self.axis.index(),
        )
    }

    /// Leave Stopping.
    fn release_stop(&self, p: Python<'_>) -> PyResult<()> {
        py(p.allow_threads(|| self.axis.release_stop()))
    }

    /// MC_Reset: ErrorStop → Standstill.
    fn reset(&self, p: Python<'_>) -> PyResult<()> {
        py(p.allow_threads(|| self.axis.reset()))
    }

    /// The velocity override (1.0 = 100 %, 0 to 2).
    fn set_override(&self, p: Python<'_>, factor: f64) -> PyResult<()> {
        py(p.allow_threads(|| self.axis.set_override(factor)))
    }

    /// Wait for the last motion started on this axis; the actual position at its end.
    #[pyo3(signature = (timeout = None))]
    fn wait_done(&self, p: Python<'_>, timeout: Option<f64>) -> PyResult<f64> {
        wait_sliced(p, timeout, |s| self.axis.wait_done(s))
    }

    /// A consistent snapshot of the axis's status.
    fn status(&self) -> PyResult<Status> {
        Ok(Status::from(py(self.axis.status())?))
    }

    /// Configure MC_Home: `method` a CiA 402 number (1–14, 17–30, 33, 34, 35/37 the current
    /// position, -1/-2 hard stops); the other settings by keyword, in counts and seconds as
    /// the card keeps them; those not given stay.
    #[pyo3(signature = (method, *, search_velocity = None, creep_velocity = None, acceleration = None, jerk = None, offset = None, timeout = None, max_distance = None, index = None))]
    #[allow(clippy::too_many_arguments)]
    fn configure_homing(
        &self,
        p: Python<'_>,
        method: i32,
        search_velocity: Option<f64>,
        creep_velocity: Option<f64>,
        acceleration: Option<f64>,
        jerk: Option<f64>,
        offset: Option<f64>,
        timeout: Option<f64>,
        max_distance: Option<f64>,
        index: Option<bool>,
    ) -> PyResult<()> {
        let mut h = py(self.axis.homing_settings())?;
        h.method = method;
        let set = |f: &mut f64, v: Option<f64>| {
            if let Some(v) = v {
                *f = v;
            }
        };
        set(&mut h.search_vel, search_velocity);
        set(&mut h.creep_vel, creep_velocity);
        set(&mut h.accel, acceleration);
        set(&mut h.jerk, jerk);
        set(&mut h.home_offset, offset);
        set(&mut h.timeout, timeout);
        set(&mut h.max_distance, max_distance);
        if let Some(i) = index {
            let bit = sdk::HomingFlags::INDEX.bits();
            h.flags = if i { h.flags | bit } else { h.flags & !bit };
        }
        py(p.allow_threads(|| self.axis.configure_homing(&h)))
    }

    /// MC_Home with the configured method: the home point will read `position`. The motion
    /// ends homed; `HomingFailedError` from its wait when no home point was found.
    #[pyo3(signature = (position = 0.0))]
    fn home(&self, p: Python<'_>, position: f64) -> PyResult<Motion> {
        started(
            p.allow_threads(|| self.axis.home(position)),
            self.axis.index(),
        )
    }

    /// MC_SetPosition: the actual position reads `position` (added to it if `relative`).
    #[pyo3(signature = (position, relative = false))]
    fn set_position(&self, p: Python<'_>, position: f64, relative: bool) -> PyResult<()> {
        py(p.allow_threads(|| self.axis.set_position(position, relative)))
    }

    /// MC_GearIn: follow `master` (an axis; `source` "commanded", "actual", "actual_lead",
    /// or "aux": auxiliary encoder `master`) at `numerator/denominator`, caught up within
    /// `velocity`, `acceleration` and `jerk`; `Motion.wait_in_sync` waits until in gear.
    #[pyo3(signature = (master, numerator, denominator, velocity, acceleration, jerk, *, source = "commanded"))]
    #[allow(clippy::too_many_arguments)]
    fn gear_in(
        &self,
        p: Python<'_>,
        master: usize,
        numerator: i64,
        denominator: i64,
        velocity: f64,
        acceleration: f64,
        jerk: f64,
        source: &str,
    ) -> PyResult<Motion> {
        let m = master_of(source, master)?;
        let l = sdk::SyncLimits::new(velocity, acceleration, jerk);
        started(
            p.allow_threads(|| self.axis.gear_in(m, numerator, denominator, &l)),
            self.axis.index(),
        )
    }

    /// MC_GearOut: leave the gear at the velocity reached (then halt or move on).
    fn gear_out(&self, p: Python<'_>) -> PyResult<Motion> {
        started(p.allow_threads(|| self.axis.gear_out()), self.axis.index())
    }

    /// MC_CamIn: follow `master` through cam table `table` (loaded with
    /// `Card.load_cam_table`), caught up within the limits.
    #[pyo3(signature = (master, table, velocity, acceleration, jerk, *, source = "commanded", relative = false))]
    #[allow(clippy::too_many_arguments)]
    fn cam_in(
        &self,
        p: Python<'_>,
        master: usize,
        table: usize,
        velocity: f64,
        acceleration: f64,
        jerk: f64,
        source: &str,
        relative: bool,
    ) -> PyResult<Motion> {
        let m = master_of(source, master)?;
        let l = sdk::SyncLimits::new(velocity, acceleration, jerk);
        let mut cam = sdk::CamSettings::new(table);
        cam.relative = relative;
        started(
            p.allow_threads(|| self.axis.cam_in(m, &cam, &l)),
            self.axis.index(),
        )
    }

    /// MC_CamTableSelect + MC_CamIn at the end of the cycle: on an axis that cams, table
    /// `table` takes over when the current cycle ends, its offsets continuing the slave's
    /// position from there (`Motion.wait_cam_switch` waits for it). `InvalidStateError` if
    /// the axis does not cam, `CamTableError` for a table not loaded.
    #[pyo3(signature = (master, table, velocity, acceleration, jerk, *, source = "commanded"))]
    #[allow(clippy::too_many_arguments)]
    fn cam_switch(
        &self,
        p: Python<'_>,
        master: usize,
        table: usize,
        velocity: f64,
        acceleration: f64,
        jerk: f64,
        source: &str,
    ) -> PyResult<Motion> {
        let m = master_of(source, master)?;
        let l = sdk::SyncLimits::new(velocity, acceleration, jerk);
        let cam = sdk::CamSettings::new(table);
        started(
            p.allow_threads(|| self.axis.cam_switch(m, &cam, &l)),
            self.axis.index(),
        )
    }

    /// Set the axis's post-interpolation acc/dec filters, one per feed type (those not
    /// given keep the card's): each `(kind, time_constant_s)`, kind "none", "linear"
    /// (moving average), "exponential" (first order) or "bell" (linear then exponential).
    /// They act in groups configured with `accdec="post"` or "both", and are applied when the
    /// axis holds no distance. Refused: `NotFiniteError`, and the card's refusal of a time
    /// constant out of its range (nothing changes).
    #[pyo3(signature = (*, rapid = None, cutting = None, jog = None))]
    fn set_filters(
        &self,
        p: Python<'_>,
        rapid: Option<(String, f64)>,
        cutting: Option<(String, f64)>,
        jog: Option<(String, f64)>,
    ) -> PyResult<()> {
        let mut f = py(self.axis.filter_settings())?;
        for (slot, arg) in [
            (&mut f.rapid, rapid),
            (&mut f.cutting, cutting),
            (&mut f.jog, jog),
        ] {
            if let Some((kind, tau)) = arg {
                *slot = (filter_kind(&kind)?, tau);
            }
        }
        py(p.allow_threads(|| self.axis.set_filters(&f)))
    }

    /// The axis's acc/dec filters as the card holds them: `{"rapid": (kind, time_constant_s),
    /// "cutting": ..., "jog": ...}`.
    fn filter_settings(
        &self,
    ) -> PyResult<std::collections::BTreeMap<&'static str, (&'static str, f64)>> {
        let f = py(self.axis.filter_settings())?;
        Ok([("rapid", f.rapid), ("cutting", f.cutting), ("jog", f.jog)]
            .into_iter()
            .map(|(k, (kind, tau))| (k, (filter_name(kind), tau)))
            .collect())
    }

    /// MC_CamOut.
    fn cam_out(&self, p: Python<'_>) -> PyResult<Motion> {
        started(p.allow_threads(|| self.axis.cam_out()), self.axis.index())
    }

    /// Run a PT/PVT stream: `points` are (time from the start of the stream s, position,
    /// velocity) (PT: the velocity ignored), the whole stream sent before it starts (at most
    /// the card's buffer, `PVT_LEN`), within `velocity` and `acceleration`. The motion is done
    /// at the last point.
    #[pyo3(signature = (points, velocity, acceleration, *, mode = "pvt"))]
    fn pvt(
        &self,
        p: Python<'_>,
        points: Vec<(f64, f64, f64)>,
        velocity: f64,
        acceleration: f64,
        mode: &str,
    ) -> PyResult<Motion> {
        let mode = match mode {
            "pvt" => sdk::PvtMode::Pvt,
            "pt" => sdk::PvtMode::Pt,
            other => {
                return Err(pyo3::exceptions::PyValueError::new_err(format!(
                    "mode {other:?}: \"pvt\" or \"pt\""
                )))
            }
        };
        let pts: Vec<sdk::PvtPoint> = points
            .iter()
            .map(|&(t, x, v)| sdk::PvtPoint::new(t, x, v))
            .collect();
        let lim = sdk::PvtLimits {
            velocity,
            acceleration,
        };
        started(
            p.allow_threads(|| {
                self.axis.pvt_begin(mode, &lim, 0)?;
                self.axis.pvt_push(&pts, true)?;
                self.axis.pvt_start()
            }),
            self.axis.index(),
        )
    }

    /// Compare channel `channel` watching this axis.
    fn compare(&self, channel: usize) -> crate::io::Compare {
        crate::io::Compare {
            compare: self.axis.compare(channel),
        }
    }

    /// Touch-probe channel `channel` capturing this axis.
    fn touch_probe(&self, channel: usize) -> crate::io::Probe {
        crate::io::Probe {
            probe: self.axis.touch_probe(channel),
        }
    }

    /// The servo law the axis runs: `"ffpiv"` (`configure`), `"pdplus"` or `"pidff"`.
    fn servo_law(&self) -> PyResult<&'static str> {
        self.do_servo_law()
    }

    /// Switch to the PID + feed-forward law (any state; at rest the switch does not step the
    /// output): `kp`, `ki`, `kd`, `kvff`, `kaff`, `friction`, `friction_deadband`,
    /// `d_filter_hz` (volts, counts, seconds); those not given stay as the axis has them
    /// (the card's default tuning when it runs another law). `PidffGainsError`: a gain
    /// negative, a cut-off or deadband not above 0.
    #[pyo3(signature = (**gains))]
    fn configure_pidff(
        &self,
        p: Python<'_>,
        gains: Option<std::collections::HashMap<String, f64>>,
    ) -> PyResult<()> {
        self.do_configure_pidff(p, gains)
    }

    /// The PID+FF gains the axis runs, by name (None: it runs another law).
    fn pidff_settings(&self) -> PyResult<Option<std::collections::BTreeMap<&'static str, f64>>> {
        self.do_pidff_settings()
    }

    /// Switch to the PD+ law with its drive model: `kp`, `kd`, `kv`, `ka` (gains), `kc`,
    /// `tau`, `ke` (the drive), `umax` (the drive limit, V); from another law every one must
    /// be given, on PD+ those not given stay.
    #[pyo3(signature = (**settings))]
    fn configure_pdplus(
        &self,
        p: Python<'_>,
        settings: Option<std::collections::HashMap<String, f64>>,
    ) -> PyResult<()> {
        self.do_configure_pdplus(p, settings)
    }

    /// The PD+ law the axis runs, by name (None: it runs another law).
    fn pdplus_settings(&self) -> PyResult<Option<std::collections::BTreeMap<&'static str, f64>>> {
        self.do_pdplus_settings()
    }

    /// Put `filter` in slot `slot` (0 to 3) of the servo output's biquads. Refused, nothing
    /// changed: `FilterKindError` (the slot), `FilterFreqError`, `FilterParamError`,
    /// `FilterUnstableError`, `NotFiniteError`.
    fn set_servo_filter(
        &self,
        p: Python<'_>,
        slot: usize,
        filter: crate::servo::ServoFilter,
    ) -> PyResult<()> {
        self.do_set_servo_filter(p, slot, &filter)
    }

    /// Empty filter slot `slot` (None: every slot).
    #[pyo3(signature = (slot = None))]
    fn clear_servo_filter(&self, p: Python<'_>, slot: Option<usize>) -> PyResult<()> {
        self.do_clear_servo_filter(p, slot)
    }

    /// The filters the axis holds, slot by slot (None: empty), with the card's coefficients.
    fn servo_filters(&self) -> PyResult<Vec<Option<crate::servo::ServoFilter>>> {
        self.do_servo_filters()
    }

    /// Measure the frequency response (the axis enabled, at rest): a stepped sine on the
    /// position reference (`mode="reference"`: the closed loop; `amplitude` in user units) or
    /// on the servo output (`"output"`: the plant and the open loop; volts), `points`
    /// log-spaced from `from_hz` to `to_hz`, `cycles` periods each after `settle_s`. Waits
    /// for its end (`timeout` s; emulated time on a stepped card); `AbortedError` when it
    /// ended early.
    #[pyo3(signature = (*, mode = "reference", from_hz = 5.0, to_hz = 1000.0, points = 40, amplitude = 100.0, cycles = 4, settle_s = 0.2, timeout = None))]
    #[allow(clippy::too_many_arguments)]
    fn frequency_response(
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
    ) -> PyResult<crate::servo::FreqResponse> {
        self.do_frequency_response(
            p, mode, from_hz, to_hz, points, amplitude, cycles, settle_s, timeout,
        )
    }

    /// Load `table` (a `Compensation`) as the axis's pitch-error and backlash compensation,
    /// used while the axis is homed (or its position set). Checked as the card checks it:
    /// `CompTableError`, `CompOrderError`, `CompBoundError`, `NotFiniteError`; `CompBusyError`
    /// when the axis is not at rest. A refused table changes nothing.
    fn set_compensation(&self, p: Python<'_>, table: crate::machine::Compensation) -> PyResult<()> {
        self.do_set_compensation(p, &table)
    }

    /// Switch the compensation off (its correction ramps out); `CompBusyError` unless at rest.
    fn clear_compensation(&self, p: Python<'_>) -> PyResult<()> {
        self.do_clear_compensation(p)
    }

    /// The compensation the card holds, read back (None: none).
    fn compensation(&self, p: Python<'_>) -> PyResult<Option<crate::machine::Compensation>> {
        self.do_compensation(p)
    }

    /// Jog the axis with auxiliary encoder `input` (a handwheel): each detent (`detent`
    /// auxiliary counts) moves it `ratio` encoder counts, within its jog limits. The motion
    /// is done once the wheel is let go (`handwheel_off`, or the input selected for another
    /// axis) and the axis is in position. `HandwheelInputError`, `HandwheelRatioError`.
    #[pyo3(signature = (input, *, ratio = 1, detent = 4))]
    fn handwheel(&self, p: Python<'_>, input: usize, ratio: i32, detent: u32) -> PyResult<Motion> {
        self.do_handwheel(p, input, ratio, detent)
    }

    /// Let go of the axis's handwheel: it goes on to where the wheel put it
    /// (`InvalidStateError` when no handwheel drives it).
    fn handwheel_off(&self, p: Python<'_>) -> PyResult<()> {
        self.do_handwheel_off(p)
    }

    /// The axis's safety configuration as the card holds it, in user units.
    fn safety_settings(&self, p: Python<'_>) -> PyResult<crate::safety::SafetySettings> {
        let s = py(p.allow_threads(|| self.axis.safety_settings()))?;
        Ok(crate::safety::SafetySettings { s })
    }

    /// Write the axis's safety configuration (limits, following error, stop ramp; user
    /// units through the axis's scale) and have the card apply it. Refused:
    /// `NotFiniteError`, `BadConfigError` (soft limits not in order), and what the card
    /// refuses (`StopTooLongError`: the stop ramp from `max_velocity` does not fit the
    /// card's longest stop); nothing changes then.
    fn configure_safety(
        &self,
        p: Python<'_>,
        settings: crate::safety::SafetySettings,
    ) -> PyResult<()> {
        py(p.allow_threads(|| self.axis.configure_safety(&settings.s)))
    }

    /// Why the axis's last motion ended (`motioncard.StopReason`).
    fn stop_reason<'py>(&self, p: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        crate::safety::stop_reason(p, &self.axis)
    }

    /// The stop reason and the card's timing of the axis's last safety stop.
    fn stop_info(&self) -> PyResult<crate::safety::StopInfo> {
        Ok(py(self.axis.stop_info())?.into())
    }

    fn __repr__(&self) -> String {
        format!("<motioncard.Axis {}>", self.axis.index())
    }
}

/// A motion in progress. Wait for it with `wait(timeout)`, or `await` it.
#[pyclass(module = "motioncard", frozen)]
pub struct Motion {
    pub(crate) motion: sdk::Motion,
    pub(crate) axis: usize,
}

#[pymethods]
impl Motion {
    /// The seq of the command that started it.
    #[getter]
    fn seq(&self) -> u32 {
        self.motion.seq()
    }

    /// The axis it moves.
    #[getter]
    fn axis(&self) -> usize {
        self.axis
    }

    /// Wait until the axis is in position and return the actual position; `AbortedError`
    /// when something ended it first, `TimeoutError` after `timeout` seconds (None: no
    /// end; emulated time on a stepped card). Ctrl-C ends the wait.
    #[pyo3(signature = (timeout = None))]
    fn wait(&self, p: Python<'_>, timeout: Option<f64>) -> PyResult<f64> {
        wait_sliced(p, timeout, |s| self.motion.wait(s))
    }

    /// Wait until a buffered move starts (PLCopen Active); its target.
    #[pyo3(signature = (timeout = None))]
    fn wait_active(&self, p: Python<'_>, timeout: Option<f64>) -> PyResult<f64> {
        wait_sliced(p, timeout, |s| self.motion.wait_active(s))
    }

    /// Wait until a gear or cam motion is in gear (in sync); the slave's commanded position
    /// then.
    #[pyo3(signature = (timeout = None))]
    fn wait_in_sync(&self, p: Python<'_>, timeout: Option<f64>) -> PyResult<f64> {
        wait_sliced(p, timeout, |s| self.motion.wait_in_sync(s))
    }

    /// Wait until the table switch of `Axis.cam_switch` took place; the slave's commanded
    /// position then.
    #[pyo3(signature = (timeout = None))]
    fn wait_cam_switch(&self, p: Python<'_>, timeout: Option<f64>) -> PyResult<f64> {
        wait_sliced(p, timeout, |s| self.motion.wait_cam_switch(s))
    }

    /// Wait until a velocity move runs at its velocity; returns it.
    #[pyo3(signature = (timeout = None))]
    fn wait_in_velocity(&self, p: Python<'_>, timeout: Option<f64>) -> PyResult<f64> {
        wait_sliced(p, timeout, |s| self.motion.wait_in_velocity(s))
    }

    /// `await motion`: `motioncard.wait_async(motion)`.
    fn __await__<'py>(slf: Bound<'py, Self>) -> PyResult<Bound<'py, PyAny>> {
        let p = slf.py();
        p.import("motioncard")?
            .getattr("wait_async")?
            .call1((slf,))?
            .call_method0("__await__")
    }

    fn __repr__(&self) -> String {
        format!(
            "<motioncard.Motion axis {} seq {}>",
            self.axis,
            self.motion.seq()
        )
    }
}

/// An axis's status, in user units.
#[pyclass(module = "motioncard", frozen)]
pub struct Status {
    state_raw: u32,
    /// Actual position.
    #[pyo3(get)]
    position: f64,
    /// Actual velocity.
    #[pyo3(get)]
    velocity: f64,
    /// Following error (commanded − actual).
    #[pyo3(get)]
    following_error: f64,
    /// Commanded position.
    #[pyo3(get)]
    command_position: f64,
    /// The motor's reference, the commanded position plus the compensation's correction
    /// (`Axis.set_compensation`); the commanded position without one.
    #[pyo3(get)]
    compensated_position: f64,
    /// Commanded velocity.
    #[pyo3(get)]
    command_velocity: f64,
    /// Commanded acceleration.
    #[pyo3(get)]
    command_acceleration: f64,
    /// DAC output, volts.
    #[pyo3(get)]
    dac_volts: f64,
    /// Fault bits (`MC_FAULT_*`).
    #[pyo3(get)]
    faults: u32,
    /// Buffered moves waiting in the axis's queue.
    #[pyo3(get)]
    queued: u32,
    /// The velocity override in force.
    #[pyo3(get)]
    override_factor: f64,
    /// The servo tick of the snapshot.
    #[pyo3(get)]
    tick: u64,
    /// The current or last move's statistics, in counts as the card keeps them: its
    /// largest |commanded velocity|, counts/s.
    #[pyo3(get)]
    peak_velocity: f64,
    /// Largest commanded acceleration in the direction of motion, counts/s².
    #[pyo3(get)]
    peak_acceleration: f64,
    /// Largest commanded deceleration, counts/s².
    #[pyo3(get)]
    peak_deceleration: f64,
    /// Largest |commanded jerk|, counts/s³.
    #[pyo3(get)]
    peak_jerk: f64,
    /// Largest |following error|, counts.
    #[pyo3(get)]
    max_following_error: f64,
    /// The planned profile's duration, s.
    #[pyo3(get)]
    planned_time: f64,
    /// From start to motion done (in position), s; 0 while moving.
    #[pyo3(get)]
    move_time: f64,
    /// Moves started since boot.
    #[pyo3(get)]
    move_count: u32,
    /// The raw encoder count.
    #[pyo3(get)]
    encoder: i64,
    /// Has the position been set by homing or `set_position`?
    #[pyo3(get)]
    homed: bool,
    /// A gear or cam motion is in gear (in sync).
    #[pyo3(get)]
    in_sync: bool,
    stop_reason_raw: u32,
}

impl From<sdk::Status> for Status {
    fn from(s: sdk::Status) -> Self {
        Status {
            state_raw: s.state as u32,
            position: s.actual_position,
            compensated_position: s.compensated_position,
            velocity: s.actual_velocity,
            following_error: s.following_error,
            command_position: s.command_position,
            command_velocity: s.command_velocity,
            command_acceleration: s.command_acceleration,
            dac_volts: s.dac_volts,
            faults: s.faults.bits(),
            queued: s.queued,
            override_factor: s.override_factor,
            tick: s.raw.tick,
            peak_velocity: s.raw.peak_vel,
            peak_acceleration: s.raw.peak_acc,
            peak_deceleration: s.raw.peak_dec,
            peak_jerk: s.raw.peak_jerk,
            max_following_error: s.raw.max_ferr,
            planned_time: s.raw.planned_time,
            move_time: s.raw.move_time,
            move_count: s.raw.move_count,
            encoder: s.raw.encoder,
            homed: s.homed(),
            in_sync: s.in_sync(),
            stop_reason_raw: s.raw.stop_reason,
        }
    }
}

#[pymethods]
impl Status {
    /// The PLCopen state (`motioncard.AxisState`).
    #[getter]
    fn state<'py>(&self, p: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        py_enum(p, "AxisState", self.state_raw as i64)
    }

    /// Why the axis's last motion ended (`motioncard.StopReason`; `StopReason.NONE` while
    /// one runs).
    #[getter]
    fn stop_reason<'py>(&self, p: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        py_enum(p, "StopReason", self.stop_reason_raw as i64)
    }

    fn __repr__(&self, p: Python<'_>) -> PyResult<String> {
        Ok(format!(
            "Status({}, position={}, velocity={}, following_error={})",
            self.state(p)?.getattr("name")?,
            self.position,
            self.velocity,
            self.following_error
        ))
    }
}

/// The master of a gear or cam.
const FILTER_KINDS: [(&str, sdk::FilterKind); 4] = [
    ("none", sdk::FilterKind::None),
    ("linear", sdk::FilterKind::Linear),
    ("exponential", sdk::FilterKind::Exponential),
    ("bell", sdk::FilterKind::Bell),
];

fn filter_kind(name: &str) -> PyResult<sdk::FilterKind> {
    FILTER_KINDS
        .iter()
        .find(|(n, _)| *n == name)
        .map(|(_, k)| *k)
        .ok_or_else(|| {
            pyo3::exceptions::PyValueError::new_err(format!(
                "filter {name:?}: \"none\", \"linear\", \"exponential\" or \"bell\""
            ))
        })
}

fn filter_name(kind: sdk::FilterKind) -> &'static str {
    FILTER_KINDS
        .iter()
        .find(|(_, k)| *k == kind)
        .map_or("?", |(n, _)| *n)
}

fn master_of(source: &str, index: usize) -> PyResult<sdk::Master> {
    Ok(match source {
        "commanded" => sdk::Master::Commanded(index),
        "actual" => sdk::Master::Actual(index),
        "actual_lead" => sdk::Master::ActualLead(index),
        "aux" => sdk::Master::Aux(index),
        other => {
            return Err(pyo3::exceptions::PyValueError::new_err(format!(
                "source {other:?}: \"commanded\", \"actual\", \"actual_lead\" or \"aux\""
            )))
        }
    })
}
