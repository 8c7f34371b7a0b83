use super::*;
use firmware_proto::limit_range;
use proptest::prelude::*;
use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};
use std::cell::RefCell;

fn runner(cases: u32, seed: u8) -> TestRunner {
    let config = Config {
        cases,
        failure_persistence: None,
        max_shrink_iters: 4096,
        ..Config::default()
    };
    TestRunner::new_with_rng(
        config,
        TestRng::from_seed(RngAlgorithm::ChaCha, &[seed; 32]),
    )
}

/// Any `f64` an attacker could pick: every bit pattern, log-uniform magnitudes over the
/// whole exponent range (subnormals included), and the named extremes.
fn wild() -> impl Strategy<Value = f64> {
    prop_oneof![
        any::<f64>(),
        (0u64..2047, any::<u64>(), any::<bool>()).prop_map(|(e, m, neg)| {
            let x = f64::from_bits(e << 52 | m >> 12);
            if neg {
                -x
            } else {
                x
            }
        }),
        (1u64..1 << 52).prop_map(f64::from_bits),
        prop::sample::select(vec![
            0.0,
            -0.0,
            1e-320,
            1e-300,
            1e-30,
            1e300,
            f64::MAX,
            -f64::MAX,
            f64::MIN_POSITIVE,
            -1.0,
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
        ]),
    ]
}

/// A limit: any value, log-uniform inside the range of its order, or the range's
/// low or high end moved by -1, 0 or +1 ulp.
#[derive(Clone, Copy, Debug)]
enum Pick {
    Value(f64),
    InRange(f64),
    Edge(bool, i8),
}

fn pick() -> impl Strategy<Value = Pick> {
    prop_oneof![
        1 => wild().prop_map(Pick::Value),
        24 => (0.0..=1.0f64).prop_map(Pick::InRange),
        3 => (any::<bool>(), -1i8..=1).prop_map(|(hi, u)| Pick::Edge(hi, u)),
    ]
}

fn ulps(x: f64, k: i8) -> f64 {
    match k {
        -1 => x.next_down(),
        1 => x.next_up(),
        _ => x,
    }
}

fn resolve(p: Pick, order: i32, rate: u32) -> f64 {
    let r = limit_range(order, rate);
    let (lo, hi) = (*r.start(), *r.end());
    match p {
        Pick::Value(x) => x,
        Pick::InRange(u) => (lo.ln() + u * (hi.ln() - lo.ln())).exp().clamp(lo, hi),
        Pick::Edge(top, k) => ulps(if top { hi } else { lo }, k),
    }
}

/// Seven picks and how they are tied: 0 independent, 1 symmetric (`dmax = amax`, one
/// jerk), 2 as `mcctl` (`j3 = j1`, `j7 = j5`).
fn limits(p: [Pick; 7], tie: u8, rate: u32) -> Limits {
    let x = |i: usize, order| resolve(p[i], order, rate);
    let mut l = Limits {
        vmax: x(0, 1),
        amax: x(1, 2),
        dmax: x(2, 2),
        j1: x(3, 3),
        j3: x(4, 3),
        j5: x(5, 3),
        j7: x(6, 3),
    };
    if tie == 1 {
        (l.dmax, l.j3, l.j5, l.j7) = (l.amax, l.j1, l.j1, l.j1);
    } else if tie == 2 {
        (l.j3, l.j7) = (l.j1, l.j5);
    }
    l
}

/// A start or end velocity: any value, a fraction of vmax (uniform, or log-uniform down
/// to underflow), or vmax moved by -1, 0, +1 ulp.
#[derive(Clone, Copy, Debug)]
enum Vel {
    Value(f64),
    Frac(f64),
    Tiny(f64),
    Vmax(i8),
}

fn vel() -> impl Strategy<Value = Vel> {
    prop_oneof![
        6 => Just(Vel::Frac(0.0)),
        1 => wild().prop_map(Vel::Value),
        2 => (0.0..=1.0f64).prop_map(Vel::Frac),
        1 => (0.0..=1.0f64).prop_map(Vel::Tiny),
        1 => (-1i8..=1).prop_map(Vel::Vmax),
    ]
}

fn resolve_vel(v: Vel, vmax: f64) -> f64 {
    match v {
        Vel::Value(x) => x,
        Vel::Frac(u) => u * vmax,
        Vel::Tiny(u) => vmax * (-1100.0 * u).exp2(),
        Vel::Vmax(k) => ulps(vmax, k),
    }
}

/// A distance: any value, log-uniform 1e-12..1e16 counts, a factor or ±1 ulp of the
/// shortest feasible distance, a factor of the distance that reaches vmax, or one that
/// takes about MAX_MOVE_TIME at vmax.
#[derive(Clone, Copy, Debug)]
enum Dist {
    Value(f64),
    Log(f64),
    Shortest(f64),
    ShortestUlps(i8),
    Cruise(f64),
    Longest(f64),
}

fn dist() -> impl Strategy<Value = (Dist, bool)> {
    let d = prop_oneof![
        1 => wild().prop_map(Dist::Value),
        4 => (0.0..=1.0f64).prop_map(Dist::Log),
        1 => (0.5..2.0f64).prop_map(Dist::Shortest),
        1 => (-1i8..=1).prop_map(Dist::ShortestUlps),
        1 => (0.3..3.0f64).prop_map(Dist::Cruise),
        1 => (0.9..1.1f64).prop_map(Dist::Longest),
    ];
    (d, any::<bool>())
}

fn resolve_dist(d: (Dist, bool), v0: f64, v1: f64, l: &Limits) -> f64 {
    let shortest = || ref_dist(v0, v1, v0.max(v1), l).1;
    let mag = match d.0 {
        Dist::Value(x) => x,
        Dist::Log(u) => 10f64.powf(-12.0 + 28.0 * u),
        Dist::Shortest(f) => shortest() * f,
        Dist::ShortestUlps(k) => ulps(shortest(), k),
        Dist::Cruise(f) => ref_dist(v0, v1, l.vmax, l).1 * f,
        Dist::Longest(f) => l.vmax * crate::MAX_MOVE_TIME * f,
    };
    if d.1 {
        -mag
    } else {
        mag
    }
}

fn start_pos() -> impl Strategy<Value = f64> {
    prop_oneof![
        2 => Just(0.0),
        2 => -1e3..1e3f64,
        2 => -crate::MAX_POSITION..=crate::MAX_POSITION,
        1 => wild(),
    ]
}

fn rate() -> impl Strategy<Value = u32> {
    prop_oneof![
        1 => Just(1000u32),
        1 => Just(20_000u32),
        4 => 1000u32..=20_000,
    ]
}

/// The refusal the request earns before any planning, in `plan_checked`'s order.
fn refusal(p0: f64, d: f64, v0: f64, v1: f64, l: &Limits, rate: u32) -> Option<PlanError> {
    let all = [l.vmax, l.amax, l.dmax, l.j1, l.j3, l.j5, l.j7];
    let orders = [1, 2, 2, 3, 3, 3, 3];
    if ![p0, d, v0, v1].iter().all(|x| x.is_finite()) || !all.iter().all(|x| x.is_finite()) {
        Some(PlanError::NonFinite)
    } else if all.iter().any(|&x| x <= 0.0) {
        Some(PlanError::NonPositiveLimit)
    } else if all
        .iter()
        .zip(orders)
        .any(|(x, k)| !limit_range(k, rate).contains(x))
    {
        Some(PlanError::LimitRange)
    } else if v0 > l.vmax {
        Some(PlanError::StartVelocityTooHigh)
    } else if v0 < 0.0 || v1 < 0.0 || v1 > l.vmax {
        Some(PlanError::Infeasible)
    } else {
        None
    }
}

fn index(e: PlanError) -> usize {
    match e {
        PlanError::NonFinite => 0,
        PlanError::NonPositiveLimit => 1,
        PlanError::LimitRange => 2,
        PlanError::StartVelocityTooHigh => 3,
        PlanError::Infeasible => 4,
        PlanError::PlanCheck => 5,
    }
}

#[derive(Default, Debug)]
struct Figures {
    /// Refusals by error (NonFinite, NonPositiveLimit, LimitRange,
    /// StartVelocityTooHigh, Infeasible, PlanCheck), then accepted.
    outcomes: [usize; 7],
    /// Accepted plans with non-zero boundary velocities, and ones reaching vmax.
    moving_ends: usize,
    at_vmax: usize,
    /// Worst relative limit excess (velocity, acceleration, jerk) sampled densely.
    limit_excess: f64,
    /// Worst end-position error of the integrated profile, in ulps of max(|p0|, |d|)
    /// where that is at least 1 count, and in counts where it is less.
    end_ulps: f64,
    end_small: f64,
    /// Infeasible: shorter than the shortest distance, or longer than MAX_MOVE_TIME.
    too_short: usize,
    too_long: usize,
    /// Plans the bare planner makes from limits out of range (positive and finite):
    /// passed the check (and then kept every limit), too long, failed the check.
    net: [usize; 3],
    /// Worst relative mismatch of the duration against the reference minimum time.
    time_rel: f64,
}

const CASES: u32 = 100_000;

#[test]
fn plan_checked_over_the_whole_f64_range() {
    let strategy = (
        prop::array::uniform7(pick()),
        0u8..3,
        rate(),
        (vel(), vel()),
        dist(),
        start_pos(),
    );
    let fig = RefCell::new(Figures::default());
    let result = runner(CASES, 0x5c).run(&strategy, |(p, tie, rate, (a, b), dd, p0)| {
        let l = limits(p, tie, rate);
        let (v0, v1) = (resolve_vel(a, l.vmax), resolve_vel(b, l.vmax));
        let d = resolve_dist(dd, v0, v1, &l);
        let r = Profile::plan_checked(p0, d, v0, v1, &l, rate);
        let mut f = fig.borrow_mut();
        let case = format!("p0={p0:e} d={d:e} v0={v0:e} v1={v1:e} {l:?} rate={rate}");
        if let Some(e) = refusal(p0, d, v0, v1, &l, rate) {
            prop_assert_eq!(r.map(|_| ()), Err(e), "{}", case);
            f.outcomes[index(e)] += 1;
            // The check as a safety net under the range check: a plan the bare
            // planner makes from out-of-range limits runs only if it passes, and
            // then it must keep every limit and reach its target.
            if e == PlanError::LimitRange {
                if let Ok(p) = Profile::plan(p0, d, v0, v1, &l) {
                    match p.verify_plan(p0, d, v0, v1, &l) {
                        Ok(()) => {
                            // (the test's tolerances are relative to the limits:
                            // meaningless for limits near the subnormals, where the
                            // check allows MIN_POSITIVE)
                            // (and slots shorter than the normal range, whose few
                            // bits the check allows for)
                            let all = [l.vmax, l.amax, l.dmax, l.j1, l.j3, l.j5, l.j7];
                            let normal = |t: &f64| *t == 0.0 || t.is_normal();
                            if all.iter().all(|&x| x >= 1e-290) && p.phases().iter().all(normal) {
                                check_plan(&p, &l, p0, d, v0, v1);
                            }
                            f.net[0] += 1;
                        }
                        Err(PlanError::Infeasible) => f.net[1] += 1,
                        Err(_) => f.net[2] += 1,
                    }
                }
            }
            return Ok(());
        }
        let dist = d.abs();
        let shortest = ref_dist(v0, v1, v0.max(v1), &l).1;
        let reference = ref_min_time(v0, v1, dist, &l);
        match r {
            Ok(p) => {
                let w = check_plan(&p, &l, p0, d, v0, v1);
                let t = p.duration();
                prop_assert!(t.is_finite() && t <= crate::MAX_MOVE_TIME, "{}", case);
                let tol = 8.0 * f64::EPSILON * p0.abs().max(dist) + 1e-12;
                prop_assert!(t >= (dist - tol) / l.vmax * (1.0 - 1e-9), "{t:e} {}", case);
                prop_assert!(shortest <= dist * (1.0 + 1e-9) + tol, "{}", case);
                // (None: accepted within rounding of the shortest distance; the
                // reference's bisection ends on a tiny vp for d = 0)
                let t_ref = match reference {
                    _ if dist == 0.0 => 0.0,
                    Some((t_ref, _)) => t_ref,
                    None => t,
                };
                let rel = (t - t_ref).abs() / t_ref.max(f64::MIN_POSITIVE);
                if dist > 1e-250 {
                    prop_assert!(rel <= 1e-9, "duration {t:e} vs {t_ref:e}: {}", case);
                    f.time_rel = f.time_rel.max(rel);
                }
                let err = (p.slot_end(6).0 - dist).abs();
                let scale = p0.abs().max(dist);
                if scale >= 1.0 {
                    f.end_ulps = f.end_ulps.max(err / (f64::EPSILON * scale));
                } else {
                    f.end_small = f.end_small.max(err);
                }
                f.limit_excess = f.limit_excess.max(w.limit_excess);
                f.outcomes[6] += 1;
                f.moving_ends += usize::from(v0 > 0.0 || v1 > 0.0);
                f.at_vmax += usize::from(p.peak_velocity() == l.vmax);
            }
            Err(PlanError::Infeasible) => {
                let too_long =
                    reference.is_some_and(|(t, _)| t > crate::MAX_MOVE_TIME * (1.0 - 1e-9));
                let too_short = shortest > dist * (1.0 - 1e-9);
                prop_assert!(too_short || too_long, "refused a feasible move: {}", case);
                f.too_short += usize::from(too_short);
                f.too_long += usize::from(!too_short);
                f.outcomes[4] += 1;
            }
            Err(PlanError::NonFinite) => {
                // the positions or the cruise time overflow
                let overflow = p0.abs() + dist > 1e300 || !(dist / l.vmax).is_finite();
                prop_assert!(overflow, "{}", case);
                f.outcomes[0] += 1;
            }
            Err(e) => prop_assert!(false, "{e:?} for limits in range: {}", case),
        }
        Ok(())
    });
    let f = fig.into_inner();
    eprintln!("plan_checked, {CASES} cases: {f:?}");
    if let Err(e) = result {
        panic!("{e}");
    }
    // Every way of refusing, and enough accepted plans of each kind.
    assert!(
        f.outcomes
            .iter()
            .enumerate()
            .all(|(i, &n)| n >= 200 || i == 5),
        "{f:?}"
    );
    assert_eq!(f.outcomes[5], 0);
    assert!(f.moving_ends >= 500 && f.at_vmax >= 500, "{f:?}");
}

/// A stop's start velocity: any value, 0, or log-uniform up to the velocity range's
/// top; signed.
#[derive(Clone, Copy, Debug)]
enum StopVel {
    Value(f64),
    Zero,
    Log(f64),
}

/// A stop's start acceleration (along the velocity): any value, 0, a factor of dmax,
/// or a factor (or ±1 ulp) of the largest deceleration that can be ramped out at j7
/// without reversing, `sqrt(2 j7 v)`.
#[derive(Clone, Copy, Debug)]
enum StopAcc {
    Value(f64),
    Zero,
    Dmax(f64),
    Reverse(f64),
    ReverseUlps(i8),
}

fn stop_state() -> impl Strategy<Value = (f64, (StopVel, bool), StopAcc)> {
    let v = prop_oneof![
        1 => wild().prop_map(StopVel::Value),
        1 => Just(StopVel::Zero),
        6 => (0.0..=1.0f64).prop_map(StopVel::Log),
    ];
    let a = prop_oneof![
        1 => wild().prop_map(StopAcc::Value),
        2 => Just(StopAcc::Zero),
        4 => (-4.0..3.0f64).prop_map(StopAcc::Dmax),
        2 => (0.5..2.0f64).prop_map(StopAcc::Reverse),
        1 => (-1i8..=1).prop_map(StopAcc::ReverseUlps),
    ];
    (start_pos(), (v, any::<bool>()), a)
}

#[derive(Default, Debug)]
struct StopFigures {
    /// Refusals by error (as for plans), then accepted.
    outcomes: [usize; 7],
    /// Accepted stops with a > 0, with a deceleration beyond dmax, from v = 0.
    kinds: [usize; 3],
    /// Worst relative jerk or deceleration excess (sampled densely).
    excess: f64,
    /// Worst backwards velocity relative to the stop's peak velocity.
    backwards: f64,
    /// Longest accepted stop, s.
    longest: f64,
    /// Accepted stops from a state beyond what the card can hold (position, velocity or
    /// acceleration out of range): checked by the card's check only.
    beyond: usize,
}

#[test]
fn stop_checked_over_the_whole_f64_range() {
    let strategy = (
        prop::array::uniform4(pick()),
        0u8..2,
        prop::option::weighted(0.1, prop::array::uniform3(wild())),
        rate(),
        stop_state(),
    );
    let fig = RefCell::new(StopFigures::default());
    let result = runner(CASES, 0x57).run(&strategy, |(p, tie, other, rate, st)| {
        let x = |i: usize, order| resolve(p[i], order, rate);
        let (dmax, j3) = (x(0, 2), x(1, 3));
        let (j5, j7) = if tie == 1 {
            (j3, j3)
        } else {
            (x(2, 3), x(3, 3))
        };
        // As the axis stops: vmax = f64::MAX, amax = dmax, j1 = j3 (or anything).
        let [vmax, amax, j1] = other.unwrap_or([f64::MAX, dmax, j3]);
        let l = Limits {
            vmax,
            amax,
            dmax,
            j1,
            j3,
            j5,
            j7,
        };
        let (p0, (sv, neg), sa) = st;
        let top = *limit_range(1, rate).end();
        let v = match sv {
            StopVel::Value(x) => x,
            StopVel::Zero => 0.0,
            StopVel::Log(u) => (1e-12f64.ln() + u * (top.ln() - 1e-12f64.ln())).exp(),
        };
        let reverse = (2.0 * j7).sqrt() * v.abs().sqrt();
        let a = match sa {
            StopAcc::Value(x) => x,
            StopAcc::Zero => 0.0,
            StopAcc::Dmax(f) => f * dmax,
            StopAcc::Reverse(f) => -f * reverse,
            StopAcc::ReverseUlps(k) => -ulps(reverse, k),
        };
        let (v0, a0) = if neg { (-v, -a) } else { (v, a) };
        let r = Profile::stop_checked(p0, v0, a0, &l, rate);
        let case = format!("p0={p0:e} v0={v0:e} a0={a0:e} {l:?} rate={rate}");
        let mut f = fig.borrow_mut();
        let all = [l.vmax, l.amax, l.dmax, l.j1, l.j3, l.j5, l.j7];
        let used = [(2, dmax), (3, j3), (3, j5), (3, j7)];
        let want = if ![p0, v0, a0].iter().chain(&all).all(|x| x.is_finite()) {
            Some(PlanError::NonFinite)
        } else if all.iter().any(|&x| x <= 0.0) {
            Some(PlanError::NonPositiveLimit)
        } else if used.iter().any(|(k, x)| !limit_range(*k, rate).contains(x)) {
            Some(PlanError::LimitRange)
        } else {
            None
        };
        if let Some(e) = want {
            prop_assert_eq!(r.map(|_| ()), Err(e), "{}", case);
            f.outcomes[index(e)] += 1;
            return Ok(());
        }
        // Motion frame: the direction of v0, or of a0 from rest.
        let dir = if v0 > 0.0 || (v0 == 0.0 && a0 >= 0.0) {
            1.0
        } else {
            -1.0
        };
        let (v, a) = (v0.abs(), dir * a0);
        let need = if a < 0.0 { 0.5 * a * (a / j7) } else { 0.0 };
        // A state the card can hold: from one beyond (1e210 counts/s) the test's own
        // extrapolation overflows.
        let sane =
            p0.abs() <= crate::MAX_POSITION && v <= top && a.abs() <= *limit_range(2, rate).end();
        match r {
            Ok(p) => {
                if sane {
                    f.excess = f.excess.max(check_stop(&p, &l, p0, v0, a0));
                } else {
                    f.beyond += 1;
                }
                prop_assert!(p.duration().is_finite(), "{}", case);
                prop_assert!(v >= need * (1.0 - 1e-9), "must reverse: {}", case);
                let (vlow, vhigh) = p.velocity_range();
                let back = (-vlow / vhigh.max(v).max(f64::MIN_POSITIVE)).max(0.0);
                f.backwards = f.backwards.max(back);
                f.longest = f.longest.max(p.duration());
                f.outcomes[6] += 1;
                f.kinds[0] += usize::from(a > 0.0 && v > 0.0);
                f.kinds[1] += usize::from(-a > dmax);
                f.kinds[2] += usize::from(v == 0.0);
            }
            Err(PlanError::Infeasible) => {
                prop_assert!(a < 0.0 && v < need * (1.0 + 1e-9), "{}", case);
                f.outcomes[4] += 1;
            }
            // Only from a state beyond anything the card holds: the stop overflows,
            // or loses its velocity to rounding (its check refuses it).
            Err(e @ (PlanError::NonFinite | PlanError::PlanCheck)) => {
                prop_assert!(!sane, "{e:?}: {}", case);
                f.outcomes[index(e)] += 1;
            }
            Err(e) => prop_assert!(false, "{e:?} for limits in range: {}", case),
        }
        Ok(())
    });
    let f = fig.into_inner();
    eprintln!("stop_checked, {CASES} cases: {f:?}");
    if let Err(e) = result {
        panic!("{e}");
    }
    let o = f.outcomes;
    assert!(
        o[0] >= 200 && o[1] >= 200 && o[2] >= 200 && o[4] >= 200,
        "{f:?}"
    );
    assert!(
        o[6] >= CASES as usize / 2 && f.kinds.iter().all(|&n| n >= 1000),
        "{f:?}"
    );
    assert!(o[5] <= CASES as usize / 1000, "{f:?}");
}
