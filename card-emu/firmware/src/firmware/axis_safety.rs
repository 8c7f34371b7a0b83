//! An axis's safety configuration and state: the limits, the following-error rule (LinuxCNC's
//! FERROR and MIN_FERROR), the stop ramp, the stop in progress, the latched faults; and the
//! starvation rule. Plain data the axis carries; the safety layer (`safety.rs`) acts on it.

use crate::motion::scurve::{plan_stop, Profile, State};
use firmware_proto::{raw, AxisSafetyFlags, Faults, Io, NackCode, StopCategory, StopReason};

/// The validated copy of an axis's safety configuration (counts, seconds).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AxisSafetyConfig {
    /// The checks the axis makes.
    pub flags: AxisSafetyFlags,
    /// The stop a hard or soft limit makes.
    pub limit_category: StopCategory,
    /// Soft limits, counts (enforced with `MC_AXSAFE_SOFT_LIMITS`).
    pub soft_limit_neg: f64,
    /// Soft limits, counts.
    pub soft_limit_pos: f64,
    /// LinuxCNC FERROR: the following-error limit at `max_velocity`, counts.
    pub ferror: f64,
    /// LinuxCNC MIN_FERROR: the limit at rest, counts.
    pub min_ferror: f64,
    /// The velocity FERROR applies at, counts/s.
    pub max_velocity: f64,
    /// Deceleration of category 1 and 2 stops, counts/s².
    pub stop_decel: f64,
    /// Jerk of those stops, counts/s³.
    pub stop_jerk: f64,
    /// Fastest physically possible encoder velocity, counts/s: a larger change in one tick is
    /// an encoder jump.
    pub encoder_max_velocity: f64,
}

impl AxisSafetyConfig {
    /// The register block (`mc_axis_safety`) that holds this configuration.
    pub fn to_block(&self) -> raw::mc_axis_safety {
        raw::mc_axis_safety {
            flags: self.flags.bits(),
            limit_category: self.limit_category as u32,
            soft_limit_neg: self.soft_limit_neg,
            soft_limit_pos: self.soft_limit_pos,
            ferror: self.ferror,
            min_ferror: self.min_ferror,
            max_velocity: self.max_velocity,
            stop_decel: self.stop_decel,
            stop_jerk: self.stop_jerk,
            encoder_max_velocity: self.encoder_max_velocity,
            ..Default::default()
        }
    }

    /// Decode a register block (validated by the caller); an unknown stop category is
    /// `BadCategory`.
    pub fn from_block(b: &raw::mc_axis_safety) -> Result<Self, NackCode> {
        Ok(Self {
            flags: AxisSafetyFlags::from_bits_retain(b.flags),
            limit_category: StopCategory::from_raw(b.limit_category)
                .ok_or(NackCode::BadCategory)?,
            soft_limit_neg: b.soft_limit_neg,
            soft_limit_pos: b.soft_limit_pos,
            ferror: b.ferror,
            min_ferror: b.min_ferror,
            max_velocity: b.max_velocity,
            stop_decel: b.stop_decel,
            stop_jerk: b.stop_jerk,
            encoder_max_velocity: b.encoder_max_velocity,
        })
    }
}

impl Default for AxisSafetyConfig {
    /// For the default plant (10,000 counts/rev, about 9.5·10⁶ counts/s² at full output):
    /// FERROR one revolution at 10⁶ counts/s (6,000 rpm), MIN_FERROR 0.1 revolution, stops at
    /// 5·10⁶ counts/s² and 5·10⁸ counts/s³, encoder jumps beyond 5·10⁷ counts/s.
    fn default() -> Self {
        Self {
            flags: DEFAULT_FLAGS,
            limit_category: StopCategory::Cat1,
            soft_limit_neg: -crate::MAX_POSITION,
            soft_limit_pos: crate::MAX_POSITION,
            ferror: 10_000.0,
            min_ferror: 1_000.0,
            max_velocity: 1e6,
            stop_decel: 5e6,
            stop_jerk: 5e8,
            encoder_max_velocity: 5e7,
        }
    }
}

impl AxisSafetyConfig {
    /// Check every field.
    pub fn validate(&self) -> Result<(), NackCode> {
        let all = [
            self.soft_limit_neg,
            self.soft_limit_pos,
            self.ferror,
            self.min_ferror,
            self.max_velocity,
            self.stop_decel,
            self.stop_jerk,
            self.encoder_max_velocity,
        ];
        if !AxisSafetyFlags::all().contains(self.flags) || all.iter().any(|x| !x.is_finite()) {
            return Err(NackCode::BadConfig);
        }
        let positive = [
            self.min_ferror,
            self.max_velocity,
            self.stop_decel,
            self.stop_jerk,
            self.encoder_max_velocity,
        ];
        if positive.iter().any(|x| *x <= 0.0)
            || self.ferror < self.min_ferror
            || self.soft_limit_neg >= self.soft_limit_pos
        {
            return Err(NackCode::BadConfig);
        }
        Ok(())
    }

    /// [`AxisSafetyConfig::validate`], then what depends on the card: the velocities and the
    /// stop ramp within [`firmware_proto::limit_range`] at `rate_hz` (`LimitRange`), and the
    /// stop from `max_velocity` within `max_stop_time` s (`StopTooLong`).
    pub fn validate_on_card(&self, rate_hz: u32, max_stop_time: f64) -> Result<(), NackCode> {
        self.validate()?;
        let in_range = |order, x: f64| firmware_proto::limit_range(order, rate_hz).contains(&x);
        if !(in_range(1, self.max_velocity)
            && in_range(1, self.encoder_max_velocity)
            && in_range(2, self.stop_decel)
            && in_range(3, self.stop_jerk))
        {
            return Err(NackCode::LimitRange);
        }
        if self.stop_time_from(self.max_velocity) > max_stop_time {
            return Err(NackCode::StopTooLong);
        }
        Ok(())
    }

    /// How long the stop ramp takes from velocity `v` at zero acceleration, s (infinite if it
    /// cannot be planned).
    pub fn stop_time_from(&self, v: f64) -> f64 {
        plan_stop(0.0, v, 0.0, self.stop_decel, self.stop_jerk)
            .map_or(f64::INFINITY, |p| p.duration())
    }

    /// LinuxCNC's following-error limit at commanded velocity `v`:
    /// `FERROR · |v| / v_max`, never below `MIN_FERROR`.
    pub fn ferror_limit(&self, v: f64) -> f64 {
        (self.ferror * v.abs() / self.max_velocity).max(self.min_ferror)
    }

    /// Is the following error `ferr` within [`AxisSafetyConfig::ferror_limit`] at `v`? The
    /// limit is never below `MIN_FERROR`, so an error within that needs no division (most
    /// ticks of most axes). NaN is not within.
    #[inline]
    pub fn ferror_within(&self, ferr: f64, v: f64) -> bool {
        let e = ferr.abs();
        e <= self.min_ferror || e <= self.ferror_limit(v)
    }

    pub(crate) fn has(&self, flag: AxisSafetyFlags) -> bool {
        self.flags.intersects(flag)
    }
}

/// A safety stop in progress or held.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ActiveStop {
    /// Its category.
    pub category: StopCategory,
    /// Tick it began.
    pub started: u64,
    /// Planned duration of its ramp, s (0 for category 0).
    pub ramp: f64,
    /// The axis has reached rest since.
    pub at_rest: bool,
}

/// One axis's safety configuration and state (a field of [`Axis`](crate::firmware::axis::Axis)).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AxisSafety {
    /// Active configuration.
    pub config: AxisSafetyConfig,
    /// Why the last motion ended.
    pub stop_reason: StopReason,
    /// The safety stop in progress or held, if any.
    pub stop: Option<ActiveStop>,
    /// In ErrorStop: the drive is still powered (a category 1 ramp, or category 2 holding).
    pub powered: bool,
    /// Latched and live safety fault bits (`MC_FAULT_*`, bits 8..31).
    pub faults: Faults,
    /// The inputs and drive-enable output of the last tick.
    pub io: Io,
    pub(crate) last_encoder: Option<i64>,
}

impl Default for AxisSafety {
    fn default() -> Self {
        Self::new()
    }
}

/// Fault bits that follow their input (or position) instead of latching.
pub(crate) const LIVE_FAULTS: Faults = Faults::HARD_LIMIT_POS
    .union(Faults::HARD_LIMIT_NEG)
    .union(Faults::SOFT_LIMIT_POS)
    .union(Faults::SOFT_LIMIT_NEG);

/// Every check but the soft limits (which need limits the host sets).
const DEFAULT_FLAGS: AxisSafetyFlags =
    AxisSafetyFlags::all().difference(AxisSafetyFlags::SOFT_LIMITS);

impl AxisSafety {
    /// Defaults, no stop.
    pub const fn new() -> Self {
        Self {
            config: AxisSafetyConfig {
                flags: DEFAULT_FLAGS,
                limit_category: StopCategory::Cat1,
                soft_limit_neg: -crate::MAX_POSITION,
                soft_limit_pos: crate::MAX_POSITION,
                ferror: 10_000.0,
                min_ferror: 1_000.0,
                max_velocity: 1e6,
                stop_decel: 5e6,
                stop_jerk: 5e8,
                encoder_max_velocity: 5e7,
            },
            stop_reason: StopReason::None,
            stop: None,
            powered: false,
            faults: Faults::empty(),
            io: Io::empty(),
            last_encoder: None,
        }
    }

    /// MC_Reset (the checks were made by
    /// [`Safety::check_command`](crate::firmware::safety::Safety::check_command)): clear the
    /// latches and the stop. Returns whether the drive is still powered.
    pub(crate) fn reset(&mut self) -> bool {
        self.faults &= LIVE_FAULTS;
        self.stop = None;
        core::mem::take(&mut self.powered)
    }
}

/// The starvation rule: a profile that ends moving with nothing queued after it continues as a
/// jerk-limited stop from its end state with the axis's stop ramp. `None` if even that cannot
/// be planned (then the axis holds the end position: it cannot happen with a validated
/// configuration).
///
/// A motion queue calls this when it runs dry: with the state (position, velocity,
/// acceleration) at the end of the last queued segment, it replaces the missing successor with
/// the returned profile and sets the stop reason to `StopReason::Starvation`.
pub fn starvation_stop(safety: &AxisSafety, end: &State) -> Option<Profile> {
    let c = &safety.config;
    plan_stop(end.pos, end.vel, end.acc, c.stop_decel, c.stop_jerk).ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ferror_limit_is_linuxcnc_rule() {
        let c = AxisSafetyConfig {
            ferror: 100.0,
            min_ferror: 10.0,
            max_velocity: 1000.0,
            ..AxisSafetyConfig::default()
        };
        assert_eq!(c.ferror_limit(0.0), 10.0);
        assert_eq!(c.ferror_limit(50.0), 10.0);
        assert_eq!(c.ferror_limit(-500.0), 50.0);
        assert_eq!(c.ferror_limit(2000.0), 200.0);
        // Within, at and beyond each side of the limit, and NaN.
        for (ferr, v, within) in [
            (10.0, 0.0, true),
            (-10.0, 50.0, true),
            (10.5, 50.0, false),
            (-50.0, -500.0, true),
            (50.5, -500.0, false),
            (200.0, 2000.0, true),
            (-200.1, 2000.0, false),
            (f64::NAN, 0.0, false),
            (f64::NAN, 2000.0, false),
        ] {
            assert_eq!(c.ferror_within(ferr, v), within, "{ferr} at {v}");
            assert_eq!(ferr.abs() <= c.ferror_limit(v), within, "{ferr} at {v}");
        }
    }

    #[test]
    fn defaults_validate_and_garbage_does_not() {
        assert_eq!(AxisSafetyConfig::default().validate(), Ok(()));
        assert_eq!(AxisSafety::new().config, AxisSafetyConfig::default());
        let bad = [
            AxisSafetyConfig {
                ferror: f64::NAN,
                ..Default::default()
            },
            AxisSafetyConfig {
                min_ferror: 0.0,
                ..Default::default()
            },
            AxisSafetyConfig {
                ferror: 1.0,
                min_ferror: 2.0,
                ..Default::default()
            },
            AxisSafetyConfig {
                soft_limit_neg: 5.0,
                soft_limit_pos: 5.0,
                ..Default::default()
            },
            AxisSafetyConfig {
                flags: AxisSafetyFlags::from_bits_retain(1 << 9),
                ..Default::default()
            },
            AxisSafetyConfig {
                stop_jerk: -1.0,
                ..Default::default()
            },
        ];
        for c in bad {
            assert_eq!(c.validate(), Err(NackCode::BadConfig), "{c:?}");
        }
    }
}
