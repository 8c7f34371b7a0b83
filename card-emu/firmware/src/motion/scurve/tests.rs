use super::*;

use crate::testkit::rng::Rng;

fn random_limits(rng: &mut Rng) -> Limits {
    let vmax = rng.log_uniform(1e-2, 1e5);
    let amax = rng.log_uniform(1e-1, 1e6);
    let dmax = if rng.chance(0.25) {
        amax
    } else {
        rng.log_uniform(1e-1, 1e6)
    };
    if rng.chance(0.25) {
        let j = rng.log_uniform(1.0, 1e9);
        Limits {
            vmax,
            amax,
            dmax,
            j1: j,
            j3: j,
            j5: j,
            j7: j,
        }
    } else {
        Limits {
            vmax,
            amax,
            dmax,
            j1: rng.log_uniform(1.0, 1e9),
            j3: rng.log_uniform(1.0, 1e9),
            j5: rng.log_uniform(1.0, 1e9),
            j7: rng.log_uniform(1.0, 1e9),
        }
    }
}

// ---------------------------------------------------------------------------------------
// Independent reference model (written separately from the planner's formulas).
//
// A ramp of speed change dv has acceleration magnitude a(t) = min(ja t, ap, jb (T - t)),
// and the distance it contributes beyond the start speed is  ∫_0^T (T - t) a(t) dt,
// evaluated with Simpson's rule on each of the three pieces (exact: the integrand is a
// quadratic on each piece).
// ---------------------------------------------------------------------------------------

/// Returns (T, peak, ∫_0^T (T - t) a(t) dt).
fn ref_ramp(dv: f64, amax: f64, ja: f64, jb: f64) -> (f64, f64, f64) {
    if dv <= 0.0 {
        return (0.0, 0.0, 0.0);
    }
    let h = 0.5 / ja + 0.5 / jb;
    let ap = if dv >= amax * amax * h {
        amax
    } else {
        dv.sqrt() / h.sqrt()
    };
    let plateau = ((dv - ap * ap * h) / ap).max(0.0);
    let (ta, tb) = (ap / ja, ap / jb);
    let total = ta + plateau + tb;
    let g = |t: f64| (total - t) * (ja * t).min(ap).min(jb * (total - t)).max(0.0);
    let simpson = |p: f64, q: f64| (q - p) / 6.0 * (g(p) + 4.0 * g(0.5 * (p + q)) + g(q));
    let m = simpson(0.0, ta) + simpson(ta, ta + plateau) + simpson(ta + plateau, total);
    (total, ap, m)
}

/// (time without cruise, distance) for peak speed vp.
fn ref_dist(v0: f64, v1: f64, vp: f64, l: &Limits) -> (f64, f64) {
    let (ta, _, ma) = ref_ramp(vp - v0, l.amax, l.j1, l.j3);
    // deceleration magnitude d(t) = min(j5 t, dp, j7 (T - t)); v = vp - ∫ d
    let (td, _, md) = ref_ramp(vp - v1, l.dmax, l.j5, l.j7);
    (ta + td, v0 * ta + ma + vp * td - md)
}

/// Minimum time by bisection on vp (to f64 convergence).  None if infeasible.
fn ref_min_time(v0: f64, v1: f64, dist: f64, l: &Limits) -> Option<(f64, f64)> {
    let vlo = v0.max(v1);
    if ref_dist(v0, v1, vlo, l).1 > dist {
        return None;
    }
    let vp = if ref_dist(v0, v1, l.vmax, l).1 <= dist {
        l.vmax
    } else {
        let (mut lo, mut hi) = (vlo, l.vmax);
        for _ in 0..3000 {
            let mid = 0.5 * (lo + hi);
            if !(mid > lo && mid < hi) {
                break;
            }
            if ref_dist(v0, v1, mid, l).1 <= dist {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        lo
    };
    let (t, s) = ref_dist(v0, v1, vp, l);
    let cruise = if vp > 0.0 {
        (dist - s).max(0.0) / vp
    } else {
        0.0
    };
    Some((t + cruise, vp))
}

/// Distance drawn so that every regime (triangular / saturated on each side, with and
/// without cruise, tiny, huge) is exercised.
fn random_distance(rng: &mut Rng, v0: f64, v1: f64, l: &Limits) -> f64 {
    let vlo = v0.max(v1);
    let mag = match rng.next_u64() % 8 {
        0 => rng.log_uniform(1e-9, 1e-3),
        1 => rng.log_uniform(1.0, 1e12),
        2 => ref_dist(v0, v1, l.vmax, l).1 * rng.log_uniform(1.0, 1e3),
        _ => {
            let lo = (l.vmax * 1e-7).max(vlo);
            let vp = if lo < l.vmax {
                rng.log_uniform(lo, l.vmax)
            } else {
                l.vmax
            };
            ref_dist(v0, v1, vp, l).1
        }
    };
    rng.sign() * mag
}

fn segment_of(p: &Profile, t: f64) -> usize {
    (0..7).find(|&i| t < p.t0[i + 1]).unwrap_or(7)
}

/// Worst values seen by a check.
#[derive(Default, Clone, Copy, Debug)]
struct Worst {
    limit_excess: f64,
    end_pos_err: f64,
    continuity_err: f64,
}

impl Worst {
    fn merge(&mut self, o: Worst) {
        self.limit_excess = self.limit_excess.max(o.limit_excess);
        self.end_pos_err = self.end_pos_err.max(o.end_pos_err);
        self.continuity_err = self.continuity_err.max(o.continuity_err);
    }
}

/// Test-side exact cubic extrapolation of a state by tau.
fn extrapolate(s: State, tau: f64) -> State {
    State {
        pos: s.pos + s.vel * tau + 0.5 * s.acc * tau * tau + s.jerk * tau * tau * tau / 6.0,
        vel: s.vel + s.acc * tau + 0.5 * s.jerk * tau * tau,
        acc: s.acc + s.jerk * tau,
        jerk: s.jerk,
    }
}

/// Continuity of position, velocity and acceleration across all segment boundaries,
/// checked in the motion frame (relative to p0, so no world-coordinate rounding) with a
/// test-side extrapolation.  The last non-empty segment must land on `end`
/// (frame position, if given, and velocity; acceleration 0).
/// Returns (worst relative error, relative end position error).
fn check_continuity(p: &Profile, end: (Option<f64>, f64), scales: (f64, f64, f64)) -> (f64, f64) {
    let (pos_scale, vel_scale, acc_scale) = scales;
    let mut worst: f64 = 0.0;
    let mut end_err: f64 = 0.0;
    for i in 0..7 {
        let d = p.dur[i];
        if d <= 0.0 {
            continue;
        }
        let start = State {
            pos: p.x[i],
            vel: p.v[i],
            acc: p.a[i],
            jerk: p.jerk[i],
        };
        let left = extrapolate(start, d);
        // Decide "last" by index, not by time: a segment much shorter than ulp(total)
        // can vanish from the time axis but still exists in the state chain.
        let last = p.dur[i + 1..].iter().all(|&t| t <= 0.0);
        let right = if last {
            (end.0.unwrap_or(left.pos), end.1, 0.0)
        } else {
            (p.x[i + 1], p.v[i + 1], p.a[i + 1])
        };
        let ep = (left.pos - right.0).abs() / pos_scale;
        // (velocities and accelerations below the normal range count as 0)
        let beyond = |e: f64| (e - f64::MIN_POSITIVE).max(0.0);
        let ev = beyond((left.vel - right.1).abs()) / vel_scale;
        let ea = beyond((left.acc - right.2).abs()) / acc_scale;
        assert!(
            ep <= 1e-9 && ev <= 1e-9 && ea <= 1e-9,
            "discontinuity at boundary {i}: {ep:e} {ev:e} {ea:e} {p:?}"
        );
        worst = worst.max(ep).max(ev).max(ea);
        if last {
            end_err = end_err.max(ep);
        }
    }
    (worst, end_err)
}

fn check_plan(p: &Profile, l: &Limits, p0: f64, d: f64, v0: f64, v1: f64) -> Worst {
    let tol = 1e-9;
    let dir = if d < 0.0 { -1.0 } else { 1.0 };
    let jlim = [l.j1, 0.0, l.j3, 0.0, l.j5, 0.0, l.j7, 0.0];
    let total = p.duration();
    assert!(total.is_finite() && total >= 0.0);
    assert!(p.phases().iter().all(|&t| t >= 0.0), "{:?}", p.phases());
    let mut w = Worst::default();
    let mut visit = |t: f64| {
        let s = p.sample(t);
        let seg = segment_of(p, t.max(0.0));
        let (v, a) = (dir * s.vel, dir * s.acc);
        assert!(v >= -tol * l.vmax, "velocity reversal {v} at {t}");
        let ej = if jlim[seg] == 0.0 {
            assert_eq!(s.jerk, 0.0, "jerk in zero-jerk segment {seg}");
            0.0
        } else {
            s.jerk.abs() / jlim[seg] - 1.0
        };
        let ex = (v.abs() / l.vmax - 1.0)
            .max(a / l.amax - 1.0)
            .max(-a / l.dmax - 1.0)
            .max(ej);
        assert!(
            ex <= tol,
            "limit exceeded by {ex:e} at t={t} seg={seg} {s:?} {l:?} d={d}"
        );
        w.limit_excess = w.limit_excess.max(ex);
    };
    for k in 0..=2000 {
        visit(total * k as f64 / 2000.0);
    }
    for i in 0..8 {
        visit(p.t0[i]);
        visit(p.t0[i] * (1.0 - 1e-13));
    }
    visit(total * 2.0 + 1.0);
    // start / end states (a zero-duration plan only has its end, no farther than the
    // position tolerance of the plan check from its start)
    let s = p.sample(0.0);
    if total > 0.0 {
        assert_eq!(s.pos, p0);
        assert!((s.vel - dir * v0).abs() <= 1e-12 * l.vmax);
    } else {
        assert!(d.abs() <= 8.0 * f64::EPSILON * p0.abs() + 1e-12 || v0 == v1 && d == 0.0);
    }
    let e = p.sample(total);
    assert_eq!(e, p.sample(total + 1.0));
    assert_eq!(e.pos, p0 + d);
    assert_eq!(e.vel, dir * v1);
    assert_eq!((e.acc, e.jerk), (0.0, 0.0));
    assert_eq!(p.end_pos(), p0 + d);
    // continuity, including the integrated end (left limit) vs the exact target
    let pos_scale = d.abs().max(1.0e-9);
    let scales = (pos_scale, l.vmax, l.amax.max(l.dmax));
    let (c, end_err) = check_continuity(p, (Some(d.abs()), v1), scales);
    w.continuity_err = c;
    w.end_pos_err = end_err;
    w
}

#[test]
fn hand_computed_cases() {
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * b.abs().max(1e-3);
    // vmax=1000, amax=1e4, j=1e6, d=1e4:
    //   amax^2/j = 100 <= 1000 -> amax reached; T1 = T3 = amax/j = 0.01,
    //   T2 = (1000 - 100)/1e4 = 0.09; accel distance = vmax/2 * 0.11 = 55 each side,
    //   cruise = (1e4 - 110)/1000 = 9.89; total 10.11.
    let l = Limits::symmetric(1000.0, 1e4, 1e6);
    let p = Profile::plan(5.0, 1e4, 0.0, 0.0, &l).unwrap();
    let want = [0.01, 0.09, 0.01, 9.89, 0.01, 0.09, 0.01];
    for (g, w) in p.phases().iter().zip(want) {
        assert!(close(*g, w), "{:?}", p.phases());
    }
    assert!(close(p.duration(), 10.11));
    assert!(close(p.peak_velocity(), 1000.0));
    assert!(close(p.peak_acceleration(), 1e4) && close(p.peak_deceleration(), 1e4));
    assert_eq!(p.end_pos(), 1e4 + 5.0);

    // Same limits, d = 100 (no cruise, amax reached): each side covers
    // vp/2 (vp/amax + amax/j), so vp^2/1e4 + 0.01 vp = 100 ->
    // vp = (-100 + sqrt(4.01e6))/2 = 951.249219725...; T = 2 (0.02 + (vp - 100)/1e4).
    let vp = (-100.0 + 4.01e6f64.sqrt()) / 2.0;
    let p = Profile::plan(0.0, 100.0, 0.0, 0.0, &l).unwrap();
    assert!(close(p.peak_velocity(), vp));
    assert!(close(p.duration(), 2.0 * (0.02 + (vp - 100.0) / 1e4)));
    assert!(p.phases()[3] < 1e-12);

    // d = 1 (triangular acceleration): 2 a_p^3 / j^2 = d -> a_p = cbrt(j^2 d / 2) = 7937.005...,
    // T = 4 a_p / j = 4 cbrt(d/(2j)) = 0.0317480210..., vp = a_p^2 / j.
    let ap = (1e12f64 / 2.0).cbrt();
    let p = Profile::plan(0.0, -1.0, 0.0, 0.0, &l).unwrap();
    assert!(close(p.duration(), 4.0 * (1.0f64 / 2e6).cbrt()));
    assert!(close(p.peak_acceleration(), ap));
    assert!(close(p.peak_velocity(), ap * ap / 1e6));
    assert_eq!(p.end_pos(), -1.0);

    // Asymmetric: dmax = 5e3: T5 = T7 = 0.005, T6 = (1000 - 25)/5e3 = 0.195,
    // decel distance = 500 * 0.205 = 102.5, cruise = (1e4 - 55 - 102.5)/1000 = 9.8425.
    let la = Limits { dmax: 5e3, ..l };
    let p = Profile::plan(0.0, 1e4, 0.0, 0.0, &la).unwrap();
    let want = [0.01, 0.09, 0.01, 9.8425, 0.005, 0.195, 0.005];
    for (g, w) in p.phases().iter().zip(want) {
        assert!(close(*g, w), "{:?}", p.phases());
    }

    // Non-zero v0 = 100: accel ramp 100 -> 1000 has T1 = T3 = 0.01, T2 = (900 - 100)/1e4 = 0.08,
    // distance (100 + 1000)/2 * 0.1 = 55 (symmetric jerks); decel 55; cruise 9.89.
    let p = Profile::plan(0.0, 1e4, 100.0, 0.0, &l).unwrap();
    assert!(close(p.phases()[1], 0.08));
    assert!(close(p.phases()[3], (1e4 - 55.0 - 55.0) / 1000.0));

    // stop from 1000 counts/s, a = 0: T5 = T7 = 0.01, T6 = 0.09, distance 55.
    let s = Profile::stop(1.0, -1000.0, 0.0, &l).unwrap();
    let want = [0.0, 0.0, 0.0, 0.0, 0.01, 0.09, 0.01];
    for (g, w) in s.phases().iter().zip(want) {
        assert!(close(*g, w), "{:?}", s.phases());
    }
    assert!(close(s.end_pos(), 1.0 - 55.0));

    // stop from v = 100, a = +5000: T3 = 0.005, v -> 100 + 12.5 = 112.5;
    // then T5 = T7 = 0.01, T6 = (112.5 - 100)/1e4 = 0.00125.
    let s = Profile::stop(0.0, 100.0, 5000.0, &l).unwrap();
    let want = [0.0, 0.0, 0.005, 0.0, 0.01, 0.00125, 0.01];
    for (g, w) in s.phases().iter().zip(want) {
        assert!(close(*g, w), "{:?}", s.phases());
    }

    // stop from v = 1000, a = -2e4 (|a| > dmax): +j7 for 0.01 s (dv = (4e8-1e8)/2e6 = 150),
    // v = 850; hold (850 - 50)/1e4 = 0.08; ramp-out 0.01.
    let s = Profile::stop(0.0, 1000.0, -2e4, &l).unwrap();
    let want = [0.0, 0.0, 0.0, 0.0, 0.01, 0.08, 0.01];
    for (g, w) in s.phases().iter().zip(want) {
        assert!(close(*g, w), "{:?}", s.phases());
    }
    assert!(s.sample(0.005).jerk > 0.0);
}

#[test]
fn limits_end_and_continuity_random() {
    let mut rng = Rng::new(0x5eed_0001);
    let mut worst = Worst::default();
    let mut n = 0;
    let mut regimes = [0usize; 4]; // [amax reached, dmax reached, cruise, neither]
    for _ in 0..1500 {
        let l = random_limits(&mut rng);
        let (v0, v1) = if rng.chance(0.6) {
            (0.0, 0.0)
        } else {
            (
                rng.uniform(0.0, l.vmax) * f64::from(u8::from(rng.chance(0.7))),
                rng.uniform(0.0, l.vmax) * f64::from(u8::from(rng.chance(0.7))),
            )
        };
        let d = random_distance(&mut rng, v0, v1, &l);
        let p0 = rng.uniform(-1e3, 1e3);
        match Profile::plan(p0, d, v0, v1, &l) {
            Ok(p) => {
                worst.merge(check_plan(&p, &l, p0, d, v0, v1));
                n += 1;
                let ph = p.phases();
                regimes[0] += usize::from(ph[1] > 0.0);
                regimes[1] += usize::from(ph[5] > 0.0);
                regimes[2] += usize::from(ph[3] > 1e-9 * p.duration());
                regimes[3] += usize::from(ph[1] == 0.0 && ph[5] == 0.0);
            }
            Err(e) => {
                assert_eq!(e, PlanError::Infeasible);
                assert!(ref_dist(v0, v1, v0.max(v1), &l).1 > d.abs() * (1.0 - 1e-9));
            }
        }
    }
    eprintln!("limits: {n} feasible plans, regimes {regimes:?}, worst {worst:?}");
    assert!(n >= 1000);
    assert!(regimes.iter().all(|&r| r >= 100), "{regimes:?}");
}

#[test]
fn time_optimal_vs_independent_bisection() {
    let mut rng = Rng::new(0x0071_3e57);
    let mut worst_rel: f64 = 0.0;
    let mut worst_vp: f64 = 0.0;
    let (mut n, mut infeasible) = (0, 0);
    for case in 0..2000 {
        let l = random_limits(&mut rng);
        let (v0, v1) = if case % 2 == 0 {
            (0.0, 0.0)
        } else {
            (rng.uniform(0.0, l.vmax), rng.uniform(0.0, l.vmax))
        };
        let d = random_distance(&mut rng, v0, v1, &l) * if case % 7 == 0 { 0.5 } else { 1.0 };
        let dist = d.abs();
        let min_dist = ref_dist(v0, v1, v0.max(v1), &l).1;
        let res = Profile::plan(0.0, d, v0, v1, &l);
        match ref_min_time(v0, v1, dist, &l) {
            None => {
                if min_dist > dist * (1.0 + 1e-9) {
                    assert_eq!(res, Err(PlanError::Infeasible));
                    infeasible += 1;
                }
            }
            Some((t_ref, vp_ref)) => {
                let p = res.unwrap_or_else(|e| panic!("{e:?} for feasible {l:?} {d} {v0} {v1}"));
                let rel = (p.duration() - t_ref).abs() / t_ref.max(1e-300);
                assert!(
                    (p.duration() - t_ref).abs() <= 1e-9 * t_ref + 1e-15,
                    "duration {} vs reference {t_ref} ({rel:e}) {l:?} d={d} v0={v0} v1={v1}",
                    p.duration()
                );
                let evp = (p.peak_velocity() - vp_ref).abs() / l.vmax;
                assert!(evp <= 1e-9, "vp {} vs {vp_ref}", p.peak_velocity());
                worst_rel = worst_rel.max(rel);
                worst_vp = worst_vp.max(evp);
                n += 1;
            }
        }
    }
    eprintln!(
        "optimality: {n} feasible cases, {infeasible} infeasible; worst rel duration \
         mismatch {worst_rel:e}, worst vp mismatch/vmax {worst_vp:e}"
    );
    assert!(n >= 1000 && infeasible >= 50);
}

#[test]
fn derivatives_consistent() {
    // Central differences of the closed-form samples must reproduce vel/acc/jerk
    // (pos is cubic: (x(t+h) - x(t-h)) / 2h = v + j h^2/6 exactly; v quadratic; a linear).
    let mut rng = Rng::new(77);
    for _ in 0..300 {
        let l = random_limits(&mut rng);
        let d = random_distance(&mut rng, 0.0, 0.0, &l);
        let p = Profile::plan(0.0, d, 0.0, 0.0, &l).unwrap();
        for i in 0..7 {
            let dur = p.phases()[i];
            if dur <= p.duration() * 1e-6 {
                continue;
            }
            let t = p.t0[i] + dur * rng.uniform(0.3, 0.7);
            let h = dur * 0.1;
            let (a, b, c) = (p.sample(t - h), p.sample(t), p.sample(t + h));
            let x_scale = d.abs() / h;
            let dv = (c.pos - a.pos) / (2.0 * h) - b.vel - b.jerk * h * h / 6.0;
            assert!(
                dv.abs() <= 1e-9 * x_scale,
                "pos/vel mismatch {dv:e} in seg {i}"
            );
            let da = (c.vel - a.vel) / (2.0 * h) - b.acc;
            assert!(da.abs() <= 1e-9 * l.vmax / h, "vel/acc mismatch {da:e}");
            let dj = (c.acc - a.acc) / (2.0 * h) - b.jerk;
            assert!(
                dj.abs() <= 1e-9 * l.amax.max(l.dmax) / h,
                "acc/jerk mismatch"
            );
        }
    }
}

#[test]
fn degenerate_distances() {
    let l = Limits {
        vmax: 3000.0,
        amax: 2e5,
        dmax: 5e4,
        j1: 1e8,
        j3: 3e7,
        j5: 2e6,
        j7: 9e8,
    };
    // d = 0: zero-duration, at rest
    let p = Profile::plan(12.0, 0.0, 0.0, 0.0, &l).unwrap();
    assert_eq!(p.duration(), 0.0);
    assert_eq!(p.phases(), [0.0; 7]);
    let rest = State {
        pos: 12.0,
        vel: 0.0,
        acc: 0.0,
        jerk: 0.0,
    };
    assert_eq!(p.sample(0.0), rest);
    assert_eq!(p.sample(1.0), rest);
    assert_eq!(p.sample(f64::NAN), rest);
    // tiny / huge / mirrored
    for d in [1e-9, -1e-9, 1e-6, 1e12, -1e12, 0.37] {
        let p = Profile::plan(-4.0, d, 0.0, 0.0, &l).unwrap();
        check_plan(&p, &l, -4.0, d, 0.0, 0.0);
        let (t, _) = ref_min_time(0.0, 0.0, d.abs(), &l).unwrap();
        assert!((p.duration() - t).abs() <= 1e-9 * t, "{d}");
        let (p, q) = (
            Profile::plan(0.0, d, 0.0, 0.0, &l).unwrap(),
            Profile::plan(0.0, -d, 0.0, 0.0, &l).unwrap(),
        );
        assert_eq!(p.phases(), q.phases());
        for k in 0..=50 {
            let t = p.duration() * k as f64 / 50.0;
            let (a, b) = (p.sample(t), q.sample(t));
            assert_eq!(a.pos, -b.pos);
            assert_eq!((a.vel, a.acc, a.jerk), (-b.vel, -b.acc, -b.jerk));
        }
    }
    // pure cruise at vmax
    let p = Profile::plan(0.0, 30.0, 3000.0, 3000.0, &l).unwrap();
    assert_eq!(p.phases()[3], 0.01);
    assert_eq!(p.duration(), 0.01);
    // v0 = v1 > 0 and d = 0: zero duration moving state
    let p = Profile::plan(1.0, 0.0, 5.0, 5.0, &l).unwrap();
    assert_eq!(p.duration(), 0.0);
    assert_eq!(p.sample(3.0).vel, 5.0);
}

#[test]
fn nonzero_boundary_velocities() {
    let mut rng = Rng::new(0xbeef);
    let (mut ok, mut bad) = (0, 0);
    for _ in 0..2000 {
        let l = random_limits(&mut rng);
        let v0 = rng.uniform(0.0, l.vmax);
        let v1 = rng.uniform(0.0, l.vmax);
        let need = ref_dist(v0, v1, v0.max(v1), &l).1;
        let dist = need * rng.log_uniform(0.01, 100.0);
        let d = rng.sign() * dist;
        let r = Profile::plan(3.0, d, v0, v1, &l);
        if dist >= need * (1.0 + 1e-9) {
            let p = r.unwrap();
            check_plan(&p, &l, 3.0, d, v0, v1);
            let dir = d.signum();
            assert_eq!(p.sample(p.duration()).vel, dir * v1);
            // the integrated velocity at the end (left limit) also matches v1
            let last = (0..7).rev().find(|&i| p.phases()[i] > 0.0).unwrap();
            let left = extrapolate(p.sample(p.t0[last]), p.phases()[last]);
            assert!((left.vel - dir * v1).abs() <= 1e-9 * l.vmax);
            assert!((left.pos - (3.0 + d)).abs() <= 1e-9 * dist + 1e-14);
            ok += 1;
        } else if dist <= need * (1.0 - 1e-9) {
            assert_eq!(r, Err(PlanError::Infeasible), "{l:?} {d} {v0} {v1}");
            bad += 1;
        }
    }
    assert!(ok >= 500 && bad >= 500, "{ok} {bad}");
    let l = Limits::symmetric(100.0, 1000.0, 1e5);
    assert_eq!(
        Profile::plan(0.0, 1e-3, 100.0, 0.0, &l),
        Err(PlanError::Infeasible)
    );
    assert_eq!(
        Profile::plan(0.0, 1e-3, 0.0, 100.0, &l),
        Err(PlanError::Infeasible)
    );
}

#[test]
fn input_errors() {
    let l = Limits::symmetric(100.0, 1000.0, 1e5);
    let nan = f64::NAN;
    let inf = f64::INFINITY;
    for (p0, d, v0, v1) in [
        (nan, 1.0, 0.0, 0.0),
        (0.0, nan, 0.0, 0.0),
        (0.0, 1.0, nan, 0.0),
        (0.0, 1.0, 0.0, nan),
        (inf, 1.0, 0.0, 0.0),
        (0.0, -inf, 0.0, 0.0),
        (0.0, 1.0, inf, 0.0),
    ] {
        assert_eq!(Profile::plan(p0, d, v0, v1, &l), Err(PlanError::NonFinite));
    }
    for (p0, v0, a0) in [(nan, 0.0, 0.0), (0.0, inf, 0.0), (0.0, 1.0, nan)] {
        assert_eq!(Profile::stop(p0, v0, a0, &l), Err(PlanError::NonFinite));
    }
    let fields: [fn(&mut Limits) -> &mut f64; 7] = [
        |l| &mut l.vmax,
        |l| &mut l.amax,
        |l| &mut l.dmax,
        |l| &mut l.j1,
        |l| &mut l.j3,
        |l| &mut l.j5,
        |l| &mut l.j7,
    ];
    for f in fields {
        for (bad, err) in [
            (nan, PlanError::NonFinite),
            (inf, PlanError::NonFinite),
            (0.0, PlanError::NonPositiveLimit),
            (-1.0, PlanError::NonPositiveLimit),
        ] {
            let mut lb = l;
            *f(&mut lb) = bad;
            assert_eq!(lb.validate(), Err(err));
            assert_eq!(Profile::plan(0.0, 1.0, 0.0, 0.0, &lb), Err(err));
            assert_eq!(Profile::stop(0.0, 1.0, 0.0, &lb), Err(err));
        }
    }
    assert_eq!(l.validate(), Ok(()));
    assert_eq!(
        Profile::plan(0.0, 1.0, 100.0001, 0.0, &l),
        Err(PlanError::StartVelocityTooHigh)
    );
    assert_eq!(
        Profile::plan(0.0, 1e6, 0.0, 100.0001, &l),
        Err(PlanError::Infeasible)
    );
    assert_eq!(
        Profile::plan(0.0, 1e6, -1.0, 0.0, &l),
        Err(PlanError::Infeasible)
    );
}

fn check_stop(p: &Profile, l: &Limits, p0: f64, v0: f64, a0: f64) -> f64 {
    let tol = 1e-9;
    let dir = if v0 > 0.0 || (v0 == 0.0 && a0 >= 0.0) {
        1.0
    } else {
        -1.0
    };
    let a_start = dir * a0;
    let total = p.duration();
    let vscale = p.peak_velocity().max(v0.abs()).max(1e-300);
    let ascale = a0.abs().max(l.dmax);
    let mut worst: f64 = 0.0;
    let mut prev_dec = f64::INFINITY;
    let mut prev_acc = f64::INFINITY;
    let n = 2000;
    for k in 0..=n + 16 {
        let t = if k <= n {
            total * k as f64 / n as f64
        } else {
            p.t0[(k - n - 1) / 2] * if k % 2 == 0 { 1.0 } else { 1.0 - 1e-13 }
        };
        let s = p.sample(t);
        let seg = segment_of(p, t);
        let (v, a, j) = (dir * s.vel, dir * s.acc, dir * s.jerk);
        // (below the normal range there is no relative precision: as in the plan check)
        assert!(
            v >= -tol * vscale - f64::MIN_POSITIVE,
            "velocity sign change {v} ({s:?})"
        );
        let jl = match seg {
            2 => l.j3,
            4 if j > 0.0 => l.j7,
            4 => l.j5,
            6 => l.j7,
            _ => 0.0,
        };
        if jl == 0.0 {
            assert_eq!(j, 0.0, "unexpected jerk in slot {seg}");
        } else {
            let ej = j.abs() / jl - 1.0;
            assert!(ej <= tol, "jerk excess {ej:e}");
            worst = worst.max(ej);
        }
        let dec = -a;
        if dec > l.dmax * (1.0 + tol) {
            // still correcting an initial |a| > dmax: only allowed to shrink
            assert!(
                k > n || dec <= prev_dec * (1.0 + 1e-12),
                "decel grew above dmax"
            );
            assert!(dec <= -a_start * (1.0 + 1e-12) + 1e-12 * ascale);
        } else if !(seg == 4 && j > 0.0) {
            // (inside the correction segment the decel is legitimately still >= dmax)
            worst = worst.max(dec / l.dmax - 1.0);
        }
        if a > 0.0 {
            // (a ramp-out of a deceleration ends within rounding of 0, on either side)
            assert!(a <= a_start.max(0.0) * (1.0 + 1e-12) + 1e-12 * ascale);
            assert!(k > n || a <= prev_acc.max(0.0) * (1.0 + 1e-12) + 1e-12 * ascale);
        }
        if k <= n {
            prev_dec = dec;
            prev_acc = a;
        }
    }
    let e = p.sample(total);
    assert_eq!((e.vel, e.acc, e.jerk), (0.0, 0.0, 0.0));
    assert_eq!(e, p.sample(total * 3.0 + 1.0));
    let s = p.sample(0.0);
    assert_eq!((s.pos, s.vel), (p0, v0));
    // (a stop from rest with an acceleration below jerk x 5e-324 may take no time: its start
    // is its end)
    let jdt = [l.j3, l.j5, l.j7].iter().fold(0.0f64, |m, &j| m.max(j)) * 2e-323;
    assert!((s.acc - a0).abs() <= 1e-15 * a0.abs() + f64::MIN_POSITIVE + jdt);
    let pos_scale = p.x[6].abs().max(1e-12);
    check_continuity(p, (None, 0.0), (pos_scale, vscale, ascale));
    worst
}

#[test]
fn stop_random_states() {
    let mut rng = Rng::new(0x5709);
    let mut worst: f64 = 0.0;
    let mut counts = [0usize; 5]; // ok, infeasible, a>0, |a|>dmax, v0=0
    for _ in 0..3000 {
        let l = random_limits(&mut rng);
        let dir = rng.sign();
        let a_frame = match rng.next_u64() % 5 {
            0 => 0.0,
            1 => rng.uniform(0.0, 3.0) * l.amax,
            2 => -rng.uniform(0.0, 1.0) * l.dmax,
            _ => -rng.uniform(1.0, 4.0) * l.dmax,
        };
        let need = if a_frame < 0.0 {
            0.5 * a_frame * a_frame / l.j7
        } else {
            0.0
        };
        let v = match rng.next_u64() % 4 {
            0 => 0.0,
            1 => rng.log_uniform(1e-6, 1.0) * l.vmax,
            _ if need == 0.0 => rng.log_uniform(1e-6, 1.0) * l.vmax,
            _ => need * rng.log_uniform(0.3, 100.0),
        };
        let (v0, a0) = (dir * v, dir * a_frame);
        // At v0 = 0 the motion direction is that of a0, so the acceleration is "positive".
        let (a_frame, need) = if v == 0.0 {
            (a_frame.abs(), 0.0)
        } else {
            (a_frame, need)
        };
        let p0 = rng.uniform(-1e3, 1e3);
        match Profile::stop(p0, v0, a0, &l) {
            Ok(p) => {
                assert!(
                    v >= need * (1.0 - 1e-9),
                    "accepted a state that must reverse"
                );
                worst = worst.max(check_stop(&p, &l, p0, v0, a0));
                counts[0] += 1;
                counts[2] += usize::from(a_frame > 0.0 && v > 0.0);
                counts[3] += usize::from(-a_frame > l.dmax);
                counts[4] += usize::from(v == 0.0);
            }
            Err(e) => {
                assert_eq!(e, PlanError::Infeasible);
                assert!(v < need * (1.0 + 1e-9));
                counts[1] += 1;
            }
        }
    }
    eprintln!(
        "stop: counts [ok, infeasible, a>0, |a|>dmax, v0=0] = {counts:?}, worst excess {worst:e}"
    );
    assert!(counts.iter().all(|&c| c >= 100), "{counts:?}");
}

#[test]
fn garbage_inputs_never_panic() {
    let mut rng = Rng::new(0xdead);
    fn pick(rng: &mut Rng) -> f64 {
        match rng.next_u64() % 6 {
            0 => f64::from_bits(rng.next_u64()),
            1 => rng.log_uniform(1e-300, 1e300) * rng.sign(),
            2 => 0.0,
            3 => f64::MIN_POSITIVE * rng.unit(),
            _ => rng.log_uniform(1e-3, 1e6),
        }
    }
    for _ in 0..20000 {
        let l = Limits {
            vmax: pick(&mut rng),
            amax: pick(&mut rng),
            dmax: pick(&mut rng),
            j1: pick(&mut rng),
            j3: pick(&mut rng),
            j5: pick(&mut rng),
            j7: pick(&mut rng),
        };
        let (a, b, c, d) = (
            pick(&mut rng),
            pick(&mut rng),
            pick(&mut rng),
            pick(&mut rng),
        );
        for p in [Profile::plan(a, b, c, d, &l), Profile::stop(a, b, c, &l)]
            .into_iter()
            .flatten()
        {
            assert!(p.duration().is_finite());
            for k in 0..=8 {
                let _ = p.sample(p.duration() * k as f64 / 8.0);
            }
            let _ = (
                p.peak_velocity(),
                p.peak_acceleration(),
                p.peak_deceleration(),
            );
        }
    }
}

/// The attacks that produced impossible plans before the range check and the plan check:
/// each is refused by `plan_checked`, and the plan `plan` still makes of it fails its check.
#[test]
fn attacks_are_refused() {
    let sym = |v, a, j| Limits::symmetric(v, a, j);
    let sub = f64::MIN_POSITIVE / 3.0;
    let cases = [
        ("jmax 1e-246", sym(2e5, 2e6, 1e-246)),
        ("amax 1e-306", sym(2e5, 1e-306, 1e8)),
        ("subnormal amax", sym(2e5, sub, 1e8)),
        (
            "subnormal dmax",
            Limits {
                dmax: sub,
                ..sym(2e5, 2e6, 1e8)
            },
        ),
        (
            "jdec 1e-320",
            Limits {
                j5: 1e-320,
                j7: 1e-320,
                ..sym(2e5, 2e6, 1e8)
            },
        ),
        ("vmax 1e300", sym(1e300, 2e6, 1e8)),
    ];
    for (what, l) in cases {
        let r = Profile::plan_checked(0.0, 1e5, 0.0, 0.0, &l, 10_000);
        assert_eq!(r.map(|_| ()), Err(PlanError::LimitRange), "{what}");
        // The safety net under the range: what the bare planner makes of it is refused.
        if let Ok(p) = Profile::plan(0.0, 1e5, 0.0, 0.0, &l) {
            let v = p.verify_plan(0.0, 1e5, 0.0, 0.0, &l);
            assert!(
                matches!(v, Err(PlanError::PlanCheck | PlanError::Infeasible))
                    || (what == "vmax 1e300" && v.is_ok()),
                "{what}: {v:?} for {p:?}"
            );
        }
    }
    // The range's ends are inside, one ulp beyond is not.
    for rate in [1000, 10_000, 20_000] {
        for order in 1..=3 {
            let r = firmware_proto::limit_range(order, rate);
            for (x, inside) in [
                (*r.start(), true),
                (*r.end(), true),
                (r.start().next_down(), false),
                (r.end().next_up(), false),
            ] {
                let mut l = sym(1e3, 1e5, 1e7);
                match order {
                    1 => l.vmax = x,
                    2 => l.dmax = x,
                    _ => l.j5 = x,
                }
                let want = if inside {
                    Ok(())
                } else {
                    Err(PlanError::LimitRange)
                };
                assert_eq!(l.check_range(rate), want, "order {order} {x:e} at {rate}");
            }
        }
    }
    // A stop ignores vmax, amax and j1 (the axis passes vmax = f64::MAX).
    let l = Limits {
        vmax: f64::MAX,
        ..sym(1e3, 1e5, 1e7)
    };
    assert_eq!(l.check_range(10_000), Err(PlanError::LimitRange));
    assert!(Profile::stop_checked(0.0, 500.0, 0.0, &l, 10_000).is_ok());
    let l = Limits { j7: 1e-19, ..l };
    assert_eq!(
        Profile::stop_checked(0.0, 500.0, 0.0, &l, 10_000),
        Err(PlanError::LimitRange)
    );
}

/// The check refuses a profile that does not do what was asked of it.
#[test]
fn verify_refuses_a_wrong_profile() {
    let l = Limits::symmetric(1000.0, 1e4, 1e6);
    let p = Profile::plan(5.0, 1e4, 0.0, 0.0, &l).unwrap();
    assert_eq!(p.verify_plan(5.0, 1e4, 0.0, 0.0, &l), Ok(()));
    // another request than the one planned
    assert_eq!(
        p.verify_plan(5.0, 1e4 + 1e-6, 0.0, 0.0, &l),
        Err(PlanError::PlanCheck)
    );
    assert_eq!(
        p.verify_plan(4.0, 1e4, 0.0, 0.0, &l),
        Err(PlanError::PlanCheck)
    );
    assert_eq!(
        p.verify_plan(5.0, -1e4, 0.0, 0.0, &l),
        Err(PlanError::PlanCheck)
    );
    // tighter limits than those planned with
    for tight in [
        Limits { vmax: 999.0, ..l },
        Limits { amax: 9e3, ..l },
        Limits { dmax: 9e3, ..l },
        Limits { j3: 9e5, ..l },
        Limits { j7: 9e5, ..l },
    ] {
        assert_eq!(
            p.verify_plan(5.0, 1e4, 0.0, 0.0, &tight),
            Err(PlanError::PlanCheck)
        );
    }
    // broken profiles: a cruise too short (off target, and shorter than |d|/vmax), a NaN,
    // an acceleration jump, a move too long
    let mut q = p;
    q.dur[3] *= 0.5;
    q.t0[4..].iter_mut().for_each(|t| *t -= p.dur[3] * 0.5);
    assert_eq!(
        q.verify_plan(5.0, 1e4, 0.0, 0.0, &l),
        Err(PlanError::PlanCheck)
    );
    let mut q = p;
    q.x[5] = f64::NAN;
    assert_eq!(
        q.verify_plan(5.0, 1e4, 0.0, 0.0, &l),
        Err(PlanError::PlanCheck)
    );
    let mut q = p;
    q.a[2] *= 1.001;
    assert_eq!(
        q.verify_plan(5.0, 1e4, 0.0, 0.0, &l),
        Err(PlanError::PlanCheck)
    );
    let slow = Limits::symmetric(1e-3, 1.0, 1.0);
    let p = Profile::plan(0.0, 2e3, 0.0, 0.0, &slow).unwrap();
    assert!(p.duration() > crate::MAX_MOVE_TIME);
    assert_eq!(
        p.verify_plan(0.0, 2e3, 0.0, 0.0, &slow),
        Err(PlanError::Infeasible)
    );
    // a stop: checked against its own state, reversal refused
    let s = Profile::stop(1.0, -1000.0, 0.0, &l).unwrap();
    assert_eq!(s.verify_stop(1.0, -1000.0, 0.0, &l), Ok(()));
    assert_eq!(
        s.verify_stop(1.0, -999.0, 0.0, &l),
        Err(PlanError::PlanCheck)
    );
    assert_eq!(
        s.verify_stop(1.0, -1000.0, 0.0, &Limits { j5: 9e5, ..l }),
        Err(PlanError::PlanCheck)
    );
    let mut q = s;
    q.dur[6] *= 2.0; // ramps the deceleration out past zero: backwards
    q.t0[7] += s.dur[6];
    assert_eq!(
        q.verify_stop(1.0, -1000.0, 0.0, &l),
        Err(PlanError::PlanCheck)
    );
}

/// Seeded property tests over the whole `f64` range (proptest with a fixed ChaCha seed:
/// the same cases on every run; `PROPTEST_CASES` is overridden by the counts here).
mod props;
