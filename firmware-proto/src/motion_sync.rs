//! Synchronised motion (layout 1.7): the codes of electronic gearing's commands and events.
//!
//! The opcodes, the event kinds and the nack codes are in [`crate::wire`]'s enums with the
//! others; here are the master sources (the flags of `MC_OP_GEAR_IN`), the sub-cases of
//! `MC_EV_SYNC` and the gear ratio's arithmetic, which host and card share.

use crate::raw;

// The master sources and the codes of `MC_EV_SYNC` and `MC_EV_PVT`, generated from the header's
// defines (`cargo xtask codegen`).
pub use crate::codes::{MasterSource, PvtEvent, SyncEvent};

/// Auxiliary encoder inputs of the card.
pub const AUX_ENCODERS: usize = raw::MC_AUX_ENCODERS as usize;
/// The largest |numerator| and denominator of a gear ratio.
pub const GEAR_RATIO_MAX: f64 = raw::MC_GEAR_RATIO_MAX;
/// A commanded master counts in 1/2^16 of a count (its position is an `f64`).
pub const COMMANDED_SUBCOUNTS: i128 = 1 << 16;

/// Points buffered per axis in a PT/PVT stream.
pub const PVT_LEN: usize = raw::MC_PVT_LEN as usize;
/// Points per `MC_OP_PVT_POINTS` command.
pub const PVT_POINTS_MAX: usize = raw::MC_PVT_POINTS_MAX as usize;
/// `MC_OP_PVT_BEGIN` flag: PT (velocities from the neighbouring points).
pub const PVT_PT: u32 = raw::MC_PVT_PT;
/// `MC_OP_PVT_POINTS` flag: the last point of the command ends the stream.
pub const PVT_LAST: u32 = raw::MC_PVT_LAST;

/// Cam tables the card holds.
pub const CAM_TABLES: usize = raw::MC_CAM_TABLES as usize;
/// Points of a cam table.
pub const CAM_MAX_POINTS: usize = raw::MC_CAM_MAX_POINTS as usize;
/// Points per `MC_OP_CAM_DATA`.
pub const CAM_DATA_MAX: usize = raw::MC_CAM_DATA_MAX as usize;
/// `MC_OP_CAM_TABLE` flag: cubic spline (else linear).
pub const CAM_CUBIC: u32 = raw::MC_CAM_CUBIC;
/// `MC_OP_CAM_TABLE` flag: periodic.
pub const CAM_PERIODIC: u32 = raw::MC_CAM_PERIODIC;
/// `MC_OP_CAM_IN` flag: switch at the end of the current cycle.
pub const CAM_AT_CYCLE_END: u32 = raw::MC_CAM_AT_CYCLE_END;
/// `MC_OP_CAM_IN` flag: PLCopen StartMode relative (the cam starts where the slave stands).
pub const CAM_RELATIVE: u32 = raw::MC_CAM_RELATIVE;

impl MasterSource {
    /// The flags word.
    pub fn to_raw(self) -> u32 {
        self as u32
    }
}

/// A gear ratio: slave counts per master count, `num / den`, both integers.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct GearRatio {
    /// Numerator, nonzero, |num| ≤ [`GEAR_RATIO_MAX`].
    pub num: i64,
    /// Denominator, 1..=[`GEAR_RATIO_MAX`].
    pub den: i64,
}

impl GearRatio {
    /// The ratio of two command arguments: `None` unless both are integers, the numerator
    /// nonzero, the denominator positive, and both of magnitude ≤ [`GEAR_RATIO_MAX`] (NaN and
    /// infinities included).
    pub fn from_args(num: f64, den: f64) -> Option<Self> {
        let int = |x: f64| x.is_finite() && x % 1.0 == 0.0 && x.abs() <= GEAR_RATIO_MAX;
        (int(num) && int(den) && num != 0.0 && den > 0.0).then_some(Self {
            num: num as i64,
            den: den as i64,
        })
    }

    /// The ratio as a float.
    pub fn as_f64(&self) -> f64 {
        self.num as f64 / self.den as f64
    }

    /// The slave's distance for `dm` master units of which `per_count` make one count, as the
    /// integer quotient and the remainder over `den · per_count`: `num · dm = q · den' + r`,
    /// `0 ≤ r < den'` (Euclidean). Exact for any |dm| < 2^95.
    pub fn divide(&self, dm: i128, per_count: i128) -> (i128, i128) {
        let den = self.den as i128 * per_count;
        let n = self.num as i128 * dm;
        (n.div_euclid(den), n.rem_euclid(den))
    }

    /// [`GearRatio::divide`] as counts: `q + r / den'`. The integer part is exact up to 2^53
    /// counts; the fraction is rounded once.
    pub fn distance(&self, dm: i128, per_count: i128) -> f64 {
        let (q, r) = self.divide(dm, per_count);
        q as f64 + r as f64 / (self.den as i128 * per_count) as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ratios_from_args() {
        assert_eq!(
            GearRatio::from_args(3.0, 7.0),
            Some(GearRatio { num: 3, den: 7 })
        );
        assert_eq!(
            GearRatio::from_args(-3.0, 7.0),
            Some(GearRatio { num: -3, den: 7 })
        );
        for (n, d) in [
            (0.0, 1.0),
            (1.0, 0.0),
            (1.0, -2.0),
            (1.5, 2.0),
            (1.0, f64::NAN),
            (f64::INFINITY, 1.0),
            (1e300, 1.0),
            (1.0, 4e9),
            (f64::MIN_POSITIVE / 4.0, 1.0),
        ] {
            assert_eq!(GearRatio::from_args(n, d), None, "{n} / {d}");
        }
    }

    /// 10^9 master counts at 3/7 and at 2^31-1 / 2^31-2: the quotient and remainder are
    /// what the ratio says, exactly; a sum of per-tick float increments drifts.
    #[test]
    fn no_drift_after_a_billion_counts() {
        let r = GearRatio { num: 3, den: 7 };
        assert_eq!(r.divide(1_000_000_000, 1), (428_571_428, 4));
        assert_eq!(r.divide(-1_000_000_000, 1), (-428_571_429, 3));
        let big = GearRatio {
            num: 2_147_483_647,
            den: 2_147_483_646,
        };
        let (q, rem) = big.divide(1_000_000_000, 1);
        assert_eq!(q * 2_147_483_646 + rem, 2_147_483_647 * 1_000_000_000);
        // A commanded master in 1/65536 counts.
        let (q, rem) = r.divide(1_000_000_000 * COMMANDED_SUBCOUNTS, COMMANDED_SUBCOUNTS);
        assert_eq!((q, rem), (428_571_428, 4 * COMMANDED_SUBCOUNTS));
        // The per-tick float sum of 1000 counts per tick: off after 10^6 ticks.
        let mut naive = 0.0f64;
        for _ in 0..1_000_000 {
            naive += 1000.0 * r.as_f64();
        }
        assert_ne!(naive, r.distance(1_000_000_000, 1));
    }
}
