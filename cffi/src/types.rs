//! The plain structs and constants of the C ABI, and their conversions from the SDK's types.
//!
//! Enumerations cross as `uint32_t` fields with `MC_` constants (a C enum holding a value the
//! library does not know would be undefined behaviour in C++). The constants are literals for
//! cbindgen; the tests check them against the SDK.

use motioncard_sdk::{AxisSettings, AxisState, CardEvent, CardInfo, EventKind, MoveLimits, Status};

/// Axis state (`mc_status.state`, `MC_EVENT_STATE_CHANGED` codes): PLCopen's states.
pub const MC_AXIS_STATE_DISABLED: u32 = 0;
/// Powered, at rest, ready for a move.
pub const MC_AXIS_STATE_STANDSTILL: u32 = 1;
/// Homing.
pub const MC_AXIS_STATE_HOMING: u32 = 2;
/// A point-to-point move.
pub const MC_AXIS_STATE_DISCRETE_MOTION: u32 = 3;
/// A velocity move.
pub const MC_AXIS_STATE_CONTINUOUS_MOTION: u32 = 4;
/// Coupled to another axis or a group.
pub const MC_AXIS_STATE_SYNCHRONIZED_MOTION: u32 = 5;
/// `mc_stop` in progress or held (until `mc_release_stop`).
pub const MC_AXIS_STATE_STOPPING: u32 = 6;
/// Stopped by a fault; only `mc_reset` leaves it.
pub const MC_AXIS_STATE_ERROR_STOP: u32 = 7;

/// Fault bit of `mc_status.faults`: the servo output hit the DAC limit.
pub const MC_AXIS_FAULT_DAC_SATURATED: u32 = 1;

/// Capability bit of `mc_card_info.capabilities`: S-curve profiles.
pub const MC_CARD_CAP_SCURVE: u32 = 1;
/// Capability bit: FFPIV servo loop.
pub const MC_CARD_CAP_FFPIV: u32 = 2;
/// Capability bit: events raise an interrupt (`mc_irq_fd` works).
pub const MC_CARD_CAP_EVENT_IRQ: u32 = 4;

/// Event kind (`mc_event.kind`): a command was accepted. Taken by the library, never delivered.
pub const MC_EVENT_ACK: u32 = 1;
/// A command was refused. Taken by the library, never delivered.
pub const MC_EVENT_NACK: u32 = 2;
/// The axis finished its move and is in position; `value` is the actual position (user units).
pub const MC_EVENT_MOTION_DONE: u32 = 3;
/// The axis changed state; `code` is the new `MC_AXIS_STATE_`, `value` the old one.
pub const MC_EVENT_STATE_CHANGED: u32 = 4;
/// A fault was raised; `code` is the `MC_AXIS_FAULT_` bit, `value` a measurement.
pub const MC_EVENT_FAULT: u32 = 5;
/// A move ended before its target; `code` is the command (opcode) or fault that ended it.
pub const MC_EVENT_MOTION_ABORTED: u32 = 6;
/// A group move finished (`axis`: the group; `value` 1 when the group is at rest in position).
pub const MC_EVENT_GROUP_MOTION_DONE: u32 = 8;
/// A group changed state (`axis`: the group; `code`: the new group state).
pub const MC_EVENT_GROUP_STATE_CHANGED: u32 = 9;
/// A group move was aborted (`axis`: the group).
pub const MC_EVENT_GROUP_MOTION_ABORTED: u32 = 10;

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

/// Servo gains and in-position windows of an axis (counts, seconds, volts). Start from
/// `mc_axis_settings_default`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[allow(non_camel_case_types)]
pub struct mc_axis_settings {
    /// Position gain, 1/s.
    pub kp: f64,
    /// Velocity-loop integral gain, 1/s.
    pub ki: f64,
    /// Velocity-loop gain, V per count/s.
    pub kv: f64,
    /// Velocity feed-forward fraction.
    pub kvff: f64,
    /// Acceleration feed-forward, V per count/s².
    pub kaff: f64,
    /// Velocity estimator cut-off, Hz.
    pub vel_filter_hz: f64,
    /// Output clamp, V.
    pub dac_limit_v: f64,
    /// In-position window, counts.
    pub in_pos_window: f64,
    /// In-velocity window, counts/s.
    pub in_vel_window: f64,
    /// Settle time, s.
    pub settle_time: f64,
}

impl From<mc_axis_settings> for AxisSettings {
    fn from(s: mc_axis_settings) -> Self {
        AxisSettings {
            kp: s.kp,
            ki: s.ki,
            kv: s.kv,
            kvff: s.kvff,
            kaff: s.kaff,
            vel_filter_hz: s.vel_filter_hz,
            dac_limit_v: s.dac_limit_v,
            in_pos_window: s.in_pos_window,
            in_vel_window: s.in_vel_window,
            settle_time: s.settle_time,
        }
    }
}

impl From<AxisSettings> for mc_axis_settings {
    fn from(s: AxisSettings) -> Self {
        Self {
            kp: s.kp,
            ki: s.ki,
            kv: s.kv,
            kvff: s.kvff,
            kaff: s.kaff,
            vel_filter_hz: s.vel_filter_hz,
            dac_limit_v: s.dac_limit_v,
            in_pos_window: s.in_pos_window,
            in_vel_window: s.in_vel_window,
            settle_time: s.settle_time,
        }
    }
}

/// Everything the card publishes about an axis, in counts and seconds (no scale applied).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[allow(non_camel_case_types)]
pub struct mc_raw_status {
    /// Commanded (profile) position, counts.
    pub cmd_pos: f64,
    /// Commanded velocity, counts/s.
    pub cmd_vel: f64,
    /// Commanded acceleration, counts/s².
    pub cmd_acc: f64,
    /// Actual (encoder) position, counts.
    pub act_pos: f64,
    /// Actual velocity (filtered), counts/s.
    pub act_vel: f64,
    /// Following error = commanded − actual position, counts.
    pub ferr: f64,
    /// DAC output, volts.
    pub dac_v: f64,
    /// Target of the current or last move, counts.
    pub target: f64,
    /// `MC_AXIS_STATE_` value.
    pub state: u32,
    /// `MC_AXIS_FAULT_` bits.
    pub faults: u32,
    /// Seq of the last command accepted for this axis.
    pub last_seq: u32,
    /// Moves started since boot.
    pub move_count: u32,
    /// Servo tick of this snapshot.
    pub tick: u64,
    /// Raw encoder count.
    pub encoder: i64,
    /// Max |commanded velocity| of the current or last move, counts/s.
    pub peak_vel: f64,
    /// Max commanded acceleration of the move, counts/s².
    pub peak_acc: f64,
    /// Max commanded deceleration of the move, counts/s².
    pub peak_dec: f64,
    /// Max |commanded jerk| of the move, counts/s³.
    pub peak_jerk: f64,
    /// Max |following error| of the move, counts.
    pub max_ferr: f64,
    /// Planned profile duration, s.
    pub planned_time: f64,
    /// Time from start to motion done (in position), s; 0 while the move runs.
    pub move_time: f64,
}

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
}

/// The `MC_AXIS_STATE_` value of a state.
pub(crate) fn state_code(s: AxisState) -> u32 {
    match s {
        AxisState::Disabled => MC_AXIS_STATE_DISABLED,
        AxisState::Standstill => MC_AXIS_STATE_STANDSTILL,
        AxisState::Homing => MC_AXIS_STATE_HOMING,
        AxisState::DiscreteMotion => MC_AXIS_STATE_DISCRETE_MOTION,
        AxisState::ContinuousMotion => MC_AXIS_STATE_CONTINUOUS_MOTION,
        AxisState::SynchronizedMotion => MC_AXIS_STATE_SYNCHRONIZED_MOTION,
        AxisState::Stopping => MC_AXIS_STATE_STOPPING,
        AxisState::ErrorStop => MC_AXIS_STATE_ERROR_STOP,
    }
}

/// The `MC_EVENT_` value of an event kind.
pub(crate) fn event_code(k: EventKind) -> u32 {
    match k {
        EventKind::Ack => MC_EVENT_ACK,
        EventKind::Nack => MC_EVENT_NACK,
        EventKind::MotionDone => MC_EVENT_MOTION_DONE,
        EventKind::StateChanged => MC_EVENT_STATE_CHANGED,
        EventKind::Fault => MC_EVENT_FAULT,
        EventKind::MotionAborted => MC_EVENT_MOTION_ABORTED,
        EventKind::GroupMotionDone => MC_EVENT_GROUP_MOTION_DONE,
        EventKind::GroupStateChanged => MC_EVENT_GROUP_STATE_CHANGED,
        EventKind::GroupMotionAborted => MC_EVENT_GROUP_MOTION_ABORTED,
    }
}

impl From<&Status> for mc_status {
    fn from(s: &Status) -> Self {
        let r = &s.raw;
        Self {
            state: state_code(s.state),
            faults: s.faults,
            command_position: s.command_position,
            command_velocity: s.command_velocity,
            command_acceleration: s.command_acceleration,
            actual_position: s.actual_position,
            actual_velocity: s.actual_velocity,
            following_error: s.following_error,
            dac_volts: s.dac_volts,
            raw: mc_raw_status {
                cmd_pos: r.cmd_pos,
                cmd_vel: r.cmd_vel,
                cmd_acc: r.cmd_acc,
                act_pos: r.act_pos,
                act_vel: r.act_vel,
                ferr: r.ferr,
                dac_v: r.dac_v,
                target: r.target,
                state: r.state,
                faults: r.faults,
                last_seq: r.last_seq,
                move_count: r.move_count,
                tick: r.tick,
                encoder: r.encoder,
                peak_vel: r.peak_vel,
                peak_acc: r.peak_acc,
                peak_dec: r.peak_dec,
                peak_jerk: r.peak_jerk,
                max_ferr: r.max_ferr,
                planned_time: r.planned_time,
                move_time: r.move_time,
            },
        }
    }
}

/// An event from the card, in user units.
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
    /// Kind-specific value (positions in user units).
    pub value: f64,
}

impl From<&CardEvent> for mc_event {
    fn from(e: &CardEvent) -> Self {
        Self {
            kind: event_code(e.kind),
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
    use motioncard_sdk::proto::raw;

    #[test]
    fn constants_match_the_card() {
        for s in AxisState::ALL {
            assert_eq!(state_code(*s), *s as u32, "{s:?}");
        }
        for k in EventKind::ALL {
            assert_eq!(event_code(*k), *k as u32, "{k:?}");
        }
        assert_eq!(MC_AXIS_FAULT_DAC_SATURATED, raw::MC_FAULT_DAC_SATURATED);
        assert_eq!(MC_CARD_CAP_SCURVE, raw::MC_CAP_SCURVE);
        assert_eq!(MC_CARD_CAP_FFPIV, raw::MC_CAP_FFPIV);
        assert_eq!(MC_CARD_CAP_EVENT_IRQ, raw::MC_CAP_EVENT_IRQ);
    }

    #[test]
    fn limits_and_settings_round_trip() {
        let l = MoveLimits::new(1.0, 2.0, 3.0)
            .deceleration(4.0)
            .decel_jerk(5.0);
        assert_eq!(MoveLimits::from(mc_move_limits::from(l)), l);
        let s = AxisSettings::default();
        assert_eq!(AxisSettings::from(mc_axis_settings::from(s)), s);
    }
}
