//! The card's analog inputs as the machine drives them (layout 1.11): what each of the 8 pins
//! is wired to, and the noise on it.
//!
//! A pin is wired to one [`AnalogSource`]:
//! - [`AnalogSource::Constant`]: a fixed voltage (a set-point potentiometer, a test level);
//! - [`AnalogSource::Position`]: a linear function of an axis's load position, `offset +
//!   volts_per_count · position` (a height sensor, a linear potentiometer on the axis);
//! - [`AnalogSource::LoadForce`]: a load cell between the axis and its load, `offset +
//!   volts_per_nm · torque`, the torque the load takes: the coupling's spring and damper
//!   torque of a two-mass axis, else the external disturbance torque (the process force a test
//!   sets with [`Motor::disturbance`]).
//!
//! Optional noise ([`Noise`]) is added to a pin: uniform in `±amplitude` V from a xorshift64*
//! generator of its own seed, one draw per period, so a run is the same every time. The pin's
//! voltage is what the card's ADC samples at the period's start (it quantises and saturates:
//! `firmware::analog`).

use super::Motor;
use firmware_proto::ANALOG_INPUTS;

/// What drives an analog input pin.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum AnalogSource {
    /// A fixed voltage.
    Constant(f64),
    /// `offset + volts_per_count · (axis's load position, counts)`.
    Position {
        /// The axis.
        axis: usize,
        /// Gain, V per encoder count.
        volts_per_count: f64,
        /// Volts at position 0.
        offset: f64,
    },
    /// `offset + volts_per_nm · (the torque the axis's load takes, N·m)`.
    LoadForce {
        /// The axis.
        axis: usize,
        /// Gain, V per N·m.
        volts_per_nm: f64,
        /// Volts at no load.
        offset: f64,
    },
}

impl Default for AnalogSource {
    fn default() -> Self {
        Self::Constant(0.0)
    }
}

/// Deterministic uniform noise on a pin.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Noise {
    /// Peak amplitude, V (the draw is uniform in ±amplitude).
    pub amplitude: f64,
    /// The generator's seed (0 is taken as 1).
    pub seed: u64,
}

/// The torque axis `m`'s load takes, N·m: a two-mass axis's coupling torque, else the external
/// disturbance torque.
pub fn load_torque(m: &Motor) -> f64 {
    match m.params.resonance {
        Some(r) => r.stiffness * (m.theta - m.load_theta) + r.damping * (m.omega - m.load_omega),
        None => m.disturbance,
    }
}

/// The analog input pins.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct AnalogBank {
    sources: [AnalogSource; ANALOG_INPUTS],
    noise: [Option<(Noise, u64)>; ANALOG_INPUTS],
}

impl AnalogBank {
    /// Wire input `i` to `source` (ignored beyond the inputs).
    pub fn set(&mut self, i: usize, source: AnalogSource) {
        if let Some(s) = self.sources.get_mut(i) {
            *s = source;
        }
    }

    /// Put noise on input `i` (`None`: none); the generator starts from its seed.
    pub fn set_noise(&mut self, i: usize, noise: Option<Noise>) {
        if let Some(n) = self.noise.get_mut(i) {
            *n = noise.map(|n| (n, n.seed.max(1)));
        }
    }

    /// Input `i`'s source.
    pub fn source(&self, i: usize) -> Option<AnalogSource> {
        self.sources.get(i).copied()
    }

    /// The pins' voltages with the axes' `motors` as they are (one noise draw each).
    pub fn sample(&mut self, motors: &[Motor]) -> [f64; ANALOG_INPUTS] {
        core::array::from_fn(|i| {
            let clean = match self.sources[i] {
                AnalogSource::Constant(v) => v,
                AnalogSource::Position {
                    axis,
                    volts_per_count,
                    offset,
                } => motors.get(axis).map_or(offset, |m| {
                    offset + volts_per_count * m.load_position_counts()
                }),
                AnalogSource::LoadForce {
                    axis,
                    volts_per_nm,
                    offset,
                } => motors
                    .get(axis)
                    .map_or(offset, |m| offset + volts_per_nm * load_torque(m)),
            };
            match &mut self.noise[i] {
                Some((n, state)) => clean + n.amplitude * uniform(state),
                None => clean,
            }
        })
    }
}

/// xorshift64*: the next draw, uniform in [-1, 1).
fn uniform(state: &mut u64) -> f64 {
    let mut x = *state;
    x ^= x >> 12;
    x ^= x << 25;
    x ^= x >> 27;
    *state = x;
    let r = x.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11; // 53 bits
    r as f64 / (1u64 << 52) as f64 - 1.0
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plant::MotorParams;

    #[test]
    fn sources_and_deterministic_noise() {
        let mut m = Motor::new(MotorParams::default());
        m.theta = 1.0;
        m.disturbance = 0.5;
        let mut b = AnalogBank::default();
        b.set(0, AnalogSource::Constant(1.25));
        b.set(
            1,
            AnalogSource::Position {
                axis: 0,
                volts_per_count: 1e-3,
                offset: -1.0,
            },
        );
        b.set(
            2,
            AnalogSource::LoadForce {
                axis: 0,
                volts_per_nm: 2.0,
                offset: 0.5,
            },
        );
        let noise = Noise {
            amplitude: 0.01,
            seed: 7,
        };
        b.set_noise(3, Some(noise));
        let v = b.sample(&[m]);
        assert_eq!(v[0], 1.25);
        assert_eq!(v[1], -1.0 + 1e-3 * m.load_position_counts());
        assert_eq!(v[2], 1.5);
        assert!(v[3].abs() <= 0.01 && v[3] != 0.0);
        let mut again = AnalogBank::default();
        again.set_noise(3, Some(noise));
        assert_eq!(again.sample(&[m])[3], v[3], "the same seed, the same draw");
        assert_ne!(b.sample(&[m])[3], v[3], "a new draw each period");
    }
}
