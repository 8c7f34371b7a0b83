//! Axes groups: configuration and state, the move queue (lines, arcs and helices, synchronised
//! point-to-point, NURBS curves) and the continuous path (layout 1.6). The command's target is
//! the group.
//!
//! A move names one target per group axis, in group order; how many a group has is the card's
//! to know, so a move carries [`MAX_AXES`] of them and the card reads its group's (and checks
//! only those). The same holds for the NURBS header's sizes and the path segments' ids: the
//! card checks them after the group's state and the values before them.

use super::{bit, not_in_family, put, set, take, uint, Args, DecodeError, Fault, StopRamp};
use crate::wire::{move_flags, path_flags, Command, NackCode, Opcode, CMD_ARGS};
use crate::{MAX_AXES, NURBS_DATA_MAX, PTP_LIMITS_MAX};
use heapless::Vec;

/// The limits of a group move along its path (counts, seconds; a point-to-point move's per
/// axis): velocity (the feed), acceleration, deceleration, jerk.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FeedLimits {
    /// Velocity.
    pub vmax: f64,
    /// Acceleration.
    pub amax: f64,
    /// Deceleration.
    pub dmax: f64,
    /// Jerk.
    pub jerk: f64,
}

impl FeedLimits {
    /// As arguments, in order.
    pub fn to_array(&self) -> [f64; 4] {
        [self.vmax, self.amax, self.dmax, self.jerk]
    }

    /// From arguments, in order.
    pub fn from_array([vmax, amax, dmax, jerk]: [f64; 4]) -> Self {
        Self {
            vmax,
            amax,
            dmax,
            jerk,
        }
    }
}

/// The flags a group move shares: relative, buffered, the feed type.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct MoveOpts {
    /// Targets relative to the end of the move before (`MC_MOVE_RELATIVE`).
    pub relative: bool,
    /// Queued behind the moves queued (`MC_MOVE_BUFFERED`).
    pub buffered: bool,
    /// The feed type selecting the acc/dec filters (`MC_FEED_*`, 2 bits; 3 is none: the card
    /// refuses it).
    pub feed_type: u8,
}

impl MoveOpts {
    fn bits(&self) -> u32 {
        set(self.relative, move_flags::RELATIVE)
            | set(self.buffered, move_flags::BUFFERED)
            | (self.feed_type as u32 & 3) << move_flags::FEED_TYPE_SHIFT
    }

    fn from_bits(f: u32) -> Self {
        Self {
            relative: bit(f, move_flags::RELATIVE),
            buffered: bit(f, move_flags::BUFFERED),
            feed_type: ((f >> move_flags::FEED_TYPE_SHIFT) & 3) as u8,
        }
    }
}

/// `MC_OP_GROUP_MOVE_LINEAR`, MC_MoveLinear (args: v, a, d, j, then one target per group axis;
/// flags: [`MoveOpts`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinearMove {
    /// The limits along the line.
    pub limits: FeedLimits,
    /// The targets (distances if relative), group axis order; those past the group's axes are
    /// not read.
    pub targets: [f64; MAX_AXES],
    /// Relative, buffered, feed type.
    pub opts: MoveOpts,
}

impl Args for LinearMove {
    fn encode(&self, args: &mut [f64; CMD_ARGS]) -> u32 {
        put(args, 0, &self.limits.to_array());
        put(args, 4, &self.targets);
        self.opts.bits()
    }
    fn decode(flags: u32, args: &[f64; CMD_ARGS]) -> Result<Self, DecodeError> {
        Ok(Self {
            limits: FeedLimits::from_array(take(args, 0)),
            targets: take(args, 4),
            opts: MoveOpts::from_bits(flags),
        })
    }
}

/// `MC_OP_GROUP_MOVE_PTP`, synchronised point-to-point (Kim eq 10–14; args as a line's; flags:
/// [`MoveOpts`], `MC_PTP_AXIS_LIMITS`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PtpMove {
    /// The limits (per axis), the targets and the options, as a line's.
    pub line: LinearMove,
    /// Each axis also within the limits staged for it (`MC_PTP_AXIS_LIMITS`).
    pub axis_limits: bool,
}

impl Args for PtpMove {
    fn encode(&self, args: &mut [f64; CMD_ARGS]) -> u32 {
        self.line.encode(args) | set(self.axis_limits, move_flags::PTP_AXIS_LIMITS)
    }
    fn decode(flags: u32, args: &[f64; CMD_ARGS]) -> Result<Self, DecodeError> {
        Ok(Self {
            line: LinearMove::decode(flags, args)?,
            axis_limits: bit(flags, move_flags::PTP_AXIS_LIMITS),
        })
    }
}

/// An arc's flags: how `aux` is read, the plane, the direction, helix distances.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct ArcFlags {
    /// `MC_CIRC_BY_CENTRE`, `_RADIUS` or `_BORDER` (2 bits; 3 is none: the card refuses it).
    pub mode: u8,
    /// `MC_PLANE_XY`, `_YZ`, `_ZX` or `_AXES` (2 bits).
    pub plane: u8,
    /// `MC_PLANE_AXES`: the plane's group axes (3 bits each; 0 otherwise).
    pub axes: (u8, u8),
    /// Counter-clockwise (else clockwise; ignored for a border-point arc).
    pub ccw: bool,
    /// The helical targets are distances even in an absolute move.
    pub helix_relative: bool,
}

impl ArcFlags {
    fn bits(&self) -> u32 {
        (self.mode as u32 & 3) << move_flags::CIRC_MODE_SHIFT
            | (self.plane as u32 & 3) << move_flags::PLANE_SHIFT
            | (self.axes.0 as u32 & 7) << move_flags::CIRC_U_SHIFT
            | (self.axes.1 as u32 & 7) << move_flags::CIRC_V_SHIFT
            | set(self.ccw, move_flags::CIRC_CCW)
            | set(self.helix_relative, move_flags::CIRC_HELIX_RELATIVE)
    }

    fn from_bits(f: u32) -> Self {
        Self {
            mode: ((f >> move_flags::CIRC_MODE_SHIFT) & 3) as u8,
            plane: ((f >> move_flags::PLANE_SHIFT) & 3) as u8,
            axes: (
                ((f >> move_flags::CIRC_U_SHIFT) & 7) as u8,
                ((f >> move_flags::CIRC_V_SHIFT) & 7) as u8,
            ),
            ccw: bit(f, move_flags::CIRC_CCW),
            helix_relative: bit(f, move_flags::CIRC_HELIX_RELATIVE),
        }
    }
}

/// An arc's points in its plane and the helical targets.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ArcGeometry {
    /// The end point (u, v).
    pub end: [f64; 2],
    /// The centre, a point on the arc, or (radius, unused), by [`ArcFlags::mode`].
    pub aux: [f64; 2],
    /// The targets of the group's other axes, in group order (a helix).
    pub helix: [f64; MAX_AXES - 2],
    /// Mode, plane, direction, helix distances.
    pub flags: ArcFlags,
}

impl ArcGeometry {
    /// Into `args[at..]`: end, aux, helix; the flag bits.
    fn put(&self, args: &mut [f64; CMD_ARGS], at: usize) -> u32 {
        put(
            args,
            at,
            &[self.end[0], self.end[1], self.aux[0], self.aux[1]],
        );
        put(args, at + 4, &self.helix);
        self.flags.bits()
    }

    fn get(flags: u32, args: &[f64; CMD_ARGS], at: usize) -> Self {
        Self {
            end: take(args, at),
            aux: take(args, at + 2),
            helix: take(args, at + 4),
            flags: ArcFlags::from_bits(flags),
        }
    }
}

/// `MC_OP_GROUP_MOVE_CIRCULAR`, MC_MoveCircular (args: v, a, d, j, end_u, end_v, aux_u, aux_v,
/// then the helical targets of the group's other axes; flags: [`MoveOpts`], [`ArcFlags`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CircularMove {
    /// The limits along the path.
    pub limits: FeedLimits,
    /// The arc.
    pub arc: ArcGeometry,
    /// Relative, buffered, feed type.
    pub opts: MoveOpts,
}

impl Args for CircularMove {
    fn encode(&self, args: &mut [f64; CMD_ARGS]) -> u32 {
        put(args, 0, &self.limits.to_array());
        self.arc.put(args, 4) | self.opts.bits()
    }
    fn decode(flags: u32, args: &[f64; CMD_ARGS]) -> Result<Self, DecodeError> {
        Ok(Self {
            limits: FeedLimits::from_array(take(args, 0)),
            arc: ArcGeometry::get(flags, args, 4),
            opts: MoveOpts::from_bits(flags),
        })
    }
}

/// `MC_OP_GROUP_PTP_LIMITS` (args: first group axis, count (1..MC_PTP_LIMITS_MAX), then v, a, d,
/// j of each): limits staged for the next point-to-point move. A first axis or count that is
/// NaN is `MC_NACK_NOT_FINITE`, any other fault in them `MC_NACK_BAD_CONFIG` (the card checks
/// the group's state before either).
#[derive(Debug, Clone, PartialEq)]
pub struct PtpLimits {
    /// The group axis of the first limits.
    pub first: u32,
    /// The limits of `first`, `first + 1`, ...
    pub limits: Vec<FeedLimits, PTP_LIMITS_MAX>,
}

/// The largest integer the card reads as a count or index of a group command (its `whole`).
const WHOLE_MAX: u64 = 1_000_000_000;

impl Args for PtpLimits {
    fn encode(&self, args: &mut [f64; CMD_ARGS]) -> u32 {
        put(args, 0, &[self.first as f64, self.limits.len() as f64]);
        for (k, l) in self.limits.iter().enumerate() {
            put(args, 2 + 4 * k, &l.to_array());
        }
        0
    }
    fn decode(_: u32, args: &[f64; CMD_ARGS]) -> Result<Self, DecodeError> {
        let nan = NackCode::NotFinite;
        if !args[0].is_finite() {
            return Err(DecodeError::arg(0, Fault::NotFinite, nan));
        }
        if !args[1].is_finite() {
            return Err(DecodeError::arg(1, Fault::NotFinite, nan));
        }
        let bad = NackCode::BadConfig;
        let first = uint(args, 0, WHOLE_MAX, nan, bad)?;
        let count = uint(args, 1, WHOLE_MAX, nan, bad)? as usize;
        if count == 0 || count > PTP_LIMITS_MAX {
            return Err(DecodeError::arg(1, Fault::OutOfRange, bad));
        }
        let mut limits = Vec::new();
        for k in 0..count {
            let _ = limits.push(FeedLimits::from_array(take(args, 2 + 4 * k))); // <= capacity
        }
        Ok(Self {
            first: first as u32,
            limits,
        })
    }
}

/// `MC_OP_GROUP_SET_OVERRIDE`, a group's MC_SetOverride (args: feed factor, rapid factor).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GroupOverride {
    /// The factor of lines, arcs and the path.
    pub feed: f64,
    /// The factor of point-to-point moves.
    pub rapid: f64,
}

impl Args for GroupOverride {
    fn encode(&self, args: &mut [f64; CMD_ARGS]) -> u32 {
        put(args, 0, &[self.feed, self.rapid]);
        0
    }
    fn decode(_: u32, args: &[f64; CMD_ARGS]) -> Result<Self, DecodeError> {
        Ok(Self {
            feed: args[0],
            rapid: args[1],
        })
    }
}

/// The most stages of a group's home order (`MC_GROUP_HOME_STAGES`).
pub const GROUP_HOME_STAGES: usize = crate::raw::MC_GROUP_HOME_STAGES as usize;

/// `MC_OP_GROUP_HOME`, MC_GroupHome (layout 1.11): args: the stage count (0: the group's
/// configured order), then each stage's mask of group axes. Carried as sent: the card checks
/// the count and the masks in its order (see the header), after the group's state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GroupHome {
    /// The stage count.
    pub stages: f64,
    /// Stage k's group axes (bit i: group axis i).
    pub masks: [f64; GROUP_HOME_STAGES],
}

impl GroupHome {
    /// The command of an order given as masks (at most [`GROUP_HOME_STAGES`]; an empty slice:
    /// the configured order).
    pub fn from_masks(masks: &[u8]) -> Self {
        let mut m = [0.0; GROUP_HOME_STAGES];
        for (x, &b) in m.iter_mut().zip(masks) {
            *x = f64::from(b);
        }
        Self {
            stages: masks.len() as f64,
            masks: m,
        }
    }
}

impl Args for GroupHome {
    fn encode(&self, args: &mut [f64; CMD_ARGS]) -> u32 {
        args[0] = self.stages;
        put(args, 1, &self.masks);
        0
    }
    fn decode(_: u32, args: &[f64; CMD_ARGS]) -> Result<Self, DecodeError> {
        Ok(Self {
            stages: args[0],
            masks: take(args, 1),
        })
    }
}

/// A NURBS curve's sizes as sent: degree, control points, knots (integers with `n_knots =
/// n_ctrl + degree + 1`, checked by the card after the group's state and the header's other
/// values, with the group's axis count in between).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CurveSize {
    /// Degree (1..5).
    pub degree: f64,
    /// Control points.
    pub n_ctrl: f64,
    /// Knots.
    pub n_knots: f64,
}

impl CurveSize {
    /// As arguments, in order.
    pub fn to_array(self) -> [f64; 3] {
        [self.degree, self.n_ctrl, self.n_knots]
    }

    /// From arguments, in order.
    pub fn from_array([degree, n_ctrl, n_knots]: [f64; 3]) -> Self {
        Self {
            degree,
            n_ctrl,
            n_knots,
        }
    }
}

/// `MC_OP_NURBS_BEGIN` (args: degree, n_ctrl, n_knots, feed, accel, jerk, chord tolerance,
/// saturation budget; flags: `MC_MOVE_BUFFERED`, `MC_NURBS_SATURATION`, the feed type): opens a
/// curve's transfer; `MC_OP_NURBS_DATA` entries follow, `MC_OP_NURBS_END` queues it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NurbsBegin {
    /// The curve's sizes.
    pub size: CurveSize,
    /// The feed along the curve, counts/s.
    pub feed: f64,
    /// Tangential acceleration.
    pub accel: f64,
    /// Tangential jerk.
    pub jerk: f64,
    /// The chord tolerance (> 0), counts.
    pub chord_tolerance: f64,
    /// The saturation-aware feed's budget, (0, 1] (0 allowed without it).
    pub budget: f64,
    /// Queued behind the moves queued.
    pub buffered: bool,
    /// The saturation-aware feed (Yeh §3.4).
    pub saturation: bool,
    /// The feed type (`MC_FEED_*`; 3 is taken as jog).
    pub feed_type: u8,
}

impl Args for NurbsBegin {
    fn encode(&self, args: &mut [f64; CMD_ARGS]) -> u32 {
        put(args, 0, &self.size.to_array());
        let rest = [
            self.feed,
            self.accel,
            self.jerk,
            self.chord_tolerance,
            self.budget,
        ];
        put(args, 3, &rest);
        set(self.buffered, move_flags::BUFFERED)
            | set(self.saturation, move_flags::NURBS_SATURATION)
            | (self.feed_type as u32 & 3) << move_flags::FEED_TYPE_SHIFT
    }
    fn decode(flags: u32, args: &[f64; CMD_ARGS]) -> Result<Self, DecodeError> {
        Ok(Self {
            size: CurveSize::from_array(take(args, 0)),
            feed: args[3],
            accel: args[4],
            jerk: args[5],
            chord_tolerance: args[6],
            budget: args[7],
            buffered: bit(flags, move_flags::BUFFERED),
            saturation: bit(flags, move_flags::NURBS_SATURATION),
            feed_type: ((flags >> move_flags::FEED_TYPE_SHIFT) & 3) as u8,
        })
    }
}

/// `MC_OP_NURBS_DATA` (args: offset into the stream, count (1..MC_NURBS_DATA_MAX), then count
/// values). Any fault in the offset or count is `MC_NACK_NURBS_SEQUENCE`.
#[derive(Debug, Clone, PartialEq)]
pub struct NurbsData {
    /// Where the values go in the stream (control points, weights, knots).
    pub offset: u32,
    /// The values.
    pub values: Vec<f64, NURBS_DATA_MAX>,
}

impl Args for NurbsData {
    fn encode(&self, args: &mut [f64; CMD_ARGS]) -> u32 {
        put(args, 0, &[self.offset as f64, self.values.len() as f64]);
        put(args, 2, &self.values);
        0
    }
    fn decode(_: u32, args: &[f64; CMD_ARGS]) -> Result<Self, DecodeError> {
        let seq = NackCode::NurbsSequence;
        let offset = uint(args, 0, WHOLE_MAX, seq, seq)?;
        let count = uint(args, 1, NURBS_DATA_MAX as u64, seq, seq)? as usize;
        if count == 0 {
            return Err(DecodeError::arg(1, Fault::OutOfRange, seq));
        }
        Ok(Self {
            offset: offset as u32,
            values: Vec::from_slice(&args[2..2 + count]).unwrap_or_default(),
        })
    }
}

/// A path segment's flags: relative, PLCopen's BufferMode and TransitionMode, the last segment.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct PathFlags {
    /// Targets relative to the path's end (`MC_MOVE_RELATIVE`).
    pub relative: bool,
    /// `MC_PATH_ABORTING` .. `MC_PATH_BLEND_HIGH` (3 bits; 6 and 7 are none: refused).
    pub buffer: u8,
    /// `MC_TM_*` (2 bits).
    pub transition: u8,
    /// The last segment of a program (`MC_PATH_LAST`).
    pub last: bool,
}

impl PathFlags {
    fn bits(&self) -> u32 {
        set(self.relative, move_flags::RELATIVE)
            | (self.buffer as u32 & 7) << path_flags::BUFFER_SHIFT
            | (self.transition as u32 & 3) << path_flags::TRANSITION_SHIFT
            | set(self.last, path_flags::LAST)
    }

    fn from_bits(f: u32) -> Self {
        Self {
            relative: bit(f, move_flags::RELATIVE),
            buffer: path_flags::buffer(f) as u8,
            transition: path_flags::transition(f) as u8,
            last: bit(f, path_flags::LAST),
        }
    }
}

/// `MC_OP_PATH_LINE` (args: id, feed, tolerance, then one target per group axis; flags:
/// [`PathFlags`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathLine {
    /// The user's id (an integer 0..2^32-1; checked by the card after the targets).
    pub id: f64,
    /// The feed, counts/s.
    pub feed: f64,
    /// The blend's tolerance, counts.
    pub tolerance: f64,
    /// The end point (distances if relative), group axis order.
    pub targets: [f64; MAX_AXES],
    /// Relative, buffer and transition modes, last.
    pub flags: PathFlags,
}

impl Args for PathLine {
    fn encode(&self, args: &mut [f64; CMD_ARGS]) -> u32 {
        put(args, 0, &[self.id, self.feed, self.tolerance]);
        put(args, 3, &self.targets);
        self.flags.bits()
    }
    fn decode(flags: u32, args: &[f64; CMD_ARGS]) -> Result<Self, DecodeError> {
        Ok(Self {
            id: args[0],
            feed: args[1],
            tolerance: args[2],
            targets: take(args, 3),
            flags: PathFlags::from_bits(flags),
        })
    }
}

/// `MC_OP_PATH_ARC` (args: id, feed, tolerance, end_u, end_v, aux_u, aux_v, then the other
/// group axes' targets; flags: [`PathFlags`], [`ArcFlags`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathArc {
    /// The user's id (an integer; checked by the card).
    pub id: f64,
    /// The feed, counts/s.
    pub feed: f64,
    /// The blend's tolerance, counts.
    pub tolerance: f64,
    /// The arc, as MC_MoveCircular's.
    pub arc: ArcGeometry,
    /// Relative, buffer and transition modes, last.
    pub flags: PathFlags,
}

impl Args for PathArc {
    fn encode(&self, args: &mut [f64; CMD_ARGS]) -> u32 {
        put(args, 0, &[self.id, self.feed, self.tolerance]);
        self.arc.put(args, 3) | self.flags.bits()
    }
    fn decode(flags: u32, args: &[f64; CMD_ARGS]) -> Result<Self, DecodeError> {
        Ok(Self {
            id: args[0],
            feed: args[1],
            tolerance: args[2],
            arc: ArcGeometry::get(flags, args, 3),
            flags: PathFlags::from_bits(flags),
        })
    }
}

/// `MC_OP_PATH_ARC_PLANE` (layout 1.12; args: a, b, c, n_a, n_b, n_c): the group's plane for
/// normal-vector arcs: three group axes and the normal in their coordinates. The card checks
/// the numbers (whole, distinct group axes; a normal not zero).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathArcPlane {
    /// The plane's three group axes (whole numbers below the group's axis count).
    pub axes: [f64; 3],
    /// The normal, on those axes (any length but 0); the arcs turn counter-clockwise about it.
    pub normal: [f64; 3],
}

impl Args for PathArcPlane {
    fn encode(&self, args: &mut [f64; CMD_ARGS]) -> u32 {
        put(args, 0, &self.axes);
        put(args, 3, &self.normal);
        0
    }
    fn decode(_flags: u32, args: &[f64; CMD_ARGS]) -> Result<Self, DecodeError> {
        Ok(Self {
            axes: take(args, 0),
            normal: take(args, 3),
        })
    }
}

/// `MC_OP_PATH_ARC_NORMAL` (layout 1.12; args: id, feed, tolerance, centre (3), end (3) on the
/// plane's axes, then the other group axes' targets; flags: [`PathFlags`], `MC_ARC_RISE`): an
/// arc in the group's normal plane (`MC_OP_PATH_ARC_PLANE`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathArcNormal {
    /// The user's id (an integer; checked by the card).
    pub id: f64,
    /// The feed, counts/s.
    pub feed: f64,
    /// The blend's tolerance, counts.
    pub tolerance: f64,
    /// The centre, on the plane's axes a, b, c.
    pub centre: [f64; 3],
    /// The end, on the plane's axes a, b, c.
    pub end: [f64; 3],
    /// The targets of the group's other axes, in group order (a helix).
    pub helix: [f64; MAX_AXES - 3],
    /// The end may lie off the plane along the normal (`MC_ARC_RISE`).
    pub rise: bool,
    /// The other axes' targets are distances even in an absolute arc
    /// (`MC_CIRC_HELIX_RELATIVE`).
    pub helix_relative: bool,
    /// Relative, buffer and transition modes, last.
    pub flags: PathFlags,
}

impl Args for PathArcNormal {
    fn encode(&self, args: &mut [f64; CMD_ARGS]) -> u32 {
        put(args, 0, &[self.id, self.feed, self.tolerance]);
        put(args, 3, &self.centre);
        put(args, 6, &self.end);
        put(args, 9, &self.helix);
        set(self.rise, crate::raw::MC_ARC_RISE)
            | set(self.helix_relative, crate::raw::MC_CIRC_HELIX_RELATIVE)
            | self.flags.bits()
    }
    fn decode(flags: u32, args: &[f64; CMD_ARGS]) -> Result<Self, DecodeError> {
        Ok(Self {
            id: args[0],
            feed: args[1],
            tolerance: args[2],
            centre: take(args, 3),
            end: take(args, 6),
            helix: take(args, 9),
            rise: bit(flags, crate::raw::MC_ARC_RISE),
            helix_relative: bit(flags, crate::raw::MC_CIRC_HELIX_RELATIVE),
            flags: PathFlags::from_bits(flags),
        })
    }
}

/// `MC_OP_GROUP_MOVE_CIRCULAR_NORMAL` (layout 1.13; args: v, a, d, j, centre (3), end (3) on
/// the plane's axes, turns; flags: [`MoveOpts`], `MC_ARC_RISE`, `MC_CIRC_HELIX_RELATIVE`):
/// MC_MoveCircular in a plane given by a normal vector. Its plane and the other axes' targets
/// are the [`CircularPlane`] entry published right after it; the card takes the two as one move.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CircularNormalMove {
    /// The limits along the path.
    pub limits: FeedLimits,
    /// The centre, on the plane's axes a, b, c.
    pub centre: [f64; 3],
    /// The end, on the plane's axes a, b, c.
    pub end: [f64; 3],
    /// Full turns added to the arc (a whole number; checked by the card).
    pub turns: f64,
    /// The end may lie off the plane along the normal (`MC_ARC_RISE`).
    pub rise: bool,
    /// The other axes' targets are distances even in an absolute move
    /// (`MC_CIRC_HELIX_RELATIVE`).
    pub helix_relative: bool,
    /// Relative, buffered, feed type.
    pub opts: MoveOpts,
}

impl Args for CircularNormalMove {
    fn encode(&self, args: &mut [f64; CMD_ARGS]) -> u32 {
        put(args, 0, &self.limits.to_array());
        put(args, 4, &self.centre);
        put(args, 7, &self.end);
        args[10] = self.turns;
        set(self.rise, crate::raw::MC_ARC_RISE)
            | set(self.helix_relative, crate::raw::MC_CIRC_HELIX_RELATIVE)
            | self.opts.bits()
    }
    fn decode(flags: u32, args: &[f64; CMD_ARGS]) -> Result<Self, DecodeError> {
        Ok(Self {
            limits: FeedLimits::from_array(take(args, 0)),
            centre: take(args, 4),
            end: take(args, 7),
            turns: args[10],
            rise: bit(flags, crate::raw::MC_ARC_RISE),
            helix_relative: bit(flags, crate::raw::MC_CIRC_HELIX_RELATIVE),
            opts: MoveOpts::from_bits(flags),
        })
    }
}

/// `MC_OP_GROUP_CIRCULAR_PLANE` (layout 1.13; args: a, b, c, n_a, n_b, n_c, then the other
/// group axes' targets in group order): the second entry of a
/// [`CircularNormalMove`], published with it. The card checks the numbers (whole, distinct
/// group axes; a normal not zero; finite targets).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CircularPlane {
    /// The plane's three group axes and its normal on them.
    pub plane: PathArcPlane,
    /// The targets of the group's other axes, in group order (a helix).
    pub helix: [f64; MAX_AXES - 3],
}

impl Args for CircularPlane {
    fn encode(&self, args: &mut [f64; CMD_ARGS]) -> u32 {
        self.plane.encode(args);
        put(args, 6, &self.helix);
        0
    }
    fn decode(flags: u32, args: &[f64; CMD_ARGS]) -> Result<Self, DecodeError> {
        Ok(Self {
            plane: PathArcPlane::decode(flags, args)?,
            helix: take(args, 6),
        })
    }
}

/// `MC_OP_PATH_DWELL` (args: id, seconds; flags: `MC_PATH_LAST`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathDwell {
    /// The user's id (an integer; checked by the card).
    pub id: f64,
    /// The wait, s (0 < t <= MC_MAX_MOVE_TIME).
    pub seconds: f64,
    /// The last segment of a program.
    pub last: bool,
}

impl Args for PathDwell {
    fn encode(&self, args: &mut [f64; CMD_ARGS]) -> u32 {
        put(args, 0, &[self.id, self.seconds]);
        set(self.last, path_flags::LAST)
    }
    fn decode(flags: u32, args: &[f64; CMD_ARGS]) -> Result<Self, DecodeError> {
        Ok(Self {
            id: args[0],
            seconds: args[1],
            last: bit(flags, path_flags::LAST),
        })
    }
}

/// `MC_OP_PATH_OUTPUT` (args: output, on, distance; flags: when, `MC_PATH_OUT_*`): an output
/// action for the next motion segment queued. The card checks the numbers after the path's
/// state (the output an integer below MC_OUTPUTS, `on` 0 or 1).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathOutput {
    /// The output.
    pub output: f64,
    /// Set (1) or clear (0).
    pub on: f64,
    /// At this distance into the segment (`MC_PATH_OUT_AT_DISTANCE`), counts.
    pub distance: f64,
    /// `MC_PATH_OUT_AT_START`, `_AT_END`, `_AT_DISTANCE` (2 bits; 3 is none: refused).
    pub when: u8,
}

impl Args for PathOutput {
    fn encode(&self, args: &mut [f64; CMD_ARGS]) -> u32 {
        put(args, 0, &[self.output, self.on, self.distance]);
        self.when as u32 & 3
    }
    fn decode(flags: u32, args: &[f64; CMD_ARGS]) -> Result<Self, DecodeError> {
        Ok(Self {
            output: args[0],
            on: args[1],
            distance: args[2],
            when: (flags & 3) as u8,
        })
    }
}

/// `MC_OP_PATH_PAUSE` (args: on): 1 pauses the path at the end of the first segment it can
/// stop at, 0 goes on. The card checks the number (0 or 1).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathPause {
    /// 1: pause; 0: go on.
    pub on: f64,
}

impl Args for PathPause {
    fn encode(&self, args: &mut [f64; CMD_ARGS]) -> u32 {
        put(args, 0, &[self.on]);
        0
    }
    fn decode(_flags: u32, args: &[f64; CMD_ARGS]) -> Result<Self, DecodeError> {
        Ok(Self { on: args[0] })
    }
}

/// `MC_OP_PATH_NURBS` (args: id, feed, tolerance, degree, n_ctrl, n_knots, fit tolerance;
/// flags: [`PathFlags`]): a NURBS curve as one path segment; its data follows as a NURBS
/// move's.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathNurbs {
    /// The user's id (an integer; checked by the card).
    pub id: f64,
    /// The feed, counts/s.
    pub feed: f64,
    /// The blend's tolerance, counts.
    pub tolerance: f64,
    /// The curve's sizes.
    pub size: CurveSize,
    /// The largest distance of the commanded path from the curve (> 0), counts.
    pub fit_tolerance: f64,
    /// Relative, buffer and transition modes, last.
    pub flags: PathFlags,
}

impl Args for PathNurbs {
    fn encode(&self, args: &mut [f64; CMD_ARGS]) -> u32 {
        put(args, 0, &[self.id, self.feed, self.tolerance]);
        put(args, 3, &self.size.to_array());
        args[6] = self.fit_tolerance;
        self.flags.bits()
    }
    fn decode(flags: u32, args: &[f64; CMD_ARGS]) -> Result<Self, DecodeError> {
        Ok(Self {
            id: args[0],
            feed: args[1],
            tolerance: args[2],
            size: CurveSize::from_array(take(args, 3)),
            fit_tolerance: args[6],
            flags: PathFlags::from_bits(flags),
        })
    }
}

/// `MC_OP_PATH_MORE` (layout 1.14; args: the targets of a segment's dimensions past those its
/// own entry holds, in order): the second entry of a segment of a path across cards.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathMore {
    /// The targets (those past the segment's dimensions are ignored).
    pub targets: [f64; CMD_ARGS],
}

impl Args for PathMore {
    fn encode(&self, args: &mut [f64; CMD_ARGS]) -> u32 {
        *args = self.targets;
        0
    }
    fn decode(_flags: u32, args: &[f64; CMD_ARGS]) -> Result<Self, DecodeError> {
        Ok(Self { targets: *args })
    }
}

/// `MC_OP_PATH_RELEASE` (layout 1.14; args: count): the oldest `count` staged segments go into
/// the path. The card checks the number (a whole number, 1..=staged).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathRelease {
    /// How many.
    pub count: f64,
}

impl Args for PathRelease {
    fn encode(&self, args: &mut [f64; CMD_ARGS]) -> u32 {
        put(args, 0, &[self.count]);
        0
    }
    fn decode(_flags: u32, args: &[f64; CMD_ARGS]) -> Result<Self, DecodeError> {
        Ok(Self { count: args[0] })
    }
}

/// A group command (the command's target is the group).
#[derive(Debug, Clone, PartialEq)]
pub enum GroupCmd {
    /// `MC_OP_GROUP_CONFIGURE`.
    Configure,
    /// `MC_OP_GROUP_ENABLE`.
    Enable,
    /// `MC_OP_GROUP_DISABLE`.
    Disable,
    /// `MC_OP_GROUP_STOP`.
    Stop(StopRamp),
    /// `MC_OP_GROUP_STOP_RELEASE`.
    StopRelease,
    /// `MC_OP_GROUP_RESET`.
    Reset,
    /// `MC_OP_GROUP_HALT`.
    Halt(StopRamp),
    /// `MC_OP_GROUP_MOVE_LINEAR`.
    MoveLinear(LinearMove),
    /// `MC_OP_GROUP_MOVE_CIRCULAR`.
    MoveCircular(CircularMove),
    /// `MC_OP_GROUP_MOVE_PTP`.
    MovePtp(PtpMove),
    /// `MC_OP_GROUP_PTP_LIMITS`.
    PtpLimits(PtpLimits),
    /// `MC_OP_GROUP_SET_OVERRIDE`.
    SetOverride(GroupOverride),
    /// `MC_OP_NURBS_BEGIN`.
    NurbsBegin(NurbsBegin),
    /// `MC_OP_NURBS_DATA`.
    NurbsData(NurbsData),
    /// `MC_OP_NURBS_END`.
    NurbsEnd,
    /// `MC_OP_PATH_LINE`.
    PathLine(PathLine),
    /// `MC_OP_PATH_ARC`.
    PathArc(PathArc),
    /// `MC_OP_PATH_DWELL`.
    PathDwell(PathDwell),
    /// `MC_OP_PATH_OUTPUT`.
    PathOutput(PathOutput),
    /// `MC_OP_PATH_NURBS`.
    PathNurbs(PathNurbs),
    /// `MC_OP_PATH_PAUSE` (layout 1.11).
    PathPause(PathPause),
    /// `MC_OP_APPLY_GROUP_PATH`.
    ApplyPath,
    /// `MC_OP_GROUP_HOME` (layout 1.11).
    Home(GroupHome),
    /// `MC_OP_PATH_ARC_PLANE` (layout 1.12).
    PathArcPlane(PathArcPlane),
    /// `MC_OP_PATH_ARC_NORMAL` (layout 1.12).
    PathArcNormal(PathArcNormal),
    /// `MC_OP_GROUP_MOVE_CIRCULAR_NORMAL` (layout 1.13).
    MoveCircularNormal(CircularNormalMove),
    /// `MC_OP_GROUP_CIRCULAR_PLANE` (layout 1.13), its second entry.
    CircularPlane(CircularPlane),
    /// `MC_OP_APPLY_GROUP_DIMS` (layout 1.14).
    ApplyDims,
    /// `MC_OP_PATH_MORE` (layout 1.14), a segment's second entry.
    PathMore(PathMore),
    /// `MC_OP_PATH_RELEASE` (layout 1.14).
    PathRelease(PathRelease),
}

impl GroupCmd {
    /// The opcode.
    pub fn opcode(&self) -> Opcode {
        match self {
            Self::Configure => Opcode::GroupConfigure,
            Self::Enable => Opcode::GroupEnable,
            Self::Disable => Opcode::GroupDisable,
            Self::Stop(_) => Opcode::GroupStop,
            Self::StopRelease => Opcode::GroupStopRelease,
            Self::Reset => Opcode::GroupReset,
            Self::Halt(_) => Opcode::GroupHalt,
            Self::MoveLinear(_) => Opcode::GroupMoveLinear,
            Self::MoveCircular(_) => Opcode::GroupMoveCircular,
            Self::MovePtp(_) => Opcode::GroupMovePtp,
            Self::PtpLimits(_) => Opcode::GroupPtpLimits,
            Self::SetOverride(_) => Opcode::GroupSetOverride,
            Self::NurbsBegin(_) => Opcode::NurbsBegin,
            Self::NurbsData(_) => Opcode::NurbsData,
            Self::NurbsEnd => Opcode::NurbsEnd,
            Self::PathLine(_) => Opcode::PathLine,
            Self::PathArc(_) => Opcode::PathArc,
            Self::PathDwell(_) => Opcode::PathDwell,
            Self::PathOutput(_) => Opcode::PathOutput,
            Self::PathNurbs(_) => Opcode::PathNurbs,
            Self::PathPause(_) => Opcode::PathPause,
            Self::ApplyPath => Opcode::ApplyGroupPath,
            Self::Home(_) => Opcode::GroupHome,
            Self::PathArcPlane(_) => Opcode::PathArcPlane,
            Self::PathArcNormal(_) => Opcode::PathArcNormal,
            Self::MoveCircularNormal(_) => Opcode::GroupMoveCircularNormal,
            Self::CircularPlane(_) => Opcode::GroupCircularPlane,
            Self::ApplyDims => Opcode::ApplyGroupDims,
            Self::PathMore(_) => Opcode::PathMore,
            Self::PathRelease(_) => Opcode::PathRelease,
        }
    }

    /// Decode an entry of an opcode of this family.
    pub fn decode(op: Opcode, flags: u32, args: &[f64; CMD_ARGS]) -> Result<Self, DecodeError> {
        let f = flags;
        Ok(match op {
            Opcode::GroupConfigure => Self::Configure,
            Opcode::GroupEnable => Self::Enable,
            Opcode::GroupDisable => Self::Disable,
            Opcode::GroupStop => Self::Stop(Args::decode(f, args)?),
            Opcode::GroupStopRelease => Self::StopRelease,
            Opcode::GroupReset => Self::Reset,
            Opcode::GroupHalt => Self::Halt(Args::decode(f, args)?),
            Opcode::GroupMoveLinear => Self::MoveLinear(Args::decode(f, args)?),
            Opcode::GroupMoveCircular => Self::MoveCircular(Args::decode(f, args)?),
            Opcode::GroupMovePtp => Self::MovePtp(Args::decode(f, args)?),
            Opcode::GroupPtpLimits => Self::PtpLimits(Args::decode(f, args)?),
            Opcode::GroupSetOverride => Self::SetOverride(Args::decode(f, args)?),
            Opcode::NurbsBegin => Self::NurbsBegin(Args::decode(f, args)?),
            Opcode::NurbsData => Self::NurbsData(Args::decode(f, args)?),
            Opcode::NurbsEnd => Self::NurbsEnd,
            Opcode::PathLine => Self::PathLine(Args::decode(f, args)?),
            Opcode::PathArc => Self::PathArc(Args::decode(f, args)?),
            Opcode::PathDwell => Self::PathDwell(Args::decode(f, args)?),
            Opcode::PathOutput => Self::PathOutput(Args::decode(f, args)?),
            Opcode::PathNurbs => Self::PathNurbs(Args::decode(f, args)?),
            Opcode::PathPause => Self::PathPause(Args::decode(f, args)?),
            Opcode::ApplyGroupPath => Self::ApplyPath,
            Opcode::GroupHome => Self::Home(Args::decode(f, args)?),
            Opcode::PathArcPlane => Self::PathArcPlane(Args::decode(f, args)?),
            Opcode::PathArcNormal => Self::PathArcNormal(Args::decode(f, args)?),
            Opcode::GroupMoveCircularNormal => Self::MoveCircularNormal(Args::decode(f, args)?),
            Opcode::GroupCircularPlane => Self::CircularPlane(Args::decode(f, args)?),
            Opcode::ApplyGroupDims => Self::ApplyDims,
            Opcode::PathMore => Self::PathMore(Args::decode(f, args)?),
            Opcode::PathRelease => Self::PathRelease(Args::decode(f, args)?),
            _ => return Err(not_in_family()),
        })
    }

    /// The entry for group `group` (seq 0, no deadline).
    pub fn command(&self, group: u16) -> Command {
        let op = self.opcode();
        match self {
            Self::Stop(a) | Self::Halt(a) => super::entry(op, group, a),
            Self::MoveLinear(a) => super::entry(op, group, a),
            Self::MoveCircular(a) => super::entry(op, group, a),
            Self::MovePtp(a) => super::entry(op, group, a),
            Self::PtpLimits(a) => super::entry(op, group, a),
            Self::SetOverride(a) => super::entry(op, group, a),
            Self::NurbsBegin(a) => super::entry(op, group, a),
            Self::NurbsData(a) => super::entry(op, group, a),
            Self::PathLine(a) => super::entry(op, group, a),
            Self::PathArc(a) => super::entry(op, group, a),
            Self::PathDwell(a) => super::entry(op, group, a),
            Self::PathOutput(a) => super::entry(op, group, a),
            Self::PathNurbs(a) => super::entry(op, group, a),
            Self::PathPause(a) => super::entry(op, group, a),
            Self::Home(a) => super::entry(op, group, a),
            Self::PathArcPlane(a) => super::entry(op, group, a),
            Self::PathArcNormal(a) => super::entry(op, group, a),
            Self::MoveCircularNormal(a) => super::entry(op, group, a),
            Self::CircularPlane(a) => super::entry(op, group, a),
            Self::PathMore(a) => super::entry(op, group, a),
            Self::PathRelease(a) => super::entry(op, group, a),
            Self::Configure
            | Self::Enable
            | Self::Disable
            | Self::StopRelease
            | Self::Reset
            | Self::NurbsEnd
            | Self::ApplyPath
            | Self::ApplyDims => Command::new(op, group),
        }
    }
}
