//! Layout 1.10: rotary (modulo) axes on the stepped card. The period is set, read back and
//! refused with its own error kind (and C code) when it is zero, out of range, or changed
//! while the axis moves; the status wraps into [0, period) in velocity mode with the encoder
//! running on; absolute moves go the shortest way or the way they name; a slave geared to a
//! modulo master does not jump when the master wraps, and a cam slave stays on its periodic
//! table across many of the master's turns both ways; soft limits do not hold on a modulo
//! axis; position compare is turn-aware (layout 1.13): every crossing of a place on the turn
//! fires once, within half a count, across the wrap, both ways, and what does not fit the turn
//! is refused.
mod common;

use common::stepped_card_with;
use motioncard_sdk::{
    AxisState, Card, Direction, EmuOptions, ErrorKind, IoState, Master, MoveDirection, MoveLimits,
    Status, SyncLimits, VelocityLimits,
};
use std::time::Duration;

const RATE: u32 = 10_000;
const LONG: Duration = Duration::from_secs(60);
/// 10,000 counts a turn (the default motor's), the positions in degrees.
const COUNTS_PER_TURN: f64 = 10_000.0;
const SCALE: f64 = COUNTS_PER_TURN / 360.0;

fn card(axes: usize) -> Card {
    let card = stepped_card_with(EmuOptions::new(axes, RATE));
    for a in 0..axes {
        card.axis(a).unwrap().enable().unwrap();
    }
    card
}

fn status(card: &Card, a: usize) -> Status {
    card.axis(a).unwrap().status().unwrap()
}

fn limits() -> MoveLimits {
    // Degrees: 720 °/s, 36,000 °/s², 3.6e6 °/s³.
    MoveLimits::new(720.0, 36_000.0, 3.6e6)
}

/// The period is read back as set (held to 1/65536 count), 0 through `set_modulo` is its own
/// refusal (`ModuloZero`, -116, nothing sent), a negative or non-finite period is refused
/// before it is sent and one the card finds out of range by the card (`ModuloRange`, -117), a
/// change while moving `ModuloBusy` (-118): none of them changes the period.
#[test]
fn the_period_is_set_read_back_and_refused_with_its_own_kinds() {
    let card = card(1);
    let axis = card.axis(0).unwrap();
    axis.set_scale(SCALE).unwrap();
    assert_eq!(axis.modulo().unwrap(), 0.0, "linear at boot");
    axis.set_modulo(360.0).unwrap();
    assert_eq!(axis.modulo().unwrap(), 360.0, "read back as written");
    assert_eq!(axis.settings().unwrap().modulo, COUNTS_PER_TURN);
    let refusals = [
        (0.0, ErrorKind::ModuloZero, -116),
        (-360.0, ErrorKind::ModuloRange, -117),
        (f64::NAN, ErrorKind::ModuloRange, -117),
        (f64::INFINITY, ErrorKind::ModuloRange, -117),
        (1e10, ErrorKind::ModuloRange, -117), // 2.8e11 counts: the card's refusal
        (1e-3, ErrorKind::ModuloRange, -117), // 0.028 counts
    ];
    for (p, kind, code) in refusals {
        let e = axis.set_modulo(p).unwrap_err();
        assert_eq!((e.kind(), e.kind().code()), (kind, code), "{p}: {e}");
        assert_eq!(axis.settings().unwrap().modulo, COUNTS_PER_TURN, "{p}");
    }
    axis.move_velocity(90.0, &VelocityLimits::new(3600.0, 3.6e5))
        .unwrap();
    card.sim().unwrap().step(10);
    for p in [720.0, 180.0] {
        let e = axis.set_modulo(p).unwrap_err();
        assert_eq!((e.kind(), e.kind().code()), (ErrorKind::ModuloBusy, -118));
    }
    let e = axis.clear_modulo().unwrap_err();
    assert_eq!(e.kind(), ErrorKind::ModuloBusy);
    assert_eq!(axis.settings().unwrap().modulo, COUNTS_PER_TURN);
    axis.halt(36_000.0, 3.6e6).unwrap().wait(LONG).unwrap();
    axis.clear_modulo().unwrap();
    assert_eq!(axis.modulo().unwrap(), 0.0);
}

/// Velocity mode on a modulo axis: 5 turns a second for 4 s of the stepped card (20 turns).
/// Every tick's status is in [0, 360), and the actual position is the encoder's count within
/// its turn, exactly (the encoder itself, the shaft's count, runs on past 200,000).
#[test]
fn velocity_mode_wraps_the_status_and_the_encoder_runs_on() {
    let card = card(1);
    let axis = card.axis(0).unwrap();
    axis.set_scale(SCALE).unwrap();
    axis.set_modulo(360.0).unwrap();
    axis.move_velocity(1800.0, &VelocityLimits::new(36_000.0, 3.6e6))
        .unwrap();
    let sim = card.sim().unwrap();
    let mut wraps = 0;
    let mut last = status(&card, 0).actual_position;
    for _ in 0..40_000 {
        sim.step(1);
        let s = status(&card, 0);
        for x in [s.command_position, s.actual_position] {
            assert!((0.0..360.0).contains(&x), "{x}");
        }
        let enc = s.raw.encoder;
        let in_turn = enc.rem_euclid(COUNTS_PER_TURN as i64) as f64 / SCALE;
        assert!(
            (s.actual_position - in_turn).abs() < 1e-9,
            "{} against the count {enc}",
            s.actual_position
        );
        if s.actual_position < last - 180.0 {
            wraps += 1;
        }
        last = s.actual_position;
    }
    let enc = status(&card, 0).raw.encoder;
    assert!(enc > 190_000, "the raw count runs on: {enc}");
    assert!(wraps >= 19, "{wraps} wraps");
}

/// From 10°: to 350° the shortest way goes back 20°; positively it goes forward 340°; to
/// 20° negatively it goes back 350°; `Current` after that goes back again. The encoder moves
/// by exactly those distances (within the in-position window), and each move ends done at its
/// target in [0, 360).
#[test]
fn absolute_moves_go_the_shortest_way_or_the_way_they_name() {
    let card = card(1);
    let axis = card.axis(0).unwrap();
    axis.set_scale(SCALE).unwrap();
    axis.set_modulo(360.0).unwrap();
    axis.move_absolute(10.0, &limits())
        .unwrap()
        .wait(LONG)
        .unwrap();
    let cases = [
        (350.0, MoveDirection::Shortest, -20.0),
        (340.0, MoveDirection::Positive, 350.0),
        (20.0, MoveDirection::Negative, -320.0),
        (10.0, MoveDirection::Current, -10.0),
        (20.0, MoveDirection::Current, -350.0),
        (200.0, MoveDirection::Shortest, 180.0), // half a turn: positive
    ];
    for (target, dir, way) in cases {
        let e0 = status(&card, 0).raw.encoder;
        let done = axis
            .move_absolute_dir(target, dir, &limits())
            .unwrap()
            .wait(LONG)
            .unwrap();
        let moved = (status(&card, 0).raw.encoder - e0) as f64 / SCALE;
        assert!(
            (moved - way).abs() < 2.0 / SCALE,
            "to {target} {dir:?}: moved {moved}°, not {way}°"
        );
        assert!((done - target).abs() < 2.0 / SCALE, "done at {done}");
        let s = status(&card, 0);
        assert_eq!(s.state, AxisState::Standstill);
        assert!((0.0..360.0).contains(&s.actual_position));
    }
    // A target outside the turn, and a direction on a linear axis: ModuloMove (-119).
    for t in [360.0, -1.0, 725.0] {
        let e = axis.move_absolute(t, &limits()).unwrap_err();
        assert_eq!((e.kind(), e.kind().code()), (ErrorKind::ModuloMove, -119));
    }
    axis.clear_modulo().unwrap();
    let e = axis
        .move_absolute_dir(10.0, MoveDirection::Positive, &limits())
        .unwrap_err();
    assert_eq!(e.kind(), ErrorKind::ModuloMove);
}

/// A slave geared 1:2 to a modulo master's command runs on smoothly while the master wraps
/// (each of its per-tick increments half the master's unwrapped one, to the master's
/// rounding to 1/65536 count): the master turns 4 times, the slave's position never jumps.
#[test]
fn a_slave_geared_to_a_modulo_master_does_not_jump_at_the_wrap() {
    let card = card(2);
    let (slave, master) = (card.axis(0).unwrap(), card.axis(1).unwrap());
    master.set_modulo(COUNTS_PER_TURN).unwrap();
    master
        .move_velocity(20_000.0, &VelocityLimits::new(2e5, 2e7))
        .unwrap()
        .wait_in_velocity(LONG)
        .unwrap();
    slave
        .gear_in(
            Master::Commanded(1),
            1,
            2,
            &SyncLimits::new(15_000.0, 1e5, 1e7),
        )
        .unwrap()
        .wait_in_sync(LONG)
        .unwrap();
    let sim = card.sim().unwrap();
    let mut prev = card.statuses(&[0, 1]).unwrap();
    let mut wraps = 0;
    for k in 0..20_000 {
        sim.step(1);
        let now = card.statuses(&[0, 1]).unwrap();
        let mut dm = now[1].command_position - prev[1].command_position;
        if dm < -COUNTS_PER_TURN / 2.0 {
            dm += COUNTS_PER_TURN;
            wraps += 1;
        }
        let ds = now[0].command_position - prev[0].command_position;
        assert!((dm - 2.0).abs() < 1e-6, "tick {k}: master moved {dm}");
        assert!(
            (ds - dm / 2.0).abs() <= 1.0 / 65_536.0,
            "tick {k}: slave {ds}, master {dm}"
        );
        prev = now;
    }
    assert_eq!(wraps, 4, "{wraps} wraps");
}

/// Soft limits do not hold on a modulo axis: a homed axis with soft limits at ±90° runs in
/// velocity mode through them (a turn and more) without a trip; made linear again, they hold.
#[test]
fn soft_limits_do_not_apply_to_a_modulo_axis() {
    let card = card(1);
    let axis = card.axis(0).unwrap();
    axis.set_scale(SCALE).unwrap();
    let mut s = axis.safety_settings().unwrap();
    s.soft_limits = Some((-90.0, 90.0));
    axis.configure_safety(&s).unwrap();
    axis.set_position(0.0, false).unwrap();
    axis.set_modulo(360.0).unwrap();
    axis.move_velocity(720.0, &VelocityLimits::new(36_000.0, 3.6e6))
        .unwrap();
    card.sim().unwrap().step(10_000);
    let st = status(&card, 0);
    assert_eq!(st.state, AxisState::ContinuousMotion);
    assert!(
        st.raw.encoder > 15_000,
        "a turn and more: {}",
        st.raw.encoder
    );
    axis.halt(36_000.0, 3.6e6).unwrap().wait(LONG).unwrap();
    // Linear again (the position where it was, within its turn): the limits hold.
    axis.clear_modulo().unwrap();
    let e = axis.move_absolute(200.0, &limits()).unwrap_err();
    assert_eq!(e.kind(), ErrorKind::SoftLimit, "{e}");
}

/// `modulo` in `[axis.N]` of the configuration file: a card's period saved (in the file's
/// user units), loaded into another card (applied, no difference left), `modulo = 0` makes the
/// axis linear again, and a negative period is refused naming the key, nothing applied.
#[test]
fn the_period_goes_through_the_configuration_file() {
    let a = card(1);
    let ax = a.axis(0).unwrap();
    ax.set_scale(SCALE).unwrap();
    ax.set_modulo(360.0).unwrap();
    let text = a.save_config().unwrap();
    let line = text
        .lines()
        .find(|l| l.starts_with("modulo"))
        .expect("modulo saved");
    assert_eq!(line, "modulo = 360.0");
    let b = card(1);
    let report = b.load_config(&text, "a.toml").unwrap();
    assert!(
        report.applied.iter().any(|k| k == "axis.0.modulo"),
        "{:?}",
        report.applied
    );
    assert!((b.axis(0).unwrap().modulo().unwrap() - 360.0).abs() < 1e-9);
    assert!(b.diff_config(&text, "a.toml").unwrap().is_empty());

    let linear = text.replace(line, "modulo = 0.0");
    b.load_config(&linear, "l.toml").unwrap();
    assert_eq!(b.axis(0).unwrap().modulo().unwrap(), 0.0);

    let c = card(1);
    let bad = text.replace(line, "modulo = -360.0");
    match c.load_config(&bad, "bad.toml").unwrap_err() {
        motioncard_sdk::Error::ConfigFile { key, .. } => assert_eq!(key, "axis.0.modulo"),
        e => panic!("{e}"),
    }
    assert_eq!(c.axis(0).unwrap().modulo().unwrap(), 0.0);
    assert_eq!(c.axis(0).unwrap().scale_factor(), 1.0, "nothing applied");
}

/// A probe on a modulo axis reports its captures wrapped: continuous capture on the index
/// pulse (every 10,000 counts of the plant) of an axis whose period is 25,000 counts, in
/// velocity mode over five turns: the k-th pulse at count 10,000·k is captured at
/// (10,000·k mod 25,000) + 0.5 (the cell's middle), across every wrap.
#[test]
fn probe_captures_on_a_modulo_axis_are_wrapped() {
    use motioncard_sdk::ProbeTrigger;
    let card = card(1);
    let ax = card.axis(0).unwrap();
    ax.set_modulo(25_000.0).unwrap();
    let p = ax.touch_probe(1);
    p.arm(&ProbeTrigger {
        continuous: true,
        ..ProbeTrigger::index()
    })
    .unwrap();
    ax.move_velocity(5e5, &VelocityLimits::new(5e6, 5e8))
        .unwrap();
    let sim = card.sim().unwrap();
    while status(&card, 0).raw.encoder < 125_000 {
        sim.step(10);
    }
    let st = p.status().unwrap();
    let n = st.captures as i64;
    assert_eq!(n, 12, "{st:?}");
    let want: Vec<f64> = (n - 7..=n)
        .map(|k| (10_000 * k).rem_euclid(25_000) as f64 + 0.5)
        .collect();
    assert_eq!(st.positions, want);
}

/// Issue 35 part 4: a cam slave following a modulo master stays exact across the master's
/// wrap: a periodic cubic table over one turn of the master, the master in velocity mode for
/// 25 turns forward then 25 back; every tick the slave's command is the table at the
/// master's position within the turn (to 1e-6 count), never a jump at the wrap.
#[test]
fn a_cam_slave_follows_a_modulo_master_exactly_across_many_turns() {
    use motioncard_sdk::CamSettings;
    let card = card(2);
    let (slave, master) = (card.axis(0).unwrap(), card.axis(1).unwrap());
    master.set_modulo(COUNTS_PER_TURN).unwrap();
    // a cam over one turn (its ends equal: periodic)
    let pts = [
        (0.0, 0.0),
        (2_500.0, 4_000.0),
        (5_000.0, 1_000.0),
        (7_500.0, -3_000.0),
        (10_000.0, 0.0),
    ];
    card.load_cam_table(0, &pts, true, true).unwrap();
    let table = card_emu::motion::cam::CamTable::new(&pts, true, true).unwrap();
    let vl = VelocityLimits::new(2e5, 2e7);
    let sim = card.sim().unwrap();
    slave
        .cam_in(
            Master::Commanded(1),
            &CamSettings::new(0),
            &SyncLimits::new(1e6, 1e8, 1e10),
        )
        .unwrap()
        .wait_in_sync(LONG)
        .unwrap();
    for dir in [1.0, -1.0] {
        // 50,000 counts/s: a turn every 2000 ticks
        master
            .move_velocity(dir * 50_000.0, &vl)
            .unwrap()
            .wait_in_velocity(LONG)
            .unwrap();
        let mut prev = card.statuses(&[0, 1]).unwrap();
        let (mut wraps, mut worst) = (0, 0.0f64);
        for _ in 0..50_000 {
            sim.step(1);
            let now = card.statuses(&[0, 1]).unwrap();
            let m = now[1].command_position;
            assert!((0.0..COUNTS_PER_TURN).contains(&m), "master at {m}");
            if (m - prev[1].command_position).abs() > COUNTS_PER_TURN / 2.0 {
                wraps += 1;
            }
            let want = table.eval(m).s;
            worst = worst.max((now[0].command_position - want).abs());
            prev = now;
        }
        assert!(wraps >= 24, "{wraps} wraps");
        assert!(
            worst < 1e-6,
            "dir {dir}: the slave off its table by {worst}"
        );
    }
}

/// Layout 1.13: the compare pulses recorded by the plant: (channel, place on the turn in
/// degrees, shaft at the pulse in counts, unwrapped, the shaft's velocity, and the error: the
/// shaft's place on the turn less the position programmed, counts, in [−half, half) a turn).
fn turn_fires(card: &Card) -> Vec<(usize, f64, f64, f64, f64)> {
    let rec = card.sim().unwrap().with_emulator(|e| e.take_fires());
    rec.iter()
        .map(|f| {
            let e = (f.shaft - f.position).rem_euclid(COUNTS_PER_TURN);
            let e = if e >= COUNTS_PER_TURN / 2.0 {
                e - COUNTS_PER_TURN
            } else {
                e
            };
            (f.channel, f.position / SCALE, f.shaft, f.velocity, e)
        })
        .collect()
}

/// The largest error of the pulses (counts): the bound is half a count, the comparator's.
fn worst(f: &[(usize, f64, f64, f64, f64)]) -> f64 {
    f.iter().fold(0.0f64, |m, r| m.max(r.4.abs()))
}

/// The places `q + j·360` strictly between `a` and `b` (degrees, unwrapped).
fn places_between(a: f64, b: f64, q: f64) -> usize {
    let (lo, hi) = (a.min(b), a.max(b));
    let first = ((lo - q) / 360.0).floor() as i64 + 1;
    let last = ((hi - q) / 360.0).ceil() as i64 - 1;
    (last - first + 1).max(0) as usize
}

/// Layout 1.13: compare on the turn in velocity mode, up to 100 turns a second (10⁶ counts/s)
/// for 0.3 s, then down for 0.6 s (5·10⁶ counts/s² each way): a camera trigger every 10° from 5° (count 0: the whole turn) crossing
/// upwards only, and a pulse at 0° (the wrap itself) either way. Every pulse is within half a
/// count of its place (the shaft's true position at the pulse's instant, from the plant); the
/// grid fires each place once, in order, one pitch after the other with none skipped (the
/// first within a pitch of the arm, the last within a pitch of where the axis turned back),
/// only while moving up; the pulse at 0° fires at every crossing, one turn apart, the turn it
/// went back through twice.
#[test]
fn compare_on_the_turn_fires_every_crossing_in_velocity_mode() {
    let card = card(1);
    let axis = card.axis(0).unwrap();
    axis.set_scale(SCALE).unwrap();
    axis.set_modulo(360.0).unwrap();
    let sim = card.sim().unwrap();
    sim.with_emulator(|e| e.record_fires(true));
    let grid = axis.compare(0);
    grid.arm_series_each_turn(0, 2, 5.0, 10.0, 0, Direction::Positive)
        .unwrap();
    let zero = axis.compare(1);
    zero.arm_single_each_turn(1, 2, 0.0, Direction::Either)
        .unwrap();
    let e0 = status(&card, 0).raw.encoder as f64;
    let lim = VelocityLimits::new(180_000.0, 1.8e7);
    axis.move_velocity(36_000.0, &lim).unwrap();
    sim.step(3000);
    axis.move_velocity(-36_000.0, &lim).unwrap();
    let mut peak = f64::MIN;
    for _ in 0..6000 {
        sim.step(1);
        peak = peak.max(status(&card, 0).raw.encoder as f64);
    }
    axis.halt(180_000.0, 1.8e7).unwrap().wait(LONG).unwrap();
    let fires = turn_fires(&card);
    let pitch = 10.0 * SCALE;
    let g: Vec<_> = fires.iter().filter(|f| f.0 == 0).collect();
    let z: Vec<_> = fires.iter().filter(|f| f.0 == 1).collect();
    println!(
        "compare on the turn at 1e6 counts/s: {} grid pulses (every 10 deg, up), {} at 0 deg \
         (either way), max |error| {:.3} and {:.3} counts",
        g.len(),
        z.len(),
        worst(&g.iter().map(|f| **f).collect::<Vec<_>>()),
        worst(&z.iter().map(|f| **f).collect::<Vec<_>>())
    );
    let (gs, zs) = (grid.status().unwrap(), zero.status().unwrap());
    assert_eq!((gs.fires as usize, gs.missed), (g.len(), 0));
    assert_eq!((zs.fires as usize, zs.missed), (z.len(), 0));
    assert_eq!(
        (gs.state, gs.pending, zs.state, zs.pending),
        (IoState::Armed, 36, IoState::Armed, 1)
    );
    assert!(g.len() > 600, "{} grid pulses", g.len());
    assert!(worst(&fires) <= 0.5 + 1e-6, "{}", worst(&fires));
    assert!(g.iter().all(|f| f.3 > 0.0), "the grid fires moving up only");
    assert!(
        g[0].2 - e0 < pitch + 1.0 && g[0].2 > e0,
        "the first place after the arm"
    );
    assert!(
        peak - g[g.len() - 1].2 < pitch + 1.0,
        "the last before the axis turned back"
    );
    for w in g.windows(2) {
        assert!(
            (w[1].2 - w[0].2 - pitch).abs() <= 1.0,
            "{:?} then {:?}",
            w[0],
            w[1]
        );
        let step = (w[1].1 - w[0].1).rem_euclid(360.0);
        assert!((step - 10.0).abs() < 1e-9, "{:?} then {:?}", w[0], w[1]);
    }
    // The crossings of 0°: turn numbers up by one, then the same once (the turn back), then
    // down by one.
    let turns: Vec<i64> = z
        .iter()
        .map(|f| (f.2 / COUNTS_PER_TURN).round() as i64)
        .collect();
    let steps: Vec<i64> = turns.windows(2).map(|w| w[1] - w[0]).collect();
    let back = steps.iter().position(|&d| d == 0).expect("the turn back");
    assert!(steps[..back].iter().all(|&d| d == 1), "{steps:?}");
    assert!(steps[back + 1..].iter().all(|&d| d == -1), "{steps:?}");
    assert!(back > 20 && steps.len() - back > 10, "{steps:?}");
    assert!(z.iter().all(|f| f.1 == 0.0));
}

/// Layout 1.13: compare on the turn through back-and-forth moves (absolute moves the way they
/// name, a relative move of −1000°, several turns): a series every 30° from 15° on every turn
/// crossing downwards, a pulse at 0° either way, and a single at 90° crossing upwards once.
/// Each fires exactly as often as the moves cross its places (counted from the moves' ends,
/// none near a place), within half a count, in its direction only; the single fires once
/// (the first upward crossing, after the arm) and is done.
#[test]
fn compare_on_the_turn_counts_every_crossing_of_back_and_forth_moves() {
    let card = card(1);
    let axis = card.axis(0).unwrap();
    axis.set_scale(SCALE).unwrap();
    axis.set_modulo(360.0).unwrap();
    axis.move_absolute(50.0, &limits())
        .unwrap()
        .wait(LONG)
        .unwrap();
    card.sim().unwrap().with_emulator(|e| e.record_fires(true));
    let down = axis.compare(0);
    down.arm_series_each_turn(0, 2, 15.0, 30.0, 0, Direction::Negative)
        .unwrap();
    let zero = axis.compare(1);
    zero.arm_single_each_turn(1, 2, 0.0, Direction::Either)
        .unwrap();
    let once = axis.compare(2);
    once.arm_single(2, 2, 90.0, Direction::Positive).unwrap();
    // (unwrapped start, end) of each move, degrees.
    let mut at = 50.0;
    let mut moves = Vec::new();
    let plan = [
        (Some(300.0), MoveDirection::Negative, -110.0),
        (Some(200.0), MoveDirection::Positive, 260.0),
        (None, MoveDirection::Current, -1000.0),
        (Some(100.0), MoveDirection::Positive, 180.0),
        (Some(250.0), MoveDirection::Negative, -210.0),
    ];
    for (target, dir, travel) in plan {
        let m = match target {
            Some(t) => axis.move_absolute_dir(t, dir, &limits()).unwrap(),
            None => axis.move_relative(travel, &limits()).unwrap(),
        };
        m.wait(LONG).unwrap();
        moves.push((at, at + travel));
        at += travel;
        let p = status(&card, 0).actual_position;
        assert!((p - at.rem_euclid(360.0)).abs() < 0.1, "at {p}, not {at}");
    }
    let fires = turn_fires(&card);
    let count = |ch: usize| fires.iter().filter(|f| f.0 == ch).count();
    let want_down: usize = moves
        .iter()
        .filter(|(a, b)| b < a)
        .map(|&(a, b)| {
            (0..12)
                .map(|k| places_between(a, b, 15.0 + 30.0 * k as f64))
                .sum::<usize>()
        })
        .sum();
    let want_zero: usize = moves.iter().map(|&(a, b)| places_between(a, b, 0.0)).sum();
    println!(
        "compare on the turn, back and forth: {} pulses every 30 deg down ({want_down} \
         crossed), {} at 0 deg ({want_zero}), max |error| {:.3} counts",
        count(0),
        count(1),
        worst(&fires)
    );
    assert_eq!((count(0), count(1), count(2)), (want_down, want_zero, 1));
    assert!(want_down > 40 && want_zero >= 6, "{want_down} {want_zero}");
    assert!(worst(&fires) <= 0.5 + 1e-6, "{}", worst(&fires));
    assert!(fires.iter().filter(|f| f.0 == 0).all(|f| f.3 < 0.0));
    assert!(fires
        .iter()
        .filter(|f| f.0 == 2)
        .all(|f| f.3 > 0.0 && f.1 == 90.0));
    let (d, z, o) = (
        down.status().unwrap(),
        zero.status().unwrap(),
        once.status().unwrap(),
    );
    assert_eq!(
        (d.fires as usize, d.missed, z.fires as usize, z.missed),
        (want_down, 0, want_zero, 0)
    );
    assert_eq!((o.fires, o.missed, o.state), (1, 0, IoState::Done));
}

/// Layout 1.13: what compare on the turn refuses, each with `CompareTurn` (−146) and nothing
/// changed: each turn on a linear axis; on a rotary axis a position off the turn, a series
/// longer than a turn, one that does not fit a turn each turn, a pitch over the turn; a period
/// change while a channel watches the axis (after the disarm it changes); a table position off
/// the turn. A table on the turn takes its places in any order, each fired once at the next
/// crossing after the one before (the same place again: a turn later).
#[test]
fn compare_on_the_turn_refuses_what_does_not_fit_the_turn() {
    let card = card(1);
    let axis = card.axis(0).unwrap();
    axis.set_scale(SCALE).unwrap();
    let ch = axis.compare(0);
    let turn = |r: motioncard_sdk::Result<()>| {
        let e = r.unwrap_err();
        assert_eq!(
            (e.kind(), e.kind().code()),
            (ErrorKind::CompareTurn, -146),
            "{e}"
        );
    };
    turn(ch.arm_single_each_turn(0, 2, 10.0, Direction::Positive));
    axis.set_modulo(360.0).unwrap();
    turn(ch.arm_single(0, 2, 360.0, Direction::Positive));
    turn(ch.arm_single(0, 2, -0.001, Direction::Either));
    turn(ch.arm_series(0, 2, 0.0, 10.0, 37, Direction::Positive));
    turn(ch.arm_series_each_turn(0, 2, 0.0, 10.0, 37, Direction::Positive));
    turn(ch.arm_series_each_turn(0, 2, 0.0, 400.0, 0, Direction::Positive));
    turn(ch.arm_series_each_turn(0, 2, 360.0, 10.0, 0, Direction::Negative));
    assert_eq!(ch.status().unwrap().state, IoState::Idle, "nothing armed");
    ch.arm_series(0, 2, 350.0, 10.0, 36, Direction::Negative)
        .unwrap();
    turn(axis.set_modulo(720.0));
    assert_eq!(axis.modulo().unwrap(), 360.0);
    ch.disarm().unwrap();
    axis.set_modulo(720.0).unwrap();
    axis.set_modulo(360.0).unwrap();
    // A table: 350, 10, 10 (a turn later), pushed after the arm in that order.
    card.sim().unwrap().with_emulator(|e| e.record_fires(true));
    ch.arm_table(0, 2, 0, Direction::Positive).unwrap();
    ch.push(Direction::Positive, &[350.0, 10.0, 10.0]).unwrap();
    let e = ch.push(Direction::Positive, &[360.0]).unwrap_err();
    assert_eq!(e.kind(), ErrorKind::CompareTurn);
    assert_eq!(ch.status().unwrap().pending, 3);
    axis.move_relative(800.0, &limits())
        .unwrap()
        .wait(LONG)
        .unwrap();
    let f = turn_fires(&card);
    let turns: Vec<(f64, f64)> = f
        .iter()
        .map(|f| (f.1, f.2 / COUNTS_PER_TURN * 360.0))
        .collect();
    assert_eq!(turns.len(), 3, "{turns:?}");
    for ((place, deg), want) in turns.iter().zip([350.0, 370.0, 730.0]) {
        assert!(
            (deg - want).abs() < 0.1 && (place - want.rem_euclid(360.0)).abs() < 1e-9,
            "{turns:?}"
        );
    }
    assert!(worst(&f) <= 0.5 + 1e-6);
    assert_eq!(ch.status().unwrap().pending, 0);
}
