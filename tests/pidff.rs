//! Layout 1.11: the PID + feed-forward servo law and the biquad filters on the servo output,
//! on the stepped card against the emulator's plant. The following errors of PID+FF and FFPIV
//! on the same S-curve are printed: `cargo test --release --test pidff -- --nocapture`.
mod common;

use common::stepped_card_with;
use motioncard_sdk::{
    AxisState, BiquadKind, BiquadSpec, Card, EmuOptions, ErrorKind, MotorParams, MoveLimits,
    PidffSettings, BIQUADS,
};
use std::time::Duration;

const RATE: u32 = 10_000;
const LONG: Duration = Duration::from_secs(30);

fn card_with(motor: MotorParams) -> Card {
    let mut emu = EmuOptions::new(1, RATE);
    emu.motors[0] = motor;
    let card = stepped_card_with(emu);
    card.axis(0).unwrap().enable().unwrap();
    card
}

/// PID+FF for the default plant: the default placement with the plant's viscous damping and
/// Coulomb friction fed forward (volts per count/s, volts).
fn tuned(m: &MotorParams) -> PidffSettings {
    let volts_per_torque = 1.0 / (m.kt * m.amp_gain);
    PidffSettings {
        kvff: m.damping / m.counts_per_rad() * volts_per_torque,
        friction: m.coulomb * volts_per_torque,
        friction_deadband: 50.0,
        ..PidffSettings::for_drive(m.accel_per_volt(), 2.0 * std::f64::consts::PI * 60.0)
    }
}

/// The largest |following error| over a 50,000-count S-curve and the 50 ms after it.
fn worst_error(card: &Card) -> f64 {
    let axis = card.axis(0).unwrap();
    let sim = card.sim().unwrap();
    let lim = MoveLimits::new(2e5, 2e6, 1e8);
    let m = axis.move_relative(50_000.0, &lim).unwrap();
    let mut worst: f64 = 0.0;
    sim.trace(0, 10_000, |s| {
        worst = worst.max(s.raw.ferr.abs());
        s.state == AxisState::DiscreteMotion
    })
    .unwrap();
    m.wait(LONG).unwrap();
    sim.trace(0, 500, |s| {
        worst = worst.max(s.raw.ferr.abs());
        true
    })
    .unwrap();
    worst
}

/// Under PID+FF with the plant's inertia, damping and friction fed forward the axis follows an
/// S-curve (2·10⁵ counts/s, 2·10⁶ counts/s², 10⁸ counts/s³) within 2 counts. The bound: the
/// output of tick k holds over [k, k+1) while the reference's acceleration moves on by j·T in
/// it, a mismatch of j·T/2 = 5,000 counts/s² on average, whose double integral over a jerk
/// phase (a/j = 20 ms) is j·T/2·(a/j)²/2 = 1 count with no feedback at all; the encoder's
/// quantisation adds a count. (The friction feed-forward steps at ±50 counts/s, the plant's
/// friction at 0: 0.033 V for the 1 ms between, 0.02 count.) FFPIV on the same move is
/// printed beside it.
#[test]
fn pidff_follows_an_s_curve_within_its_bound() {
    let m = MotorParams::default_servo();
    let card = card_with(m);
    card.axis(0).unwrap().configure_pidff(&tuned(&m)).unwrap();
    let pid = worst_error(&card);
    let card = card_with(m);
    let ffpiv = worst_error(&card);
    println!("S-curve 50,000 counts: worst following error PID+FF {pid:.2} counts, FFPIV {ffpiv:.2} counts");
    assert!(pid <= 2.0, "PID+FF following error {pid}");
}

/// The settings read back are those set; refused gains change nothing.
#[test]
fn pidff_gains_are_read_back_and_bad_ones_refused() {
    let card = card_with(MotorParams::default_servo());
    let axis = card.axis(0).unwrap();
    assert_eq!(axis.pidff_settings().unwrap(), None);
    let g = tuned(&MotorParams::default_servo());
    axis.configure_pidff(&g).unwrap();
    assert_eq!(axis.pidff_settings().unwrap(), Some(g));
    for (bad, kind) in [
        (PidffSettings { ki: -1.0, ..g }, ErrorKind::PidffGains),
        (
            PidffSettings {
                friction: -0.1,
                ..g
            },
            ErrorKind::PidffGains,
        ),
        (
            PidffSettings {
                friction_deadband: 0.0,
                ..g
            },
            ErrorKind::PidffGains,
        ),
        (
            PidffSettings {
                d_filter_hz: 0.0,
                ..g
            },
            ErrorKind::PidffGains,
        ),
        (PidffSettings { kd: f64::NAN, ..g }, ErrorKind::NotFinite),
        (
            PidffSettings {
                kp: f64::INFINITY,
                ..g
            },
            ErrorKind::NotFinite,
        ),
    ] {
        assert_eq!(
            axis.configure_pidff(&bad).unwrap_err().kind(),
            kind,
            "{bad:?}"
        );
        assert_eq!(axis.pidff_settings().unwrap(), Some(g));
    }
}

/// At rest against a constant load torque the integrator holds the output; switching the law
/// (FFPIV → PID+FF → FFPIV) does not step the DAC.
#[test]
fn switching_the_law_at_rest_is_bumpless() {
    let m = MotorParams::default_servo();
    let card = card_with(m);
    let sim = card.sim().unwrap();
    let axis = card.axis(0).unwrap();
    sim.with_emulator(|e| e.motor_mut(0).unwrap().disturbance = 0.45);
    sim.step(20_000);
    let dac = || axis.status().unwrap().raw.dac_v;
    let held = dac();
    assert!(held.abs() > 1.0, "the integrator holds {held} V");
    let settings = axis.settings().unwrap();
    let mut worst: f64 = 0.0;
    let mut watch = |card: &Card| {
        card.sim()
            .unwrap()
            .trace(0, 200, |s| {
                worst = worst.max((s.raw.dac_v - held).abs());
                true
            })
            .unwrap();
    };
    axis.configure_pidff(&tuned(&m)).unwrap();
    watch(&card);
    axis.configure(&settings).unwrap();
    watch(&card);
    println!("law switched at {held:.3} V: the DAC moved at most {worst:.4} V");
    assert!(worst < 0.05, "the DAC stepped by {worst} V");
}

/// Filters through the SDK: set and read back, refused with their own codes changing nothing,
/// cleared.
#[test]
fn filters_are_set_read_back_refused_and_cleared() {
    let card = card_with(MotorParams::default_servo());
    let axis = card.axis(0).unwrap();
    assert!(axis.servo_filters().unwrap().iter().all(Option::is_none));
    let notch = BiquadSpec::notch(24.0, 0.2, -20.0);
    axis.set_servo_filter(1, &notch).unwrap();
    axis.set_servo_filter(3, &BiquadSpec::low_pass(800.0, 0.7))
        .unwrap();
    let held = axis.servo_filters().unwrap();
    assert_eq!(held[1].unwrap().spec, notch);
    assert_eq!(held[3].unwrap().spec.kind, BiquadKind::LowPass);
    assert!(held[0].is_none() && held[2].is_none());
    let nyquist = RATE as f64 / 2.0;
    for (slot, spec, kind) in [
        (4, notch, ErrorKind::FilterKind),
        (
            0,
            BiquadSpec::notch(nyquist, 0.2, -20.0),
            ErrorKind::FilterFreq,
        ),
        (0, BiquadSpec::lead_lag(10.0, 7000.0), ErrorKind::FilterFreq),
        (
            0,
            BiquadSpec::notch(24.0, -0.2, -20.0),
            ErrorKind::FilterParam,
        ),
        (0, BiquadSpec::notch(24.0, 0.2, 6.0), ErrorKind::FilterParam),
        (
            0,
            BiquadSpec::raw([1.0, 0.0, 0.0, -2.0, 1.0]),
            ErrorKind::FilterUnstable,
        ),
        (0, BiquadSpec::low_pass(f64::NAN, 0.7), ErrorKind::NotFinite),
        (
            1,
            BiquadSpec::notch(24.0, 0.2, f64::INFINITY),
            ErrorKind::NotFinite,
        ),
    ] {
        let e = axis.set_servo_filter(slot, &spec).unwrap_err();
        assert_eq!(e.kind(), kind, "slot {slot} {spec:?}");
        assert_eq!(axis.servo_filters().unwrap(), held, "changed by {spec:?}");
    }
    assert_eq!(
        axis.clear_servo_filter(BIQUADS).unwrap_err().kind(),
        ErrorKind::FilterKind
    );
    axis.clear_servo_filters().unwrap();
    assert!(axis.servo_filters().unwrap().iter().all(Option::is_none));
}

/// Four filters on the servo output of an axis at rest: a set filter does not step the DAC;
/// a move under PID+FF with a notch and a low-pass still ends in position.
#[test]
fn filters_set_at_rest_do_not_step_the_dac_and_the_loop_still_settles() {
    let m = MotorParams::default_servo();
    let card = card_with(m);
    let sim = card.sim().unwrap();
    let axis = card.axis(0).unwrap();
    axis.configure_pidff(&tuned(&m)).unwrap();
    sim.with_emulator(|e| e.motor_mut(0).unwrap().disturbance = 0.3);
    sim.step(20_000);
    let held = axis.status().unwrap().raw.dac_v;
    axis.set_servo_filter(0, &BiquadSpec::notch(300.0, 0.3, -20.0))
        .unwrap();
    axis.set_servo_filter(1, &BiquadSpec::low_pass(1500.0, 0.7))
        .unwrap();
    axis.set_servo_filter(2, &BiquadSpec::lead_lag(400.0, 600.0))
        .unwrap();
    axis.set_servo_filter(3, &BiquadSpec::notch(2000.0, 0.2, -10.0))
        .unwrap();
    let mut worst: f64 = 0.0;
    sim.trace(0, 100, |s| {
        worst = worst.max((s.raw.dac_v - held).abs());
        true
    })
    .unwrap();
    assert!(worst < 0.02, "the DAC stepped by {worst} V from {held} V");
    let at = axis
        .move_relative(20_000.0, &MoveLimits::new(1e5, 1e6, 1e8))
        .unwrap()
        .wait(LONG)
        .unwrap();
    assert!((at - axis.status().unwrap().raw.target).abs() <= 1.0);
}

/// The scope samples the filter chain's input and output and the friction feed-forward: with
/// a low-pass set, over a move the output lags the input (they differ), and the friction term
/// is ±friction while the reference moves beyond the deadband.
#[test]
fn the_scope_samples_the_filter_chain_and_the_friction_term() {
    use motioncard_sdk::{ScopeSettings, Signal, Source};
    let m = MotorParams::default_servo();
    let card = card_with(m);
    let axis = card.axis(0).unwrap();
    let g = tuned(&m);
    axis.configure_pidff(&g).unwrap();
    axis.set_servo_filter(0, &BiquadSpec::low_pass(500.0, 0.7))
        .unwrap();
    let settings = ScopeSettings::new(
        &[
            Source::axis(Signal::FilterIn, 0),
            Source::axis(Signal::FilterOut, 0),
            Source::axis(Signal::URequest, 0),
            Source::axis(Signal::ServoFriction, 0),
            Source::axis(Signal::CmdVel, 0),
        ],
        2_000,
    );
    let cap = card
        .scope()
        .capture(&settings, LONG, |_| {
            axis.move_relative(20_000.0, &MoveLimits::new(2e5, 2e6, 1e8))
                .map(|_| ())
        })
        .unwrap();
    assert_eq!(cap.samples.len(), 2_000);
    let mut differ = 0;
    for s in &cap.samples {
        let v = s.value;
        assert_eq!(v[1], v[2], "the chain's output is u_request");
        if (v[0] - v[1]).abs() > 1e-3 {
            differ += 1;
        }
        let want = if v[4] > g.friction_deadband {
            g.friction
        } else {
            0.0
        };
        assert_eq!(v[3], want, "friction term at v_ref {}", v[4]);
    }
    assert!(differ > 100, "the low-pass changed {differ} samples");
}

/// The machine table of the Shin experiment with its coupling resonating at 300 Hz
/// (`MotorParams::machine_table`: motor 2·10⁻⁴, table 3·10⁻⁴ kg·m², ζ = 0.03), under PID+FF
/// placed for a 60 Hz crossover, with a notch at the resonance or a second-order low-pass at
/// 600 Hz on the servo output: the loop stays stable, the move ends in position and the axis
/// holds within a count (2 counts peak-to-peak of following error) over the last 100 ms of a
/// second at rest. (The same without a filter is printed beside them. Not shown here: a
/// resonance that makes this loop ring. With the encoder on the motor the emulator's coupling
/// did not, at any tuning that was stable on the plain plant.)
#[test]
fn a_notch_or_low_pass_on_a_resonant_plant_keeps_the_loop_stable() {
    const HZ: f64 = 300.0;
    const LP: f64 = 600.0;
    let run = |filter: Option<BiquadSpec>| {
        let m = MotorParams::machine_table(HZ);
        let card = card_with(m);
        let axis = card.axis(0).unwrap();
        let g = PidffSettings::for_drive(m.accel_per_volt(), 2.0 * std::f64::consts::PI * 60.0);
        axis.configure_pidff(&g).unwrap();
        if let Some(f) = filter {
            axis.set_servo_filter(0, &f).unwrap();
        }
        let mv = axis
            .move_relative(5_000.0, &MoveLimits::new(1e5, 1e6, 1e8))
            .unwrap();
        let sim = card.sim().unwrap();
        sim.step(9_000);
        let (mut lo, mut hi) = (f64::MAX, f64::MIN);
        sim.trace(0, 1_000, |s| {
            lo = lo.min(s.raw.ferr);
            hi = hi.max(s.raw.ferr);
            true
        })
        .unwrap();
        let st = axis.status().unwrap();
        assert_ne!(
            st.state,
            AxisState::ErrorStop,
            "{filter:?}: stop {:?}",
            st.raw.stop_reason
        );
        (hi - lo, mv.wait(Duration::ZERO).is_ok())
    };
    let bare = run(None);
    let notched = run(Some(BiquadSpec::notch(HZ, 0.3, -30.0)));
    let low = run(Some(BiquadSpec::low_pass(LP, 0.7)));
    println!(
        "resonance {HZ} Hz: p-p following error at rest: none {:.0}, notch {:.0}, low-pass {:.0} counts",
        bare.0, notched.0, low.0
    );
    for (name, (pp, done)) in [("notch", notched), ("low-pass", low)] {
        assert!(done, "{name}: the move did not end in position");
        assert!(pp <= 2.0, "{name}: {pp} counts peak-to-peak");
    }
}

/// `[axis.N.pidff]` in the configuration file: saved from the card, loaded onto another card
/// (the same gains read back), and refused whole, naming the key, with a negative gain or
/// without its table.
#[test]
fn pidff_goes_through_the_configuration_file() {
    let m = MotorParams::default_servo();
    let card = card_with(m);
    let g = tuned(&m);
    card.axis(0).unwrap().configure_pidff(&g).unwrap();
    let text = card.save_config().unwrap();
    assert!(text.contains("servo_law = \"pidff\""), "{text}");
    assert!(text.contains("[axis.0.pidff]"), "{text}");
    let other = card_with(m);
    other.load_config(&text, "machine.toml").unwrap();
    assert_eq!(other.axis(0).unwrap().pidff_settings().unwrap(), Some(g));
    // A negative gain: refused whole, naming the key; nothing changed.
    let fresh = card_with(m);
    let bad = text.replace(&format!("ki = {:?}", g.ki), "ki = -1.0");
    assert_ne!(bad, text, "the ki line");
    let e = fresh.load_config(&bad, "machine.toml").unwrap_err();
    assert_eq!(e.kind(), ErrorKind::ConfigFile);
    assert!(e.to_string().contains("axis.0.pidff"), "{e}");
    assert_eq!(fresh.axis(0).unwrap().pidff_settings().unwrap(), None);
    // The law without its table.
    let start = text.find("[axis.0.pidff]").unwrap();
    let end = text[start + 1..]
        .find("\n[")
        .map_or(text.len(), |k| start + 1 + k);
    let without = format!("{}{}", &text[..start], &text[end..]);
    let e = fresh.load_config(&without, "machine.toml").unwrap_err();
    assert!(
        e.to_string().contains("needs the table [axis.0.pidff]"),
        "{e}"
    );
}
