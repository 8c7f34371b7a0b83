//! `Group` (coordinated moves, the path, G-code), `GroupMotion`, `GroupStatus`, `PathLimits`.
use crate::errors::py;
use crate::names::py_enum;
use crate::wait::wait_sliced;
use motioncard_sdk as sdk;
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;

/// Limits along a path: feed (velocity), acceleration, jerk; deceleration by keyword.
#[pyclass(module = "motioncard", frozen)]
#[derive(Clone, Copy)]
pub struct PathLimits {
    limits: sdk::PathLimits,
}

#[pymethods]
impl PathLimits {
    #[new]
    #[pyo3(signature = (velocity, acceleration, jerk, *, deceleration = None))]
    fn new(velocity: f64, acceleration: f64, jerk: f64, deceleration: Option<f64>) -> Self {
        let mut limits = sdk::PathLimits::new(velocity, acceleration, jerk);
        if let Some(d) = deceleration {
            limits.deceleration = d;
        }
        PathLimits { limits }
    }

    /// Feed.
    #[getter]
    fn velocity(&self) -> f64 {
        self.limits.velocity
    }

    /// Tangential acceleration.
    #[getter]
    fn acceleration(&self) -> f64 {
        self.limits.acceleration
    }

    /// Tangential deceleration.
    #[getter]
    fn deceleration(&self) -> f64 {
        self.limits.deceleration
    }

    /// Tangential jerk.
    #[getter]
    fn jerk(&self) -> f64 {
        self.limits.jerk
    }
}

/// One segment of a group's path: build it with `Segment.line`, `Segment.arc` or
/// `Segment.dwell`, then `Group.stream_path([...])`.
#[pyclass(module = "motioncard", frozen)]
#[derive(Clone)]
pub struct Segment {
    pub(crate) segment: sdk::Segment,
}

#[pymethods]
impl Segment {
    /// A line to `target` (one value per group axis) at `feed`, blended into the segment
    /// before within `tolerance` of the corner (0: an exact stop). `relative`: from where
    /// the segment before ends; `last`: the end of the program.
    #[staticmethod]
    #[pyo3(signature = (id, target, feed, tolerance = 0.0, *, relative = false, last = false))]
    fn line(
        id: u32,
        target: Vec<f64>,
        feed: f64,
        tolerance: f64,
        relative: bool,
        last: bool,
    ) -> Segment {
        finish(
            sdk::Segment::line(id, &target, feed, tolerance),
            relative,
            last,
        )
    }

    /// An arc to `end` at `feed`, blended as a line: around `centre`, or of `radius`
    /// (negative: the arc longer than half a turn), counter-clockwise unless `ccw=False`; or
    /// through the point `via` on it (the direction follows the points). One of the three.
    /// `end`, `centre` and `via` are in the coordinates of `plane` (see `Group.move_circular`;
    /// default "XY"); `helix`: the group's other axes' targets (empty: they stay).
    #[staticmethod]
    #[pyo3(signature = (id, end, centre = None, feed = None, tolerance = 0.0, *, radius = None, via = None, ccw = None, plane = None, helix = Vec::new(), relative = false, last = false))]
    #[allow(clippy::too_many_arguments)]
    fn arc(
        id: u32,
        end: [f64; 2],
        centre: Option<[f64; 2]>,
        feed: Option<f64>,
        tolerance: f64,
        radius: Option<f64>,
        via: Option<[f64; 2]>,
        ccw: Option<bool>,
        plane: Option<PlaneArg>,
        helix: Vec<f64>,
        relative: bool,
        last: bool,
    ) -> PyResult<Segment> {
        let arc = arc_spec(end, centre, radius, via, ccw)?;
        let plane = self::plane(plane)?;
        let feed = feed.ok_or_else(|| PyTypeError::new_err("Segment.arc: feed is missing"))?;
        let s = sdk::Segment::arc(id, arc, plane, &helix, feed, tolerance);
        Ok(finish(s, relative, last))
    }

    /// An arc in the plane of three group axes `axes` (default X, Y, Z) given by its
    /// `normal`: counter-clockwise about it (the right-hand rule) in the plane through the
    /// start, around `centre`, to `end` (at the start: a full turn), at `feed`, blended as a
    /// line; `centre` and `end` on the three axes, in order (they need one scale). With
    /// `rise` the end may lie off the plane along the normal (a helix along it); `helix`: the
    /// group's other axes' targets (empty: they stay). The card refuses a centre off the plane
    /// or an end off the circle by more than the group's tolerance (`ArcOffPlaneError`,
    /// `CentreNotEquidistantError`), a zero normal (`ArcNormalError`), an axis twice
    /// (`ArcAxesError`).
    #[staticmethod]
    #[pyo3(signature = (id, end, centre, feed, tolerance = 0.0, *, normal, axes = [0, 1, 2], rise = false, helix = Vec::new(), relative = false, last = false))]
    #[allow(clippy::too_many_arguments)]
    fn arc_normal(
        id: u32,
        end: [f64; 3],
        centre: [f64; 3],
        feed: f64,
        tolerance: f64,
        normal: [f64; 3],
        axes: [usize; 3],
        rise: bool,
        helix: Vec<f64>,
        relative: bool,
        last: bool,
    ) -> Segment {
        let mut s = sdk::Segment::arc_normal(id, axes, normal, centre, end, feed, tolerance);
        if let sdk::Geometry::ArcNormal {
            rise: r, helix: h, ..
        } = &mut s.geometry
        {
            *r = rise;
            *h = helix;
        }
        finish(s, relative, last)
    }

    /// A NURBS `curve` (`Nurbs`, control points in group axis order, absolute, starting
    /// where the segment before ends; relative: from there) at `feed`, blended into the
    /// segment before as a line, run within `fit_tolerance` (first axis's units) of the
    /// curve; it takes a buffer entry per piece the card fits to it.
    #[staticmethod]
    #[pyo3(signature = (id, curve, feed, tolerance = 0.0, *, fit_tolerance, relative = false, last = false))]
    fn nurbs(
        id: u32,
        curve: Nurbs,
        feed: f64,
        tolerance: f64,
        fit_tolerance: f64,
        relative: bool,
        last: bool,
    ) -> Segment {
        let s = sdk::Segment::nurbs(id, curve.curve, feed, tolerance, fit_tolerance);
        finish(s, relative, last)
    }

    /// A dwell of `seconds` (an exact stop, then a wait).
    #[staticmethod]
    #[pyo3(signature = (id, seconds, *, last = false))]
    fn dwell(id: u32, seconds: f64, last: bool) -> Segment {
        finish(sdk::Segment::dwell(id, seconds), false, last)
    }

    /// The id reported as it starts and ends (`EventKind.SEGMENT_START`, `SEGMENT_END`).
    #[getter]
    fn id(&self) -> u32 {
        self.segment.id
    }

    /// This segment joining the one before it by `mode` (PLCopen BufferMode): "aborting"
    /// (the running path stops along its geometry within its limits, everything queued is
    /// dropped, and this segment starts from where it came to rest), "buffered" (an exact
    /// stop at the corner), or a blend whose corner speed is at most the lower of the two
    /// feeds ("blending_low", the default), the previous segment's ("blending_previous"),
    /// this one's ("blending_next") or the higher ("blending_high").
    fn with_buffer(&self, mode: &str) -> PyResult<Segment> {
        let b = crate::path::buffer(mode)?;
        Ok(Segment {
            segment: self.segment.clone().buffer(b),
        })
    }

    /// This segment with its blend sized by `kind` (PLCopen TransitionMode; in the first
    /// group axis's units): "none" (an exact stop), "max_deviation" (within `distance` of
    /// the corner: what `tolerance` sets), "corner_distance" (the blend begins `distance`
    /// before the corner) or "time_shift" (between two lines: each its own S-curve, this one
    /// starting while the one before decelerates, the path within `distance` of the corner).
    #[pyo3(signature = (kind, distance = 0.0))]
    fn with_transition(&self, kind: &str, distance: f64) -> PyResult<Segment> {
        let t = crate::path::transition(kind, distance)?;
        Ok(Segment {
            segment: self.segment.clone().transition(t),
        })
    }

    /// This segment fitted by the chord fitter within `tolerance` of its points (G64 Q)
    /// rather than the transition's tolerance; 0 sends it as it is.
    fn fit_within(&self, tolerance: f64) -> Segment {
        Segment {
            segment: self.segment.clone().fit_within(tolerance),
        }
    }

    /// Its buffer mode's name (see `with_buffer`).
    #[getter]
    fn buffer(&self) -> &'static str {
        crate::path::buffer_name(self.segment.buffer)
    }

    /// Its transition: (kind, distance) (see `with_transition`).
    #[getter]
    fn transition(&self) -> (&'static str, f64) {
        crate::path::transition_pair(self.segment.transition)
    }

    /// The chord fitter's tolerance for it (None: the transition's; see `fit_within`).
    #[getter]
    fn fit_tolerance(&self) -> Option<f64> {
        self.segment.fit_tolerance
    }
}

/// A plane as Python names it: "XY", a pair of group axes.
#[derive(FromPyObject)]
pub(crate) enum PlaneArg {
    Name(String),
    Axes((usize, usize)),
}

/// The plane of `arg` (None: XY). Two different letters of X, Y, Z (group axes 0, 1, 2):
/// XY, YZ and ZX are the G17 to G19 planes, any other pair is that pair of axes in order.
fn plane(arg: Option<PlaneArg>) -> PyResult<sdk::Plane> {
    let name = match arg {
        None => return Ok(sdk::Plane::XY),
        Some(PlaneArg::Axes((u, v))) => return Ok(sdk::Plane::Axes(u, v)),
        Some(PlaneArg::Name(n)) => n,
    };
    let axis = |c: char| "XYZ".find(c.to_ascii_uppercase());
    let mut it = name.chars();
    match (it.next().and_then(axis), it.next().and_then(axis), it.next()) {
        (Some(u), Some(v), None) if u != v => Ok(match (u, v) {
            (0, 1) => sdk::Plane::XY,
            (1, 2) => sdk::Plane::YZ,
            (2, 0) => sdk::Plane::ZX,
            _ => sdk::Plane::Axes(u, v),
        }),
        _ => Err(PyValueError::new_err(format!(
            "plane {name:?}: two different letters of X, Y, Z (\"XY\", \"ZX\", \"YZ\", \"XZ\", ...) \
             or a pair of group axes"
        ))),
    }
}

/// The arc of `move_circular`'s and `Segment.arc`'s keywords: exactly one of `centre`,
/// `radius`, `via`; `ccw` (default counter-clockwise) only with the first two.
fn arc_spec(
    end: [f64; 2],
    centre: Option<[f64; 2]>,
    radius: Option<f64>,
    via: Option<[f64; 2]>,
    ccw: Option<bool>,
) -> PyResult<sdk::ArcSpec> {
    let dir = ccw.unwrap_or(true);
    match (centre, radius, via) {
        (Some(centre), None, None) => Ok(sdk::ArcSpec::Centre {
            end,
            centre,
            ccw: dir,
        }),
        (None, Some(radius), None) => Ok(sdk::ArcSpec::Radius {
            end,
            radius,
            ccw: dir,
        }),
        (None, None, Some(via)) if ccw.is_none() => Ok(sdk::ArcSpec::Border { end, via }),
        (None, None, Some(_)) => Err(PyValueError::new_err(
            "an arc through `via` follows the points: no `ccw`",
        )),
        _ => Err(PyValueError::new_err(
            "an arc: exactly one of `centre`, `radius`, `via`",
        )),
    }
}

fn finish(mut s: sdk::Segment, relative: bool, last: bool) -> Segment {
    s.relative = relative;
    s.last = last;
    Segment { segment: s }
}

/// A NURBS curve: `Nurbs(control_points, degree=3)`, checked when made.
#[pyclass(module = "motioncard", frozen)]
#[derive(Clone)]
pub struct Nurbs {
    curve: sdk::Nurbs,
}

impl Nurbs {
    /// The curve of these arguments, as `Nurbs(...)` takes them.
    fn build(
        control_points: Vec<Vec<f64>>,
        degree: usize,
        weights: Option<Vec<f64>>,
        knots: Option<Vec<f64>>,
    ) -> PyResult<Nurbs> {
        let a = curve_args(control_points, degree, weights, knots)?;
        let curve = py(
            sdk::Nurbs::new(degree, a.dim, &a.ctrl, &a.weights, &a.knots).map_err(sdk::Error::from),
        )?;
        Ok(Nurbs { curve })
    }
}

/// A curve's arguments as `sdk::Nurbs::new` takes them.
struct CurveArgs {
    dim: usize,
    ctrl: Vec<f64>,
    weights: Vec<f64>,
    knots: Vec<f64>,
}

/// The dimension, the flat control points, the weights (default 1) and the knots (default
/// clamped uniform) of a curve given as Python gives it.
fn curve_args(
    control_points: Vec<Vec<f64>>,
    degree: usize,
    weights: Option<Vec<f64>>,
    knots: Option<Vec<f64>>,
) -> PyResult<CurveArgs> {
    let n = control_points.len();
    let dim = control_points.first().map_or(0, Vec::len);
    if control_points.iter().any(|c| c.len() != dim) {
        return Err(PyValueError::new_err(
            "control points: the same number of values each",
        ));
    }
    let weights = weights.unwrap_or_else(|| vec![1.0; n]);
    let knots = match knots {
        Some(k) => k,
        None => py(sdk::clamped_uniform_knots(n, degree).map_err(sdk::Error::from))?,
    };
    Ok(CurveArgs {
        dim,
        ctrl: control_points.concat(),
        weights,
        knots,
    })
}

#[pymethods]
impl Nurbs {
    /// A curve of `degree` (1 to 5) through `control_points` (one value per group axis each,
    /// the group's user units), with `weights` (default 1) and `knots` (clamped: the first and
    /// last repeated degree + 1 times; default uniform). A curve that is not one raises its
    /// error: `NurbsDegreeError`, `NurbsCtrlCountError`, `NurbsKnotCountError`,
    /// `NurbsKnotsDecreasingError`, `NurbsKnotMultiplicityError`, `NurbsNotClampedError`,
    /// `NurbsWeightError`, ...; control points of different lengths: `ValueError`.
    #[new]
    #[pyo3(signature = (control_points, *, degree = 3, weights = None, knots = None))]
    fn new(
        control_points: Vec<Vec<f64>>,
        degree: usize,
        weights: Option<Vec<f64>>,
        knots: Option<Vec<f64>>,
    ) -> PyResult<Nurbs> {
        Nurbs::build(control_points, degree, weights, knots)
    }

    /// A curve of any number of control points cut into pieces of at most `max_ctrl` (default
    /// and at most the card's `NURBS_MAX_CTRL`) for `Group.move_nurbs_path`: exactly the curve,
    /// each piece starting where the one before ends. Arguments as `Nurbs(...)`.
    #[staticmethod]
    #[pyo3(signature = (control_points, *, degree = 3, weights = None, knots = None, max_ctrl = sdk::NURBS_MAX_CTRL))]
    fn split(
        control_points: Vec<Vec<f64>>,
        degree: usize,
        weights: Option<Vec<f64>>,
        knots: Option<Vec<f64>>,
        max_ctrl: usize,
    ) -> PyResult<Vec<Nurbs>> {
        let a = curve_args(control_points, degree, weights, knots)?;
        let pieces = py(
            sdk::split_nurbs(degree, a.dim, &a.ctrl, &a.weights, &a.knots, max_ctrl)
                .map_err(sdk::Error::from),
        )?;
        Ok(pieces.into_iter().map(|curve| Nurbs { curve }).collect())
    }

    /// The degree.
    #[getter]
    fn degree(&self) -> usize {
        self.curve.degree()
    }

    /// The control points, one list per point.
    #[getter]
    fn control_points(&self) -> Vec<Vec<f64>> {
        let d = self.curve.dim();
        (0..self.curve.n_ctrl())
            .filter_map(|i| self.curve.control_point(i))
            .map(|pt| pt.as_slice()[..d].to_vec())
            .collect()
    }

    /// The weights.
    #[getter]
    fn weights(&self) -> Vec<f64> {
        (0..self.curve.n_ctrl())
            .filter_map(|i| self.curve.weight(i))
            .collect()
    }

    /// The knot vector.
    #[getter]
    fn knots(&self) -> Vec<f64> {
        self.curve.knots().to_vec()
    }

    /// The point of the curve at parameter `u`, from the first knot to the last (outside, or
    /// not finite: an error).
    fn point(&self, u: f64) -> PyResult<Vec<f64>> {
        let pt = py(self.curve.point(u).map_err(sdk::Error::from))?;
        Ok(pt.as_slice()[..self.curve.dim()].to_vec())
    }

    fn __repr__(&self) -> String {
        format!(
            "<motioncard.Nurbs degree {}, {} control points of {} axes>",
            self.curve.degree(),
            self.curve.n_ctrl(),
            self.curve.dim()
        )
    }
}

/// An axes group of a card.
#[pyclass(module = "motioncard", frozen)]
pub struct Group {
    pub(crate) group: sdk::Group,
}

fn options(relative: bool, buffered: bool) -> sdk::MoveOptions {
    sdk::MoveOptions {
        relative,
        buffered,
        ..Default::default()
    }
}

fn motion(m: sdk::Result<sdk::GroupMotion>) -> PyResult<GroupMotion> {
    Ok(GroupMotion { motion: py(m)? })
}

#[pymethods]
impl Group {
    /// The group's number.
    #[getter]
    fn index(&self) -> usize {
        self.group.index()
    }

    /// Make the group of these card axes (its X, Y, Z, ...; 1 to 8), exact arcs;
    /// `tolerance`: the geometry tolerance in the first axis's units. `accdec`: "pre" (an
    /// S-curve of the feed along the path, the default), "post" (constant feed along the
    /// path, each axis's acc/dec filter after interpolation: `Axis.set_filters`) or "both".
    #[pyo3(signature = (axes, *, tolerance = None, accdec = "pre"))]
    fn configure(
        &self,
        p: Python<'_>,
        axes: Vec<usize>,
        tolerance: Option<f64>,
        accdec: &str,
    ) -> PyResult<()> {
        let mut s = sdk::GroupSettings::new(&axes);
        if let Some(t) = tolerance {
            s.tolerance = t;
        }
        s.accdec = match accdec {
            "pre" => sdk::AccDec::Pre,
            "post" => sdk::AccDec::Post,
            "both" => sdk::AccDec::Both,
            other => {
                return Err(PyValueError::new_err(format!(
                    "accdec {other:?}: \"pre\", \"post\" or \"both\""
                )))
            }
        };
        py(p.allow_threads(|| self.group.configure(&s)))
    }

    /// The group's path (the look-ahead buffer that G-code and `move_path` use), every axis
    /// limited to `velocity`, `acceleration` and `jerk`.
    fn configure_path(
        &self,
        p: Python<'_>,
        velocity: f64,
        acceleration: f64,
        jerk: f64,
    ) -> PyResult<()> {
        let n = self.axes()?.len();
        let s = sdk::PathSettings::uniform(n, velocity, acceleration, jerk);
        py(p.allow_threads(|| self.group.configure_path(&s)))
    }

    /// The card axes of the group, in order (empty: not configured).
    fn axes(&self) -> PyResult<Vec<usize>> {
        Ok(py(self.group.settings())?
            .map(|s| s.axes)
            .unwrap_or_default())
    }

    /// Enable the group (its axes enabled).
    fn enable(&self, p: Python<'_>) -> PyResult<()> {
        py(p.allow_threads(|| self.group.enable()))
    }

    /// Disable the group.
    fn disable(&self, p: Python<'_>) -> PyResult<()> {
        py(p.allow_threads(|| self.group.disable()))
    }

    /// A straight line to `target` (one value per group axis) within `limits`; `relative`:
    /// from where the previous move ends; `buffered`: behind the moves queued. `feed_type`
    /// ("rapid", "cutting" or "jog") picks each axis's acc/dec filter (`Axis.set_filters`)
    /// in a group configured with `accdec="post"` or "both".
    #[pyo3(signature = (target, limits, *, relative = false, buffered = false, feed_type = "cutting"))]
    fn move_linear(
        &self,
        p: Python<'_>,
        target: Vec<f64>,
        limits: PathLimits,
        relative: bool,
        buffered: bool,
        feed_type: &str,
    ) -> PyResult<GroupMotion> {
        let mut o = options(relative, buffered);
        o.feed_type = match feed_type {
            "rapid" => sdk::FeedType::Rapid,
            "cutting" => sdk::FeedType::Cutting,
            "jog" => sdk::FeedType::Jog,
            other => {
                return Err(PyValueError::new_err(format!(
                    "feed_type {other:?}: \"rapid\", \"cutting\" or \"jog\""
                )))
            }
        };
        motion(p.allow_threads(|| self.group.move_linear(&target, &limits.limits, o)))
    }

    /// Synchronised point-to-point: every axis starts and ends together.
    #[pyo3(signature = (target, limits, *, relative = false, buffered = false))]
    fn move_ptp(
        &self,
        p: Python<'_>,
        target: Vec<f64>,
        limits: PathLimits,
        relative: bool,
        buffered: bool,
    ) -> PyResult<GroupMotion> {
        let o = options(relative, buffered);
        motion(p.allow_threads(|| self.group.move_ptp(&target, &limits.limits, o)))
    }

    /// MC_MoveCircular: an arc to `end` within `limits` (along the path), given one of three
    /// ways: around `centre` (`end` at the start: a full circle), of `radius` (negative: the
    /// arc longer than half a turn), both counter-clockwise unless `ccw=False`; or through the
    /// point `via` on it (a three-point circle; the direction follows the points).
    /// `plane`: "XY" (G17, default), "ZX" (G18), "YZ" (G19), any other two of X, Y, Z (group
    /// axes 0, 1, 2; "XZ" is counter-clockwise from X towards Z, G18's reverse), or a pair
    /// `(u, v)` of group axes; `end`, `centre` and `via` are (u, v) coordinates in it.
    /// `helix`: targets of the group's other axes, which move linearly with it (empty: they
    /// stay). Refused: `RadiusTooSmallError`, `CentreNotEquidistantError`,
    /// `CollinearPointsError`, `ZeroLengthArcError`, `PlaneAxesError`, ...
    #[pyo3(signature = (end, centre = None, limits = None, *, radius = None, via = None, ccw = None, plane = None, helix = Vec::new(), relative = false, buffered = false))]
    #[allow(clippy::too_many_arguments)]
    fn move_circular(
        &self,
        p: Python<'_>,
        end: [f64; 2],
        centre: Option<[f64; 2]>,
        limits: Option<PathLimits>,
        radius: Option<f64>,
        via: Option<[f64; 2]>,
        ccw: Option<bool>,
        plane: Option<PlaneArg>,
        helix: Vec<f64>,
        relative: bool,
        buffered: bool,
    ) -> PyResult<GroupMotion> {
        let arc = arc_spec(end, centre, radius, via, ccw)?;
        let plane = self::plane(plane)?;
        let limits =
            limits.ok_or_else(|| PyTypeError::new_err("Group.move_circular: limits is missing"))?;
        let o = options(relative, buffered);
        motion(p.allow_threads(|| {
            self.group
                .move_circular(&arc, plane, &helix, &limits.limits, o)
        }))
    }

    /// MC_MoveCircular in the plane of three group axes `axes` (default X, Y, Z) given by its
    /// `normal`: counter-clockwise about it (the right-hand rule; reverse the normal for the
    /// other way) in the plane through the start, around `centre`, to `end` (at the start: a
    /// full turn), then `turns` more full turns, a rest-to-rest S-curve within `limits` along
    /// it. `centre` and `end` are on the three axes, in order (they need one scale); with
    /// `rise` the end may lie off the plane along the normal (a helix along it); `helix`: the
    /// group's other axes' targets (empty: they stay). Refused: `ArcNormalError` (a zero
    /// normal), `ArcAxesError` (an axis twice), `ArcOffPlaneError` (the centre, or without
    /// `rise` the end, off the plane), `CentreNotEquidistantError`, `ZeroLengthArcError`,
    /// `BadAxisError`, `NotFiniteError`; nothing is queued.
    #[pyo3(signature = (end, centre, limits, *, normal, axes = [0, 1, 2], rise = false, turns = 0, helix = Vec::new(), relative = false, buffered = false))]
    #[allow(clippy::too_many_arguments)]
    fn move_circular_normal(
        &self,
        p: Python<'_>,
        end: [f64; 3],
        centre: [f64; 3],
        limits: PathLimits,
        normal: [f64; 3],
        axes: [usize; 3],
        rise: bool,
        turns: u32,
        helix: Vec<f64>,
        relative: bool,
        buffered: bool,
    ) -> PyResult<GroupMotion> {
        let arc = sdk::NormalArc {
            axes,
            normal,
            centre,
            end,
            rise,
            turns,
        };
        let o = options(relative, buffered);
        motion(p.allow_threads(|| {
            self.group
                .move_circular_normal(&arc, &helix, &limits.limits, o)
        }))
    }

    /// MC_GroupHalt: decelerate along the path to rest.
    fn halt(&self, p: Python<'_>, deceleration: f64, jerk: f64) -> PyResult<GroupMotion> {
        motion(p.allow_threads(|| self.group.halt(deceleration, jerk)))
    }

    /// MC_GroupStop: decelerate and stay stopped until `release_stop`.
    fn stop(&self, p: Python<'_>, deceleration: f64, jerk: f64) -> PyResult<GroupMotion> {
        motion(p.allow_threads(|| self.group.stop(deceleration, jerk)))
    }

    /// Leave the stopped state.
    fn release_stop(&self, p: Python<'_>) -> PyResult<()> {
        py(p.allow_threads(|| self.group.release_stop()))
    }

    /// MC_GroupReset: out of ErrorStop.
    fn reset(&self, p: Python<'_>) -> PyResult<()> {
        py(p.allow_threads(|| self.group.reset()))
    }

    /// Feed and rapid overrides (1.0 = 100 %).
    fn set_override(&self, p: Python<'_>, feed: f64, rapid: f64) -> PyResult<()> {
        py(p.allow_threads(|| self.group.set_override(feed, rapid)))
    }

    /// Wait for the last move queued on the group.
    #[pyo3(signature = (timeout = None))]
    fn wait_done(&self, p: Python<'_>, timeout: Option<f64>) -> PyResult<()> {
        wait_sliced(p, timeout, |s| self.group.wait_done(s))
    }

    /// Send `segments` to the group's path (configured with `configure_path`): queued as the
    /// path has room while it runs (runs of lines that sample a curve are sent as that curve).
    /// Returns the last segment's motion (wait on it for the end of the path), None when
    /// nothing was queued. A refusal raises its error with `index` (the segment that failed)
    /// and `accepted` (how many the card took) set on it; Ctrl-C cancels the stream.
    fn stream_path(
        &self,
        p: Python<'_>,
        segments: Vec<crate::path::ItemArg>,
    ) -> PyResult<Option<GroupMotion>> {
        let items: Vec<sdk::PathItem> = segments.into_iter().map(Into::into).collect();
        let streamer = self.group.spawn_path_stream(items);
        while !streamer.is_finished() {
            if let Err(e) = p.check_signals() {
                streamer.cancel();
                let _ = p.allow_threads(|| streamer.join());
                return Err(e);
            }
            p.allow_threads(|| std::thread::sleep(std::time::Duration::from_millis(2)));
        }
        match p.allow_threads(|| streamer.join()) {
            Ok(m) => Ok(m.map(|motion| GroupMotion { motion })),
            Err(e) => {
                let err = PyErr::from(crate::errors::Error(e.error));
                let v = err.value(p);
                v.setattr("index", e.index)?;
                v.setattr("accepted", e.accepted)?;
                Err(err)
            }
        }
    }

    /// Queue one item (a `Segment` or a `PathOutput`) on the group's path and wait for the
    /// card's answer: a segment's motion (its `wait` is the path's end when it is the last
    /// one queued), None for an output action. A segment `with_buffer("aborting")` replaces
    /// what is queued. Refused with the segment's own error, nothing queued changing.
    fn path_push(
        &self,
        p: Python<'_>,
        item: crate::path::ItemArg,
    ) -> PyResult<Option<GroupMotion>> {
        let output = matches!(item, crate::path::ItemArg::Output(_));
        let item: sdk::PathItem = item.into();
        let m = py(p.allow_threads(|| self.group.path_push(&item)))?;
        Ok((!output).then_some(GroupMotion { motion: m }))
    }

    /// Pause the path at the end of a segment: it comes to rest at the end of the first
    /// segment it can stop at within its limits (an exact stop or a dwell's end ahead, or the
    /// first segment end beyond its braking distance), holds there with the rest queued
    /// (more may be queued meanwhile), and goes on along the same path at `path_resume()`.
    /// `path_pause_state()` says when it is there; the card posts `EventKind.PATH_PAUSED`.
    fn path_pause(&self, p: Python<'_>) -> PyResult<()> {
        py(p.allow_threads(|| self.group.path_pause()))
    }

    /// End a pause: the path goes on from the pause point (asked before it got there, it
    /// does not stop).
    fn path_resume(&self, p: Python<'_>) -> PyResult<()> {
        py(p.allow_threads(|| self.group.path_resume()))
    }

    /// Where a pause is: ("none", None), ("pausing", None) while braking for the pause
    /// point, or ("paused", id) at rest on the end of segment `id` (0: none ran).
    fn path_pause_state(&self) -> PyResult<(&'static str, Option<u32>)> {
        Ok(match py(self.group.path_pause_state())? {
            sdk::PauseState::None => ("none", None),
            sdk::PauseState::Pausing => ("pausing", None),
            sdk::PauseState::Paused { id } => ("paused", Some(id)),
        })
    }

    /// Free entries in the card's path buffer.
    fn path_free(&self) -> PyResult<usize> {
        py(self.group.path_free())
    }

    /// Run the card's path-speed output (PSO) on this group (configured): the output is
    /// `clamp(min + (max - min)·v/v_ref, min, max)` from the group's actual tangential speed
    /// `v` (user units/s), while digital output `gate` is on (the path's M62-M65 outputs).
    /// `output`: a spare DAC output (`min`, `max` in volts), or with `pwm_hz` a PWM on that
    /// digital output (duties 0 to 1). `filter_hz`: the speed filter (0: none).
    /// `PsoConfigError`, `PsoGroupError`, `PsoOutputError`, `NotFiniteError`.
    #[pyo3(signature = (output, *, gate, min, max, v_ref, pwm_hz = None, filter_hz = 0.0))]
    #[allow(clippy::too_many_arguments)]
    fn pso(
        &self,
        p: Python<'_>,
        output: usize,
        gate: usize,
        min: f64,
        max: f64,
        v_ref: f64,
        pwm_hz: Option<f64>,
        filter_hz: f64,
    ) -> PyResult<()> {
        let s = crate::machine::pso(output, pwm_hz, gate, min, max, v_ref, filter_hz);
        py(p.allow_threads(|| self.group.pso(&s)))
    }

    /// Move along a NURBS curve of `degree` through `control_points` (one value per group
    /// axis each, absolute, the first where the group's path is), with `weights` (default 1)
    /// and `knots` (clamped; default uniform), at `feed` within `acceleration` and `jerk`
    /// along it; the feed is lowered where the curvature needs it to keep the chord error
    /// within `chord_tolerance` (default one count), and with `saturation` (a fraction of
    /// the drives' limit, PD+ on every axis) where the drives would saturate. A curve the
    /// card does not take: its `Nurbs*Error`.
    #[pyo3(signature = (control_points, *, degree, feed, acceleration, jerk, weights = None, knots = None, chord_tolerance = None, saturation = None, buffered = false))]
    #[allow(clippy::too_many_arguments)]
    fn move_nurbs(
        &self,
        p: Python<'_>,
        control_points: Vec<Vec<f64>>,
        degree: usize,
        feed: f64,
        acceleration: f64,
        jerk: f64,
        weights: Option<Vec<f64>>,
        knots: Option<Vec<f64>>,
        chord_tolerance: Option<f64>,
        saturation: Option<f64>,
        buffered: bool,
    ) -> PyResult<GroupMotion> {
        let curve = Nurbs::build(control_points, degree, weights, knots)?.curve;
        let f = sdk::NurbsFeed {
            chord_tolerance,
            saturation,
            ..sdk::NurbsFeed::new(feed, acceleration, jerk)
        };
        let o = options(false, buffered);
        motion(p.allow_threads(|| self.group.move_nurbs(&curve, &f, o)))
    }

    /// Move along a NURBS path of several `pieces` (`Nurbs`, each starting where the one
    /// before ends, the first where the group's path is), at `feed` within `acceleration`
    /// and `jerk`, the feed lowered as `move_nurbs` lowers it: the pieces are queued one after
    /// another, waiting for earlier ones to finish whenever the group's queue is full (up to
    /// `timeout` seconds each; None: no end); pieces that join with the same tangent (as
    /// `Nurbs.split`'s do) run through the joint without stopping while the queue keeps up.
    /// Returns the last piece's motion. A piece the card refuses raises its error (the pieces
    /// before it stay queued); an empty path is `UnsupportedError`.
    #[pyo3(signature = (pieces, *, feed, acceleration, jerk, chord_tolerance = None, saturation = None, timeout = None))]
    #[allow(clippy::too_many_arguments)]
    fn move_nurbs_path(
        &self,
        p: Python<'_>,
        pieces: Vec<Nurbs>,
        feed: f64,
        acceleration: f64,
        jerk: f64,
        chord_tolerance: Option<f64>,
        saturation: Option<f64>,
        timeout: Option<f64>,
    ) -> PyResult<GroupMotion> {
        let f = sdk::NurbsFeed {
            chord_tolerance,
            saturation,
            ..sdk::NurbsFeed::new(feed, acceleration, jerk)
        };
        // `sdk::Group::move_nurbs_path`'s loop, its waits sliced so that Ctrl-C ends them.
        let mut queued = std::collections::VecDeque::new();
        let mut last = None;
        for piece in &pieces {
            loop {
                let r = p.allow_threads(|| {
                    self.group
                        .move_nurbs(&piece.curve, &f, sdk::MoveOptions::buffered())
                });
                match r {
                    Ok(m) => {
                        queued.push_back(m.clone());
                        last = Some(m);
                        break;
                    }
                    Err(e) if e.kind() == sdk::ErrorKind::QueueFull => match queued.pop_front() {
                        Some(m) => wait_sliced(p, timeout, |s| m.wait(s))?,
                        None => return Err(crate::errors::Error(e).into()),
                    },
                    Err(e) => return Err(crate::errors::Error(e).into()),
                }
            }
        }
        let last = last.ok_or_else(|| sdk::Error::Unsupported("an empty NURBS path".into()));
        motion(last)
    }

    /// MC_GroupHome: home the group's axes in `order`, stages of group axis indices (0: the
    /// group's first axis), each stage's axes together with their own homing settings
    /// (`Axis.configure_homing`), a stage once the one before is homed and at rest:
    /// `[[2], [0, 1]]` is Z first, then X and Y. Empty: the group's configured order.
    /// Refused: `GroupDisabledError`, `InvalidStateError`, `AxisBusyError`, `HomeAxisError`
    /// (an index the group does not have), `HomeTwiceError`, `HomeStageError` (an empty
    /// stage, or no order at all), each axis's homing refusals.
    #[pyo3(signature = (order = Vec::new()))]
    fn home(&self, p: Python<'_>, order: Vec<Vec<usize>>) -> PyResult<GroupHoming> {
        let stages: Vec<&[usize]> = order.iter().map(Vec::as_slice).collect();
        Ok(GroupHoming {
            homing: py(p.allow_threads(|| self.group.home(&stages)))?,
        })
    }

    /// A snapshot of the group's status.
    fn status(&self) -> PyResult<GroupStatus> {
        let (state, st) = py(self.group.status())?;
        Ok(GroupStatus {
            state_raw: state as u32,
            queued: st.queued,
        })
    }

    /// Run the RS274/NGC program `text` on the group (enabled, its path configured) to its
    /// end: checked whole first (a wrong line is `GcodeError` and nothing moves), then
    /// queued and run. `axes`: the program's letter of each group axis. Returns how it
    /// ended: "done", "paused" (M0/M1/M60) or "aborted".
    #[pyo3(signature = (text, *, axes = "XYZ", rapid_feed = None, max_feed = None, timeout = None))]
    fn run_gcode(
        &self,
        p: Python<'_>,
        text: &str,
        axes: &str,
        rapid_feed: Option<f64>,
        max_feed: Option<f64>,
        timeout: Option<f64>,
    ) -> PyResult<&'static str> {
        use sdk::gcode::run::{group_position, NoHooks, RunSettings, RunState, Runner};
        use sdk::gcode::{Options, Program};
        let mut run = RunSettings {
            axes: axes.to_string(),
            report: false,
            ..RunSettings::default()
        };
        if let Some(f) = rapid_feed {
            run.rapid_feed = f;
        }
        if let Some(f) = max_feed {
            run.max_feed = f;
        }
        let opts = Options {
            start: py(group_position(&self.group, &run.axes))?,
            ..Options::default()
        };
        for op in Program::from_text(text, &opts) {
            py(op.map_err(sdk::Error::from))?;
        }
        let mut runner = py(Runner::new(
            &self.group,
            Program::from_text(text, &opts),
            run,
            NoHooks,
        ))?;
        let state = wait_sliced(p, timeout, |s| runner.run(s))?;
        Ok(match state {
            RunState::Done => "done",
            RunState::Paused => "paused",
            RunState::Aborted => "aborted",
            RunState::Running | RunState::Draining => "running",
        })
    }

    fn __repr__(&self) -> String {
        format!("<motioncard.Group {}>", self.group.index())
    }
}

/// A group's move in progress.
#[pyclass(module = "motioncard", frozen)]
pub struct GroupMotion {
    motion: sdk::GroupMotion,
}

#[pymethods]
impl GroupMotion {
    /// The seq of the command that queued it.
    #[getter]
    fn seq(&self) -> u32 {
        self.motion.seq()
    }

    /// Wait until the move is done (the group in position); `AbortedError`, `TimeoutError`.
    #[pyo3(signature = (timeout = None))]
    fn wait(&self, p: Python<'_>, timeout: Option<f64>) -> PyResult<()> {
        wait_sliced(p, timeout, |s| self.motion.wait(s))
    }

    /// `await motion`: `motioncard.group_wait_async(motion)`.
    fn __await__<'py>(slf: Bound<'py, Self>) -> PyResult<Bound<'py, PyAny>> {
        let p = slf.py();
        p.import("motioncard")?
            .getattr("group_wait_async")?
            .call1((slf,))?
            .call_method0("__await__")
    }
}

/// A group's homing in progress (`Group.home`).
#[pyclass(module = "motioncard", frozen)]
pub struct GroupHoming {
    homing: sdk::GroupHoming,
}

#[pymethods]
impl GroupHoming {
    /// The command's seq.
    #[getter]
    fn seq(&self) -> u32 {
        self.homing.seq()
    }

    /// Wait until every member is homed and the group stands by: the stages run. A member
    /// that failed (or a halt, stop, disable, safety stop): `HomingFailedError` naming it.
    #[pyo3(signature = (timeout = None))]
    fn wait(&self, p: Python<'_>, timeout: Option<f64>) -> PyResult<usize> {
        wait_sliced(p, timeout, |s| self.homing.wait(s))
    }
}

/// A group's status.
#[pyclass(module = "motioncard", frozen)]
pub struct GroupStatus {
    state_raw: u32,
    /// Moves queued.
    #[pyo3(get)]
    queued: u32,
}

#[pymethods]
impl GroupStatus {
    /// The PLCopen group state (`motioncard.GroupState`).
    #[getter]
    fn state<'py>(&self, p: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        py_enum(p, "GroupState", self.state_raw as i64)
    }
}
