//! Axes groups on the stepped emulated card: states, interpolation geometry, filters, nacks.
mod common;

use common::stepped_card;
use motioncard_sdk::{
    AccDec, ArcSpec, AxisState, Card, ErrorKind, FilterKind, FilterSettings, GroupSettings,
    GroupState, Interpolator, MoveLimits, MoveOptions, PathLimits, Plane,
};
use std::time::Duration;

const T: Duration = Duration::from_secs(30);

/// The largest correction a group's snap to its programmed end may make. The commanded
/// positions are error-free sums (double-f64) of what the filters emit, and each filter emits
/// its whole remainder, as a pair, on the tick it empties: Σ outputs = Σ inputs exactly. The
/// inputs are the interpolator's increments `p(k) − p(k−1)`; their sum telescopes exactly to
/// end − start except where a subtraction rounds, which (Sterbenz) needs consecutive points
/// more than a factor 2 apart, i.e. a coordinate within a few increments of zero, where the
/// rounding is at most 2^-53 of an increment (≈ 1e-15 counts here). So the correction is 0 up
/// to ~1e-14 counts on these moves (measured: 0 to 2e-18). A filter that dropped its settle
/// remainder (up to 1e-9 counts), or a plain f64 sum of the increments (thousands of roundings
/// of an ulp of the position, ~1e-11 each), would exceed it.
const SNAP_BOUND: f64 = 1e-12;

/// The group's snap corrections (last, largest since enable) are within [`SNAP_BOUND`].
fn assert_snap(g: &motioncard_sdk::Group, what: &str) {
    let s = g.status().unwrap().1;
    assert!(
        s.snap_last <= SNAP_BOUND && s.snap_max <= SNAP_BOUND,
        "{what}: snap corrected {} (largest {}) counts",
        s.snap_last,
        s.snap_max
    );
}

fn lim() -> PathLimits {
    PathLimits::new(50_000.0, 5e5, 5e7)
}

/// A card with axes `axes` enabled and group 0 over them, enabled.
fn group_card(axes: &[usize], accdec: AccDec) -> (Card, motioncard_sdk::Group) {
    let card = stepped_card();
    for &a in axes {
        card.axis(a).unwrap().enable().unwrap();
    }
    let g = card.group(0).unwrap();
    g.configure(&GroupSettings {
        accdec,
        ..GroupSettings::new(axes)
    })
    .unwrap();
    g.enable().unwrap();
    (card, g)
}

fn cmd(card: &Card, a: usize) -> f64 {
    card.axis(a).unwrap().status().unwrap().raw.cmd_pos
}

#[test]
fn linear_move_follows_the_line_and_ends_on_target() {
    for accdec in [AccDec::Pre, AccDec::Post, AccDec::Both] {
        let (card, g) = group_card(&[0, 1, 2], accdec);
        let sim = card.sim().unwrap();
        let target = [30_000.0, -40_000.0, 12_000.0];
        let len = (target.iter().map(|x| x * x).sum::<f64>()).sqrt();
        let m = g
            .move_linear(&target, &lim(), MoveOptions::default())
            .unwrap();
        let mut worst: f64 = 0.0;
        let mut ticks = 0;
        while g.status().unwrap().0 == GroupState::Moving && ticks < 200_000 {
            sim.step(1);
            ticks += 1;
            let p: Vec<f64> = (0..3).map(|a| cmd(&card, a)).collect();
            // Distance of the commanded point from the line through 0 and target.
            let along: f64 = p.iter().zip(&target).map(|(x, t)| x * t).sum::<f64>() / len;
            let off = p
                .iter()
                .zip(&target)
                .map(|(x, t)| (x - along * t / len).powi(2))
                .sum::<f64>()
                .sqrt();
            worst = worst.max(off);
        }
        m.wait(T).unwrap();
        for (a, t) in target.iter().enumerate() {
            assert_eq!(cmd(&card, a), *t, "{accdec:?}: commanded end of axis {a}");
            let act = card.axis(a).unwrap().status().unwrap().actual_position;
            assert!((act - t).abs() <= 1.0, "{accdec:?}: axis {a} at {act}");
        }
        assert_snap(&g, &format!("{accdec:?}"));
        // Linear interpolation through any filter has no path error beyond rounding (Kim §4).
        assert!(
            worst < 1e-6,
            "{accdec:?}: commanded path left the line by {worst} counts"
        );
        for a in 0..3 {
            assert_eq!(
                card.axis(a).unwrap().status().unwrap().state,
                AxisState::Standstill
            );
        }
    }
}

/// Trace the commanded positions of `axes` every tick until the group is at rest.
fn trace(card: &Card, g: &motioncard_sdk::Group, axes: &[usize]) -> Vec<Vec<f64>> {
    let sim = card.sim().unwrap();
    let mut out = Vec::new();
    for _ in 0..2_000_000 {
        sim.step(1);
        out.push(axes.iter().map(|&a| cmd(card, a)).collect());
        if g.status().unwrap().0 != GroupState::Moving {
            break;
        }
    }
    out
}

#[test]
fn arcs_by_centre_radius_and_border_point_in_every_plane() {
    let r = 20_000.0;
    // Arcs from the group's position (0, 0) to (-r, r) around the centre (-r, 0), written every
    // way: a quarter turn counter-clockwise, or three quarters clockwise.
    let specs = [
        (
            ArcSpec::Centre {
                end: [-r, r],
                centre: [-r, 0.0],
                ccw: true,
            },
            true,
        ),
        (
            ArcSpec::Radius {
                end: [-r, r],
                radius: r,
                ccw: true,
            },
            true,
        ),
        (
            ArcSpec::Border {
                end: [-r, r],
                via: [-r + r * 0.5f64.sqrt(), r * 0.5f64.sqrt()],
            },
            true,
        ),
        (
            ArcSpec::Centre {
                end: [-r, r],
                centre: [-r, 0.0],
                ccw: false,
            },
            false,
        ),
        (
            ArcSpec::Radius {
                end: [-r, r],
                radius: -r,
                ccw: false,
            },
            false,
        ),
    ];
    for plane in [Plane::XY, Plane::YZ, Plane::ZX] {
        let (u, v) = plane.axes();
        for (spec, ccw) in specs {
            let (card, g) = group_card(&[0, 1, 2], AccDec::Pre);
            let m = g
                .move_circular(&spec, plane, &[], &lim(), MoveOptions::default())
                .unwrap();
            let pts = trace(&card, &g, &[u, v]);
            m.wait(T).unwrap();
            let c = (-r, 0.0);
            let worst = pts
                .iter()
                .map(|p| ((p[0] - c.0).hypot(p[1] - c.1) - r).abs())
                .fold(0.0, f64::max);
            assert!(worst < 1e-6, "{plane:?} {spec:?}: radius error {worst}");
            // Direction: the first points turn the right way around the centre.
            let a0 = (pts[pts.len() / 4][1] - c.1).atan2(pts[pts.len() / 4][0] - c.0);
            assert_eq!(a0 > 0.0, ccw, "{plane:?} {spec:?}: went the wrong way");
            let end = &pts[pts.len() - 1];
            assert!(
                (end[0] + r).abs() < 1e-6 && (end[1] - r).abs() < 1e-6,
                "{plane:?} {spec:?}: ended at {end:?}"
            );
            // The third axis did not move.
            let w = 3 - u - v;
            assert_eq!(cmd(&card, w), 0.0);
            // The long CW way round is three quarters of a turn: longer path, longer time.
            if !ccw {
                assert!(
                    pts.len() > 2 * specs_len_hint(),
                    "{plane:?} {spec:?}: {} ticks",
                    pts.len()
                );
            }
        }
    }
}

/// Ticks of the quarter arc at the test's feed, as a floor for the three-quarter arcs.
fn specs_len_hint() -> usize {
    let l = 20_000.0 * std::f64::consts::FRAC_PI_2;
    (l / 50_000.0 * 10_000.0) as usize
}

#[test]
fn helical_move_climbs_linearly_with_the_angle() {
    let (card, g) = group_card(&[0, 1, 2], AccDec::Pre);
    let r = 10_000.0;
    // A full turn around (r, 0)... from the origin, climbing 5,000 counts in Z.
    let m = g
        .move_circular(
            &ArcSpec::Centre {
                end: [0.0, 0.0],
                centre: [r, 0.0],
                ccw: true,
            },
            Plane::XY,
            &[5_000.0],
            &lim(),
            MoveOptions::default(),
        )
        .unwrap();
    let pts = trace(&card, &g, &[0, 1, 2]);
    m.wait(T).unwrap();
    for p in &pts {
        let rad = (p[0] - r).hypot(p[1]);
        assert!((rad - r).abs() < 1e-6, "radius {rad}");
        // z / 5000 = swept angle / 2π.
        let ang = (p[1]).atan2(p[0] - r);
        let swept = (ang - std::f64::consts::PI).rem_euclid(std::f64::consts::TAU);
        let want = 5_000.0 * swept / std::f64::consts::TAU;
        if p[2] > 1.0 && p[2] < 4_999.0 {
            assert!((p[2] - want).abs() < 1e-3, "z {} vs {want}", p[2]);
        }
    }
    assert_eq!(cmd(&card, 2), 5_000.0);
}

/// Layout 1.10: an arc in the plane of any two group axes, here group axes 3 and 0 of a
/// four-axis group (a rotary table's plane), group axes 1 and 2 moving linearly with the
/// angle (a helix); the same path through the path buffer; the plane (0, 1) is exactly
/// `Plane::XY`. One axis named twice is the card's refusal (`MC_NACK_PLANE_AXES`), an axis
/// beyond the group the SDK's.
#[test]
fn arcs_in_the_plane_of_any_two_group_axes() {
    let r = 10_000.0;
    let turn = ArcSpec::Centre {
        end: [0.0, 0.0],
        centre: [r, 0.0],
        ccw: true,
    };
    let (card, g) = group_card(&[0, 1, 2, 3], AccDec::Pre);
    let m = g
        .move_circular(
            &turn,
            Plane::Axes(3, 0),
            &[2_000.0, -3_000.0],
            &lim(),
            MoveOptions::default(),
        )
        .unwrap();
    let pts = trace(&card, &g, &[3, 0, 1, 2]);
    m.wait(T).unwrap();
    let tau = std::f64::consts::TAU;
    for p in &pts {
        let rad = (p[0] - r).hypot(p[1]);
        assert!((rad - r).abs() < 1e-6, "radius {rad} at {p:?}");
        // Counter-clockwise from axis 3 towards axis 0, from the angle π.
        let swept = (p[1].atan2(p[0] - r) - std::f64::consts::PI).rem_euclid(tau);
        if p[2] > 1.0 && p[2] < 1_999.0 {
            assert!((p[2] - 2_000.0 * swept / tau).abs() < 1e-3, "{p:?}");
            assert!((p[3] + 3_000.0 * swept / tau).abs() < 1e-3, "{p:?}");
        }
    }
    let quarter = &pts[pts.len() / 4];
    assert!(quarter[1] < -0.5 * r, "went the wrong way: {quarter:?}");
    assert_eq!((cmd(&card, 1), cmd(&card, 2)), (2_000.0, -3_000.0));
    assert!(cmd(&card, 3).abs() < 1e-6 && cmd(&card, 0).abs() < 1e-6);

    // The plane (0, 1) is XY's, tick for tick.
    let run = |plane: Plane| {
        let (card, g) = group_card(&[0, 1, 2], AccDec::Pre);
        g.move_circular(&turn, plane, &[500.0], &lim(), MoveOptions::default())
            .unwrap();
        trace(&card, &g, &[0, 1, 2])
    };
    assert_eq!(run(Plane::Axes(0, 1)), run(Plane::XY));

    // One axis twice: the card refuses it; an axis beyond the group: the SDK.
    let e = g
        .move_circular(
            &turn,
            Plane::Axes(2, 2),
            &[],
            &lim(),
            MoveOptions::default(),
        )
        .unwrap_err();
    assert_eq!(e.kind(), ErrorKind::PlaneAxes, "{e}");
    let e = g
        .move_circular(
            &turn,
            Plane::Axes(0, 4),
            &[],
            &lim(),
            MoveOptions::default(),
        )
        .unwrap_err();
    assert_eq!(e.kind(), ErrorKind::BadAxis, "{e}");

    // Through the path buffer: a line, then the helix in the plane (3, 0).
    g.configure_path(&motioncard_sdk::PathSettings::uniform(
        4, 50_000.0, 5e5, 5e7,
    ))
    .unwrap();
    let items = [
        motioncard_sdk::Segment::line(1, &[0.0, 2_000.0, -3_000.0, 5_000.0], 40_000.0, 0.0),
        motioncard_sdk::Segment::arc(
            2,
            ArcSpec::Centre {
                end: [5_000.0, 0.0],
                centre: [5_000.0 + r, 0.0],
                ccw: false,
            },
            Plane::Axes(3, 0),
            &[0.0, 0.0],
            40_000.0,
            0.0,
        )
        .last(),
    ];
    g.stream_path(items.map(motioncard_sdk::PathItem::from), |_| {})
        .map_err(|e| e.error)
        .unwrap();
    let pts = trace(&card, &g, &[3, 0, 1, 2]);
    assert!(pts.len() > 1000, "{} ticks", pts.len());
    let end = [3, 0, 1, 2].map(|a| cmd(&card, a));
    assert!(
        (end[0] - 5_000.0).abs() < 1e-6 && end[1].abs() < 1e-6 && end[2] == 0.0 && end[3] == 0.0,
        "{end:?}"
    );
}

#[test]
fn synchronised_ptp_axes_start_and_end_on_the_same_tick() {
    let (card, g) = group_card(&[0, 1, 2, 3], AccDec::Pre);
    let sim = card.sim().unwrap();
    let target = [80_000.0, -20_000.0, 5_000.0, 0.5];
    let m = g
        .move_ptp(
            &target,
            &PathLimits::new(100_000.0, 1e6, 5e7),
            MoveOptions::default(),
        )
        .unwrap();
    let mut first = [None; 4];
    let mut last = [0u64; 4];
    let mut peak = [0.0f64; 4];
    for tick in 1..200_000u64 {
        sim.step(1);
        for a in 0..4 {
            let v = card.axis(a).unwrap().status().unwrap().raw.cmd_vel;
            if v != 0.0 {
                first[a].get_or_insert(tick);
                last[a] = tick;
                peak[a] = peak[a].max(v.abs());
            }
        }
        if g.status().unwrap().0 != GroupState::Moving {
            break;
        }
    }
    m.wait(T).unwrap();
    assert!(
        first.iter().all(|f| *f == first[0]) && first[0].is_some(),
        "start ticks {first:?}"
    );
    assert!(last.iter().all(|l| *l == last[0]), "end ticks {last:?}");
    // The longest axis runs at the feed; the others scale with their distance (Kim eq 11).
    assert!((peak[0] - 100_000.0).abs() < 1e-6, "peak {peak:?}");
    for a in 1..4 {
        let want = 100_000.0 * (target[a] / target[0]).abs();
        assert!(
            (peak[a] - want).abs() < 1e-6 * 100_000.0,
            "axis {a}: peak {} vs {want}",
            peak[a]
        );
    }
    for (a, t) in target.iter().enumerate() {
        assert_eq!(cmd(&card, a), *t);
    }
}

#[test]
fn buffered_moves_run_in_order_and_each_reports_done() {
    let (card, g) = group_card(&[0, 1], AccDec::Post);
    let pts = [
        [10_000.0, 0.0],
        [10_000.0, 10_000.0],
        [0.0, 10_000.0],
        [0.0, 0.0],
    ];
    let moves: Vec<_> = pts
        .iter()
        .map(|p| g.move_linear(p, &lim(), MoveOptions::buffered()).unwrap())
        .collect();
    assert_eq!(g.status().unwrap().1.queued, 4);
    for m in &moves {
        m.wait(T).unwrap();
    }
    assert_eq!(g.status().unwrap().0, GroupState::Standby);
    assert_eq!((cmd(&card, 0), cmd(&card, 1)), (0.0, 0.0));
    assert_snap(&g, "four buffered moves through the default filters");
}

#[test]
fn group_states_follow_plcopen() {
    let card = stepped_card();
    let g = card.group(1).unwrap();
    let (x, y) = (card.axis(4).unwrap(), card.axis(5).unwrap());
    g.configure(&GroupSettings::new(&[4, 5])).unwrap();
    assert_eq!(g.status().unwrap().0, GroupState::Disabled);
    assert_eq!(
        g.move_linear(&[1.0, 1.0], &lim(), MoveOptions::default())
            .err()
            .unwrap()
            .kind(),
        ErrorKind::GroupDisabled
    );
    assert_eq!(g.enable().unwrap_err().kind(), ErrorKind::AxisDisabled);
    x.enable().unwrap();
    y.enable().unwrap();
    // An axis moving on its own keeps the group from enabling.
    let solo = x
        .move_relative(50_000.0, &MoveLimits::new(1e5, 1e6, 1e8))
        .unwrap();
    assert_eq!(g.enable().unwrap_err().kind(), ErrorKind::AxisBusy);
    solo.wait(T).unwrap();
    g.enable().unwrap();
    assert_eq!(g.status().unwrap().0, GroupState::Standby);
    // Grouped axes refuse single-axis motion.
    assert_eq!(
        x.move_relative(10.0, &MoveLimits::new(1e5, 1e6, 1e8))
            .err()
            .unwrap()
            .kind(),
        ErrorKind::AxisGrouped
    );
    assert_eq!(x.disable().unwrap_err().kind(), ErrorKind::AxisGrouped);
    assert_eq!(g.reset().unwrap_err().kind(), ErrorKind::InvalidState);
    // Stop: decelerate along the path, stay Stopping until released; queued moves aborted.
    let sim = card.sim().unwrap();
    let m1 = g
        .move_linear(&[200_000.0, 100_000.0], &lim(), MoveOptions::default())
        .unwrap();
    let m2 = g
        .move_linear(&[0.0, 0.0], &lim(), MoveOptions::buffered())
        .unwrap();
    sim.step(5_000);
    assert_eq!(x.status().unwrap().state, AxisState::SynchronizedMotion);
    let st = g.stop(1e6, 1e8).unwrap();
    assert_eq!(m1.wait(T).unwrap_err().kind(), ErrorKind::Aborted);
    assert_eq!(m2.wait(T).unwrap_err().kind(), ErrorKind::Aborted);
    st.wait(T).unwrap();
    assert_eq!(g.status().unwrap().0, GroupState::Stopping);
    assert_eq!(
        g.move_linear(&[0.0, 0.0], &lim(), MoveOptions::default())
            .err()
            .unwrap()
            .kind(),
        ErrorKind::InvalidState
    );
    let stopped_at = (cmd(&card, 4), cmd(&card, 5));
    // The line from (50000, 0) (where the solo move left X) to (200000, 100000).
    let off_line = (stopped_at.1 - (stopped_at.0 - 50_000.0) * 2.0 / 3.0).abs();
    assert!(
        stopped_at.0 < 200_000.0 && off_line < 1e-6,
        "stopped off the line at {stopped_at:?}"
    );
    g.release_stop().unwrap();
    sim.step(1);
    assert_eq!(g.status().unwrap().0, GroupState::Standby);
    // Halt from motion: back to Standby by itself.
    g.move_linear(&[0.0, 0.0], &lim(), MoveOptions::default())
        .unwrap();
    sim.step(2_000);
    g.halt(5e5, 5e7).unwrap().wait(T).unwrap();
    assert_eq!(g.status().unwrap().0, GroupState::Standby);
    assert_eq!(x.status().unwrap().state, AxisState::Standstill);
    g.disable().unwrap();
    assert_eq!(g.status().unwrap().0, GroupState::Disabled);
    x.move_relative(10.0, &MoveLimits::new(1e5, 1e6, 1e8))
        .unwrap()
        .wait(T)
        .unwrap();
}

#[test]
fn every_group_nack_code_is_provoked() {
    use motioncard_sdk::NackCode as N;
    let mut seen = Vec::new();
    let mut expect = |want: ErrorKind, code: N, got: ErrorKind| {
        assert_eq!(got, want, "{code:?}");
        seen.push(code);
    };
    let (card, g) = group_card(&[0, 1], AccDec::Pre);
    let l = lim();
    let o = MoveOptions::default();
    expect(
        ErrorKind::BadGroup,
        N::BadGroup,
        card.group(9).err().unwrap().kind(),
    );
    let other = card.group(2).unwrap();
    expect(
        ErrorKind::AxisInOtherGroup,
        N::AxisInOtherGroup,
        other
            .configure(&GroupSettings::new(&[1, 2]))
            .unwrap_err()
            .kind(),
    );
    expect(
        ErrorKind::GroupDisabled,
        N::GroupDisabled,
        other.move_linear(&[1.0, 2.0], &l, o).err().unwrap().kind(),
    );
    // The card's own check, below the SDK's: a raw move on a disabled group.
    let raw_move =
        motioncard_sdk::proto::Command::new(motioncard_sdk::proto::Opcode::GroupMoveLinear, 3)
            .with_args(&[1e4, 1e5, 1e5, 1e6, 1.0]);
    let seq = card.send_raw(raw_move).unwrap();
    assert_eq!(card.wait_ack(seq).unwrap(), Err(N::GroupDisabled));
    expect(
        ErrorKind::AxisNotInGroup,
        N::AxisNotInGroup,
        g.move_circular(
            &ArcSpec::Radius {
                end: [1000.0, 1000.0],
                radius: 1000.0,
                ccw: true,
            },
            Plane::YZ,
            &[],
            &l,
            o,
        )
        .err()
        .unwrap()
        .kind(),
    );
    expect(
        ErrorKind::AxisGrouped,
        N::AxisGrouped,
        card.axis(0).unwrap().halt(1e6, 1e7).err().unwrap().kind(),
    );
    expect(
        ErrorKind::ZeroLengthArc,
        N::ZeroLengthArc,
        g.move_circular(
            &ArcSpec::Centre {
                end: [0.0, 0.0],
                centre: [0.0, 0.0],
                ccw: true,
            },
            Plane::XY,
            &[],
            &l,
            o,
        )
        .err()
        .unwrap()
        .kind(),
    );
    expect(
        ErrorKind::CentreNotEquidistant,
        N::CentreNotEquidistant,
        g.move_circular(
            &ArcSpec::Centre {
                end: [1000.0, 0.0],
                centre: [300.0, 0.0],
                ccw: true,
            },
            Plane::XY,
            &[],
            &l,
            o,
        )
        .err()
        .unwrap()
        .kind(),
    );
    expect(
        ErrorKind::RadiusTooSmall,
        N::RadiusTooSmall,
        g.move_circular(
            &ArcSpec::Radius {
                end: [1000.0, 0.0],
                radius: 400.0,
                ccw: true,
            },
            Plane::XY,
            &[],
            &l,
            o,
        )
        .err()
        .unwrap()
        .kind(),
    );
    expect(
        ErrorKind::CollinearPoints,
        N::CollinearPoints,
        g.move_circular(
            &ArcSpec::Border {
                end: [1000.0, 0.0],
                via: [500.0, 0.5],
            },
            Plane::XY,
            &[],
            &l,
            o,
        )
        .err()
        .unwrap()
        .kind(),
    );
    // Queue: one active plus GROUP_QUEUE_LEN waiting, then full.
    let mut full = None;
    for i in 0..40 {
        if let Err(e) = g.move_linear(&[i as f64 * 10.0, 0.0], &l, MoveOptions::buffered()) {
            full = Some(e.kind());
            break;
        }
    }
    expect(ErrorKind::QueueFull, N::QueueFull, full.unwrap());
    expect(
        ErrorKind::InvalidState,
        N::InvalidState,
        g.move_linear(&[0.0, 0.0], &l, o).err().unwrap().kind(),
    );
    // Filters cannot change while they hold distance (post acc/dec, mid-move).
    let (card2, g2) = group_card(&[0, 1], AccDec::Post);
    g2.move_linear(&[100_000.0, 0.0], &l, o).unwrap();
    card2.sim().unwrap().step(100);
    expect(
        ErrorKind::FilterBusy,
        N::FilterBusy,
        card2
            .axis(0)
            .unwrap()
            .set_filters(&FilterSettings::all(FilterKind::Linear, 0.01))
            .unwrap_err()
            .kind(),
    );
    // Kim's reference-word interpolator steps at constant feed: no pre-interpolation S-curve.
    let g3 = card2.group(3).unwrap();
    let bad = GroupSettings {
        interpolator: Interpolator::ReferenceWord,
        accdec: AccDec::Both,
        ..GroupSettings::new(&[6, 7])
    };
    expect(
        ErrorKind::IncompatibleMode,
        N::IncompatibleMode,
        g3.configure(&bad).unwrap_err().kind(),
    );
    // AxisBusy is provoked in group_states_follow_plcopen.
    seen.push(N::AxisBusy);
    for code in motioncard_sdk::NackCode::ALL
        .iter()
        .filter(|c| (16..32).contains(&(**c as i32)))
    {
        assert!(seen.contains(code), "{code:?} never provoked");
    }
}

#[test]
fn filters_conserve_distance_for_every_kind_and_feed_type() {
    let kinds = [
        FilterKind::Linear,
        FilterKind::Exponential,
        FilterKind::Bell,
    ];
    for (i, kind) in kinds.into_iter().enumerate() {
        let (card, g) = group_card(&[0, 1], AccDec::Post);
        g.disable().unwrap();
        for a in 0..2 {
            card.axis(a)
                .unwrap()
                .set_filters(&FilterSettings::all(kind, 0.007 + 0.011 * i as f64))
                .unwrap();
        }
        g.enable().unwrap();
        let target = [12_345.678, -9_876.5];
        g.move_linear(
            &target,
            &PathLimits::new(33_333.3, 1e6, 1e8),
            MoveOptions {
                feed_type: motioncard_sdk::FeedType::Jog,
                ..Default::default()
            },
        )
        .unwrap()
        .wait(T)
        .unwrap();
        for (a, t) in target.iter().enumerate() {
            assert_eq!(cmd(&card, a), *t, "{kind:?}: axis {a}");
        }
        // …and the filter, not the snap, put them there.
        assert_snap(&g, &format!("{kind:?}"));
    }
}

/// Kim §4: linear interpolation through any of the filters has no path error (only rounding);
/// relative targets add to where the previous move ended.
#[test]
fn linear_path_is_exact_through_every_filter_kind_and_relative_moves_chain() {
    for kind in [
        FilterKind::Linear,
        FilterKind::Exponential,
        FilterKind::Bell,
    ] {
        let card = stepped_card();
        for a in 0..2 {
            let ax = card.axis(a).unwrap();
            ax.set_filters(&FilterSettings::all(kind, 0.025)).unwrap();
            ax.enable().unwrap();
        }
        let g = card.group(0).unwrap();
        g.configure(&GroupSettings {
            accdec: AccDec::Post,
            ..GroupSettings::new(&[0, 1])
        })
        .unwrap();
        g.enable().unwrap();
        let sim = card.sim().unwrap();
        let rel = MoveOptions {
            relative: true,
            ..Default::default()
        };
        g.move_linear(&[7_000.0, 3_000.0], &lim(), rel)
            .unwrap()
            .wait(T)
            .unwrap();
        // Second leg, relative: from (7000, 3000) by (-2000, 9000).
        let m = g.move_linear(&[-2_000.0, 9_000.0], &lim(), rel).unwrap();
        let (p0, d) = ((7_000.0, 3_000.0), (-2_000.0f64, 9_000.0f64));
        let len = d.0.hypot(d.1);
        let mut worst: f64 = 0.0;
        while g.status().unwrap().0 == GroupState::Moving {
            sim.step(1);
            let (x, y) = (cmd(&card, 0) - p0.0, cmd(&card, 1) - p0.1);
            worst = worst.max((x * d.1 - y * d.0).abs() / len);
        }
        m.wait(T).unwrap();
        assert!(worst < 1e-7, "{kind:?}: {worst} counts off the line");
        assert_eq!(
            (cmd(&card, 0), cmd(&card, 1)),
            (5_000.0, 12_000.0),
            "{kind:?}"
        );
        assert_snap(&g, &format!("{kind:?}, two relative moves"));
    }
}

/// Commanded (position, velocity, acceleration) of `axes` in counts, every tick until the
/// group is at rest.
fn trace_raw(card: &Card, g: &motioncard_sdk::Group, axes: &[usize]) -> Vec<Vec<(f64, f64, f64)>> {
    let sim = card.sim().unwrap();
    let mut out = Vec::new();
    for _ in 0..2_000_000 {
        sim.step(1);
        out.push(
            axes.iter()
                .map(|&a| {
                    let r = card.axis(a).unwrap().status().unwrap().raw;
                    (r.cmd_pos, r.cmd_vel, r.cmd_acc)
                })
                .collect(),
        );
        if g.status().unwrap().0 != GroupState::Moving {
            break;
        }
    }
    out
}

/// All eight axes of the card in one group: a linear move (with the S-curve, and with the S-curve
/// and the default filters) stays on the line and ends exactly; a helix turns X and Y on the
/// circle while the six other axes move linearly with the swept angle.
#[test]
fn eight_axis_line_and_helix_with_six_linear_axes() {
    let axes: Vec<usize> = (0..8).collect();
    let target = [
        30_000.0, -40_000.0, 12_000.0, 5_000.5, -7_777.0, 100.0, 0.25, 64_000.0,
    ];
    let len = target.iter().map(|x| x * x).sum::<f64>().sqrt();
    for accdec in [AccDec::Pre, AccDec::Both] {
        let (card, g) = group_card(&axes, accdec);
        let m = g
            .move_linear(&target, &lim(), MoveOptions::default())
            .unwrap();
        let pts = trace(&card, &g, &axes);
        m.wait(T).unwrap();
        let worst = pts
            .iter()
            .map(|p| {
                let along = p.iter().zip(&target).map(|(x, t)| x * t).sum::<f64>() / len;
                p.iter()
                    .zip(&target)
                    .map(|(x, t)| (x - along * t / len).powi(2))
                    .sum::<f64>()
                    .sqrt()
            })
            .fold(0.0, f64::max);
        assert!(worst < 1e-6, "{accdec:?}: {worst} counts off the line");
        for (a, t) in target.iter().enumerate() {
            assert_eq!(cmd(&card, a), *t, "{accdec:?}: axis {a}");
        }
        assert_snap(&g, &format!("8-axis line, {accdec:?}"));
    }

    // A helix: a full turn in XY around (r, 0), the six other axes climbing with the angle.
    let (card, g) = group_card(&axes, AccDec::Pre);
    let r = 10_000.0;
    let climb = [5_000.0, -2_500.0, 1_234.5, 10_000.0, -64.0, 0.5];
    let m = g
        .move_circular(
            &ArcSpec::Centre {
                end: [0.0, 0.0],
                centre: [r, 0.0],
                ccw: true,
            },
            Plane::XY,
            &climb,
            &lim(),
            MoveOptions::default(),
        )
        .unwrap();
    let pts = trace(&card, &g, &axes);
    m.wait(T).unwrap();
    let mut prev = 0.0;
    for p in &pts {
        let rad = (p[0] - r).hypot(p[1]);
        assert!((rad - r).abs() < 1e-6, "radius {rad}");
        // Each linear axis is climb · swept / 2π; measure the swept angle from Z (the first)
        // and check the others against it, and the angle against X/Y away from the ends.
        let f = p[2] / climb[0];
        assert!(
            f >= prev - 1e-12 && f <= 1.0 + 1e-12,
            "fraction {f} after {prev}"
        );
        prev = f;
        for (k, c) in climb.iter().enumerate() {
            assert!(
                (p[2 + k] - c * f).abs() <= 1e-6 * c.abs().max(1.0),
                "axis {}: {} vs {}",
                2 + k,
                p[2 + k],
                c * f
            );
        }
        let ang = p[1].atan2(p[0] - r);
        let swept = (ang - std::f64::consts::PI).rem_euclid(std::f64::consts::TAU);
        if f > 1e-3 && f < 1.0 - 1e-3 {
            assert!(
                (swept / std::f64::consts::TAU - f).abs() < 1e-6,
                "swept {swept} rad at fraction {f}"
            );
        }
    }
    // The arc's end is its start angle plus the sweep on the circle: within rounding of the
    // programmed point (the linear axes end exactly).
    assert!(cmd(&card, 0).abs() < 1e-9 && cmd(&card, 1).abs() < 1e-9);
    for (k, c) in climb.iter().enumerate() {
        assert_eq!(cmd(&card, 2 + k), *c, "axis {}", 2 + k);
    }
    assert_snap(&g, "8-axis helix");
}

/// Arcs through the post-interpolation filters (every kind, exact and reference-word
/// interpolators, XY and YZ planes): each commanded point is a weighted mean of earlier points
/// of the arc (the filters' impulse responses are non-negative and sum to 1), so it lies inside
/// the circle, at most the steady-state ΔR of Kim §4 inside; the third axis never moves; the
/// arc ends exactly on its end point, put there by the filters (snap within SNAP_BOUND).
#[test]
fn arcs_through_post_filters_stay_inside_the_circle_and_end_exactly() {
    use card_emu::motion::arc::{exponential_filter_radial_error, linear_filter_radial_error};
    use card_emu::motion::filters::exponential_pole;
    let (r, tau, ts) = (20_000.0, 0.025, 1e-4);
    let v = lim().velocity;
    let dr_lin = linear_filter_radial_error(r, v, ts, (tau / ts).round() as usize);
    let dr_exp = exponential_filter_radial_error(r, v, ts, exponential_pole(tau, ts));
    for kind in [
        FilterKind::Linear,
        FilterKind::Exponential,
        FilterKind::Bell,
    ] {
        let steady = match kind {
            FilterKind::Linear => dr_lin,
            FilterKind::Exponential => dr_exp,
            // Linear then exponential: the gains multiply.
            _ => r - (r - dr_lin) * (r - dr_exp) / r,
        };
        for interp in [Interpolator::Exact, Interpolator::ReferenceWord] {
            for (plane, (u, v)) in [(Plane::XY, (0, 1)), (Plane::YZ, (1, 2))] {
                let card = stepped_card();
                for a in 0..3 {
                    let ax = card.axis(a).unwrap();
                    ax.set_filters(&FilterSettings::all(kind, tau)).unwrap();
                    ax.enable().unwrap();
                }
                let g = card.group(0).unwrap();
                g.configure(&GroupSettings {
                    accdec: AccDec::Post,
                    interpolator: interp,
                    ..GroupSettings::new(&[0, 1, 2])
                })
                .unwrap();
                g.enable().unwrap();
                // Three quarters clockwise around (-r, 0), from the origin to (-r, r).
                let m = g
                    .move_circular(
                        &ArcSpec::Centre {
                            end: [-r, r],
                            centre: [-r, 0.0],
                            ccw: false,
                        },
                        plane,
                        &[],
                        &lim(),
                        MoveOptions::default(),
                    )
                    .unwrap();
                let pts = trace(&card, &g, &[u, v, 3 - u - v]);
                m.wait(T).unwrap();
                let what = format!("{kind:?} {interp:?} {plane:?}");
                let (mut outer, mut inner) = (0.0f64, 0.0f64);
                for p in &pts {
                    let d = (p[0] + r).hypot(p[1]) - r;
                    outer = outer.max(d);
                    inner = inner.max(-d);
                    assert_eq!(p[2], 0.0, "{what}: the third axis moved");
                }
                assert!(outer <= 1e-6, "{what}: {outer} counts outside the circle");
                assert!(
                    inner <= steady * 1.01 + 1e-6 && inner >= 0.9 * steady,
                    "{what}: {inner} counts inside, steady-state ΔR {steady}"
                );
                let end = (cmd(&card, u), cmd(&card, v));
                assert!(
                    (end.0 + r).abs() < 1e-9 && (end.1 - r).abs() < 1e-9,
                    "{what}: ended at {end:?}"
                );
                assert_snap(&g, &what);
            }
        }
    }
}

/// Synchronised point-to-point with each axis's own limits (Kim eq 10–14): the axis that needs
/// the most time within its limits sets it, the others scale, every axis stays within its own
/// limits, and all start and end on the same tick.
#[test]
fn ptp_with_per_axis_limits_the_slowest_axis_sets_the_time() {
    let alone = common::rest_to_rest_time;
    let fast = PathLimits::new(100_000.0, 1e6, 5e7);
    // Y (scale 2 counts per unit) is the tightest in every limit once scaled to X's distance.
    let slow_y = PathLimits::new(2_000.0, 2e4, 1e6);
    // A mixed case: Y limits the acceleration, Z the velocity.
    let low_acc_y = PathLimits::new(100_000.0, 2e4, 5e7);
    let low_vel_z = PathLimits::new(4_000.0, 1e6, 5e7);
    let target = [80_000.0, -10_000.0, 20_000.0];
    for (name, limits) in [
        ("slow y", [fast, slow_y, fast]),
        ("y acceleration, z velocity", [fast, low_acc_y, low_vel_z]),
    ] {
        let (card, g) = group_card(&[0, 1, 2], AccDec::Pre);
        g.disable().unwrap();
        card.axis(1).unwrap().set_scale(2.0).unwrap();
        g.enable().unwrap();
        let user_target = [target[0], target[1] / 2.0, target[2]];
        let m = g
            .move_ptp_axes(&user_target, &limits, MoveOptions::default())
            .unwrap();
        let tr = trace_raw(&card, &g, &[0, 1, 2]);
        m.wait(T).unwrap();
        // Limits in counts: axis 1's user units are 2 counts.
        let counts = |a: usize, x: f64| if a == 1 { 2.0 * x } else { x };
        let solo: Vec<f64> = (0..3)
            .map(|a| {
                let l = limits[a];
                let c = PathLimits {
                    velocity: counts(a, l.velocity),
                    acceleration: counts(a, l.acceleration),
                    deceleration: counts(a, l.deceleration),
                    jerk: counts(a, l.jerk),
                };
                alone(&c, target[a])
            })
            .collect();
        let longest = solo.iter().copied().fold(0.0, f64::max);
        let (mut first, mut last) = ([None; 3], [0usize; 3]);
        let (mut vpeak, mut apeak) = ([0.0f64; 3], [0.0f64; 3]);
        for (k, row) in tr.iter().enumerate() {
            for (a, &(_, v, acc)) in row.iter().enumerate() {
                if v != 0.0 {
                    first[a].get_or_insert(k);
                    last[a] = k;
                }
                vpeak[a] = vpeak[a].max(v.abs());
                apeak[a] = apeak[a].max(acc.abs());
            }
        }
        assert!(
            first.iter().all(|f| *f == first[0] && f.is_some())
                && last.iter().all(|l| *l == last[0]),
            "{name}: start ticks {first:?}, end ticks {last:?}"
        );
        for a in 0..3 {
            let l = limits[a];
            assert!(
                vpeak[a] <= counts(a, l.velocity) * (1.0 + 1e-9),
                "{name}: axis {a} velocity {} over {}",
                vpeak[a],
                counts(a, l.velocity)
            );
            assert!(
                apeak[a] <= counts(a, l.acceleration) * (1.0 + 1e-6),
                "{name}: axis {a} acceleration {} over {}",
                apeak[a],
                counts(a, l.acceleration)
            );
            assert_eq!(cmd(&card, a), target[a], "{name}: axis {a} end");
        }
        let time = (last[0] + 1 - first[0].unwrap()) as f64 * 1e-4;
        // Never faster than the slowest axis alone.
        assert!(
            time >= longest - 2e-4,
            "{name}: {time} s, slowest alone {longest} s"
        );
        if name == "slow y" {
            // Y is the tightest in every limit: the move takes exactly Y's own time, Y runs
            // at its limits and X scales (8×).
            assert!(
                (time - solo[1]).abs() <= 2e-4,
                "{time} vs y alone {}",
                solo[1]
            );
            assert!(solo[1] > solo[0] && solo[1] > solo[2], "{solo:?}");
            assert!((vpeak[1] - 4_000.0).abs() < 1e-6, "{vpeak:?}");
            assert!((vpeak[0] - 8.0 * vpeak[1]).abs() < 1e-6, "{vpeak:?}");
        } else {
            // Each binding axis reaches its own limit.
            assert!((vpeak[2] - 4_000.0).abs() < 1e-6, "{vpeak:?}");
            // Y's own acceleration limit, 2e4 units/s² = 4e4 counts/s².
            assert!(apeak[1] > 0.99 * 4e4, "{apeak:?}");
        }
        assert_snap(&g, name);
    }

    // The same limits for every axis through move_ptp_axes is move_ptp.
    let (card, g) = group_card(&[0, 1], AccDec::Pre);
    let sim = card.sim().unwrap();
    let t0 = sim.time();
    g.move_ptp(&[50_000.0, 10_000.0], &fast, MoveOptions::default())
        .unwrap()
        .wait(T)
        .unwrap();
    let common = sim.time() - t0;
    let t0 = sim.time();
    g.move_ptp_axes(&[0.0, 0.0], &[fast, fast], MoveOptions::default())
        .unwrap()
        .wait(T)
        .unwrap();
    assert!(((sim.time() - t0) - common).abs() < 1e-3);

    // Refusals: the SDK's and the card's own.
    use motioncard_sdk::proto::{Command, MoveFlags, Opcode};
    use motioncard_sdk::NackCode as N;
    assert_eq!(
        g.move_ptp_axes(&[1.0, 1.0], &[fast], MoveOptions::default())
            .err()
            .unwrap()
            .kind(),
        ErrorKind::BadAxis
    );
    let raw = |op: Opcode, flags: u32, args: &[f64]| {
        let mut c = Command::new(op, 0).with_args(args);
        c.flags = flags;
        card.wait_ack(card.send_raw(c).unwrap()).unwrap()
    };
    let ptp_args = [1e4, 1e5, 1e5, 1e6, 100.0, 100.0];
    // The flag without every axis staged.
    assert_eq!(
        raw(
            Opcode::GroupMovePtp,
            MoveFlags::PTP_AXIS_LIMITS.bits(),
            &ptp_args
        ),
        Err(N::BadConfig)
    );
    assert_eq!(
        raw(Opcode::GroupPtpLimits, 0, &[0.0, 1.0, 1e4, 1e5, 1e5, 1e6]),
        Ok(())
    );
    assert_eq!(
        raw(
            Opcode::GroupMovePtp,
            MoveFlags::PTP_AXIS_LIMITS.bits(),
            &ptp_args
        ),
        Err(N::BadConfig),
        "axis 1 was not staged"
    );
    // Any point-to-point command consumes what was staged.
    assert_eq!(
        raw(
            Opcode::GroupPtpLimits,
            0,
            &[0.0, 2.0, 1e4, 1e5, 1e5, 1e6, 1e4, 1e5, 1e5, 1e6]
        ),
        Ok(())
    );
    assert_eq!(
        raw(Opcode::GroupMovePtp, 0, &[0.0; 6]),
        Err(N::NonPositiveLimit)
    );
    assert_eq!(
        raw(
            Opcode::GroupMovePtp,
            MoveFlags::PTP_AXIS_LIMITS.bits(),
            &ptp_args
        ),
        Err(N::BadConfig)
    );
    assert_eq!(
        raw(
            Opcode::GroupPtpLimits,
            0,
            &[1.0, 2.0, 1e4, 1e5, 1e5, 1e6, 1e4, 1e5, 1e5, 1e6]
        ),
        Err(N::AxisNotInGroup)
    );
    assert_eq!(
        raw(Opcode::GroupPtpLimits, 0, &[0.0, 0.0]),
        Err(N::BadConfig)
    );
    assert_eq!(
        raw(Opcode::GroupPtpLimits, 0, &[0.0, 4.0]),
        Err(N::BadConfig)
    );
    assert_eq!(
        raw(Opcode::GroupPtpLimits, 0, &[0.5, 1.0, 1e4, 1e5, 1e5, 1e6]),
        Err(N::BadConfig)
    );
    assert_eq!(
        raw(Opcode::GroupPtpLimits, 0, &[0.0, 1.0, 1e4, -1e5, 1e5, 1e6]),
        Err(N::NonPositiveLimit)
    );
    assert_eq!(
        raw(
            Opcode::GroupPtpLimits,
            0,
            &[0.0, 1.0, 1e4, f64::NAN, 1e5, 1e6]
        ),
        Err(N::NotFinite)
    );
    let other = card.group(2).unwrap();
    assert_eq!(
        other
            .move_ptp_axes(&[1.0], &[fast], MoveOptions::default())
            .err()
            .unwrap()
            .kind(),
        ErrorKind::GroupDisabled
    );
    // Staged limits and the flag, both axes: accepted, and the move runs.
    assert_eq!(
        raw(
            Opcode::GroupPtpLimits,
            0,
            &[0.0, 2.0, 1e4, 1e5, 1e5, 1e6, 1e3, 1e5, 1e5, 1e6]
        ),
        Ok(())
    );
    assert_eq!(
        raw(
            Opcode::GroupMovePtp,
            MoveFlags::PTP_AXIS_LIMITS.bits(),
            &ptp_args
        ),
        Ok(())
    );
    g.wait_done(T).ok();
    card.sim().unwrap().step(20_000);
    assert_eq!(g.status().unwrap().0, GroupState::Standby);
    assert_eq!((cmd(&card, 0), cmd(&card, 1)), (100.0, 100.0));
}

/// A group motion counts in its members' own statistics, as a move of their own would: the
/// move count, the peaks (within the path's limits), the following error, and why it ended.
#[test]
fn members_keep_statistics_of_their_group_motions() {
    let (card, g) = group_card(&[0, 1], AccDec::Pre);
    let (x, y) = (card.axis(0).unwrap(), card.axis(1).unwrap());
    g.move_linear(&[30_000.0, 40_000.0], &lim(), MoveOptions::default())
        .unwrap();
    g.wait_done(T).unwrap();
    for (ax, share) in [(&x, 0.6), (&y, 0.8)] {
        let s = ax.status().unwrap();
        assert_eq!(s.raw.move_count, 1);
        assert_eq!(s.stop_reason(), Some(motioncard_sdk::StopReason::Done));
        // Each axis's share of the 50,000 counts/s feed along the 3-4-5 line.
        let v = 50_000.0 * share;
        assert!(
            (s.raw.peak_vel - v).abs() <= v * 1e-6,
            "peak {} vs {v}",
            s.raw.peak_vel
        );
        assert!(s.raw.peak_acc <= 5e5 * share * (1.0 + 1e-6) && s.raw.peak_acc > 0.0);
        assert!(s.raw.max_ferr > 0.0 && s.raw.max_ferr < 50.0);
        assert!(s.raw.move_time > 1.0);
    }
    // A halt of the group ends its members' motion with the halt as the reason.
    g.move_linear(&[330_000.0, 440_000.0], &lim(), MoveOptions::default())
        .unwrap();
    card.sim().unwrap().step(5_000);
    g.halt(5e5, 5e7).unwrap().wait(T).unwrap();
    let s = x.status().unwrap();
    assert_eq!(s.raw.move_count, 2);
    assert_eq!(s.stop_reason(), Some(motioncard_sdk::StopReason::Halt));
}

/// Path limits outside what the card accepts are refused, for lines, halts and point-to-point
/// moves alike (subnormal, absurdly small or large).
#[test]
fn group_limits_outside_the_cards_range_are_refused() {
    let (_card, g) = group_card(&[0, 1], AccDec::Pre);
    for bad in [
        PathLimits::new(50_000.0, 5e5, 1e-300),
        PathLimits::new(50_000.0, 5e-324, 5e7),
        PathLimits::new(1e300, 5e5, 5e7),
    ] {
        assert_eq!(
            g.move_linear(&[100.0, 100.0], &bad, MoveOptions::default())
                .unwrap_err()
                .kind(),
            ErrorKind::LimitRange,
            "{bad:?}"
        );
    }
    assert_eq!(
        g.halt(5e5, 1e-300).unwrap_err().kind(),
        ErrorKind::LimitRange
    );
    assert_eq!(g.status().unwrap().0, GroupState::Standby);
}

/// The group override (pre-interpolation S-curve): 50 % at cruise brings the path speed to half
/// along the path within its acceleration (no stop, the path stays on the line); 0 % holds the
/// group on its path in Moving; 200 % resumes at twice the feed; the move ends exactly on its
/// target. The rapid override applies to point-to-point moves only.
#[test]
fn group_override_scales_the_path_speed_and_holds_at_zero() {
    let (card, g) = group_card(&[0, 1], AccDec::Pre);
    let sim = card.sim().unwrap();
    let target = [300_000.0, -400_000.0];
    let l = lim(); // 50,000 counts/s along the path
    let m = g.move_linear(&target, &l, MoveOptions::default()).unwrap();
    sim.step(5_000);
    let feed = |g: &motioncard_sdk::Group| g.status().unwrap().1.feed;
    assert_eq!(feed(&g), l.velocity);
    g.set_override(0.5, 1.0).unwrap();
    let mut slowest = f64::MAX;
    let mut prev = feed(&g);
    for _ in 0..20_000 {
        sim.step(1);
        let f = feed(&g);
        // (per tick: at most the path acceleration)
        assert!((f - prev).abs() <= l.acceleration * 1e-4 * (1.0 + 1e-6) + 1e-6);
        prev = f;
        slowest = slowest.min(f);
        if g.status().unwrap().1.feed_acc == 0.0 && f <= 0.5 * l.velocity * (1.0 + 1e-9) {
            break;
        }
    }
    assert!((feed(&g) - 0.5 * l.velocity).abs() < 1e-6, "{}", feed(&g));
    assert!(slowest >= 0.5 * l.velocity * (1.0 - 1e-9), "{slowest}");
    assert_eq!(g.status().unwrap().1.feed_override, 0.5);
    g.set_override(0.0, 1.0).unwrap();
    sim.step(5_000);
    let held = (cmd(&card, 0), cmd(&card, 1));
    sim.step(1_000);
    assert_eq!((cmd(&card, 0), cmd(&card, 1)), held);
    assert_eq!(g.status().unwrap().0, GroupState::Moving);
    // On the line: 4 x + 3 y = 0.
    assert!((4.0 * held.0 + 3.0 * held.1).abs() < 1e-6);
    // Out of range: refused, nothing changes.
    let e = g.set_override(2.5, 1.0).unwrap_err();
    assert_eq!(e.kind(), ErrorKind::OverrideRange);
    assert_eq!(g.status().unwrap().1.feed_override, 0.0);
    g.set_override(2.0, 1.0).unwrap();
    let mut fastest: f64 = 0.0;
    while g.status().unwrap().0 == GroupState::Moving {
        sim.step(1);
        fastest = fastest.max(feed(&g));
    }
    assert!((fastest - 2.0 * l.velocity).abs() < 1e-6, "{fastest}");
    m.wait(T).unwrap();
    assert_eq!((cmd(&card, 0), cmd(&card, 1)), (target[0], target[1]));
    // The rapid override is the one point-to-point moves take.
    g.set_override(1.0, 0.25).unwrap();
    let p = g.move_ptp(&[0.0, 0.0], &l, MoveOptions::default()).unwrap();
    let mut peak: f64 = 0.0;
    while g.status().unwrap().0 == GroupState::Moving {
        sim.step(1);
        peak = peak.max(card.axis(1).unwrap().status().unwrap().raw.cmd_vel.abs());
    }
    p.wait(T).unwrap();
    assert!(peak <= 0.25 * l.velocity * (1.0 + 1e-9), "{peak}");
    assert!(peak >= 0.25 * l.velocity * (1.0 - 1e-9), "{peak}");
}
