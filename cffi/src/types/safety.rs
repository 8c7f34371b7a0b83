//! Safety: stop categories and reasons, the card's safety status, an axis's safety settings.

use crate::codes::{MC_STOP_CATEGORY_0, MC_STOP_CATEGORY_1, MC_STOP_CATEGORY_2};
use crate::result::Failure;
use motioncard_sdk::ErrorKind;
use motioncard_sdk::{SafetySettings, SafetyStatus, StopCategory, StopInfo};

/// The stop category of an `MC_STOP_CATEGORY_` value; any other value is
/// `MC_ERR_BAD_CATEGORY`, the code the card gives for one.
pub(crate) fn stop_category(v: u32) -> Result<StopCategory, Failure> {
    match v {
        MC_STOP_CATEGORY_0 => Ok(StopCategory::Cat0),
        MC_STOP_CATEGORY_1 => Ok(StopCategory::Cat1),
        MC_STOP_CATEGORY_2 => Ok(StopCategory::Cat2),
        v => Err(Failure::new(
            ErrorKind::BadCategory.code(),
            format!("unknown stop category {v}: expected MC_STOP_CATEGORY_0, _1 or _2"),
        )),
    }
}

/// The card-wide safety state (`mc_get_safety_status`). Flags are 0 or 1.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[allow(non_camel_case_types)]
pub struct mc_safety_status {
    /// The host watchdog tripped; latched until `mc_reset_faults`.
    pub watchdog_tripped: u32,
    /// The host's e-stop (`mc_estop`) is latched.
    pub estop_command: u32,
    /// The e-stop input tripped; latched until reset with the input released.
    pub estop_input: u32,
    /// The watchdog is watching: a session is attached (armed by its open, disarmed by its
    /// close). Outside a session the card takes no motion (`MC_ERR_NO_SESSION`).
    pub watchdog_armed: u32,
    /// Servo tick at which the card last saw the heartbeat change.
    pub last_heartbeat_tick: u64,
    /// Servo tick of the last watchdog trip (0: never).
    pub watchdog_trip_tick: u64,
    /// The tick of the last heartbeat the card saw before that trip.
    pub trip_heartbeat_tick: u64,
    /// Protocol errors (corrupt ring indices) the card detected since boot.
    pub protocol_errors: u32,
    /// The session id of the program attached to the card (this one's while it is open).
    pub session: u32,
    /// Programs that opened the card while another's session was still open, since boot (each
    /// stopped the motion the vanished program left).
    pub host_changes: u32,
    /// Heartbeats that came later than the declared period after the one before, since this
    /// program opened the card: how close it runs to its watchdog.
    pub late_heartbeats: u32,
    /// The longest gap between two heartbeats the card saw since this program opened it, µs.
    pub max_heartbeat_gap_us: u32,
    /// Servo tick of the last open (this program's, while it is open).
    pub attach_tick: u64,
}

impl From<SafetyStatus> for mc_safety_status {
    fn from(s: SafetyStatus) -> Self {
        Self {
            watchdog_tripped: s.watchdog_tripped.into(),
            estop_command: s.estop_command.into(),
            estop_input: s.estop_input.into(),
            watchdog_armed: s.watchdog_armed.into(),
            last_heartbeat_tick: s.last_heartbeat_tick,
            watchdog_trip_tick: s.watchdog_trip_tick,
            trip_heartbeat_tick: s.trip_heartbeat_tick,
            protocol_errors: s.protocol_errors,
            session: s.session,
            host_changes: s.host_changes,
            late_heartbeats: s.late_heartbeats,
            max_heartbeat_gap_us: u32::try_from(s.max_heartbeat_gap.as_micros())
                .unwrap_or(u32::MAX),
            attach_tick: s.attach_tick,
        }
    }
}

/// An axis's safety configuration (`mc_configure_safety`), in user units (see `mc_set_scale`).
/// Start from `mc_safety_settings_default`. Flags: non-zero is on.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[allow(non_camel_case_types)]
pub struct mc_safety_settings {
    /// Enforce `soft_limit_neg` .. `soft_limit_pos` (off by default).
    pub soft_limits: u32,
    /// Honour the limit switch inputs.
    pub hard_limits: u32,
    /// Honour the amplifier alarm input.
    pub amp_alarm: u32,
    /// Honour encoder loss and jumps.
    pub encoder_checks: u32,
    /// The stop a hard or soft limit makes (`MC_STOP_CATEGORY_`).
    pub limit_stop: u32,
    /// Negative soft limit (used when `soft_limits` is on; 0 in the defaults).
    pub soft_limit_neg: f64,
    /// Positive soft limit (used when `soft_limits` is on; 0 in the defaults).
    pub soft_limit_pos: f64,
    /// Following-error limit at `max_velocity` (LinuxCNC FERROR); the limit at velocity v is
    /// `max(ferror * |v| / max_velocity, min_ferror)`.
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

impl mc_safety_settings {
    pub(crate) fn to_sdk(self) -> Result<SafetySettings, Failure> {
        Ok(SafetySettings {
            soft_limits: (self.soft_limits != 0)
                .then_some((self.soft_limit_neg, self.soft_limit_pos)),
            hard_limits: self.hard_limits != 0,
            amp_alarm: self.amp_alarm != 0,
            encoder_checks: self.encoder_checks != 0,
            limit_stop: stop_category(self.limit_stop)?,
            ferror: self.ferror,
            min_ferror: self.min_ferror,
            max_velocity: self.max_velocity,
            stop_deceleration: self.stop_deceleration,
            stop_jerk: self.stop_jerk,
            encoder_max_velocity: self.encoder_max_velocity,
        })
    }
}

impl From<SafetySettings> for mc_safety_settings {
    fn from(s: SafetySettings) -> Self {
        let (neg, pos) = s.soft_limits.unwrap_or((0.0, 0.0));
        Self {
            soft_limits: s.soft_limits.is_some().into(),
            hard_limits: s.hard_limits.into(),
            amp_alarm: s.amp_alarm.into(),
            encoder_checks: s.encoder_checks.into(),
            limit_stop: s.limit_stop as u32,
            soft_limit_neg: neg,
            soft_limit_pos: pos,
            ferror: s.ferror,
            min_ferror: s.min_ferror,
            max_velocity: s.max_velocity,
            stop_deceleration: s.stop_deceleration,
            stop_jerk: s.stop_jerk,
            encoder_max_velocity: s.encoder_max_velocity,
        }
    }
}

/// How an axis's last safety stop went, measured by the card (`mc_get_stop_info`).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[allow(non_camel_case_types)]
pub struct mc_stop_info {
    /// Why the last motion ended (`MC_STOP_REASON_` value).
    pub reason: u32,
    /// 1 when the axis has come to rest after its last safety stop (`rest_tick` is valid), 0
    /// while it is still stopping or when there was none.
    pub at_rest: u32,
    /// Servo tick at which the last safety stop began (0: none since boot).
    pub stop_tick: u64,
    /// Servo tick at which the axis came to rest after it (0 while still stopping).
    pub rest_tick: u64,
    /// Planned duration of the stop's deceleration ramp, s (0 for category 0).
    pub ramp_time: f64,
}

impl From<StopInfo> for mc_stop_info {
    fn from(i: StopInfo) -> Self {
        Self {
            reason: i.reason as u32,
            at_rest: i.rest_tick.is_some().into(),
            stop_tick: i.stop_tick,
            rest_tick: i.rest_tick.unwrap_or(0),
            ramp_time: i.ramp_time.as_secs_f64(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::codes::MC_STOP_REASON_SOFT_LIMIT_NEG;
    use motioncard_sdk::StopReason;

    #[test]
    fn stop_categories_round_trip() {
        for c in StopCategory::ALL {
            assert_eq!(stop_category(*c as u32).unwrap(), *c);
        }
    }

    #[test]
    fn safety_types_round_trip_and_unknown_categories_are_refused() {
        let d = SafetySettings::default();
        let c = mc_safety_settings::from(d);
        assert_eq!((c.soft_limits, c.hard_limits), (0, 1));
        assert_eq!(c.to_sdk().unwrap(), d);
        let s = SafetySettings {
            soft_limits: Some((-5.0, 7.0)),
            hard_limits: false,
            amp_alarm: false,
            encoder_checks: false,
            limit_stop: StopCategory::Cat2,
            ..d
        };
        let c = mc_safety_settings::from(s);
        assert_eq!(c.limit_stop, MC_STOP_CATEGORY_2);
        assert_eq!(c.to_sdk().unwrap(), s);
        // Any non-zero flag is on.
        let on = mc_safety_settings {
            hard_limits: 7,
            soft_limits: 0xFFFF_FFFF,
            ..c
        }
        .to_sdk()
        .unwrap();
        assert!(on.hard_limits && on.soft_limits == Some((-5.0, 7.0)));
        for v in [3, 4, u32::MAX] {
            let bad = mc_safety_settings { limit_stop: v, ..c };
            assert_eq!(
                bad.to_sdk().unwrap_err().code,
                ErrorKind::BadCategory.code(),
                "{v}"
            );
            assert_eq!(
                stop_category(v).unwrap_err().code,
                ErrorKind::BadCategory.code()
            );
        }
        let info = mc_stop_info::from(StopInfo {
            reason: StopReason::SoftLimitNeg,
            stop_tick: 10,
            rest_tick: None,
            ramp_time: std::time::Duration::from_millis(20),
        });
        assert_eq!(
            info,
            mc_stop_info {
                reason: MC_STOP_REASON_SOFT_LIMIT_NEG,
                at_rest: 0,
                stop_tick: 10,
                rest_tick: 0,
                ramp_time: 0.02
            }
        );
    }
}
