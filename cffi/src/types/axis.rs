//! What a card and its axes say and take: the card's identity, an axis's move limits,
//! settings, status and events.

use motioncard_sdk::{CardEvent, CardInfo, MoveLimits, Status};

/// `mc_event.axis` of an event about the whole card.
pub const MC_EVENT_CARD_WIDE: u32 = 0xFFFF;

/// What the card says about itself (`mc_card_info`).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[allow(non_camel_case_types)]
pub struct mc_card_info {
    /// Firmware version, `major << 16 | minor << 8 | patch`.
    pub firmware_version: u32,
    /// DPRAM layout major version.
    pub layout_major: u16,
    /// DPRAM layout minor version.
    pub layout_minor: u16,
    /// Axes on the card (axis numbers 0 .. axes-1).
    pub axes: u32,
    /// Servo rate, Hz.
    pub servo_rate_hz: u32,
    /// `MC_CARD_CAP_` bits.
    pub capabilities: u32,
}

impl From<CardInfo> for mc_card_info {
    fn from(i: CardInfo) -> Self {
        Self {
            firmware_version: i.firmware_version,
            layout_major: i.layout.0,
            layout_minor: i.layout.1,
            axes: i.axes as u32,
            servo_rate_hz: i.servo_rate_hz,
            capabilities: i.capabilities,
        }
    }
}

/// Limits of a point-to-point move, in user units (see `mc_set_scale`). Every value must be
/// finite and greater than zero.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[allow(non_camel_case_types)]
pub struct mc_move_limits {
    /// Maximum velocity.
    pub velocity: f64,
    /// Maximum acceleration.
    pub acceleration: f64,
    /// Maximum deceleration.
    pub deceleration: f64,
    /// Jerk of the seven-segment phases 1, 3 (acceleration) and 5, 7 (deceleration).
    pub jerk: [f64; 4],
}

impl From<mc_move_limits> for MoveLimits {
    fn from(l: mc_move_limits) -> Self {
        MoveLimits {
            velocity: l.velocity,
            acceleration: l.acceleration,
            deceleration: l.deceleration,
            jerk: l.jerk,
        }
    }
}

impl From<MoveLimits> for mc_move_limits {
    fn from(l: MoveLimits) -> Self {
        Self {
            velocity: l.velocity,
            acceleration: l.acceleration,
            deceleration: l.deceleration,
            jerk: l.jerk,
        }
    }
}

/// Servo gains and in-position windows of an axis (counts, seconds, volts): the card's
/// `mc_axis_config` register block, the same struct as in the register map. Start from
/// `mc_axis_settings_default`; `mc_configure` selects FFPIV whatever `servo_law` holds.
#[allow(non_camel_case_types)]
pub type mc_axis_settings = firmware_proto::raw::mc_axis_config;

/// Everything the card publishes about an axis, in counts and seconds (no scale applied): the
/// card's `mc_axis_status_payload`, the same struct as in the register map (`state` is an
/// `MC_AXIS_STATE_` value, `faults` `MC_AXIS_FAULT_` bits, `stop_reason` an
/// `MC_STOP_REASON_` value, `io` `MC_IO_` bits; `checksum` is 0: the library checked it).
#[allow(non_camel_case_types)]
pub type mc_raw_status = firmware_proto::raw::mc_axis_status_payload;

/// A consistent snapshot of an axis's status, in user units (see `mc_set_scale`), with
/// everything the card published in counts in `raw`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[allow(non_camel_case_types)]
pub struct mc_status {
    /// `MC_AXIS_STATE_` value.
    pub state: u32,
    /// `MC_AXIS_FAULT_` bits.
    pub faults: u32,
    /// Commanded position.
    pub command_position: f64,
    /// Commanded velocity.
    pub command_velocity: f64,
    /// Commanded acceleration.
    pub command_acceleration: f64,
    /// Actual position.
    pub actual_position: f64,
    /// Actual velocity.
    pub actual_velocity: f64,
    /// Following error (commanded − actual).
    pub following_error: f64,
    /// DAC output, volts.
    pub dac_volts: f64,
    /// The same snapshot in counts, with the card's per-move statistics.
    pub raw: mc_raw_status,
    /// Why the last motion ended (`MC_STOP_REASON_` value; a newer card may report one this
    /// library has no constant for).
    pub stop_reason: u32,
    /// The axis's limit switch, home, amplifier alarm, encoder fault and e-stop inputs and its
    /// drive-enable output (`MC_IO_` bits).
    pub io: u32,
}

impl From<&Status> for mc_status {
    fn from(s: &Status) -> Self {
        let r = &s.raw;
        Self {
            state: s.state as u32,
            faults: s.faults.bits(),
            command_position: s.command_position,
            command_velocity: s.command_velocity,
            command_acceleration: s.command_acceleration,
            actual_position: s.actual_position,
            actual_velocity: s.actual_velocity,
            following_error: s.following_error,
            dac_volts: s.dac_volts,
            raw: *r,
            stop_reason: s.stop_reason().map_or(r.stop_reason, |r| r as u32),
            io: s.io().bits(),
        }
    }
}

/// An event from the card. The unit rule, one for every kind: a `value` that is a position
/// or a distance is in user units of the axis it concerns (`axis`, or for `MC_EVENT_COMPARE`
/// and `MC_EVENT_PROBE` the axis the channel watches), as `mc_status` gives them: motion done
/// and active, in velocity (user units/s), homing failed, sync, PVT done, compare fired or
/// missed, probe captures, and the safety stops whose measurement is a position, a following
/// error or an encoder count. Every other value is as the card posts it: states, times in
/// seconds, counts of things, ids, words.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[allow(non_camel_case_types)]
pub struct mc_event {
    /// `MC_EVENT_` value.
    pub kind: u32,
    /// Axis, or `MC_EVENT_CARD_WIDE`.
    pub axis: u32,
    /// Seq of the command it concerns (motion events: the command that started the motion;
    /// compare with `mc_motion.seq`).
    pub seq: u32,
    /// Kind-specific code.
    pub code: i32,
    /// Servo tick at which the card raised it.
    pub tick: u64,
    /// Kind-specific value (positions and distances in user units: the rule above).
    pub value: f64,
}

impl From<&CardEvent> for mc_event {
    fn from(e: &CardEvent) -> Self {
        Self {
            kind: e.kind as u32,
            axis: e.axis as u32,
            seq: e.seq,
            code: e.code,
            tick: e.tick,
            value: e.value,
        }
    }
}

/// A motion started by `mc_move_absolute`, `mc_move_relative`, `mc_halt` or `mc_stop`; wait for
/// it with `mc_motion_wait`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[allow(non_camel_case_types)]
pub struct mc_motion {
    /// The axis.
    pub axis: u32,
    /// The seq of the command that started it (events about it carry the same seq).
    pub seq: u32,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn limits_and_settings_round_trip() {
        let l = MoveLimits::new(1.0, 2.0, 3.0)
            .deceleration(4.0)
            .decel_jerk(5.0);
        assert_eq!(MoveLimits::from(mc_move_limits::from(l)), l);
    }
}
