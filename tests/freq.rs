//! Layout 1.12: the frequency response measured on the card (a stepped sine), on the stepped
//! card against the emulator's plant, checked against the simulated axis's own transfer
//! function. The agreement is printed: `cargo test --release --test freq -- --nocapture`.
mod common;

use common::stepped_card_with;
use firmware_proto::reset::DEFAULT_BANDWIDTH;
use firmware_proto::FfpivGains;
use motioncard_sdk::{Card, EmuOptions, FreqMode, FreqSweep, MotorParams, Phasor};
use std::f64::consts::PI;
use std::time::Duration;

const RATE: u32 = 10_000;
const LONG: Duration = Duration::from_secs(600);

/// The model-check plant: the default servo without Coulomb friction (the one nonlinearity
/// of the rigid body) and with a fine encoder (2^24 counts/rev), so that neither the
/// encoder's count nor the DAC's step is a visible part of the sines measured.
fn fine_motor() -> MotorParams {
    MotorParams {
        coulomb: 0.0,
        counts_per_rev: 1 << 24,
        ..MotorParams::default_servo()
    }
}

/// A stepped card with `motor` on axis 0, FFPIV placed for it at the default bandwidth,
/// the following-error and velocity limits widened for a sweep of 0.01 revolution to 2.5 kHz,
/// enabled.
fn card_with(motor: MotorParams) -> Card {
    let mut emu = EmuOptions::new(1, RATE);
    emu.motors[0] = motor;
    let card = stepped_card_with(emu);
    let axis = card.axis(0).unwrap();
    let mut cfg = axis.settings().unwrap();
    cfg.ffpiv = FfpivGains::for_drive(motor.accel_per_volt(), DEFAULT_BANDWIDTH);
    axis.configure(&cfg).unwrap();
    let mut s = axis.safety_settings().unwrap();
    let cpr = motor.counts_per_rev as f64;
    s.min_ferror = cpr;
    s.ferror = 10.0 * cpr;
    s.max_velocity = 3e9;
    s.stop_deceleration = 3e10;
    s.stop_jerk = 3e12;
    s.encoder_max_velocity = 1e11;
    axis.configure_safety(&s).unwrap();
    axis.enable().unwrap();
    card
}

/// The simulated axis's analytic response at `hz` under FFPIV at rest, the sine on the
/// position reference: (T, P) with T = X/D, P = X/U (counts per volt).
///
/// The plant: J θ'' = K_t K_a u − b θ', x = θ·counts/rad, its input held over each servo
/// period (the DAC is written in tick k and holds until tick k+1; the encoder is read at the
/// period's start). Exactly discretised (zero-order hold) with a = b/J, g = K_t K_a c/J
/// (c: counts per radian), E = e^{−aT}:
///   Φ = [[1, (1−E)/a], [0, E]],  Γ = g·[(T − (1−E)/a)/a, (1−E)/a],  x = [1 0]·state,
///   P(z) = [1 0] (zI − Φ)⁻¹ Γ  (one tick from u[k] to x[k+1]: the loop's delay).
/// The law (ffpiv.rs) on the sine d at rest (v_ref = a_ref = 0, the sine does not reach the
/// velocity feed-forward):
///   v̂ = H_v x,  H_v(z) = α (1 − z⁻¹)/T / (1 − (1−α) z⁻¹),  α = 1 − e^{−2π f_v T};
///   u = C_v (kp (d − x) − v̂),  C_v(z) = kv (1 + ki T / (1 − z⁻¹));
/// so X = P C_v (kp D − (kp + H_v) X) and T = P C_v kp / (1 + P C_v (kp + H_v)). The DAC's
/// quantisation (20/4096 V) is left out: the sweep's outputs span thousands of its steps.
fn model(m: &MotorParams, g: &FfpivGains, hz: f64) -> (Phasor, Phasor) {
    let ts = 1.0 / RATE as f64;
    let z = Phasor::unit(2.0 * PI * hz * ts);
    let zi = Phasor::new(1.0, 0.0).div(z);
    let one = Phasor::new(1.0, 0.0);
    let c = m.counts_per_rad();
    let a = m.damping / m.inertia;
    let gain = m.kt * m.amp_gain * c / m.inertia;
    let e = (-a * ts).exp();
    let (p12, p22) = ((1.0 - e) / a, e);
    let (g1, g2) = (gain * (ts - (1.0 - e) / a) / a, gain * (1.0 - e) / a);
    // (zI − Φ)⁻¹ Γ, first row: [z−1, −p12; 0, z−p22]⁻¹ = 1/((z−1)(z−p22)) [z−p22, p12; 0, z−1]
    let zm1 = z.sub(one);
    let zmp = z.sub(Phasor::new(p22, 0.0));
    let num = zmp
        .mul(Phasor::new(g1, 0.0))
        .add(Phasor::new(p12 * g2, 0.0));
    let p = num.div(zm1.mul(zmp));
    let alpha = 1.0 - (-2.0 * PI * g.vel_filter_hz * ts).exp();
    let hv = Phasor::new(alpha / ts, 0.0)
        .mul(one.sub(zi))
        .div(one.sub(zi.mul(Phasor::new(1.0 - alpha, 0.0))));
    let cv = Phasor::new(g.kv, 0.0).mul(one.add(Phasor::new(g.ki * ts, 0.0).div(one.sub(zi))));
    let kp = Phasor::new(g.kp, 0.0);
    let pc = p.mul(cv);
    let t = pc.mul(kp).div(one.add(pc.mul(kp.add(hv))));
    (t, p)
}

fn angle_deg(a: Phasor, b: Phasor) -> f64 {
    let d = a.div(b).arg().to_degrees();
    d.abs()
}

/// The measured closed loop and plant of the simulated axis match its analytic response
/// within 0.5 dB and 5° from 5 Hz to a quarter of the servo rate (2.5 kHz).
#[test]
fn measured_response_matches_the_model_below_a_quarter_of_the_servo_rate() {
    let m = fine_motor();
    let card = card_with(m);
    let axis = card.axis(0).unwrap();
    let gains = axis.settings().unwrap().ffpiv;
    let sweep = FreqSweep {
        mode: FreqMode::Reference,
        from_hz: 5.0,
        to_hz: RATE as f64 / 4.0,
        points: 30,
        amplitude: m.counts_per_rev as f64 / 100.0,
        cycles: 4,
        settle_s: 0.3,
    };
    let r = axis.frequency_response(&sweep, LONG).unwrap();
    assert!(r.complete);
    assert_eq!(r.points.len(), 30);
    let (mut t_db, mut t_deg, mut p_db, mut p_deg) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    let (t, p) = (r.closed_loop(), r.plant());
    for k in 0..r.points.len() {
        let hz = r.points[k].hz;
        let (tm, pm) = model(&m, &gains, hz);
        let e = [
            (t[k].gain_db - tm.db()).abs(),
            angle_deg(t[k].value, tm),
            (p[k].gain_db - pm.db()).abs(),
            angle_deg(p[k].value, pm),
        ];
        println!(
            "{hz:8.2} Hz  T {:7.2} dB {:7.1}°  (model {:7.2} dB {:7.1}°)  P {:7.2} dB {:7.1}° (model {:7.2} dB {:7.1}°)",
            t[k].gain_db,
            t[k].phase_deg,
            tm.db(),
            tm.arg().to_degrees(),
            p[k].gain_db,
            p[k].phase_deg,
            pm.db(),
            pm.arg().to_degrees()
        );
        assert!(e.iter().all(|x| x.is_finite()), "{hz} Hz: {e:?}");
        t_db = t_db.max(e[0]);
        t_deg = t_deg.max(e[1]);
        p_db = p_db.max(e[2]);
        p_deg = p_deg.max(e[3]);
    }
    println!(
        "model check 5 Hz..2.5 kHz: closed loop {t_db:.3} dB {t_deg:.2}°, plant {p_db:.3} dB {p_deg:.2}° worst"
    );
    assert!(
        t_db <= 0.5 && t_deg <= 5.0,
        "closed loop off the model by {t_db} dB, {t_deg}°"
    );
    assert!(
        p_db <= 0.5 && p_deg <= 5.0,
        "plant off the model by {p_db} dB, {p_deg}°"
    );
}
