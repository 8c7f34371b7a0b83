//! The papers' experiments, reproduced on the stepped emulated card: Kim Fig 7 and §4 (radial
//! error of circles through the acc/dec filters), Shin's corner test.
mod common;

use card_emu::circle::{exponential_filter_radial_error, linear_filter_radial_error};
use card_emu::filters::exponential_pole;
use common::stepped_card_with;
use motioncard::{
    AccDec, ArcSpec, Card, EmuOptions, FeedType, FilterKind, FilterSettings, GroupSettings,
    GroupState, Interpolator, MotorParams, MoveOptions, PathLimits, Plane,
};
use std::time::Duration;

const T: Duration = Duration::from_secs(60);

/// A card with a 2-axis group (axes 0, 1) using post-interpolation filters of `kind`/`tau`.
fn filtered_group(
    emu: EmuOptions,
    kind: FilterKind,
    tau: f64,
    interp: Interpolator,
) -> (Card, motioncard::Group) {
    let card = stepped_card_with(emu);
    for a in 0..2 {
        let ax = card.axis(a).unwrap();
        ax.set_filters(&FilterSettings::all(kind, tau)).unwrap();
        ax.enable().unwrap();
    }
    let g = card.group(0).unwrap();
    g.configure(&GroupSettings {
        accdec: AccDec::Post,
        interpolator: interp,
        ..GroupSettings::new(&[0, 1])
    })
    .unwrap();
    g.enable().unwrap();
    (card, g)
}

fn cmd(card: &Card, a: usize) -> (f64, f64) {
    let s = card.axis(a).unwrap().status().unwrap().raw;
    (s.cmd_pos, s.cmd_vel)
}

/// Kim Fig 7: 81,920 pulses on X with linear and with exponential acc/dec. The commanded
/// position ends exactly on the goal; the velocity ramps are the filters' step responses.
#[test]
fn kim_fig7_x_move_through_linear_and_exponential_acc_dec() {
    let mut emu = EmuOptions::new(2, 1000);
    emu.motors[0].counts_per_rev = 4096; // Kim's encoder: 4096 pulses/rev
    let (feed, tau) = (40_960.0, 0.1); // 10 rev/s, 100 ms
    for kind in [FilterKind::Linear, FilterKind::Exponential] {
        let (card, g) = filtered_group(emu, kind, tau, Interpolator::Exact);
        let sim = card.sim().unwrap();
        let m = g
            .move_linear(
                &[81_920.0, 0.0],
                &PathLimits::new(feed, 1e9, 1e12),
                MoveOptions::default(),
            )
            .unwrap();
        let mut vel = Vec::new();
        while g.status().unwrap().0 == GroupState::Moving {
            sim.step(1);
            vel.push(cmd(&card, 0).1);
        }
        m.wait(T).unwrap();
        assert_eq!(cmd(&card, 0).0, 81_920.0, "{kind:?}: commanded end");
        let act = card.axis(0).unwrap().status().unwrap().actual_position;
        assert!((act - 81_920.0).abs() <= 1.0, "{kind:?}: actual {act}");
        match kind {
            // Kim eq 1: the velocity ramps linearly over m = τ/T = 100 ticks.
            FilterKind::Linear => {
                for (k, v) in vel.iter().take(100).enumerate() {
                    assert!(
                        (v - feed * (k + 1) as f64 / 100.0).abs() < 1e-6,
                        "tick {k}: {v}"
                    );
                }
                assert!((vel[150] - feed).abs() < 1e-6);
            }
            // Kim eq 7–9: v(k) = V (1 − a^(k+1)), a = τ/(τ+T).
            _ => {
                let a = exponential_pole(tau, 1e-3);
                for (k, v) in vel.iter().take(300).enumerate() {
                    assert!(
                        (v - feed * (1.0 - a.powi(k as i32 + 1))).abs() < 1e-6 * feed,
                        "tick {k}: {v}"
                    );
                }
            }
        }
    }
}

/// Steady-state radius of the commanded circle over the third lap, and the closed form.
fn measured_radial_error(
    kind: FilterKind,
    r: f64,
    omega: f64,
    rate: u32,
    tau: f64,
    interp: Interpolator,
) -> (f64, f64) {
    let ts = 1.0 / rate as f64;
    let (card, g) = filtered_group(EmuOptions::new(2, rate), kind, tau, interp);
    let sim = card.sim().unwrap();
    let v = omega * r;
    // Start on the circle around (0, 0): move to (r, 0) first, then three full laps.
    g.move_linear(
        &[r, 0.0],
        &PathLimits::new(v, 1e9, 1e12),
        MoveOptions::default(),
    )
    .unwrap()
    .wait(T)
    .unwrap();
    let lap = ArcSpec::Centre {
        end: [r, 0.0],
        centre: [0.0, 0.0],
        ccw: true,
    };
    let laps: Vec<_> = (0..3)
        .map(|_| {
            g.move_circular(
                &lap,
                Plane::XY,
                &[],
                &PathLimits::new(v, 1e9, 1e12),
                MoveOptions::buffered(),
            )
            .unwrap()
        })
        .collect();
    laps[1].wait(T).unwrap();
    // Lap 3: skip its first quarter (the lap joint disturbs the filter for m ticks / a few τ).
    let lap_ticks = (std::f64::consts::TAU / (omega * ts)) as u64;
    sim.step(lap_ticks / 4);
    let (mut sum, mut n) = (0.0, 0.0);
    for _ in 0..lap_ticks / 2 {
        sim.step(1);
        let (x, y) = (cmd(&card, 0).0, cmd(&card, 1).0);
        sum += x.hypot(y);
        n += 1.0;
    }
    let formula = match kind {
        FilterKind::Linear => linear_filter_radial_error(r, v, ts, (tau / ts).round() as usize),
        _ => exponential_filter_radial_error(r, v, ts, exponential_pole(tau, ts)),
    };
    (r - sum / n, formula)
}

/// Kim §4: circles through the linear filter match the corrected eq 28, through the
/// exponential filter eq 32, within 1% of ΔR, over 24 combinations each of radius, feed,
/// sample time and time constant, with the exact and the reference-word interpolators.
#[test]
fn kim_sec4_radial_error_matches_eq28_and_eq32() {
    let mut cases = 0;
    let mut worst: f64 = 0.0;
    for kind in [FilterKind::Linear, FilterKind::Exponential] {
        for (i, &(r, omega, rate, tau)) in [
            (5_000.0, 4.0, 1000, 0.030),
            (5_000.0, 8.0, 2000, 0.020),
            (20_000.0, 3.0, 1000, 0.050),
            (20_000.0, 6.0, 5000, 0.015),
            (50_000.0, 2.0, 2000, 0.060),
            (50_000.0, 5.0, 1000, 0.010),
            (8_000.0, 10.0, 5000, 0.012),
            (8_000.0, 2.5, 10_000, 0.040),
            (12_000.0, 7.0, 2000, 0.025),
            (30_000.0, 4.0, 4000, 0.035),
            (3_000.0, 12.0, 1000, 0.008),
            (100_000.0, 1.5, 1000, 0.080),
        ]
        .iter()
        .enumerate()
        {
            for interp in [Interpolator::Exact, Interpolator::ReferenceWord] {
                let (measured, formula) = measured_radial_error(kind, r, omega, rate, tau, interp);
                let rel = (measured - formula).abs() / formula;
                worst = worst.max(rel);
                assert!(
                    formula > 1e-4 * r / 10.0,
                    "case {i}: ΔR {formula} too small to measure"
                );
                assert!(rel <= 0.01, "{kind:?} {interp:?} case {i} (R {r}, Ω {omega}, {rate} Hz, τ {tau}): measured ΔR {measured}, formula {formula}");
                cases += 1;
            }
        }
    }
    assert!(cases >= 40);
    println!("{cases} cases, worst |ΔR measured − formula| / ΔR = {worst:.2e}");
}

/// The programmed corner: along X to (L, 0), then along Y to (L, L).
fn corner_distance(p: (f64, f64), l: f64) -> f64 {
    let d1 = if p.0 <= l {
        p.1.abs()
    } else {
        (p.0 - l).hypot(p.1)
    };
    let d2 = if p.1 >= 0.0 {
        (p.0 - l).abs()
    } else {
        (p.0 - l).hypot(p.1)
    };
    d1.min(d2)
}

/// Shin's corner test: a 90° corner at 1 m/min, time constants 15 and 30 ms, linear and
/// exponential filters, on the machine-table plant (a coupling resonance at 33 Hz, the
/// encoder on the motor). Returns (command rounding, tracking error of the table, total) in
/// µm (1 count = 1 µm).
pub fn shin_corner(kind: FilterKind, tau: f64) -> (f64, f64, f64) {
    let mut emu = EmuOptions::new(2, 10_000);
    emu.motors[0] = MotorParams::machine_table(33.0);
    emu.motors[1] = MotorParams::machine_table(33.0);
    let (card, g) = filtered_group(emu, kind, tau, Interpolator::Exact);
    let sim = card.sim().unwrap();
    let (l, feed) = (20_000.0, 1_000_000.0 / 60.0);
    let o = MoveOptions {
        buffered: true,
        feed_type: FeedType::Cutting,
        ..Default::default()
    };
    g.move_linear(&[l, 0.0], &PathLimits::new(feed, 1e9, 1e12), o)
        .unwrap();
    let last = g
        .move_linear(&[l, l], &PathLimits::new(feed, 1e9, 1e12), o)
        .unwrap();
    let (mut e_cmd, mut e_track, mut e_total) = (0.0f64, 0.0f64, 0.0f64);
    while g.status().unwrap().0 == GroupState::Moving {
        sim.step(1);
        let c = (cmd(&card, 0).0, cmd(&card, 1).0);
        let load = sim.with_emulator(|e| {
            (
                e.motor(0).unwrap().load_position_counts(),
                e.motor(1).unwrap().load_position_counts(),
            )
        });
        // Around the corner only (the straight parts have no contour error to speak of).
        if (c.0 - l).abs() < 3_000.0 && c.1 < 3_000.0 {
            e_cmd = e_cmd.max(corner_distance(c, l));
            e_track = e_track.max((load.0 - c.0).hypot(load.1 - c.1));
            e_total = e_total.max(corner_distance(load, l));
        }
    }
    last.wait(T).unwrap();
    (e_cmd, e_track, e_total)
}

/// The trade-off of Shin's corner test appears: the longer time constant rounds the commanded
/// corner more but excites the coupling less, so the table tracks its command better.
#[test]
fn shin_corner_time_constant_trade_off() {
    for kind in [FilterKind::Linear, FilterKind::Exponential] {
        let short = shin_corner(kind, 0.015);
        let long = shin_corner(kind, 0.030);
        println!(
            "{kind:?}: 15 ms {short:?}, 30 ms {long:?} (command rounding, tracking, total) µm"
        );
        assert!(
            long.0 > short.0,
            "{kind:?}: a longer filter should round the command more"
        );
        assert!(
            long.1 < short.1,
            "{kind:?}: a longer filter should excite the resonance less"
        );
    }
}
