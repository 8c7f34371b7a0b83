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

/// `Ffpiv::set_mid_count` (a gantry's members): a shaft cruising at 10⁶ counts/s (100 counts
/// a tick, the reference on a whole count every tick), started 0.1 or 0.9 count past the
/// reference. Reading the count as it is, the position error is 0 anywhere within the count:
/// the shaft wanders over the whole count ahead of the reference, and two shafts on the same
/// reference part by up to a count while their encoders agree. Reading it at its middle, the
/// shaft is held on the count's edge at the reference, within a twentieth of a count of it.
#[test]
fn reading_the_count_at_its_middle_holds_a_cruising_shaft_on_its_reference() {
    let params = MotorParams::default_servo();
    let gains = FfpivGains::default();
    let ts = 1e-4;
    let v = 1e6;
    let cpr = params.counts_per_rad();
    // (largest |shaft − reference| over the last 10,000 ticks, its smallest, the mean)
    let cruise = |start: f64, mid: bool| -> (f64, f64, f64) {
        let mut m = Motor::new(params);
        m.theta = start / cpr;
        m.omega = v / cpr;
        let mut s = Ffpiv::default();
        s.set_mid_count(mid);
        // The integrator holds the drag at speed (viscous and Coulomb): start it there.
        let drag = params.damping * m.omega + params.coulomb;
        s.transfer(drag / (params.kt * params.amp_gain), &gains);
        let (mut hi, mut lo, mut sum) = (f64::MIN, f64::MAX, 0.0);
        for k in 0..30_000u32 {
            let t = k as f64 * ts;
            let r = Reference {
                pos: v * t,
                vel: v,
                acc: 0.0,
            };
            let enc = m.encoder();
            if k >= 20_000 {
                let off = m.position_counts() - r.pos;
                hi = hi.max(off);
                lo = lo.min(off);
                sum += off;
            }
            s.measure(enc, &gains, ts);
            let u = s
                .update(&r, enc as f64, &gains, ts, 10.0)
                .clamp(-10.0, 10.0);
            m.step(Dac::output(u).0, ts);
        }
        (hi, lo, sum / 10_000.0)
    };
    let (a, b) = (cruise(0.1, false), cruise(0.9, false));
    println!("the count as read: shafts {a:?} and {b:?} past the reference (most, least, mean)");
    for (hi, lo, _) in [a, b] {
        assert!(
            hi - lo > 0.9,
            "the shaft wanders within its count: {a:?} {b:?}"
        );
    }
    let (a, b) = (cruise(0.1, true), cruise(0.9, true));
    println!("the count read at its middle: shafts {a:?} and {b:?} past the reference (most, least, mean)");
    for (hi, lo, _) in [a, b] {
        assert!(hi.abs() < 0.05 && lo.abs() < 0.05, "{a:?} {b:?}");
    }
    assert!((a.2 - b.2).abs() < 0.05, "{a:?} {b:?}");
}
