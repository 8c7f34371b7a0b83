//! Arcs in a plane given by a normal vector (`Geom::ArcNormal`, layout 1.12): every point on
//! the circle and in the plane, the length r·θ (with a helix's linear part), every axis
//! within its limits, and the same motion as the plane arc of two axes when the normal is an
//! axis.

use super::tests::{arc_xy, line, path, pt, Run, TS};
use super::*;

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

/// `v` turned by `th` about the unit `k` (Rodrigues).
fn rotate(v: P3, k: P3, th: f64) -> P3 {
    let (s, c) = th.sin_cos();
    let kv = cross(k, v);
    let kd = dot(k, v) * (1.0 - c);
    [
        v[0] * c + kv[0] * s + k[0] * kd,
        v[1] * c + kv[1] * s + k[1] * kd,
        v[2] * c + kv[2] * s + k[2] * kd,
    ]
}

fn arc_normal(id: u32, normal: P3, centre: P3, end: V, rise: bool, feed: f64) -> Segment {
    Segment {
        id,
        geom: Geom::ArcNormal {
            axes: [0, 1, 2],
            normal,
            centre,
            rise,
            end,
        },
        feed,
        transition: Transition::MaxDeviation(20.0),
        blend: BlendSpeed::Low,
        last: true,
    }
}

/// An oblique arc of `theta` about `normal` from `p0` (x, y, z and a fourth axis moving to
/// `w1`), radius `r`, rising `rise` along the normal: its segment, end and centre.
fn oblique(p0: V, normal: P3, r: f64, theta: f64, rise: f64, w1: f64) -> (Segment, V, P3) {
    let nh = unit(normal);
    // a radius in the plane: any vector off the normal with its normal part taken out
    let q = if nh[0].abs() < 0.9 {
        [1.0, 0.0, 0.0]
    } else {
        [0.0, 1.0, 0.0]
    };
    let d = dot(q, nh);
    let u = unit([q[0] - d * nh[0], q[1] - d * nh[1], q[2] - d * nh[2]]);
    let c = [p0[0] - r * u[0], p0[1] - r * u[1], p0[2] - r * u[2]];
    let ru = rotate([r * u[0], r * u[1], r * u[2]], nh, theta);
    let mut end = p0;
    for k in 0..3 {
        end[k] = c[k] + ru[k] + rise * nh[k];
    }
    end[3] = w1;
    (arc_normal(1, normal, c, end, rise != 0.0, 5e4), end, c)
}

/// Every tick's point of an oblique circle and helix lies on its cylinder (radius within
/// 1e-6 counts) at the height the arc length gives it along the normal (in the plane for a
/// circle), the fourth axis moves linearly with it, the segment's length is
/// √((r·θ)² + rise² + w²), every axis keeps its velocity, acceleration and jerk limit, and
/// the end is reached exactly.
#[test]
fn oblique_arcs_keep_their_circle_length_and_every_axis_limit() {
    let p0 = pt(&[1_000.0, -2_000.0, 500.0, 0.0]);
    let (r, theta) = (6_000.0, 1.75 * std::f64::consts::PI);
    for (normal, rise, w1) in [
        ([1.0, 2.0, 3.0], 0.0, 0.0),
        ([-0.3, 1.0, 0.2], 0.0, 0.0),
        ([1.0, 1.0, 1.0], 4_000.0, 0.0),
        ([0.0, 3.0, -4.0], -2_500.0, 3_000.0),
        ([2.0, -1.0, 0.5], 0.0, -7_000.0),
    ] {
        let (seg, end, c) = oblique(p0, normal, r, theta, rise, w1);
        let mut p = path(4, TS, p0);
        p.push(seg).unwrap();
        let len = p.seg(0).prog.len();
        let want = ((r * theta).powi(2) + rise * rise + w1 * w1).sqrt();
        assert!(
            (len - want).abs() <= 1e-9 * want,
            "{normal:?}: length {len}, r·θ {want}"
        );
        let mut run = Run::default();
        assert!(run.go(&mut p, 1.0, 200_000), "{normal:?} did not end");
        run.assert_within(&p.lim, "oblique arc");
        assert_eq!(*run.pos.last().unwrap(), end, "{normal:?}");
        let nh = unit(normal);
        let mut worst = (0.0f64, 0.0f64, 0.0f64);
        let mut turned = 0.0f64;
        for q in &run.pos {
            let d = [q[0] - c[0], q[1] - c[1], q[2] - c[2]];
            let h = dot(d, nh);
            let radial = [d[0] - h * nh[0], d[1] - h * nh[1], d[2] - h * nh[2]];
            worst.0 = worst.0.max((dot(radial, radial).sqrt() - r).abs());
            // the height and the fourth axis are the same share of the length
            let share = if w1 != 0.0 { q[3] / w1 } else { h / rise };
            if rise != 0.0 {
                worst.1 = worst.1.max((h - share * rise).abs());
            } else {
                worst.1 = worst.1.max(h.abs());
            }
            // the angle turned about the normal, from the start's radius
            let r0 = [p0[0] - c[0], p0[1] - c[1], p0[2] - c[2]];
            let ang = dot(cross(r0, radial), nh).atan2(dot(r0, radial));
            turned = turned.max(ang.rem_euclid(std::f64::consts::TAU));
            if w1 != 0.0 {
                // the angle is the same share of θ (the fourth axis's share of its move)
                let a = ang.rem_euclid(std::f64::consts::TAU);
                let s = q[3] / w1;
                if s > 1e-9 && s < 1.0 - 1e-9 {
                    worst.2 = worst.2.max(
                        (a - s * theta)
                            .abs()
                            .min((a - s * theta + std::f64::consts::TAU).abs()),
                    );
                }
            }
        }
        assert!(worst.0 < 1e-6, "{normal:?}: radius off by {}", worst.0);
        assert!(worst.1 < 1e-6, "{normal:?}: height off by {}", worst.1);
        assert!(worst.2 < 1e-9, "{normal:?}: angle off by {}", worst.2);
        // counter-clockwise about the normal: the angle grows to θ
        assert!((turned - theta).abs() < 1e-6, "{normal:?}: turned {turned}");
    }
}

/// With the normal along z (x, y, z), an oblique arc is the (x, y) arc counter-clockwise: the
/// same points every tick to 1e-9 (a circle, and a helix rising on z with a fourth axis); with
/// the normal along −z it is the clockwise one. Between lines, with their blends.
#[test]
fn an_oblique_arc_about_z_is_the_xy_arc() {
    let start = pt(&[10_000.0, 0.0, 0.0, 0.0]);
    let pre = pt(&[10_000.0, -5_000.0, 0.0, 0.0]);
    let tr = Transition::MaxDeviation(30.0);
    for (nz, end, ccw) in [
        (1.0, pt(&[0.0, -5_000.0, 0.0, 0.0]), true),
        (1.0, pt(&[5_000.0, 0.0, 8_000.0, -3_000.0]), true),
        (-1.0, pt(&[5_000.0, -10_000.0, 0.0, 0.0]), false),
        (-1.0, pt(&[10_000.0, -5_000.0, 2_000.0, 500.0]), false),
    ] {
        let centre = [5_000.0, -5_000.0];
        let run = |oblique: bool| {
            let mut p = path(4, TS, start);
            p.push(line(1, pre, 6e4, tr)).unwrap();
            let mut a = if oblique {
                let mut s = arc_normal(
                    2,
                    [0.0, 0.0, nz],
                    [centre[0], centre[1], 0.0],
                    end,
                    true,
                    6e4,
                );
                s.transition = tr;
                s
            } else {
                let mut s = arc_xy(2, centre, end, 6e4, tr);
                if let Geom::Arc { ccw: c, .. } = &mut s.geom {
                    *c = ccw;
                }
                s
            };
            a.last = false;
            p.push(a).unwrap();
            let mut s3 = line(3, pt(&[end[0] + 3_000.0, end[1], end[2], end[3]]), 6e4, tr);
            s3.last = true;
            p.push(s3).unwrap();
            let mut r = Run::default();
            assert!(r.go(&mut p, 1.0, 200_000));
            r.assert_within(&p.lim, "arc");
            r
        };
        let (a, b) = (run(false), run(true));
        assert_eq!(a.pos.len(), b.pos.len(), "end {end:?}");
        let worst = a
            .pos
            .iter()
            .zip(&b.pos)
            .flat_map(|(x, y)| x.iter().zip(y).map(|(u, v)| (u - v).abs()))
            .fold(0.0f64, f64::max);
        assert!(worst <= 1e-9, "end {end:?}: off by {worst}");
    }
}

/// A full turn (the end at the start) in an oblique plane: length 2πr, back exactly.
#[test]
fn an_oblique_full_turn() {
    let p0 = pt(&[0.0, 0.0, 0.0]);
    let c = [3_000.0, -3_000.0, 0.0]; // in the plane x + y + 2z = 0 through the origin
    let mut p = path(3, TS, p0);
    p.push(arc_normal(1, [1.0, 1.0, 2.0], c, p0, false, 4e4))
        .unwrap();
    let r = (18e6f64).sqrt();
    let len = p.seg(0).prog.len();
    assert!(
        (len - std::f64::consts::TAU * r).abs() < 1e-9 * len,
        "{len}"
    );
    let mut run = Run::default();
    assert!(run.go(&mut p, 1.0, 100_000));
    run.assert_within(&p.lim, "full turn");
    assert_eq!(*run.pos.last().unwrap(), p0);
}

/// What `push` refuses, leaving the path as it was: a zero or NaN normal, a plane of an
/// axis twice or beyond the group, the centre off the plane, the end off the plane (unless
/// it rises) or off the circle.
#[test]
fn oblique_arc_refusals() {
    let p0 = pt(&[0.0, 0.0, 0.0]);
    let seg = |axes: [usize; 3], normal: P3, centre: P3, end: V, rise: bool| Segment {
        geom: Geom::ArcNormal {
            axes,
            normal,
            centre,
            rise,
            end,
        },
        ..arc_normal(1, normal, centre, end, rise, 1e4)
    };
    let z = [0.0, 0.0, 1.0];
    let c = [1_000.0, 0.0, 0.0];
    let e = pt(&[2_000.0, 0.0, 0.0]);
    let e_up = pt(&[2_000.0, 0.0, 50.0]);
    for (s, want) in [
        (seg([0, 1, 2], [0.0; 3], c, e, false), PathError::BadNormal),
        (
            seg([0, 1, 2], [f64::NAN, 0.0, 1.0], c, e, false),
            PathError::NotFinite,
        ),
        (seg([0, 1, 1], z, c, e, false), PathError::BadAxis),
        (seg([0, 1, 3], z, c, e, false), PathError::BadAxis),
        (
            seg([0, 1, 2], z, [1_000.0, 0.0, 5.0], e, false),
            PathError::OffPlane,
        ),
        (seg([0, 1, 2], z, c, e_up, false), PathError::OffPlane),
        (
            seg([0, 1, 2], z, c, pt(&[2_001.0, 0.0, 0.0]), false),
            PathError::ArcEndOffCircle,
        ),
    ] {
        let mut p = path(3, TS, p0);
        assert_eq!(p.push(s), Err(want), "{s:?}");
        assert_eq!(p.queued(), 0);
    }
    // the same end rising along the normal is a helix
    let mut p = path(3, TS, p0);
    p.push(seg([0, 1, 2], z, c, e_up, true)).unwrap();
    assert_eq!(p.queued(), 1);
}
