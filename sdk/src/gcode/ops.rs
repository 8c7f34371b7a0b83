//! Canonical operations: what a program does, in machine coordinates, one operation per
//! action, each naming its source line. The interpreter ([`super::Interp`]) makes them; the
//! runner ([`super::run`]) and `mcctl gcode` consume them.

/// A position in machine coordinates: X, Y, Z in mm, A, B, C in degrees.
pub type Pos = [f64; 6];

/// Moves whose ends are no farther apart than this on any axis (mm, degrees) do not move: the
/// card refuses them, and the runner does not send them.
pub const ZERO_LENGTH: f64 = 1e-6;

/// Axis letters in [`Pos`] order.
pub const AXIS_LETTERS: [char; 6] = ['X', 'Y', 'Z', 'A', 'B', 'C'];

/// The plane of arcs and of cutter compensation (G17, G18, G19).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Plane {
    /// G17: X then Y, normal Z.
    #[default]
    Xy,
    /// G18: Z then X, normal Y.
    Zx,
    /// G19: Y then Z, normal X.
    Yz,
}

impl Plane {
    /// The axis indices (first, second, normal): a right-handed triple, so counter-clockwise
    /// is the positive rotation from the first axis to the second in every plane.
    pub const fn axes(self) -> (usize, usize, usize) {
        match self {
            Plane::Xy => (0, 1, 2),
            Plane::Zx => (2, 0, 1),
            Plane::Yz => (1, 2, 0),
        }
    }
}

/// How a motion meets the next one (G61, G61.1, G64).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum Blend {
    /// G61: stop exactly at the end.
    #[default]
    ExactStop,
    /// G61.1: exact path (no corner rounding), speed kept where the corner allows.
    ExactPath,
    /// G64: blend within `tolerance` mm of the corner (`None`: G64 without P, the best
    /// speed: the runner's own tolerance). `naive` is Q, LinuxCNC's "naive CAM" tolerance:
    /// the chord fitter's (mm; 0 sends each line as it is; `None`: P's, as LinuxCNC).
    #[allow(missing_docs)]
    Blended {
        tolerance: Option<f64>,
        naive: Option<f64>,
    },
}

/// Spindle direction.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SpindleDir {
    /// M3.
    Cw,
    /// M4.
    Ccw,
    /// M5.
    Off,
}

/// What stops the program at an M0, M1 or M60.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PauseKind {
    /// M0: always.
    Program,
    /// M1: when the optional stop switch is on (the interpreter emits it only then).
    Optional,
    /// M60: pallet change, then pause.
    Pallet,
}

/// A spline as a NURBS curve in machine coordinates (G5 and G5.1 become Bézier pieces, G5.2
/// and G5.3 the programmed NURBS): `degree`, control `points` (the first is the start),
/// their `weights` (1 for polynomial curves), and a clamped `knots` vector of
/// `points.len() + degree + 1` values.
#[derive(Debug, Clone, PartialEq)]
#[allow(missing_docs)]
pub struct Spline {
    pub degree: usize,
    pub points: Vec<Pos>,
    pub weights: Vec<f64>,
    pub knots: Vec<f64>,
}

/// A normal-vector arc's circle ([`OpKind::ArcNormal`]): the point at angle θ and height h
/// is `centre + radius·(cos θ·u + sin θ·v) + h·axis`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ArcFrame {
    /// The centre, in the plane through the start (X, Y, Z).
    pub centre: [f64; 3],
    /// Unit, from the centre toward the start.
    pub u: [f64; 3],
    /// Unit, in the plane a quarter turn from `u` the way the arc runs.
    pub v: [f64; 3],
    /// Unit, `u × v`: the axis the arc turns counter-clockwise about (the op's normal, or
    /// its reverse for a clockwise arc).
    pub axis: [f64; 3],
    /// The radius at the start.
    pub radius: f64,
    /// The angle of the partial turn, in (0, 2π] (2π: the end at the start in the plane).
    pub sweep: f64,
    /// The end's height above the plane through the start, along `axis`.
    pub rise: f64,
}

/// One canonical operation and the 1-based source line it came from.
#[derive(Debug, Clone, PartialEq)]
pub struct Op {
    /// 1-based source line.
    pub line: usize,
    /// What it does.
    pub kind: OpKind,
}

/// The operations. Motions carry their start and end; `feed` is along the path in mm/s (for
/// a move of rotary axes alone, deg/s), already converted from G93/G94/G95; `blend` is the
/// path control mode in effect. (Fields are described with their variant.)
#[derive(Debug, Clone, PartialEq)]
#[allow(missing_docs)]
pub enum OpKind {
    /// G0 (and the rapid parts of G28/G30, canned cycles): at the machine's rapid speed.
    Rapid { start: Pos, end: Pos, blend: Blend },
    /// G1 (and feed parts of canned cycles).
    Feed {
        start: Pos,
        end: Pos,
        feed: f64,
        blend: Blend,
    },
    /// G2/G3: a circular arc in `plane` about `centre` (absolute; its normal coordinate is
    /// the start's), the normal axis and A/B/C moving linearly (a helix when the normal
    /// moves). `turns` is the number of full turns beyond the first partial one (G2 P2:
    /// `turns` = 1). Start and end coinciding in the plane is a full turn.
    Arc {
        start: Pos,
        end: Pos,
        centre: [f64; 3],
        plane: Plane,
        ccw: bool,
        turns: u32,
        feed: f64,
        blend: Blend,
    },
    /// G2/G3 in a plane that is not the plane of two machine axes (G18/G19 in a coordinate
    /// system rotated about Z, G10 L2 R): a circular arc about `centre` (absolute, in the plane
    /// through `start`) in the plane through `start` whose unit normal is `normal` (the
    /// program plane's normal axis in machine coordinates, so that `ccw` turns
    /// counter-clockwise about it by the right-hand rule, as [`OpKind::Arc`] in its plane).
    /// What the end has off that plane along `normal` is a helix's rise; A, B, C move
    /// linearly. `turns` as [`OpKind::Arc`]'s; start and end coinciding in the plane is a
    /// full turn.
    ArcNormal {
        start: Pos,
        end: Pos,
        centre: [f64; 3],
        normal: [f64; 3],
        ccw: bool,
        turns: u32,
        feed: f64,
        blend: Blend,
    },
    /// G5, G5.1, G5.2/G5.3.
    Spline {
        start: Pos,
        end: Pos,
        spline: Spline,
        feed: f64,
        blend: Blend,
    },
    /// G38.2–G38.5: move toward `end` until the probe trips (`toward`: G38.2/G38.3, until
    /// it opens: G38.4/G38.5); `must_trip`: G38.2/G38.4 (an error if it does not).
    Probe {
        start: Pos,
        end: Pos,
        feed: f64,
        toward: bool,
        must_trip: bool,
    },
    /// G33 (`tap` false) and G33.1 (`tap` true, which returns along the same line): motion
    /// synchronised with the spindle, `pitch` mm per revolution.
    SpindleSync {
        start: Pos,
        end: Pos,
        pitch: f64,
        tap: bool,
    },
    /// G4: wait `seconds`.
    Dwell { seconds: f64 },
    /// M3/M4/M5 and S: the spindle's speed (rpm) and direction.
    Spindle { speed: f64, dir: SpindleDir },
    /// M19 (and G87's oriented stops): the spindle stopped at `angle` degrees from its index,
    /// turning to it clockwise (`dir` Cw, M19 P0), counter-clockwise (Ccw, P1) or the shorter
    /// way (Off, P2).
    SpindleOrient { angle: f64, dir: SpindleDir },
    /// M7/M8/M9: coolant state after the block.
    Coolant { mist: bool, flood: bool },
    /// M62–M65: digital output `index` on or off, `synced` with the next motion's start
    /// (M62/M63) or at once (M64/M65).
    Output { index: u32, on: bool, synced: bool },
    /// M67 (synced) / M68 (at once): analog output `index` set to `value`.
    AnalogOutput {
        index: u32,
        value: f64,
        synced: bool,
    },
    /// M66: wait for input `index` (digital unless `analog`), `mode` 0–4 as LinuxCNC's L
    /// word, at most `timeout` seconds. The result goes to #5399.
    WaitInput {
        index: u32,
        analog: bool,
        mode: u8,
        timeout: f64,
    },
    /// M6: change to `tool` (a host hook).
    ToolChange { tool: u32 },
    /// M0, M1 (optional stop on), M60.
    Pause { kind: PauseKind },
    /// `(MSG, …)` and `(PRINT, …)`/`(DEBUG, …)` text, parameters substituted.
    Message { text: String },
    /// M48–M53: which overrides are enabled after the block.
    Overrides { feed: bool, spindle: bool },
    /// M100–M199: a user hook with its P and Q words.
    Hook {
        code: u32,
        p: Option<f64>,
        q: Option<f64>,
    },
    /// M2 (`rewind` false) or M30 (`rewind` true): the end of the program.
    End { rewind: bool },
}

impl OpKind {
    /// The name `mcctl gcode --json` prints as `kind`.
    pub fn name(&self) -> &'static str {
        match self {
            OpKind::Rapid { .. } => "rapid",
            OpKind::Feed { .. } => "feed",
            OpKind::Arc { .. } => "arc",
            OpKind::ArcNormal { .. } => "arc_normal",
            OpKind::Spline { .. } => "spline",
            OpKind::Probe { .. } => "probe",
            OpKind::SpindleSync { .. } => "spindle_sync",
            OpKind::Dwell { .. } => "dwell",
            OpKind::Spindle { .. } => "spindle",
            OpKind::SpindleOrient { .. } => "spindle_orient",
            OpKind::Coolant { .. } => "coolant",
            OpKind::Output { .. } | OpKind::AnalogOutput { .. } => "output",
            OpKind::WaitInput { .. } => "wait_input",
            OpKind::ToolChange { .. } => "tool_change",
            OpKind::Pause { .. } => "pause",
            OpKind::Message { .. } => "message",
            OpKind::Overrides { .. } => "overrides",
            OpKind::Hook { .. } => "hook",
            OpKind::End { .. } => "end",
        }
    }

    /// A straight motion (rapid, feed, probe, spindle-synchronised) whose ends are within
    /// [`ZERO_LENGTH`] of each other on every axis. Arcs and splines are never null: start and
    /// end coinciding make a full turn or a closed curve.
    pub fn is_null_motion(&self) -> bool {
        match *self {
            OpKind::Rapid { start, end, .. }
            | OpKind::Feed { start, end, .. }
            | OpKind::Probe { start, end, .. }
            | OpKind::SpindleSync { start, end, .. } => start
                .iter()
                .zip(&end)
                .all(|(a, b)| (a - b).abs() <= ZERO_LENGTH),
            _ => false,
        }
    }

    /// Start and end of a motion.
    pub fn ends(&self) -> Option<(Pos, Pos)> {
        match *self {
            OpKind::Rapid { start, end, .. }
            | OpKind::Feed { start, end, .. }
            | OpKind::Arc { start, end, .. }
            | OpKind::ArcNormal { start, end, .. }
            | OpKind::Spline { start, end, .. }
            | OpKind::Probe { start, end, .. }
            | OpKind::SpindleSync { start, end, .. } => Some((start, end)),
            _ => None,
        }
    }
}
