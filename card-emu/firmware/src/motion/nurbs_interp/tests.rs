use super::*;
use crate::motion::path_speed::*;
use crate::motion::saturation::*;
use crate::presets::*;
use crate::servo::pdplus::*;

/// The tests' seeded generator, uniform in [0, 1).
fn uniform01(seed: u64) -> impl FnMut() -> f64 {
    crate::testkit::rng::Rng::new(seed).units()
}
use crate::motion::nurbs::clamped_uniform_knots;

fn pt(xs: &[f64]) -> Point {
    let mut p = Point::zeros();
    for (i, x) in xs.iter().enumerate() {
        p[i] = *x;
    }
    p
}

/// 60 control points, degree 3, 3-D, with two double interior knots.
fn many_knot_curve() -> Nurbs {
    let n = 60;
    let mut ctrl = Vec::new();
    for i in 0..n {
        let t = i as f64;
        ctrl.extend([
            20_000.0 * (t / 6.0).cos(),
            15_000.0 * (t / 5.0).sin(),
            300.0 * t + 2_000.0 * (t / 3.0).sin(),
        ]);
    }
    let mut knots = clamped_uniform_knots(n, 3).unwrap();
    // make two interior knots double (drop two others to keep the count)
    knots[20] = knots[19];
    knots[40] = knots[39];
    Nurbs::new(3, 3, &ctrl, &vec![1.0; n], &knots).unwrap()
}

/// Degree-5 rational 2-D curve with varied weights.
fn rational_quintic() -> Nurbs {
    let ctrl = [
        0.0, 0.0, 8000.0, 15000.0, 20000.0, -6000.0, 32000.0, 9000.0, 41000.0, 30000.0, 30000.0,
        42000.0, 12000.0, 36000.0, 5000.0, 52000.0, 26000.0, 60000.0,
    ];
    let w = [1.0, 2.5, 0.4, 3.0, 0.7, 1.9, 0.5, 4.0, 1.0];
    let mut knots = vec![0.0; 6];
    knots.extend([0.2, 0.45, 0.7]);
    knots.extend([1.0; 6]);
    Nurbs::new(5, 2, &ctrl, &w, &knots).unwrap()
}

fn circle() -> Nurbs {
    Nurbs::circle([3000.0, -2000.0], 10_000.0).unwrap()
}

/// Runs `advance(v)` to the end; returns (worst |chord/Ts - V|/V over all but the last
/// step, steps, final point error, max corrections used).
fn run_constant(curve: Nurbs, v: f64, corr: u32) -> (f64, usize, f64, u32) {
    let cfg = InterpConfig {
        feed: v,
        max_corrections: corr,
        ..InterpConfig::default()
    };
    let end = curve.point(curve.domain().1).unwrap();
    let mut ip = Interpolator::new(curve, cfg).unwrap();
    let mut worst = 0.0f64;
    let mut n = 0;
    let mut max_corr = 0;
    loop {
        let t = ip.advance(v).unwrap();
        n += 1;
        max_corr = max_corr.max(t.corrections);
        if t.done {
            assert!(t.feed <= v * (1.0 + 1e-9), "last step longer than V·Ts");
            return (worst, n, (t.pos - end).amax(), max_corr);
        }
        worst = worst.max((t.feed - v).abs() / v);
        assert!(n < 1_000_000);
    }
}

#[test]
fn constant_feed_fluctuation_three_curves() {
    let cases: [(&str, Nurbs, f64); 3] = [
        ("circle R=10000 (rational)", circle(), 200_000.0),
        ("60 ctrl pts, degree 3, 3-D", many_knot_curve(), 300_000.0),
        ("rational quintic", rational_quintic(), 250_000.0),
    ];
    for (name, c, v) in cases {
        let rho_min = (0..=20_000)
            .map(|i| {
                let (_, d1, d2) = c.eval(i as f64 / 20_000.0).unwrap();
                radius_of_curvature(&d1, &d2)
            })
            .fold(f64::INFINITY, f64::min);
        println!(
            "{name}: min radius of curvature {rho_min:.0} counts, step V·Ts = {:.0} counts",
            v * 1e-3
        );
        let (taylor, _, _, _) = run_constant(c.clone(), v, 0);
        let (one, _, _, _) = run_constant(c.clone(), v, 1);
        let (two, _, _, _) = run_constant(c.clone(), v, 2);
        let (w, n, end_err, mc) = run_constant(c, v, 3);
        println!(
            "{name}: V={v} counts/s, {n} steps; worst feed fluctuation: eq 3.1 alone {taylor:.2e}, \
             +1 Newton {one:.2e}, +2 Newton {two:.2e}, up to 3 Newton {w:.2e} (max used {mc}); end error {end_err:.1e}"
        );
        assert!(w <= 1e-4, "{name}: {w}");
        assert!(two <= 1e-4, "{name}: two corrections {two}");
        assert_eq!(end_err, 0.0, "{name}: last step must land on C(u_end)");
    }
}

/// Max distance between the curve and each chord of a tick sequence.
fn chord_errors(curve: &Nurbs, us: &[f64]) -> f64 {
    let mut worst = 0.0f64;
    for w in us.windows(2) {
        let a = curve.point(w[0]).unwrap();
        let b = curve.point(w[1]).unwrap();
        let ab = b - a;
        let l2 = ab.norm_squared();
        for i in 1..16 {
            let u = w[0] + (w[1] - w[0]) * i as f64 / 16.0;
            let p = curve.point(u).unwrap();
            let t = if l2 > 0.0 {
                ((p - a).dot(&ab) / l2).clamp(0.0, 1.0)
            } else {
                0.0
            };
            worst = worst.max((p - (a + ab * t)).norm());
        }
    }
    worst
}

struct PlanRun {
    ticks: usize,
    chord_err: f64,
    max_acc: f64,
    max_jerk: f64,
    last_feed: f64,
    end_err: f64,
    peak_feed: f64,
}

/// First and second differences of a feed sequence over Ts and Ts².
fn feed_differences(feeds: &[f64], ts: f64) -> (Vec<f64>, Vec<f64>) {
    let acc: Vec<f64> = feeds.windows(2).map(|w| (w[1] - w[0]) / ts).collect();
    let jerk: Vec<f64> = acc.windows(2).map(|w| (w[1] - w[0]) / ts).collect();
    (acc, jerk)
}

fn run_planned(curve: Nurbs, cfg: InterpConfig) -> PlanRun {
    let end = curve.point(curve.domain().1).unwrap();
    let mut ip = Interpolator::new(curve.clone(), cfg).unwrap();
    let mut us = vec![curve.domain().0];
    // at rest before the start and after the end: the feed's differences at both ends count
    let mut feeds = vec![0.0, 0.0];
    loop {
        let t = ip.tick().unwrap();
        us.push(t.u);
        feeds.push(t.feed);
        if t.done {
            break;
        }
        assert!(us.len() < 2_000_000);
    }
    let last_feed = feeds[feeds.len() - 1];
    for _ in 0..3 {
        let t = ip.tick().unwrap();
        assert!(t.done && t.feed == 0.0);
        feeds.push(t.feed);
    }
    let (acc, jerk) = feed_differences(&feeds, cfg.ts);
    PlanRun {
        ticks: us.len() - 1,
        chord_err: chord_errors(&curve, &us),
        max_acc: acc.iter().fold(0.0, |m, a| m.max(a.abs())),
        max_jerk: jerk.iter().fold(0.0, |m, a| m.max(a.abs())),
        last_feed,
        end_err: (ip.position() - end).amax(),
        peak_feed: feeds.iter().fold(0.0, |m, f| m.max(*f)),
    }
}

#[test]
fn planned_feed_chord_error_and_exact_end() {
    let cases: [(&str, Nurbs, f64); 3] = [
        ("circle", circle(), 600_000.0),
        ("60 ctrl pts", many_knot_curve(), 600_000.0),
        ("rational quintic", rational_quintic(), 600_000.0),
    ];
    for (name, c, feed) in cases {
        for (accel, jerk, ts) in [(2e7, 2e10, 1e-3), (2e7, 2e9, 1e-3), (5e6, 1e9, 1e-4)] {
            let cfg = InterpConfig {
                ts,
                feed,
                accel,
                jerk,
                chord_tol: 1.0,
                ..InterpConfig::default()
            };
            let r = run_planned(c.clone(), cfg);
            println!(
                "{name} (A {accel:.0e}, J {jerk:.0e}, Ts {ts:.0e}): {} ticks, peak feed {:.0}, max chord error {:.4} counts (tol 1), \
                 max |dV/dt|/A {:.12}, max |d²V/dt²|/J {:.12}, last step {:.3} counts/s, end err {:.1e}",
                r.ticks, r.peak_feed, r.chord_err, r.max_acc / accel, r.max_jerk / jerk, r.last_feed, r.end_err
            );
            assert!(r.chord_err <= 1.0, "{name}: chord error {}", r.chord_err);
            assert_eq!(r.end_err, 0.0);
            let ulp = f64::EPSILON * 1e5;
            assert!(r.peak_feed <= feed * (1.0 + 1e-9));
            assert!(
                r.max_acc <= accel * (1.0 + 1e-9) + 8.0 * ulp / (ts * ts),
                "{name}: acc {}",
                r.max_acc
            );
            assert!(
                r.max_jerk <= jerk * (1.0 + 1e-9) + 16.0 * ulp / (ts * ts * ts),
                "{name}: jerk {}",
                r.max_jerk
            );
        }
    }
}

/// Time of the continuous time-optimal rest-to-rest S-curve over `l` (no constant-speed
/// phase when V is not reached).
fn ideal_time(l: f64, v: f64, a: f64, j: f64) -> f64 {
    // distance to reach speed w and come back to rest: w·(w/a + a/j) or 2·w^1.5/√j
    let ramp = |w: f64| {
        if w <= a * a / j {
            2.0 * w * (w / j).sqrt()
        } else {
            w * (w / a + a / j)
        }
    };
    let time = |w: f64| {
        if w <= a * a / j {
            4.0 * (w / j).sqrt()
        } else {
            2.0 * (w / a + a / j)
        }
    };
    if ramp(v) <= l {
        return time(v) + (l - ramp(v)) / v;
    }
    let (mut lo, mut hi) = (0.0, v);
    for _ in 0..200 {
        let m = 0.5 * (lo + hi);
        if ramp(m) > l {
            hi = m;
        } else {
            lo = m;
        }
    }
    time(lo)
}

/// The path-speed S-curve starts and stops within its speed, acceleration and jerk limits
/// (measured as the sampled feed and its first and second differences, with the rest
/// before the start and after the end included) to 1e-9 relative, lands exactly on the
/// end, and takes about the continuous optimum's time.
#[test]
fn planner_s_curve_on_lines() {
    let cases = [
        // (length, V, A, J, Ts)
        (100_000.0, 500_000.0, 1e7, 1e9, 1e-3),
        (3_000.0, 500_000.0, 1e7, 1e9, 1e-3),
        (100_000.0, 200_000.0, 5e6, 2e10, 1e-3),
        (777.7, 100_000.0, 1e6, 1e8, 1e-3),
        (20_000.0, 200_000.0, 2e6, 5e8, 1e-4),
        (5.0, 100_000.0, 1e7, 1e10, 1e-3),
    ];
    for (len, feed, accel, jerk, ts) in cases {
        let line = Nurbs::new(
            1,
            2,
            &[0.0, 0.0, 0.6 * len, 0.8 * len],
            &[1.0, 1.0],
            &[0.0, 0.0, 1.0, 1.0],
        )
        .unwrap();
        let cfg = InterpConfig {
            ts,
            feed,
            accel,
            jerk,
            chord_tol: 1.0,
            ..InterpConfig::default()
        };
        let r = run_planned(line, cfg);
        let ideal = ideal_time(len, feed, accel, jerk) / ts;
        println!(
            "line {len}: {} ticks (continuous optimum {ideal:.1}), peak {:.3}/{feed}, max |a|/A {:.12}, \
             max |j|/J {:.12}, last step {:.3} counts/s",
            r.ticks,
            r.peak_feed,
            r.max_acc / accel,
            r.max_jerk / jerk,
            r.last_feed
        );
        // 1e-9 relative, plus what rounding the positions (|p| ≤ len) does to the feed's
        // differences: a few ulps of |p| over Ts² and Ts³
        let ulp = f64::EPSILON * len;
        assert!(r.peak_feed <= feed * (1.0 + 1e-9) + 4.0 * ulp / ts);
        let acc_tol = accel * 1e-9 + 8.0 * ulp / (ts * ts);
        let jerk_tol = jerk * 1e-9 + 16.0 * ulp / (ts * ts * ts);
        assert!(r.max_acc <= accel + acc_tol, "acc {}", r.max_acc / accel);
        assert!(r.max_jerk <= jerk + jerk_tol, "jerk {}", r.max_jerk / jerk);
        assert_eq!(r.end_err, 0.0);
        assert!(
            (r.ticks as f64) <= ideal * 1.01 + 3.0 && (r.ticks as f64) >= ideal,
            "ticks {} vs {ideal}",
            r.ticks
        );
    }
}

/// A curve split in pieces runs through the joints as the whole curve does: same feed at
/// every tick (the joint's tick included) to 1e-9, the same limits, the same number of
/// ticks, the same end.
#[test]
fn continuation_runs_through_joints_like_the_whole_curve() {
    let n = 300;
    let ctrl: Vec<f64> = (0..n)
        .flat_map(|i| {
            let t = i as f64;
            [400.0 * t, 5_000.0 * (t / 25.0).sin()]
        })
        .collect();
    let w: Vec<f64> = (0..n).map(|i| 1.0 + 0.3 * (i as f64 / 9.0).cos()).collect();
    let knots = clamped_uniform_knots(n, 3).unwrap();
    let whole = Nurbs::new(3, 2, &ctrl, &w, &knots).unwrap();
    let pieces = crate::motion::nurbs::split_curve(3, 2, &ctrl, &w, &knots, 70).unwrap();
    assert!(pieces.len() >= 4);
    let cfg = InterpConfig {
        feed: 300_000.0,
        accel: 1e7,
        jerk: 1e9,
        chord_tol: 1.0,
        ..InterpConfig::default()
    };
    let run_whole = {
        let mut ip = Interpolator::new(whole.clone(), cfg).unwrap();
        let mut f = vec![0.0, 0.0];
        loop {
            let t = ip.tick().unwrap();
            f.push(t.feed);
            if t.done {
                break;
            }
        }
        f
    };
    let mut ips: Vec<Interpolator> = pieces
        .iter()
        .map(|p| Interpolator::new(p.clone(), cfg).unwrap())
        .collect();
    let mut feeds = vec![0.0, 0.0];
    let mut prev = ips[0].position();
    let mut k = 0;
    let mut joints = Vec::new();
    loop {
        let (head, tail) = ips.split_at_mut(k + 1);
        let cur = &mut head[k];
        let next = tail.first().and_then(|n| cur.continuation(n));
        let mut t = cur.tick_into(next).unwrap();
        if t.done && k + 1 < ips.len() {
            let (head, tail) = ips.split_at_mut(k + 1);
            t = tail[0].take_over(&head[k]).unwrap();
            joints.push(feeds.len());
            k += 1;
        }
        // the feed as the axes see it: the step between consecutive reference points
        feeds.push((t.pos - prev).norm() / cfg.ts);
        prev = t.pos;
        if t.done && k + 1 == ips.len() {
            break;
        }
        assert!(feeds.len() < 100_000);
    }
    feeds.extend([0.0; 3]);
    let (acc, jerk) = feed_differences(&feeds, cfg.ts);
    let max_acc = acc.iter().fold(0.0f64, |m, a| m.max(a.abs()));
    let max_jerk = jerk.iter().fold(0.0f64, |m, a| m.max(a.abs()));
    let diff = feeds
        .iter()
        .zip(&run_whole)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0f64, f64::max);
    let end = whole.point(whole.domain().1).unwrap();
    println!(
        "{} pieces, joints at ticks {joints:?}: {} ticks (whole curve {}), feed at the joints {:?}, \
         largest feed difference to the whole curve {diff:.3e}, max |a|/A {:.12}, max |j|/J {:.12}",
        pieces.len(),
        feeds.len() - 5,
        run_whole.len() - 2,
        joints.iter().map(|&j| feeds[j]).collect::<Vec<_>>(),
        max_acc / cfg.accel,
        max_jerk / cfg.jerk
    );
    assert_eq!(joints.len(), pieces.len() - 1);
    assert_eq!(prev, end);
    assert!(max_acc <= cfg.accel * (1.0 + 1e-9));
    assert!(max_jerk <= cfg.jerk * (1.0 + 1e-9));
    for &j in &joints {
        assert!(
            (feeds[j] - cfg.feed).abs() <= 1e-9 * cfg.feed,
            "joint feed {}",
            feeds[j]
        );
    }
    assert!((feeds.len() as i64 - 3 - run_whole.len() as i64).abs() <= 2);
}

/// The die-bonder path cut in three and run through its joints with the saturation-aware
/// feed in the closed loop (PD+ on the plant model): |u| ≤ Umax on every tick, joints
/// included, and the end is reached exactly.
#[test]
fn saturation_aware_feed_across_joints() {
    let preset = die_bonder_preset();
    let ts = preset.ts;
    let sat = SaturationAwareFeed::new(&preset.axes, ts).unwrap();
    let whole = die_bonder_path();
    let n = whole.n_ctrl();
    let ctrl: Vec<f64> = (0..n)
        .flat_map(|i| {
            let p = whole.control_point(i).unwrap();
            [p[0], p[1]]
        })
        .collect();
    let w: Vec<f64> = (0..n).map(|i| whole.weight(i).unwrap()).collect();
    let pieces = crate::motion::nurbs::split_curve(3, 2, &ctrl, &w, whole.knots(), 7).unwrap();
    assert!(pieces.len() >= 3);
    let cfg = InterpConfig {
        ts,
        feed: 400_000.0,
        accel: 4e7,
        jerk: 4e10,
        chord_tol: 1.0,
        max_corrections: 3,
    };
    let mut ips: Vec<Interpolator> = pieces
        .iter()
        .map(|p| Interpolator::with_actuator_limits(p.clone(), cfg, &sat, 0.8).unwrap())
        .collect();
    let start = whole.point(0.0).unwrap();
    let end = whole.point(1.0).unwrap();
    let (mut th, mut vel, mut th_prev) = ([start[0], start[1]], [0.0; 2], [start[0], start[1]]);
    let mut pd: Vec<PdPlus> = preset
        .axes
        .iter()
        .map(|a| PdPlus::new(a.gains, ts).unwrap())
        .collect();
    for (j, c) in pd.iter_mut().enumerate() {
        c.reset(th[j]);
    }
    let (mut k, mut worst, mut joints, mut ticks) = (0, 0.0f64, 0, 0);
    loop {
        let theta_a = pt(&th);
        let w_a = pt(&[(th[0] - th_prev[0]) / ts, (th[1] - th_prev[1]) / ts]);
        let (head, tail) = ips.split_at_mut(k + 1);
        let cur = &mut head[k];
        let next = tail.first().and_then(|nx| cur.continuation(nx));
        let (mut t, _) = cur.tick_guarded_into(&sat, &theta_a, &w_a, next).unwrap();
        if t.done && k + 1 < ips.len() {
            let (head, tail) = ips.split_at_mut(k + 1);
            t = tail[0].take_over(&head[k]).unwrap();
            k += 1;
            joints += 1;
        }
        th_prev = th;
        for j in 0..2 {
            let u = pd[j].update(t.pos[j], t.vel[j], t.acc[j], th[j]);
            worst = worst.max(u.abs() / preset.axes[j].umax);
            (th[j], vel[j]) = preset.axes[j].plant.step(ts, th[j], vel[j], u);
        }
        ticks += 1;
        if t.done && k + 1 == ips.len() {
            assert_eq!(t.pos, end);
            break;
        }
        assert!(ticks < 10_000);
    }
    println!(
        "{} pieces, {joints} joints, {ticks} ticks, max |u|/Umax {worst:.9}",
        pieces.len()
    );
    assert_eq!(joints, pieces.len() - 1);
    assert!(worst <= 1.0, "|u| over Umax: {worst}");
}

#[test]
fn stopping_distance_matches_simulation() {
    for &(v, a) in &[
        (100_000.0, 0.0),
        (300_000.0, 5e6),
        (50_000.0, -8e6),
        (1_000.0, 0.0),
    ] {
        let (amax, j, ts) = (1e7, 1e9, 1e-5);
        let d = PathSpeedPlanner::stopping_distance(v, a, amax, j);
        let mut p = PathSpeedPlanner::new(ts, amax, j).unwrap();
        p.v = v;
        p.a = a;
        let mut s = 0.0;
        for _ in 0..10_000_000 {
            s += p.next(0.0, 1e12) * ts;
            if p.speed() <= 0.0 && p.accel() == 0.0 {
                break;
            }
        }
        println!("stop from v={v} a={a}: formula {d:.3}, simulated {s:.3}");
        assert!((s - d).abs() <= 1e-3 * d.max(1.0) + v * ts, "{s} vs {d}");
    }
}

#[test]
fn pd_plus_equals_eq_3_5_and_window_edges_hit_umax() {
    let p = die_bonder_preset();
    let ts = p.ts;
    let sat = SaturationAwareFeed::new(&p.axes, ts).unwrap();
    let g = p.axes[0].gains;
    let mut pd = PdPlus::new(g, ts).unwrap();
    pd.reset(100.0);
    let _ = pd.update(110.0, 5_000.0, 1e5, 100.0);
    // tick k: θ_a[k-1] = 100, θ_a[k] = 104, θ_d[k-1] = 110, w_d[k-1] = 5000
    let st = AxisSample {
        theta_d_prev: 110.0,
        w_d_prev: 5_000.0,
        theta_a: 104.0,
        w_a: 4_000.0,
    };
    let w_d = 7_000.0;
    let u = pd.update(110.0 + w_d * ts, w_d, (w_d - 5_000.0) / ts, 104.0);
    let pred = sat.predict_drive(0, &st, w_d);
    assert!(
        (u - pred).abs() <= 1e-12 * u.abs().max(1.0),
        "{u} vs {pred}"
    );
    let (lo, hi) = sat.speed_window(0, &st);
    // the window keeps GUARD_MARGIN (1e-6) below Umax
    assert!((sat.predict_drive(0, &st, hi) - (1.0 - GUARD_MARGIN)).abs() < 1e-12);
    assert!((sat.predict_drive(0, &st, lo) + (1.0 - GUARD_MARGIN)).abs() < 1e-12);
    assert!(sat.predict_drive(5, &st, 1.0).is_nan());
    // the gains read from Table 1
    let c = g.drive_coefficient(ts);
    assert!(
        (c - (0.0136e-3 + 0.03 / 1591.5494 + (1.0 + 310.0) / (2506.17 * 1591.5494))).abs() < 1e-15
    );
}

#[test]
fn limit_feed_cases_without_plant() {
    let p = die_bonder_preset();
    let sat = SaturationAwareFeed::new(&p.axes, p.ts).unwrap();
    let dir = pt(&[0.6, 0.8]);
    // at rest, on target
    let rest = [AxisSample::default(); 2];
    let d = sat.limit_feed(1e6, 1e6, &dir, &rest).unwrap();
    assert!(d.limited && d.feasible && !d.raised);
    assert!(
        (d.max_drive_ratio - (1.0 - GUARD_MARGIN)).abs() < 1e-12,
        "binding axis at Umax: {}",
        d.max_drive_ratio
    );
    let small = sat.limit_feed(1_000.0, 1e6, &dir, &rest).unwrap();
    assert!(!small.limited && small.feed == 1_000.0 && small.max_drive_ratio < 1.0);
    // moving fast along +x, previous command 300 000 counts/s: stopping x at once needs a
    // big negative drive -> the feed is raised (eq 3.10 lower case)
    let moving = [
        AxisSample {
            theta_d_prev: 0.0,
            w_d_prev: 300_000.0,
            theta_a: 0.0,
            w_a: 300_000.0,
        },
        AxisSample::default(),
    ];
    let d = sat.limit_feed(0.0, 1e6, &pt(&[1.0, 0.0]), &moving).unwrap();
    assert!(d.raised && d.feasible && d.feed > 250_000.0 && d.max_drive_ratio <= 1.0 + 1e-12);
    // perpendicular direction: x must drop to 0 -> impossible; least violation returned
    let d = sat
        .limit_feed(100_000.0, 1e6, &pt(&[0.0, 1.0]), &moving)
        .unwrap();
    assert!(!d.feasible && d.max_drive_ratio > 1.0);
    let best = d.max_drive_ratio;
    for v in [0.0, 1e3, 1e5, 1e6] {
        assert!(sat.drive_ratio(v, &pt(&[0.0, 1.0]), &moving) >= best - 1e-9);
    }
    // bad inputs are errors, not panics
    assert_eq!(
        sat.limit_feed(f64::NAN, 1.0, &dir, &rest),
        Err(InterpError::BadFeed)
    );
    assert_eq!(
        sat.limit_feed(1.0, -1.0, &dir, &rest),
        Err(InterpError::BadFeed)
    );
    assert_eq!(
        sat.limit_feed(1.0, 1.0, &pt(&[f64::NAN, 0.0]), &rest),
        Err(InterpError::NonFiniteInput)
    );
    let mut bad = rest;
    bad[1].w_a = f64::INFINITY;
    assert_eq!(
        sat.limit_feed(1.0, 1.0, &dir, &bad),
        Err(InterpError::NonFiniteInput)
    );
    assert!(matches!(
        sat.limit_feed(1.0, 1.0, &dir, &rest[..1]),
        Err(InterpError::DimensionMismatch { .. })
    ));
}

#[test]
fn plant_step_is_exact_and_predicted_state_predicts_next_drive() {
    let p = die_bonder_preset();
    let ax = p.axes[0];
    // exact ZOH vs fine RK-free Euler with 1e5 substeps
    let (th, v) = ax.plant.step(p.ts, 10.0, 2_000.0, 0.3);
    let (mut th2, mut v2) = (10.0, 2_000.0);
    let n = 100_000;
    let h = p.ts / n as f64;
    for _ in 0..n {
        let dv = -v2 / ax.plant.tau + ax.plant.counts_gain() / ax.plant.tau * 0.3;
        th2 += h * (v2 + 0.5 * h * dv);
        v2 += h * dv;
    }
    assert!(
        (th - th2).abs() < 1e-3 && (v - v2).abs() < 1e-2,
        "{th} {th2} {v} {v2}"
    );
    // u_a[k+1] predicted from the model equals the PD+ output computed one tick later
    let sat = SaturationAwareFeed::new(&p.axes, p.ts).unwrap();
    let mut pd = PdPlus::new(ax.gains, p.ts).unwrap();
    let (theta_k, vel_k) = (50.0, 20_000.0);
    pd.reset(theta_k - vel_k * p.ts);
    let u_k = pd.update(60.0, 21_000.0, 1e6, theta_k);
    let st = AxisSample::predicted(&ax.plant, p.ts, theta_k, vel_k, u_k, 60.0, 21_000.0);
    let w_next = 22_000.0;
    let pred = sat.predict_drive(0, &st, w_next);
    let (theta_next, _) = ax.plant.step(p.ts, theta_k, vel_k, u_k);
    let actual = pd.update(
        60.0 + w_next * p.ts,
        w_next,
        (w_next - 21_000.0) / p.ts,
        theta_next,
    );
    assert!((pred - actual).abs() < 1e-12 * actual.abs().max(1.0));
}

#[test]
fn bad_inputs_are_errors() {
    let c = circle();
    let ok = InterpConfig::default();
    let bad = |f: fn(&mut InterpConfig)| {
        let mut cfg = ok;
        f(&mut cfg);
        Interpolator::new(c.clone(), cfg).err()
    };
    assert_eq!(bad(|c| c.ts = 0.0), Some(InterpError::BadSampleTime));
    assert_eq!(bad(|c| c.ts = f64::NAN), Some(InterpError::BadSampleTime));
    assert_eq!(bad(|c| c.feed = -1.0), Some(InterpError::BadFeed));
    assert_eq!(
        bad(|c| c.accel = f64::INFINITY),
        Some(InterpError::BadAccel)
    );
    assert_eq!(bad(|c| c.jerk = 0.0), Some(InterpError::BadJerk));
    assert_eq!(
        bad(|c| c.chord_tol = f64::NAN),
        Some(InterpError::BadChordTolerance)
    );
    assert_eq!(
        bad(|c| c.max_corrections = 99),
        Some(InterpError::BadCorrections)
    );
    let dot = Nurbs::new(2, 2, &[1.0; 6], &[1.0; 3], &[0.0, 0.0, 0.0, 1.0, 1.0, 1.0]).unwrap();
    assert_eq!(
        Interpolator::new(dot, ok).err(),
        Some(InterpError::ZeroLengthCurve)
    );
    let mut ip = Interpolator::new(c.clone(), ok).unwrap();
    assert_eq!(ip.advance(f64::NAN).err(), Some(InterpError::BadFeed));
    assert_eq!(ip.advance(-3.0).err(), Some(InterpError::BadFeed));
    let t = ip.advance(0.0).unwrap();
    assert!(!t.done && t.feed == 0.0);
    let p = die_bonder_preset();
    let sat = SaturationAwareFeed::new(&p.axes, p.ts).unwrap();
    assert_eq!(
        ip.tick_guarded(&sat, &pt(&[f64::NAN, 0.0]), &Point::zeros())
            .err(),
        Some(InterpError::NonFiniteInput)
    );
    assert_eq!(
        Interpolator::with_actuator_limits(c.clone(), ok, &sat, 0.0).err(),
        Some(InterpError::BadBudget)
    );
    assert!(matches!(
        Interpolator::with_actuator_limits(many_knot_curve(), ok, &sat, 0.5).err(),
        Some(InterpError::DimensionMismatch { .. })
    ));
    let mut ax = p.axes;
    ax[1].umax = 0.0;
    assert_eq!(
        SaturationAwareFeed::new(&ax, 1e-3).err(),
        Some(InterpError::Model(ModelError::BadUmax { axis: 1 }))
    );
    let mut ax = p.axes;
    ax[0].plant.tau = -1.0;
    assert_eq!(
        SaturationAwareFeed::new(&ax, 1e-3).err(),
        Some(InterpError::Model(ModelError::BadPlant { axis: 0 }))
    );
    let mut ax = p.axes;
    ax[1].gains.kd = f64::NAN;
    assert_eq!(
        SaturationAwareFeed::new(&ax, 1e-3).err(),
        Some(InterpError::Model(ModelError::BadGain { axis: 1 }))
    );
    assert!(SaturationAwareFeed::new(&[], 1e-3).is_err());
    assert_eq!(
        SaturationAwareFeed::new(&p.axes, 0.0).err(),
        Some(InterpError::BadSampleTime)
    );
    let mut pd = PdPlus::new(p.axes[0].gains, 1e-3).unwrap();
    assert_eq!(pd.update(0.0, 0.0, 0.0, f64::NAN), 0.0);
    assert!(pd.fault());
    assert_eq!(pd.update(f64::NAN, 0.0, 0.0, 1.0), 0.0);
    assert!(PathSpeedPlanner::new(1e-3, 0.0, 1.0).is_err());
    let mut pl = PathSpeedPlanner::new(1e-3, 1e7, 1e10).unwrap();
    assert_eq!(pl.next(f64::NAN, f64::NAN), 0.0);
    assert_eq!(chord_feed_limit(f64::NAN, 1e-3, 1.0), 0.0);
    assert_eq!(chord_feed_limit(f64::INFINITY, 1e-3, 1.0), f64::INFINITY);
    assert_eq!(chord_feed_limit(0.5, 1e-3, 1.0), 1000.0);
    for e in [
        InterpError::BadFeed,
        InterpError::Curve(NurbsError::NotClamped),
        InterpError::Model(ModelError::BadGain { axis: 1 }),
    ] {
        assert!(!e.to_string().is_empty());
    }
}

/// Random valid curves and random feeds/limits: every call returns Ok/Err, nothing
/// panics, and every run ends on C(u_end).
#[test]
fn random_curves_random_settings_never_panic() {
    let mut rnd = uniform01(0x1234_5678_9abc_def0u64);
    let p = die_bonder_preset();
    let sat = SaturationAwareFeed::new(&p.axes, p.ts).unwrap();
    for case in 0..60 {
        let deg = 1 + (rnd() * 5.0) as usize % 5;
        let n = deg + 1 + (rnd() * 30.0) as usize;
        let ctrl: Vec<f64> = (0..2 * n).map(|_| (rnd() - 0.5) * 2e4).collect();
        let w: Vec<f64> = (0..n).map(|_| 0.2 + 4.8 * rnd()).collect();
        let knots = clamped_uniform_knots(n, deg).unwrap();
        let curve = Nurbs::new(deg, 2, &ctrl, &w, &knots).unwrap();
        let end = curve.point(1.0).unwrap();
        let cfg = InterpConfig {
            feed: 2e4 + rnd() * 1e6,
            accel: 1e5 + rnd() * 1e8,
            jerk: 1e7 + rnd() * 1e11,
            chord_tol: 0.01 + rnd() * 10.0,
            max_corrections: (rnd() * 4.0) as u32,
            ..InterpConfig::default()
        };
        let guarded = case % 2 == 0;
        let mut ip = if guarded {
            Interpolator::with_actuator_limits(curve, cfg, &sat, 0.2 + 0.8 * rnd()).unwrap()
        } else {
            Interpolator::new(curve, cfg).unwrap()
        };
        let mut k = 0;
        let mut th = ip.position();
        while !ip.is_done() {
            let t = if guarded {
                let w = (ip.position() - th) / cfg.ts;
                th = ip.position();
                ip.tick_guarded(&sat, &th, &w).unwrap().0
            } else {
                ip.tick().unwrap()
            };
            assert!(t.feed.is_finite() && t.pos.iter().all(|x| x.is_finite()));
            k += 1;
            assert!(k < 2_000_000, "case {case} does not finish");
        }
        assert_eq!(ip.position(), end);
    }
}

#[test]
fn arc_length_is_exact_on_circle_and_line() {
    let c = circle();
    let ip = Interpolator::new(c.clone(), InterpConfig::default()).unwrap();
    let exact = 2.0 * core::f64::consts::PI * 10_000.0;
    println!("circle length {:.9} vs 2πR {:.9}", ip.length(), exact);
    assert!((ip.length() - exact).abs() < 1e-9 * exact);
    assert!((arc_length(&c, 0.0, 0.25) - exact / 4.0).abs() < 1e-9 * exact);
    assert_eq!(arc_length(&c, 0.5, 0.5), 0.0);
    assert_eq!(arc_length(&c, 0.6, 0.5), 0.0);
    assert_eq!(arc_length(&c, f64::NAN, 0.5), 0.0);
    let line = Nurbs::new(
        1,
        2,
        &[0.0, 0.0, 3.0, 4.0],
        &[1.0, 3.0],
        &[0.0, 0.0, 1.0, 1.0],
    )
    .unwrap();
    assert!((arc_length(&line, 0.0, 1.0) - 5.0).abs() < 1e-12);
}

#[test]
fn preset_units_and_loop_damping() {
    let p = die_bonder_preset();
    assert_eq!(p.ts, 1e-3);
    let zeta: Vec<f64> = p
        .axes
        .iter()
        .map(|a| {
            let pl = a.plant;
            // closed loop in counts: s² + (1/τ + G kd/τ) s + G kp/τ
            let g = pl.counts_gain();
            let wn = (g * a.gains.kp / pl.tau).sqrt();
            (1.0 / pl.tau + g * a.gains.kd / pl.tau) / (2.0 * wn)
        })
        .collect();
    println!("loop damping X {:.3}, Y {:.3}", zeta[0], zeta[1]);
    assert!((zeta[1] - 0.714).abs() < 0.01);
    assert!((zeta[0] - 0.294).abs() < 0.01);
    // kv·(K_c K_e) = 1: the speed feed-forward alone holds a constant speed
    for a in &p.axes {
        assert!((a.gains.kv * a.plant.counts_gain() - 1.0).abs() < 1e-12);
    }
}

// ----------------------------------------------------------------------------------
// Closed loop: die-bonder path with two sharp corners (like Yeh Fig 5)
// ----------------------------------------------------------------------------------

/// Distance from q to the curve, searched near parameter u_ref.
fn contour_error(curve: &Nurbs, q: &Point, u_ref: f64) -> f64 {
    let (a, b) = curve.domain();
    let lo = (u_ref - 0.04).max(a);
    let hi = (u_ref + 0.01).min(b);
    let mut best = (f64::INFINITY, u_ref);
    for i in 0..=400 {
        let u = lo + (hi - lo) * i as f64 / 400.0;
        let d = (curve.point(u).unwrap() - q).norm();
        if d < best.0 {
            best = (d, u);
        }
    }
    let mut u = best.1;
    for _ in 0..8 {
        let (c, d1, d2) = curve.eval_clamped(u);
        let r = c - q;
        let g = r.dot(&d1);
        let gp = d1.norm_squared() + r.dot(&d2);
        if gp <= 0.0 {
            break;
        }
        u = (u - g / gp).clamp(lo, hi);
    }
    best.0.min((curve.point(u).unwrap() - q).norm())
}

#[derive(Clone, Copy, PartialEq, Debug)]
enum Mode {
    /// Planner + chord-error look-ahead, no saturation awareness.
    Plain,
    /// Same, but the plant input is clipped to ±Umax (a real saturating drive).
    PlainClipped,
    /// Yeh's per-tick guard (§3.4) on the plain planner, no actuator look-ahead.
    GuardOnly,
    /// Actuator-aware look-ahead profile + Yeh's per-tick guard.
    Aware,
}

#[derive(Debug)]
struct SimResult {
    max_u: [f64; 2],
    ticks_over: usize,
    contour: f64,
    follow: [f64; 2],
    motion_ticks: usize,
    limited: usize,
    raised: usize,
    infeasible: usize,
    max_pred_err: f64,
    end_err: f64,
}

/// Closed loop at Ts = 1 ms: plant of eq 2.2 (exact ZOH), PD+ of eq 2.12 per axis, encoder
/// read -> interpolation -> control law -> drive output in every tick. With `predicted`,
/// the interpolator gets θ_a\[k\], w_a\[k\] from the plant model's one-tick-ahead prediction
/// made at tick k-1 (AxisSample::predicted) instead of the encoder.
fn simulate(mode: Mode, predicted: bool) -> SimResult {
    let preset = die_bonder_preset();
    let ts = preset.ts;
    let sat = SaturationAwareFeed::new(&preset.axes, ts).unwrap();
    let curve = die_bonder_path();
    let cfg = InterpConfig {
        ts,
        feed: 400_000.0, // 0.4 m/s at 1 µm/count
        accel: 4e7,      // ≈ 4 g: more than the X drive can give (Umax/ka ≈ 1.29e7)
        jerk: 4e10,
        chord_tol: 1.0,
        max_corrections: 3,
    };
    let mut ip = match mode {
        Mode::Aware => Interpolator::with_actuator_limits(curve.clone(), cfg, &sat, 0.8).unwrap(),
        _ => Interpolator::new(curve.clone(), cfg).unwrap(),
    };
    let start = curve.point(0.0).unwrap();
    let end = curve.point(1.0).unwrap();
    let mut th = [start[0], start[1]];
    let mut vel = [0.0f64; 2];
    let (mut th_prev, mut vel_prev) = (th, vel);
    let mut pd: Vec<PdPlus> = preset
        .axes
        .iter()
        .map(|a| PdPlus::new(a.gains, ts).unwrap())
        .collect();
    for (j, c) in pd.iter_mut().enumerate() {
        c.reset(th[j]);
    }
    let mut u_prev = [0.0f64; 2];
    let mut r = SimResult {
        max_u: [0.0; 2],
        ticks_over: 0,
        contour: 0.0,
        follow: [0.0; 2],
        motion_ticks: 0,
        limited: 0,
        raised: 0,
        infeasible: 0,
        max_pred_err: 0.0,
        end_err: 0.0,
    };
    let mut after = 0;
    let mut k = 0;
    while after < 300 {
        k += 1;
        assert!(k < 100_000);
        let (theta_a, w_a) = if predicted && k > 1 {
            let mut t = Point::zeros();
            let mut w = Point::zeros();
            for j in 0..2 {
                let a = &preset.axes[j];
                let st = AxisSample::predicted(
                    &a.plant,
                    ts,
                    th_prev[j],
                    vel_prev[j],
                    u_prev[j],
                    0.0,
                    0.0,
                );
                t[j] = st.theta_a;
                w[j] = st.w_a;
            }
            (t, w)
        } else {
            (
                pt(&[th[0], th[1]]),
                pt(&[(th[0] - th_prev[0]) / ts, (th[1] - th_prev[1]) / ts]),
            )
        };
        let (t, dec) = match mode {
            Mode::Plain | Mode::PlainClipped => (ip.tick().unwrap(), None),
            Mode::GuardOnly | Mode::Aware => {
                let (t, d) = ip.tick_guarded(&sat, &theta_a, &w_a).unwrap();
                (t, Some(d))
            }
        };
        let mut ratio = 0.0f64;
        for j in 0..2 {
            let u = pd[j].update(t.pos[j], t.vel[j], t.acc[j], th[j]);
            r.max_u[j] = r.max_u[j].max(u.abs());
            ratio = ratio.max(u.abs() / preset.axes[j].umax);
            u_prev[j] = u;
            r.follow[j] = r.follow[j].max((t.pos[j] - th[j]).abs());
        }
        if let Some(d) = dec {
            r.max_pred_err = r.max_pred_err.max((d.max_drive_ratio - ratio).abs());
            r.infeasible += usize::from(!d.feasible);
            r.limited += usize::from(d.limited);
            r.raised += usize::from(d.raised);
        }
        r.ticks_over += usize::from(ratio > 1.0);
        r.contour = r
            .contour
            .max(contour_error(&curve, &pt(&[th[0], th[1]]), t.u));
        th_prev = th;
        vel_prev = vel;
        for j in 0..2 {
            let um = preset.axes[j].umax;
            let u = if mode == Mode::PlainClipped {
                u_prev[j].clamp(-um, um)
            } else {
                u_prev[j] // NOT clipped: |u| is what the loop asked for
            };
            (th[j], vel[j]) = preset.axes[j].plant.step(ts, th[j], vel[j], u);
        }
        if t.done {
            after += 1;
        } else {
            r.motion_ticks += 1;
        }
    }
    r.end_err = ((th[0] - end[0]).powi(2) + (th[1] - end[1]).powi(2)).sqrt();
    r
}

#[test]
fn die_bonder_closed_loop_saturation() {
    let runs = [
        ("without (unclipped plant)", simulate(Mode::Plain, false)),
        (
            "without, drive clipped at Umax",
            simulate(Mode::PlainClipped, false),
        ),
        ("Yeh per-tick guard only", simulate(Mode::GuardOnly, false)),
        ("with (look-ahead + guard)", simulate(Mode::Aware, false)),
        ("with, model-predicted state", simulate(Mode::Aware, true)),
    ];
    for (name, r) in &runs {
        println!(
            "{name}: max|u| X {:.3} Y {:.3} DU (Umax 1), ticks over Umax {}, guard limited/raised/infeasible \
             {}/{}/{}, max contour error {:.2} counts, max following error X {:.1} Y {:.1} counts, \
             motion {:.3} s, |predicted-actual| |u|/Umax {:.1e}, final error {:.3} counts",
            r.max_u[0],
            r.max_u[1],
            r.ticks_over,
            r.limited,
            r.raised,
            r.infeasible,
            r.contour,
            r.follow[0],
            r.follow[1],
            r.motion_ticks as f64 * 1e-3,
            r.max_pred_err,
            r.end_err
        );
    }
    let plain = &runs[0].1;
    let aware = &runs[3].1;
    let aware_pred = &runs[4].1;
    assert!(
        plain.max_u[0] > 1.0 && plain.ticks_over > 0,
        "without: |u| must exceed Umax"
    );
    assert!(
        aware.max_u[0] <= 1.0 && aware.max_u[1] <= 1.0,
        "with: |u| ≤ Umax"
    );
    assert_eq!(aware.ticks_over, 0);
    assert_eq!(aware.infeasible, 0);
    assert!(aware.limited > 0, "the guard must have had work to do");
    assert!(
        aware.max_pred_err < 1e-9,
        "eq 3.5 prediction is exact for PD+"
    );
    assert!(aware.contour < 25.0, "contour error {}", aware.contour);
    assert!(aware.end_err < 1e-3);
    // one-tick-ahead ordering with the model's prediction gives the same run
    assert!((aware_pred.max_u[0] - aware.max_u[0]).abs() < 1e-9);
    assert!((aware_pred.contour - aware.contour).abs() < 1e-6);
    assert_eq!(aware_pred.ticks_over, 0);
}
