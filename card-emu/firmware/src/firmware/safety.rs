//! Safety: the host watchdog, hard and soft limits, following error, amplifier alarm and
//! encoder faults, e-stop, IEC 60204-1 stop categories, and the per-axis stop reason.
//!
//! The anchors:
//! - **Watchdog** (Mesa hostmot2): the host increments `host.heartbeat`; while a session is
//!   attached the watchdog is *armed* (the attach counts as the first heartbeat), and a heartbeat
//!   as old as the configured timeout (default 100 ms; 0 or under 1.5 × the host's declared
//!   period is refused) makes every powered axis do a category 1 stop. The fault latches: nothing
//!   moves again until the host sends `MC_OP_SAFETY_RESET` with its heartbeat alive, even if the
//!   heartbeat came back.
//! - **Following error** (LinuxCNC `control.c`): the limit is `FERROR · |v_cmd| / v_max`,
//!   never below `MIN_FERROR`, checked every servo tick on every powered axis; a trip is a
//!   category 0 stop into ErrorStop.
//! - **ErrorStop** (PLCopen): every safety stop ends in ErrorStop, left only by MC_Reset, which
//!   is refused while the cause is present.
//! - **Stop categories** (IEC 60204-1): 0 removes power now; 1 decelerates along a jerk-limited
//!   ramp (`stop_decel`, `stop_jerk` of the axis, planned by `Profile::stop`), then removes
//!   power once at rest; 2 decelerates the same way and keeps power, holding position.
//! - **Bounded stops**: every stop (halt, stop, the safety stops, starvation, group halts and
//!   stops) ends within the card-wide maximum stop time (default 2 s). A halt whose own ramp
//!   would take longer runs on the axis's stop ramp instead (the harder of the two); a stop
//!   still running at the bound loses power there (category 0, reason `StopTimeout`). Each
//!   axis's stop ramp from its `max_velocity` must fit in the bound (else `StopTooLong`).
//! - **Host sessions**: a host attaches before its first heartbeat and detaches when it closes
//!   the card. An attach that finds another session open (its host died or hung) stops every
//!   enabled axis, category 1, reason `HostChanged`: a new host never inherits motion it did not
//!   start. The attach arms the watchdog at once; a detach halts what moves along the stop ramps
//!   and disarms the watchdog, no fault. So "in command" (a session attached, its watchdog
//!   armed) holds from an attach to its detach.
//! - **The session gate** ([`allowed_without_session`], [`Safety::in_command`]): with nobody in
//!   command the card refuses (`NoSession`) every command that could start motion, give power,
//!   or change an output, a configuration or a latch; an allowlist names the few that stop,
//!   read, observe or stage data, so an opcode added later is refused by default. And a
//!   backstop ([`Safety::stop_unattended`], every tick): an axis still driven towards a goal of
//!   its own, or by a coupling, stream or group, with nobody in command is stopped (category 1,
//!   `NoSession`): nothing moves without a watchdog.
//! - **Homing** (CiA 402, `homing.rs`): a homing method that has limit switches in its
//!   definition watches them itself (it reverses there, or fails), so while the axis homes the
//!   limit switches it names ([`Axis::homing_limits`]) do not trip it; any other limit still
//!   does. Soft limits hold only once the axis is homed ([`Axis::homed`]): before that its
//!   positions mean nothing. An encoder fault makes the axis not homed.
//!
//! Hooks elsewhere, each marked `[safety]`: one call per servo tick
//! ([`Safety::tick`], from `Firmware::tick`), one check per command
//! ([`Safety::check_command`], from `Firmware::execute`), the safety opcodes
//! ([`Safety::command`]), the ring-corruption report ([`Safety::protocol_error`]), and in
//! `axis/` the ErrorStop power flag, MC_Reset and the starvation stop at the end of a profile
//! that ends moving ([`starvation_stop`](super::axis_safety::starvation_stop)).
//!
//! Like the rest of the firmware: no allocation, no panic, no clock; time is the tick count.

use crate::firmware::axis::{Axis, MoveKind};
use crate::firmware::axis_safety::{ActiveStop, AxisSafetyConfig, LIVE_FAULTS};
use crate::firmware::outbox::SafetyEvents;
use crate::motion::scurve::plan_stop;
use crate::motion::scurve::Profile;
use firmware_proto::cmd::{self, AxisCmd, CardCmd};
use firmware_proto::layout::{self, safety_status as ss};
use firmware_proto::{
    raw, AxisSafetyFlags, AxisState, CardFaults, Event, EventKind, Faults, Io, Mem, NackCode,
    Opcode, StopCategory, StopReason, MAX_AXES,
};

/// Axis number of card-wide events.
pub const CARD_WIDE: u16 = 0xFFFF;

/// Default watchdog timeout, µs: above the heartbeat gaps of an ordinary loaded Linux host
/// (p99.99 15.5 ms, longest 32 ms over 60 s at normal priority with 2 spinning threads per
/// core: `cargo bench -p motioncard-sdk --bench heartbeat`), as EtherCAT's sync-manager
/// watchdog default. Real-time hosts set a shorter one.
pub const WATCHDOG_TIMEOUT_DEFAULT_US: u32 = 100_000;

/// Default of the card-wide maximum stop time, µs.
pub const MAX_STOP_TIME_DEFAULT_US: u32 = 2_000_000;

/// The range of the maximum stop time, µs (10 ms to 10 minutes).
pub const MAX_STOP_TIME_RANGE_US: core::ops::RangeInclusive<u32> = 10_000..=600_000_000;

/// The card's inputs for one tick (the FPGA's input register), sampled from the plant by the
/// emulator: per axis `MC_IO_*` input bits and the index latch, and the card's e-stop input.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Inputs {
    /// Limit, home, amplifier-alarm and encoder-fault inputs of each axis.
    pub axis: [Io; MAX_AXES],
    /// The index latch of each axis's encoder interface.
    pub index: [IndexLatch; MAX_AXES],
    /// The e-stop input (active: stop).
    pub estop: bool,
}

/// An encoder interface's latch on the index (Z) channel, as the FPGA holds it: the raw
/// encoder count captured at the last index pulse, and how many pulses it has latched
/// (wrapping). A change of `latches` between two ticks is a pulse crossed in between, at
/// exactly `count`, however short it was.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct IndexLatch {
    /// The raw encoder count at the last index pulse.
    pub count: i64,
    /// Index pulses latched since power-up (wrapping).
    pub latches: u32,
}

/// The validated copy of the card-wide safety configuration.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SafetyConfig {
    /// Watchdog timeout, µs.
    pub watchdog_timeout_us: u32,
    /// The stop the e-stop input makes.
    pub estop_input_category: StopCategory,
    /// Every stop ends within this, µs, or loses power at it.
    pub max_stop_time_us: u32,
}

impl SafetyConfig {
    /// The maximum stop time, s.
    pub fn max_stop_time(&self) -> f64 {
        self.max_stop_time_us as f64 * 1e-6
    }

    /// The register block (`mc_safety_config`) that holds this configuration.
    pub fn to_block(&self) -> raw::mc_safety_config {
        raw::mc_safety_config {
            watchdog_timeout_us: self.watchdog_timeout_us,
            estop_input_category: self.estop_input_category as u32,
            max_stop_time_us: self.max_stop_time_us,
            ..Default::default()
        }
    }

    /// Check a `safety` block on its own, for a host whose heartbeat period is
    /// `host_period_us`: the watchdog timeout (0, or under 1.5 × the period:
    /// `WatchdogTimeout`), the e-stop input's category (`BadCategory`), the maximum stop time's
    /// range (`StopTooLong`). Whether every axis's stop ramp fits in it is checked on apply.
    pub fn validate(b: &raw::mc_safety_config, host_period_us: u32) -> Result<Self, NackCode> {
        let timeout = b.watchdog_timeout_us;
        // 0 is refused, and so is anything under 1.5 x the host's declared period.
        if timeout == 0 || 2 * (timeout as u64) < 3 * host_period_us as u64 {
            return Err(NackCode::WatchdogTimeout);
        }
        let category =
            StopCategory::from_raw(b.estop_input_category).ok_or(NackCode::BadCategory)?;
        if !MAX_STOP_TIME_RANGE_US.contains(&b.max_stop_time_us) {
            return Err(NackCode::StopTooLong);
        }
        Ok(Self {
            watchdog_timeout_us: timeout,
            estop_input_category: category,
            max_stop_time_us: b.max_stop_time_us,
        })
    }
}

impl Default for SafetyConfig {
    fn default() -> Self {
        Self {
            watchdog_timeout_us: WATCHDOG_TIMEOUT_DEFAULT_US,
            estop_input_category: StopCategory::Cat1,
            max_stop_time_us: MAX_STOP_TIME_DEFAULT_US,
        }
    }
}

fn event(kind: EventKind, axis: u16, code: i32, tick: u64, value: f64) -> Event {
    Event {
        seq: 0,
        kind: kind as u16,
        axis,
        code,
        tick,
        value,
    }
}

/// What tripped, and how hard to stop.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Trip {
    category: StopCategory,
    reason: StopReason,
    fault: Faults,
    value: f64,
}

/// The card-wide safety state: configuration, watchdog, latches, inputs.
#[derive(Debug, Clone)]
pub struct Safety {
    config: SafetyConfig,
    inputs: Inputs,
    armed: bool,
    last_heartbeat: u32,
    last_heartbeat_tick: u64,
    latched: CardFaults,
    evt_ring_bad: bool,
    protocol_errors: u32,
    session: u32,
    host_changes: u32,
    late_heartbeats: u32,
    max_heartbeat_gap_us: u32,
    /// Events waiting to be posted by the firmware.
    pub events: SafetyEvents,
}

impl Safety {
    /// The board's watchdog timeout at boot, µs, instead of [`WATCHDOG_TIMEOUT_DEFAULT_US`]
    /// (an emulated card set up for debugging a host under gdb or valgrind: the watchdog
    /// stays armed, with a longer timeout). Before the first tick; a host may change it as
    /// ever. `WatchdogTimeout` for 0.
    pub fn set_boot_watchdog_timeout<M: Mem>(&mut self, mem: &M, us: u32) -> Result<(), NackCode> {
        if us == 0 {
            return Err(NackCode::WatchdogTimeout);
        }
        self.config.watchdog_timeout_us = us;
        layout::SAFETY_CONFIG.write(mem, &self.config.to_block());
        Ok(())
    }

    /// Boot: write the default configuration blocks and a clean status into the window.
    pub fn boot<M: Mem>(mem: &M) -> Self {
        let config = SafetyConfig::default();
        layout::SAFETY_CONFIG.write(mem, &config.to_block());
        for a in 0..MAX_AXES {
            layout::AXIS_SAFETY
                .at(a)
                .write(mem, &AxisSafetyConfig::default().to_block());
        }
        let s = Self {
            config,
            inputs: Inputs::default(),
            armed: false,
            last_heartbeat: mem.read32(layout::HEARTBEAT),
            last_heartbeat_tick: 0,
            latched: CardFaults::empty(),
            evt_ring_bad: false,
            protocol_errors: 0,
            session: 0,
            host_changes: 0,
            late_heartbeats: 0,
            max_heartbeat_gap_us: 0,
            events: SafetyEvents::new(),
        };
        mem.write32(ss::FAULTS, 0);
        mem.write32(ss::WATCHDOG_ARMED, 0);
        mem.write64(ss::LAST_HEARTBEAT_TICK, 0);
        mem.write64(ss::WATCHDOG_TRIP_TICK, 0);
        mem.write64(ss::TRIP_HEARTBEAT_TICK, 0);
        mem.write32(ss::PROTOCOL_ERRORS, 0);
        for off in [
            ss::SESSION,
            ss::HOST_CHANGES,
            ss::LATE_HEARTBEATS,
            ss::MAX_HEARTBEAT_GAP_US,
        ] {
            mem.write32(off, 0);
        }
        mem.write64(ss::ATTACH_TICK, 0);
        for a in 0..MAX_AXES {
            mem.write64(ss::stop_tick(a), 0);
            mem.write64(ss::rest_tick(a), 0);
            mem.write_f64(ss::ramp_time(a), 0.0);
        }
        s
    }

    /// The active card-wide configuration.
    pub fn config(&self) -> &SafetyConfig {
        &self.config
    }

    /// Latched card-wide faults (`MC_CARD_FAULT_*`).
    pub fn latched(&self) -> CardFaults {
        self.latched
    }

    /// Is the watchdog armed (a session attached, from its attach to its detach)?
    pub fn watchdog_armed(&self) -> bool {
        self.armed
    }

    /// Is a host in command: a session attached, its watchdog armed? Only then does the card
    /// take a command [`allowed_without_session`] does not name, and only then may anything
    /// move.
    pub fn in_command(&self) -> bool {
        self.session != 0 && self.armed
    }

    /// The inputs of the coming tick (the emulator samples them from the plant).
    pub fn set_inputs(&mut self, inputs: Inputs) {
        self.inputs = inputs;
    }

    /// The inputs of this tick.
    pub fn inputs(&self) -> &Inputs {
        &self.inputs
    }

    /// The attached host's session id (0: none).
    pub fn session(&self) -> u32 {
        self.session
    }

    /// Track the heartbeat word: measure the gaps between beats while armed (late ones counted
    /// against the host's declared period). Beats never arm the watchdog: only an attach does.
    /// Returns the heartbeat's age in ticks.
    fn heartbeat<M: Mem>(&mut self, mem: &M, tick: u64, rate_hz: u32) -> u64 {
        let us = |ticks: u64| ticks_us(ticks, rate_hz);
        let hb = mem.read32(layout::HEARTBEAT);
        if hb != self.last_heartbeat {
            if self.armed {
                let gap = u32::try_from(us(tick.saturating_sub(self.last_heartbeat_tick)))
                    .unwrap_or(u32::MAX);
                if gap > mem.read32(layout::HOST_PERIOD_US) {
                    self.late_heartbeats = self.late_heartbeats.saturating_add(1);
                    mem.write32(ss::LATE_HEARTBEATS, self.late_heartbeats);
                }
                if gap > self.max_heartbeat_gap_us {
                    self.max_heartbeat_gap_us = gap;
                    mem.write32(ss::MAX_HEARTBEAT_GAP_US, gap);
                }
            }
            self.last_heartbeat = hb;
            self.last_heartbeat_tick = tick;
            mem.write64(ss::LAST_HEARTBEAT_TICK, tick);
        }
        tick.saturating_sub(self.last_heartbeat_tick)
    }

    /// Arm the watchdog: this tick counts as a heartbeat (an attach).
    fn arm<M: Mem>(&mut self, mem: &M, tick: u64) {
        self.armed = true;
        self.last_heartbeat = mem.read32(layout::HEARTBEAT);
        self.last_heartbeat_tick = tick;
        mem.write64(ss::LAST_HEARTBEAT_TICK, tick);
        mem.write32(ss::WATCHDOG_ARMED, 1);
    }

    /// Disarm the watchdog (a departing host): until the next attach nothing is watched, and
    /// nothing may move.
    fn disarm<M: Mem>(&mut self, mem: &M) {
        self.armed = false;
        self.last_heartbeat = mem.read32(layout::HEARTBEAT);
        mem.write32(ss::WATCHDOG_ARMED, 0);
    }

    /// `MC_OP_HOST_ATTACH`: a new session. Another session still open means its host vanished:
    /// every enabled axis stops (category 1, [`StopReason::HostChanged`]). The watchdog is
    /// armed at once: the attach is the new host's first heartbeat, so a host that attaches and
    /// then dies or hangs trips it after the timeout. Returns how many axes that stop reached.
    fn attach<M: Mem>(
        &mut self,
        mem: &M,
        session: u32,
        tick: u64,
        axes: &mut [Axis],
    ) -> Result<f64, NackCode> {
        if session == 0 {
            return Err(NackCode::BadConfig);
        }
        let mut stopped = 0.0;
        if self.session != 0 {
            self.host_changes = self.host_changes.wrapping_add(1);
            mem.write32(ss::HOST_CHANGES, self.host_changes);
            let before = axes
                .iter()
                .filter(|a| a.state == AxisState::ErrorStop)
                .count();
            let trip = Trip {
                category: StopCategory::Cat1,
                reason: StopReason::HostChanged,
                fault: Faults::empty(),
                value: self.session as f64,
            };
            self.trip_all(mem, tick, axes, trip);
            let after = axes
                .iter()
                .filter(|a| a.state == AxisState::ErrorStop)
                .count();
            stopped = after.saturating_sub(before) as f64;
        }
        self.session = session;
        mem.write32(ss::SESSION, session);
        mem.write64(ss::ATTACH_TICK, tick);
        self.late_heartbeats = 0;
        self.max_heartbeat_gap_us = 0;
        mem.write32(ss::LATE_HEARTBEATS, 0);
        mem.write32(ss::MAX_HEARTBEAT_GAP_US, 0);
        self.arm(mem, tick);
        Ok(stopped)
    }

    /// `MC_OP_HOST_DETACH`, the card-wide part (the firmware halts what moves): the session
    /// ends and the watchdog is disarmed, without a fault.
    pub(crate) fn detach<M: Mem>(&mut self, mem: &M, session: u32) -> Result<(), NackCode> {
        if self.session != 0 && session != self.session {
            return Err(NackCode::Session);
        }
        self.session = 0;
        mem.write32(ss::SESSION, 0);
        self.disarm(mem);
        Ok(())
    }

    fn latch<M: Mem>(&mut self, mem: &M, bit: CardFaults) {
        self.latched |= bit;
        mem.write32(ss::FAULTS, self.latched.bits());
    }

    /// The servo-tick hook, after every axis has run its tick: watchdog, e-stop input, encoder
    /// and amplifier faults, hard and soft limits, following error, and the progress of the
    /// stops. A category 0 stop zeroes the axis's output in `dac` this very tick.
    /// `evt_ring_ok`: the event ring's indices are consistent (else the card cannot talk to the
    /// host, and stops every axis).
    #[allow(clippy::too_many_arguments)]
    pub fn tick<M: Mem>(
        &mut self,
        mem: &M,
        tick: u64,
        rate_hz: u32,
        axes: &mut [Axis],
        encoders: &[i64; MAX_AXES],
        dac: &mut [f64; MAX_AXES],
        evt_ring_ok: bool,
    ) {
        let ts = 1.0 / rate_hz.max(1) as f64;
        // Host watchdog.
        let age = self.heartbeat(mem, tick, rate_hz);
        if self.armed
            && !self.latched.contains(CardFaults::WATCHDOG)
            && ticks_reach_us(age, rate_hz, self.config.watchdog_timeout_us)
        {
            let age_us = ticks_us(age, rate_hz);
            self.latch(mem, CardFaults::WATCHDOG);
            mem.write64(ss::WATCHDOG_TRIP_TICK, tick);
            mem.write64(ss::TRIP_HEARTBEAT_TICK, self.last_heartbeat_tick);
            let trip = Trip {
                category: StopCategory::Cat1,
                reason: StopReason::Watchdog,
                fault: Faults::WATCHDOG,
                value: age_us as f64 * 1e-6,
            };
            self.trip_all(mem, tick, axes, trip);
        }
        // E-stop input.
        if self.inputs.estop && !self.latched.contains(CardFaults::ESTOP_INPUT) {
            self.latch(mem, CardFaults::ESTOP_INPUT);
            let trip = Trip {
                category: self.config.estop_input_category,
                reason: StopReason::EStopInput,
                fault: Faults::ESTOP,
                value: 0.0,
            };
            self.trip_all(mem, tick, axes, trip);
        }
        // A card that cannot post events cannot tell the host anything: stop.
        if !evt_ring_ok && !self.evt_ring_bad {
            self.protocol_errors = self.protocol_errors.wrapping_add(1);
            mem.write32(ss::PROTOCOL_ERRORS, self.protocol_errors);
            let trip = Trip {
                category: StopCategory::Cat1,
                reason: StopReason::EvtRing,
                fault: Faults::PROTOCOL,
                value: 0.0,
            };
            self.trip_all(mem, tick, axes, trip);
        }
        self.evt_ring_bad = !evt_ring_ok;

        for (i, axis) in axes.iter_mut().enumerate() {
            let enc = encoders[i];
            let mut inputs = self.inputs.axis[i]
                & (Io::LIMIT_POS | Io::LIMIT_NEG | Io::HOME | Io::AMP_ALARM | Io::ENCODER_FAULT);
            if self.inputs.estop {
                inputs |= Io::ESTOP;
            }
            for trip in axis_trips(axis, inputs, enc, ts).into_iter().flatten() {
                self.trip_axis(mem, tick, i, axis, trip);
            }
            axis.safety.last_encoder = Some(enc);
            self.follow_stop(mem, tick, ts, i, axis);
            self.bound_stop(mem, tick, i, axis);
            if !axis.is_powered() {
                dac[i] = 0.0;
            }
            axis.safety.io = inputs
                | if axis.is_powered() {
                    Io::DRIVE_ENABLE
                } else {
                    Io::empty()
                };
        }
    }

    /// A safety stop in progress: category 1 disables the drive once at rest (or at the
    /// maximum stop time); every category reports reaching rest once.
    fn follow_stop<M: Mem>(&mut self, mem: &M, tick: u64, ts: f64, i: usize, axis: &mut Axis) {
        let Some(mut stop) = axis.safety.stop else {
            return;
        };
        if stop.at_rest {
            return;
        }
        let elapsed = tick.saturating_sub(stop.started) as f64 * ts;
        let still = axis.measured_velocity().abs() <= axis.config.in_vel_window;
        let ramp_done = !axis.profile_running();
        let rest = ramp_done && (still || elapsed + 1e-9 >= self.config.max_stop_time());
        if !rest {
            return;
        }
        if stop.category == StopCategory::Cat1 && axis.state == AxisState::ErrorStop {
            axis.remove_power();
        }
        stop.at_rest = true;
        axis.safety.stop = Some(stop);
        mem.write64(ss::rest_tick(i), tick);
        self.events.push(event(
            EventKind::AtRest,
            i as u16,
            axis.safety.stop_reason as i32,
            tick,
            elapsed,
        ));
    }

    /// Every stop ends within the maximum stop time: a stop whose ramp still runs at the bound
    /// loses power there (category 0). A safety stop keeps the reason that tripped it; a
    /// halt, stop or starvation stop becomes [`StopReason::StopTimeout`].
    fn bound_stop<M: Mem>(&mut self, mem: &M, tick: u64, i: usize, axis: &mut Axis) {
        let Some(elapsed) = axis.stop_elapsed() else {
            return;
        };
        let ended = match axis.state {
            AxisState::ErrorStop => {
                !axis.is_powered() || axis.safety.stop.is_none_or(|s| s.at_rest)
            }
            _ => !axis.profile_running(),
        };
        if ended {
            axis.end_stop_clock();
        } else if elapsed + 1e-9 >= self.config.max_stop_time() {
            self.stop_overran(mem, tick, i, axis, elapsed);
        }
    }

    /// A stop of axis `i` ran out of time (`elapsed` s): power off now.
    pub(crate) fn stop_overran<M: Mem>(
        &mut self,
        mem: &M,
        tick: u64,
        i: usize,
        axis: &mut Axis,
        elapsed: f64,
    ) {
        axis.end_stop_clock();
        if axis.state == AxisState::ErrorStop {
            axis.remove_power();
            if let Some(st) = &mut axis.safety.stop {
                st.category = StopCategory::Cat0;
            }
            self.events.push(event(
                EventKind::SafetyStop,
                i as u16,
                StopReason::StopTimeout as i32,
                tick,
                elapsed,
            ));
        } else {
            let trip = Trip {
                category: StopCategory::Cat0,
                reason: StopReason::StopTimeout,
                fault: Faults::STOP_TIMEOUT,
                value: elapsed,
            };
            self.trip_axis(mem, tick, i, axis, trip);
        }
    }

    fn trip_all<M: Mem>(&mut self, mem: &M, tick: u64, axes: &mut [Axis], trip: Trip) {
        self.events.push(event(
            EventKind::SafetyStop,
            CARD_WIDE,
            trip.reason as i32,
            tick,
            trip.value,
        ));
        for (i, axis) in axes.iter_mut().enumerate() {
            if axis.state != AxisState::Disabled {
                self.trip_axis(mem, tick, i, axis, trip);
            }
        }
    }

    /// Stop one axis. A disabled axis only goes to ErrorStop for a fault of its own (alarm,
    /// encoder). An axis already stopping only changes to a harsher category.
    fn trip_axis<M: Mem>(&mut self, mem: &M, tick: u64, i: usize, axis: &mut Axis, trip: Trip) {
        axis.safety.faults |= trip.fault;
        if trip.fault.contains(Faults::ENCODER) {
            // [homing] the count no longer says where the shaft is
            axis.lose_home();
        }
        let harsher = match axis.safety.stop {
            Some(s) if axis.state == AxisState::ErrorStop => {
                (trip.category as u32) < (s.category as u32) && axis.is_powered()
            }
            _ => true,
        };
        if !harsher {
            return;
        }
        if axis.state == AxisState::Disabled
            && !matches!(
                trip.reason,
                StopReason::AmpAlarm | StopReason::EncoderLoss | StopReason::EncoderJump
            )
        {
            return;
        }
        let axis_no = i as u16;
        for seq in axis.pending_motion().into_iter().chain(axis.drain_queue()) {
            self.events.push(Event {
                seq,
                ..event(
                    EventKind::MotionAborted,
                    axis_no,
                    trip.fault.bits() as i32,
                    tick,
                    0.0,
                )
            });
        }
        let r = axis.reference();
        let ramp = match trip.category {
            StopCategory::Cat0 => None,
            _ if !axis.is_powered() => None,
            _ => plan_stop(
                r.pos,
                r.vel,
                r.acc,
                axis.safety.config.stop_decel,
                axis.safety.config.stop_jerk,
            )
            .ok(),
        };
        // A ramp that cannot be planned (it cannot happen with a validated configuration)
        // falls back to category 0: removing power is always possible.
        let category = if ramp.is_none() {
            StopCategory::Cat0
        } else {
            trip.category
        };
        let ramp_time = ramp.map_or(0.0, |p: Profile| p.duration());
        let old = axis.enter_error_stop(ramp);
        axis.safety.stop_reason = trip.reason;
        axis.safety.stop = Some(ActiveStop {
            category,
            started: tick,
            ramp: ramp_time,
            at_rest: false,
        });
        mem.write64(ss::stop_tick(i), tick);
        mem.write64(ss::rest_tick(i), 0);
        mem.write_f64(ss::ramp_time(i), ramp_time);
        self.events.push(event(
            EventKind::SafetyStop,
            axis_no,
            trip.reason as i32,
            tick,
            trip.value,
        ));
        if let Some(old) = old {
            self.events.push(event(
                EventKind::StateChanged,
                axis_no,
                AxisState::ErrorStop as i32,
                tick,
                old as u32 as f64,
            ));
        }
    }

    /// A member of a moving group made a safety stop: the members still in synchronised
    /// motion make the same category of stop (the harshest among the members that tripped),
    /// with reason [`StopReason::Group`] and the first tripped axis as the event value, so a
    /// coordinated move never leaves healthy axes driving on or frozen on the spot. A category
    /// 0 stop zeroes their output in `dac` and their drive enable this very tick. The group
    /// itself goes to
    /// GroupErrorStop on its next tick.
    pub fn trip_group<M: Mem>(
        &mut self,
        mem: &M,
        tick: u64,
        axes: &mut [Axis],
        members: &[usize],
        dac: &mut [f64; MAX_AXES],
    ) {
        let mut first = None;
        let mut category = None::<StopCategory>;
        for &a in members {
            let Some(axis) = axes.get(a) else { continue };
            if let (AxisState::ErrorStop, Some(stop)) = (axis.state, axis.safety.stop) {
                first.get_or_insert(a);
                if category.is_none_or(|c| (stop.category as u32) < (c as u32)) {
                    category = Some(stop.category);
                }
            }
        }
        let (Some(first), Some(category)) = (first, category) else {
            return;
        };
        let trip = Trip {
            category,
            reason: StopReason::Group,
            fault: Faults::empty(),
            value: first as f64,
        };
        for &a in members {
            let Some(axis) = axes.get_mut(a) else {
                continue;
            };
            // (Homing and a halt of it: a group homing's members, layout 1.11)
            if matches!(
                axis.state,
                AxisState::SynchronizedMotion | AxisState::Homing | AxisState::DiscreteMotion
            ) {
                self.trip_axis(mem, tick, a, axis, trip);
                if !axis.is_powered() {
                    dac[a] = 0.0;
                    axis.safety.io.remove(Io::DRIVE_ENABLE);
                }
            }
        }
    }

    /// Layout 1.10: a gantry stops as one (`gantry.rs`). Every member of `members` that is
    /// not already in ErrorStop (nor Disabled) makes a `category` stop with `reason` (the skew
    /// limit: [`StopReason::GantrySkew`]; a member's own safety stop: [`StopReason::Gantry`]),
    /// `value` its event's measurement. A category 0 stop zeroes its output in `dac` now.
    #[allow(clippy::too_many_arguments)]
    pub fn trip_gantry<M: Mem>(
        &mut self,
        mem: &M,
        tick: u64,
        axes: &mut [Axis],
        members: &[usize],
        category: StopCategory,
        reason: StopReason,
        value: f64,
        dac: &mut [f64; MAX_AXES],
    ) {
        let trip = Trip {
            category,
            reason,
            fault: Faults::empty(),
            value,
        };
        for &a in members {
            let Some(axis) = axes.get_mut(a) else {
                continue;
            };
            if matches!(axis.state, AxisState::ErrorStop | AxisState::Disabled) {
                continue;
            }
            self.trip_axis(mem, tick, a, axis, trip);
            if !axis.is_powered() {
                dac[a] = 0.0;
                axis.safety.io.remove(Io::DRIVE_ENABLE);
            }
        }
    }

    /// The backstop of the session gate, once per servo tick before [`Safety::tick`]: with
    /// nobody in command ([`Safety::in_command`]), each axis `driven` still marks (moving
    /// towards a goal of its own, homing, or driven by a coupling, a stream or a moving group;
    /// not one already stopping) makes a category 1 stop, reason [`StopReason::NoSession`].
    /// Nothing in the firmware starts motion outside a session, so this finds nothing unless
    /// a path past the gate exists: then it is stopped on the tick it starts, not left running
    /// without a watchdog.
    pub fn stop_unattended<M: Mem>(
        &mut self,
        mem: &M,
        tick: u64,
        axes: &mut [Axis],
        driven: &[bool; MAX_AXES],
    ) {
        if self.in_command() {
            return;
        }
        let trip = Trip {
            category: StopCategory::Cat1,
            reason: StopReason::NoSession,
            fault: Faults::empty(),
            value: 0.0,
        };
        for (i, axis) in axes.iter_mut().enumerate() {
            if driven[i] && axis.state != AxisState::ErrorStop {
                self.trip_axis(mem, tick, i, axis, trip);
            }
        }
    }

    /// The host broke the command ring (its head is beyond anything it could have written):
    /// every powered axis makes a category 1 stop, and the host is told.
    pub fn protocol_error<M: Mem>(
        &mut self,
        mem: &M,
        tick: u64,
        axes: &mut [Axis],
        code: i32,
        index: u32,
    ) {
        self.protocol_errors = self.protocol_errors.wrapping_add(1);
        mem.write32(ss::PROTOCOL_ERRORS, self.protocol_errors);
        self.events.push(event(
            EventKind::ProtocolError,
            CARD_WIDE,
            code,
            tick,
            index as f64,
        ));
        let trip = Trip {
            category: StopCategory::Cat1,
            reason: StopReason::CmdRing,
            fault: Faults::PROTOCOL,
            value: index as f64,
        };
        self.trip_all(mem, tick, axes, trip);
    }

    /// The check every single-axis command (decoded: `cmd`) passes before it acts on axis
    /// `axis` (already validated): card-wide latches for power-on and reset, causes still
    /// present for reset, and limits for moves. Commands that move an axis to a target (this
    /// firmware's MC_MoveAbsolute, MC_MoveRelative and MC_MoveAdditive; a group or queued move
    /// for each of its axes) must pass [`check_target`] with the axis's start and target.
    pub fn check_command(&self, cmd: &AxisCmd, axis: &Axis) -> Result<(), NackCode> {
        let latch = || {
            if self.latched.contains(CardFaults::WATCHDOG) {
                Err(NackCode::WatchdogTripped)
            } else if self
                .latched
                .intersects(CardFaults::ESTOP_COMMAND | CardFaults::ESTOP_INPUT)
            {
                Err(NackCode::EStopActive)
            } else {
                Ok(())
            }
        };
        match cmd {
            AxisCmd::PowerOn => latch(),
            AxisCmd::Reset if axis.state == AxisState::ErrorStop => {
                latch()?;
                let s = &axis.safety;
                if s.stop.is_some_and(|st| !st.at_rest) {
                    return Err(NackCode::InvalidState);
                }
                let c = &s.config;
                if (c.has(AxisSafetyFlags::AMP_ALARM) && s.io.contains(Io::AMP_ALARM))
                    || (c.has(AxisSafetyFlags::ENCODER) && s.io.contains(Io::ENCODER_FAULT))
                {
                    return Err(NackCode::CauseActive);
                }
                Ok(())
            }
            // Layout 1.10: the handwheel moves only where the wheel turns it, within the soft
            // limits (handwheel.rs); a latched stop is named as for a jog.
            AxisCmd::Handwheel(_) if axis.state == AxisState::ErrorStop => latch(),
            AxisCmd::Move(..) | AxisCmd::MoveVelocity(_) | AxisCmd::Jog(_) => {
                // A move refused for a stop the card latched names the latch, not the state.
                if axis.state == AxisState::ErrorStop {
                    latch()?;
                }
                let (start, target) = match cmd {
                    AxisCmd::Move(kind, m) => {
                        let kind = MoveKind::from(*kind);
                        let start = if m.buffered {
                            axis.last_target()
                        } else {
                            axis.reference().pos
                        };
                        (start, axis.move_target(kind, m.position, m.buffered)?)
                    }
                    // Velocity mode: only the direction counts.
                    AxisCmd::MoveVelocity(cmd::VelocityMove { velocity: v, .. })
                    | AxisCmd::Jog(cmd::Jog { velocity: v }) => {
                        let start = axis.reference().pos;
                        let step = if *v > 0.0 {
                            1.0
                        } else if *v < 0.0 {
                            -1.0
                        } else {
                            0.0
                        };
                        (start, start + step)
                    }
                    _ => return Ok(()),
                };
                check_target(axis, start, target)
            }
            _ => Ok(()),
        }
    }

    /// The safety opcodes and the host attach (decoded: `cmd`; `axis`: the command's target).
    /// `None` for any other command; else the outcome, with the ack's value.
    pub fn command<M: Mem>(
        &mut self,
        mem: &M,
        cmd: &CardCmd,
        axis: u16,
        tick: u64,
        rate_hz: u32,
        axes: &mut [Axis],
    ) -> Option<Result<f64, NackCode>> {
        if let CardCmd::HostAttach(s) = cmd {
            return Some(self.attach(mem, s.id, tick, axes));
        }
        Some(
            match cmd {
                CardCmd::ApplySafetyConfig => self.apply_config(mem, axes),
                CardCmd::ApplyAxisSafety => match axes.get_mut(axis as usize) {
                    None => Err(NackCode::BadAxis),
                    Some(ax) => read_axis_safety(mem, axis as usize).and_then(|cfg| {
                        cfg.validate_on_card(rate_hz, self.config.max_stop_time())?;
                        ax.safety.config = cfg;
                        Ok(())
                    }),
                },
                CardCmd::EStop(e) => {
                    self.latch(mem, CardFaults::ESTOP_COMMAND);
                    let trip = Trip {
                        category: e.category,
                        reason: StopReason::EStopCommand,
                        fault: Faults::ESTOP,
                        value: e.category as u32 as f64,
                    };
                    self.trip_all(mem, tick, axes, trip);
                    Ok(())
                }
                CardCmd::SafetyReset => {
                    let age = self.heartbeat(mem, tick, rate_hz);
                    let heartbeat_dead = self.latched.contains(CardFaults::WATCHDOG)
                        && ticks_reach_us(age, rate_hz, self.config.watchdog_timeout_us);
                    let estop_held =
                        self.latched.contains(CardFaults::ESTOP_INPUT) && self.inputs.estop;
                    if heartbeat_dead || estop_held {
                        Err(NackCode::CauseActive)
                    } else {
                        self.latched = CardFaults::empty();
                        mem.write32(ss::FAULTS, 0);
                        Ok(())
                    }
                }
                _ => return None,
            }
            .map(|()| 0.0),
        )
    }

    fn apply_config<M: Mem>(&mut self, mem: &M, axes: &[Axis]) -> Result<(), NackCode> {
        let block = layout::SAFETY_CONFIG.read(mem);
        let config = SafetyConfig::validate(&block, mem.read32(layout::HOST_PERIOD_US))?;
        // Every axis's stop ramp from its max velocity must still fit.
        if axes.iter().any(|a| {
            a.safety.config.stop_time_from(a.safety.config.max_velocity) > config.max_stop_time()
        }) {
            return Err(NackCode::StopTooLong);
        }
        self.config = config;
        Ok(())
    }
}

/// The session gate's allowlist: the commands the card takes with nobody in command (no
/// session attached with its watchdog armed). They stop or remove something (NOP, power off,
/// halts and stops, the group's disable, e-stop, a compare channel's disarm, a probe's abort),
/// begin or end a session, read or observe (the configuration read-back, a touch probe, the
/// scope), or stage data for a later command that starts nothing itself (a NURBS curve's
/// begin and data, a point-to-point move's limits, PT/PVT points, cam tables). Anything else
/// is refused with [`NackCode::NoSession`]: motion, power, outputs, the configuration applies
/// (they change what the next motion or a holding axis does), MC_Reset and the safety reset
/// (they clear latches), MC_Stop's release, the override (raising it from 0 % resumes motion),
/// and any opcode added later, until it is named here.
pub fn allowed_without_session(op: Opcode) -> bool {
    matches!(
        op,
        Opcode::Nop
            | Opcode::PowerOff
            | Opcode::Halt
            | Opcode::Stop
            | Opcode::GroupHalt
            | Opcode::GroupStop
            | Opcode::GroupDisable
            | Opcode::EStop
            | Opcode::CompareDisarm
            | Opcode::ProbeAbort
            | Opcode::HostAttach
            | Opcode::HostDetach
            | Opcode::ReadConfig
            | Opcode::CompRead
            | Opcode::ProbeArm
            | Opcode::ScopeConfigure
            | Opcode::ScopeArm
            | Opcode::ScopeTrigger
            | Opcode::ScopeStop
            | Opcode::NurbsBegin
            | Opcode::NurbsData
            | Opcode::GroupPtpLimits
            | Opcode::PvtPoints
            | Opcode::CamTable
            | Opcode::CamData
            | Opcode::TimedCancel
    )
}

/// Would a move of `axis` from `start` to `target` go further into an active limit? Moving out
/// of a limit is always allowed.
pub fn check_target(axis: &Axis, start: f64, target: f64) -> Result<(), NackCode> {
    let s = &axis.safety;
    let c = &s.config;
    if c.has(AxisSafetyFlags::HARD_LIMITS)
        && ((s.io.contains(Io::LIMIT_POS) && target > start)
            || (s.io.contains(Io::LIMIT_NEG) && target < start))
    {
        return Err(NackCode::HardLimit);
    }
    // Soft limits hold once the axis is homed: before that its positions mean nothing. Not on a
    // modulo axis (layout 1.10): every position comes round again.
    if c.has(AxisSafetyFlags::SOFT_LIMITS)
        && axis.homed()
        && !axis.is_modulo()
        && ((target > c.soft_limit_pos && target > start)
            || (target < c.soft_limit_neg && target < start))
    {
        return Err(NackCode::SoftLimit);
    }
    Ok(())
}

/// `ticks` servo ticks at `rate_hz`, in whole µs (rounded down; saturating).
fn ticks_us(ticks: u64, rate_hz: u32) -> u64 {
    ticks.saturating_mul(1_000_000) / u64::from(rate_hz.max(1))
}

/// Have `ticks` servo ticks at `rate_hz` reached `limit_us` µs, counted as [`ticks_us`] counts
/// them? The same answer as `ticks_us(ticks, rate_hz) >= limit_us` (⌊a/r⌋ ≥ t ⇔ a ≥ t·r for
/// integers, and t·r fits in 64 bits) without the division: the watchdog asks every tick.
fn ticks_reach_us(ticks: u64, rate_hz: u32, limit_us: u32) -> bool {
    ticks.saturating_mul(1_000_000) >= u64::from(limit_us) * u64::from(rate_hz.max(1))
}

/// Everything that trips an axis this tick, given its inputs and encoder reading. Also
/// refreshes the live limit fault bits.
fn axis_trips(axis: &mut Axis, inputs: Io, enc: i64, ts: f64) -> [Option<Trip>; 4] {
    let c = axis.safety.config;
    let r = axis.reference();
    let powered = axis.is_powered();
    let ferr = axis.following_error();
    // [homing] the limit switches the homing method watches itself, and soft limits once homed
    let homing_limits = axis.homing_limits();
    let soft = c.has(AxisSafetyFlags::SOFT_LIMITS) && axis.homed() && !axis.is_modulo();
    let s = &mut axis.safety;
    let mut out = [None; 4];
    let cat0 = |reason, fault, value| {
        Some(Trip {
            category: StopCategory::Cat0,
            reason,
            fault,
            value,
        })
    };
    // Encoder: the line-break detector, or a jump no motor can make in one tick.
    if c.has(AxisSafetyFlags::ENCODER) {
        let step = s
            .last_encoder
            .map_or(0, |p| enc.wrapping_sub(p))
            .unsigned_abs() as f64;
        if inputs.contains(Io::ENCODER_FAULT) {
            out[0] = cat0(StopReason::EncoderLoss, Faults::ENCODER, enc as f64);
        } else if step > c.encoder_max_velocity * ts + 2.0 {
            out[0] = cat0(StopReason::EncoderJump, Faults::ENCODER, step);
        }
    }
    if c.has(AxisSafetyFlags::AMP_ALARM) && inputs.contains(Io::AMP_ALARM) {
        out[1] = cat0(StopReason::AmpAlarm, Faults::AMP_ALARM, enc as f64);
    }
    // Limits: live fault bits; a trip only while the axis is driven into the limit.
    s.faults.remove(LIVE_FAULTS);
    let limit = |reason, fault| {
        Some(Trip {
            category: c.limit_category,
            reason,
            fault,
            value: r.pos,
        })
    };
    if c.has(AxisSafetyFlags::HARD_LIMITS) {
        if inputs.contains(Io::LIMIT_POS) {
            s.faults |= Faults::HARD_LIMIT_POS;
            if powered && r.vel > 0.0 && !homing_limits.contains(Io::LIMIT_POS) {
                out[2] = limit(StopReason::HardLimitPos, Faults::HARD_LIMIT_POS);
            }
        }
        if inputs.contains(Io::LIMIT_NEG) {
            s.faults |= Faults::HARD_LIMIT_NEG;
            if powered && r.vel < 0.0 && !homing_limits.contains(Io::LIMIT_NEG) {
                out[2] = limit(StopReason::HardLimitNeg, Faults::HARD_LIMIT_NEG);
            }
        }
    }
    if soft {
        if r.pos > c.soft_limit_pos {
            s.faults |= Faults::SOFT_LIMIT_POS;
            if powered && r.vel > 0.0 && out[2].is_none() {
                out[2] = limit(StopReason::SoftLimitPos, Faults::SOFT_LIMIT_POS);
            }
        }
        if r.pos < c.soft_limit_neg {
            s.faults |= Faults::SOFT_LIMIT_NEG;
            if powered && r.vel < 0.0 && out[2].is_none() {
                out[2] = limit(StopReason::SoftLimitNeg, Faults::SOFT_LIMIT_NEG);
            }
        }
    }
    // Following error (LinuxCNC): on every axis whose servo ran this tick. NaN trips too.
    let within = c.ferror_within(ferr, r.vel);
    if powered && !within {
        out[3] = cat0(StopReason::FollowingError, Faults::FOLLOWING_ERROR, ferr);
    }
    out
}

/// Read and validate `axis_safety[a]`.
fn read_axis_safety<M: Mem>(mem: &M, a: usize) -> Result<AxisSafetyConfig, NackCode> {
    let cfg = AxisSafetyConfig::from_block(&layout::AXIS_SAFETY.at(a).read(mem))?;
    cfg.validate()?;
    Ok(cfg)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::motion::scurve::Limits;

    /// The watchdog's comparison without the division answers as the one with it, at the
    /// edges and where the product saturates.
    #[test]
    fn ticks_reach_us_is_the_division_compared() {
        let rates = [1, 3, 1000, 7919, 10_000, 40_000, u32::MAX];
        let limits = [0, 1, 99, 100, 100_000, 123_457, u32::MAX];
        let mut ticks: Vec<u64> = vec![0, 1, 2, 999, 1000, 1001, u64::MAX / 1_000_000 + 1];
        ticks.push(u64::MAX);
        for &r in &rates {
            for &t in &limits {
                // Around the exact boundary t·r / 10⁶ ticks.
                let b = (u64::from(t) * u64::from(r)) / 1_000_000;
                for k in ticks
                    .iter()
                    .copied()
                    .chain([b.saturating_sub(1), b, b + 1, b + 2])
                {
                    assert_eq!(
                        ticks_reach_us(k, r, t),
                        ticks_us(k, r) >= u64::from(t),
                        "{k} ticks at {r} Hz against {t} us"
                    );
                }
            }
        }
    }

    /// A profile that ends moving (a queue that ran dry) continues as a planned stop: the
    /// commanded velocity never jumps, and the axis comes to rest with reason Starvation.
    #[test]
    fn starvation_ends_in_a_planned_stop_not_a_jump() {
        let mut ax = Axis::new();
        ax.power(true).unwrap();
        let lim = Limits::symmetric(2e5, 2e6, 1e8);
        let p = Profile::plan(0.0, 50_000.0, 0.0, 1e5, &lim).unwrap();
        ax.run_profile(7, p);
        let ts = 1e-4;
        let mut prev = ax.reference();
        let mut peak_dv: f64 = 0.0;
        let mut enc = 0i64;
        for _ in 0..20_000 {
            ax.tick(enc, ts);
            let r = ax.reference();
            peak_dv = peak_dv.max((r.vel - prev.vel).abs());
            enc = r.pos.round() as i64; // an ideal drive
            prev = r;
        }
        let r = ax.reference();
        assert_eq!((r.vel, r.acc), (0.0, 0.0));
        assert!(
            r.pos > 50_000.0,
            "stopped past the end of the queue at {}",
            r.pos
        );
        // Per tick the velocity changes by at most a·ts (plus the jerk term): no jump.
        assert!(peak_dv <= 5e6 * ts * 1.01, "velocity jumped by {peak_dv}");
        assert_eq!(ax.safety.stop_reason, StopReason::Starvation);
        assert_eq!(ax.state, AxisState::Standstill);
    }
}
