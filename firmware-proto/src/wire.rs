//! Encodings of what crosses the window: commands, events, status payloads, and the code enums.
//!
//! Each entry is moved as 64-bit words (`to_words` / `from_words`); decoding never fails, and the
//! meaning of a decoded value (is the opcode known, is the axis in range) is checked by whoever
//! acts on it.

use crate::raw;

// The code enums whose variants are the header's defines, generated from it.
pub use crate::codes::{AxisState, EventKind, GroupState, Opcode, StopCategory, StopReason};

/// Arguments per command.
pub const CMD_ARGS: usize = raw::MC_CMD_ARGS as usize;
/// Words per command entry.
pub const CMD_WORDS: usize = crate::layout::CMD_BYTES / 8;
/// Words per event entry.
pub const EVT_WORDS: usize = crate::layout::EVT_BYTES / 8;
/// Values per NURBS data entry.
pub const NURBS_DATA_MAX: usize = raw::MC_NURBS_DATA_MAX as usize;
/// Axes whose limits one `GroupPtpLimits` entry stages.
pub const PTP_LIMITS_MAX: usize = raw::MC_PTP_LIMITS_MAX as usize;
/// Words of a status payload.
pub const STATUS_WORDS: usize = crate::layout::STATUS_WORDS;

code_enum! {
    /// Why a command was refused. One code per distinct fault.
    NackCode: i32 {
        /// The opcode is not defined by this firmware.
        UnknownOpcode = raw::MC_NACK_UNKNOWN_OPCODE,
        /// The axis number is not one of this card's axes.
        BadAxis = raw::MC_NACK_BAD_AXIS,
        /// An argument is NaN or infinite.
        NotFinite = raw::MC_NACK_NOT_FINITE,
        /// A velocity, acceleration or jerk limit is zero or negative.
        NonPositiveLimit = raw::MC_NACK_NON_POSITIVE_LIMIT,
        /// A move was commanded on a disabled axis.
        AxisDisabled = raw::MC_NACK_AXIS_DISABLED,
        /// The command is not allowed in the axis's current state.
        InvalidState = raw::MC_NACK_INVALID_STATE,
        /// A configuration block holds a value out of its range.
        BadConfig = raw::MC_NACK_BAD_CONFIG,
        /// No profile satisfies the request.
        Infeasible = raw::MC_NACK_INFEASIBLE,
        /// A position or distance is beyond the card's range.
        OutOfRange = raw::MC_NACK_OUT_OF_RANGE,
        /// The card configuration can only change while every axis is disabled.
        AxesEnabled = raw::MC_NACK_AXES_ENABLED,
        /// No such group.
        BadGroup = raw::MC_NACK_BAD_GROUP,
        /// An axis already belongs to another group.
        AxisInOtherGroup = raw::MC_NACK_AXIS_IN_OTHER_GROUP,
        /// The move needs an axis the group does not have.
        AxisNotInGroup = raw::MC_NACK_AXIS_NOT_IN_GROUP,
        /// An axis of the group is moving on its own.
        AxisBusy = raw::MC_NACK_AXIS_BUSY,
        /// Single-axis motion on an axis of an enabled group.
        AxisGrouped = raw::MC_NACK_AXIS_GROUPED,
        /// The arc has zero length (or zero radius).
        ZeroLengthArc = raw::MC_NACK_ZERO_LENGTH_ARC,
        /// The centre is not equidistant from start and end within the tolerance.
        CentreNotEquidistant = raw::MC_NACK_CENTRE_NOT_EQUIDISTANT,
        /// The radius is shorter than half the chord.
        RadiusTooSmall = raw::MC_NACK_RADIUS_TOO_SMALL,
        /// The three points of a border-point arc are on one line.
        CollinearPoints = raw::MC_NACK_COLLINEAR_POINTS,
        /// The group's move queue is full.
        QueueFull = raw::MC_NACK_QUEUE_FULL,
        /// The interpolator cannot run with the group's acc/dec mode.
        IncompatibleMode = raw::MC_NACK_INCOMPATIBLE_MODE,
        /// A move on a disabled group.
        GroupDisabled = raw::MC_NACK_GROUP_DISABLED,
        /// Filters can change only while they hold no distance.
        FilterBusy = raw::MC_NACK_FILTER_BUSY,
        /// NURBS data or end without a begin, out of order, or missing.
        NurbsSequence = raw::MC_NACK_NURBS_SEQUENCE,
        /// NURBS degree outside 1..5.
        NurbsDegree = raw::MC_NACK_NURBS_DEGREE,
        /// NURBS on a group of fewer than 2 axes.
        NurbsDimension = raw::MC_NACK_NURBS_DIMENSION,
        /// Too few or too many control points.
        NurbsCtrlCount = raw::MC_NACK_NURBS_CTRL_COUNT,
        /// Knot count is not n_ctrl + degree + 1.
        NurbsKnotCount = raw::MC_NACK_NURBS_KNOT_COUNT,
        /// Knots decrease.
        NurbsKnotsDecreasing = raw::MC_NACK_NURBS_KNOTS_DECREASING,
        /// An interior knot repeated more than degree times.
        NurbsKnotMultiplicity = raw::MC_NACK_NURBS_KNOT_MULTIPLICITY,
        /// End knots not repeated degree + 1 times, or an empty domain.
        NurbsNotClamped = raw::MC_NACK_NURBS_NOT_CLAMPED,
        /// A weight is not finite and positive.
        NurbsWeight = raw::MC_NACK_NURBS_WEIGHT,
        /// A control point is not finite.
        NurbsPoint = raw::MC_NACK_NURBS_POINT,
        /// The curve does not start where the group's path is.
        NurbsStart = raw::MC_NACK_NURBS_START,
        /// The curve has zero length.
        NurbsZeroLength = raw::MC_NACK_NURBS_ZERO_LENGTH,
        /// A knot is not finite (NaN or infinite).
        NurbsKnot = raw::MC_NACK_NURBS_KNOT,
        /// The host watchdog fault is latched: reset it first.
        WatchdogTripped = raw::MC_NACK_WATCHDOG_TRIPPED,
        /// An e-stop is latched: reset it first.
        EStopActive = raw::MC_NACK_ESTOP_ACTIVE,
        /// The move goes further into an active limit switch.
        HardLimit = raw::MC_NACK_HARD_LIMIT,
        /// The move goes further beyond a soft limit.
        SoftLimit = raw::MC_NACK_SOFT_LIMIT,
        /// A reset was refused: its cause is still present.
        CauseActive = raw::MC_NACK_CAUSE_ACTIVE,
        /// A watchdog timeout of 0 or under 1.5 × the host's declared period.
        WatchdogTimeout = raw::MC_NACK_WATCHDOG_TIMEOUT,
        /// A stop category other than 0, 1 or 2.
        BadCategory = raw::MC_NACK_BAD_CATEGORY,
        /// A kinematic limit outside its range ([`limit_range`]).
        LimitRange = raw::MC_NACK_LIMIT_RANGE,
        /// The planned profile failed the card's own check: refused, not run.
        PlanCheck = raw::MC_NACK_PLAN_CHECK,
        /// Served after its deadline: not executed.
        Expired = raw::MC_NACK_EXPIRED,
        /// An override factor outside 0 to [`OVERRIDE_MAX`](crate::OVERRIDE_MAX).
        OverrideRange = raw::MC_NACK_OVERRIDE_RANGE,
        /// A stop ramp longer than the maximum stop time, or a maximum stop time out of range.
        StopTooLong = raw::MC_NACK_STOP_TOO_LONG,
        /// A detach by a host whose session is not the attached one.
        Session = raw::MC_NACK_SESSION,
        /// A command the session gate refuses: no host session is attached with its watchdog
        /// armed, and the command could start motion, give power, or change an output, a
        /// configuration or a latch.
        NoSession = raw::MC_NACK_NO_SESSION,
        /// A homing method the axis cannot do: an unknown number, or an index method on an
        /// encoder without an index channel.
        HomingMethod = raw::MC_NACK_HOMING_METHOD,
        /// A move, jog or MC_Home on an axis that is homing.
        AxisHoming = raw::MC_NACK_AXIS_HOMING,
        /// A path buffer mode or transition mode the card does not know.
        PathMode = raw::MC_NACK_PATH_MODE,
        /// A path line of length zero.
        PathZeroLength = raw::MC_NACK_PATH_ZERO_LENGTH,
        /// A bad output number or value, or too many output actions pending.
        PathOutput = raw::MC_NACK_PATH_OUTPUT,
        /// A path segment while group moves run, a group move while the path runs, or the
        /// path configuration applied while it runs.
        PathBusy = raw::MC_NACK_PATH_BUSY,
        /// A segment id that is not an integer in 0..2³²−1.
        PathId = raw::MC_NACK_PATH_ID,
        /// A NURBS path segment with a point of zero tangent, or needing more pieces than the
        /// path buffer holds.
        PathCurve = raw::MC_NACK_PATH_CURVE,
        /// `io_config`: a mask bit beyond the inputs, or a debounce too long.
        IoConfig = raw::MC_NACK_IO_CONFIG,
        /// A compare or probe channel that does not exist.
        IoChannel = raw::MC_NACK_IO_CHANNEL,
        /// A compare mode, direction, output, pulse width, low-water mark, pitch or count out
        /// of its range.
        CompareMode = raw::MC_NACK_COMPARE_MODE,
        /// The compare table has no room for the positions.
        CompareFull = raw::MC_NACK_COMPARE_FULL,
        /// Compare table positions not strictly monotonic in the direction.
        CompareOrder = raw::MC_NACK_COMPARE_ORDER,
        /// The compare channel (or its output) is in use.
        CompareBusy = raw::MC_NACK_COMPARE_BUSY,
        /// A probe input, edge or window the card cannot take.
        ProbeInput = raw::MC_NACK_PROBE_INPUT,
        /// Layout 1.7 (sync): a gear ratio that is not integer, a zero numerator, a
        /// denominator ≤ 0, or a magnitude above `MC_GEAR_RATIO_MAX`.
        GearRatio = raw::MC_NACK_GEAR_RATIO,
        /// A master source the card does not know, a master it does not have, the slave
        /// itself, or a master axis disabled or in ErrorStop.
        SyncMaster = raw::MC_NACK_SYNC_MASTER,
        /// A PT/PVT point not at least one servo period after the one before, or a segment
        /// longer than the longest move.
        PvtTime = raw::MC_NACK_PVT_TIME,
        /// A PT/PVT point whose segment breaks the stream's velocity or acceleration limit.
        PvtLimit = raw::MC_NACK_PVT_LIMIT,
        /// PT/PVT commands out of sequence.
        PvtSequence = raw::MC_NACK_PVT_SEQUENCE,
        /// A cam table number, point count or flags out of range, points not strictly
        /// increasing in the master or not finite, a table not loaded, or one in use.
        CamTable = raw::MC_NACK_CAM_TABLE,
        /// Cam data without an open table or out of order.
        CamSequence = raw::MC_NACK_CAM_SEQUENCE,
        /// Layout 1.8: a scope signal the card does not know, or an axis or group it has not.
        ScopeSignal = raw::MC_NACK_SCOPE_SIGNAL,
        /// Scope channels 0 or more than `MC_SCOPE_CHANNELS`.
        ScopeChannels = raw::MC_NACK_SCOPE_CHANNELS,
        /// A scope divider 0 or above `MC_SCOPE_DIVIDER_MAX`.
        ScopeDivider = raw::MC_NACK_SCOPE_DIVIDER,
        /// An unknown scope mode, trigger or edge, a trigger channel or input out of range, a
        /// level not finite, or a one-shot capture of no samples.
        ScopeTrigger = raw::MC_NACK_SCOPE_TRIGGER,
        /// More pre-trigger samples than the card keeps (`MC_SCOPE_PRETRIGGER_MAX`).
        ScopePretrigger = raw::MC_NACK_SCOPE_PRETRIGGER,
        /// A scope command its state does not allow (configure or arm while armed, trigger
        /// while not waiting, stop while idle, arm before a configure).
        ScopeState = raw::MC_NACK_SCOPE_STATE,
        /// Layout 1.8: a configuration read-back of a block kind the card does not know.
        ConfigKind = raw::MC_NACK_CONFIG_KIND,
    }
}

code_enum! {
    /// Layout 1.8: the configuration blocks `MC_OP_READ_CONFIG` reads back (`MC_CONFIG_*`).
    ConfigKind: u32 {
        /// `card_config` (index 0).
        Card = raw::MC_CONFIG_CARD,
        /// `axis_config[i]` (with the scale) and `axis_pdplus[i]`.
        Axis = raw::MC_CONFIG_AXIS,
        /// `axis_filter[i]`.
        AxisFilter = raw::MC_CONFIG_AXIS_FILTER,
        /// `group_config[i]` (`naxes` 0: not configured).
        Group = raw::MC_CONFIG_GROUP,
        /// `safety` (index 0).
        Safety = raw::MC_CONFIG_SAFETY,
        /// `axis_safety[i]`.
        AxisSafety = raw::MC_CONFIG_AXIS_SAFETY,
        /// `axis_homing[i]`.
        AxisHoming = raw::MC_CONFIG_AXIS_HOMING,
        /// `group_path[i]`.
        GroupPath = raw::MC_CONFIG_GROUP_PATH,
        /// `io_config` (index 0).
        Io = raw::MC_CONFIG_IO,
    }
}

impl ConfigKind {
    /// Is the index an axis (else a group, or 0 for a card-wide block)?
    pub fn per_axis(self) -> bool {
        matches!(
            self,
            Self::Axis | Self::AxisFilter | Self::AxisSafety | Self::AxisHoming
        )
    }

    /// Is the index a group?
    pub fn per_group(self) -> bool {
        matches!(self, Self::Group | Self::GroupPath)
    }
}

/// A group's status, published under a seqlock like the axes': the header's
/// `mc_group_status_payload` (its fields are listed there).
pub type GroupStatus = raw::mc_group_status_payload;

impl raw::mc_group_status_payload {
    /// Encode as words, with the checksum in the last word.
    #[inline]
    pub fn to_words(&self) -> [u64; STATUS_WORDS] {
        let mut w = crate::block::to_words(self);
        w[STATUS_WORDS - 1] = status_checksum(&w);
        w
    }

    /// Decode; `None` when the checksum does not match. The checksum field of the result is
    /// 0: it has been checked.
    pub fn from_words(w: &[u64; STATUS_WORDS]) -> Option<Self> {
        if status_checksum(w) != w[STATUS_WORDS - 1] {
            return None;
        }
        let mut s: Self = crate::block::from_words(w);
        s.checksum = 0;
        Some(s)
    }

    /// The state, if known.
    pub fn state(&self) -> Option<GroupState> {
        GroupState::from_raw(self.state)
    }
}

/// Flags of the group move commands: the shifts of the multi-bit fields, and the single-bit
/// flags of [`MoveFlags`] as plain words for code that tests a raw [`Command::flags`].
pub mod move_flags {
    use super::MoveFlags;
    use crate::raw;
    /// Targets are relative to the start of the move.
    pub const RELATIVE: u32 = MoveFlags::RELATIVE.bits();
    /// Queue behind the moves already queued.
    pub const BUFFERED: u32 = MoveFlags::BUFFERED.bits();
    /// Shift of the 2-bit circle mode (`MC_CIRC_BY_*`).
    pub const CIRC_MODE_SHIFT: u32 = raw::MC_CIRC_MODE_SHIFT;
    /// Counter-clockwise (else clockwise).
    pub const CIRC_CCW: u32 = MoveFlags::CIRC_CCW.bits();
    /// Shift of the 2-bit plane (`MC_PLANE_*`).
    pub const PLANE_SHIFT: u32 = raw::MC_CIRC_PLANE_SHIFT;
    /// Helical targets are distances even in an absolute move.
    pub const CIRC_HELIX_RELATIVE: u32 = MoveFlags::CIRC_HELIX_RELATIVE.bits();
    /// Saturation-aware feed for a NURBS move (Yeh §3.4).
    pub const NURBS_SATURATION: u32 = MoveFlags::NURBS_SATURATION.bits();
    /// Shift of the 2-bit feed type (`MC_FEED_*`).
    pub const FEED_TYPE_SHIFT: u32 = raw::MC_FEED_TYPE_SHIFT;
    /// Point-to-point: every axis also within the limits staged for it.
    pub const PTP_AXIS_LIMITS: u32 = MoveFlags::PTP_AXIS_LIMITS.bits();
}

/// The flags of the path opcodes (`MC_OP_PATH_LINE`, `_ARC`, `_DWELL`, `_OUTPUT`). Lines and arcs
/// also take [`move_flags::RELATIVE`] and the circle bits of [`move_flags`].
pub mod path_flags {
    use crate::raw;
    /// Shift of the 3-bit PLCopen buffer mode (`MC_PATH_ABORTING` … `MC_PATH_BLEND_HIGH`).
    pub const BUFFER_SHIFT: u32 = raw::MC_PATH_BUFFER_SHIFT;
    /// Shift of the 2-bit transition mode (`MC_TM_*`).
    pub const TRANSITION_SHIFT: u32 = raw::MC_PATH_TRANSITION_SHIFT;
    /// The last segment of a program: its stop is the end, not starvation.
    pub const LAST: u32 = raw::MC_PATH_LAST;
    /// The buffer mode of a segment's flags.
    pub fn buffer(flags: u32) -> u32 {
        (flags >> BUFFER_SHIFT) & 7
    }
    /// The transition mode of a segment's flags.
    pub fn transition(flags: u32) -> u32 {
        (flags >> TRANSITION_SHIFT) & 3
    }
}

code_enum! {
    /// Why homing failed (the `code` of [`EventKind::HomingFailed`]).
    HomingError: i32 {
        /// A limit switch the method did not reverse at: its switch is missing.
        LimitReached = raw::MC_HOMING_ERR_LIMIT,
        /// The axis went the maximum distance from the start without the switch or hard stop.
        DistanceExceeded = raw::MC_HOMING_ERR_DISTANCE,
        /// Not homed within the timeout.
        Timeout = raw::MC_HOMING_ERR_TIMEOUT,
        /// No index pulse within the index distance.
        NoIndex = raw::MC_HOMING_ERR_NO_INDEX,
        /// A motion of the method could not be planned.
        Plan = raw::MC_HOMING_ERR_PLAN,
    }
}

/// `MC_SET_POSITION_RELATIVE`: MC_SetPosition moves the position by its argument (else the
/// position becomes it).
pub const SET_POSITION_RELATIVE: u32 = raw::MC_SET_POSITION_RELATIVE;

bitflags::bitflags! {
    /// `mc_axis_homing.flags` (`MC_HOMING_*`).
    #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
    pub struct HomingFlags: u32 {
        /// The encoder has an index channel (the index methods need it).
        const INDEX = raw::MC_HOMING_INDEX;
        /// End at the home point (else where the axis came to rest after finding it).
        const MOVE_TO_HOME = raw::MC_HOMING_MOVE_TO_HOME;
    }
}

impl StopReason {
    /// A stop made by the safety layer (not by a command or the end of a move).
    pub fn is_safety(self) -> bool {
        self as u32 >= raw::MC_STOP_WATCHDOG
    }
}

/// A command entry.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Command {
    /// Sequence number, echoed by the ack or nack.
    pub seq: u32,
    /// Raw opcode ([`Opcode`] when known).
    pub opcode: u16,
    /// Axis number.
    pub axis: u16,
    /// Flags (per opcode).
    pub flags: u32,
    /// The host time (`host.host_time_ms`) after which the card refuses the command with
    /// [`NackCode::Expired`]; 0: no deadline.
    pub deadline_ms: u32,
    /// Arguments.
    pub args: [f64; CMD_ARGS],
}

impl Command {
    /// A command with all arguments zero.
    pub fn new(opcode: Opcode, axis: u16) -> Self {
        Self {
            seq: 0,
            opcode: opcode as u16,
            axis,
            flags: 0,
            deadline_ms: 0,
            args: [0.0; CMD_ARGS],
        }
    }

    /// With the first arguments set.
    pub fn with_args(mut self, args: &[f64]) -> Self {
        for (dst, src) in self.args.iter_mut().zip(args) {
            *dst = *src;
        }
        self
    }

    /// Encode as words.
    pub fn to_words(&self) -> [u64; CMD_WORDS] {
        let mut w = [0u64; CMD_WORDS];
        w[0] = self.seq as u64 | (self.opcode as u64) << 32 | (self.axis as u64) << 48;
        w[1] = self.flags as u64 | (self.deadline_ms as u64) << 32;
        for (dst, a) in w[2..].iter_mut().zip(self.args.iter()) {
            *dst = a.to_bits();
        }
        w
    }

    /// Decode from words (any bit pattern decodes).
    pub fn from_words(w: &[u64; CMD_WORDS]) -> Self {
        let mut args = [0.0; CMD_ARGS];
        for (dst, src) in args.iter_mut().zip(w[2..].iter()) {
            *dst = f64::from_bits(*src);
        }
        Self {
            seq: w[0] as u32,
            opcode: (w[0] >> 32) as u16,
            axis: (w[0] >> 48) as u16,
            flags: w[1] as u32,
            deadline_ms: (w[1] >> 32) as u32,
            args,
        }
    }
}

/// An event entry.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Event {
    /// The command's seq for ack and nack, else 0.
    pub seq: u32,
    /// Raw kind ([`EventKind`] when known).
    pub kind: u16,
    /// Axis number (or 0xFFFF for card-wide events).
    pub axis: u16,
    /// Kind-specific code.
    pub code: i32,
    /// Servo tick at which it was raised.
    pub tick: u64,
    /// Kind-specific value.
    pub value: f64,
}

impl Event {
    /// Encode as words.
    pub fn to_words(&self) -> [u64; EVT_WORDS] {
        [
            self.seq as u64 | (self.kind as u64) << 32 | (self.axis as u64) << 48,
            self.code as u32 as u64,
            self.tick,
            self.value.to_bits(),
        ]
    }

    /// Decode from words (any bit pattern decodes).
    pub fn from_words(w: &[u64; EVT_WORDS]) -> Self {
        Self {
            seq: w[0] as u32,
            kind: (w[0] >> 32) as u16,
            axis: (w[0] >> 48) as u16,
            code: w[1] as u32 as i32,
            tick: w[2],
            value: f64::from_bits(w[3]),
        }
    }

    /// The kind, if known.
    pub fn kind(&self) -> Option<EventKind> {
        EventKind::from_raw(self.kind)
    }
}

bitflags::bitflags! {
    /// Fault bits of [`AxisStatus::faults`] (`MC_FAULT_*`). Decoded with
    /// `from_bits_retain`: a bit this layout does not name is kept, not dropped.
    #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
    pub struct Faults: u32 {
        /// The servo output hit the DAC limit this tick.
        const DAC_SATURATED = raw::MC_FAULT_DAC_SATURATED;
        /// The host watchdog tripped.
        const WATCHDOG = raw::MC_FAULT_WATCHDOG;
        /// An e-stop (command or input) stopped the axis.
        const ESTOP = raw::MC_FAULT_ESTOP;
        /// At or beyond the positive limit switch.
        const HARD_LIMIT_POS = raw::MC_FAULT_HARD_LIMIT_POS;
        /// At or beyond the negative limit switch.
        const HARD_LIMIT_NEG = raw::MC_FAULT_HARD_LIMIT_NEG;
        /// Beyond the positive soft limit.
        const SOFT_LIMIT_POS = raw::MC_FAULT_SOFT_LIMIT_POS;
        /// Beyond the negative soft limit.
        const SOFT_LIMIT_NEG = raw::MC_FAULT_SOFT_LIMIT_NEG;
        /// Following error beyond its limit.
        const FOLLOWING_ERROR = raw::MC_FAULT_FOLLOWING_ERROR;
        /// The amplifier's alarm input.
        const AMP_ALARM = raw::MC_FAULT_AMP_ALARM;
        /// Encoder loss or jump.
        const ENCODER = raw::MC_FAULT_ENCODER;
        /// The host broke the protocol (corrupt ring indices).
        const PROTOCOL = raw::MC_FAULT_PROTOCOL;
        /// A stop ran past the card's maximum stop time: its power was removed.
        const STOP_TIMEOUT = raw::MC_FAULT_STOP_TIMEOUT;
    }

    /// Bits of [`AxisStatus::io`] (`MC_IO_*`): the card's inputs for the axis and its
    /// drive-enable output.
    #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
    pub struct Io: u32 {
        /// Positive limit switch.
        const LIMIT_POS = raw::MC_IO_LIMIT_POS;
        /// Negative limit switch.
        const LIMIT_NEG = raw::MC_IO_LIMIT_NEG;
        /// Home switch.
        const HOME = raw::MC_IO_HOME;
        /// Amplifier alarm.
        const AMP_ALARM = raw::MC_IO_AMP_ALARM;
        /// Encoder line-break detector.
        const ENCODER_FAULT = raw::MC_IO_ENCODER_FAULT;
        /// The card's e-stop input (the same on every axis).
        const ESTOP = raw::MC_IO_ESTOP;
        /// Output: the amplifier is enabled.
        const DRIVE_ENABLE = raw::MC_IO_DRIVE_ENABLE;
    }

    /// Bits of [`AxisStatus::motion_flags`] (`MC_MOTION_*`, layout 1.5).
    #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
    pub struct MotionFlags: u32 {
        /// Velocity mode at its (overridden) velocity.
        const IN_VELOCITY = raw::MC_MOTION_IN_VELOCITY;
        /// Held still by a 0 % override, in its motion state.
        const PAUSED = raw::MC_MOTION_PAUSED;
        /// The position was set by homing or MC_SetPosition.
        const HOMED = raw::MC_MOTION_HOMED;
        /// The motion running is one that was buffered.
        const BUFFERED_ACTIVE = raw::MC_MOTION_BUFFERED_ACTIVE;
        /// Layout 1.7 (sync): the slave follows its master (InGear, InSync).
        const IN_SYNC = raw::MC_MOTION_IN_SYNC;
    }

    /// The single-bit flags of the group move commands (`MC_MOVE_*`, `MC_CIRC_CCW`, ...) in
    /// [`Command::flags`]; the multi-bit fields (circle mode, plane, feed type) are shifted in
    /// with the shifts of [`move_flags`].
    #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
    pub struct MoveFlags: u32 {
        /// Targets are relative to the start of the move.
        const RELATIVE = raw::MC_MOVE_RELATIVE;
        /// Queue behind the moves already queued.
        const BUFFERED = raw::MC_MOVE_BUFFERED;
        /// Counter-clockwise (else clockwise).
        const CIRC_CCW = raw::MC_CIRC_CCW;
        /// Helical targets are distances even in an absolute move.
        const CIRC_HELIX_RELATIVE = raw::MC_CIRC_HELIX_RELATIVE;
        /// Saturation-aware feed for a NURBS move (Yeh §3.4); `MC_OP_NURBS_BEGIN` only (the bit
        /// is the circle mode's in an arc).
        const NURBS_SATURATION = raw::MC_NURBS_SATURATION;
        /// Point-to-point: every axis also within the limits staged for it.
        const PTP_AXIS_LIMITS = raw::MC_PTP_AXIS_LIMITS;
    }

    /// `mc_axis_safety.flags` (`MC_AXSAFE_*`): the checks an axis makes.
    #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
    pub struct AxisSafetyFlags: u32 {
        /// Enforce the soft limits.
        const SOFT_LIMITS = raw::MC_AXSAFE_SOFT_LIMITS;
        /// Honour the limit switch inputs.
        const HARD_LIMITS = raw::MC_AXSAFE_HARD_LIMITS;
        /// Honour the amplifier alarm input.
        const AMP_ALARM = raw::MC_AXSAFE_AMP_ALARM;
        /// Honour encoder loss and jumps.
        const ENCODER = raw::MC_AXSAFE_ENCODER;
    }

    /// Card-wide safety latches, `mc_safety_status.faults` (`MC_CARD_FAULT_*`).
    #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
    pub struct CardFaults: u32 {
        /// The host watchdog tripped.
        const WATCHDOG = raw::MC_CARD_FAULT_WATCHDOG;
        /// The host's e-stop command.
        const ESTOP_COMMAND = raw::MC_CARD_FAULT_ESTOP_COMMAND;
        /// The card's e-stop input.
        const ESTOP_INPUT = raw::MC_CARD_FAULT_ESTOP_INPUT;
    }
}

// The header's catch-all agrees with the named flags, and the single-bit move flags stay clear
// of the multi-bit fields (but the NURBS flag, whose opcode has no circle mode).
const _: () = {
    assert!(AxisSafetyFlags::all().bits() == raw::MC_AXSAFE_ALL);
    let fields =
        3 << raw::MC_CIRC_MODE_SHIFT | 3 << raw::MC_CIRC_PLANE_SHIFT | 3 << raw::MC_FEED_TYPE_SHIFT;
    assert!(
        MoveFlags::all()
            .difference(MoveFlags::NURBS_SATURATION)
            .bits()
            & fields
            == 0
    );
};

/// What the card publishes about an axis each tick: the header's `mc_axis_status_payload`
/// (its fields are listed there), moved under the axis's seqlock as [`STATUS_WORDS`] words.
pub type AxisStatus = raw::mc_axis_status_payload;

impl raw::mc_axis_status_payload {
    /// Encode as words, with the checksum in the last word.
    #[inline]
    pub fn to_words(&self) -> [u64; STATUS_WORDS] {
        let mut w = crate::block::to_words(self);
        w[STATUS_WORDS - 1] = status_checksum(&w);
        w
    }

    /// Decode from words; `None` when the checksum does not match (a torn or corrupted copy).
    /// The checksum field of the result is 0: it has been checked.
    pub fn from_words(w: &[u64; STATUS_WORDS]) -> Option<Self> {
        if status_checksum(w) != w[STATUS_WORDS - 1] {
            return None;
        }
        let mut s: Self = crate::block::from_words(w);
        s.checksum = 0;
        Some(s)
    }

    /// The state, if known.
    pub fn state(&self) -> Option<AxisState> {
        AxisState::from_raw(self.state)
    }

    /// The fault bits as a set (bits this layout does not name are kept).
    pub fn faults(&self) -> Faults {
        Faults::from_bits_retain(self.faults)
    }

    /// The input and drive-enable bits as a set (bits this layout does not name are kept).
    pub fn io(&self) -> Io {
        Io::from_bits_retain(self.io)
    }

    /// The motion bits as a set (bits this layout does not name are kept).
    pub fn motion(&self) -> MotionFlags {
        MotionFlags::from_bits_retain(self.motion_flags)
    }

    /// The stop reason, if known.
    pub fn stop_reason(&self) -> Option<StopReason> {
        StopReason::from_raw(self.stop_reason)
    }
}

/// The checksum of a status payload: a position-dependent mix of the first 15 words.
#[inline]
pub fn status_checksum(w: &[u64; STATUS_WORDS]) -> u64 {
    w[..STATUS_WORDS - 1]
        .iter()
        .enumerate()
        .fold(raw::MC_STATUS_CHECK as u64, |acc, (i, x)| {
            acc.rotate_left(7) ^ x.wrapping_mul(0x9E37_79B9_7F4A_7C15 ^ i as u64)
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn command_round_trip() {
        let mut c = Command::new(Opcode::MoveAbsolute, 7).with_args(&[1.5, -2.0, f64::NAN]);
        c.seq = 0xDEAD_BEEF;
        c.flags = 3;
        c.deadline_ms = 0xFFFF_FFFE;
        let d = Command::from_words(&c.to_words());
        assert_eq!(d.deadline_ms, 0xFFFF_FFFE);
        assert_eq!(d.seq, c.seq);
        assert_eq!(d.opcode, Opcode::MoveAbsolute as u16);
        assert_eq!(d.axis, 7);
        assert_eq!(d.flags, 3);
        assert_eq!(d.args[0], 1.5);
        assert!(d.args[2].is_nan());
    }

    #[test]
    fn event_round_trip_keeps_negative_codes() {
        let e = Event {
            seq: 9,
            kind: EventKind::Nack as u16,
            axis: 0xFFFF,
            code: -5,
            tick: u64::MAX,
            value: -0.25,
        };
        assert_eq!(Event::from_words(&e.to_words()), e);
    }

    #[test]
    fn status_checksum_detects_any_single_word_change() {
        let s = AxisStatus {
            cmd_pos: 1.0,
            act_pos: 2.0,
            state: 3,
            tick: 99,
            encoder: -4,
            stop_reason: 23,
            io: 0x101,
            faults: (Faults::WATCHDOG | Faults::from_bits_retain(1 << 31)).bits(),
            ..Default::default()
        };
        let w = s.to_words();
        assert_eq!(AxisStatus::from_words(&w), Some(s));
        assert_eq!(s.io(), Io::from_bits_retain(0x101));
        assert!(s.faults().contains(Faults::WATCHDOG));
        for i in 0..STATUS_WORDS {
            let mut bad = w;
            bad[i] ^= 1 << (i % 64);
            assert_eq!(AxisStatus::from_words(&bad), None, "word {i}");
        }
    }

    #[test]
    fn every_named_flag_is_its_own_single_bit() {
        fn check<F: bitflags::Flags<Bits = u32>>(what: &str) {
            let mut seen = 0u32;
            for (name, f) in F::all().iter_names() {
                let b = f.bits();
                assert_eq!(b.count_ones(), 1, "{what}::{name} = {b:#x}");
                assert_eq!(seen & b, 0, "{what}::{name} overlaps another flag");
                seen |= b;
            }
            assert_eq!(seen, F::all().bits(), "{what}");
        }
        check::<Faults>("Faults");
        check::<Io>("Io");
        check::<MoveFlags>("MoveFlags");
        check::<AxisSafetyFlags>("AxisSafetyFlags");
        check::<CardFaults>("CardFaults");
        check::<MotionFlags>("MotionFlags");
        check::<HomingFlags>("HomingFlags");
        assert_eq!(Faults::all().iter().count(), 12);
        assert_eq!(Io::all().iter().count(), 7);
    }

    #[test]
    fn codes_match_the_header() {
        assert_eq!(Opcode::from_raw(raw::MC_OP_HALT as u16), Some(Opcode::Halt));
        assert_eq!(Opcode::from_raw(0), None);
        assert_eq!(NackCode::ALL.len(), 79);
        assert_eq!(ConfigKind::ALL.len(), 9);
        assert_eq!(Opcode::from_raw(49), Some(Opcode::Home));
        assert_eq!(HomingError::from_raw(4), Some(HomingError::NoIndex));
        assert!(!StopReason::HomingFailed.is_safety());
        assert_eq!(Opcode::from_raw(34), Some(Opcode::EStop));
        assert_eq!(StopReason::from_raw(23), Some(StopReason::FollowingError));
        assert!(StopReason::Watchdog.is_safety() && !StopReason::Halt.is_safety());
        assert!(StopReason::HostChanged.is_safety() && StopReason::StopTimeout.is_safety());
        assert!(!StopReason::HostDetach.is_safety());
        let mut codes: Vec<i32> = NackCode::ALL.iter().map(|c| *c as i32).collect();
        codes.dedup();
        assert_eq!(codes.len(), NackCode::ALL.len());
        assert_eq!(AxisState::from_raw(7), Some(AxisState::ErrorStop));
    }
}
