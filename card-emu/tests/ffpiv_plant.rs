//! The FFPIV servo law (`card_firmware::servo::ffpiv`) closed around the plant's default motor:
//! the default tuning on the default motor (the firmware crate has no plant).
use card_emu::firmware::dac::Dac;
use card_emu::servo::ffpiv::{Ffpiv, FfpivGains, Reference};
use card_emu::{Motor, MotorParams};

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
        m.step(Dac::output(u).0, ts);
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
        m.step(Dac::output(u).0, ts);
    }
    assert!(
        (m.encoder() as f64 - 40.5).abs() <= 0.5,
        "settled at {}",
        m.encoder()
    );
    assert_eq!(changes, 0, "the encoder kept changing after settling");
}
