//! The papers' experiments, reproduced on the stepped emulated card (the runs themselves are in
//! `motioncard::papers`; here they are checked).
use card_emu::filters::exponential_pole;
use motioncard::papers::{
    kim_fig7, radial_error, shin_corner, KIM_FIG7_FEED, KIM_FIG7_TAU, RADIAL_CASES,
};
use motioncard::{FilterKind, Interpolator, MotorParams};

/// Kim Fig 7: 81,920 pulses on X with linear and with exponential acc/dec. The commanded
/// position ends exactly on the goal; the velocity ramps are the filters' step responses.
#[test]
fn kim_fig7_x_move_through_linear_and_exponential_acc_dec() {
    let feed = KIM_FIG7_FEED;
    for kind in [FilterKind::Linear, FilterKind::Exponential] {
        let r = kim_fig7(kind).unwrap();
        assert_eq!(r.final_cmd, 81_920.0, "{kind:?}: commanded end");
        assert!(
            (r.final_act - 81_920.0).abs() <= 1.0,
            "{kind:?}: actual {}",
            r.final_act
        );
        let m = (KIM_FIG7_TAU * 1000.0).round() as usize;
        match kind {
            // Kim eq 1: the velocity ramps linearly over m = τ/T ticks.
            FilterKind::Linear => {
                for (k, v) in r.vel.iter().take(m).enumerate() {
                    assert!(
                        (v - feed * (k + 1) as f64 / m as f64).abs() < 1e-6,
                        "tick {k}: {v}"
                    );
                }
                assert!((r.vel[m + 50] - feed).abs() < 1e-6);
            }
            // Kim eq 7–9: v(k) = V (1 − a^(k+1)), a = τ/(τ+T).
            _ => {
                let a = exponential_pole(KIM_FIG7_TAU, 1e-3);
                for (k, v) in r.vel.iter().take(3 * m).enumerate() {
                    assert!(
                        (v - feed * (1.0 - a.powi(k as i32 + 1))).abs() < 1e-6 * feed,
                        "tick {k}: {v}"
                    );
                }
            }
        }
    }
}

/// Kim §4: circles through the linear filter match the corrected eq 28, through the
/// exponential filter eq 32, within 1% of ΔR, over 12 combinations each of radius, feed,
/// sample time and time constant, with the exact and the reference-word interpolators.
#[test]
fn kim_sec4_radial_error_matches_eq28_and_eq32() {
    let mut cases = 0;
    let mut worst: f64 = 0.0;
    for kind in [FilterKind::Linear, FilterKind::Exponential] {
        for (i, &(r, omega, rate, tau)) in RADIAL_CASES.iter().enumerate() {
            for interp in [Interpolator::Exact, Interpolator::ReferenceWord] {
                let (measured, formula) = radial_error(kind, r, omega, rate, tau, interp).unwrap();
                assert!(
                    formula > 1e-5 * r,
                    "case {i}: ΔR {formula} too small to measure"
                );
                let rel = (measured - formula).abs() / formula;
                worst = worst.max(rel);
                assert!(rel <= 0.01, "{kind:?} {interp:?} case {i} (R {r}, Ω {omega}, {rate} Hz, τ {tau}): measured ΔR {measured}, formula {formula}");
                cases += 1;
            }
        }
    }
    assert_eq!(cases, 48);
    println!("{cases} cases, worst |ΔR measured − formula| / ΔR = {worst:.2e}");
}

/// Shin's corner test on the machine-table plant (a coupling resonance at 33 Hz): the longer
/// time constant rounds the commanded corner more but excites the coupling less, so the table
/// tracks its command better; with the linear filter the table's total corner error drops.
#[test]
fn shin_corner_time_constant_trade_off() {
    let table = MotorParams::machine_table(33.0);
    for kind in [FilterKind::Linear, FilterKind::Exponential] {
        let short = shin_corner(table, kind, 0.015).unwrap();
        let long = shin_corner(table, kind, 0.030).unwrap();
        assert!(
            long.command_rounding > short.command_rounding,
            "{kind:?}: a longer filter should round the command more"
        );
        assert!(
            long.tracking < short.tracking,
            "{kind:?}: a longer filter should excite the resonance less"
        );
        if kind == FilterKind::Linear {
            assert!(
                long.total < short.total,
                "linear: 30 ms {} µm vs 15 ms {} µm",
                long.total,
                short.total
            );
        }
    }
    // The rigid default plant has no resonance to excite: the tracking error barely changes.
    let rigid = MotorParams::default_servo();
    let (s, l) = (
        shin_corner(rigid, FilterKind::Linear, 0.015).unwrap(),
        shin_corner(rigid, FilterKind::Linear, 0.030).unwrap(),
    );
    assert!(
        s.tracking < 10.0 && l.tracking < 10.0,
        "rigid tracking {} / {} µm",
        s.tracking,
        l.tracking
    );
}
