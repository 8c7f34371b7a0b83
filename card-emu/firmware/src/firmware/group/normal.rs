//! Layout 1.13: MC_MoveCircular in a plane given by a normal vector, in the move queue.
//!
//! The move's arguments do not fit one entry (limits, centre, end, turns; then the plane's
//! three axes, its normal and the other axes' targets), so it takes two:
//! `MC_OP_GROUP_MOVE_CIRCULAR_NORMAL` and `MC_OP_GROUP_CIRCULAR_PLANE`, published together.
//! The command manager pairs them (`Firmware::serve_commands`: the second is taken only when it
//! is the very next entry, for the same group) and this file checks the pair as one move. The
//! plane travels with the move rather than coming from the group's `MC_OP_PATH_ARC_PLANE`: a
//! queued move's geometry is fixed when it is taken, whatever sets a path's plane later.
//!
//! The geometry is the path's (`path::normal_arc` checks it within the group's tolerance and
//! makes it exact, `motion::path::Helix` runs it), so a move and a path segment of the same
//! arc have the same points; here it runs as the move queue's circle does: a rest-to-rest
//! S-curve of the path length within the move's limits along the path (or the constant feed
//! and the filters), with `turns` full turns added to the sweep.

use super::path::{arc_plane, normal_arc};
use super::*;
use crate::motion::path::{normal_basis, Geom, Helix};
use firmware_proto::cmd::{PathArcNormal, PathFlags};

/// The geometry of a normal-vector arc move from `start` (the end of what is queued; with
/// `relative`, the centre, the end and the other axes' targets from there).
pub(super) fn geometry(
    cfg: &GroupConfig,
    m: &CircularNormalMove,
    p: &CircularPlane,
    start: &[f64; MAX_AXES],
    relative: bool,
) -> Result<Geometry, NackCode> {
    let plane = arc_plane(cfg, &p.plane)?;
    let turns = whole(m.turns).ok_or(NackCode::OutOfRange)? as u32; // (whole: at most 1e9)
    let arc = PathArcNormal {
        id: 0.0,
        feed: 0.0,
        tolerance: 0.0,
        centre: m.centre,
        end: m.end,
        helix: p.helix,
        rise: m.rise,
        helix_relative: m.helix_relative,
        flags: PathFlags::default(),
    };
    let Geom::ArcNormal {
        axes,
        normal,
        centre,
        end,
        ..
    } = normal_arc(cfg, &arc, &plane, start, relative)?
    else {
        return Err(NackCode::BadConfig);
    };
    let basis = normal_basis(axes, normal).ok_or(NackCode::ArcNormal)?;
    let on = |e: &[f64; MAX_AXES]| (0..3).map(|k| centre[k] * e[axes[k]]).sum::<f64>();
    let c2 = [on(&basis.0), on(&basis.1)];
    let h = Helix::normal_turns(cfg.naxes, *start, end, basis, c2, turns)
        .map_err(|_| NackCode::ZeroLengthArc)?;
    if !h.length().is_finite() {
        return Err(NackCode::OutOfRange);
    }
    Ok(Geometry::ArcNormal(h))
}

#[cfg(test)]
mod tests {
    use super::super::testing::{Bench, TS};
    use super::*;
    use crate::motion::path::{BlendSpeed, Path, PathLimits, Segment, Transition};
    use firmware_proto::cmd::{Args, PathArcPlane};

    const LIM: [f64; 4] = [20_000.0, 4e5, 4e5, 4e7];

    fn mv(centre: [f64; 3], end: [f64; 3], turns: f64, rise: bool) -> CircularNormalMove {
        CircularNormalMove {
            limits: FeedLimits::from_array(LIM),
            centre,
            end,
            turns,
            rise,
            helix_relative: false,
            opts: MoveOpts::default(),
        }
    }

    fn plane(axes: [f64; 3], normal: [f64; 3], helix: &[f64]) -> CircularPlane {
        let mut h = [0.0; MAX_AXES - 3];
        h[..helix.len()].copy_from_slice(helix);
        CircularPlane {
            plane: PathArcPlane { axes, normal },
            helix: h,
        }
    }

    fn queue(
        b: &mut Bench,
        seq: u32,
        m: &CircularNormalMove,
        p: &CircularPlane,
    ) -> Result<(), NackCode> {
        let tick = b.tick;
        b.g.queue_move(seq, GroupMove::CircularNormal(m, p), TS, tick, &mut b.out)
    }

    /// Unit vector along `v`.
    fn unit(v: [f64; 3]) -> [f64; 3] {
        let m = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        [v[0] / m, v[1] / m, v[2] / m]
    }

    fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
        a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
    }

    /// A tilted circle of radius 5,000 through the origin (the group's start) with its centre
    /// at `c` (in the plane through the origin with normal `nrm`), 1¼ turns (a quarter turn and
    /// one added) with the fourth axis climbing 3,000 counts: on every tick the commanded
    /// point of axes 0..3 is 5,000 from the centre and in the plane within 1e-6 counts
    /// relative (an independent computation from the normal and the centre, not the card's
    /// basis), the fourth axis is linear in the swept angle, the sweep turns counter-clockwise
    /// about the normal, the run is 1¼ turns long, and the end is reached exactly.
    #[test]
    fn a_tilted_helix_with_a_turn_added_stays_on_its_circle_and_ends_exactly() {
        let nrm = [1.0, -2.0, 2.0];
        let nh = unit(nrm);
        // a radius vector in the plane, and the one a quarter turn on (n̂ × u)
        let u = unit([2.0, 1.0, 0.0]);
        let w = [
            nh[1] * u[2] - nh[2] * u[1],
            nh[2] * u[0] - nh[0] * u[2],
            nh[0] * u[1] - nh[1] * u[0],
        ];
        let r = 5_000.0;
        // the start (the origin) is centre + r·u: the centre is −r·u
        let c = [-r * u[0], -r * u[1], -r * u[2]];
        // a quarter turn counter-clockwise about n̂: centre + r·w
        let e = [c[0] + r * w[0], c[1] + r * w[1], c[2] + r * w[2]];
        let mut b = Bench::new(4, true, false);
        queue(
            &mut b,
            1,
            &mv(c, e, 1.0, false),
            &plane([0.0, 1.0, 2.0], nrm, &[3_000.0]),
        )
        .unwrap();
        let geom = b.g.queue.front().map(|m| m.geom).unwrap();
        let (len, programmed) = (geom.len(), geom.end(4));
        let sweep = 1.25 * core::f64::consts::TAU;
        let want = (sweep * r).hypot(3_000.0);
        assert!((len - want).abs() <= 1e-9 * want, "length {len} vs {want}");
        let (mut worst_r, mut worst_h, mut worst_z) = (0.0f64, 0.0f64, 0.0f64);
        let mut swept = 0.0;
        let mut last_ang = 0.0;
        let mut ticks = 0;
        while b.g.state != GroupState::Standby && ticks < 200_000 {
            b.tick();
            ticks += 1;
            let p: Vec<f64> = (0..3).map(|a| b.pos(a)).collect();
            let d = [p[0] - c[0], p[1] - c[1], p[2] - c[2]];
            worst_r = worst_r.max((dot(d, d).sqrt() - r).abs() / r);
            worst_h = worst_h.max(dot(d, nh).abs() / r);
            let ang = dot(d, w).atan2(dot(d, u));
            let step = (ang - last_ang + 3.0 * core::f64::consts::PI)
                .rem_euclid(core::f64::consts::TAU)
                - core::f64::consts::PI;
            assert!(step >= -1e-12, "turned clockwise by {step} at tick {ticks}");
            swept += step;
            last_ang = ang;
            if swept < sweep - 1e-9 {
                worst_z = worst_z.max((b.pos(3) - 3_000.0 * swept / sweep).abs());
            }
        }
        assert!(
            worst_r <= 1e-6 && worst_h <= 1e-6,
            "radius {worst_r}, height {worst_h}"
        );
        assert!(
            (swept - sweep).abs() < 1e-9,
            "swept {swept} rad, want {sweep}"
        );
        assert!(worst_z < 1e-6, "the fourth axis left its line by {worst_z}");
        // the end: the programmed one exactly, the one given within rounding (the card put
        // it exactly on the circle)
        for (k, p) in programmed.iter().enumerate().take(4) {
            assert_eq!(b.pos(k), *p, "axis {k}");
        }
        for (k, (p, g)) in programmed.iter().zip(&e).enumerate() {
            assert!((p - g).abs() <= 1e-9, "axis {k}: {p}");
        }
        assert_eq!(b.pos(3), 3_000.0);
    }

    /// The move's points are the path's for the same arc: a path segment of the same
    /// normal-vector helix (rise along the normal, the fourth axis moving) has the same length
    /// and, at every arc length, the same point (the path runs it on its own feed; the
    /// geometry is shared).
    #[test]
    fn the_same_arc_as_the_path_buffers() {
        let nrm = [0.0, 1.0, 1.0];
        let c = [0.0, -2_000.0, 2_000.0];
        // the start (origin) and an end half a turn on, 800 counts up along the normal
        let nh = unit(nrm);
        let e = [
            0.0 + 800.0 * nh[0],
            -4_000.0 + 800.0 * nh[1],
            4_000.0 + 800.0 * nh[2],
        ];
        let mut b = Bench::new(4, true, false);
        let p = plane([0.0, 1.0, 2.0], nrm, &[-1_500.0]);
        queue(&mut b, 1, &mv(c, e, 0.0, true), &p).unwrap();
        let geom = b.g.queue.front().map(|m| m.geom).unwrap();
        let mut path = Path::with_capacity(4);
        let lim = PathLimits {
            naxes: 4,
            ts: TS,
            vmax: [1e5; MAX_AXES],
            amax: [1e6; MAX_AXES],
            jmax: [1e8; MAX_AXES],
            accel: 0.0,
            jerk: 0.0,
            plan_ticks: 1,
        };
        path.reset([0.0; MAX_AXES], lim, 1).unwrap();
        let end = geom.end(4);
        path.push(Segment {
            id: 1,
            geom: Geom::ArcNormal {
                axes: [0, 1, 2],
                normal: nrm,
                centre: c,
                rise: true,
                end,
            },
            feed: 1e4,
            transition: Transition::Exact,
            blend: BlendSpeed::Low,
            last: true,
        })
        .unwrap();
        let plen = path.seg_point(0, 0.0).0;
        assert!(
            (plen - geom.len()).abs() <= 1e-9 * plen,
            "{plen} vs {}",
            geom.len()
        );
        for k in 0..=64 {
            let s = plen * k as f64 / 64.0;
            let (m, q) = (geom.point(s, 4), path.seg_point(0, s).1);
            for (a, (x, y)) in m.iter().zip(&q).enumerate().take(4) {
                assert!((x - y).abs() <= 1e-9, "s {s}: axis {a}: {x} vs {y}");
            }
        }
        assert_eq!(end[3], -1_500.0);
    }

    /// Every refusal of the move, with its code, and nothing queued by any of them.
    #[test]
    fn every_refusal_has_its_code_and_queues_nothing() {
        let r = 5_000.0;
        let xyz = [0.0, 1.0, 2.0];
        let z = [0.0, 0.0, 1.0];
        let ok = mv([-r, 0.0, 0.0], [-2.0 * r, 0.0, 0.0], 0.0, false);
        let cases: [(CircularNormalMove, CircularPlane, NackCode); 12] = [
            (ok, plane(xyz, [0.0; 3], &[]), NackCode::ArcNormal),
            (ok, plane([0.0, 1.0, 1.0], z, &[]), NackCode::ArcAxes),
            (ok, plane([0.0, 1.5, 2.0], z, &[]), NackCode::ArcAxes),
            (ok, plane([0.0, 1.0, 3.0], z, &[]), NackCode::AxisNotInGroup),
            (
                ok,
                plane(xyz, [f64::NAN, 0.0, 1.0], &[]),
                NackCode::NotFinite,
            ),
            (
                mv([-r, 0.0, 10.0], [-2.0 * r, 0.0, 0.0], 0.0, false),
                plane(xyz, z, &[]),
                NackCode::ArcOffPlane,
            ),
            (
                mv([-r, 0.0, 0.0], [-2.0 * r, 0.0, 10.0], 0.0, false),
                plane(xyz, z, &[]),
                NackCode::ArcOffPlane,
            ),
            (
                mv([-r, 0.0, 0.0], [-2.0 * r - 10.0, 0.0, 0.0], 0.0, false),
                plane(xyz, z, &[]),
                NackCode::CentreNotEquidistant,
            ),
            (
                mv([0.0, 0.0, 0.0], [0.0, 0.0, 0.0], 0.0, false),
                plane(xyz, z, &[]),
                NackCode::ZeroLengthArc,
            ),
            (
                mv([-r, 0.0, 0.0], [-2.0 * r, 0.0, 0.0], 0.5, false),
                plane(xyz, z, &[]),
                NackCode::OutOfRange,
            ),
            (
                mv([-r, 0.0, 0.0], [-2.0 * r, 0.0, 0.0], -1.0, false),
                plane(xyz, z, &[]),
                NackCode::OutOfRange,
            ),
            (
                mv([-r, 0.0, 0.0], [-2.0 * r, 0.0, 0.0], 2e6, false),
                plane(xyz, z, &[]),
                NackCode::Infeasible,
            ),
        ];
        let mut b = Bench::new(3, true, false);
        for (m, p, code) in &cases {
            assert_eq!(queue(&mut b, 1, m, p), Err(*code), "{m:?} {p:?}");
            assert!(b.g.queue.is_empty() && b.g.state == GroupState::Standby);
        }
        // The same move accepted: the cases differ from it in the one fault each.
        queue(&mut b, 2, &ok, &plane(xyz, z, &[])).unwrap();
        assert_eq!(b.g.queue.len(), 1);
        // (the args a host sends decode to what was checked)
        let mut args = [0.0; firmware_proto::CMD_ARGS];
        let f = ok.encode(&mut args);
        assert_eq!(CircularNormalMove::decode(f, &args).unwrap(), ok);
    }
}
