//! Layout 1.12: the frequency response measured on the card (a stepped sine), on the stepped
//! card against the emulator's plant, checked against the simulated axis's own transfer
//! function. The agreement is printed: `cargo test --release --test freq -- --nocapture`.
mod common;

use common::stepped_card_with;
use firmware_proto::reset::DEFAULT_BANDWIDTH;
use firmware_proto::FfpivGains;
use motioncard_sdk::{
    AxisState, BiquadSpec, Card, EmuOptions, ErrorKind, FreqMode, FreqSweep, MotorParams,
    MoveLimits, Phasor,
};
use std::f64::consts::PI;
use std::ops::{Add, Div, Mul, Sub};
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

/// A card with the default axis (10,000 counts/rev, default FFPIV and safety), enabled.
fn default_card() -> Card {
    let card = stepped_card_with(EmuOptions::new(1, RATE));
    card.axis(0).unwrap().enable().unwrap();
    card
}

/// Bad input, each refused with its own error and nothing changed: a frequency above the
/// Nyquist frequency or above a quarter of the servo rate, a negative or NaN amplitude, a
/// sine beyond the axis's following-error or velocity limits, volts beyond the DAC limit,
/// no points, a disabled axis.
#[test]
fn bad_sweeps_are_refused_with_their_own_errors_and_change_nothing() {
    let card = default_card();
    let axis = card.axis(0).unwrap();
    let before = axis.status().unwrap();
    let ok = FreqSweep {
        from_hz: 10.0,
        to_hz: 100.0,
        points: 5,
        amplitude: 100.0,
        ..FreqSweep::default()
    };
    let refused = |s: FreqSweep| axis.start_frequency_sweep(&s).unwrap_err().kind();
    let cases = [
        (
            FreqSweep {
                to_hz: 6000.0,
                ..ok
            },
            ErrorKind::FreqRange,
        ),
        (
            FreqSweep {
                to_hz: 2600.0,
                ..ok
            },
            ErrorKind::FreqRange,
        ),
        (
            FreqSweep {
                from_hz: 200.0,
                ..ok
            },
            ErrorKind::FreqRange,
        ),
        (FreqSweep { points: 0, ..ok }, ErrorKind::FreqRange),
        (FreqSweep { points: 257, ..ok }, ErrorKind::FreqRange),
        (
            FreqSweep {
                amplitude: -1.0,
                ..ok
            },
            ErrorKind::FreqAmplitude,
        ),
        (
            FreqSweep {
                amplitude: 0.0,
                ..ok
            },
            ErrorKind::FreqAmplitude,
        ),
        (
            FreqSweep {
                amplitude: f64::NAN,
                ..ok
            },
            ErrorKind::NotFinite,
        ),
        // 2 × 600 counts beyond the 1,000-count following-error limit at rest.
        (
            FreqSweep {
                amplitude: 600.0,
                ..ok
            },
            ErrorKind::FreqLimits,
        ),
        // 100 counts at 2.5 kHz: 1.6·10⁶ counts/s, beyond the 10⁶ the axis allows.
        (
            FreqSweep {
                to_hz: 2500.0,
                ..ok
            },
            ErrorKind::FreqLimits,
        ),
        (
            FreqSweep {
                mode: FreqMode::Output,
                amplitude: 10.5,
                ..ok
            },
            ErrorKind::FreqAmplitude,
        ),
    ];
    for (s, kind) in cases {
        assert_eq!(refused(s), kind, "{s:?}");
        let p = axis.freq_progress();
        assert_eq!(p.state, 0, "a refused sweep left the card's sweep {p:?}");
    }
    let after = axis.status().unwrap();
    assert_eq!(after.state, AxisState::Standstill);
    assert_eq!(after.command_position, before.command_position);
    axis.disable().unwrap();
    assert_eq!(refused(ok), ErrorKind::AxisDisabled);
    assert_eq!(axis.freq_progress().state, 0);
}

/// While a sweep runs its axis takes no move and the card no second sweep (FreqBusy); a halt
/// ends it (MC_FREQ_ABORTED, MC_EV_FREQ_DONE with the points measured), the sine removed.
#[test]
fn a_sweep_refuses_moves_and_ends_on_a_halt() {
    let card = default_card();
    let axis = card.axis(0).unwrap();
    let sim = card.sim().unwrap();
    let s = FreqSweep {
        from_hz: 20.0,
        to_hz: 200.0,
        points: 10,
        amplitude: 50.0,
        settle_s: 0.1,
        ..FreqSweep::default()
    };
    let seq = axis.start_frequency_sweep(&s).unwrap();
    sim.step(6_000);
    let p = axis.freq_progress();
    assert_eq!((p.state, p.seq, p.points), (1, seq, 10));
    assert!(p.done >= 1, "{p:?}");
    let lim = MoveLimits::new(1e5, 1e6, 1e8);
    assert_eq!(
        axis.move_absolute(1000.0, &lim).unwrap_err().kind(),
        ErrorKind::FreqBusy
    );
    assert_eq!(
        axis.start_frequency_sweep(&s).unwrap_err().kind(),
        ErrorKind::FreqBusy
    );
    axis.halt(1e6, 1e8).unwrap();
    let p = axis.freq_progress();
    assert_eq!(p.state, 3, "{p:?}");
    let done = p.done;
    assert!(done < 10);
    let mut ev = None;
    while let Some(e) = card.next_event(Duration::from_millis(50)).unwrap() {
        if e.kind == motioncard_sdk::EventKind::FreqDone {
            ev = Some(e);
        }
    }
    let e = ev.expect("MC_EV_FREQ_DONE");
    assert_eq!((e.seq, e.code, e.value), (seq, 3, done as f64));
    let r = axis.freq_result();
    assert!(!r.complete);
    assert_eq!(r.points.len(), done);
    // The sine is off: the axis holds its position again, and moves.
    sim.step(2_000);
    assert!(axis.status().unwrap().actual_position.abs() <= 2.0);
    axis.move_absolute(1000.0, &lim)
        .unwrap()
        .wait(LONG)
        .unwrap();
}

/// The machine table (a 24 Hz coupling, ζ = 0.03) read on the load, tuned low (the velocity
/// loop's crossover at 0.7 Hz: the resonance lifts the loop's gain 16.7× there, to about 0.5).
/// The in-position window is 20 counts (20 µm of the table).
fn resonant_card(crossover_hz: f64) -> Card {
    let mut m = MotorParams::machine_table(24.0);
    m.coulomb = 0.0;
    m.resonance = m.resonance.map(|r| r.on_load());
    let mut emu = EmuOptions::new(1, RATE);
    emu.motors[0] = m;
    let card = stepped_card_with(emu);
    let axis = card.axis(0).unwrap();
    let mut cfg = axis.settings().unwrap();
    cfg.ffpiv = FfpivGains::for_drive(m.accel_per_volt(), 2.0 * PI * crossover_hz);
    cfg.in_pos_window = 20.0;
    cfg.settle_time = 0.05;
    axis.configure(&cfg).unwrap();
    axis.enable().unwrap();
    card
}

/// Ticks from a move's start to its MotionDone (in position for the settle time).
fn move_ticks(card: &Card, to: f64) -> u64 {
    let axis = card.axis(0).unwrap();
    let t0 = axis.status().unwrap().raw.tick;
    let lim = MoveLimits::new(4e4, 2e6, 1e9);
    axis.move_absolute(to, &lim).unwrap().wait(LONG).unwrap();
    axis.status().unwrap().raw.tick - t0
}

/// The notch (part 3): the sweep on the servo output finds the load's 24 Hz resonance in the
/// plant; a notch set there through the biquad API lowers the open loop's peak by at least
/// 10 dB (a second sweep), and a move then settles sooner.
#[test]
fn a_notch_at_the_resonance_the_sweep_found_lowers_its_peak_and_the_move_settles_sooner() {
    let card = resonant_card(0.7);
    let axis = card.axis(0).unwrap();
    let s = FreqSweep {
        mode: FreqMode::Output,
        from_hz: 10.0,
        to_hz: 60.0,
        points: 60,
        amplitude: 0.5,
        cycles: 8,
        settle_s: 1.2,
    };
    let before = match axis.frequency_response(&s, LONG) {
        Ok(r) => r,
        Err(e) => panic!("{e}: {:?} {:?}", axis.status().unwrap(), axis.freq_result()),
    };
    let found: Vec<_> = before
        .resonances()
        .into_iter()
        .filter(|r| !r.anti)
        .collect();
    println!(
        "found: {:?}",
        found.iter().map(|r| r.name()).collect::<Vec<_>>()
    );
    assert_eq!(found.len(), 1, "{found:?}");
    let res = found[0];
    assert!((res.hz - 24.0).abs() < 1.0, "{res:?}");
    let l0 = before.open_loop();
    let k = (0..l0.len())
        .max_by(|&a, &b| l0[a].gain_db.total_cmp(&l0[b].gain_db))
        .unwrap();
    let ticks0 = move_ticks(&card, 20_000.0);
    axis.set_servo_filter(0, &BiquadSpec::notch(res.hz, 0.1, -30.0))
        .unwrap();
    let after = axis.frequency_response(&s, LONG).unwrap();
    let l1 = after.open_loop();
    let drop = l0[k].gain_db - l1[k].gain_db;
    let peak1 = l1.iter().map(|b| b.gain_db).fold(f64::MIN, f64::max);
    let ticks1 = move_ticks(&card, 0.0);
    println!(
        "notch at {:.2} Hz: open loop at {:.2} Hz {:.1} dB -> {:.1} dB (drop {drop:.1} dB; peak after {peak1:.1} dB); 20,000-count move done in {:.1} ms -> {:.1} ms",
        res.hz,
        l0[k].hz,
        l0[k].gain_db,
        l1[k].gain_db,
        ticks0 as f64 * 1e3 / RATE as f64,
        ticks1 as f64 * 1e3 / RATE as f64,
    );
    assert!(drop >= 10.0, "the notch lowered the peak by {drop} dB");
    // Without the notch the table rings at 24 Hz through the 20-count window for seconds.
    assert!(
        2 * ticks1 < ticks0,
        "{ticks1} ticks with the notch, {ticks0} without"
    );
}

/// `mcctl freq`'s JSON: the points (hz, gain_db, phase_deg), the resonances, the plant and
/// the open loop.
#[test]
fn mcctl_freq_json_has_points_and_resonances() {
    let card = default_card();
    let s = FreqSweep {
        from_hz: 10.0,
        to_hz: 100.0,
        points: 4,
        amplitude: 100.0,
        ..FreqSweep::default()
    };
    let r = mcctl::cli::freq::freq(&card, 0, &s).unwrap();
    let j = mcctl::cli::freq::to_json(&r);
    let pts = j["points"].as_array().unwrap();
    assert_eq!(pts.len(), 4);
    for p in pts {
        assert!(p["hz"].as_f64().unwrap() > 9.0);
        assert!(p["gain_db"].as_f64().unwrap().is_finite());
        assert!(p["phase_deg"].as_f64().unwrap().abs() <= 180.0);
    }
    assert!(j["resonances"].is_array());
    assert_eq!(j["plant"].as_array().unwrap().len(), 4);
    assert_eq!(j["open_loop"].as_array().unwrap().len(), 4);
    assert!(mcctl::cli::freq::table(&r).contains("closed loop"));
}

/// The scope samples the sweep's sine (`MC_SIG_FREQ_INJECT`, counts on the reference) and
/// its frequency (`MC_SIG_FREQ_HZ`): the sine within its amplitude, the frequencies of the
/// points the card runs, 0 on another axis.
#[test]
fn the_scope_samples_the_sweeps_sine_and_frequency() {
    use motioncard_sdk::{ScopeSettings, Signal, Source};
    let card = stepped_card_with(EmuOptions::new(2, RATE));
    let axis = card.axis(0).unwrap();
    axis.enable().unwrap();
    let s = FreqSweep {
        from_hz: 50.0,
        to_hz: 100.0,
        points: 2,
        amplitude: 80.0,
        settle_s: 0.0,
        ..FreqSweep::default()
    };
    let settings = ScopeSettings::new(
        &[
            Source::axis(Signal::FreqInject, 0),
            Source::axis(Signal::FreqHz, 0),
            Source::axis(Signal::FreqInject, 1),
        ],
        3_000,
    );
    let cap = card
        .scope()
        .capture(&settings, LONG, |_| {
            axis.start_frequency_sweep(&s).map(|_| ())
        })
        .unwrap();
    let (mut peak, mut hz) = (0.0f64, Vec::new());
    for smp in &cap.samples {
        let v = smp.value;
        assert!(v[0].abs() <= 80.0 + 1e-9, "{v:?}");
        assert_eq!(v[2], 0.0);
        peak = peak.max(v[0].abs());
        if !hz.contains(&v[1]) {
            hz.push(v[1]);
        }
    }
    assert!(peak > 70.0, "the sine's peak {peak}");
    assert!(hz.contains(&50.0), "{hz:?}");
}
