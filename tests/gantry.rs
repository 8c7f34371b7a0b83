//! Layout 1.10: gantry axes on the stepped card. A bridge of two axes (master 0, slave 1),
//! each its own default servo motor, the slave's load 30 % heavier (`MotorParams::inertia`).
//! Issue 35 part 1: with each side tuned for its load (both plants measured by a frequency
//! sweep, which finds the load ratio 1.297 for the plant's 1.3; the slave's FFPIV placed at the
//! master's bandwidth for its own acceleration per volt) the skew on a full-speed S-curve out
//! and back is within a count on every tick: the encoders' difference at most 1 (the card's
//! `max_skew`, the scope's `Signal::GantrySkew` and the plant's encoders agree), the shafts'
//! true difference at most 0.563 count (0.969 and 0.986 with and without the yaw loop from
//! shafts racked 0.95 count apart within their counts). On the default tuning the yaw loop
//! holds it to 2 counts (shafts 2.03), without it 23. A jammed side stops both within the
//! stop bound, homing squares the bridge to its offset from any start (the encoders' difference
//! the same from six starts), a group drives the slave through its master, and every refusal.
//! The figures are printed: `cargo test --release --test gantry -- --nocapture`.
mod common;

use common::stepped_card_with;
use firmware_proto::FfpivGains;
use motioncard_sdk::{
    AxisState, Card, EmuOptions, ErrorKind, EventKind, FreqSweep, GantryConfig, GantryPhase,
    GroupSettings, HomeSwitch, HomingSettings, Master, MoveLimits, PathSettings, ScopeMode,
    ScopeSettings, Signal, Source, StopReason, Switches, SyncLimits,
};
use std::f64::consts::TAU;
use std::time::Duration;

const RATE: u32 = 10_000;
const LONG: Duration = Duration::from_secs(30);
/// The slave's load, relative to the master's.
const HEAVIER: f64 = 1.3;

/// Three axes of the default servo, axis 1's inertia 30 % more.
fn card() -> Card {
    let mut emu = EmuOptions::new(3, RATE);
    emu.motors[1].inertia *= HEAVIER;
    stepped_card_with(emu)
}

fn enable(card: &Card, axes: &[usize]) {
    for &a in axes {
        card.axis(a).unwrap().enable().unwrap();
    }
}

fn cfg(kp: f64, ki: f64) -> GantryConfig {
    GantryConfig {
        kp,
        ki,
        skew_limit: 200.0,
        offsets: vec![0.0],
    }
}

/// The axes' full speed: the safety layer's default velocity limit (10⁶ counts/s, 100 rev/s),
/// an acceleration the heavier side still has a third of its current in reserve for.
fn full_speed() -> MoveLimits {
    MoveLimits::new(1e6, 5e6, 5e8)
}

/// The drive's acceleration per volt (counts/s² per V) of axis `a` as the tuning tools
/// measure it: the plant `P = X/U` of a frequency sweep from 20 to 200 Hz, where a rigid
/// inertia's `|P|·ω²` is its acceleration per volt (the viscous corner is at 0.03 Hz), the
/// median over the points.
fn measured_accel_per_volt(card: &Card, a: usize) -> f64 {
    let sweep = FreqSweep {
        from_hz: 20.0,
        to_hz: 200.0,
        points: 5,
        ..FreqSweep::default()
    };
    let r = card
        .axis(a)
        .unwrap()
        .frequency_response(&sweep, LONG)
        .unwrap();
    assert!(r.complete);
    let mut k: Vec<f64> = r
        .plant()
        .iter()
        .map(|b| b.value.abs() * (TAU * b.hz).powi(2))
        .collect();
    k.sort_by(f64::total_cmp);
    k[k.len() / 2]
}

/// Commission each side for its own load, as a machine builder tunes each drive of a gantry:
/// both axes' plants measured, the slave's FFPIV placed at the master's bandwidth for its own
/// acceleration per volt (its `kv` and `kaff` times the load ratio). Returns the ratio found.
fn tune_each_side_for_its_load(card: &Card) -> f64 {
    let ratio = measured_accel_per_volt(card, 0) / measured_accel_per_volt(card, 1);
    let master = card.axis(0).unwrap().settings().unwrap();
    let slave = card.axis(1).unwrap();
    let mut cfg = slave.settings().unwrap();
    cfg.ffpiv = FfpivGains {
        kv: master.ffpiv.kv * ratio,
        kaff: master.ffpiv.kaff * ratio,
        ..master.ffpiv
    };
    slave.configure(&cfg).unwrap();
    // The sweep's end leaves both axes settling: at rest before the gantry forms.
    card.sim().unwrap().step(5000);
    ratio
}

/// The skew over the S-curve, every tick, three ways (counts, less the slave's offset).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Skews {
    /// The largest the card saw (`GantrySide::max_skew`: its encoders' difference).
    card: f64,
    /// The largest of the encoders' difference, read from the plant after every tick.
    encoders: i64,
    /// The largest difference of the two shafts (the bridge's true yaw), from the plant.
    shafts: f64,
    /// The largest sample of the scope's `Signal::GantrySkew`.
    scope: f64,
}

/// The skews over an S-curve out and back at full speed; `tuned`: each side tuned for its
/// load first (the load ratio found is returned with them); `racked`: each shaft put this far
/// into its count (master, slave) before the first move, the encoders unchanged.
fn skews_over_s_curve(
    tuned: bool,
    kp: f64,
    ki: f64,
    racked: Option<(f64, f64)>,
) -> (Skews, Option<f64>) {
    let card = card();
    enable(&card, &[0, 1]);
    let ratio = tuned.then(|| tune_each_side_for_its_load(&card));
    let g = card.gantry(0, &[1], &cfg(kp, ki)).unwrap();
    assert_eq!(
        card.axis(1).unwrap().status().unwrap().state,
        AxisState::SynchronizedMotion
    );
    let hold = g.status().unwrap().slaves[0].hold;
    if let Some((a, b)) = racked {
        // Each shaft placed within its count (the encoders read what they read before).
        card.sim().unwrap().with_emulator(|e| {
            for (k, within) in [(0, a), (1, b)] {
                let m = e.motor_mut(k).unwrap();
                let c = m.params.counts_per_rad();
                m.theta = (m.encoder() as f64 + within) / c;
            }
        });
    }
    let m = g.master().unwrap();
    let sim = card.sim().unwrap();
    let scope = card.scope();
    scope
        .configure(&ScopeSettings {
            mode: ScopeMode::Continuous,
            ..ScopeSettings::new(
                &[
                    Source::axis(Signal::GantrySkew, 1),
                    Source::axis(Signal::ActPos, 0),
                    Source::axis(Signal::ActPos, 1),
                ],
                1,
            )
        })
        .unwrap();
    scope.arm().unwrap();
    let mut samples = Vec::new();
    let (mut encoders, mut shafts) = (0i64, 0.0f64);
    for target in [2e6, 0.0] {
        let motion = m.move_absolute(target, &full_speed()).unwrap();
        let mut done = false;
        let mut ticks = 0u64;
        // To MotionDone (in position for the settle time), then 2,000 ticks at rest.
        while !done || ticks < 2000 {
            sim.step(1);
            ticks += 1;
            let (enc, shaft) = sim.with_emulator(|e| {
                let (a, b) = (e.motor(0).unwrap(), e.motor(1).unwrap());
                (
                    b.encoder() - a.encoder(),
                    b.position_counts() - a.position_counts(),
                )
            });
            encoders = encoders.max((enc as f64 - hold).abs() as i64);
            shafts = shafts.max((shaft - hold).abs());
            while let Some(e) = card.next_event(Duration::ZERO).unwrap() {
                if e.kind == EventKind::MotionDone && e.seq == motion.seq() && !done {
                    done = true;
                    ticks = 0;
                }
            }
            if ticks.is_multiple_of(1000) {
                scope.read(&mut samples).unwrap();
            }
        }
    }
    scope.read(&mut samples).unwrap();
    assert_eq!(scope.status().unwrap().lost, 0);
    assert!(samples.len() > 40_000, "{}", samples.len());
    // The scope's skew is the card's actual positions' difference less the offset.
    for s in &samples {
        assert_eq!(
            s.value[0],
            s.value[2] - s.value[1] - hold,
            "tick {}",
            s.tick
        );
    }
    let scope_max = samples.iter().map(|s| s.value[0].abs()).fold(0.0, f64::max);
    let st = g.status().unwrap();
    assert_eq!(st.phase, GantryPhase::Coupled);
    // The slave followed: it stands where the master does.
    let (a0, a1) = (
        m.status().unwrap().actual_position,
        card.axis(1).unwrap().status().unwrap().actual_position,
    );
    assert!((a1 - a0 - st.slaves[0].hold).abs() <= 1.0, "{a0} {a1}");
    let skews = Skews {
        card: st.slaves[0].max_skew,
        encoders,
        shafts,
        scope: scope_max,
    };
    (skews, ratio)
}

/// Issue 35 part 1: the skew within ±1 count on the S-curve at full speed, the slave's load
/// 30 % heavier, with each side tuned for its load (its plant measured, its FFPIV placed for
/// it) and the yaw loop on: the encoders' difference never beyond a count on any tick, and the
/// shafts themselves (the bridge's true yaw) within half a count. The members read their
/// encoders' counts at the middle while moving (`ffpiv.rs`): without it the shafts drift
/// apart within their counts and the encoders' difference reads 2 (see ARCHITECTURE.md).
/// Untuned, the slave's missing 30 % of acceleration feed-forward is carried by the yaw loop
/// on a skew it can only see whole counts of: 2 counts; without the yaw loop, more than 10.
#[test]
fn skew_is_held_within_one_count_on_a_full_speed_s_curve_with_each_side_tuned_for_its_load() {
    let (tuned, ratio) = skews_over_s_curve(true, 1e6, 0.0, None);
    let ratio = ratio.unwrap();
    let (racked, _) = skews_over_s_curve(true, 1e6, 0.0, Some((0.97, 0.02)));
    let (racked_no_yaw, _) = skews_over_s_curve(true, 0.0, 0.0, Some((0.97, 0.02)));
    let (untuned, _) = skews_over_s_curve(false, 1e6, 0.0, None);
    let (without, _) = skews_over_s_curve(false, 0.0, 0.0, None);
    println!("gantry load ratio from the sides' plants (frequency response): {ratio:.4} (the plant's: {HEAVIER})");
    for (what, s) in [
        ("each side tuned for its load, yaw loop kp 10⁶/s²", tuned),
        (
            "each side tuned, kp 10⁶/s², the shafts racked 0.95 count within their counts at the start",
            racked,
        ),
        ("each side tuned, no yaw loop, racked alike", racked_no_yaw),
        ("both sides on the default tuning, yaw loop kp 10⁶/s²", untuned),
        ("both on the default tuning, no yaw loop", without),
    ] {
        println!(
            "gantry skew, 2·10⁶ counts out and back at 10⁶ counts/s, 5·10⁶ counts/s², slave load +30 %, {what}: encoders' difference at most {} counts (card {}, scope {}), shafts' difference at most {:.3} counts",
            s.encoders, s.card, s.scope, s.shafts
        );
        // The card's figure, the scope's and the plant's encoders agree.
        assert_eq!(
            (s.card, s.scope),
            (s.encoders as f64, s.encoders as f64),
            "{s:?}"
        );
        // Two encoders differ by at most the whole counts between their shafts, plus one.
        assert!((s.encoders as f64) < s.shafts + 1.0, "{s:?}");
    }
    assert!((ratio / HEAVIER - 1.0).abs() < 0.01, "load ratio {ratio}");
    assert!(tuned.encoders <= 1, "{tuned:?}");
    assert!(tuned.shafts < 0.6, "{tuned:?}");
    // Racked within the count (which no encoder sees), the first move starts with the skew
    // the rack is, until the counts' middles bring the shafts to the same edge.
    for r in [racked, racked_no_yaw] {
        assert!(r.shafts < 1.0 && r.encoders <= 1, "{r:?}");
    }
    assert!(
        untuned.encoders >= 2,
        "tuning each side is what holds it: {untuned:?}"
    );
    assert!(
        without.encoders > 10,
        "the yaw loop is what holds it: {without:?}"
    );
}

#[test]
fn a_jammed_side_stops_both_within_the_stop_bound() {
    let card = card();
    enable(&card, &[0, 1]);
    let g = card.gantry(0, &[1], &cfg(1e6, 0.0)).unwrap();
    let m = g.master().unwrap();
    let sim = card.sim().unwrap();
    let _motion = m.move_absolute(5e6, &full_speed()).unwrap();
    sim.step(3000); // at full speed
    while card.next_event(Duration::ZERO).unwrap().is_some() {}
    sim.with_emulator(|e| e.faults().stall(1, true));
    let max_stop = card.safety_settings().unwrap().max_stop_time_us as f64 * 1e-6;
    // The stop bound from the limits: the master's stop ramp from full speed, an S-curve
    // (v/a + a/j), plus two ticks (sensing and the stop's first tick).
    let ramp = card.axis(0).unwrap().safety_settings().unwrap();
    let v = full_speed().velocity;
    let bound =
        v / ramp.stop_deceleration + ramp.stop_deceleration / ramp.stop_jerk + 2.0 / RATE as f64;
    assert!(bound < max_stop);
    let t0 = sim.time();
    let mut fault = None;
    let mut at_rest = [None, None];
    let mut steps = 0;
    while at_rest.iter().any(Option::is_none) && steps < 20_000 {
        sim.step(1);
        steps += 1;
        while let Some(e) = card.next_event(Duration::ZERO).unwrap() {
            match e.kind {
                EventKind::GantryFault => fault = Some((e, sim.time() - t0)),
                EventKind::AtRest if (e.axis as usize) < 2 => {
                    at_rest[e.axis as usize] = Some(sim.time() - t0)
                }
                _ => {}
            }
        }
    }
    let (fault, tripped) = fault.expect("a gantry fault event");
    assert_eq!(fault.axis, 0, "it names the gantry");
    assert_eq!(fault.code, StopReason::GantrySkew as i32);
    assert!(
        fault.value.abs() > 200.0,
        "the skew beyond the limit: {}",
        fault.value
    );
    for (a, rest) in at_rest.iter().enumerate() {
        let st = card.axis(a).unwrap().status().unwrap();
        assert_eq!(st.state, AxisState::ErrorStop, "axis {a}");
        // The jammed side cannot follow the stop ramp either: its following error trips it
        // harder (category 0) on the way.
        let reason = card.axis(a).unwrap().stop_reason().unwrap();
        let expected: &[StopReason] = if a == 0 {
            &[StopReason::GantrySkew]
        } else {
            &[StopReason::GantrySkew, StopReason::FollowingError]
        };
        assert!(expected.contains(&reason), "axis {a}: {reason:?}");
        // From the trip (the skew beyond its limit), within the ramp's bound.
        let t = rest.expect("at rest") - tripped;
        assert!(
            t <= bound,
            "axis {a} at rest {t} s after the trip (bound {bound} s)"
        );
    }
    println!(
        "gantry skew fault (slave jammed at 10⁶ counts/s, tripped {:.4} s later): both sides at rest {:.4} s and {:.4} s after the trip, stop bound {bound:.4} s (the card's maximum stop time {max_stop} s)",
        tripped,
        at_rest[0].unwrap() - tripped,
        at_rest[1].unwrap() - tripped
    );
    // MC_Reset of the master resets both; the gantry couples again where they stand.
    sim.with_emulator(|e| e.faults().stall(1, false));
    m.reset().unwrap();
    sim.step(2);
    assert_eq!(m.status().unwrap().state, AxisState::Disabled);
    m.enable().unwrap();
    sim.step(2);
    assert_eq!(
        card.axis(1).unwrap().status().unwrap().state,
        AxisState::SynchronizedMotion
    );
    assert!(!g.status().unwrap().squared);
}

#[test]
fn a_slave_cannot_be_used_by_itself() {
    let card = card();
    enable(&card, &[0, 1]);
    let g = card.gantry(0, &[1], &cfg(1e6, 0.0)).unwrap();
    let slave = card.axis(1).unwrap();
    let lim = MoveLimits::new(1e5, 1e6, 1e8);
    let kind = |r: motioncard_sdk::Result<_>| r.err().map(|e: motioncard_sdk::Error| e.kind());
    assert_eq!(
        kind(slave.move_absolute(10.0, &lim).map(|_| ())),
        Some(ErrorKind::GantrySlave)
    );
    assert_eq!(kind(slave.disable()), Some(ErrorKind::GantrySlave));
    assert_eq!(
        kind(slave.halt(1e6, 1e8).map(|_| ())),
        Some(ErrorKind::GantrySlave)
    );
    let sync = SyncLimits {
        velocity: 1e5,
        acceleration: 1e6,
        jerk: 1e8,
    };
    assert_eq!(
        kind(slave.gear_in(Master::Commanded(2), 1, 1, &sync).map(|_| ())),
        Some(ErrorKind::GantrySlave)
    );
    let group = card.group(0).unwrap();
    assert_eq!(
        kind(group.configure(&GroupSettings::new(&[1, 2]))),
        Some(ErrorKind::GantrySlave)
    );
    // The master homes only as the gantry.
    assert_eq!(
        kind(card.axis(0).unwrap().home(0.0).map(|_| ())),
        Some(ErrorKind::GantryState)
    );
    // The master powers both off and on.
    card.axis(0).unwrap().disable().unwrap();
    assert_eq!(slave.status().unwrap().state, AxisState::Disabled);
    card.axis(0).unwrap().enable().unwrap();
    card.sim().unwrap().step(1);
    assert_eq!(slave.status().unwrap().state, AxisState::SynchronizedMotion);
    // Dissolved, the slave is its own axis again, where it stood.
    g.dissolve().unwrap();
    assert_eq!(slave.status().unwrap().state, AxisState::Standstill);
    slave.move_absolute(10.0, &lim).unwrap().wait(LONG).unwrap();
}

#[test]
fn formations_are_refused_for_their_own_reasons() {
    let card = card();
    for a in 0..3 {
        card.axis(a).unwrap().enable().unwrap();
    }
    let c = cfg(1e6, 0.0);
    let kind = |r: motioncard_sdk::Result<motioncard_sdk::Gantry>| r.err().unwrap().kind();
    assert_eq!(kind(card.gantry(0, &[0], &c)), ErrorKind::GantryAxes);
    assert_eq!(kind(card.gantry(0, &[1, 1], &c)), ErrorKind::GantryAxes);
    assert_eq!(kind(card.gantry(0, &[], &c)), ErrorKind::GantryAxes);
    assert_eq!(kind(card.gantry(0, &[5], &c)), ErrorKind::BadAxis);
    for bad in [
        GantryConfig {
            kp: 2e9,
            ..c.clone()
        },
        GantryConfig {
            ki: -1.0,
            ..c.clone()
        },
        GantryConfig {
            skew_limit: 0.0,
            ..c.clone()
        },
        GantryConfig {
            offsets: vec![0.0, 1.0],
            ..c.clone()
        },
    ] {
        assert_eq!(
            kind(card.gantry(0, &[1], &bad)),
            ErrorKind::GantryGains,
            "{bad:?}"
        );
    }
    assert_eq!(
        kind(card.gantry(
            0,
            &[1],
            &GantryConfig {
                kp: f64::NAN,
                ..c.clone()
            }
        )),
        ErrorKind::NotFinite
    );
    // The card's own checks, past the SDK's.
    let raw = |args: &[f64]| {
        let mut cmd =
            motioncard_sdk::proto::Command::new(motioncard_sdk::proto::Opcode::GantryForm, 0);
        cmd.args[..args.len()].copy_from_slice(args);
        card.execute_raw(cmd).err().map(|e| e.kind())
    };
    assert_eq!(
        raw(&[0.0, 1.0, 1e6, 0.0, 10.0, 0.0, 0.0]),
        Some(ErrorKind::GantryAxes)
    );
    assert_eq!(
        raw(&[0.0, 1.0, -1.0, 0.0, 10.0, 1.0, 0.0]),
        Some(ErrorKind::GantryGains)
    );
    assert_eq!(
        raw(&[0.0, 1.0, 1e6, 0.0, -1.0, 1.0, 0.0]),
        Some(ErrorKind::GantryGains)
    );
    assert_eq!(
        raw(&[0.0, 5.0, 1e6, 0.0, 10.0, 1.0, 0.0]),
        Some(ErrorKind::GantryAxes)
    );
    // A slave in use: geared, or in another gantry.
    let sync = SyncLimits {
        velocity: 1e5,
        acceleration: 1e6,
        jerk: 1e8,
    };
    card.axis(2)
        .unwrap()
        .gear_in(Master::Commanded(0), 1, 1, &sync)
        .unwrap();
    assert_eq!(kind(card.gantry(0, &[2], &c)), ErrorKind::GantryInUse);
    card.axis(2)
        .unwrap()
        .halt(1e6, 1e8)
        .unwrap()
        .wait(LONG)
        .unwrap();
    let g = card.gantry(0, &[1], &c).unwrap();
    assert_eq!(g.index(), 0);
    assert_eq!(
        kind(card.gantry(1, &[2], &c)),
        ErrorKind::GantryInUse,
        "the master is in gantry 0"
    );
    assert_eq!(
        kind(card.gantry(2, &[1], &c)),
        ErrorKind::GantryInUse,
        "axis 1 is in gantry 0"
    );
    assert_eq!(
        kind(card.gantry_at(0, 2, &[1], &c)),
        ErrorKind::GantryState,
        "gantry 0 is formed"
    );
    // A slave in a group as its own axis.
    g.dissolve().unwrap();
    card.group(0)
        .unwrap()
        .configure(&GroupSettings::new(&[0, 2]))
        .unwrap();
    assert_eq!(kind(card.gantry(1, &[2], &c)), ErrorKind::GantryInUse);
    // The master may be in a group.
    card.gantry(0, &[1], &c).unwrap();
}

#[test]
fn a_group_with_the_master_drives_the_slave() {
    let card = card();
    enable(&card, &[0, 1, 2]);
    let g = card.gantry(0, &[1], &cfg(1e6, 0.0)).unwrap();
    let group = card.group(0).unwrap();
    group.configure(&GroupSettings::new(&[0, 2])).unwrap();
    group.enable().unwrap();
    group
        .configure_path(&PathSettings::uniform(2, 2e5, 2e6, 2e8))
        .unwrap();
    let lim = motioncard_sdk::PathLimits::new(2e5, 2e6, 2e8);
    group
        .move_linear(&[40_000.0, 30_000.0], &lim, Default::default())
        .unwrap()
        .wait(LONG)
        .unwrap();
    let s1 = card.axis(1).unwrap().status().unwrap();
    let st = g.status().unwrap();
    assert!((s1.command_position - 40_000.0 - st.slaves[0].hold).abs() < 1.0);
    assert!(
        (s1.actual_position - 40_000.0).abs() <= 1.0,
        "{}",
        s1.actual_position
    );
    assert!(st.slaves[0].max_skew <= 1.0, "{}", st.slaves[0].max_skew);
}

/// Each side's home switch: active above its edge, the slave's 137.5 counts further out
/// than the master's (the bridge's two switches are not square).
const EDGE: [f64; 2] = [-2_000.5, -1_863.0];
const OFFSET: f64 = 25.0;

#[test]
fn homing_squares_the_bridge_to_its_offset_from_any_start() {
    let mut squared = Vec::new();
    for (k, start) in [
        (0.0, 0.0),
        (3_000.0, 3_040.0),
        (-500.0, -620.0),
        (8_000.0, 7_950.0),
        (2_000.0, 2_150.0),
        (-3_000.0, -3_100.0),
    ]
    .into_iter()
    .enumerate()
    {
        let card = card();
        let sim = card.sim().unwrap();
        for (a, &edge) in EDGE.iter().enumerate() {
            sim.with_emulator(|e| {
                e.faults().set_switches(
                    a,
                    Switches::limits(-1e7, 1e7).with_home(HomeSwitch::Above(edge)),
                )
            });
            let ax = card.axis(a).unwrap();
            ax.configure_homing(&HomingSettings {
                method: 19,
                ..HomingSettings::default()
            })
            .unwrap();
            ax.enable().unwrap();
        }
        // The bridge racked by the start's difference: each side where the start says.
        let lim = MoveLimits::new(1e5, 1e6, 1e8);
        for (a, p) in [start.0, start.1].into_iter().enumerate() {
            card.axis(a)
                .unwrap()
                .move_absolute(p, &lim)
                .unwrap()
                .wait(LONG)
                .unwrap();
        }
        let g = card
            .gantry(
                0,
                &[1],
                &GantryConfig {
                    offsets: vec![OFFSET],
                    ..cfg(1e6, 0.0)
                },
            )
            .unwrap();
        let skew = g.home().unwrap().wait(LONG).unwrap();
        sim.step(2000);
        let st = g.status().unwrap();
        assert!(st.squared && st.phase == GantryPhase::Coupled);
        assert_eq!(st.slaves[0].hold, OFFSET);
        // Square: the encoders' difference, the same from every start.
        let enc = |a: usize| card.axis(a).unwrap().status().unwrap().raw.encoder as f64;
        squared.push(enc(1) - enc(0));
        println!(
            "start {k} {start:?}: squared with skew {skew} counts, encoders apart by {}",
            enc(1) - enc(0)
        );
        assert!(skew.abs() <= 1.0);
    }
    let (lo, hi) = squared
        .iter()
        .fold((f64::MAX, f64::MIN), |(l, h), &x| (l.min(x), h.max(x)));
    println!(
        "gantry squaring at homing: encoder difference {lo}..{hi} over {} starts",
        squared.len()
    );
    // The switches are 137.5 counts apart, the offset 25: square is 162.5, each start within
    // a count of it and of each other.
    assert!(hi - lo <= 1.0, "{squared:?}");
    assert!(
        (lo - 162.5).abs() <= 1.0 && (hi - 162.5).abs() <= 1.0,
        "{squared:?}"
    );
}

#[test]
fn a_failed_side_ends_gantry_homing_naming_the_gantry_and_the_axis() {
    let card = card();
    let sim = card.sim().unwrap();
    for a in 0..2 {
        // The slave has no home switch: it runs to its maximum distance.
        let home = if a == 0 {
            HomeSwitch::Above(EDGE[0])
        } else {
            HomeSwitch::None
        };
        sim.with_emulator(|e| {
            e.faults()
                .set_switches(a, Switches::limits(-1e7, 1e7).with_home(home))
        });
        let ax = card.axis(a).unwrap();
        ax.configure_homing(&HomingSettings {
            method: 19,
            max_distance: 20_000.0,
            ..HomingSettings::default()
        })
        .unwrap();
        ax.enable().unwrap();
    }
    let g = card.gantry(0, &[1], &cfg(1e6, 0.0)).unwrap();
    let err = g.home().unwrap().wait(LONG).unwrap_err();
    assert_eq!(err.kind(), ErrorKind::HomingFailed);
    match err {
        motioncard_sdk::Error::GantryHomingFailed {
            gantry,
            axis,
            error,
        } => {
            assert_eq!((gantry, axis), (0, 1));
            assert_eq!(error, Some(motioncard_sdk::HomingError::DistanceExceeded));
        }
        e => panic!("{e}"),
    }
    sim.step(5000);
    let st = g.status().unwrap();
    assert_eq!(st.phase, GantryPhase::Coupled);
    assert!(!st.squared);
    assert_eq!(
        card.axis(1).unwrap().status().unwrap().state,
        AxisState::SynchronizedMotion
    );
}

#[test]
fn a_safety_stop_of_one_side_stops_the_other() {
    let card = card();
    enable(&card, &[0, 1]);
    let g = card.gantry(0, &[1], &cfg(1e6, 0.0)).unwrap();
    let m = g.master().unwrap();
    let sim = card.sim().unwrap();
    let _motion = m.move_absolute(5e6, &full_speed()).unwrap();
    sim.step(2000);
    while card.next_event(Duration::ZERO).unwrap().is_some() {}
    // The slave's amplifier alarms: it loses power at once, and the master stops with it.
    sim.with_emulator(|e| e.faults().set_alarm(1, true));
    sim.step(1);
    let mut fault = None;
    while let Some(e) = card.next_event(Duration::ZERO).unwrap() {
        if e.kind == EventKind::GantryFault {
            fault = Some(e);
        }
    }
    let fault = fault.expect("a gantry fault event");
    assert_eq!((fault.axis, fault.code), (0, StopReason::AmpAlarm as i32));
    assert_eq!(fault.value, 1.0, "the side that stopped first");
    assert_eq!(m.status().unwrap().state, AxisState::ErrorStop);
    assert_eq!(m.stop_reason().unwrap(), StopReason::Gantry);
    assert_eq!(
        card.axis(1).unwrap().stop_reason().unwrap(),
        StopReason::AmpAlarm
    );
}

/// `[gantry.N]` in the configuration file: a card's gantry saved, loaded into a fresh card
/// (formed last, read back equal, saved to the same bytes, a second load changes nothing), and
/// each bad key or value refused naming its key, nothing applied.
#[test]
fn a_gantry_goes_through_the_configuration_file() {
    let a = card();
    enable(&a, &[0, 1]);
    let c = GantryConfig {
        kp: 2e6,
        ki: 5e7,
        skew_limit: 150.5,
        offsets: vec![25.0],
    };
    a.gantry_at(1, 0, &[1], &c).unwrap();
    let text = a.save_config().unwrap();
    assert!(
        text.contains("[gantry.1]\nmaster = 0\nslaves = [1]\nkp = 2000000.0\nki = 50000000.0\nskew_limit = 150.5\noffsets = [25.0]\n"),
        "{text}"
    );
    let b = card();
    let report = b.load_config(&text, "a.toml").unwrap();
    assert_eq!(report.applied.last().map(String::as_str), Some("gantry.1"));
    let st = b.gantry_handle(1).unwrap().status().unwrap();
    assert_eq!((st.master, st.slaves[0].axis), (0, 1));
    assert_eq!(st.config(), c);
    assert_eq!(
        b.axis(1).unwrap().status().unwrap().state,
        AxisState::Disabled,
        "formed disabled, as the axes were"
    );
    assert_eq!(b.save_config().unwrap(), text);
    assert!(b.diff_config(&text, "a.toml").unwrap().is_empty());
    assert!(b.load_config(&text, "a.toml").unwrap().applied.is_empty());

    let key_of = |card: &Card, t: &str| match card.load_config(t, "bad.toml").unwrap_err() {
        motioncard_sdk::Error::ConfigFile { key, .. } => key,
        e => panic!("{e}"),
    };
    let fresh = card();
    let with = |from: &str, to: &str| {
        let t = text.replace(from, to);
        assert_ne!(t, text, "{from}");
        t
    };
    for (bad, key) in [
        (with("slaves = [1]", "slaves = [0]"), "gantry.1.slaves"),
        (with("slaves = [1]", "slaves = []"), "gantry.1.slaves"),
        (with("slaves = [1]", "slaves = [7]"), "gantry.1.slaves"),
        (
            with("master = 0\nslaves", "master = 9\nslaves"),
            "gantry.1.master",
        ),
        (with("kp = 2000000.0", "kp = -1.0"), "gantry.1.kp"),
        (with("ki = 50000000.0", "ki = nan"), "gantry.1.ki"),
        (
            with("skew_limit = 150.5", "skew_limit = 0.0"),
            "gantry.1.skew_limit",
        ),
        (
            with("offsets = [25.0]", "offsets = [25.0, 1.0]"),
            "gantry.1.offsets",
        ),
        (with("[gantry.1]", "[gantry.9]"), "gantry.9"),
        (
            with("offsets = [25.0]\n", "offsets = [25.0]\nyaw = 1\n"),
            "gantry.1.yaw",
        ),
    ] {
        assert_eq!(key_of(&fresh, &bad), key, "{bad}");
    }
    assert!(fresh.gantries().is_empty(), "nothing applied");
    // The axes must be at rest, all powered or all disabled.
    fresh.axis(0).unwrap().enable().unwrap();
    assert_eq!(key_of(&fresh, &text), "gantry.1.master");
    // A slave in a group is in use.
    fresh.axis(1).unwrap().enable().unwrap();
    fresh
        .group(0)
        .unwrap()
        .configure(&GroupSettings::new(&[1, 2]))
        .unwrap();
    assert_eq!(key_of(&fresh, &text), "gantry.1.slaves");
    assert!(fresh.gantries().is_empty());
    // A gantry the card holds with other settings is not re-formed by a file.
    let held = card();
    held.gantry_at(1, 0, &[1], &cfg(1e6, 0.0)).unwrap();
    assert_eq!(key_of(&held, &text), "gantry.1");
    assert_eq!(
        held.gantry_handle(1).unwrap().status().unwrap().config(),
        cfg(1e6, 0.0)
    );
}
