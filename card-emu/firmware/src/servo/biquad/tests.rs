use super::*;
use proptest::prelude::*;

const RATE: f64 = 10_000.0;

fn gain_db(spec: &BiquadSpec, hz: f64) -> f64 {
    Biquad::new(design(spec, RATE).unwrap())
        .response(hz, RATE)
        .0
}

/// The discrete transfer function of a notch: the set depth at its centre (to 0.1 dB, exact by
/// the pre-warping), about 0 dB a decade either side.
#[test]
fn a_notch_has_its_depth_at_its_centre_and_nothing_a_decade_away() {
    for (hz, zeta, depth) in [
        (24.0, 0.2, -20.0),
        (300.0, 0.1, -40.0),
        (1500.0, 0.3, -12.0),
        (4000.0, 0.05, -30.0),
    ] {
        let n = BiquadSpec::notch(hz, zeta, depth);
        let centre = gain_db(&n, hz);
        assert!(
            (centre - depth).abs() < 0.1,
            "{hz} Hz: {centre} dB, set {depth}"
        );
        if hz * 10.0 < RATE / 2.0 {
            let above = gain_db(&n, hz * 10.0);
            assert!(above.abs() < 0.5, "{hz} Hz ×10: {above} dB");
        }
        let below = gain_db(&n, hz / 10.0);
        assert!(below.abs() < 0.5, "{hz} Hz ÷10: {below} dB");
        assert!((Biquad::new(design(&n, RATE).unwrap()).dc_gain() - 1.0).abs() < 1e-12);
    }
}

/// Amplitude of the last `n` samples of a sine run through the filter.
fn measured_gain_db(spec: &BiquadSpec, hz: f64) -> f64 {
    let mut f = Biquad::new(design(spec, RATE).unwrap());
    let (mut sc, mut ss) = (0.0, 0.0);
    let settle = 40_000; // 4 s: the lightest damping here settles in well under that
    let n = (RATE / hz * 200.0).round() as usize; // 200 whole periods
    for k in 0..settle + n {
        let th = 2.0 * core::f64::consts::PI * hz * k as f64 / RATE;
        let y = f.run(th.sin());
        if k >= settle {
            sc += y * th.cos();
            ss += y * th.sin();
        }
    }
    let amp = 2.0 * (sc * sc + ss * ss).sqrt() / n as f64;
    20.0 * amp.log10()
}

/// The same through the firmware's filter: a sine in, its amplitude out.
#[test]
fn a_sine_through_the_notch_comes_out_at_the_set_depth() {
    let n = BiquadSpec::notch(24.0, 0.2, -20.0);
    let centre = measured_gain_db(&n, 24.0);
    assert!((centre + 20.0).abs() < 0.1, "{centre} dB at the centre");
    let above = measured_gain_db(&n, 240.0);
    assert!(above.abs() < 0.5, "{above} dB a decade above");
    let below = measured_gain_db(&n, 2.4);
    assert!(below.abs() < 0.5, "{below} dB a decade below");
}

#[test]
fn a_low_pass_and_a_lead_lag_have_their_prototypes_corners() {
    // Second order, ζ = 0.707: −3 dB at the corner; −40 dB a decade above.
    let lp = BiquadSpec::low_pass(200.0, core::f64::consts::FRAC_1_SQRT_2);
    assert!((gain_db(&lp, 200.0) + 3.0103).abs() < 0.01);
    assert!(gain_db(&lp, 2.0).abs() < 0.01);
    assert!(gain_db(&lp, 2000.0) < -38.0);
    // A lead from 50 to 500 Hz: +20 dB at high frequency, 0 at DC.
    let lead = BiquadSpec::lead_lag(50.0, 500.0);
    assert!(gain_db(&lead, 0.5).abs() < 0.01);
    let hi = gain_db(&lead, 4900.0);
    assert!((hi - 20.0).abs() < 0.5, "{hi}");
    // The lag the other way round.
    assert!((gain_db(&BiquadSpec::lead_lag(500.0, 50.0), 4900.0) + 20.0).abs() < 0.5);
}

#[test]
fn bad_filters_are_refused_with_their_own_codes() {
    let nyq = RATE / 2.0;
    let e = |s: BiquadSpec| design(&s, RATE).unwrap_err();
    assert_eq!(e(BiquadSpec::notch(nyq, 0.2, -20.0)), NackCode::FilterFreq);
    assert_eq!(
        e(BiquadSpec::notch(6000.0, 0.2, -20.0)),
        NackCode::FilterFreq
    );
    assert_eq!(e(BiquadSpec::notch(0.0, 0.2, -20.0)), NackCode::FilterFreq);
    assert_eq!(e(BiquadSpec::low_pass(-5.0, 0.7)), NackCode::FilterFreq);
    assert_eq!(e(BiquadSpec::lead_lag(50.0, nyq)), NackCode::FilterFreq);
    assert_eq!(
        e(BiquadSpec::notch(100.0, 0.0, -20.0)),
        NackCode::FilterParam
    );
    assert_eq!(
        e(BiquadSpec::notch(100.0, -0.1, -20.0)),
        NackCode::FilterParam
    );
    assert_eq!(e(BiquadSpec::notch(100.0, 0.2, 3.0)), NackCode::FilterParam);
    assert_eq!(
        e(BiquadSpec::notch(100.0, 0.2, -121.0)),
        NackCode::FilterParam
    );
    assert_eq!(
        e(BiquadSpec::notch(f64::NAN, 0.2, -20.0)),
        NackCode::NotFinite
    );
    assert_eq!(
        e(BiquadSpec::low_pass(100.0, f64::INFINITY)),
        NackCode::NotFinite
    );
    // Raw: a pole at 1.1, and a pair on the circle.
    assert_eq!(
        e(BiquadSpec::raw([1.0, 0.0, 0.0, -1.1, 0.0])),
        NackCode::FilterUnstable
    );
    assert_eq!(
        e(BiquadSpec::raw([1.0, 0.0, 0.0, 0.0, 1.0])),
        NackCode::FilterUnstable
    );
    // A notch so light and low its poles lie within the margin of the circle.
    assert_eq!(
        e(BiquadSpec::notch(1e-3, 1e-3, -20.0)),
        NackCode::FilterUnstable
    );
    assert!(design(&BiquadSpec::raw([0.5, 0.5, 0.0, 0.0, 0.0]), RATE).is_ok());
}

/// A filter set on a chain at rest with a constant input starts from that input's steady
/// state (no step), and a cleared one is gone.
#[test]
fn a_filter_set_at_rest_does_not_step_the_output() {
    let mut ch = ServoFilters::default();
    assert!(!ch.any());
    ch.set(2, &BiquadSpec::low_pass(100.0, 0.7), RATE, 1.5)
        .unwrap();
    ch.set(0, &BiquadSpec::notch(24.0, 0.2, -20.0), RATE, 1.5)
        .unwrap();
    for _ in 0..10 {
        assert!((ch.run(1.5) - 1.5).abs() < 1e-12);
    }
    // A refused filter changes nothing.
    let before = ch;
    assert_eq!(
        ch.set(1, &BiquadSpec::notch(9000.0, 0.2, -20.0), RATE, 1.5),
        Err(NackCode::FilterFreq)
    );
    assert_eq!(ch, before);
    ch.clear(0);
    ch.clear(2);
    assert!(!ch.any());
    assert_eq!(ch.run(0.25), 0.25);
    assert_eq!(ch.block().active, 0);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(4000))]
    /// Any numbers at all: never a panic; accepted and stable, or refused.
    #[test]
    fn any_filter_parameters_are_accepted_stable_or_refused(
        kind in 0usize..4,
        f in any::<u64>().prop_map(f64::from_bits),
        d in any::<u64>().prop_map(f64::from_bits),
        depth in any::<u64>().prop_map(f64::from_bits),
        f2 in any::<u64>().prop_map(f64::from_bits),
        c in proptest::array::uniform5(any::<u64>().prop_map(f64::from_bits)),
        scale in prop_oneof![Just(1.0), Just(0.0)],
        rate in prop_oneof![Just(1000.0), Just(10_000.0), Just(20_000.0)],
    ) {
        // Half the cases in the plausible range (the bit patterns are mostly huge or tiny).
        let squash = |x: f64| if scale == 0.0 { (x.abs() % 1e4) - 50.0 } else { x };
        let spec = BiquadSpec {
            kind: BiquadKind::ALL[kind],
            freq_hz: squash(f),
            damping: if scale == 0.0 { d.abs() % 2.0 } else { d },
            depth_db: squash(depth) % 130.0,
            freq2_hz: squash(f2),
            coeffs: c.map(|x| if scale == 0.0 { x % 3.0 } else { x }),
        };
        if let Ok(c) = design(&spec, rate) {
            prop_assert!(c.iter().all(|x| x.is_finite()));
            prop_assert!(pole_radius(c[3], c[4]) <= 1.0 - POLE_MARGIN);
            // And the filter runs: bounded for a bounded input.
            let mut b = Biquad::new(c);
            for k in 0..64 {
                let x = if k % 2 == 0 { 1.0 } else { -1.0 };
                let y = b.run(x);
                prop_assert!(y.is_finite());
            }
        }
    }
}
