//! Fault injection: what the tests do to the card's surroundings. Each injected fault acts
//! where it would on a machine (a switch input, the amplifier, the encoder signal, the motor
//! shaft), never inside the firmware, which sees only its inputs and encoder counts.
//!
//! Reach it through [`crate::Emulator::faults`] (in-process cards: `Sim::with_emulator`).
//! Stopping the host's heartbeat is the host's business: the SDK's `Card::set_heartbeat`;
//! killing the host is a process kill.

use crate::firmware::safety::Inputs;
use crate::plant::{Motor, Reading, Switches};
use firmware_proto::{Io, MAX_AXES};

/// A limit switch's direction.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Direction {
    /// The positive end of travel.
    Positive,
    /// The negative end of travel.
    Negative,
}

/// What is injected on one axis.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct AxisFaults {
    /// The switches along the travel.
    pub switches: Switches,
    /// Limit switches forced active (a tripped switch, a broken wire), positive and negative.
    pub forced_limits: [bool; 2],
    /// The amplifier's alarm output.
    pub alarm: bool,
    /// Encoder lost: the line-break detector fires and the count freezes where it was.
    pub encoder_lost: Option<i64>,
    /// Added to the encoder count (a corrupted counter: a jump when it changes).
    pub encoder_offset: i64,
    /// The amplifier saturates at this fraction of its input range (a weak or failing drive).
    pub saturation: Option<f64>,
    /// The shaft is jammed (a crash, a brake that did not release): it does not move.
    pub stalled: bool,
}

/// The fault injector of a card.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct FaultInjector {
    axes: [AxisFaults; MAX_AXES],
    estop: bool,
}

impl FaultInjector {
    fn axis(&mut self, axis: usize) -> Option<&mut AxisFaults> {
        self.axes.get_mut(axis)
    }

    /// What is injected on `axis`.
    pub fn get(&self, axis: usize) -> Option<&AxisFaults> {
        self.axes.get(axis)
    }

    /// Place the limit and home switches of `axis`.
    pub fn set_switches(&mut self, axis: usize, switches: Switches) {
        if let Some(a) = self.axis(axis) {
            a.switches = switches;
        }
    }

    /// Force a limit switch active (`true`) or let it follow the position again.
    pub fn trip_limit(&mut self, axis: usize, dir: Direction, active: bool) {
        if let Some(a) = self.axis(axis) {
            a.forced_limits[(dir == Direction::Negative) as usize] = active;
        }
    }

    /// Raise or clear the amplifier alarm.
    pub fn set_alarm(&mut self, axis: usize, on: bool) {
        if let Some(a) = self.axis(axis) {
            a.alarm = on;
        }
    }

    /// Lose the encoder signal (`true`), or restore it.
    pub fn lose_encoder(&mut self, axis: usize, lost: bool, motor: &Motor) {
        if let Some(a) = self.axis(axis) {
            a.encoder_lost = lost.then(|| motor.encoder() + a.encoder_offset);
        }
    }

    /// Corrupt the encoder count: it jumps by `counts` (and stays offset).
    pub fn corrupt_encoder(&mut self, axis: usize, counts: i64) {
        if let Some(a) = self.axis(axis) {
            a.encoder_offset = a.encoder_offset.wrapping_add(counts);
        }
    }

    /// Saturate the amplifier at `fraction` of its range (`None`: healthy).
    pub fn saturate(&mut self, axis: usize, fraction: Option<f64>) {
        if let Some(a) = self.axis(axis) {
            a.saturation = fraction.map(|f| {
                if f.is_finite() {
                    f.clamp(0.0, 1.0)
                } else {
                    0.0
                }
            });
        }
    }

    /// Jam the shaft of `axis` (or free it).
    pub fn stall(&mut self, axis: usize, stalled: bool) {
        if let Some(a) = self.axis(axis) {
            a.stalled = stalled;
        }
    }

    /// Press (`true`) or release the e-stop input.
    pub fn set_estop(&mut self, pressed: bool) {
        self.estop = pressed;
    }

    /// Sample what the card sees this tick: fills the encoder counts and returns the inputs.
    pub fn sense(&self, motors: &[Motor; MAX_AXES], enc: &mut [i64; MAX_AXES]) -> Inputs {
        let readings = core::array::from_fn(|i| motors[i].reading());
        self.sense_counts(&readings, enc)
    }

    /// [`FaultInjector::sense`] with the shafts' readings (`Motor::reading`) given.
    pub fn sense_counts(
        &self,
        readings: &[Reading; MAX_AXES],
        enc: &mut [i64; MAX_AXES],
    ) -> Inputs {
        let mut inputs = Inputs {
            estop: self.estop,
            ..Inputs::default()
        };
        for i in 0..MAX_AXES {
            let (f, r) = (&self.axes[i], &readings[i]);
            let mut bits = f.switches.inputs(r.position);
            if f.forced_limits[0] {
                bits |= Io::LIMIT_POS;
            }
            if f.forced_limits[1] {
                bits |= Io::LIMIT_NEG;
            }
            if f.alarm {
                bits |= Io::AMP_ALARM;
            }
            enc[i] = match f.encoder_lost {
                Some(frozen) => {
                    bits |= Io::ENCODER_FAULT;
                    frozen
                }
                None => r.count.wrapping_add(f.encoder_offset),
            };
            inputs.axis[i] = bits;
        }
        inputs
    }

    /// Advance `motor` of `axis` by `dt` with the DAC at `volts`, through the injected faults.
    pub fn step_motor(&self, axis: usize, motor: &mut Motor, volts: f64, dt: f64) {
        let Some(f) = self.axes.get(axis) else {
            return motor.step(volts, dt);
        };
        let volts = match f.saturation {
            Some(frac) => volts.clamp(-10.0 * frac, 10.0 * frac),
            None => volts,
        };
        if f.stalled {
            motor.omega = 0.0;
            return;
        }
        motor.step(volts, dt);
    }
}
