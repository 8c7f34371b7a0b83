//! S-curve moves on the stepped emulated card: positions, limits, time-optimality, done.
mod common;

use common::{stepped_card, Rng};
use motioncard_sdk::{AxisState, EventKind, MoveLimits};
use std::time::Duration;

const REL: f64 = 1e-9;

#[test]
fn target_reached_within_one_count_and_held() {
    let card = stepped_card();
    let sim = card.sim().unwrap();
    let targets = [
        123_456.0, -98_765.0, 7.0, 400_000.0, -1.0, 55_555.0, 0.0, -250_000.0,
    ];
    let mut motions = Vec::new();
    for (i, t) in targets.iter().enumerate() {
        let ax = card.axis(i).unwrap();
        ax.enable().unwrap();
        let lim = MoveLimits::new(150_000.0 + 20_000.0 * i as f64, 1.5e6, 6e7);
        motions.push(ax.move_absolute(*t, &lim).unwrap());
    }
    for (i, (m, t)) in motions.iter().zip(targets).enumerate() {
        let pos = m.wait(Duration::from_secs(10)).unwrap();
        assert!(
            (pos - t).abs() <= 1.0,
            "axis {i}: done at {pos}, target {t}"
        );
    }
    // Held: one more second, every tick, every axis.
    for _ in 0..10_000 {
        sim.step(1);
        for (i, t) in targets.iter().enumerate() {
            let s = card.axis(i).unwrap().status().unwrap();
            assert!(
                (s.raw.encoder as f64 - t).abs() <= 1.0,
                "axis {i} drifted to {} (target {t})",
                s.raw.encoder
            );
            assert_eq!(s.state, AxisState::Standstill);
        }
    }
}

/// Every tick of the commanded profile stays inside its limits; jerk is the finite difference
/// of the commanded acceleration (exact for a piecewise-linear acceleration).
#[test]
fn commanded_profile_never_exceeds_its_limits() {
    let card = stepped_card();
    let sim = card.sim().unwrap();
    let ax = card.axis(0).unwrap();
    ax.enable().unwrap();
    let ts = 1.0 / card.info().servo_rate_hz as f64;
    let mut rng = Rng::new(7);
    let mut ticks_checked = 0u64;
    for case in 0..120 {
        let v = rng.log_uniform(2e3, 3e5);
        let a = rng.log_uniform(1e5, 4e6);
        let d = rng.log_uniform(1e5, 4e6);
        let j = [
            rng.log_uniform(1e6, 1e9),
            rng.log_uniform(1e6, 1e9),
            rng.log_uniform(1e6, 1e9),
            rng.log_uniform(1e6, 1e9),
        ];
        let lim = MoveLimits {
            velocity: v,
            acceleration: a,
            deceleration: d,
            jerk: j,
        };
        let dist = rng.uniform(-1.0, 1.0) * rng.log_uniform(10.0, 3e5);
        let dir = dist.signum();
        let m = ax.move_relative(dist, &lim).unwrap();
        let s0 = ax.status().unwrap().raw;
        let mut prev_acc = s0.cmd_acc * dir;
        let mut done = false;
        let max_ticks = ((s0.planned_time + 2.0) / ts) as u64;
        sim.trace(0, max_ticks, |s| {
            let r = &s.raw;
            let acc = r.cmd_acc * dir;
            let jerk = (acc - prev_acc) / ts;
            assert!(
                r.cmd_vel.abs() <= v * (1.0 + REL),
                "case {case}: |v| {} > {v}",
                r.cmd_vel
            );
            assert!(r.cmd_vel * dir >= -v * REL, "case {case}: moves backwards");
            assert!(acc <= a * (1.0 + REL), "case {case}: acc {acc} > {a}");
            assert!(-acc <= d * (1.0 + REL), "case {case}: dec {} > {d}", -acc);
            // Signed, per phase: in one tick the acceleration can only change at the jerks of
            // the phases that tick touches (1: +j1, 3: −j3, 5: −j5, 7: +j7, the others 0).
            let (lo, hi) = if acc >= 0.0 && prev_acc >= 0.0 {
                (-j[1], j[0])
            } else if acc <= 0.0 && prev_acc <= 0.0 {
                (-j[2], j[3])
            } else {
                (-j[1].max(j[2]), 0.0)
            };
            assert!(
                jerk <= hi * (1.0 + REL) + 1e-3 && jerk >= lo * (1.0 + REL) - 1e-3,
                "case {case}: jerk {jerk} outside [{lo}, {hi}]"
            );
            prev_acc = acc;
            ticks_checked += 1;
            done = s.state == AxisState::Standstill;
            !done
        })
        .unwrap();
        assert!(done, "case {case} never finished");
        let end = m.wait(Duration::ZERO).unwrap();
        assert!((end - ax.status().unwrap().raw.target).abs() <= 1.0);
    }
    assert!(ticks_checked > 10_000);
}

/// Duration of a time-optimal rest-to-rest S-curve, computed here independently of the
/// firmware's planner: integrate each ramp segment by segment, and bisect on the peak
/// velocity for the largest one whose ramps fit in the distance.
fn optimal_duration(dist: f64, vmax: f64, amax: f64, dmax: f64, j: [f64; 4]) -> f64 {
    // Ramp from rest to v with jerks (ja up, jb down) and acceleration limit a: (time, distance).
    fn ramp(v: f64, a: f64, ja: f64, jb: f64) -> (f64, f64) {
        let ap = if v >= a * a / 2.0 * (1.0 / ja + 1.0 / jb) {
            a
        } else {
            (2.0 * v / (1.0 / ja + 1.0 / jb)).sqrt()
        };
        let (t1, t3) = (ap / ja, ap / jb);
        let t2 = ((v - ap * ap / 2.0 * (1.0 / ja + 1.0 / jb)) / ap).max(0.0);
        let (mut x, mut vel, mut acc, mut t) = (0.0, 0.0, 0.0, 0.0);
        for (dt, jerk) in [(t1, ja), (t2, 0.0), (t3, -jb)] {
            x += vel * dt + acc * dt * dt / 2.0 + jerk * dt * dt * dt / 6.0;
            vel += acc * dt + jerk * dt * dt / 2.0;
            acc += jerk * dt;
            t += dt;
        }
        (t, x)
    }
    let fits = |v: f64| ramp(v, amax, j[0], j[1]).1 + ramp(v, dmax, j[3], j[2]).1 <= dist;
    let vp = if fits(vmax) {
        vmax
    } else {
        let (mut lo, mut hi) = (0.0, vmax);
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if fits(mid) {
                lo = mid
            } else {
                hi = mid
            }
        }
        lo
    };
    let (ta, xa) = ramp(vp, amax, j[0], j[1]);
    let (td, xd) = ramp(vp, dmax, j[3], j[2]);
    ta + td + ((dist - xa - xd) / vp).max(0.0)
}

/// The card's planned duration equals the independently computed optimum over 1,000 random
/// limit/distance cases (planned only: each move is cut off by power-off after its ack).
#[test]
fn planned_duration_is_time_optimal() {
    let card = stepped_card();
    let ax = card.axis(3).unwrap();
    let mut rng = Rng::new(2024);
    let mut worst: f64 = 0.0;
    for case in 0..1000 {
        let v = rng.log_uniform(1e2, 1e6);
        let a = rng.log_uniform(1e3, 1e8);
        let d = if case % 3 == 0 {
            a
        } else {
            rng.log_uniform(1e3, 1e8)
        };
        let mut j = [0.0; 4];
        for x in j.iter_mut() {
            *x = rng.log_uniform(1e4, 1e10);
        }
        if case % 2 == 0 {
            j = [j[0], j[0], j[2], j[2]];
        }
        let dist = rng.log_uniform(1e-2, 1e7);
        ax.enable().unwrap();
        ax.move_relative(
            dist,
            &MoveLimits {
                velocity: v,
                acceleration: a,
                deceleration: d,
                jerk: j,
            },
        )
        .unwrap();
        let planned = ax.status().unwrap().raw.planned_time;
        ax.disable().unwrap();
        let want = optimal_duration(dist, v, a, d, j);
        let rel = (planned - want).abs() / want;
        worst = worst.max(rel);
        assert!(rel <= 1e-9, "case {case}: planned {planned} s, optimum {want} s (v {v}, a {a}, d {d}, j {j:?}, dist {dist})");
    }
    println!("worst relative duration mismatch over 1000 cases: {worst:e}");
}

/// Motion done comes only once the axis is in position: with the output clamped low the axis
/// lags far behind the profile, and done must wait for it.
#[test]
fn done_never_before_in_position() {
    let card = stepped_card();
    let sim = card.sim().unwrap();
    let ax = card.axis(1).unwrap();
    let mut cfg = motioncard_sdk::AxisSettings {
        dac_limit_v: 0.3,
        ..Default::default()
    };
    ax.configure(&cfg).unwrap();
    // The axis lags far behind on purpose: widen its following-error limit.
    ax.configure_safety(&lagging()).unwrap();
    ax.enable().unwrap();
    let m = ax
        .move_absolute(200_000.0, &MoveLimits::new(200_000.0, 4e6, 1e9))
        .unwrap();
    let planned = ax.status().unwrap().raw.planned_time;
    let window = cfg.in_pos_window;
    let mut done_at = None;
    let mut ticks = 0u64;
    while done_at.is_none() && ticks < 200_000 {
        sim.step(1);
        ticks += 1;
        while let Some(e) = card.next_event(Duration::ZERO).unwrap() {
            if e.kind == EventKind::MotionDone && e.seq == m.seq() {
                let s = ax.status().unwrap().raw;
                assert!(
                    (s.target - s.act_pos).abs() <= window,
                    "done while {} counts from target",
                    s.target - s.act_pos
                );
                assert!(s.act_vel.abs() <= cfg.in_vel_window);
                done_at = Some(sim.time());
            }
        }
        if done_at.is_none() {
            // Not done yet: then it must not be settled in position for the settle time.
            let s = ax.status().unwrap().raw;
            assert_eq!(s.move_time, 0.0);
        }
    }
    let done_at = done_at.expect("move finished");
    assert!(
        done_at > planned + 0.1,
        "done at {done_at} s, profile ended at {planned} s: the lag should delay done"
    );
    // The same move with the default clamp is done within a few ms of the profile end.
    cfg.dac_limit_v = 10.0;
    ax.configure(&cfg).unwrap();
    let t0 = sim.time();
    ax.move_absolute(0.0, &MoveLimits::new(200_000.0, 4e6, 1e9))
        .unwrap()
        .wait(Duration::from_secs(5))
        .unwrap();
    assert!(sim.time() - t0 < planned + 0.02);
}

/// Plant parameters are per axis: a heavier axis follows the same profile with a larger
/// following error, and still ends in position.
#[test]
fn plant_parameters_are_per_axis() {
    let mut emu = motioncard_sdk::EmuOptions::default();
    emu.motors[1].inertia *= 4.0;
    let card = common::stepped_card_with(emu);
    let lim = MoveLimits::new(2e5, 3e6, 1e8);
    let mut ferr = [0.0; 2];
    for (i, f) in ferr.iter_mut().enumerate() {
        let ax = card.axis(i).unwrap();
        ax.configure_safety(&lagging()).unwrap(); // the heavier axis lags on purpose
        ax.enable().unwrap();
        let pos = ax
            .move_absolute(50_000.0, &lim)
            .unwrap()
            .wait(Duration::from_secs(5))
            .unwrap();
        assert!((pos - 50_000.0).abs() <= 1.0);
        *f = ax.status().unwrap().raw.max_ferr;
    }
    assert!(
        ferr[1] > 1.5 * ferr[0],
        "following errors {ferr:?}: the heavier axis should lag more (same gains)"
    );
}

/// A following-error limit wide enough for an axis made to lag on purpose.
fn lagging() -> motioncard_sdk::SafetySettings {
    motioncard_sdk::SafetySettings {
        ferror: 1e7,
        min_ferror: 1e6,
        ..Default::default()
    }
}
