//! Safety from the host: the card's watchdog timeout and maximum stop time, e-stop, fault
//! reset, the card-wide safety status, per-axis safety settings (limits, following error, stop
//! ramp) and stop reasons.
//!
//! The card arms its watchdog when a host's session attaches (the attach counts as its first
//! heartbeat; [`crate::HEARTBEAT_PERIOD_US`], see the heartbeat module): a host that vanishes
//! without closing the card makes every enabled axis do a category 1 stop after the timeout,
//! latched until [`Card::reset_faults`]. Closing the card ([`Card::close`], or dropping the
//! last clone) halts what moves and disarms the watchdog without a fault. Outside a session
//! the card refuses what could start motion, give power or change outputs, configuration or
//! latches ([`crate::ErrorKind::NoSession`]), and stops any motion it finds. Stepping a stepped card's
//! emulator directly (`Sim::with_emulator`) does not beat: that is how a test makes a host
//! hang, besides [`Card::set_heartbeat`].

use crate::card::{Axis, Card, Status};
use crate::error::{Error, Result, Target};
use firmware_proto::cmd::{CardCmd, EStop};
use firmware_proto::layout::{self, safety_status as ss};
use firmware_proto::{
    raw, AxisSafetyFlags, AxisState, CardFaults, Io, Mem, StopCategory, StopReason, MAX_AXES,
};
use std::sync::atomic::Ordering;
use std::time::Duration;

/// The card's default watchdog timeout.
pub const WATCHDOG_TIMEOUT_DEFAULT: Duration =
    Duration::from_micros(card_firmware::host::WATCHDOG_TIMEOUT_DEFAULT_US as u64);

/// The card-wide safety state.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SafetyStatus {
    /// The host watchdog tripped; latched until [`Card::reset_faults`].
    pub watchdog_tripped: bool,
    /// The host's e-stop command is latched.
    pub estop_command: bool,
    /// The e-stop input tripped; latched until reset with the input released.
    pub estop_input: bool,
    /// The watchdog is watching: a session is attached (armed by its attach, disarmed by its
    /// detach). Outside a session the card takes no motion (`ErrorKind::NoSession`).
    pub watchdog_armed: bool,
    /// Servo tick at which the card last saw the heartbeat change.
    pub last_heartbeat_tick: u64,
    /// Servo tick of the last watchdog trip (0: never).
    pub watchdog_trip_tick: u64,
    /// The tick of the last heartbeat the card saw before that trip.
    pub trip_heartbeat_tick: u64,
    /// Protocol errors (corrupt ring indices) the card detected since boot.
    pub protocol_errors: u32,
    /// The session id of the host attached to the card (this one's while it is open).
    pub session: u32,
    /// Servo tick of the last attach (this host's open, while it is open).
    pub attach_tick: u64,
    /// Hosts that opened the card while another's session was still open, since boot (each
    /// stopped the motion the vanished host left).
    pub host_changes: u32,
    /// Heartbeats that came later than the host's declared period after the one before,
    /// since this host attached: how close the host runs to its watchdog.
    pub late_heartbeats: u32,
    /// The longest gap between two heartbeats the card saw since this host attached.
    pub max_heartbeat_gap: Duration,
    /// What the card lost since boot (layout 1.4; 0 on an older card). Each nonzero count is a
    /// bug: accesses to the window out of range or misaligned that the card's handle refused,
    pub bad_accesses: u32,
    /// events that found the firmware's outbox full (before the event ring),
    pub outbox_lost: u32,
    /// and safety events that found the safety layer's event buffer full.
    pub safety_events_lost: u32,
}

/// How an axis's last safety stop went, measured by the card.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StopInfo {
    /// Why the last motion ended.
    pub reason: StopReason,
    /// Servo tick at which the last safety stop began (0: none since boot).
    pub stop_tick: u64,
    /// Servo tick at which the axis came to rest after it (`None` while still stopping).
    pub rest_tick: Option<u64>,
    /// Planned duration of the stop's deceleration ramp (0 for category 0).
    pub ramp_time: Duration,
}

/// An axis's safety configuration, in user units (see [`Axis::set_scale`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SafetySettings {
    /// Soft limits (negative, positive), or `None`.
    pub soft_limits: Option<(f64, f64)>,
    /// Honour the limit switch inputs.
    pub hard_limits: bool,
    /// Honour the amplifier alarm input.
    pub amp_alarm: bool,
    /// Honour encoder loss and jumps.
    pub encoder_checks: bool,
    /// The stop a hard or soft limit makes.
    pub limit_stop: StopCategory,
    /// Following-error limit at `max_velocity` (LinuxCNC FERROR).
    pub ferror: f64,
    /// Following-error limit at rest (LinuxCNC MIN_FERROR).
    pub min_ferror: f64,
    /// The velocity `ferror` applies at.
    pub max_velocity: f64,
    /// Deceleration of category 1 and 2 stops.
    pub stop_deceleration: f64,
    /// Jerk of those stops.
    pub stop_jerk: f64,
    /// Fastest physically possible encoder velocity: a larger change in one tick is a fault.
    pub encoder_max_velocity: f64,
}

impl Default for SafetySettings {
    /// The card's defaults, in counts.
    fn default() -> Self {
        let c = card_firmware::host::AxisSafetyConfig::default();
        let has = |f| c.flags.contains(f);
        Self {
            soft_limits: has(AxisSafetyFlags::SOFT_LIMITS)
                .then_some((c.soft_limit_neg, c.soft_limit_pos)),
            hard_limits: has(AxisSafetyFlags::HARD_LIMITS),
            amp_alarm: has(AxisSafetyFlags::AMP_ALARM),
            encoder_checks: has(AxisSafetyFlags::ENCODER),
            limit_stop: c.limit_category,
            ferror: c.ferror,
            min_ferror: c.min_ferror,
            max_velocity: c.max_velocity,
            stop_deceleration: c.stop_decel,
            stop_jerk: c.stop_jerk,
            encoder_max_velocity: c.encoder_max_velocity,
        }
    }
}

impl Card {
    /// Stop (`false`) or resume the heartbeat. A stopped heartbeat is a hung host to the card:
    /// its watchdog trips after the timeout. For tests of the watchdog.
    pub fn set_heartbeat(&self, on: bool) {
        self.with_heartbeat(|h| h.enabled.store(on, Ordering::Relaxed));
    }

    /// Set the card's watchdog timeout (default [`WATCHDOG_TIMEOUT_DEFAULT`], 100 ms: above the
    /// heartbeat gaps of a loaded host without real-time scheduling; a real-time host can run
    /// a much shorter one, down to 1.5 × [`crate::HEARTBEAT_PERIOD_US`]; see
    /// [`SafetyStatus::late_heartbeats`] for how close a host runs). The card refuses zero
    /// and anything under 1.5 × the heartbeat period with
    /// [`crate::ErrorKind::WatchdogTimeout`]. On a `sim` card opened with
    /// [`crate::SIM_WATCHDOG_ENV`] set (debugging), a shorter timeout gets that one.
    pub fn set_watchdog_timeout(&self, timeout: Duration) -> Result<()> {
        let us = u32::try_from(timeout.as_micros()).unwrap_or(u32::MAX);
        // A `sim` card set up for debugging (SIM_WATCHDOG_ENV) keeps its longer timeout.
        let floor = self.inner().watchdog_floor_us();
        let us = if us == 0 { us } else { us.max(floor) };
        self.apply_safety_config(|b| b.watchdog_timeout_us = us, "set_watchdog_timeout")
    }

    /// The stop the card's e-stop input makes (default category 1).
    pub fn set_estop_input_category(&self, category: StopCategory) -> Result<()> {
        self.apply_safety_config(
            |b| b.estop_input_category = category as u32,
            "set_estop_input_category",
        )
    }

    /// Change the card-wide safety block and have the card apply it.
    fn apply_safety_config(
        &self,
        change: impl FnOnce(&mut raw::mc_safety_config),
        what: &'static str,
    ) -> Result<()> {
        self.apply_block(
            layout::SAFETY_CONFIG,
            change,
            CardCmd::ApplySafetyConfig.command(0),
            what,
            Target::Card,
        )
    }

    /// E-stop every axis with the given stop category. Latched: nothing moves again until
    /// [`Card::reset_faults`].
    pub fn estop(&self, category: StopCategory) -> Result<()> {
        self.execute(
            CardCmd::EStop(EStop { category }).command(0),
            "estop",
            Target::Card,
        )
    }

    /// Clear the card-wide latches (watchdog, e-stop: refused with
    /// [`crate::ErrorKind::CauseActive`] while the heartbeat is not alive or the e-stop input is
    /// pressed), then MC_Reset every axis in ErrorStop (refused while an axis's alarm or encoder
    /// fault persists). Axes whose drive was disabled by their stop end Disabled; the others
    /// Standstill.
    pub fn reset_faults(&self) -> Result<()> {
        self.execute(
            CardCmd::SafetyReset.command(0),
            "reset_faults",
            Target::Card,
        )?;
        for ax in self.axes() {
            if ax.status()?.state == AxisState::ErrorStop {
                ax.reset()?;
            }
        }
        Ok(())
    }

    /// The card-wide safety state (`NotResponding` rather than a stale one).
    pub fn safety_status(&self) -> Result<SafetyStatus> {
        self.tick()?;
        let w = self.window();
        let faults = CardFaults::from_bits_retain(w.read32(ss::FAULTS));
        let us = |off| Duration::from_micros(w.read32(off) as u64);
        Ok(SafetyStatus {
            watchdog_tripped: faults.contains(CardFaults::WATCHDOG),
            estop_command: faults.contains(CardFaults::ESTOP_COMMAND),
            estop_input: faults.contains(CardFaults::ESTOP_INPUT),
            watchdog_armed: w.read32(ss::WATCHDOG_ARMED) != 0,
            last_heartbeat_tick: w.read64(ss::LAST_HEARTBEAT_TICK),
            watchdog_trip_tick: w.read64(ss::WATCHDOG_TRIP_TICK),
            trip_heartbeat_tick: w.read64(ss::TRIP_HEARTBEAT_TICK),
            protocol_errors: w.read32(ss::PROTOCOL_ERRORS),
            session: w.read32(ss::SESSION),
            attach_tick: w.read64(ss::ATTACH_TICK),
            host_changes: w.read32(ss::HOST_CHANGES),
            late_heartbeats: w.read32(ss::LATE_HEARTBEATS),
            max_heartbeat_gap: us(ss::MAX_HEARTBEAT_GAP_US),
            bad_accesses: w.read32(layout::BAD_ACCESSES),
            outbox_lost: w.read32(layout::OUTBOX_LOST),
            safety_events_lost: w.read32(layout::SAFETY_EVENTS_LOST),
        })
    }

    /// Set the card's maximum stop time (default 2 s): every stop — halt, stop, the safety
    /// stops, starvation — ends within it; a halt whose own ramp would take longer runs on the
    /// axis's stop ramp, and a stop still running at the bound loses power (reason
    /// [`StopReason::StopTimeout`]). 10 ms to 600 s, and every axis's stop ramp from its
    /// max velocity must fit ([`crate::ErrorKind::StopTooLong`]).
    pub fn set_max_stop_time(&self, t: Duration) -> Result<()> {
        let us = u32::try_from(t.as_micros()).unwrap_or(u32::MAX);
        self.apply_safety_config(|b| b.max_stop_time_us = us, "set_max_stop_time")
    }
}

/// The card-wide safety settings as the card holds them (`mc_safety_config`): watchdog timeout
/// (µs), the e-stop input's stop category, the maximum stop time (µs).
pub use firmware_proto::raw::mc_safety_config as CardSafetySettings;

impl Card {
    /// The card-wide safety settings the card holds (layout 1.8: read back from the card).
    pub fn safety_settings(&self) -> Result<CardSafetySettings> {
        self.read_block(layout::SAFETY_CONFIG, firmware_proto::ConfigKind::Safety, 0)
    }

    /// The servo rate the card runs at (layout 1.8: read back from the card), Hz.
    pub fn servo_rate(&self) -> Result<u32> {
        let b = self.read_block(layout::CARD_CONFIG, firmware_proto::ConfigKind::Card, 0)?;
        Ok(b.servo_rate_hz)
    }
}

impl Axis {
    /// The axis's safety configuration as the card holds it (layout 1.8: read back from the
    /// card), in user units (see [`Axis::set_scale`]).
    pub fn safety_settings(&self) -> Result<SafetySettings> {
        let a = self.index();
        let b = self.card().read_block(
            layout::AXIS_SAFETY.at(a),
            firmware_proto::ConfigKind::AxisSafety,
            a,
        )?;
        let c = card_firmware::host::AxisSafetyConfig::from_block(&b)
            .map_err(|_| Error::Protocol(format!("axis {a}: unknown stop category")))?;
        let scale = self.scale();
        let k = scale.abs();
        let has = |f| c.flags.contains(f);
        let (neg, pos) = if scale < 0.0 {
            (c.soft_limit_pos / scale, c.soft_limit_neg / scale)
        } else {
            (c.soft_limit_neg / scale, c.soft_limit_pos / scale)
        };
        Ok(SafetySettings {
            soft_limits: has(AxisSafetyFlags::SOFT_LIMITS).then_some((neg, pos)),
            hard_limits: has(AxisSafetyFlags::HARD_LIMITS),
            amp_alarm: has(AxisSafetyFlags::AMP_ALARM),
            encoder_checks: has(AxisSafetyFlags::ENCODER),
            limit_stop: c.limit_category,
            ferror: c.ferror / k,
            min_ferror: c.min_ferror / k,
            max_velocity: c.max_velocity / k,
            stop_deceleration: c.stop_decel / k,
            stop_jerk: c.stop_jerk / k,
            encoder_max_velocity: c.encoder_max_velocity / k,
        })
    }

    /// Write the axis's safety configuration and have the card apply it (limits, following
    /// error, stop ramp), converting user units through the axis's scale.
    pub fn configure_safety(&self, s: &SafetySettings) -> Result<()> {
        let scale = self.scale();
        let k = scale.abs();
        let (neg, pos) = s.soft_limits.unwrap_or((-f64::MAX, f64::MAX));
        let named = [
            ("soft limit", neg),
            ("soft limit", pos),
            ("ferror", s.ferror),
            ("min_ferror", s.min_ferror),
            ("max velocity", s.max_velocity),
            ("stop deceleration", s.stop_deceleration),
            ("stop jerk", s.stop_jerk),
            ("encoder max velocity", s.encoder_max_velocity),
        ];
        for (what, v) in named {
            if !v.is_finite() {
                return Err(Error::NotFinite { what, value: v });
            }
        }
        let (neg, pos) = match s.soft_limits {
            Some((neg, pos)) if neg >= pos => {
                return Err(Error::BadConfig(format!(
                    "soft limits: the negative limit {neg} must be below the positive limit {pos}"
                )))
            }
            // In counts: a negative scale turns the user's negative limit into the larger count.
            Some((neg, pos)) if scale < 0.0 => (pos * scale, neg * scale),
            Some((neg, pos)) => (neg * scale, pos * scale),
            None => (
                -card_firmware::host::MAX_POSITION,
                card_firmware::host::MAX_POSITION,
            ),
        };
        let mut flags = AxisSafetyFlags::empty();
        flags.set(AxisSafetyFlags::SOFT_LIMITS, s.soft_limits.is_some());
        flags.set(AxisSafetyFlags::HARD_LIMITS, s.hard_limits);
        flags.set(AxisSafetyFlags::AMP_ALARM, s.amp_alarm);
        flags.set(AxisSafetyFlags::ENCODER, s.encoder_checks);
        let a = self.index();
        let block = raw::mc_axis_safety {
            flags: flags.bits(),
            limit_category: s.limit_stop as u32,
            soft_limit_neg: neg,
            soft_limit_pos: pos,
            ferror: s.ferror * k,
            min_ferror: s.min_ferror * k,
            max_velocity: s.max_velocity * k,
            stop_decel: s.stop_deceleration * k,
            stop_jerk: s.stop_jerk * k,
            encoder_max_velocity: s.encoder_max_velocity * k,
            ..Default::default()
        };
        self.card().apply_block(
            layout::AXIS_SAFETY.at(a),
            |b| *b = block,
            CardCmd::ApplyAxisSafety.command(a as u16),
            "configure_safety",
            Target::Axis(a),
        )
    }

    /// Why the axis's last motion ended (`dmc_get_stop_reason`).
    pub fn stop_reason(&self) -> Result<StopReason> {
        let s = self.status()?;
        s.stop_reason().ok_or_else(|| {
            Error::Protocol(format!(
                "axis {} reports unknown stop reason {}",
                self.index(),
                s.raw.stop_reason
            ))
        })
    }

    /// The stop reason and the card's timing of the axis's last safety stop.
    pub fn stop_info(&self) -> Result<StopInfo> {
        let a = self.index();
        let w = self.card().window();
        let reason = self.stop_reason()?; // fresh, or NotResponding
        let rest = w.read64(ss::rest_tick(a));
        let ramp = w.read_f64(ss::ramp_time(a));
        Ok(StopInfo {
            reason,
            stop_tick: w.read64(ss::stop_tick(a)),
            rest_tick: (rest != 0).then_some(rest),
            ramp_time: Duration::try_from_secs_f64(ramp).unwrap_or_default(),
        })
    }
}

impl Status {
    /// Why the axis's last motion ended (`None`: a reason this library does not know).
    pub fn stop_reason(&self) -> Option<StopReason> {
        self.raw.stop_reason()
    }

    /// The axis's input bits and drive-enable output.
    pub fn io(&self) -> Io {
        self.raw.io()
    }

    /// Is the axis's drive (amplifier) enabled?
    pub fn drive_enabled(&self) -> bool {
        self.raw.io().contains(Io::DRIVE_ENABLE)
    }
}

const _: () = assert!(MAX_AXES <= 8);
