//! Servo laws. FFPIV after Thinh Fig 5 (eq 29, `u = u_FF + u_PIV`): the position error times
//! K_P becomes a velocity correction; the velocity loop is P (K_V) plus I (K_I) on the velocity
//! error; velocity feed-forward enters the velocity command and acceleration feed-forward is
//! added to the output.
//!
//! ```text
//! v_cmd = K_P·(x_ref − x) + K_VFF·v_ref
//! e_v   = v_cmd − v̂                       (v̂: filtered encoder velocity)
//! u     = K_V·(e_v + K_I·∫e_v dt) + K_AFF·a_ref
//! ```
//!
//! Units: counts, seconds, volts. Thinh's published gains (K_P=2.5, K_I=0.02, K_V=50,
//! K_VFF=30) have no units and belong to their drive; [`FfpivGains::for_drive`] derives ours
//! from the plant instead.

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

/// The FFPIV loop's state.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Ffpiv {
    integral: f64,
    last_encoder: Option<i64>,
    vel: f64,
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
        // First-order low-pass, exact discretisation of 1/(1 + s/ωf).
        let alpha = 1.0 - (-2.0 * core::f64::consts::PI * gains.vel_filter_hz * ts).exp();
        self.vel += alpha * (raw - self.vel);
        self.vel
    }

    /// The filtered velocity.
    pub fn velocity(&self) -> f64 {
        self.vel
    }

    /// The control output before the DAC (volts), for measured position `x`. The caller clamps
    /// it to `limit`; the integrator stops growing while the output is beyond it (anti-windup).
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
        let pos = if r.vel == 0.0 && r.acc == 0.0 {
            r.pos.round()
        } else {
            r.pos
        };
        let v_cmd = gains.kp * (pos - x) + gains.kvff * r.vel;
        let ev = v_cmd - self.vel;
        let integral = self.integral + ev * ts;
        let u = gains.kv * (ev + gains.ki * integral) + gains.kaff * r.acc;
        if u.abs() <= limit {
            self.integral = integral;
        }
        u
    }

    /// Forget the integrator (on enable), keep the velocity estimate.
    pub fn reset_integral(&mut self) {
        self.integral = 0.0;
    }
}

#[cfg(all(test, feature = "emulator"))]
mod tests {
    use super::*;
    use crate::plant::{Motor, MotorParams};

    /// Closed loop on the plant: a step in the reference is followed without overshooting by
    /// more than a few counts and settles to within one count.
    #[test]
    fn default_tuning_settles_a_small_step_within_one_count() {
        let params = MotorParams::default_servo();
        let gains = FfpivGains::default();
        let ts = 1e-4;
        let mut m = Motor::new(params);
        let mut s = Ffpiv::default();
        let r = Reference {
            pos: 100.0,
            vel: 0.0,
            acc: 0.0,
        };
        let mut peak: i64 = 0;
        for _ in 0..20_000 {
            let enc = m.encoder();
            peak = peak.max(enc);
            s.measure(enc, &gains, ts);
            let u = s
                .update(&r, enc as f64, &gains, ts, 10.0)
                .clamp(-10.0, 10.0);
            m.step(crate::firmware::dac::Dac::output(u).0, ts);
        }
        assert!((m.encoder() - 100).abs() <= 1, "settled at {}", m.encoder());
        assert!(peak <= 140, "overshoot to {peak}");
    }

    /// A target between two counts: the axis settles on one of them and stays (no hunting).
    #[test]
    fn no_hunting_around_a_fractional_target() {
        let params = MotorParams::default_servo();
        let gains = FfpivGains::default();
        let ts = 1e-4;
        let mut m = Motor::new(params);
        let mut s = Ffpiv::default();
        let r = Reference {
            pos: 40.5,
            vel: 0.0,
            acc: 0.0,
        };
        let mut changes = 0;
        let mut last = m.encoder();
        for i in 0..50_000 {
            let enc = m.encoder();
            if i > 10_000 && enc != last {
                changes += 1;
            }
            last = enc;
            s.measure(enc, &gains, ts);
            let u = s
                .update(&r, enc as f64, &gains, ts, 10.0)
                .clamp(-10.0, 10.0);
            m.step(crate::firmware::dac::Dac::output(u).0, ts);
        }
        assert!(
            (m.encoder() as f64 - 40.5).abs() <= 0.5,
            "settled at {}",
            m.encoder()
        );
        assert_eq!(changes, 0, "the encoder kept changing after settling");
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
