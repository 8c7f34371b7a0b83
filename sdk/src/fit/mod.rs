//! Chord fitting: runs of short lines that sample a smooth curve (CAM output: thousands of
//! chords, coordinates rounded to the post's decimals) are streamed to the card as the curve
//! they sample, a C2 cubic B-spline within the tolerance of the polyline, instead of as
//! chords. The card runs a curve at the feed its curvature allows; as chords it would follow
//! every rounding step of the points.
//!
//! What is fitted: consecutive absolute lines with the same feed, buffer mode (a blending
//! one) and `MaxDeviation` tolerance (> 0), with no output action between them, starting
//! where a line of the same stream ended. What breaks a run:
//! - a **corner**: a vertex where the path turns by more than [`SMOOTH_TURN`] both between
//!   its two chords and between the directions to the points about [`BASELINE`] tolerances
//!   before and after it (rounding and noise within the tolerance turn short chords at
//!   random; a real corner turns the long view too). A corner stays a corner: the card blends
//!   it within the tolerance, as any other;
//! - any other item (an arc, a curve, a dwell, a relative line, an output action, a line with
//!   another feed, tolerance or buffer mode; the segment after an output action is sent as it
//!   is, so that the action keeps its place);
//! - a line marked `last`.
//!
//! A run is sent as one line when its points lie within the fit tolerance of the chord from
//! its first to its last point (collinear pieces, as LinuxCNC's `G64 P Q` merges them), else
//! as the least-squares cubic B-spline with the fewest uniform spans (at least
//! [`POINTS_PER_SPAN`] points each, so it cannot follow a zigzag) whose distance to the
//! polyline is within [`FIT_SHARE`] of the tolerance both ways: every point from the spline
//! and the spline from the chords. It starts at the run's first point and ends at its last;
//! where no spline passes, the chords are sent as they are. A long run is fitted
//! [`CHUNK`] points at a time: each spline but the last is cut at one of its knots some
//! [`OVERLAP`] points before the chunk's end, and the next starts there with its tangent and
//! curvature (a curvature-continuous join, which the card runs through without a blend).
//!
//! The fitted segment carries the id of the last line it covers (its `SegmentEnd` is that
//! line's end), its feed, buffer mode and tolerance, and a fit tolerance of
//! [`CARD_FIT_SHARE`] of the tolerance for the card (a cubic is one exact piece on the card).
//! The card blends a corner within the tolerance of the pieces it joins; beside a fitted item
//! those are up to [`FIT_SHARE`] of it from the points, so the segment that starts at such a
//! corner gets its tolerance less the fitted item's distance from its points within
//! [`CORNER_REACH`] tolerances of the corner (`Fitter::emit`).

pub(crate) mod spline;
#[cfg(test)]
mod tests;

use crate::segment::{Geometry, PathBuffer, PathItem, Segment, Transition};
use spline::{correct, deviation, dist_to_segment, fit, FitSpec, Spline, Start};
use std::collections::VecDeque;

/// Share of a segment's tolerance the fitted spline may be from the polyline.
pub const FIT_SHARE: f64 = 0.8;
/// Share of the tolerance the card's own pieces may be from the fitted spline.
pub const CARD_FIT_SHARE: f64 = 0.05;
/// Largest turn (rad) at a vertex inside a run: the card's smoothing angle.
pub const SMOOTH_TURN: f64 = card_firmware::host::SMOOTH_TURN;
/// The corner test's long view: the points about this many tolerances before and after a
/// vertex.
pub const BASELINE: f64 = 8.0;
/// Fewest points a fitted span covers.
pub const POINTS_PER_SPAN: usize = 4;
/// Fewest lines a run must hold to be fitted (shorter runs are sent as they are).
pub const MIN_RUN: usize = 6;
/// Points fitted at a time, and how many of them the next chunk refits.
pub const CHUNK: usize = 1024;
pub const OVERLAP: usize = 128;
/// Points a run may hold while it is still straight (a straight run is one line).
const STRAIGHT_MAX: usize = 16 * CHUNK;
/// Share of the fit tolerance a fit's sampled deviation may reach: the samples (four a
/// chord) can miss a little of the largest distance between them.
const DEV_MARGIN: f64 = 0.99;
/// Parameter corrections per fit.
const CORRECTIONS: usize = 2;
/// How far from a fitted item's end (tolerances of arc) the corner blend there may reach: its
/// distance from the points there is taken from that corner's tolerance.
pub const CORNER_REACH: f64 = 32.0;
/// Points the corner test looks back and ahead at most.
const LOOK: usize = 64;

/// One item the fitter hands on: what to send, and the input items it stands for
/// (`first..=last`, indices in the stream).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Fitted {
    pub item: PathItem,
    pub first: u64,
    pub last: u64,
}

/// A line of a run, as it came.
#[derive(Debug, Clone)]
struct Chord {
    seg: Segment,
    index: u64,
}

/// Points in card counts (user units times each axis's scale).
type P = [f64; 8];

#[derive(Debug)]
struct Run {
    feed: f64,
    tol: f64,
    buffer: PathBuffer,
    /// `pts[0]` is where the run starts; chord `i` goes from `pts[i]` to `pts[i + 1]`.
    pts: Vec<P>,
    /// The start in user units, exactly as the item before gave it (when it was a line).
    start_user: Option<Vec<f64>>,
    chords: Vec<Chord>,
    start: Start,
    /// The programmed point before a continued run's start (which lies on the spline before,
    /// not on the polyline): its first chord is checked against `[ghost, pts[1]]`.
    ghost: Option<P>,
    /// Vertices 1..tested passed the corner test.
    tested: usize,
    straight_checked: usize,
}

impl Run {
    /// Cuts the run at vertex `v`: it ends there, and the run returned starts there (from
    /// that point, as programmed) with the chords after it.
    fn split(&mut self, v: usize) -> Run {
        let pts = self.pts.split_off(v);
        // (the vertex is the last point of this run and the first of the next)
        self.pts.push(pts[0]);
        let chords = self.chords.split_off(v);
        let start_user = self.chords.last().map(|c| match &c.seg.geometry {
            Geometry::Line { target } => target.clone(),
            _ => unreachable!("runs hold lines"),
        });
        Run {
            feed: self.feed,
            tol: self.tol,
            buffer: self.buffer,
            pts,
            start_user,
            chords,
            start: Start::Point,
            ghost: None,
            tested: self.tested.saturating_sub(v).max(1),
            straight_checked: 0,
        }
    }
}

/// The chord fitter of a path stream (see the module doc).
#[derive(Debug)]
pub(crate) struct Fitter {
    n: usize,
    /// Counts per user unit, per group axis; the tolerance's scale (the first axis's).
    scale: [f64; 8],
    tscale: f64,
    out: VecDeque<Fitted>,
    run: Option<Run>,
    /// Where the last item ends, in counts and as given (user units), when it is a line of
    /// this stream.
    end: Option<(P, Vec<f64>)>,
    /// The next motion segment is sent as it is (an output action waits for it).
    plain_next: bool,
    /// How far the last segment handed on is from its points near its end (counts; 0 for a
    /// line as given): the corner after it is blended within what that leaves of its
    /// tolerance.
    end_dev: f64,
}

fn dist(a: &P, b: &P, n: usize) -> f64 {
    a[..n]
        .iter()
        .zip(&b[..n])
        .map(|(x, y)| (x - y) * (x - y))
        .sum::<f64>()
        .sqrt()
}

fn unit(a: &P, b: &P, n: usize) -> Option<P> {
    let d = dist(a, b, n);
    if !(d > 0.0 && d.is_finite()) {
        return None;
    }
    let mut u = [0.0; 8];
    for k in 0..n {
        u[k] = (b[k] - a[k]) / d;
    }
    Some(u)
}

fn cos_between(a: &P, b: &P, n: usize) -> f64 {
    a[..n].iter().zip(&b[..n]).map(|(x, y)| x * y).sum()
}

/// The largest distance of the points within `reach` of each end of the line from the first
/// point to the last (the points they stand for).
fn line_end_devs(pts: &[P], n: usize, reach: f64) -> (f64, f64) {
    let (a, b) = (&pts[0], &pts[pts.len() - 1]);
    let worst = |it: &mut dyn Iterator<Item = &P>, from: &P| {
        it.take_while(|p| dist(p, from, n) <= reach)
            .map(|p| dist_to_segment(&p[..n], &a[..n], &b[..n]))
            .fold(0.0f64, f64::max)
    };
    (worst(&mut pts.iter(), a), worst(&mut pts.iter().rev(), b))
}

impl Fitter {
    /// A fitter for a group of `scales.len()` axes with these counts per user unit; the
    /// tolerances are in the first axis's units.
    pub fn new(scales: &[f64]) -> Self {
        let mut scale = [1.0; 8];
        scale[..scales.len()].copy_from_slice(scales);
        Self {
            n: scales.len(),
            scale,
            tscale: scales.first().copied().unwrap_or(1.0).abs(),
            out: VecDeque::new(),
            run: None,
            end: None,
            plain_next: false,
            end_dev: 0.0,
        }
    }

    /// The path ends at `user` (user units) before the first item.
    pub fn set_start(&mut self, user: &[f64]) {
        self.end = self.counts(user).map(|p| (p, user.to_vec()));
    }

    /// The next item to send, if one is ready.
    pub fn pop(&mut self) -> Option<Fitted> {
        self.out.pop_front()
    }

    fn counts(&self, user: &[f64]) -> Option<P> {
        if user.len() != self.n {
            return None;
        }
        let mut p = [0.0; 8];
        for k in 0..self.n {
            p[k] = user[k] * self.scale[k];
        }
        p[..self.n].iter().all(|x| x.is_finite()).then_some(p)
    }

    fn pass(&mut self, item: PathItem, index: u64) {
        let f = Fitted {
            item,
            first: index,
            last: index,
        };
        self.emit(f, 0.0, 0.0);
    }

    /// Hands on `f`, a fitted item `start_dev` and `end_dev` from its points near its start
    /// and its end (counts; 0 for a line as given). The corner at its start is blended
    /// within the tolerance less the larger of its and the item before's distance there, so
    /// that the blend and the fit together stay within the tolerance of the points (0 left:
    /// an exact stop).
    fn emit(&mut self, mut f: Fitted, start_dev: f64, end_dev: f64) {
        if let PathItem::Segment(s) = &mut f.item {
            let near = self.end_dev.max(start_dev) / self.tscale;
            if let Transition::MaxDeviation(t) = &mut s.transition {
                if near > 0.0 && *t > 0.0 {
                    *t = (*t - near).max(0.0);
                }
            }
            self.end_dev = end_dev;
        }
        self.out.push_back(f);
    }

    /// Takes the next input item (its index in the stream).
    pub fn push(&mut self, item: PathItem, index: u64) {
        let seg = match item {
            PathItem::Output { .. } => {
                self.flush();
                self.plain_next = true;
                self.pass(item, index);
                return;
            }
            PathItem::Segment(s) => s,
        };
        let target = match (&seg.geometry, seg.relative) {
            (Geometry::Line { target }, false) => self.counts(target).map(|p| (p, target.clone())),
            _ => None,
        };
        // (the tolerance taken out first, then tested: another transition's payload is not a
        // number to compare)
        let t = match seg.transition {
            Transition::MaxDeviation(t) => t,
            _ => 0.0,
        };
        // (a fit tolerance of its own, G64 Q, only where the segment blends at all)
        let t = match seg.fit_tolerance {
            Some(q) if t > 0.0 => q,
            _ => t,
        };
        let tol = if t > 0.0 && t.is_finite() {
            t * self.tscale
        } else {
            0.0
        };
        let blending = matches!(
            seg.buffer,
            PathBuffer::BlendingLow
                | PathBuffer::BlendingPrevious
                | PathBuffer::BlendingNext
                | PathBuffer::BlendingHigh
        );
        let eligible = !self.plain_next && tol > 0.0 && blending && seg.feed > 0.0;
        let Some((p, user)) = target.filter(|_| eligible) else {
            self.flush();
            self.end = match &seg.geometry {
                Geometry::Line { target } if !seg.relative => {
                    self.counts(target).map(|p| (p, target.clone()))
                }
                Geometry::Dwell { .. } => self.end.take(),
                _ => None,
            };
            self.plain_next = false;
            self.pass(PathItem::Segment(seg), index);
            return;
        };
        let fits = self
            .run
            .as_ref()
            .is_some_and(|r| r.feed == seg.feed && r.tol == tol && r.buffer == seg.buffer);
        if !fits {
            self.flush();
            match self.end.take() {
                Some((e, eu)) => {
                    self.run = Some(Run {
                        feed: seg.feed,
                        tol,
                        buffer: seg.buffer,
                        pts: vec![e],
                        start_user: Some(eu),
                        chords: Vec::new(),
                        start: Start::Point,
                        ghost: None,
                        tested: 1,
                        straight_checked: 0,
                    })
                }
                None => {
                    // where the path ends is not known here: this line goes as it is, and a
                    // run may start at its end
                    self.end = Some((p, user));
                    self.pass(PathItem::Segment(seg), index);
                    return;
                }
            }
        }
        let last = seg.last;
        let run = self.run.as_mut().expect("a run");
        if dist(run.pts.last().expect("a start"), &p, self.n) == 0.0 {
            // a line of no length: the card refuses it; it goes as it is (after the run)
            self.flush();
            self.pass(PathItem::Segment(seg), index);
            return;
        }
        run.pts.push(p);
        run.chords.push(Chord { seg, index });
        self.end = Some((p, user));
        self.test_corners(false);
        if last {
            self.flush();
        } else {
            self.maybe_chunk();
        }
    }

    /// No more items: what is held is sent.
    pub fn finish(&mut self) {
        self.flush();
    }

    /// Tests the vertices whose view ahead is complete (all of them at the run's end) and
    /// cuts the run at the first corner found.
    fn test_corners(&mut self, all: bool) {
        let n = self.n;
        loop {
            let Some(run) = self.run.as_mut() else {
                return;
            };
            let m = run.pts.len() - 1;
            let v = run.tested;
            if v >= m {
                return;
            }
            let base = BASELINE * run.tol;
            // the first point at least `base` ahead
            let ahead =
                (v + 1..=m.min(v + LOOK)).find(|&j| dist(&run.pts[v], &run.pts[j], n) >= base);
            let ahead = match ahead {
                Some(j) => j,
                None if all || m >= v + LOOK => m.min(v + LOOK),
                None => return,
            };
            let behind = (v.saturating_sub(LOOK)..v)
                .rev()
                .find(|&j| dist(&run.pts[v], &run.pts[j], n) >= base)
                .unwrap_or(v.saturating_sub(LOOK));
            let cos_smooth = SMOOTH_TURN.cos();
            let local = match (
                unit(&run.pts[v - 1], &run.pts[v], n),
                unit(&run.pts[v], &run.pts[v + 1], n),
            ) {
                (Some(a), Some(b)) => cos_between(&a, &b, n) < cos_smooth,
                _ => true,
            };
            let long = match (
                unit(&run.pts[behind], &run.pts[v], n),
                unit(&run.pts[v], &run.pts[ahead], n),
            ) {
                (Some(a), Some(b)) => cos_between(&a, &b, n) < cos_smooth,
                _ => true,
            };
            run.tested += 1;
            if local && long {
                self.split_at_corner(v);
            }
        }
    }

    /// The run ends at vertex v (a corner); a new one starts there with what follows.
    fn split_at_corner(&mut self, v: usize) {
        let mut run = self.run.take().expect("a run");
        let next = run.split(v);
        self.emit_final(run);
        self.run = Some(next);
    }

    /// Sends what the run holds, ending at its last point.
    fn flush(&mut self) {
        self.test_corners(true);
        if let Some(run) = self.run.take() {
            self.emit_final(run);
        }
    }

    fn emit_lines(&mut self, chords: Vec<Chord>) {
        for c in chords {
            self.pass(PathItem::Segment(c.seg), c.index);
        }
    }

    /// The points within `eps` of the chord from the first to the last, in order along it.
    fn straight(pts: &[P], n: usize, eps: f64) -> bool {
        let (a, b) = (&pts[0], &pts[pts.len() - 1]);
        let len = dist(a, b, n);
        if len <= eps {
            return false;
        }
        let mut along_prev = -f64::INFINITY;
        for p in pts {
            if dist_to_segment(&p[..n], &a[..n], &b[..n]) > eps {
                return false;
            }
            let along: f64 = (0..n).map(|k| (p[k] - a[k]) * (b[k] - a[k])).sum::<f64>() / len;
            if along < along_prev - eps {
                return false;
            }
            along_prev = along_prev.max(along);
        }
        true
    }

    fn emit_final(&mut self, run: Run) {
        let n = self.n;
        // (a continued run starts on the spline before it: even a short one is fitted, so
        // that it ends the curve without a kink)
        if run.chords.is_empty() || (run.chords.len() < MIN_RUN && run.ghost.is_none()) {
            self.emit_lines(run.chords);
            return;
        }
        let first = run.chords[0].index;
        let last = run.chords.last().expect("chords").clone();
        let item = if run.ghost.is_none() && Self::straight(&run.pts, n, FIT_SHARE * run.tol) {
            // one line from the run's start to its end: the last line, extended back
            let devs = line_end_devs(&run.pts, n, CORNER_REACH * run.tol);
            Some((PathItem::Segment(last.seg.clone()), devs))
        } else {
            self.best_fit(&run, true)
                .map(|(s, _, devs)| (self.curve_item(&s, &run, &last.seg, true), devs))
        };
        match item {
            Some((item, (sd, ed))) => {
                let f = Fitted {
                    item,
                    first,
                    last: last.index,
                };
                self.emit(f, sd, ed)
            }
            // no spline within the tolerance: the lines as they are (a continued run's first
            // goes from the spline's end, on the polyline within the tolerance)
            None => self.emit_lines(run.chords),
        }
    }

    /// A long run: the first part fitted and sent (see the module doc).
    fn maybe_chunk(&mut self) {
        let n = self.n;
        let Some(run) = self.run.as_mut() else {
            return;
        };
        let m = run.pts.len();
        if m < CHUNK || run.tested + OVERLAP < CHUNK {
            return;
        }
        let eps = FIT_SHARE * run.tol;
        // a straight run stays one run up to STRAIGHT_MAX points, checked every half chunk
        if run.ghost.is_none() && m < STRAIGHT_MAX {
            if run.straight_checked > 0 && m < run.straight_checked + CHUNK / 2 {
                return;
            }
            run.straight_checked = m;
            if Self::straight(&run.pts, n, eps) {
                return;
            }
        }
        let run = self.run.take().expect("a run");
        if m >= STRAIGHT_MAX && run.ghost.is_none() && Self::straight(&run.pts, n, eps) {
            // one line up to here; the next run starts at that vertex
            self.cut_as_lines_or_line(run, m - 1 - OVERLAP, true);
            return;
        }
        // fit the whole run so far (free end) and keep what lies before the cut
        let mut run = run;
        let cut_point = m - 1 - OVERLAP;
        match self.best_fit(&run, false) {
            Some((s, t, (sd, _))) => {
                let k = s.n_ctrl() - spline::DEGREE;
                let mut mk = ((t[cut_point] * k as f64).round() as usize).clamp(1, k - 1);
                // the cut must leave points on both sides
                while mk > 1 && !t.iter().skip(1).any(|&x| x <= mk as f64 / k as f64) {
                    mk -= 1;
                }
                let uc = mk as f64 / k as f64;
                let covered = t.iter().skip(1).take_while(|&&x| x <= uc).count();
                let Some((tangent, curvature)) = s.frame(uc) else {
                    self.cut_as_lines_or_line(run, cut_point, false);
                    return;
                };
                if covered == 0 || covered >= run.chords.len() {
                    self.cut_as_lines_or_line(run, cut_point, false);
                    return;
                }
                let left = s.left_of_knot(mk);
                let (pc, _, _) = s.eval(uc);
                let mut rest_pts = run.pts.split_off(covered + 1);
                let rest_chords = run.chords.split_off(covered);
                let ghost = run.pts[covered];
                let mut c = [0.0; 8];
                c[..n].copy_from_slice(&pc[..n]);
                rest_pts.insert(0, c);
                let last = run.chords.last().expect("chords").clone();
                let item = self.curve_item(&left, &run, &last.seg, false);
                let f = Fitted {
                    item,
                    first: run.chords[0].index,
                    last: last.index,
                };
                // (it ends where the next curve starts with its tangent and curvature: no
                // corner there)
                self.emit(f, sd, 0.0);
                let tested = run.tested.saturating_sub(covered).max(1);
                self.run = Some(Run {
                    feed: run.feed,
                    tol: run.tol,
                    buffer: run.buffer,
                    pts: rest_pts,
                    start_user: None,
                    chords: rest_chords,
                    start: Start::Continue { tangent, curvature },
                    ghost: Some(ghost),
                    tested,
                    straight_checked: 0,
                });
            }
            None => self.cut_as_lines_or_line(run, cut_point, false),
        }
    }

    /// Sends the run's chords up to vertex `cut` (as one line when `line`, else as they
    /// are); a new run starts at that vertex with the rest.
    fn cut_as_lines_or_line(&mut self, mut run: Run, cut: usize, line: bool) {
        let next = run.split(cut);
        if line && run.ghost.is_none() {
            let first = run.chords[0].index;
            let last = run.chords.last().expect("chords");
            let f = Fitted {
                item: PathItem::Segment(last.seg.clone()),
                first,
                last: last.index,
            };
            let (sd, ed) = line_end_devs(&run.pts, self.n, CORNER_REACH * run.tol);
            self.emit(f, sd, ed);
        } else {
            self.emit_lines(run.chords);
        }
        self.run = Some(next);
    }

    /// The least-squares spline with the fewest spans within the fit tolerance, the points'
    /// parameters on it, and its largest distance from them within [`CORNER_REACH`]
    /// tolerances of its start (0 where it continues the curve before: no corner there) and of
    /// its end.
    fn best_fit(&self, run: &Run, pin_end: bool) -> Option<(Spline, Vec<f64>, (f64, f64))> {
        let n = self.n;
        let np = run.pts.len();
        let chords = np - 1;
        let eps = FIT_SHARE * run.tol;
        let mut flat = Vec::with_capacity(np * n);
        for p in &run.pts {
            flat.extend_from_slice(&p[..n]);
        }
        // chord-length parameters
        let mut t = Vec::with_capacity(np);
        let mut acc = 0.0;
        t.push(0.0);
        for i in 1..np {
            acc += dist(&run.pts[i - 1], &run.pts[i], n);
            t.push(acc);
        }
        let total = acc;
        if !(total > 0.0 && total.is_finite()) {
            return None;
        }
        for x in t.iter_mut() {
            *x /= total;
        }
        // a continued start fixes three control points; a chunk is cut at an inner knot
        let cont = matches!(run.start, Start::Continue { .. });
        let kmin = if cont || !pin_end { 2 } else { 1 };
        let kmax = (chords / POINTS_PER_SPAN)
            .min(card_firmware::host::MAX_CTRL - spline::DEGREE)
            .max(kmin);
        let smooth = 1e-6 * np as f64;
        let ghost = run.ghost;
        let attempt = |k: usize| -> Option<(Spline, Vec<f64>, f64)> {
            let mut t = t.clone();
            let spec = FitSpec {
                k,
                start: &run.start,
                speed: total,
                pin_end,
                smooth,
            };
            let mut s = fit(&flat, n, &t, &spec)?;
            for _ in 0..CORRECTIONS {
                correct(&s, &flat, &mut t, pin_end);
                s = fit(&flat, n, &t, &spec)?;
            }
            let (mut dev, _) = deviation(&s, &flat, &t);
            if let Some(g) = ghost {
                // the first chord's programmed start is the vertex before the join
                for f in [0.0, 0.25, 0.5, 0.75] {
                    let (p, _, _) = s.eval(f * t[1]);
                    dev = dev.max(dist_to_segment(&p[..n], &g[..n], &flat[n..2 * n]));
                }
            }
            (dev <= DEV_MARGIN * eps).then_some((s, t, dev))
        };
        // doubling, then bisection, for the fewest spans that pass
        let mut k = kmin;
        let mut lo = kmin - 1;
        let found = loop {
            if let Some(f) = attempt(k) {
                break f;
            }
            if k >= kmax {
                return None;
            }
            lo = k;
            k = (2 * k).min(kmax);
        };
        let (mut best, mut hi) = (found, k);
        while hi - lo > 1 {
            let mid = (lo + hi) / 2;
            match attempt(mid) {
                Some(f) => {
                    best = f;
                    hi = mid;
                }
                None => lo = mid,
            }
        }
        let (s, t) = (best.0, best.1);
        let r = CORNER_REACH * run.tol / total;
        let head = t.partition_point(|&x| x <= r) + 1;
        let tail = t.partition_point(|&x| x < 1.0 - r).saturating_sub(1);
        let head = head.min(np);
        let devs = (
            if cont {
                0.0
            } else {
                deviation(&s, &flat[..head * n], &t[..head]).0
            },
            deviation(&s, &flat[tail * n..], &t[tail..]).0,
        );
        Some((s, t, devs))
    }

    /// The NURBS segment of spline `s` (counts) for `run`, with `last`'s id and flags.
    fn curve_item(&self, s: &Spline, run: &Run, last: &Segment, pin_end: bool) -> PathItem {
        let n = self.n;
        let np = s.n_ctrl();
        let mut ctrl = Vec::with_capacity(np * n);
        for i in 0..np {
            for k in 0..n {
                ctrl.push(s.ctrl[i * n + k] / self.scale[k]);
            }
        }
        // the ends exactly as given where they are programmed points
        if let Some(su) = &run.start_user {
            ctrl[..n].copy_from_slice(su);
        }
        if pin_end {
            if let Geometry::Line { target } = &last.geometry {
                ctrl[(np - 1) * n..].copy_from_slice(target);
            }
        }
        let weights = vec![1.0; np];
        let curve = crate::nurbs::Nurbs::new(spline::DEGREE, n, &ctrl, &weights, &s.knots)
            .expect("a fitted cubic is a valid curve");
        let tol_user = run.tol / self.tscale;
        let mut seg = Segment::nurbs(
            last.id,
            curve,
            run.feed,
            tol_user,
            CARD_FIT_SHARE * tol_user,
        )
        .buffer(run.buffer);
        seg.last = pin_end && last.last;
        PathItem::Segment(seg)
    }
}

/// An iterator adaptor: the items of `inner` through a [`Fitter`].
pub(crate) struct FitIter<I> {
    inner: I,
    fitter: Fitter,
    index: u64,
    done: bool,
}

impl<I: Iterator<Item = PathItem>> FitIter<I> {
    pub fn new(inner: I, fitter: Fitter) -> Self {
        Self {
            inner,
            fitter,
            index: 0,
            done: false,
        }
    }
}

impl<I: Iterator<Item = PathItem>> Iterator for FitIter<I> {
    type Item = Fitted;
    fn next(&mut self) -> Option<Fitted> {
        loop {
            if let Some(f) = self.fitter.pop() {
                return Some(f);
            }
            if self.done {
                return None;
            }
            match self.inner.next() {
                Some(item) => {
                    self.fitter.push(item, self.index);
                    self.index += 1;
                }
                None => {
                    self.fitter.finish();
                    self.done = true;
                }
            }
        }
    }
}
