//! Servo laws. FFPIV after Thinh Fig 5 (eq 29, `u = u_FF + u_PIV`): the position error times
//! K_P becomes a velocity correction; the velocity loop is P (K_V) plus I (K_I) on the velocity
//! error; velocity feed-forward enters the velocity command and acceleration feed-forward is
//! added to the output.
//!
//! ```text
//! v_cmd = K_P·(x_ref − x) + K_VFF·v̂_ref
//! e_v   = v_cmd − v̂                       (v̂: filtered encoder velocity)
//! u     = K_V·(e_v + K_I·∫e_v dt) + K_AFF·a_ref
//! ```
//!
//! The velocity feed-forward goes through the estimator's own model before it meets v̂:
//! `v̂_ref` is `v_ref − a_ref·T/2` (what a backward difference over the last tick reads on a
//! plant that follows the reference) through the same low-pass as the encoder velocity. On a
//! ramp v̂ lags the shaft by T/2 + T·(1 − α)/α, α the low-pass's gain per tick (1.1 ticks at
//! 10 kHz with the 1,500 Hz cut-off); compared with the raw v_ref, that lag reads as a
//! velocity error of `a_ref` times the lag, which the position loop can only cancel with a
//! following error of `a_ref·lag/K_P` (2.4 counts at 2·10⁶ counts/s² with the default
//! tuning). Lagged alike, the two agree whenever the
//! axis follows its reference, and the following error during acceleration falls to the
//! encoder's quantisation (`motioncard::papers::ff_speed_sweep`).
//!
//! **Reading the count at its middle** (a gantry's members, issue 35 part 1: [`Ffpiv::set_mid_count`]).
//! The encoder reads `n` for a shaft anywhere in `[n, n + 1)`. While the reference moves the
//! loop may take the count's middle, `x = n + ½`, for the shaft's position. Without it, a
//! reference on a whole count `r` is met by any shaft in `[r, r + 1)` with no error at all
//! (at 10⁶ counts/s on a 10 kHz loop, exactly 100 counts a tick, a reference that starts on a
//! count stays on one for the whole cruise), so the shaft drifts within that count, and a
//! reference between counts is met by the shaft on the count's edge above it. With it, the
//! position error is never 0: the integrator holds the shaft on the edge between the two counts
//! nearest the reference (the encoder toggling between them), within half a count of it, and
//! two axes given the same reference hold their shafts on the same edge. At rest the reference
//! is rounded and the count is read as it is (no hunting between two counts).
//!
//! Units: counts, seconds, volts. Thinh's published gains (K_P=2.5, K_I=0.02, K_V=50,
//! K_VFF=30) have no units and belong to their drive; [`FfpivGains::for_drive`] derives ours
//! from the plant instead.

use crate::math;
pub use firmware_proto::reset::{DEFAULT_ACCEL_PER_VOLT, DEFAULT_BANDWIDTH};
/// FFPIV gains and the velocity estimator's cut-off: the register map's `mc_ffpiv_gains`
/// (its `Default` is the default tuning, [`FfpivGains::for_drive`] places gains for a drive).
pub use firmware_proto::FfpivGains;

/// The gains the card accepts: finite, K_P, K_I, K_V, K_AFF ≥ 0, 0 ≤ K_VFF ≤ 2, a positive
/// velocity-filter cut-off.
pub fn gains_valid(g: &FfpivGains) -> bool {
    let nonneg = |x: f64| x.is_finite() && x >= 0.0;
    nonneg(g.kp)
        && nonneg(g.ki)
        && nonneg(g.kv)
        && nonneg(g.kvff)
        && g.kvff <= 2.0
        && nonneg(g.kaff)
        && g.vel_filter_hz.is_finite()
        && g.vel_filter_hz > 0.0
}

/// The gain of the velocity estimator's first-order low-pass per tick: the exact
/// discretisation of `1/(1 + s/ω_f)`, `1 − e^(−ω_f·T)`.
fn velocity_filter_gain(gains: &FfpivGains, ts: f64) -> f64 {
    1.0 - math::exp(-2.0 * core::f64::consts::PI * gains.vel_filter_hz * ts)
}

/// The FFPIV loop's state.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Ffpiv {
    integral: f64,
    last_encoder: Option<i64>,
    vel: f64,
    /// v̂_ref: the reference velocity as the estimator would read it.
    vel_ref: f64,
    /// The low-pass's gain per tick, and the (cut-off, tick) it was computed for: one `exp`
    /// when either changes, not two every tick.
    filter_gain: f64,
    filter_for: (f64, f64),
    /// The terms of the last output: [`ServoTerms`].
    terms: ServoTerms,
    /// Read the count at its middle while the reference moves (the module's head).
    mid_count: bool,
}

/// The terms of a servo law's output, V (the scope's `MC_SIG_SERVO_*`): their sum is the
/// output before the clamp, up to rounding.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ServoTerms {
    /// Proportional: FFPIV kv·kp·(x_ref − x); PD+ kp·e.
    pub p: f64,
    /// Integral: FFPIV kv·ki·∫; PD+ 0.
    pub i: f64,
    /// Velocity feedback: FFPIV −kv·v̂; PD+ kd·(w_d − w_a).
    pub d: f64,
    /// Feed-forward: FFPIV kv·kvff·v̂_ref + kaff·a_ref; PD+ kv·w_d + ka·α_d.
    pub ff: f64,
}

/// One servo update's inputs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Reference {
    /// x_ref, counts.
    pub pos: f64,
    /// v_ref, counts/s.
    pub vel: f64,
    /// a_ref, counts/s².
    pub acc: f64,
}

impl Ffpiv {
    /// Update the velocity estimate from a new encoder reading; returns v̂ (counts/s).
    pub fn measure(&mut self, encoder: i64, gains: &FfpivGains, ts: f64) -> f64 {
        let raw = match self.last_encoder {
            Some(prev) => encoder.wrapping_sub(prev) as f64 / ts,
            None => 0.0,
        };
        self.last_encoder = Some(encoder);
        self.vel += self.filter_gain(gains, ts) * (raw - self.vel);
        self.vel
    }

    fn filter_gain(&mut self, gains: &FfpivGains, ts: f64) -> f64 {
        if self.filter_for != (gains.vel_filter_hz, ts) {
            self.filter_for = (gains.vel_filter_hz, ts);
            self.filter_gain = velocity_filter_gain(gains, ts);
        }
        self.filter_gain
    }

    /// v̂_ref after the last update: the reference velocity through the estimator's model,
    /// counts/s.
    pub fn reference_velocity(&self) -> f64 {
        self.vel_ref
    }

    /// The filtered velocity.
    pub fn velocity(&self) -> f64 {
        self.vel
    }

    /// The control output before the DAC (volts), for measured position `x`. The caller clamps
    /// it to `limit`; the integrator stops growing while the output is beyond it (anti-windup).
    #[inline] // called from the generic tick, instantiated in the crate that runs it
    pub fn update(
        &mut self,
        r: &Reference,
        x: f64,
        gains: &FfpivGains,
        ts: f64,
        limit: f64,
    ) -> f64 {
        // At standstill the reference is the nearest whole count: the encoder resolves no less,
        // and integrating a half-count error would make the axis hunt between the two counts
        // around a target that lies between them.
        // Moving, a gantry's member reads the count at its middle (the module's head).
        let (pos, x) = if r.vel == 0.0 && r.acc == 0.0 {
            (math::round(r.pos), x)
        } else if self.mid_count {
            (r.pos, x + 0.5)
        } else {
            (r.pos, x)
        };
        // The estimator's view of the reference: the backward difference over the tick ending
        // at the reference's time (v − a·T/2, exact for constant acceleration), low-passed as
        // the encoder velocity is.
        let raw_ref = r.vel - 0.5 * r.acc * ts;
        self.vel_ref += self.filter_gain(gains, ts) * (raw_ref - self.vel_ref);
        let v_cmd = gains.kp * (pos - x) + gains.kvff * self.vel_ref;
        let ev = v_cmd - self.vel;
        let integral = self.integral + ev * ts;
        let u = gains.kv * (ev + gains.ki * integral) + gains.kaff * r.acc;
        self.terms = ServoTerms {
            p: gains.kv * gains.kp * (pos - x),
            i: gains.kv * gains.ki * integral,
            d: -gains.kv * self.vel,
            ff: gains.kv * gains.kvff * self.vel_ref + gains.kaff * r.acc,
        };
        if u.abs() <= limit {
            self.integral = integral;
        }
        u
    }

    /// Issue 35 part 1: read the encoder's count at its middle while the reference moves (a
    /// gantry's members, from its formation to its dissolution: the module's head).
    pub fn set_mid_count(&mut self, on: bool) {
        self.mid_count = on;
    }

    /// Does it read the count at its middle while the reference moves?
    pub fn mid_count(&self) -> bool {
        self.mid_count
    }

    /// The terms of the last output.
    pub fn terms(&self) -> ServoTerms {
        self.terms
    }

    /// Layout 1.11, bumpless transfer from another law whose output was `u_prev` volts: the
    /// integrator that gives that output at rest (`kv·ki·∫ = u_prev`); none without an
    /// integral gain.
    pub fn transfer(&mut self, u_prev: f64, gains: &FfpivGains) {
        self.vel_ref = 0.0;
        let k = gains.kv * gains.ki;
        self.integral = if k > 0.0 { u_prev / k } else { 0.0 };
    }

    /// Forget the integrator and the reference's history (on enable, at rest), keep the
    /// velocity estimate.
    pub fn reset_integral(&mut self) {
        self.integral = 0.0;
        self.vel_ref = 0.0;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A shaft that follows a constant-acceleration reference exactly (one tick ahead, as the
    /// loop holds it) leaves the velocity loop nothing to do: v̂ and the reference's v̂_ref lag
    /// alike, and the output is the acceleration feed-forward alone. (Compared with the raw
    /// v_ref, v̂ reads a velocity error of a·(T/2 + T·(1 − α)/α).)
    #[test]
    fn a_shaft_on_its_reference_needs_only_the_acceleration_feed_forward() {
        let gains = FfpivGains::default();
        let (ts, a) = (1e-4, 4e9); // counts/s²: a count is 10⁻⁶ of a tick's travel at the end
        let r = |t: f64| Reference {
            pos: 0.5 * a * t * t,
            vel: a * t,
            acc: a,
        };
        let mut s = Ffpiv::default();
        let mut worst: f64 = 0.0;
        let mut lag_error: f64 = 0.0;
        for k in 0..400 {
            let t = k as f64 * ts;
            let x = r(t + ts).pos.round();
            s.measure(x as i64, &gains, ts);
            let reference = r(t + ts);
            let u = s.update(&reference, x, &gains, ts, 1e9);
            if k >= 200 {
                // From k = 1 on a_ref does not change: the feed-forward is kaff·a.
                worst = worst.max((u - gains.kaff * a).abs() / (gains.kaff * a));
                lag_error = lag_error.max((reference.vel - s.velocity()).abs());
            }
        }
        assert!(worst < 1e-3, "u off the feed-forward by {worst:e} of it");
        // Half a tick of the backward difference, and the low-pass's ramp lag T·(1 − α)/α.
        let alpha = velocity_filter_gain(&gains, ts);
        let lag = ts / 2.0 + ts * (1.0 - alpha) / alpha;
        assert!(
            (lag_error / (a * lag) - 1.0).abs() < 0.05,
            "v̂ lags v_ref by {lag_error}, a·lag = {}",
            a * lag
        );
    }

    #[test]
    fn output_clamps_and_integrator_does_not_wind_up() {
        let gains = FfpivGains::default();
        let mut s = Ffpiv::default();
        let r = Reference {
            pos: 1e9,
            vel: 0.0,
            acc: 0.0,
        };
        for _ in 0..1000 {
            assert!(s.update(&r, 0.0, &gains, 1e-4, 10.0) > 10.0);
        }
        assert_eq!(s.integral, 0.0);
    }
}
