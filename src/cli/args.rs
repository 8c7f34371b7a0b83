//! What several subcommands' arguments share: the limits of a move, the move that exercises a
//! compare, a probe or a coupling, a slave's limits while it engages; and the value parsers
//! that check a number's range. clap runs them as it parses, so a bad value is refused (exit
//! status 2, naming the argument and what it must be) before any card is opened.
//!
//! Ranges fixed by the command line or by the register map (the same on every card) are
//! clap's. An index of something on the card (an axis, an output or input, a channel, a cam
//! table, a homing method) and the override factor are left to the card, which refuses them
//! with its reason (exit status 1): how many axes a card has is the card's to say.

use crate::MoveLimits;
use clap::Args;
use std::time::Duration;

/// A value parser: what clap calls with an argument's text.
pub trait Parse<T>: Fn(&str) -> Result<T, String> + Clone + Send + Sync + 'static {}
impl<T, F: Fn(&str) -> Result<T, String> + Clone + Send + Sync + 'static> Parse<T> for F {}

/// `s` as a finite number; `what` names the argument. The messages quote the text given.
fn number(what: &str, s: &str) -> Result<f64, String> {
    let v: f64 = s
        .parse()
        .map_err(|e| format!("{what} must be a number: {e}"))?;
    if v.is_finite() {
        Ok(v)
    } else {
        Err(format!("{what} must be a finite number, got {s}"))
    }
}

/// Any finite number.
pub fn finite(what: &'static str) -> impl Parse<f64> {
    move |s| number(what, s)
}

/// A finite number greater than zero (a limit, a feed, a scale).
pub fn positive(what: &'static str) -> impl Parse<f64> {
    move |s| {
        let v = number(what, s)?;
        if v > 0.0 {
            Ok(v)
        } else {
            Err(format!("{what} must be greater than zero, got {s}"))
        }
    }
}

/// A finite number, 0 or more (a tolerance).
pub fn non_negative(what: &'static str) -> impl Parse<f64> {
    move |s| {
        let v = number(what, s)?;
        if v >= 0.0 {
            Ok(v)
        } else {
            Err(format!("{what} must be 0 or more, got {s}"))
        }
    }
}

/// Seconds, 0 or more (greater than 0 with `positive`), as a duration.
fn seconds(what: &str, s: &str, positive: bool) -> Result<Duration, String> {
    let bound = if positive { "> 0" } else { ">= 0" };
    let v: f64 = s
        .parse()
        .map_err(|e| format!("{what} must be a number of seconds: {e}"))?;
    if v.is_nan() || v < 0.0 || (positive && v == 0.0) {
        return Err(format!(
            "{what} must be a number of seconds {bound}, got {s}"
        ));
    }
    Duration::try_from_secs_f64(v).map_err(|_| {
        format!(
            "{what} must be at most {:.1e} seconds, got {s}",
            u64::MAX as f64
        )
    })
}

/// A time in seconds, 0 or more (how long to hold or watch).
pub fn duration(what: &'static str) -> impl Parse<Duration> {
    move |s| seconds(what, s, false)
}

/// A time in seconds, greater than 0 (an interval, a timeout).
pub fn positive_duration(what: &'static str) -> impl Parse<Duration> {
    move |s| seconds(what, s, true)
}

/// Limits of a move, in the axis's units (counts unless the program set a scale).
#[derive(Args, Clone, Copy)]
pub struct MoveArgs {
    /// Maximum velocity (position moves).
    #[arg(
        long,
        allow_negative_numbers = true,
        default_value_t = 100_000.0,
        value_parser = positive("--vmax")
    )]
    pub vmax: f64,
    /// Maximum acceleration.
    #[arg(
        long,
        allow_negative_numbers = true,
        default_value_t = 1e6,
        value_parser = positive("--amax")
    )]
    pub amax: f64,
    /// Maximum deceleration (default: --amax).
    #[arg(long, allow_negative_numbers = true, value_parser = positive("--dmax"))]
    pub dmax: Option<f64>,
    /// Jerk.
    #[arg(
        long,
        allow_negative_numbers = true,
        default_value_t = 5e7,
        value_parser = positive("--jmax")
    )]
    pub jmax: f64,
}

impl MoveArgs {
    /// The limits, the deceleration --amax unless --dmax.
    pub fn limits(&self) -> MoveLimits {
        MoveLimits::new(self.vmax, self.amax, self.jmax)
            .deceleration(self.dmax.unwrap_or(self.amax))
    }
}

/// The move that exercises a compare, a probe or a coupling, and how long to watch without
/// one.
#[derive(Args, Clone, Copy)]
pub struct TravelArgs {
    /// Move the axis (compare, probe) or the master axis (gear, cam) to this absolute
    /// position, and watch until it is there.
    #[arg(
        long = "move",
        allow_negative_numbers = true,
        value_name = "TARGET",
        value_parser = finite("--move")
    )]
    pub target: Option<f64>,
    #[command(flatten)]
    pub limits: MoveArgs,
    /// Without --move: seconds to watch.
    #[arg(
        long = "for",
        default_value = "1",
        allow_negative_numbers = true,
        value_parser = duration("--for")
    )]
    pub hold: Duration,
    /// Power the axes on first if they are disabled. compare, probe, gear and cam power only
    /// the axes they move, once what they arm or load is accepted, and power them off again
    /// when they end, however they end.
    #[arg(long)]
    pub enable: bool,
}

/// A slave's limits while it engages (gear, cam).
#[derive(Args, Clone, Copy)]
pub struct SyncArgs {
    /// The slave's velocity limit while it catches up.
    #[arg(
        long,
        allow_negative_numbers = true,
        default_value_t = 1e6,
        value_parser = positive("--slave-vmax")
    )]
    pub slave_vmax: f64,
    /// The slave's acceleration limit.
    #[arg(
        long,
        allow_negative_numbers = true,
        default_value_t = 1e7,
        value_parser = positive("--slave-amax")
    )]
    pub slave_amax: f64,
    /// The slave's jerk limit.
    #[arg(
        long,
        allow_negative_numbers = true,
        default_value_t = 1e9,
        value_parser = positive("--slave-jmax")
    )]
    pub slave_jmax: f64,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_are_refused_outside_their_range_with_the_argument_named() {
        assert_eq!(positive("--vmax")("2e5"), Ok(2e5));
        assert_eq!(
            positive("--vmax")("0"),
            Err("--vmax must be greater than zero, got 0".into())
        );
        assert_eq!(
            positive("--vmax")("NaN"),
            Err("--vmax must be a finite number, got NaN".into())
        );
        assert!(positive("--vmax")("x")
            .unwrap_err()
            .starts_with("--vmax must be a number"));
        assert_eq!(non_negative("--tolerance")("0"), Ok(0.0));
        assert_eq!(
            non_negative("--tolerance")("-1e-9"),
            Err("--tolerance must be 0 or more, got -1e-9".into())
        );
        assert_eq!(
            finite("--at")("-inf"),
            Err("--at must be a finite number, got -inf".into())
        );
        assert_eq!(duration("--for")("0"), Ok(Duration::ZERO));
        assert_eq!(duration("--for")("1.5"), Ok(Duration::from_millis(1500)));
        for bad in ["-1", "NaN"] {
            assert_eq!(
                duration("--for")(bad),
                Err(format!("--for must be a number of seconds >= 0, got {bad}"))
            );
        }
        assert_eq!(
            positive_duration("--timeout")("0"),
            Err("--timeout must be a number of seconds > 0, got 0".into())
        );
        // Duration::from_secs_f64 would panic on these.
        for huge in ["1e300", "inf"] {
            assert_eq!(
                duration("--for")(huge),
                Err(format!("--for must be at most 1.8e19 seconds, got {huge}"))
            );
        }
    }
}
