//! The simulated plant of one axis: 12-bit ±10 V DAC, current-mode amplifier, motor and load,
//! quantised incremental encoder, limit and home switches.
//!
//! The motor is the rigid body of Thinh Fig 5: `J dω/dt = K_t·i − b·ω − T_c·sgn(ω) − T_d`, with
//! the amplifier `i = clamp(K_a·u, ±I_max)`. Over one servo period the input is held (zero-order
//! hold), so the linear part is integrated exactly; Coulomb friction is handled piecewise: the
//! motor sticks while the drive torque cannot overcome it, and a velocity that would cross zero
//! inside the period stops at zero first.

use core::f64::consts::TAU;

/// Parameters of one axis's motor, load, amplifier and encoder (SI units).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MotorParams {
    /// Total inertia J, kg·m².
    pub inertia: f64,
    /// Viscous damping b, N·m·s/rad.
    pub damping: f64,
    /// Torque constant K_t, N·m/A.
    pub kt: f64,
    /// Coulomb friction T_c, N·m.
    pub coulomb: f64,
    /// Amplifier transconductance K_a, A/V.
    pub amp_gain: f64,
    /// Amplifier current limit, A.
    pub current_limit: f64,
    /// Encoder counts per revolution (after quadrature).
    pub counts_per_rev: u32,
}

impl MotorParams {
    /// The default axis: a 400 W class servo with its load. 10,000 counts/rev, 3 N·m peak at
    /// 10 V, J = 5·10⁻⁴ kg·m² (about 9.5·10⁶ counts/s² at full output).
    pub const fn default_servo() -> Self {
        Self {
            inertia: 5e-4,
            damping: 1e-4,
            kt: 0.3,
            coulomb: 0.01,
            amp_gain: 1.0,
            current_limit: 10.0,
            counts_per_rev: 10_000,
        }
    }

    /// Encoder counts per radian.
    pub fn counts_per_rad(&self) -> f64 {
        self.counts_per_rev as f64 / TAU
    }

    /// Volts per count/s² that produce an acceleration (ideal acceleration feed-forward).
    pub fn volts_per_accel(&self) -> f64 {
        self.inertia / (self.counts_per_rad() * self.kt * self.amp_gain)
    }

    /// Velocity, counts/s, per volt per second at the motor (loop-gain scale for tuning).
    pub fn accel_per_volt(&self) -> f64 {
        1.0 / self.volts_per_accel()
    }

    /// Are the parameters physically meaningful?
    pub fn is_valid(&self) -> bool {
        let pos = |x: f64| x.is_finite() && x > 0.0;
        let nonneg = |x: f64| x.is_finite() && x >= 0.0;
        pos(self.inertia)
            && nonneg(self.damping)
            && pos(self.kt)
            && nonneg(self.coulomb)
            && pos(self.amp_gain)
            && pos(self.current_limit)
            && self.counts_per_rev > 0
    }
}

impl Default for MotorParams {
    fn default() -> Self {
        Self::default_servo()
    }
}

/// The 12-bit bipolar DAC: code 2048 is 0 V, one LSB is 20/4096 V, codes saturate at 0 and 4095.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Dac;

impl Dac {
    /// Volts per LSB.
    pub const LSB: f64 = 20.0 / 4096.0;

    /// The code for a requested voltage (NaN gives mid-scale).
    pub fn code(volts: f64) -> u16 {
        if volts.is_nan() {
            return 2048;
        }
        let c = (volts / Self::LSB).round() + 2048.0;
        c.clamp(0.0, 4095.0) as u16
    }

    /// The voltage a code produces.
    pub fn volts(code: u16) -> f64 {
        (code.min(4095) as f64 - 2048.0) * Self::LSB
    }

    /// Quantise and saturate: the voltage actually produced, and whether it saturated.
    pub fn output(volts: f64) -> (f64, bool) {
        let code = Self::code(volts);
        (Self::volts(code), code == 0 || code == 4095)
    }
}

/// One axis's mechanical state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Motor {
    /// Parameters.
    pub params: MotorParams,
    /// Shaft angle, rad.
    pub theta: f64,
    /// Shaft speed, rad/s.
    pub omega: f64,
    /// External disturbance torque T_d, N·m (opposes positive motion when positive).
    pub disturbance: f64,
}

impl Motor {
    /// At rest at angle 0.
    pub fn new(params: MotorParams) -> Self {
        Self {
            params,
            theta: 0.0,
            omega: 0.0,
            disturbance: 0.0,
        }
    }

    /// The encoder reading: the angle quantised to whole counts.
    pub fn encoder(&self) -> i64 {
        (self.theta * self.params.counts_per_rad()).floor() as i64
    }

    /// Position in (unquantised) counts.
    pub fn position_counts(&self) -> f64 {
        self.theta * self.params.counts_per_rad()
    }

    /// Advance by `dt` seconds with the amplifier input `volts` held.
    pub fn step(&mut self, volts: f64, dt: f64) {
        let p = self.params;
        let volts = if volts.is_finite() { volts } else { 0.0 };
        let current = (p.amp_gain * volts).clamp(-p.current_limit, p.current_limit);
        let drive = p.kt * current - self.disturbance;
        let mut left = dt;
        // At most three pieces: move, stop at zero, break away the other way.
        for _ in 0..3 {
            if left <= 0.0 {
                break;
            }
            if self.omega == 0.0 {
                if drive.abs() <= p.coulomb {
                    return; // stiction holds
                }
                let sign = drive.signum();
                left -= self.integrate(drive - sign * p.coulomb, sign, left);
            } else {
                let sign = self.omega.signum();
                left -= self.integrate(drive - sign * p.coulomb, sign, left);
            }
        }
    }

    /// Integrate `J ω' = tau − b ω` exactly for up to `dt`, stopping early if ω reaches zero
    /// against `sign` (the direction friction was computed for). Returns the time used.
    fn integrate(&mut self, tau: f64, sign: f64, dt: f64) -> f64 {
        let (j, b) = (self.params.inertia, self.params.damping);
        let w0 = self.omega;
        // Time at which ω would reach zero, if it decelerates through it.
        let t_zero = if b > 0.0 {
            let w_inf = tau / b;
            // ω(t) = w_inf + (w0 − w_inf)·e^{−bt/J} = 0  ⇒  t = (J/b)·ln((w_inf − w0)/w_inf)
            let ratio = (w_inf - w0) / w_inf;
            if w0 != 0.0 && w_inf * sign < 0.0 && ratio > 1.0 {
                (j / b) * ratio.ln()
            } else {
                f64::INFINITY
            }
        } else if w0 != 0.0 && tau * sign < 0.0 {
            -w0 * j / tau
        } else {
            f64::INFINITY
        };
        let t = dt.min(t_zero);
        if b > 0.0 {
            let w_inf = tau / b;
            let decay = (-b * t / j).exp();
            self.theta += w_inf * t + (w0 - w_inf) * (j / b) * (1.0 - decay);
            self.omega = w_inf + (w0 - w_inf) * decay;
        } else {
            let a = tau / j;
            self.theta += w0 * t + 0.5 * a * t * t;
            self.omega = w0 + a * t;
        }
        if t_zero <= dt {
            self.omega = 0.0;
        }
        t
    }
}

/// The switches along an axis's travel, at positions in encoder counts. A limit switch is
/// active at and beyond its position; the home switch within `home_width / 2` of `home`.
/// Infinite positions (the default) mean no switch.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Switches {
    /// Positive limit switch, counts (`+∞`: none).
    pub limit_pos: f64,
    /// Negative limit switch, counts (`−∞`: none).
    pub limit_neg: f64,
    /// Home switch centre, counts (NaN: none).
    pub home: f64,
    /// Home switch width, counts.
    pub home_width: f64,
}

impl Default for Switches {
    fn default() -> Self {
        Self {
            limit_pos: f64::INFINITY,
            limit_neg: f64::NEG_INFINITY,
            home: f64::NAN,
            home_width: 0.0,
        }
    }
}

impl Switches {
    /// Limits at `neg` and `pos`, no home switch.
    pub fn limits(neg: f64, pos: f64) -> Self {
        Self {
            limit_neg: neg,
            limit_pos: pos,
            ..Self::default()
        }
    }

    /// The `MC_IO_*` input bits at position `counts`.
    pub fn inputs(&self, counts: f64) -> u32 {
        use firmware_proto::io;
        let mut bits = 0;
        if counts >= self.limit_pos {
            bits |= io::LIMIT_POS;
        }
        if counts <= self.limit_neg {
            bits |= io::LIMIT_NEG;
        }
        if (counts - self.home).abs() <= 0.5 * self.home_width {
            bits |= io::HOME;
        }
        bits
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dac_is_12_bit_and_saturates() {
        assert_eq!(Dac::code(0.0), 2048);
        assert_eq!(Dac::code(100.0), 4095);
        assert_eq!(Dac::code(-100.0), 0);
        assert_eq!(Dac::output(-10.0), (-10.0, true));
        let (v, sat) = Dac::output(1.0);
        assert!(!sat && (v - 1.0).abs() <= Dac::LSB / 2.0);
        assert_eq!(Dac::output(f64::NAN), (0.0, false));
    }

    #[test]
    fn constant_torque_matches_closed_form_without_friction() {
        let params = MotorParams {
            coulomb: 0.0,
            ..MotorParams::default_servo()
        };
        let mut m = Motor::new(params);
        // 1 V for 1 s in 10,000 steps.
        for _ in 0..10_000 {
            m.step(1.0, 1e-4);
        }
        let (j, b, tau) = (params.inertia, params.damping, params.kt * params.amp_gain);
        let w = tau / b * (1.0 - (-b / j).exp());
        let th = tau / b * (1.0 - j / b * (1.0 - (-b / j).exp()));
        assert!((m.omega - w).abs() < 1e-9 * w, "{} vs {}", m.omega, w);
        assert!((m.theta - th).abs() < 1e-9 * th, "{} vs {}", m.theta, th);
    }

    #[test]
    fn stiction_holds_and_friction_stops_without_reversing() {
        let mut m = Motor::new(MotorParams::default_servo());
        let below = 0.9 * m.params.coulomb / (m.params.kt * m.params.amp_gain);
        m.step(below, 1e-3);
        assert_eq!((m.theta, m.omega), (0.0, 0.0));
        m.omega = 1.0;
        for _ in 0..1000 {
            m.step(0.0, 1e-3);
            assert!(m.omega >= 0.0);
        }
        assert_eq!(m.omega, 0.0);
        // Coasting distance with friction and damping is positive and bounded by ω²J/(2T_c).
        let bound = m.params.inertia / (2.0 * m.params.coulomb);
        assert!(m.theta > 0.0 && m.theta <= bound);
    }

    #[test]
    fn switches_follow_position() {
        use firmware_proto::io;
        let s = Switches {
            home: 0.0,
            home_width: 10.0,
            ..Switches::limits(-1000.0, 2000.0)
        };
        assert_eq!(s.inputs(0.0), io::HOME);
        assert_eq!(s.inputs(500.0), 0);
        assert_eq!(s.inputs(2000.0), io::LIMIT_POS);
        assert_eq!(s.inputs(-1e9), io::LIMIT_NEG);
        assert_eq!(Switches::default().inputs(1e300), 0);
    }

    #[test]
    fn encoder_quantises_down() {
        let mut m = Motor::new(MotorParams::default_servo());
        m.theta = 1.5 / m.params.counts_per_rad();
        assert_eq!(m.encoder(), 1);
        m.theta = -0.5 / m.params.counts_per_rad();
        assert_eq!(m.encoder(), -1);
    }
}
