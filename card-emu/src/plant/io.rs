//! The card's digital inputs and outputs as the machine sees them (layout 1.7): what drives
//! each input pin, and a recorder of the compare outputs' pulses.
//!
//! An input pin is either a level the test sets ([`InputBank::set`]; the change happens at
//! the instant of the call, the end of the period the card samples next) or a sensor on an
//! axis's travel ([`Sensor`]: a touch probe hitting a part, a cam switch), active at and
//! beyond a shaft position. A sensor's edge is found within the servo period the way the
//! encoder interface's edge capture sees it: the shaft is stepped again from the period's
//! start on a copy and the crossing instant bisected to 10⁻¹² of the period, so the card gets
//! the true instant (one edge per input and period: a pin that toggles back within one period
//! shows no edge, as a sampled input would not).
//!
//! The output recorder ([`FireRecord`]) measures the compare channels: for each pulse the
//! firmware fires it replays the shaft from the period's start to the pulse's instant, and
//! records where the shaft was then — the figure a scope on the EQU output and a laser
//! interferometer on the axis would give.

use super::Motor;
use crate::firmware::io::DigitalInputs;
use firmware_proto::{INPUTS, MAX_AXES};

/// A switch on an axis's travel driving an input pin.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sensor {
    /// The axis.
    pub axis: usize,
    /// Where it switches, shaft position in encoder counts (unquantised).
    pub at: f64,
    /// Active at and above `at` (`false`: at and below).
    pub active_above: bool,
}

impl Sensor {
    /// Is the pin high with the shaft at `counts`?
    pub fn active(&self, counts: f64) -> bool {
        if self.active_above {
            counts >= self.at
        } else {
            counts <= self.at
        }
    }
}

/// The input pins.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct InputBank {
    levels: u32,
    sensors: [Option<Sensor>; INPUTS],
    /// Bit i: input i has a sensor (the pins a period's motion can switch).
    sensed: u32,
    edge_at: [f64; INPUTS],
    initialised: bool,
}

impl InputBank {
    /// Set input `i`'s pin (a level the test drives; ignored beyond the inputs).
    pub fn set(&mut self, i: usize, high: bool) {
        if i >= INPUTS {
            return;
        }
        self.sensors[i] = None;
        self.sensed &= !(1 << i);
        if self.level(i) != high {
            self.levels ^= 1 << i;
            self.edge_at[i] = 1.0;
        }
    }

    /// Drive input `i` from a sensor on an axis's travel (`None`: back to a level, held).
    pub fn set_sensor(&mut self, i: usize, sensor: Option<Sensor>) {
        if let Some(s) = self.sensors.get_mut(i) {
            *s = sensor;
            self.sensed = (self.sensed & !(1 << i)) | (u32::from(sensor.is_some()) << i);
        }
        self.initialised = false;
    }

    /// Input `i`'s pin.
    pub fn level(&self, i: usize) -> bool {
        self.levels & (1 << i) != 0
    }

    /// The pins, bit i = input i.
    pub fn levels(&self) -> u32 {
        self.levels
    }

    /// The pins for the card's sample, with the instants of the edges in the period just
    /// ended; `motors` are the shafts now.
    pub(crate) fn sample(&mut self, motors: &[Motor; MAX_AXES]) -> DigitalInputs {
        if !self.initialised {
            // A sensor just attached reads its level now (no edge).
            for (i, s) in self.sensors.iter().enumerate() {
                if let Some(s) = s.filter(|s| s.axis < MAX_AXES) {
                    let high = s.active(motors[s.axis].position_counts());
                    self.levels = (self.levels & !(1 << i)) | (u32::from(high) << i);
                }
            }
            self.initialised = true;
        }
        let d = DigitalInputs {
            levels: self.levels,
            edge_at: self.edge_at,
        };
        self.edge_at = [1.0; INPUTS];
        d
    }

    /// The shafts moved over a period of `ts` from `start` to `end`; `replay(axis, motor, dt)`
    /// steps a copy of an axis from the period's start by `dt` as the period did. Sensor
    /// edges inside the period get their instant.
    pub(crate) fn after_period(
        &mut self,
        start: &[Motor; MAX_AXES],
        end: &[Motor; MAX_AXES],
        ts: f64,
        replay: impl Fn(usize, &mut Motor, f64),
    ) {
        if self.sensed == 0 {
            return; // levels only: they change when set, not with the motion
        }
        for i in 0..INPUTS {
            let Some(s) = self.sensors[i].filter(|s| s.axis < MAX_AXES) else {
                continue;
            };
            let high = s.active(end[s.axis].position_counts());
            if high == self.level(i) {
                continue;
            }
            // Bisect the instant the sensor switched.
            let (mut lo, mut hi) = (0.0, 1.0);
            while hi - lo > 1e-12 {
                let mid = 0.5 * (lo + hi);
                let mut m = start[s.axis];
                replay(s.axis, &mut m, mid * ts);
                if s.active(m.position_counts()) == high {
                    hi = mid;
                } else {
                    lo = mid;
                }
            }
            self.levels ^= 1 << i;
            self.edge_at[i] = hi;
        }
    }
}

/// Sub-steps a period is sampled at when the shaft reverses in it.
pub const SPAN_SAMPLES: u32 = 64;

/// The lowest and highest encoder count of a shaft over a period, from `start` to `end`, as the
/// encoder interface counts every edge. With the drive held over the period the shaft's
/// velocity moves monotonically towards one value, stopping at zero where friction holds it:
/// a shaft that did not end the period moving against the way it started (or at rest) moved
/// one way, and the ends are the extremes. One that reversed is sampled on a copy at
/// [`SPAN_SAMPLES`] sub-steps (`replay(motor, dt)` steps it as the period did). An axis at rest
/// or cruising costs nothing.
pub fn encoder_span(
    start: &Motor,
    end: &Motor,
    ts: f64,
    replay: impl Fn(&mut Motor, f64),
) -> (i64, i64) {
    encoder_span_from((start.encoder(), end.encoder()), start, end, ts, replay)
}

/// [`encoder_span`] with the readings at the start and the end (`start.encoder()`,
/// `end.encoder()`) given.
#[inline]
pub fn encoder_span_from(
    (a, b): (i64, i64),
    start: &Motor,
    end: &Motor,
    ts: f64,
    replay: impl Fn(&mut Motor, f64),
) -> (i64, i64) {
    let (lo, hi) = (a.min(b), a.max(b));
    if start.omega * end.omega >= 0.0 {
        return (lo, hi);
    }
    replayed_span(lo, hi, start, ts, replay)
}

/// The span of a period in which the shaft reversed: the period replayed in samples. Out of
/// line: the emulator takes a span of every axis each period, and few of them reverse.
#[inline(never)]
fn replayed_span(
    mut lo: i64,
    mut hi: i64,
    start: &Motor,
    ts: f64,
    replay: impl Fn(&mut Motor, f64),
) -> (i64, i64) {
    let mut m = *start;
    let h = ts / f64::from(SPAN_SAMPLES);
    for _ in 0..SPAN_SAMPLES {
        replay(&mut m, h);
        let n = m.encoder();
        lo = lo.min(n);
        hi = hi.max(n);
    }
    (lo, hi)
}

/// One compare pulse as the output recorder saw it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FireRecord {
    /// The compare channel.
    pub channel: usize,
    /// The output pulsed.
    pub output: usize,
    /// The axis watched.
    pub axis: usize,
    /// The position programmed, counts.
    pub position: f64,
    /// The pulse's instant, emulated seconds since boot.
    pub time: f64,
    /// Where the shaft was at that instant, counts (unquantised).
    pub shaft: f64,
    /// The shaft's velocity then, counts/s.
    pub velocity: f64,
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plant::MotorParams;

    #[test]
    fn a_sensor_edge_gets_its_instant_within_the_period() {
        let mut start = [Motor::new(MotorParams::default_servo()); MAX_AXES];
        start[1].omega = 1e6 / start[1].params.counts_per_rad(); // 10^6 counts/s
        let mut end = start;
        let ts = 1e-4;
        for m in &mut end {
            m.step(0.0, ts);
        }
        let mut bank = InputBank::default();
        bank.set_sensor(
            3,
            Some(Sensor {
                axis: 1,
                at: 30.0,
                active_above: true,
            }),
        );
        let d = bank.sample(&start);
        assert_eq!(d.levels, 0);
        bank.after_period(&start, &end, ts, |_, m, dt| m.step(0.0, dt));
        let d = bank.sample(&end);
        assert_eq!(d.levels, 1 << 3);
        // 30 counts at about 10^6 counts/s: 0.3 of the period (a little later: damping).
        assert!((d.edge_at[3] - 0.3).abs() < 1e-3, "{}", d.edge_at[3]);
        let mut m = start[1];
        m.step(0.0, d.edge_at[3] * ts);
        assert!((m.position_counts() - 30.0).abs() < 1e-6);
        // A shaft that goes over count 30 and back within the period: its span says so.
        let mut up = start[1];
        up.omega = 300.0 / up.params.counts_per_rad(); // 300 counts/s
        up.theta = 29.998 / up.params.counts_per_rad();
        up.disturbance = 3.0; // a hard push back
        let mut back = up;
        back.step(0.0, ts);
        assert_eq!((up.encoder(), back.encoder()), (29, 29));
        let span = encoder_span(&up, &back, ts, |m, dt| m.step(0.0, dt));
        assert_eq!(span, (29, 30));
        let ends = encoder_span(&start[1], &end[1], ts, |_, _| unreachable!());
        assert_eq!(
            ends,
            (0, end[1].encoder()),
            "one way: the ends, nothing replayed"
        );
        bank.set(5, true);
        let d = bank.sample(&end);
        assert_eq!((d.levels, d.edge_at[5]), (1 << 3 | 1 << 5, 1.0));
    }
}
