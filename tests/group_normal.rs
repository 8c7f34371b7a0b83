//! Layout 1.13: MC_MoveCircular in a plane given by a normal vector, in the group's move queue
//! (`Group::move_circular_normal`), on the stepped emulated card: every tick's commanded point
//! on its circle or helix in the rotated plane, the sweep and the rest-to-rest time along the
//! whole length, every axis within the move's limits, the end reached exactly; the same end
//! as the path buffer's arc of the same geometry; every refusal with its code and nothing
//! queued by it.
mod common;

use common::{rest_to_rest_time, stepped_card};
use motioncard_sdk::proto::{Command, Opcode};
use motioncard_sdk::NackCode;
use motioncard_sdk::{
    AccDec, Card, ErrorKind, Group, GroupSettings, GroupState, MoveOptions, NormalArc, PathItem,
    PathLimits, PathSettings, Segment, Timing,
};
use std::f64::consts::{PI, TAU};
use std::time::Duration;

const T: Duration = Duration::from_secs(60);

type P3 = [f64; 3];

fn dot(a: P3, b: P3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross(a: P3, b: P3) -> P3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn unit(a: P3) -> P3 {
    let m = dot(a, a).sqrt();
    [a[0] / m, a[1] / m, a[2] / m]
}

/// A card of four axes (counts) with group 0 over them (S-curve feed only), enabled.
fn card4() -> (Card, Group) {
    let card = stepped_card();
    for a in 0..4 {
        card.axis(a).unwrap().enable().unwrap();
    }
    let g = card.group(0).unwrap();
    g.configure(&GroupSettings {
        accdec: AccDec::Pre,
        ..GroupSettings::new(&[0, 1, 2, 3])
    })
    .unwrap();
    g.enable().unwrap();
    (card, g)
}

fn lim() -> PathLimits {
    PathLimits::new(20_000.0, 4e5, 4e7)
}

/// One tick of the group's axes: commanded (position, velocity, acceleration), counts.
type Tick = Vec<(f64, f64, f64)>;

/// Every tick until the group is at rest.
fn trace(card: &Card, g: &Group) -> Vec<Tick> {
    let sim = card.sim().unwrap();
    let mut out = Vec::new();
    for _ in 0..2_000_000 {
        sim.step(1);
        out.push(
            (0..4)
                .map(|a| {
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

/// One arc of the test: the plane's group axes, the normal, the swept angle (radians, more
/// than 2π for added turns), the rise along the normal, the linear axis's target.
struct Case {
    axes: [usize; 3],
    normal: P3,
    sweep: f64,
    rise: f64,
    w1: f64,
}

/// Three oblique arcs from the origin, radius 5,000, the group's fourth axis (the one off the
/// plane) moving linearly: a quarter turn and a turn added about (1, −2, 2), 0.6 turn rising
/// −2,500 along (0, 3, −4), and a full turn (end at the start) with a turn added rising 800
/// along (−0.3, 1, 0.2) in the plane of group axes 2, 0, 3 (the linear axis is then 1).
/// Every tick: the commanded point is on the cylinder (its distance from the circle's axis R
/// within 1e-6 relative) at the height along the normal the linear axis's share gives (the
/// plane for no rise; 1e-6 of R), the angle never turns clockwise about the normal, and all
/// of it sums to the sweep; the run takes the rest-to-rest S-curve time of the whole length
/// √((R·sweep)² + rise² + w²) (within two ticks); every axis's velocity is within the feed and
/// its acceleration within √(a² + (v²/R)²) (the limits are along the path, as
/// MC_MoveCircular's: the centripetal part comes on top); the end is reached exactly (the
/// snap corrects nothing).
#[test]
fn oblique_circles_and_helices_stay_on_their_circle_within_the_limits() {
    let r = 5_000.0;
    let cases = [
        Case {
            axes: [0, 1, 2],
            normal: [1.0, -2.0, 2.0],
            sweep: 1.25 * TAU,
            rise: 0.0,
            w1: 3_000.0,
        },
        Case {
            axes: [0, 1, 2],
            normal: [0.0, 3.0, -4.0],
            sweep: 0.6 * TAU,
            rise: -2_500.0,
            w1: -7_000.0,
        },
        Case {
            axes: [2, 0, 3],
            normal: [-0.3, 1.0, 0.2],
            sweep: 2.0 * TAU,
            rise: 800.0,
            w1: 1_500.0,
        },
    ];
    let l = lim();
    for (k, c) in cases.iter().enumerate() {
        let (card, g) = card4();
        let nh = unit(c.normal);
        // a radius in the plane (any vector off the normal, its normal part taken out), and
        // the one a quarter turn on counter-clockwise about n̂
        let q = if nh[0].abs() < 0.9 {
            [1.0, 0.0, 0.0]
        } else {
            [0.0, 1.0, 0.0]
        };
        let d = dot(q, nh);
        let u = unit([q[0] - d * nh[0], q[1] - d * nh[1], q[2] - d * nh[2]]);
        let w = cross(nh, u);
        let centre = [-r * u[0], -r * u[1], -r * u[2]];
        let turns = (c.sweep / TAU).floor() as u32 - u32::from(c.sweep % TAU == 0.0);
        let th = c.sweep - TAU * turns as f64;
        let (s, co) = th.sin_cos();
        let end: P3 =
            core::array::from_fn(|i| centre[i] + r * (co * u[i] + s * w[i]) + c.rise * nh[i]);
        let arc = NormalArc {
            axes: c.axes,
            normal: c.normal,
            centre,
            end,
            rise: c.rise != 0.0,
            turns,
        };
        let lin = (0..4).find(|i| !c.axes.contains(i)).unwrap();
        let m = g
            .move_circular_normal(&arc, &[c.w1], &l, MoveOptions::default())
            .unwrap();
        let pts = trace(&card, &g);
        m.wait(T).unwrap();
        let on = |p: &Tick| -> P3 { core::array::from_fn(|i| p[c.axes[i]].0 - centre[i]) };
        let (mut worst_r, mut worst_h) = (0.0f64, 0.0f64);
        let (mut swept, mut last) = (0.0, 0.0);
        for (t, p) in pts.iter().enumerate() {
            let dv = on(p);
            let h = dot(dv, nh);
            let radial: P3 = core::array::from_fn(|i| dv[i] - h * nh[i]);
            worst_r = worst_r.max((dot(radial, radial).sqrt() - r).abs() / r);
            let share = p[lin].0 / c.w1;
            worst_h = worst_h.max((h - share * c.rise).abs() / r);
            let ang = dot(dv, w).atan2(dot(dv, u));
            let step = (ang - last + 3.0 * PI).rem_euclid(TAU) - PI;
            assert!(
                step >= -1e-12,
                "case {k}: turned clockwise by {step} at tick {t}"
            );
            swept += step;
            last = ang;
        }
        assert!(
            worst_r <= 1e-6 && worst_h <= 1e-6,
            "case {k}: radius {worst_r}, height {worst_h} (relative)"
        );
        assert!(
            (swept - c.sweep).abs() < 1e-9,
            "case {k}: swept {swept}, want {}",
            c.sweep
        );
        // the end exactly (the programmed end: on the circle; the snap corrected nothing)
        let last_p = pts.last().unwrap();
        for (&a, e) in c.axes.iter().zip(&end) {
            let p = last_p[a].0;
            assert!(
                (p - e).abs() <= 1e-9,
                "case {k}: axis {a} ended at {p}, not {e}"
            );
        }
        assert_eq!(last_p[lin].0, c.w1, "case {k}");
        let st = g.status().unwrap().1;
        assert!(st.snap_max <= 1e-12, "case {k}: snap {}", st.snap_max);
        // the S-curve of the whole length, rest to rest
        let len = ((r * c.sweep).powi(2) + c.rise * c.rise + c.w1 * c.w1).sqrt();
        let want = rest_to_rest_time(&l, len) * 10_000.0;
        // (the last tick that moved a commanded position: the group stands by once in position)
        let moving = pts
            .windows(2)
            .rposition(|t| t[0] != t[1])
            .map_or(0, |i| i + 2);
        let ticks = moving as f64;
        assert!(
            (ticks - want).abs() <= 2.0,
            "case {k}: {ticks} ticks, want {want}"
        );
        // every axis within the move's limits (and the centripetal acceleration)
        let a_bound = l.acceleration.hypot(l.velocity * l.velocity / r);
        let (mut vmax, mut amax) = (0.0f64, 0.0f64);
        for p in &pts {
            for x in p {
                vmax = vmax.max(x.1.abs());
                amax = amax.max(x.2.abs());
            }
        }
        assert!(
            vmax <= l.velocity * (1.0 + 1e-9),
            "case {k}: an axis at {vmax} counts/s"
        );
        assert!(
            amax <= a_bound * (1.0 + 1e-3),
            "case {k}: an axis at {amax} counts/s², bound {a_bound}"
        );
        println!(
            "case {k}: {moving} ticks, worst radius {worst_r:.1e}, height {worst_h:.1e}, \
             fastest axis {vmax:.1} counts/s, {amax:.0} counts/s² (bound {a_bound:.0})"
        );
    }
}

/// The same helix through the path buffer (`Segment::arc_normal`, one segment, exact stop)
/// ends on the same point, bit for bit (the card builds both with one geometry), and its
/// points lie on the same circle within 1e-6 relative.
#[test]
fn the_same_end_as_the_path_buffers_arc() {
    let normal = [1.0, 1.0, 2.0];
    let nh = unit(normal);
    let r = 4_000.0;
    let u = unit([1.0, -1.0, 0.0]);
    let w = cross(nh, u);
    let centre = [-r * u[0], -r * u[1], -r * u[2]];
    let end: P3 = core::array::from_fn(|i| {
        centre[i] - r * u[i] * 0.5 + r * w[i] * 0.75f64.sqrt() + 600.0 * nh[i]
    });
    let arc = NormalArc {
        axes: [0, 1, 2],
        normal,
        centre,
        end,
        rise: true,
        turns: 0,
    };
    let (card, g) = card4();
    g.move_circular_normal(&arc, &[2_000.0], &lim(), MoveOptions::default())
        .unwrap()
        .wait(T)
        .unwrap();
    let moved: Vec<f64> = (0..4)
        .map(|a| card.axis(a).unwrap().status().unwrap().raw.cmd_pos)
        .collect();

    let (card, g) = card4();
    g.configure_path(&PathSettings::uniform(4, 50_000.0, 5e5, 5e7))
        .unwrap();
    let mut seg = Segment::arc_normal(1, [0, 1, 2], normal, centre, end, 20_000.0, 0.0).last();
    if let motioncard_sdk::Geometry::ArcNormal { rise, helix, .. } = &mut seg.geometry {
        *rise = true;
        *helix = vec![2_000.0];
    }
    g.path_push(&PathItem::from(seg)).unwrap();
    let pts = trace(&card, &g);
    g.wait_done(T).unwrap();
    let pathed: Vec<f64> = (0..4)
        .map(|a| card.axis(a).unwrap().status().unwrap().raw.cmd_pos)
        .collect();
    assert_eq!(moved, pathed, "the move's end and the path's");
    for p in &pts {
        let dv: P3 = core::array::from_fn(|i| p[i].0 - centre[i]);
        let h = dot(dv, nh);
        let radial: P3 = core::array::from_fn(|i| dv[i] - h * nh[i]);
        let e = (dot(radial, radial).sqrt() - r).abs() / r;
        assert!(e <= 1e-6, "the path's point {p:?} off the circle by {e}");
    }
}

/// Every refusal: the card's (a zero normal, an axis twice or not whole, the centre off the
/// plane, the end off the plane without a rise, the end off the circle, a zero radius, a turn
/// count not whole, a piece of the move alone, a disabled group) and the SDK's (an axis beyond
/// the group, a wrong count of helix targets, a NaN, unequal scales on the three axes, inside
/// a timing); each leaves nothing queued and nothing moved.
#[test]
fn every_refusal_of_a_normal_vector_arc_move() {
    let (card, g) = card4();
    let r = 3_000.0;
    let ok = NormalArc::new(
        [0, 1, 2],
        [0.0, 0.0, 1.0],
        [-r, 0.0, 0.0],
        [-2.0 * r, 0.0, 0.0],
    );
    let o = MoveOptions::default;
    let refused = |arc: NormalArc, helix: &[f64]| {
        let e = g
            .move_circular_normal(&arc, helix, &lim(), o())
            .unwrap_err();
        let (state, st) = g.status().unwrap();
        assert_eq!((state, st.queued), (GroupState::Standby, 0), "{arc:?}");
        e.kind()
    };
    let with = |f: &dyn Fn(&mut NormalArc)| {
        let mut a = ok;
        f(&mut a);
        a
    };
    assert_eq!(
        refused(with(&|a| a.normal = [0.0; 3]), &[]),
        ErrorKind::ArcNormal
    );
    assert_eq!(
        refused(with(&|a| a.axes = [0, 1, 1]), &[]),
        ErrorKind::ArcAxes
    );
    assert_eq!(
        refused(with(&|a| a.centre[2] = 5.0), &[]),
        ErrorKind::ArcOffPlane
    );
    assert_eq!(
        refused(with(&|a| a.end[2] = 5.0), &[]),
        ErrorKind::ArcOffPlane
    );
    assert_eq!(
        refused(with(&|a| a.end[0] = -2.0 * r - 5.0), &[]),
        ErrorKind::CentreNotEquidistant
    );
    assert_eq!(
        refused(with(&|a| a.centre = [0.0; 3]), &[]),
        ErrorKind::ZeroLengthArc
    );
    assert_eq!(
        refused(with(&|a| a.axes = [0, 1, 4]), &[]),
        ErrorKind::BadAxis
    );
    assert_eq!(refused(ok, &[1.0, 2.0]), ErrorKind::BadAxis);
    assert_eq!(
        refused(with(&|a| a.normal[1] = f64::NAN), &[]),
        ErrorKind::NotFinite
    );
    // A piece alone, sent raw: the card refuses it (the SDK sends the two together).
    let lone = |op: Opcode, args: &[f64]| {
        let c = Command::new(op, 0).with_args(args);
        card.wait_ack(card.send_raw(c).unwrap()).unwrap()
    };
    assert_eq!(
        lone(Opcode::GroupCircularPlane, &[0.0, 1.0, 2.0, 0.0, 0.0, 1.0]),
        Err(NackCode::ArcPiece)
    );
    let mv = [2e4, 4e5, 4e5, 4e7, -r, 0.0, 0.0, -2.0 * r, 0.0, 0.0, 0.0];
    assert_eq!(
        lone(Opcode::GroupMoveCircularNormal, &mv),
        Err(NackCode::ArcPiece)
    );
    // A turn count that is not whole (raw: the SDK's is a u32), with its plane.
    // (The SDK cannot send one; the firmware's tests cover it.)
    // Inside a timing: the card times one entry.
    let at = Timing {
        tick: card.tick().unwrap() + 1_000,
        key: 0,
    };
    let e = card
        .timed(at, || g.move_circular_normal(&ok, &[], &lim(), o()))
        .err()
        .unwrap();
    assert_eq!(e.kind(), ErrorKind::Unsupported, "{e}");
    // Unequal scales on the plane's axes.
    card.axis(2).unwrap().set_scale(10.0).unwrap();
    assert_eq!(refused(ok, &[]), ErrorKind::Unsupported);
    card.axis(2).unwrap().set_scale(1.0).unwrap();
    // Nothing moved; the move itself goes through.
    for a in 0..4 {
        assert_eq!(card.axis(a).unwrap().status().unwrap().raw.cmd_pos, 0.0);
    }
    g.move_circular_normal(&ok, &[], &lim(), o())
        .unwrap()
        .wait(T)
        .unwrap();
    let x = card.axis(0).unwrap().status().unwrap().raw.cmd_pos;
    assert!((x + 2.0 * r).abs() < 1e-9, "ended at {x}");
    // A disabled group.
    g.disable().unwrap();
    assert_eq!(
        g.move_circular_normal(&ok, &[], &lim(), o())
            .unwrap_err()
            .kind(),
        ErrorKind::GroupDisabled
    );
}
