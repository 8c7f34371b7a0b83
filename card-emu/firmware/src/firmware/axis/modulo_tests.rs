//! Layout 1.10: rotary (modulo) axes on one axis set up in-process (no card, no plant): the
//! wrapped positions against an exact integer model over 10⁹ turns, the way an absolute move
//! goes round, and the frame moving under a move that crosses the wrap.

use super::*;
use crate::firmware::rate_hz;
use crate::math;
use firmware_proto::{modulo_subcounts, COMMANDED_SUBCOUNTS};

const TS: f64 = 1e-4;

fn status(ax: &Axis) -> AxisStatus {
    let mut s = ax.status(0);
    ax.wrap_status(&mut s);
    s
}

/// A powered axis at rest at count `at` with the period `m` counts.
fn rotary(at: i64, m: f64) -> Axis {
    let mut ax = Axis::new();
    ax.sense(at, TS);
    ax.set_modulo(modulo_subcounts(m));
    ax.power(true).unwrap();
    ax
}

/// The raw count where the reference is (an ideal drive), from the frame's position and turns.
fn shaft(ax: &Axis) -> i64 {
    let sub = COMMANDED_SUBCOUNTS;
    let q = math::round(ax.reference().pos * sub as f64) as i128 + ax.turn_subcounts();
    (q.div_euclid(sub)) as i64
}

/// Ideal ticks until the axis is done (at most `max`): the done report's position.
fn run_to_done(ax: &mut Axis, max: usize, mut each: impl FnMut(&Axis)) -> f64 {
    for _ in 0..max {
        let enc = shaft(ax);
        ax.sense(enc, TS);
        let (_, r) = ax.control(TS);
        each(ax);
        if let Some((_, p)) = r.done {
            return p;
        }
    }
    panic!("not done in {max} ticks");
}

/// 10⁹ turns in velocity mode: a period of 100.5 counts (not a whole count), 10¹⁰ counts/s at
/// 10 kHz (9,950.2 turns a tick) for 100,500 ticks after the ramp. The published commanded and
/// actual positions are, bit for bit, the exact integer model's reduced into [0, m): the
/// commanded `(B + k·S) mod m` (2⁻³² count), the actual `encoder mod m` (1/65536 count), the
/// encoder being the raw count (10¹² counts, unwrapped). A float trajectory's tail (a time summed
/// tick by tick, a position growing to 10¹²) is off from the first ticks on.
#[test]
fn a_billion_turns_in_velocity_mode_wrap_exactly() {
    let m = 100.5;
    let mq = modulo_subcounts(m) as i128;
    assert_eq!(mq, 100 * 65536 + 32768);
    let mut ax = rotary(0, m);
    let v = 1e10;
    let lim = Limits::symmetric(v, 1e15, 1e19);
    ax.start_velocity(1, v, &lim, rate_hz(TS)).unwrap();
    // The ramp, until the cruise starts.
    let mut k = 0;
    while !matches!(ax.motion, Motion::Cruise { .. }) {
        let enc = shaft(&ax);
        ax.sense(enc, TS);
        ax.control(TS);
        k += 1;
        assert!(k < 100, "no cruise");
    }
    let Motion::Cruise { base, step, .. } = ax.motion else {
        unreachable!()
    };
    // The exact commanded position, unwrapped, in 2^-32 count.
    let start = base + (ax.turn_subcounts() << 16);
    let period = mq << 16;
    let turns0 = ax.turns();
    let ticks: i128 = 100_500;
    let mut enc = shaft(&ax);
    for n in 1..=ticks {
        ax.sense(enc, TS);
        ax.control(TS);
        let exact_cmd = start + n * step;
        let s = status(&ax);
        let want_cmd = exact_cmd.rem_euclid(period) as f64 / 4_294_967_296.0;
        assert_eq!(s.cmd_pos, want_cmd, "commanded, tick {n}");
        let want_act = (enc as i128 * 65536).rem_euclid(mq) as f64 / 65536.0;
        assert_eq!(s.act_pos, want_act, "actual, tick {n}");
        assert!((0.0..m).contains(&s.cmd_pos) && (0.0..m).contains(&s.act_pos));
        // The shaft follows the reference exactly (an ideal drive, to the count below).
        enc = exact_cmd.div_euclid(1 << 32) as i64;
    }
    let turns = ax.turns() - turns0;
    assert!(turns >= 1_000_000_000, "{turns} turns");
    assert!(enc > 100_000_000_000, "the raw count runs on: {enc}");
    println!(
        "{turns} turns in {ticks} ticks, raw count {enc}: commanded {} and actual {} counts, \
         both exact",
        status(&ax).cmd_pos,
        status(&ax).act_pos
    );
}

/// An absolute move on a modulo axis goes the way it names: shortest (a tie of half a turn
/// positive), positive, negative, current (the motion's, else the last one's); the target must
/// be in [0, m); a linear axis takes no direction.
#[test]
fn absolute_moves_go_the_way_they_name() {
    let m = 3600.0;
    let ax = rotary(100, m);
    let t = |dir, target| ax.move_target_dir(MoveKind::Absolute, target, false, dir);
    use MoveDirection::*;
    assert_eq!(t(Shortest, 3500.0), Ok(-100.0));
    assert_eq!(t(Shortest, 300.0), Ok(300.0));
    assert_eq!(t(Shortest, 1900.0), Ok(1900.0), "a tie goes positive");
    assert_eq!(t(Shortest, 1901.0), Ok(1901.0 - m));
    assert_eq!(t(Positive, 3500.0), Ok(3500.0));
    assert_eq!(t(Positive, 50.0), Ok(50.0 + m));
    assert_eq!(t(Negative, 300.0), Ok(300.0 - m));
    assert_eq!(t(Negative, 50.0), Ok(50.0));
    assert_eq!(t(Positive, 100.0), Ok(100.0), "where it is: no turn");
    assert_eq!(t(Negative, 100.0), Ok(100.0), "where it is: no turn");
    assert_eq!(t(Current, 50.0), Ok(50.0 + m), "never moved: positive");
    for bad in [-0.5, m, 1e6, -m] {
        assert_eq!(t(Shortest, bad), Err(NackCode::ModuloMove), "{bad}");
    }
    // Relative moves go their distance, turns and all.
    assert_eq!(
        ax.move_target_dir(MoveKind::Relative, 2.5 * m, false, Positive),
        Ok(100.0 + 2.5 * m)
    );
    let lin = Axis::new();
    assert_eq!(
        lin.move_target_dir(MoveKind::Absolute, 10.0, false, Positive),
        Err(NackCode::ModuloMove)
    );
    assert_eq!(
        lin.move_target_dir(MoveKind::Absolute, 1e6, false, Shortest),
        Ok(1e6)
    );
    // Current after a negative move: negative.
    let mut ax = rotary(100, m);
    ax.start_move_dir(
        1,
        MoveKind::Absolute,
        50.0,
        &lim(),
        false,
        rate_hz(TS),
        Shortest,
    )
    .unwrap();
    run_to_done(&mut ax, 20_000, |_| {});
    let cur = ax.move_target_dir(MoveKind::Absolute, 60.0, false, Current);
    assert_eq!(cur, Ok(60.0 - m));
}

fn lim() -> Limits {
    Limits::symmetric(2e5, 2e6, 1e8)
}

/// A move across the wrap (3500 to 100 the short way, 200 counts forward): the frame moves by a
/// turn under it, the reference (unwrapped: frame + turns) runs on without a jump, the published
/// positions stay in [0, m), and the move ends done at 100, in one turn.
#[test]
fn a_move_across_the_wrap_runs_on_without_a_jump() {
    let m = 3600.0;
    let mut ax = rotary(3500, m);
    assert_eq!(status(&ax).act_pos, 3500.0);
    ax.start_move_dir(
        1,
        MoveKind::Absolute,
        100.0,
        &lim(),
        false,
        rate_hz(TS),
        MoveDirection::Shortest,
    )
    .unwrap();
    let unwrapped = |ax: &Axis| ax.reference().pos + ax.turns() as f64 * m;
    let mut prev = unwrapped(&ax);
    let mut wrapped_at = None;
    let done = run_to_done(&mut ax, 20_000, |ax| {
        let u = unwrapped(ax);
        assert!(u >= prev - 1e-9 && u - prev < 25.0, "{prev} -> {u}");
        prev = u;
        let s = status(ax);
        assert!((0.0..m).contains(&s.cmd_pos) && (0.0..m).contains(&s.act_pos));
        assert!(
            s.ferr.abs() < 2.0,
            "no jump in the following error: {}",
            s.ferr
        );
        if ax.turns() == 1 && wrapped_at.is_none() {
            wrapped_at = Some(s.cmd_pos);
        }
    });
    assert!(wrapped_at.unwrap() < 25.0);
    assert!((done - 100.0).abs() <= 1.0, "done at {done}");
    assert_eq!(ax.turns(), 1);
    assert_eq!(status(&ax).target, 100.0);
    assert_eq!(ax.encoder(), 3700);
}

/// Setting the period keeps the position and wraps it at once; making the axis linear again
/// keeps the position where it is (the turns folded into the offset), and it no longer wraps.
#[test]
fn setting_the_period_wraps_where_the_axis_is() {
    let mut ax = Axis::new();
    ax.sense(7300, TS);
    ax.set_modulo(modulo_subcounts(3600.0));
    let mut enc = 7300;
    ax.sense(enc, TS);
    ax.control(TS);
    assert_eq!(status(&ax).act_pos, 100.0);
    assert_eq!(ax.turns(), 2);
    enc += 10;
    ax.sense(enc, TS);
    ax.control(TS);
    assert_eq!(status(&ax).act_pos, 110.0);
    ax.set_modulo(0);
    ax.sense(enc, TS);
    ax.control(TS);
    assert_eq!(status(&ax).act_pos, 110.0);
    enc += 4000;
    ax.sense(enc, TS);
    ax.control(TS);
    assert_eq!(status(&ax).act_pos, 4110.0);
    assert_eq!(ax.turns(), 0);
}

/// Layout 1.13: position compare on the turn after 10⁹ turns. The axis of
/// [`a_billion_turns_in_velocity_mode_wrap_exactly`] (period 100.5 counts, 10¹⁰ counts/s, an
/// ideal drive) with a compare channel at 40.25 on every turn, fed each tick as the I/O unit
/// feeds it (the counts at the tick's two ends as cell middles in the axis's frame of now).
/// Every crossing is counted against an exact integer model (1/65536 count, unwrapped): at
/// 9,950 crossings a tick the channel examines 512 and counts the rest missed, and fires plus
/// misses equal the crossings, tick for tick, over 10⁹ turns. Then the axis slows to 2·10⁵
/// counts/s and every crossing fires, at the exact model's instant (to 1e-9 of a tick).
#[test]
fn compare_on_the_turn_is_exact_after_a_billion_turns() {
    use crate::firmware::compare::{self, Compare, Fire};
    use firmware_proto::cmd::{CompareArm, CompareKind, Direction};
    let m = 100.5;
    let mq = modulo_subcounts(m) as i128;
    let p = 40.25;
    let pq = (p * 65536.0) as i128;
    let mut ax = rotary(0, m);
    let arm = CompareArm {
        channel: 0,
        kind: CompareKind::Single,
        direction: Some(Direction::Up),
        output: 0.0,
        pulse_us: 1.0,
        low_water: 0.0,
        position: p,
        pitch: 0.0,
        count: 0.0,
        each_turn: true,
    };
    let mut ch = Compare::new();
    ch.start(compare::validate_arm(0, &arm, 10_000, 1, ax.modulo()).unwrap())
        .unwrap();
    // Crossings of p + j·m up to the cell middle of count `n`, exactly.
    let upto = |n: i64| (n as i128 * 65536 + 32768 - pq).div_euclid(mq);
    let lim = Limits::symmetric(1e10, 1e15, 1e19);
    ax.start_velocity(1, 1e10, &lim, rate_hz(TS)).unwrap();
    let turns0 = ax.turns();
    let mut enc = shaft(&ax);
    let mut tick = 0u64;
    let mut step =
        |ax: &mut Axis, ch: &mut Compare, enc: &mut i64| -> (i128, std::vec::Vec<Fire>) {
            let before = *enc;
            *enc = shaft(ax);
            ax.sense(*enc, TS);
            ax.control(TS);
            tick += 1;
            let at = |n: i64| ax.load_position_of_count(n) + 0.5;
            let (x0, x1) = (at(before), at(*enc));
            let mut f = heapless::Vec::<Fire, 512>::new();
            let span = (x0.min(x1), x0.max(x1));
            let (n0, m0) = (ch.status().fires, ch.status().missed);
            ch.tick(0, (x0, x1), span, tick, &mut f);
            let seen = (ch.status().fires - n0) + (ch.status().missed - m0);
            assert_eq!(
                i128::from(seen),
                upto(*enc) - upto(before),
                "tick {tick}: counts {before}..{enc}"
            );
            (upto(*enc) - upto(before), f.to_vec())
        };
    let mut crossed = 0i128;
    for _ in 0..100_600 {
        crossed += step(&mut ax, &mut ch, &mut enc).0;
    }
    let turns = ax.turns() - turns0;
    assert!(turns >= 1_000_000_000, "{turns} turns");
    let s = ch.status();
    assert_eq!(i128::from(s.fires) + i128::from(s.missed), crossed);
    println!(
        "{turns} turns: {crossed} crossings of {p}, {} fired (one a 1 µs pulse), {} missed",
        s.fires, s.missed
    );
    // Slow: every crossing fires at its exact instant.
    ax.start_velocity(2, 2e5, &lim, rate_hz(TS)).unwrap();
    for _ in 0..20 {
        step(&mut ax, &mut ch, &mut enc);
    }
    let missed = ch.status().missed;
    let mut fired = 0;
    for _ in 0..5_000 {
        let before = enc;
        let (n, f) = step(&mut ax, &mut ch, &mut enc);
        assert_eq!(n, f.len() as i128);
        let (x0, x1) = (before as i128 * 65536 + 32768, enc as i128 * 65536 + 32768);
        for (k, f) in f.iter().enumerate() {
            let q = pq + (upto(before) + 1 + k as i128) * mq;
            let want = (q - x0) as f64 / (x1 - x0) as f64;
            assert!((f.frac - want).abs() < 1e-9, "{} vs {want}", f.frac);
            assert_eq!(f.position, p);
        }
        fired += f.len();
    }
    assert_eq!(ch.status().missed, missed, "none missed at 2e5 counts/s");
    assert!(fired >= 900, "{fired} fires");
    println!("then at 2e5 counts/s: {fired} fires, each at the exact crossing's instant");
}
