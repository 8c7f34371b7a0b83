//! `Card`, its identity, the stepped emulator's control, events and safety.
use crate::errors::py;
use crate::group::Group;
use crate::motion::Axis;
use crate::names::py_enum;
use crate::scope::Scope;
use crate::wait::wait_sliced;
use motioncard_sdk as sdk;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use std::time::Duration;

/// A motion card, opened by URI. A context manager: leaving the `with` block closes it.
#[pyclass(module = "motioncard", frozen)]
pub struct Card {
    pub(crate) card: sdk::Card,
    pub(crate) uri: String,
}

use crate::safety::{seconds, stop_category};

/// The options of an emulated card (or set of them) in this process.
pub(crate) fn sim_options(
    clock: &str,
    axes: usize,
    servo_rate_hz: u32,
) -> PyResult<sdk::SimOptions> {
    let clock = match clock {
        "stepped" => sdk::Clock::Stepped,
        "realtime" => sdk::Clock::RealTime,
        "free" => sdk::Clock::FreeRunning,
        other => {
            return Err(PyValueError::new_err(format!(
                "clock {other:?}: expected \"stepped\", \"realtime\" or \"free\""
            )))
        }
    };
    Ok(sdk::SimOptions {
        clock,
        emu: sdk::EmuOptions::new(axes, servo_rate_hz),
    })
}

#[pymethods]
impl Card {
    /// Open a card: `sim` (an emulated card in this process, real-time clock), `emu:NAME`,
    /// `uio:/dev/uioN`, `pci:DDDD:BB:DD.F`, `name:NAME` or `serial:N`. `trace`: a file to
    /// record the card's API trace to (every command sent, configuration block written and
    /// event taken, flushed line by line; `motioncard.replay` runs it again), as the
    /// environment variable `MOTIONCARD_TRACE` does for every card a program opens.
    #[staticmethod]
    #[pyo3(signature = (uri, *, trace = None))]
    fn open(p: Python<'_>, uri: &str, trace: Option<std::path::PathBuf>) -> PyResult<Card> {
        let card = p.allow_threads(|| match &trace {
            Some(t) => sdk::Card::open_traced(uri, t),
            None => sdk::Card::open(uri),
        });
        Ok(Card {
            card: py(card)?,
            uri: uri.to_string(),
        })
    }

    /// Open an emulated card in this process. `clock`: `"stepped"` (time advances only when
    /// `card.sim.step(n)` is called or a call waits: deterministic), `"realtime"` or `"free"`
    /// (as fast as it can run). `trace`: a file for its API trace, as `Card.open`'s.
    #[staticmethod]
    #[pyo3(signature = (clock = "stepped", axes = 8, servo_rate_hz = 10_000, *, trace = None))]
    fn open_sim(
        p: Python<'_>,
        clock: &str,
        axes: usize,
        servo_rate_hz: u32,
        trace: Option<std::path::PathBuf>,
    ) -> PyResult<Card> {
        let opts = sim_options(clock, axes, servo_rate_hz)?;
        let card = p.allow_threads(|| match &trace {
            Some(t) => sdk::Card::open_sim_traced(opts, t),
            None => sdk::Card::open_sim(opts),
        });
        Ok(Card {
            card: py(card)?,
            uri: "sim".into(),
        })
    }

    /// Every card reachable from this process (`emu:` cards first, then UIO, then PCI),
    /// those held by a host too: a `CardListing` each. A card that could not be read is
    /// listed with its `error`.
    #[staticmethod]
    fn list(p: Python<'_>) -> PyResult<Vec<CardListing>> {
        let cards = py(p.allow_threads(sdk::Card::list))?;
        Ok(cards.into_iter().map(CardListing::from).collect())
    }

    /// The URI it was opened with.
    #[getter]
    fn uri(&self) -> &str {
        &self.uri
    }

    /// What the card says about itself.
    #[getter]
    fn info(&self) -> CardInfo {
        let i = self.card.info();
        CardInfo {
            firmware_version: i.firmware_version,
            layout: i.layout,
            axes: i.axes,
            servo_rate_hz: i.servo_rate_hz,
        }
    }

    /// The servo tick counter.
    fn tick(&self) -> PyResult<u64> {
        py(self.card.tick())
    }

    /// `with card.timed(tick) as t:` every command this thread sends in the block (to this
    /// card or another) is timed to `tick`: held by its card and run as the first thing of
    /// that tick (see `TimedScope`). `key` (1 to 2^32 - 1): they run only once it is
    /// committed, which leaving the block does (`sync_commit`); 0: each runs on the tick as
    /// it was held.
    #[pyo3(signature = (tick, *, key = 0))]
    fn timed(&self, tick: u64, key: u32) -> crate::timed::TimedScope {
        crate::timed::TimedScope::begin(&self.card, tick, key)
    }

    /// Commit `key` for `tick`: its timed commands run on that tick, on this card and on
    /// every follower of its bus. Only on a master or a card alone (`NotMasterError`), and
    /// before the tick (`CommitLateError`: then none of them runs, anywhere).
    fn sync_commit(&self, p: Python<'_>, key: u32, tick: u64) -> PyResult<()> {
        py(p.allow_threads(|| self.card.sync_commit(key, tick)))
    }

    /// Drop the held timed commands of `key` (0: all): how many there were. Each is refused
    /// with `TimedCancelledError`.
    #[pyo3(signature = (key = 0))]
    fn cancel_timed(&self, p: Python<'_>, key: u32) -> PyResult<u32> {
        py(p.allow_threads(|| self.card.cancel_timed(key)))
    }

    /// Axis `index` (`BadAxisError` beyond the card's axes).
    fn axis(&self, index: usize) -> PyResult<Axis> {
        Ok(Axis {
            axis: py(self.card.axis(index))?,
            card: self.card.clone(),
        })
    }

    /// Every axis of the card.
    fn axes(&self) -> Vec<Axis> {
        self.card
            .axes()
            .into_iter()
            .map(|axis| Axis {
                axis,
                card: self.card.clone(),
            })
            .collect()
    }

    /// Axes group `index` (`BadGroupError` beyond the card's groups).
    fn group(&self, index: usize) -> PyResult<Group> {
        Ok(Group {
            group: py(self.card.group(index))?,
        })
    }

    /// Form a gantry: `slaves` (1 to 4 axes, each with the master's scale) follow `master`,
    /// coupled where they stand; a yaw loop (`kp` 1/s², `ki` 1/s³) corrects each slave's
    /// skew, and a skew beyond `skew_limit` (user units) stops them all. `offsets`: each
    /// slave's square offset for `Gantry.home()`. `index`: the gantry slot (None: the first
    /// free one). `GantryAxesError`, `GantryGainsError`, `GantryInUseError`,
    /// `GantryStateError`.
    #[pyo3(signature = (master, slaves, *, skew_limit, kp = 1e6, ki = 0.0, offsets = None, index = None))]
    #[allow(clippy::too_many_arguments)]
    fn gantry(
        &self,
        p: Python<'_>,
        master: usize,
        slaves: Vec<usize>,
        skew_limit: f64,
        kp: f64,
        ki: f64,
        offsets: Option<Vec<f64>>,
        index: Option<usize>,
    ) -> PyResult<crate::machine::Gantry> {
        let cfg = sdk::GantryConfig {
            kp,
            ki,
            skew_limit,
            offsets: offsets.unwrap_or_default(),
        };
        let g = p.allow_threads(|| match index {
            Some(i) => self.card.gantry_at(i, master, &slaves, &cfg),
            None => self.card.gantry(master, &slaves, &cfg),
        });
        Ok(crate::machine::Gantry {
            gantry: py(g)?,
            card: self.card.clone(),
        })
    }

    /// Gantry `index` as it is on the card (formed here, by another host or a configuration
    /// file); `GantryStateError` if it is not formed.
    fn gantry_handle(&self, index: usize) -> PyResult<crate::machine::Gantry> {
        Ok(crate::machine::Gantry {
            gantry: py(self.card.gantry_handle(index))?,
            card: self.card.clone(),
        })
    }

    /// Every formed gantry's status, in gantry order.
    fn gantries(&self, p: Python<'_>) -> PyResult<Vec<crate::machine::GantryStatus>> {
        self.card
            .gantries()
            .into_iter()
            .map(|s| crate::machine::gantry_status(p, s))
            .collect()
    }

    /// The stepping control of a stepped emulated card (`Card.open_sim()`), else None.
    #[getter]
    fn sim(&self) -> Option<Sim> {
        self.card.sim().map(|sim| Sim { sim })
    }

    /// The card's scope.
    #[getter]
    fn scope(&self) -> Scope {
        Scope::new(&self.card)
    }

    /// A command that does nothing but come back: the round trip through the card.
    fn ping(&self, p: Python<'_>) -> PyResult<()> {
        py(p.allow_threads(|| self.card.ping()))
    }

    /// Close the card: moving axes halt, waits in progress end with `ClosedError`, and so
    /// does every later call. Closing twice is harmless.
    fn close(&self, p: Python<'_>) -> PyResult<()> {
        py(p.allow_threads(|| self.card.close()))
    }

    fn __enter__(slf: Py<Self>) -> Py<Self> {
        slf
    }

    #[pyo3(signature = (*_args))]
    fn __exit__(&self, p: Python<'_>, _args: &Bound<'_, pyo3::types::PyTuple>) -> PyResult<bool> {
        self.close(p)?;
        Ok(false)
    }

    /// End every wait in progress on this card, in any thread, with `CancelledError`.
    fn cancel_waits(&self) {
        self.card.cancel_waits()
    }

    /// The next event from the card, waiting up to `timeout` seconds (0: don't wait; None:
    /// until one comes); None when none came in time.
    #[pyo3(signature = (timeout = 0.0))]
    fn next_event(&self, p: Python<'_>, timeout: Option<f64>) -> PyResult<Option<Event>> {
        next_event(p, &self.card, timeout)
    }

    /// The card's events as an iterator: each waits up to `timeout` seconds for the next
    /// one (None: forever); the iteration ends when none comes in time.
    #[pyo3(signature = (timeout = 1.0))]
    fn events(&self, timeout: Option<f64>) -> Events {
        Events {
            card: self.card.clone(),
            timeout,
        }
    }

    /// Events dropped because nobody took them, and events the card could not post.
    fn events_lost(&self) -> (u64, u32) {
        self.card.events_lost()
    }

    /// The debounced digital inputs, one bit each.
    fn inputs(&self) -> PyResult<u32> {
        py(self.card.inputs())
    }

    /// The digital outputs, one bit each.
    fn outputs(&self) -> PyResult<u32> {
        py(self.card.outputs())
    }

    /// Set the outputs whose bits are set in `mask` to those of `value`.
    fn set_outputs(&self, p: Python<'_>, mask: u32, value: u32) -> PyResult<()> {
        py(p.allow_threads(|| self.card.set_outputs(mask, value)))
    }

    /// Set output `output` high or low.
    fn set_output(&self, p: Python<'_>, output: u32, high: bool) -> PyResult<()> {
        if output >= 32 {
            return Err(PyValueError::new_err(format!("output {output}: 0 to 31")));
        }
        let bit = 1u32 << output;
        self.set_outputs(p, bit, if high { bit } else { 0 })
    }

    /// Configure the digital inputs (those not given stay): `polarity` (bit i: input i is
    /// active low), `rise_events` / `fall_events` (bit i: an `EventKind.INPUT` event on that
    /// debounced edge of input i), `debounce` (ticks each input must hold a new level, one
    /// per input).
    #[pyo3(signature = (*, polarity = None, rise_events = None, fall_events = None, debounce = None))]
    fn configure_io(
        &self,
        p: Python<'_>,
        polarity: Option<u32>,
        rise_events: Option<u32>,
        fall_events: Option<u32>,
        debounce: Option<Vec<u16>>,
    ) -> PyResult<()> {
        let mut s = py(self.card.io_settings())?;
        if let Some(v) = polarity {
            s.polarity = v;
        }
        if let Some(v) = rise_events {
            s.rise_events = v;
        }
        if let Some(v) = fall_events {
            s.fall_events = v;
        }
        if let Some(d) = debounce {
            if d.len() != s.debounce.len() {
                return Err(PyValueError::new_err(format!(
                    "debounce: {} values, one per input ({})",
                    d.len(),
                    s.debounce.len()
                )));
            }
            s.debounce.copy_from_slice(&d);
        }
        py(p.allow_threads(|| self.card.configure_io(&s)))
    }

    /// Analog input `input`: its filtered value, volts.
    fn analog_input(&self, input: usize) -> PyResult<f64> {
        py(self.card.analog_input(input)).map(|a| a.value)
    }

    /// Analog input `input` as the card sampled it at its last tick: the ADC's sample, the
    /// filtered value, above the threshold or not, and the settings the card holds.
    fn analog_input_status(&self, input: usize) -> PyResult<crate::io::AnalogInput> {
        Ok(crate::io::AnalogInput::from(py(self
            .card
            .analog_input(input))?))
    }

    /// Set analog input `input`'s first-order filter (`cutoff_hz`, 0: none; at most half the
    /// servo rate) and its threshold with hysteresis (volts): the input goes above at
    /// `value >= threshold` and below again at `value <= threshold - hysteresis`, posting
    /// `EventKind.ANALOG` (axis: the input; code 1 above, 0 below; value: the filtered volts)
    /// when `rise_event` / `fall_event` ask for it. The filter keeps its value; the state is
    /// taken again from it, without an event. Refused: `AnalogChannelError`,
    /// `AnalogFilterError`, `AnalogThresholdError`, `NotFiniteError` (nothing changes).
    #[pyo3(signature = (input, *, cutoff_hz = 0.0, threshold = 0.0, hysteresis = 0.0, rise_event = false, fall_event = false))]
    #[allow(clippy::too_many_arguments)]
    fn configure_analog_input(
        &self,
        p: Python<'_>,
        input: usize,
        cutoff_hz: f64,
        threshold: f64,
        hysteresis: f64,
        rise_event: bool,
        fall_event: bool,
    ) -> PyResult<()> {
        let s = sdk::AnalogInputSettings {
            cutoff_hz,
            threshold,
            hysteresis,
            rise_event,
            fall_event,
        };
        py(p.allow_threads(|| self.card.configure_analog_input(input, &s)))
    }

    /// Set analog output `output` to `volts`; the volts it outputs (clamped to its range).
    fn set_analog_output(&self, p: Python<'_>, output: usize, volts: f64) -> PyResult<f64> {
        py(p.allow_threads(|| self.card.set_analog_output(output, volts)))
    }

    /// Stop the path-speed output (`Group.pso`): its output goes to 0.
    fn pso_off(&self, p: Python<'_>) -> PyResult<()> {
        py(p.allow_threads(|| self.card.pso_off()))
    }

    /// The path-speed output's state, speed and value of the last tick.
    fn pso_status(&self) -> PyResult<crate::machine::PsoStatus> {
        Ok(crate::machine::pso_status(py(self.card.pso_status())?))
    }

    /// Load cam table `table` with `points` (master, slave; counts; the master strictly
    /// increasing), `cubic` (else linear), `periodic`.
    #[pyo3(signature = (table, points, *, cubic = false, periodic = false))]
    fn load_cam_table(
        &self,
        p: Python<'_>,
        table: usize,
        points: Vec<(f64, f64)>,
        cubic: bool,
        periodic: bool,
    ) -> PyResult<()> {
        py(p.allow_threads(|| self.card.load_cam_table(table, &points, cubic, periodic)))
    }

    /// Stop every axis and group: an e-stop of `category` (0, 1 or 2), latched until
    /// `reset_faults()`.
    #[pyo3(signature = (category = 1))]
    fn estop(&self, p: Python<'_>, category: u32) -> PyResult<()> {
        let c = stop_category(category)?;
        py(p.allow_threads(|| self.card.estop(c)))
    }

    /// Clear the card's latched faults (watchdog, e-stop) and the axes' ErrorStop.
    fn reset_faults(&self, p: Python<'_>) -> PyResult<()> {
        py(p.allow_threads(|| self.card.reset_faults()))
    }

    /// The card's safety state.
    fn safety_status(&self) -> PyResult<SafetyStatus> {
        let s = py(self.card.safety_status())?;
        Ok(SafetyStatus {
            watchdog_tripped: s.watchdog_tripped,
            estop_command: s.estop_command,
            estop_input: s.estop_input,
            watchdog_armed: s.watchdog_armed,
            protocol_errors: s.protocol_errors,
            session: s.session,
        })
    }

    /// Arm the host watchdog with `timeout` seconds.
    fn set_watchdog_timeout(&self, p: Python<'_>, timeout: f64) -> PyResult<()> {
        let t = seconds("timeout", timeout)?;
        py(p.allow_threads(|| self.card.set_watchdog_timeout(t)))
    }

    /// The stop the card's e-stop input makes: `category` 0, 1 or 2 (default 1);
    /// `BadCategoryError` otherwise.
    fn set_estop_input_category(&self, p: Python<'_>, category: u32) -> PyResult<()> {
        let c = stop_category(category)?;
        py(p.allow_threads(|| self.card.set_estop_input_category(c)))
    }

    /// The card's longest stop, `seconds` (default 2 s): every stop (halt, stop, the safety
    /// stops, starvation) ends within it; a halt whose own ramp would take longer runs on
    /// the axis's stop ramp, and a stop still running at the bound loses power (reason
    /// `StopReason.STOP_TIMEOUT`). 10 ms to 600 s, and every axis's stop ramp from its
    /// `max_velocity` must fit: `StopTooLongError`.
    fn set_max_stop_time(&self, p: Python<'_>, seconds: f64) -> PyResult<()> {
        let t = crate::safety::seconds("max stop time", seconds)?;
        py(p.allow_threads(|| self.card.set_max_stop_time(t)))
    }

    /// The card-wide safety settings the card holds (watchdog timeout, the e-stop input's
    /// category, the longest stop time).
    fn safety_settings(&self, p: Python<'_>) -> PyResult<crate::safety::CardSafetySettings> {
        Ok(py(p.allow_threads(|| self.card.safety_settings()))?.into())
    }

    /// Change the servo rate (all axes disabled).
    fn set_servo_rate(&self, p: Python<'_>, hz: u32) -> PyResult<()> {
        py(p.allow_threads(|| self.card.set_servo_rate(hz)))
    }

    /// The card's whole configuration as the text of a configuration file (TOML).
    fn save_config(&self, p: Python<'_>) -> PyResult<String> {
        py(p.allow_threads(|| self.card.save_config()))
    }

    /// Apply a configuration file's text; `origin` names it in errors. Returns the sections
    /// applied (those that differed from the card).
    #[pyo3(signature = (text, origin = "<string>"))]
    fn load_config(&self, p: Python<'_>, text: &str, origin: &str) -> PyResult<Vec<String>> {
        let r = py(p.allow_threads(|| self.card.load_config(text, origin)))?;
        Ok(report_lines(&r))
    }

    /// Write the configuration file `path`.
    fn save_config_file(&self, p: Python<'_>, path: std::path::PathBuf) -> PyResult<()> {
        py(p.allow_threads(|| self.card.save_config_file(&path)))
    }

    /// Apply the configuration file `path`.
    fn load_config_file(&self, p: Python<'_>, path: std::path::PathBuf) -> PyResult<Vec<String>> {
        let r = py(p.allow_threads(|| self.card.load_config_file(&path)))?;
        Ok(report_lines(&r))
    }

    fn __repr__(&self) -> String {
        let i = self.card.info();
        format!("<motioncard.Card {} ({} axes)>", self.uri, i.axes)
    }
}

fn report_lines(r: &sdk::LoadReport) -> Vec<String> {
    r.applied.clone()
}

pub(crate) fn next_event(
    p: Python<'_>,
    card: &sdk::Card,
    timeout: Option<f64>,
) -> PyResult<Option<Event>> {
    if timeout == Some(0.0) {
        let e = py(card.next_event(Duration::ZERO))?;
        return Ok(e.map(Event::from));
    }
    let r = wait_sliced(p, timeout, |slice| match card.next_event(slice) {
        Ok(Some(e)) => Ok(e),
        Ok(None) => Err(sdk::Error::Timeout(slice)),
        Err(e) => Err(e),
    });
    match r {
        Ok(e) => Ok(Some(Event::from(e))),
        Err(e) if e.is_instance_of::<crate::errors::MotioncardError>(p) && is_timeout(p, &e) => {
            Ok(None)
        }
        Err(e) => Err(e),
    }
}

fn is_timeout(p: Python<'_>, e: &PyErr) -> bool {
    e.value(p)
        .getattr("kind")
        .and_then(|k| k.extract::<String>())
        .is_ok_and(|k| k == "Timeout")
}

/// What the card says about itself.
#[pyclass(module = "motioncard", frozen, get_all)]
pub struct CardInfo {
    /// Firmware version, `major << 16 | minor << 8 | patch`.
    firmware_version: u32,
    /// DPRAM layout (major, minor).
    layout: (u16, u16),
    /// Axes on the card.
    axes: usize,
    /// Servo rate, Hz.
    servo_rate_hz: u32,
}

#[pymethods]
impl CardInfo {
    fn __repr__(&self) -> String {
        format!(
            "CardInfo(firmware_version={:#x}, layout={:?}, axes={}, servo_rate_hz={})",
            self.firmware_version, self.layout, self.axes, self.servo_rate_hz
        )
    }
}

/// One card found by `Card.list()`.
#[pyclass(module = "motioncard", frozen, get_all)]
pub struct CardListing {
    /// The URI that opens it (`emu:NAME`, `uio:/dev/uioN`, `pci:DDDD:BB:DD.F`).
    uri: String,
    /// Its name (`card-emu --name`, the board's EEPROM name).
    name: String,
    /// The board's serial number (0: none, or not read).
    serial: u64,
    /// Axes on the card (0: not read).
    axes: usize,
    /// Servo rate, Hz (0: not read).
    servo_rate_hz: u32,
    /// DPRAM layout (major, minor); (0, 0): not read.
    layout: (u16, u16),
    /// Firmware version, `major << 16 | minor << 8 | patch` (0: not read).
    firmware_version: u32,
    /// Its place on the sync bus: `"alone"`, `"master"` or `"follower"`.
    sync_role: &'static str,
    /// Its sync state: `"free"`, `"locked"` or `"lost"`.
    sync_state: &'static str,
    /// A follower's master's name (empty otherwise).
    master: String,
    /// No host holds it: `Card.open` would get it now.
    available: bool,
    /// This process has it open.
    open_here: bool,
    /// Why it could not be read (the ErrorKind's name), None when every field was read.
    error_kind: Option<String>,
    /// What happened, and what to do about it (None when every field was read).
    error: Option<String>,
}

impl From<sdk::CardListing> for CardListing {
    fn from(l: sdk::CardListing) -> Self {
        CardListing {
            uri: l.uri,
            name: l.name,
            serial: l.serial,
            axes: l.axes,
            servo_rate_hz: l.servo_rate_hz,
            layout: l.layout,
            firmware_version: l.firmware_version,
            sync_role: l.sync_role.as_str(),
            sync_state: l.sync_state.as_str(),
            master: l.master,
            available: l.available,
            open_here: l.open_here,
            error_kind: l.error.as_ref().map(|e| format!("{:?}", e.kind)),
            error: l.error.map(|e| e.message),
        }
    }
}

#[pymethods]
impl CardListing {
    fn __repr__(&self) -> String {
        format!(
            "CardListing(uri={:?}, name={:?}, serial={}, axes={}, sync_role={:?}, available={})",
            self.uri, self.name, self.serial, self.axes, self.sync_role, self.available
        )
    }
}

/// The card's safety state.
#[pyclass(module = "motioncard", frozen, get_all)]
pub struct SafetyStatus {
    watchdog_tripped: bool,
    estop_command: bool,
    estop_input: bool,
    watchdog_armed: bool,
    protocol_errors: u32,
    session: u32,
}

/// A compare pulse the emulator recorded (`Sim.record_fires`), in counts.
#[pyclass(module = "motioncard", frozen, get_all)]
pub struct FireRecord {
    /// The compare channel.
    channel: usize,
    /// The output pulsed.
    output: usize,
    /// The axis watched.
    axis: usize,
    /// The position programmed, counts (a place on the turn on a rotary axis).
    position: f64,
    /// The pulse's instant, emulated seconds since boot.
    time: f64,
    /// Where the shaft was at that instant, counts (unquantised, unwrapped).
    shaft: f64,
    /// The shaft's velocity then, counts/s.
    velocity: f64,
}

#[pymethods]
impl FireRecord {
    fn __repr__(&self) -> String {
        format!(
            "FireRecord(channel={}, output={}, position={}, time={}, shaft={})",
            self.channel, self.output, self.position, self.time, self.shaft
        )
    }
}

/// Stepping control of a stepped emulated card: time advances only when asked.
#[pyclass(module = "motioncard", frozen)]
pub struct Sim {
    sim: sdk::Sim,
}

#[pymethods]
impl Sim {
    /// Advance `n` servo periods.
    fn step(&self, p: Python<'_>, n: u64) -> PyResult<()> {
        // in chunks, so Ctrl-C ends a long run
        let mut left = n;
        while left > 0 {
            p.check_signals()?;
            let k = left.min(10_000);
            p.allow_threads(|| self.sim.step(k));
            left -= k;
        }
        Ok(())
    }

    /// Emulated time since boot, s.
    #[getter]
    fn time(&self) -> f64 {
        self.sim.time()
    }

    /// Turn auxiliary encoder `input` (a handwheel, a master encoder) by `counts` at once.
    fn jump_aux(&self, input: usize, counts: i64) -> PyResult<()> {
        py(self.sim.jump_aux(input, counts))
    }

    /// Turn auxiliary encoder `input` at `counts_per_s` from now on (0: stop it).
    fn set_aux_velocity(&self, input: usize, counts_per_s: f64) -> PyResult<()> {
        py(self.sim.set_aux_velocity(input, counts_per_s))
    }

    /// Drive analog input `input`'s pin at `volts` (the ADC quantises it to 16 bits and
    /// saturates it at ±10 V) from now on.
    fn set_analog_input(&self, input: usize, volts: f64) -> PyResult<()> {
        if input >= sdk::ANALOG_INPUTS {
            return Err(PyValueError::new_err(format!(
                "analog input {input}: the card has {}",
                sdk::ANALOG_INPUTS
            )));
        }
        self.sim
            .with_emulator(|e| e.analog().set(input, sdk::AnalogSource::Constant(volts)));
        Ok(())
    }

    /// Press (True) or release the card's e-stop input: it stops every axis with the
    /// category `Card.set_estop_input_category` set, latched until released and
    /// `Card.reset_faults()`.
    fn set_estop(&self, pressed: bool) {
        self.sim.with_emulator(|e| e.faults().set_estop(pressed));
    }

    /// Record the compare pulses from now on (`False`: stop), with where the shaft was at
    /// each one; `take_fires()` takes them.
    fn record_fires(&self, on: bool) {
        self.sim.record_fires(on);
    }

    /// The compare pulses recorded since the last call.
    fn take_fires(&self) -> Vec<FireRecord> {
        self.sim
            .take_fires()
            .into_iter()
            .map(|f| FireRecord {
                channel: f.channel,
                output: f.output,
                axis: f.axis,
                position: f.position,
                time: f.time,
                shaft: f.shaft,
                velocity: f.velocity,
            })
            .collect()
    }

    /// Drive digital input `input`'s pin high or low.
    fn set_input(&self, input: usize, high: bool) -> PyResult<()> {
        if input >= sdk::INPUTS {
            return Err(PyValueError::new_err(format!(
                "input {input}: the card has {}",
                sdk::INPUTS
            )));
        }
        self.sim.set_input(input, high);
        Ok(())
    }
}

/// An event from the card.
#[pyclass(module = "motioncard", frozen)]
pub struct Event {
    kind: u16,
    /// Axis (or group, channel, input: see the kind; 0xFFFF for card-wide events).
    #[pyo3(get)]
    axis: u16,
    /// Seq of the command it concerns.
    #[pyo3(get)]
    seq: u32,
    /// Kind-specific code.
    #[pyo3(get)]
    code: i32,
    /// Servo tick.
    #[pyo3(get)]
    tick: u64,
    /// Kind-specific value (positions in user units).
    #[pyo3(get)]
    value: f64,
}

impl From<sdk::CardEvent> for Event {
    fn from(e: sdk::CardEvent) -> Self {
        Event {
            kind: e.kind as u16,
            axis: e.axis,
            seq: e.seq,
            code: e.code,
            tick: e.tick,
            value: e.value,
        }
    }
}

#[pymethods]
impl Event {
    /// The kind (`motioncard.EventKind`).
    #[getter]
    fn kind<'py>(&self, p: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        py_enum(p, "EventKind", self.kind as i64)
    }

    fn __repr__(&self, p: Python<'_>) -> PyResult<String> {
        let k = self.kind(p)?.getattr("name")?.to_string();
        Ok(format!(
            "Event({k}, axis={}, seq={}, code={}, tick={}, value={})",
            self.axis, self.seq, self.code, self.tick, self.value
        ))
    }
}

/// The card's events: iterate; each waits up to the timeout for the next one, and the
/// iteration ends when none comes in time.
#[pyclass(module = "motioncard", frozen)]
pub struct Events {
    card: sdk::Card,
    timeout: Option<f64>,
}

#[pymethods]
impl Events {
    fn __iter__(slf: Py<Self>) -> Py<Self> {
        slf
    }

    fn __next__(&self, p: Python<'_>) -> PyResult<Option<Event>> {
        next_event(p, &self.card, self.timeout)
    }

    /// `async for ev in card.events(timeout)`: `motioncard.events_async(events)`.
    fn __aiter__<'py>(slf: Bound<'py, Self>) -> PyResult<Bound<'py, PyAny>> {
        let p = slf.py();
        let timeout = slf.get().timeout;
        p.import("motioncard")?
            .getattr("events_async")?
            .call1((slf, timeout))
    }

    /// The next event, waiting up to `timeout` seconds (as `Card.next_event`).
    #[pyo3(signature = (timeout = 0.0))]
    fn next_event(&self, p: Python<'_>, timeout: Option<f64>) -> PyResult<Option<Event>> {
        next_event(p, &self.card, timeout)
    }

    /// The wait for each event, s.
    #[getter]
    fn timeout(&self) -> Option<f64> {
        self.timeout
    }
}
