//! The segments of a group's continuous path (see the path module): lines, arcs and helices,
//! NURBS curves, dwells and output actions, each with how it joins the one before it. Plain
//! data, built and checked on the host; the path streamer and the chord fitter both take them.

use crate::group::{ArcSpec, Plane};
use crate::nurbs::Nurbs;

/// How a segment joins the one before it (PLCopen BufferMode).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum PathBuffer {
    /// The running path stops along its geometry within its limits, everything queued is
    /// aborted, and this segment starts from where it came to rest.
    Aborting,
    /// An exact stop at the corner, then this segment.
    Buffered,
    /// A blend; the corner speed is at most the lower of the two feeds.
    #[default]
    BlendingLow,
    /// ... at most the previous segment's feed.
    BlendingPrevious,
    /// ... at most this segment's feed.
    BlendingNext,
    /// ... at most the higher of the two.
    BlendingHigh,
}

/// How a blend is sized (PLCopen TransitionMode), in the first group axis's units.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum Transition {
    /// No blend: an exact stop at the corner.
    #[default]
    None,
    /// The blend stays within this distance of the programmed corner (0: exact stop).
    MaxDeviation(f64),
    /// The blend begins this far before the corner (and ends as far after it).
    CornerDistance(f64),
    /// Thinh's blending (2014, Fig 10), between two lines: each runs as its own rest-to-rest
    /// S-curve, this one starting while the one before decelerates, as early as keeps the path
    /// within this distance of the corner and every axis within its limits (0: exact stop).
    /// Refused (`PathMode`) on or after an arc, and a blend after such a line is refused too.
    TimeShift(f64),
}

/// What a segment is.
#[derive(Debug, Clone, PartialEq)]
pub enum Geometry {
    /// A straight line to `target` (one value per group axis).
    Line {
        /// End point.
        target: Vec<f64>,
    },
    /// An arc in `plane`; `helix` holds the other group axes' targets (empty: they stay).
    Arc {
        /// The arc in its plane's coordinates.
        arc: ArcSpec,
        /// Its plane.
        plane: Plane,
        /// The other axes' targets (a helix), or empty.
        helix: Vec<f64>,
    },
    /// Layout 1.12: an arc in the plane of three group axes given by a normal vector (as APT's
    /// `CIRCLE/` record: centre, axis, then the end): counter-clockwise about `normal` (the
    /// right-hand rule; reversed, the arc runs the other way), in the plane through the start,
    /// around `centre`, to `end` (an end at the start: a full turn). `centre` and `end` are on
    /// the three axes, in order; the card refuses a centre off the plane or an end off the
    /// circle by more than the group's tolerance, and an end off the plane unless `rise`
    /// (then its offset along the normal is a helix's rise). `helix` holds the other group
    /// axes' targets, in group order (empty: they stay). The three axes need one scale.
    ArcNormal {
        /// The plane's group axes a, b, c.
        axes: [usize; 3],
        /// The normal on them (any length but 0).
        normal: [f64; 3],
        /// The centre on a, b, c.
        centre: [f64; 3],
        /// The end on a, b, c.
        end: [f64; 3],
        /// The end may lie off the plane along the normal (a helix along it).
        rise: bool,
        /// The other axes' targets (a helix), or empty.
        helix: Vec<f64>,
    },
    /// A NURBS curve (control points in group axis order and user units), run within
    /// `fit_tolerance` (first axis's units) of the curve. On the card it takes one buffer entry
    /// per piece (quintics fitted to it; [`Group::path_free`](crate::Group::path_free) counts
    /// entries). It must start within `fit_tolerance` of where the segment before ends
    /// (relative: its control points are from there). A time-shifted transition into it is
    /// refused.
    Nurbs {
        /// The curve.
        curve: Nurbs,
        /// Largest distance of the path from the curve.
        fit_tolerance: f64,
    },
    /// An exact stop, then a wait of `seconds`.
    Dwell {
        /// The wait.
        seconds: f64,
    },
}

/// One segment of a path.
#[derive(Debug, Clone, PartialEq)]
pub struct Segment {
    /// The user's id, reported as the segment starts and ends.
    pub id: u32,
    /// What it is.
    pub geometry: Geometry,
    /// Path speed, first group axis's units per second (unused by a dwell).
    pub feed: f64,
    /// How it joins the segment before it.
    pub buffer: PathBuffer,
    /// How the blend into it is sized.
    pub transition: Transition,
    /// Targets (and arc points) relative to where the segment before it ends.
    pub relative: bool,
    /// The last segment of a program: the stop at its end is the end, not starvation.
    pub last: bool,
    /// How far the chord fitter may take a run of lines from their points (G64 Q, LinuxCNC's
    /// "naive CAM" tolerance), first group axis's units; `None`: the transition's
    /// tolerance; 0: the line is sent as it is.
    pub fit_tolerance: Option<f64>,
}

impl Segment {
    /// A line to `target` at `feed`, blended into the one before it within `tolerance` of the
    /// corner (BlendingLow, MaxDeviation; 0 is an exact stop).
    pub fn line(id: u32, target: &[f64], feed: f64, tolerance: f64) -> Self {
        Self {
            id,
            geometry: Geometry::Line {
                target: target.to_vec(),
            },
            feed,
            buffer: PathBuffer::BlendingLow,
            transition: Transition::MaxDeviation(tolerance),
            relative: false,
            last: false,
            fit_tolerance: None,
        }
    }

    /// An arc (helix if `helix` is not empty) at `feed`, blended as [`Segment::line`].
    pub fn arc(
        id: u32,
        arc: ArcSpec,
        plane: Plane,
        helix: &[f64],
        feed: f64,
        tolerance: f64,
    ) -> Self {
        Self {
            geometry: Geometry::Arc {
                arc,
                plane,
                helix: helix.to_vec(),
            },
            ..Self::line(id, &[], feed, tolerance)
        }
    }

    /// An arc in the plane of group axes `axes` with `normal` (see [`Geometry::ArcNormal`]),
    /// counter-clockwise about it around `centre` to `end` (a circle: the end in the plane),
    /// at `feed`, blended as [`Segment::line`]; the other axes stay.
    pub fn arc_normal(
        id: u32,
        axes: [usize; 3],
        normal: [f64; 3],
        centre: [f64; 3],
        end: [f64; 3],
        feed: f64,
        tolerance: f64,
    ) -> Self {
        Self {
            geometry: Geometry::ArcNormal {
                axes,
                normal,
                centre,
                end,
                rise: false,
                helix: vec![],
            },
            ..Self::line(id, &[], feed, tolerance)
        }
    }

    /// A NURBS curve at `feed`, blended into the segment before as [`Segment::line`], run
    /// within `fit_tolerance` of the curve.
    pub fn nurbs(id: u32, curve: Nurbs, feed: f64, tolerance: f64, fit_tolerance: f64) -> Self {
        Self {
            geometry: Geometry::Nurbs {
                curve,
                fit_tolerance,
            },
            ..Self::line(id, &[], feed, tolerance)
        }
    }

    /// A dwell of `seconds` (an exact stop, then a wait).
    pub fn dwell(id: u32, seconds: f64) -> Self {
        Self {
            geometry: Geometry::Dwell { seconds },
            feed: 1.0,
            buffer: PathBuffer::Buffered,
            transition: Transition::None,
            ..Self::line(id, &[], 1.0, 0.0)
        }
    }

    /// With this buffer mode.
    pub fn buffer(mut self, b: PathBuffer) -> Self {
        self.buffer = b;
        self
    }

    /// With this transition.
    pub fn transition(mut self, t: Transition) -> Self {
        self.transition = t;
        self
    }

    /// Relative to the end of the segment before.
    pub fn relative(mut self) -> Self {
        self.relative = true;
        self
    }

    /// Marked as the last of its program.
    pub fn last(mut self) -> Self {
        self.last = true;
        self
    }

    /// Fitted by the chord fitter within `tolerance` of its points (G64 Q) rather than the
    /// transition's tolerance; 0 sends it as it is.
    pub fn fit_within(mut self, tolerance: f64) -> Self {
        self.fit_tolerance = Some(tolerance);
        self
    }
}

/// When an output action fires, in the next motion segment queued after it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum OutputAt {
    /// As it starts.
    Start,
    /// As it ends.
    End,
    /// Once it has run this distance (first group axis's units).
    Distance(f64),
}

/// An item of a path stream.
#[derive(Debug, Clone, PartialEq)]
pub enum PathItem {
    /// A segment.
    Segment(Segment),
    /// Set (`on`) or clear a digital output at a point of the next motion segment.
    Output {
        /// Output number, `0..OUTPUTS`.
        output: u8,
        /// Set, else clear.
        on: bool,
        /// When.
        at: OutputAt,
    },
}

impl From<Segment> for PathItem {
    fn from(s: Segment) -> Self {
        PathItem::Segment(s)
    }
}
