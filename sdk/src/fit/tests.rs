//! The chord fitter against polylines sampled from known curves (rounded as CAM posts them,
//! with noise inside the tolerance) and against zigzags, as seeded property tests: what it
//! sends stays within the tolerance of the points and of the curve they came from, covers
//! every line once and in order, ends exactly where the program does, and never fits across
//! a corner.

use super::*;
use crate::nurbs::Nurbs;
use proptest::prelude::*;
use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};

/// Counts per mm of the tests' axes (1 µm counts) and the tolerance, mm.
const SCALE: f64 = 1000.0;
const TOL: f64 = 0.01;

fn runner(cases: u32, seed: u8) -> TestRunner {
    let config = Config {
        cases,
        failure_persistence: None,
        max_shrink_iters: 256,
        ..Config::default()
    };
    TestRunner::new_with_rng(
        config,
        TestRng::from_seed(RngAlgorithm::ChaCha, &[seed; 32]),
    )
}

fn line(id: u32, p: &[f64]) -> PathItem {
    Segment::line(id, p, 100.0, TOL).into()
}

/// The fitter's output for lines through `pts` (pts[0] is where the path starts).
fn fitted(pts: &[Vec<f64>]) -> Vec<Fitted> {
    let n = pts[0].len();
    let mut f = Fitter::new(&vec![SCALE; n]);
    f.set_start(&pts[0]);
    let items: Vec<PathItem> = pts[1..]
        .iter()
        .enumerate()
        .map(|(i, p)| line(i as u32 + 1, p))
        .collect();
    FitIter::new(items.into_iter(), f).collect()
}

fn d(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y) * (x - y))
        .sum::<f64>()
        .sqrt()
}

/// Distance from each of `ps` (points in order along a path) to the polyline `line`, the
/// nearest chord looked for near the previous point's (within as many chords as the longest
/// step between two points spans of the shortest chords, and some; the first point's over
/// all of them).
fn to_polyline(ps: &[Vec<f64>], line: &[Vec<f64>]) -> Vec<f64> {
    let step = ps.windows(2).map(|w| d(&w[0], &w[1])).fold(0.0, f64::max);
    let chord = line
        .windows(2)
        .map(|w| d(&w[0], &w[1]))
        .fold(f64::INFINITY, f64::min)
        .max(1e-6);
    let window = (((step + 4.0 * TOL) / chord).ceil() as usize + 8).min(line.len());
    let mut at = 0usize;
    let mut out = Vec::with_capacity(ps.len());
    for (k, p) in ps.iter().enumerate() {
        let (lo, hi) = if k == 0 {
            (0, line.len() - 1)
        } else {
            (at.saturating_sub(window), (at + window).min(line.len() - 1))
        };
        let (mut best, mut bi) = (f64::INFINITY, at);
        for i in lo..hi.max(lo + 1).min(line.len() - 1) {
            let e = spline::dist_to_segment(p, line[i].as_slice(), line[i + 1].as_slice());
            if e < best {
                best = e;
                bi = i;
            }
        }
        if line.len() == 1 {
            best = d(p, &line[0]);
        }
        at = bi;
        out.push(best);
    }
    out
}

/// Points along a curve item, at most 2 µm apart (user units: mm): the polyline through them
/// is within 2²/(8r) of the curve, nanometres here.
fn samples(c: &Nurbs) -> Vec<Vec<f64>> {
    let knots = c.knots();
    let mut out = Vec::new();
    for s in c.degree()..c.n_ctrl() {
        let (a, b) = (knots[s], knots[s + 1]);
        if b <= a {
            continue;
        }
        let pa = c.point(a).unwrap();
        let pb = c.point(b).unwrap();
        let m = (((pb - pa).norm() * 2.0 / 0.002) as usize).clamp(24, 100_000);
        for i in 0..m {
            let u = a + (b - a) * i as f64 / m as f64;
            let p = c.point(u).unwrap();
            out.push(p.iter().take(c.dim()).copied().collect());
        }
    }
    let (_, u1) = c.domain();
    out.push(c.point(u1).unwrap().iter().take(c.dim()).copied().collect());
    out
}

/// What every output must be: the items cover the lines once each and in order; each is a
/// line of the program or a curve or line within the fit tolerance of the polyline of the
/// lines it stands for (both ways), and within `truth_tol` of the true curve (`truth`: the
/// distance of a point from it); the last ends exactly at the last point. Returns the share of
/// the lines sent as curves or merged lines.
/// The distance of a point from the true curve, and the most a fitted curve may be from it.
type Truth<'a> = (&'a dyn Fn(&[f64]) -> f64, f64);

fn check(pts: &[Vec<f64>], out: &[Fitted], truth: Option<Truth>) -> f64 {
    let eps = FIT_SHARE * TOL * (1.0 + 1e-9) + 1e-9;
    let mut next = 0u64;
    let mut merged = 0u64;
    for f in out {
        assert_eq!(f.first, next, "items in order, each once");
        assert!(f.last >= f.first);
        next = f.last + 1;
        // lines first..=last go from pts[first] to pts[last + 1]
        let (lo, hi) = (f.first as usize, f.last as usize + 1);
        let PathItem::Segment(s) = &f.item else {
            panic!("only lines in, only segments out");
        };
        assert_eq!(s.id as usize, hi, "the id of the last line covered");
        match &s.geometry {
            Geometry::Line { target } => {
                assert_eq!(target, &pts[hi], "a line ends on the program's point");
                if hi - lo > 1 {
                    merged += f.last - f.first + 1;
                    for p in &pts[lo..=hi] {
                        assert!(spline::dist_to_segment(p, &pts[lo], &pts[hi]) <= eps);
                    }
                }
            }
            Geometry::Nurbs {
                curve,
                fit_tolerance,
            } => {
                merged += f.last - f.first + 1;
                assert!((*fit_tolerance - CARD_FIT_SHARE * TOL).abs() < 1e-15);
                let sm = samples(curve);
                // a curve cut before the end of its run ends within the chord after its last
                // line, where the next curve starts
                let hi2 = (hi + 1).min(pts.len() - 1);
                for e in to_polyline(&sm, &pts[lo..=hi2]) {
                    assert!(e <= eps, "curve {lo}..{hi} is {e} from the polyline");
                }
                for e in to_polyline(&pts[lo + 1..=hi], &sm) {
                    assert!(e <= eps, "a point is {e} from curve {lo}..{hi}");
                }
                if let Some((dist_truth, tt)) = &truth {
                    for p in &sm {
                        let e = dist_truth(p);
                        assert!(e <= *tt, "curve {lo}..{hi} is {e} from the true curve");
                    }
                }
                if s.last || f.last as usize + 1 == pts.len() - 1 {
                    let end = sm.last().unwrap();
                    assert_eq!(end, &pts[hi], "the program's end exactly");
                }
            }
            g => panic!("unexpected {g:?}"),
        }
    }
    assert_eq!(next as usize, pts.len() - 1, "every line sent");
    merged as f64 / (pts.len() - 1) as f64
}

/// A smooth curve sampled by chords, rounded to `quantum` (0: not) with noise up to
/// `noise` (mm, each coordinate).
#[derive(Debug, Clone)]
struct Sampled {
    pts: Vec<Vec<f64>>,
    /// Circle (centre, radius) or helix in XY; or a wave y = a·sin(x/l).
    kind: Kind,
}

#[derive(Debug, Clone, Copy)]
enum Kind {
    Circle { r: f64, pitch: f64 },
    Wave { a: f64, l: f64 },
}

fn sampled() -> impl Strategy<Value = Sampled> {
    let kind = prop_oneof![
        (2.0f64..60.0, prop_oneof![Just(0.0), -2.0f64..2.0])
            .prop_map(|(r, pitch)| Kind::Circle { r, pitch }),
        (0.5f64..20.0, 2.0f64..30.0).prop_map(|(a, l)| Kind::Wave { a, l }),
    ];
    (
        kind,
        0.003f64..0.3,
        prop::sample::select(vec![0.0, 0.001, 0.00254]),
        0.0f64..0.3,
        50usize..700,
        any::<u64>(),
    )
        .prop_map(|(kind, chord, quantum, noise, n, seed)| {
            let mut rng = card_emu::testkit::rng::Rng::new(seed);
            let mut pts = Vec::with_capacity(n + 1);
            for i in 0..=n {
                let s = i as f64 * chord;
                let p = match kind {
                    Kind::Circle { r, pitch } => {
                        let a = s / r;
                        vec![r * a.cos(), r * a.sin(), pitch * a]
                    }
                    Kind::Wave { a, l } => vec![s, a * (s / l).sin(), 0.0],
                };
                let p: Vec<f64> = p
                    .iter()
                    .map(|x| {
                        let x = x + noise * TOL * rng.uniform(-1.0, 1.0);
                        if quantum > 0.0 {
                            (x / quantum).round() * quantum
                        } else {
                            x
                        }
                    })
                    .collect();
                if pts.last().is_none_or(|q: &Vec<f64>| d(q, &p) > 1e-9) {
                    pts.push(p);
                }
            }
            Sampled { pts, kind }
        })
}

fn truth_of(kind: Kind) -> impl Fn(&[f64]) -> f64 {
    move |p: &[f64]| match kind {
        Kind::Circle { r, pitch } => {
            // the helix's nearest point: its angle from the point's, the turn from z
            let a = p[1].atan2(p[0]);
            let turns = if pitch != 0.0 {
                ((p[2] / pitch - a) / std::f64::consts::TAU).round()
            } else {
                0.0
            };
            let a = a + turns * std::f64::consts::TAU;
            let radial = (p[0].hypot(p[1]) - r).abs();
            let axial = (p[2] - pitch * a).abs() * r / (r * r + pitch * pitch).sqrt();
            radial.hypot(axial)
        }
        Kind::Wave { a, l } => {
            // the nearest point of the wave near x, by sampling
            (-200..=200)
                .map(|i| {
                    let x = p[0] + i as f64 * 1e-4;
                    d(p, &[x, a * (x / l).sin(), 0.0])
                })
                .fold(f64::INFINITY, f64::min)
        }
    }
}

#[test]
fn polylines_of_smooth_curves_are_sent_as_curves_within_the_tolerance() {
    let fitted_share = std::cell::RefCell::new(Vec::new());
    runner(48, 1)
        .run(&sampled(), |c| {
            let out = fitted(&c.pts);
            let truth = truth_of(c.kind);
            let share = check(&c.pts, &out, Some((&truth, TOL)));
            fitted_share.borrow_mut().push(share);
            Ok(())
        })
        .unwrap();
    // a smooth curve is fitted, not sent chord by chord (short chords of curves whose
    // sagitta fits the tolerance: nearly all)
    let fitted_share = fitted_share.into_inner();
    let mean = fitted_share.iter().sum::<f64>() / fitted_share.len() as f64;
    assert!(mean > 0.9, "{mean}: {fitted_share:?}");
}

#[test]
fn a_rounded_circle_of_10000_chords_is_a_few_curves() {
    // a 1-inch-radius circle, 4 decimals in inches
    let r = 25.4;
    let mut pts = vec![];
    for i in 0..=10_000 {
        let a = std::f64::consts::TAU * i as f64 / 10_000.0;
        let q = |x: f64| (x / 25.4 * 1e4).round() / 1e4 * 25.4;
        let p = vec![q(r * a.cos()), q(r * a.sin())];
        if pts.last().is_none_or(|l: &Vec<f64>| d(l, &p) > 0.0) {
            pts.push(p);
        }
    }
    let out = fitted(&pts);
    let truth = move |p: &[f64]| (p[0].hypot(p[1]) - r).abs();
    let share = check(&pts, &out, Some((&truth, TOL)));
    assert_eq!(share, 1.0);
    // chunks of 1024 points less their overlap, cut at a knot: each one curve of a few spans
    assert!(out.len() <= 20, "{}", out.len());
    for w in out.windows(2) {
        // consecutive curves join with the same tangent and curvature
        let (PathItem::Segment(a), PathItem::Segment(b)) = (&w[0].item, &w[1].item) else {
            unreachable!()
        };
        let (Geometry::Nurbs { curve: ca, .. }, Geometry::Nurbs { curve: cb, .. }) =
            (&a.geometry, &b.geometry)
        else {
            panic!("curves")
        };
        let (_, ua) = ca.domain();
        let (pa, da, dda) = ca.eval(ua).unwrap();
        let (pb, db, ddb) = cb.eval(cb.domain().0).unwrap();
        assert!((pa - pb).norm() < 1e-9);
        let (ta, tb) = (da / da.norm(), db / db.norm());
        assert!((ta - tb).norm() < 1e-9, "tangent");
        let ka = (dda - ta * dda.dot(&ta)) / da.norm_squared();
        let kb = (ddb - tb * ddb.dot(&tb)) / db.norm_squared();
        assert!((ka - kb).norm() < 1e-6 * ka.norm(), "curvature {ka} {kb}");
    }
}

#[test]
fn collinear_pieces_are_one_line() {
    let pts: Vec<Vec<f64>> = (0..=1000)
        .map(|i| vec![25.4 * i as f64 / 1000.0, 0.0])
        .collect();
    let out = fitted(&pts);
    assert_eq!(out.len(), 1);
    check(&pts, &out, None);
    // ... and rounded to 3 decimals, with a slant
    let pts: Vec<Vec<f64>> = (0..=1000)
        .map(|i| {
            let s = 25.4 * i as f64 / 1000.0;
            vec![(s * 1e3).round() / 1e3, (0.3 * s * 1e3).round() / 1e3]
        })
        .collect();
    let out = fitted(&pts);
    assert_eq!(out.len(), 1, "{out:?}");
    check(&pts, &out, None);
}

/// A zigzag about the x axis: vertices alternately ±`amp`, `leg` apart along x.
fn zigzag(n: usize, leg: f64, amp: f64) -> Vec<Vec<f64>> {
    (0..=n)
        .map(|i| {
            let y = if i == 0 {
                0.0
            } else if i % 2 == 1 {
                amp
            } else {
                -amp
            };
            vec![i as f64 * leg, y]
        })
        .collect()
}

#[test]
fn zigzags_beyond_the_tolerance_keep_their_corners() {
    // sharp zigzags (every vertex turns more than the smoothing angle): nothing fitted
    let strat = (20usize..400, 0.005f64..2.0, 1.5f64..20.0);
    runner(64, 2)
        .run(&strat, |(n, leg, amp)| {
            let amp = amp * TOL;
            // the turn at a vertex: twice the slope angle of a leg
            let turn = 2.0 * (2.0 * amp / leg).atan();
            prop_assume!(turn > SMOOTH_TURN * 1.05);
            let pts = zigzag(n, leg, amp);
            let out = fitted(&pts);
            for f in &out {
                assert_eq!(f.first, f.last, "one line per item: {f:?}");
                assert!(matches!(
                    &f.item,
                    PathItem::Segment(Segment {
                        geometry: Geometry::Line { .. },
                        ..
                    })
                ));
            }
            check(&pts, &out, None);
            Ok(())
        })
        .unwrap();
    // gentle zigzags beyond the tolerance (turns under the smoothing angle): whatever is
    // fitted passes within the tolerance of every vertex, so the corners are kept
    let strat = (20usize..400, 0.5f64..20.0, 1.2f64..10.0);
    runner(64, 3)
        .run(&strat, |(n, leg, amp)| {
            let amp = amp * TOL;
            prop_assume!(2.0 * (2.0 * amp / leg).atan() < SMOOTH_TURN);
            let pts = zigzag(n, leg, amp);
            let out = fitted(&pts);
            check(&pts, &out, None);
            Ok(())
        })
        .unwrap();
}

#[test]
fn a_dense_square_keeps_its_corners_and_sends_each_side_as_a_line() {
    let side = 20.0;
    let per = 400;
    let corners = [
        [0.0, 0.0],
        [side, 0.0],
        [side, side],
        [0.0, side],
        [0.0, 0.0],
    ];
    let mut pts = vec![vec![0.0, 0.0]];
    for w in corners.windows(2) {
        for i in 1..=per {
            let f = i as f64 / per as f64;
            let p = [
                w[0][0] + f * (w[1][0] - w[0][0]),
                w[0][1] + f * (w[1][1] - w[0][1]),
            ];
            // rounded to 3 decimals, as a post in mm
            pts.push(p.iter().map(|x| (x * 1e3).round() / 1e3).collect());
        }
    }
    let out = fitted(&pts);
    check(&pts, &out, None);
    assert_eq!(out.len(), 4, "{out:#?}");
    for (f, c) in out.iter().zip(&corners[1..]) {
        let PathItem::Segment(Segment {
            geometry: Geometry::Line { target },
            ..
        }) = &f.item
        else {
            panic!("a line")
        };
        assert_eq!(target, &c.to_vec(), "ends exactly at the corner");
    }
}

#[test]
fn other_items_break_runs_and_keep_their_places() {
    let circle = |i: usize| {
        let a = i as f64 * 0.01;
        vec![10.0 * a.cos(), 10.0 * a.sin()]
    };
    let mut f = Fitter::new(&[SCALE, SCALE]);
    f.set_start(&circle(0));
    let mut items: Vec<PathItem> = (1..=50).map(|i| line(i as u32, &circle(i))).collect();
    // an output for the next segment: that one goes as it is
    items.push(PathItem::Output {
        output: 3,
        on: true,
        at: crate::OutputAt::End,
    });
    items.extend((51..=100).map(|i| line(i as u32, &circle(i))));
    // another feed starts a new run
    items.extend((101..=150).map(|i| {
        let mut s = Segment::line(i as u32, &circle(i), 50.0, TOL);
        s.last = i == 150;
        PathItem::Segment(s)
    }));
    let out: Vec<Fitted> = FitIter::new(items.clone().into_iter(), f).collect();
    let kinds: Vec<(u64, u64, &'static str)> = out
        .iter()
        .map(|f| {
            let k = match &f.item {
                PathItem::Output { .. } => "out",
                PathItem::Segment(s) => match s.geometry {
                    Geometry::Line { .. } => "line",
                    Geometry::Nurbs { .. } => "curve",
                    _ => "other",
                },
            };
            (f.first, f.last, k)
        })
        .collect();
    assert_eq!(
        kinds,
        vec![
            (0, 49, "curve"),
            (50, 50, "out"),
            (51, 51, "line"),
            (52, 100, "curve"),
            (101, 150, "curve"),
        ]
    );
    let PathItem::Segment(last) = &out.last().unwrap().item else {
        unreachable!()
    };
    assert!(last.last, "the program's last segment stays last");
    assert_eq!(last.feed, 50.0);
    assert_eq!(last.id, 150);
}

/// A run of chords that ends at a corner is fitted through the corner's point: the run used
/// to end one point short, its spline was fitted through the point before the corner and its
/// last control point then moved to the corner, 0.03 mm from the chords (a CAM program of
/// LinuxCNC's test set, `Cereal.ngc`). Arcs of chords, rounded to 3 decimals, each ending
/// at a corner into a line (and the next arc).
#[test]
fn a_run_that_ends_at_a_corner_is_fitted_through_the_corner() {
    let mut pts = vec![vec![0.0, 0.0, 0.0]];
    let round = |x: f64| (x * 1000.0).round() / 1000.0;
    for (r, n) in [(20.0, 63), (7.0, 22), (35.0, 110)] {
        let [x0, y0, z0] = [0, 1, 2].map(|k| pts.last().unwrap()[k]);
        // a quarter of a circle leaving along +x, then a corner: a line along +y ... and so on
        for i in 1..=n {
            let a = std::f64::consts::FRAC_PI_2 * i as f64 / n as f64;
            let z = z0 - 0.001 * i as f64;
            pts.push(vec![
                round(x0 + r * a.sin()),
                round(y0 + r * (1.0 - a.cos())),
                round(z),
            ]);
        }
        let p = pts.last().unwrap().clone();
        pts.push(vec![p[0] - 5.0, p[1] + 0.5, p[2]]);
    }
    let out = fitted(&pts);
    let curves = out
        .iter()
        .filter(|f| {
            matches!(
                &f.item,
                PathItem::Segment(Segment {
                    geometry: Geometry::Nurbs { .. },
                    ..
                })
            )
        })
        .count();
    let r: Vec<_> = out
        .iter()
        .filter(|f| f.first != f.last)
        .map(|f| (f.first, f.last))
        .collect();
    assert_eq!(curves, 3, "{} items {r:?}", out.len());
    check(&pts, &out, None);
}
