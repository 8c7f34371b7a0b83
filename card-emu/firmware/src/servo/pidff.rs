//! The PID + feed-forward servo law (layout 1.11, `MC_SERVO_PIDFF`): Kim et al. 1991 §5, "in
//! position control loop, velocity and acceleration feedforward control terms are incorporated
//! into the PID controller with individually adjustable gains for reduction or elimination of
//! following errors", with a Coulomb friction feed-forward beside them.
//!
//! ```text
//! e  = x_ref − x                                   (the following error, counts)
//! ė_f += α·((e − e[k−1])/T − ė_f),  α = 1 − e^(−2π·f_d·T)
//! I  += ki·e·T    (not while u is saturated in e's direction; |I| ≤ the DAC limit)
//! u  = kp·e + I + kd·ė_f + kvff·v_ref + kaff·a_ref + F_c·sgn(v_ref)   (0 for |v_ref| ≤ deadband)
//! ```
//!
//! Units: counts, seconds, volts. The integrator holds its term in volts (`I`, not ∫e), so a
//! change of ki at run time does not step the output.
//!
//! - **Anti-windup: clamping.** The integrator does not integrate in a tick whose output is
//!   beyond the DAC limit with the error pushing it further out (conditional integration), and
//!   its term never exceeds the limit itself; it unwinds at once when the error turns.
//! - **Derivative filter:** the backward difference of the error through the exact
//!   discretisation of `1/(1 + s/ω_d)`, as the FFPIV velocity estimator; the first tick after
//!   a (re)start takes ė as 0 (no kick from a stale e[k−1]).
//! - **Friction feed-forward:** `F_c·sgn(v_ref)` once |v_ref| exceeds the deadband, 0 inside
//!   it: at rest (v_ref = 0) the term is 0, so the output does not chatter between ±F_c with
//!   the encoder's noise (it reads the reference's velocity, never the measured one).
//! - **Bumpless transfer:** [`Pidff::transfer`] makes the next update's integrator take
//!   whatever the other terms leave of the output the axis had (`I = u_prev − P − D − FF`), so
//!   switching to this law at rest does not step the DAC.

use crate::math;
use crate::servo::ffpiv::{Reference, ServoTerms};
pub use firmware_proto::AxisPidff as PidffGains;

/// The gains the card accepts: finite, every gain ≥ 0, a positive friction deadband and
/// derivative cut-off (one at or above the Nyquist frequency filters nothing: α → 1; it is
/// not refused, so that a change of servo rate never invalidates a law in force).
pub fn gains_valid(g: &PidffGains) -> bool {
    let nonneg = |x: f64| x.is_finite() && x >= 0.0;
    nonneg(g.kp)
        && nonneg(g.ki)
        && nonneg(g.kd)
        && nonneg(g.kvff)
        && nonneg(g.kaff)
        && nonneg(g.friction)
        && g.friction_deadband.is_finite()
        && g.friction_deadband > 0.0
        && g.d_filter_hz.is_finite()
        && g.d_filter_hz > 0.0
}

/// The law's numbers that are not finite (the card refuses them with `MC_NACK_NOT_FINITE`).
pub fn all_finite(g: &PidffGains) -> bool {
    [
        g.kp,
        g.ki,
        g.kd,
        g.kvff,
        g.kaff,
        g.friction,
        g.friction_deadband,
        g.d_filter_hz,
    ]
    .iter()
    .all(|x| x.is_finite())
}

/// The Coulomb friction feed-forward for reference velocity `v`: `F_c·sgn(v)` beyond the
/// deadband, 0 within it.
pub fn friction_feed_forward(g: &PidffGains, v: f64) -> f64 {
    if v > g.friction_deadband {
        g.friction
    } else if v < -g.friction_deadband {
        -g.friction
    } else {
        0.0
    }
}

/// The PID+FF law's state at a fixed servo period.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pidff {
    gains: PidffGains,
    ts: f64,
    /// The derivative filter's gain per tick.
    alpha: f64,
    /// The integrator's term, V.
    i_term: f64,
    prev_e: f64,
    de: f64,
    primed: bool,
    /// A bumpless transfer pending: the output the next update starts from.
    transfer: Option<f64>,
    terms: ServoTerms,
    friction: f64,
}

impl Pidff {
    /// The law with `gains` at period `ts` (gains checked by [`gains_valid`]), at rest.
    pub fn new(gains: PidffGains, ts: f64) -> Self {
        Self {
            gains,
            ts,
            alpha: 1.0 - math::exp(-2.0 * core::f64::consts::PI * gains.d_filter_hz * ts),
            i_term: 0.0,
            prev_e: 0.0,
            de: 0.0,
            primed: false,
            transfer: None,
            terms: ServoTerms::default(),
            friction: 0.0,
        }
    }

    /// New gains (or period) keeping the integrator's term (V) and the derivative's state: a
    /// change of gains at rest steps the output by the change of P and FF only.
    pub fn retune(&mut self, gains: PidffGains, ts: f64) {
        let keep = *self;
        *self = Self::new(gains, ts);
        self.i_term = keep.i_term;
        self.prev_e = keep.prev_e;
        self.de = keep.de;
        self.primed = keep.primed;
        self.transfer = keep.transfer;
    }

    /// Forget the integrator and the derivative's history (on enable, after a stall).
    pub fn reset(&mut self) {
        self.i_term = 0.0;
        self.de = 0.0;
        self.primed = false;
        self.transfer = None;
    }

    /// Take over from an output of `u_prev` volts: the next update's integrator starts from
    /// what its other terms leave of it (bumpless transfer).
    pub fn transfer(&mut self, u_prev: f64) {
        self.reset();
        self.transfer = Some(u_prev);
    }

    /// The gains in force.
    pub fn gains(&self) -> &PidffGains {
        &self.gains
    }

    /// The output (V, before the filters and the clamp) for reference `r` and measured
    /// position `x`; the clamp is `limit` volts.
    #[inline]
    pub fn update(&mut self, r: &Reference, x: f64, limit: f64) -> f64 {
        let g = &self.gains;
        // At standstill the reference is the nearest whole count (as FFPIV's): the integrator
        // would hunt between two counts around a target between them.
        let pos = if r.vel == 0.0 && r.acc == 0.0 {
            math::round(r.pos)
        } else {
            r.pos
        };
        let e = pos - x;
        let raw_de = if self.primed {
            (e - self.prev_e) / self.ts
        } else {
            0.0
        };
        self.primed = true;
        self.prev_e = e;
        self.de += self.alpha * (raw_de - self.de);
        let p = g.kp * e;
        let d = g.kd * self.de;
        self.friction = friction_feed_forward(g, r.vel);
        let ff = g.kvff * r.vel + g.kaff * r.acc + self.friction;
        if let Some(u_prev) = self.transfer.take() {
            self.i_term = (u_prev - p - d - ff).clamp(-limit, limit);
        }
        let u_before = p + self.i_term + d + ff;
        // Clamping: integrate unless the output is saturated and the error drives it further.
        let pushing_out = (u_before > limit && e > 0.0) || (u_before < -limit && e < 0.0);
        if !pushing_out {
            self.i_term = (self.i_term + g.ki * e * self.ts).clamp(-limit, limit);
        }
        self.terms = ServoTerms {
            p,
            i: self.i_term,
            d,
            ff,
        };
        p + self.i_term + d + ff
    }

    /// The terms of the last output.
    pub fn terms(&self) -> ServoTerms {
        self.terms
    }

    /// The Coulomb friction feed-forward of the last output (part of its FF term), V.
    pub fn friction(&self) -> f64 {
        self.friction
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const TS: f64 = 1e-4;

    fn at(pos: f64, vel: f64, acc: f64) -> Reference {
        Reference { pos, vel, acc }
    }

    #[test]
    fn a_shaft_on_its_reference_needs_only_the_feed_forward() {
        let g = PidffGains {
            kvff: 2e-6,
            friction: 0.03,
            ..PidffGains::default()
        };
        let mut s = Pidff::new(g, TS);
        let (v, a) = (5e4, 1e6);
        for _ in 0..10 {
            let u = s.update(&at(100.0, v, a), 100.0, 10.0);
            let want = g.kvff * v + g.kaff * a + g.friction;
            assert!((u - want).abs() < 1e-12, "{u} vs {want}");
        }
        assert_eq!(s.terms().p, 0.0);
        assert_eq!(s.terms().i, 0.0);
        assert_eq!(s.terms().d, 0.0);
        assert_eq!(s.friction(), g.friction);
    }

    #[test]
    fn the_friction_feed_forward_is_zero_inside_its_deadband() {
        let g = PidffGains {
            friction: 0.5,
            friction_deadband: 10.0,
            ..PidffGains::default()
        };
        assert_eq!(friction_feed_forward(&g, 0.0), 0.0);
        assert_eq!(friction_feed_forward(&g, 10.0), 0.0);
        assert_eq!(friction_feed_forward(&g, -9.0), 0.0);
        assert_eq!(friction_feed_forward(&g, 10.5), 0.5);
        assert_eq!(friction_feed_forward(&g, -11.0), -0.5);
    }

    /// The integrator stops while the output is saturated in the error's direction and never
    /// holds more than the limit: the moment the error turns, the output leaves the limit.
    #[test]
    fn the_integrator_is_clamped_against_the_dac_limit() {
        let g = PidffGains::default();
        let mut s = Pidff::new(g, TS);
        for _ in 0..10_000 {
            assert!(s.update(&at(1e6, 0.0, 0.0), 0.0, 10.0) > 10.0);
        }
        assert!(s.terms().i <= 10.0, "{}", s.terms().i);
        // The error turns small and negative: the output comes off the limit in one tick.
        let u = s.update(&at(0.0, 0.0, 0.0), 1.0, 10.0);
        assert!(u < 10.0, "{u}");
    }

    #[test]
    fn the_derivative_is_filtered_and_does_not_kick_on_the_first_tick() {
        let g = PidffGains {
            kp: 0.0,
            ki: 0.0,
            kaff: 0.0,
            ..PidffGains::default()
        };
        let mut s = Pidff::new(g, TS);
        // A standing error of 50 counts: no derivative on the first tick.
        assert_eq!(s.update(&at(50.0, 0.0, 0.0), 0.0, 10.0), 0.0);
        // A ramp of the error at 1000 counts/s: the filtered derivative converges to it.
        let mut u = 0.0;
        for k in 1..200 {
            u = s.update(&at(50.0 + k as f64 * 0.1, 1.0, 0.0), 0.0, 10.0);
        }
        assert!((u / g.kd - 1000.0).abs() < 1.0, "{}", u / g.kd);
        // One tick after a step of the error, the filtered derivative is α of the raw one.
        let mut s = Pidff::new(g, TS);
        s.update(&at(0.0, 0.0, 0.0), 0.0, 1e9);
        let u = s.update(&at(1.0, 0.0, 0.0), 0.0, 1e9);
        let alpha = 1.0 - (-2.0 * core::f64::consts::PI * g.d_filter_hz * TS).exp();
        assert!((u / (g.kd * 1.0 / TS) - alpha).abs() < 1e-12);
    }

    /// Taking over from an output of 1.7 V at rest: the first output is 1.7 V.
    #[test]
    fn a_transfer_starts_from_the_output_it_takes_over() {
        let mut s = Pidff::new(PidffGains::default(), TS);
        s.transfer(1.7);
        let u = s.update(&at(10.0, 0.0, 0.0), 10.0, 10.0);
        assert!((u - 1.7).abs() < 1e-12, "{u}");
        assert!((s.terms().i - 1.7).abs() < 1e-12);
    }

    #[test]
    fn gains_out_of_range_are_refused() {
        let ok = PidffGains::default();
        assert!(gains_valid(&ok));
        for bad in [
            PidffGains { kp: -1.0, ..ok },
            PidffGains { ki: -1e-9, ..ok },
            PidffGains { kd: f64::NAN, ..ok },
            PidffGains {
                friction: -0.1,
                ..ok
            },
            PidffGains {
                friction_deadband: 0.0,
                ..ok
            },
            PidffGains {
                d_filter_hz: 0.0,
                ..ok
            },
        ] {
            assert!(!gains_valid(&bad), "{bad:?}");
        }
    }
}
