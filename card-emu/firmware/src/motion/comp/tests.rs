use super::*;

const RATE: u32 = 10_000;
const TS: f64 = 1.0 / RATE as f64;

fn pt(position: f64, forward: f64, reverse: f64) -> CompPoint {
    CompPoint {
        position,
        forward,
        reverse,
    }
}

fn table() -> [CompPoint; 3] {
    [
        pt(0.0, 0.0, 2.0),
        pt(1000.0, 10.0, 14.0),
        pt(3000.0, -10.0, -4.0),
    ]
}

fn params() -> CompParams {
    CompParams {
        bound: 20.0,
        backlash: 0.0,
        ramp_vel: 2000.0,
        ramp_acc: 2e6,
        bidir: true,
    }
}

#[test]
fn interpolation_is_linear_between_points_and_holds_the_ends() {
    let t = table();
    assert_eq!(interpolate(&t, 0.0, true), (0.0, 0.0));
    assert_eq!(interpolate(&t, 500.0, true), (5.0, 0.01));
    assert_eq!(interpolate(&t, 500.0, false), (8.0, 0.012));
    assert_eq!(interpolate(&t, 1000.0, true).0, 10.0);
    assert_eq!(interpolate(&t, 2000.0, true), (0.0, -0.01));
    let (c, slope) = interpolate(&t, 2500.0, false);
    assert!(
        (c - 0.5).abs() < 1e-12 && (slope + 0.009).abs() < 1e-15,
        "{c} {slope}"
    );
    // Outside: the end point's correction, no slope.
    assert_eq!(interpolate(&t, -1e9, true), (0.0, 0.0));
    assert_eq!(interpolate(&t, -1e9, false), (2.0, 0.0));
    assert_eq!(interpolate(&t, 1e12, true), (-10.0, 0.0));
    assert_eq!(interpolate(&t, 1e12, false), (-4.0, 0.0));
    // An empty table corrects nothing.
    assert_eq!(interpolate(&[], 5.0, true), (0.0, 0.0));
    // Continuous at every point, from both sides.
    for p in &t {
        for fwd in [true, false] {
            let below = interpolate(&t, p.position - 1e-9, fwd).0;
            let above = interpolate(&t, p.position + 1e-9, fwd).0;
            assert!((below - above).abs() < 1e-9, "{p:?} {fwd}");
        }
    }
}

#[test]
fn table_checks_name_each_fault() {
    let p = params();
    let t = table();
    assert_eq!(p.check_table(&t, RATE), Ok(()));
    let mut bad = t;
    bad[1].position = 0.0;
    assert_eq!(p.check_table(&bad, RATE), Err(CompError::Order));
    let mut bad = t;
    bad[2].position = 900.0;
    assert_eq!(p.check_table(&bad, RATE), Err(CompError::Order));
    let mut bad = t;
    bad[1].forward = f64::NAN;
    assert_eq!(p.check_table(&bad, RATE), Err(CompError::NotFinite));
    let mut bad = t;
    bad[1].reverse = 20.5;
    assert_eq!(p.check_table(&bad, RATE), Err(CompError::Bound));
    // One column: the reverse correction must be the forward one.
    let one = CompParams { bidir: false, ..p };
    assert_eq!(one.check_table(&t, RATE), Err(CompError::Bound));
    let same = t.map(|q| pt(q.position, q.forward, q.forward));
    assert_eq!(one.check_table(&same, RATE), Ok(()));
    // Backlash counts against the bound: 14 + 14/2 > 20 in reverse... forward 10 + 7 fits.
    let lash = CompParams {
        backlash: 14.0,
        bidir: false,
        ..p
    };
    assert_eq!(lash.check_table(&same, RATE), Ok(()));
    let lash = CompParams {
        backlash: 22.0,
        bidir: false,
        ..p
    };
    assert_eq!(lash.check_table(&same, RATE), Err(CompError::Bound));
    // Settings.
    for bad in [
        CompParams { bound: 0.0, ..p },
        CompParams {
            backlash: -1.0,
            ..p
        },
        CompParams { ramp_vel: 0.0, ..p },
        CompParams {
            ramp_acc: 1e300,
            ..p
        },
    ] {
        assert_eq!(bad.check_table(&t, RATE), Err(CompError::Table), "{bad:?}");
    }
    assert_eq!(
        CompParams {
            bound: f64::NAN,
            ..p
        }
        .check_table(&t, RATE),
        Err(CompError::NotFinite)
    );
    let many = [pt(0.0, 0.0, 0.0); MAX_POINTS + 1];
    assert_eq!(p.check_table(&many, RATE), Err(CompError::Table));
    let mut full = [pt(0.0, 0.0, 0.0); MAX_POINTS];
    for (i, q) in full.iter_mut().enumerate() {
        q.position = i as f64;
    }
    assert_eq!(p.check_table(&full, RATE), Ok(()));
}

/// A motion that reverses: x(t) = 500 sin(2π t / 0.2 s) around 1000, sampled per tick.
fn motion(k: usize) -> (f64, f64, f64) {
    let w = 2.0 * core::f64::consts::PI / 0.2;
    let t = k as f64 * TS;
    (
        1000.0 + 500.0 * (w * t).sin(),
        500.0 * w * (w * t).cos(),
        -500.0 * w * w * (w * t).sin(),
    )
}

#[test]
fn a_reversal_is_taken_up_by_a_ramp_within_its_limits_never_a_step() {
    let p = CompParams {
        backlash: 6.0,
        ..params()
    };
    let t = table();
    let mut s = CompState::new();
    s.changed(Some(p.ramp_limits()));
    let mut prev = s.applied();
    let mut ramping_ticks = 0;
    let mut reversals = 0;
    let mut was_forward = s.forward();
    for k in 0..4000 {
        let (x, v, a) = motion(k);
        let (c, cv, _) = s.step(Some((&t, &p)), x, v, a, TS);
        if s.forward() != was_forward {
            reversals += 1;
            was_forward = s.forward();
        }
        // The correction's own rate: the table's slope times the velocity, plus the ramp's.
        let (_, slope) = interpolate(&t, x, s.forward());
        let ramp_rate = cv - slope * v;
        assert!(
            ramp_rate.abs() <= p.ramp_vel * (1.0 + 1e-9),
            "tick {k}: ramp velocity {ramp_rate}"
        );
        // No step: from one tick to the next the correction moves at most what the table's
        // slope and the ramp's velocity allow.
        let table_part = 0.012 * v.abs() * TS;
        assert!(
            (c - prev.0).abs() <= table_part + p.ramp_vel * TS + 1e-9,
            "tick {k}: step {} -> {c}",
            prev.0
        );
        // The ramp's acceleration, from its velocity over one tick.
        if !s.settled() {
            ramping_ticks += 1;
        }
        prev = (c, cv, 0.0);
        // Once settled, the correction is the table's plus half the backlash.
        if s.settled() && k > 0 {
            let (tc, _) = interpolate(&t, x, s.forward());
            let want = tc + if s.forward() { 3.0 } else { -3.0 };
            assert!((c - want).abs() < 1e-12, "tick {k}: {c} vs {want}");
        }
    }
    // 0.4 s of a 0.2 s period: a reversal at each of its four turning points.
    assert!(reversals >= 4, "{reversals} reversals");
    // Each reversal took a ramp: 4 + 6 counts at 2000 counts/s are a few ms each.
    assert!(
        ramping_ticks >= reversals * 20,
        "{ramping_ticks} ticks ramping"
    );
}

#[test]
fn the_ramp_acceleration_is_within_its_limit() {
    // At rest, a table loaded: the whole correction ramps in from 0.
    let p = CompParams {
        backlash: 4.0,
        ramp_vel: 500.0,
        ramp_acc: 1e5,
        ..params()
    };
    let t = table();
    let mut s = CompState::new();
    s.changed(Some(p.ramp_limits()));
    let mut vel = Vec::new();
    let mut pos = Vec::new();
    for _ in 0..2000 {
        let (c, cv, _) = s.step(Some((&t, &p)), 500.0, 0.0, 0.0, TS);
        pos.push(c);
        vel.push(cv);
    }
    // 500 forward: 5 + 2.
    assert_eq!(*pos.last().unwrap(), 7.0);
    assert!(s.settled());
    assert!(pos[0].abs() < 1e-3, "first tick {}", pos[0]);
    for w in vel.windows(2) {
        let acc = (w[1] - w[0]) / TS;
        assert!(acc.abs() <= p.ramp_acc * (1.0 + 1e-6), "acc {acc}");
    }
    let peak = vel.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    assert!(
        peak <= p.ramp_vel * (1.0 + 1e-9) && peak > 0.5 * p.ramp_vel,
        "{peak}"
    );
    // Off again: it ramps out to exactly 0, then costs nothing.
    s.changed(None);
    for _ in 0..2000 {
        s.step(None, 500.0, 0.0, 0.0, TS);
    }
    assert_eq!(s.applied(), (0.0, 0.0, 0.0));
    assert!(s.idle());
}

#[test]
fn a_second_reversal_during_the_ramp_continues_from_its_state() {
    let p = CompParams {
        backlash: 10.0,
        ramp_vel: 1000.0,
        ..params()
    };
    let t: [CompPoint; 0] = [];
    let mut s = CompState::new();
    s.changed(Some(p.ramp_limits()));
    for _ in 0..200 {
        s.step(Some((&t, &p)), 0.0, 1.0, 0.0, TS);
    }
    assert_eq!(s.applied().0, 5.0);
    let mut prev = 5.0;
    // Reverse for 20 ticks (half-way through the 10-count ramp), then forward again.
    for k in 0..400 {
        let v = if k < 20 { -1.0 } else { 1.0 };
        let (c, _, _) = s.step(Some((&t, &p)), 0.0, v, 0.0, TS);
        assert!((c - prev).abs() <= p.ramp_vel * TS + 1e-9, "tick {k}");
        prev = c;
    }
    assert!(prev < 5.0 + 1e-12 && (prev - 5.0).abs() < 1e-12, "{prev}");
}
