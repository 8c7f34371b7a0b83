//! The SDK's one error type.

use card_firmware::host::NurbsError;
use firmware_proto::NackCode;
use std::time::Duration;

/// Declares [`ErrorKind`] from one table: for each kind its C result code (stable: a code keeps
/// its number in every later version), the name of that code in the C header, the card's nack
/// it stands for (if it is one), and its description (`mc_result_str`, and the reason in the
/// SDK's messages). The C ABI and its header take the codes from here.
macro_rules! error_kinds {
    ($($(#[doc = $doc:literal])* $kind:ident = $code:literal, $cname:ident,
        $(nack $nack:ident,)? $desc:literal;)+) => {
        /// What went wrong, as a flat code: one-to-one with the C ABI's result codes.
        ///
        /// Deliberately not `#[non_exhaustive]`: a new kind gets its C code in the same table
        /// row, and a nack code that no kind stands for does not compile.
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
        pub enum ErrorKind { $($(#[doc = $doc])* $kind,)+ }

        impl ErrorKind {
            /// Every kind, in the table's order.
            pub const ALL: &'static [ErrorKind] = &[$(ErrorKind::$kind),+];

            /// The C ABI's result code (negative).
            pub const fn code(self) -> i32 {
                match self { $(ErrorKind::$kind => $code,)+ }
            }

            /// The kind of a C result code, if it is one.
            pub fn from_code(code: i32) -> Option<Self> {
                match code { $($code => Some(ErrorKind::$kind),)+ _ => None }
            }

            /// The name of the code in the C header (`MC_ERR_…`).
            pub const fn c_name(self) -> &'static str {
                match self { $(ErrorKind::$kind => stringify!($cname),)+ }
            }

            /// A short description (what `mc_result_str` returns).
            pub const fn description(self) -> &'static str {
                match self { $(ErrorKind::$kind => $desc,)+ }
            }

            /// The description as a C string.
            pub const fn c_description(self) -> &'static core::ffi::CStr {
                match self {
                    $(ErrorKind::$kind => match core::ffi::CStr::from_bytes_with_nul(
                        concat!($desc, "\0").as_bytes(),
                    ) {
                        Ok(s) => s,
                        Err(_) => panic!("a description holds a NUL"),
                    },)+
                }
            }

            /// The kind's documentation (for the C header).
            pub const fn doc(self) -> &'static str {
                match self { $(ErrorKind::$kind => concat!($($doc, "\n"),*),)+ }
            }
        }

        impl From<NackCode> for ErrorKind {
            fn from(c: NackCode) -> Self {
                match c { $($(NackCode::$nack => ErrorKind::$kind,)?)+ }
            }
        }
    };
}

error_kinds! {
    /// The URI is not one of `sim`, `emu:NAME`, `uio:/dev/uioN`, `pci:DDDD:BB:DD.F`,
    /// `name:NAME`, `serial:N`.
    BadUri = -1, MC_ERR_BAD_URI, "bad card URI";
    /// No card at that URI.
    NotFound = -2, MC_ERR_NOT_FOUND, "no card at that URI";
    /// The card is open already: in another process, or in this one (a card is opened once
    /// per process; the message says which).
    Busy = -3, MC_ERR_BUSY, "the card is already open (by another process, or by this one)";
    /// The card's DPRAM layout major version differs from this library's.
    VersionMismatch = -4, MC_ERR_VERSION_MISMATCH, "the card's DPRAM layout version differs from the library's";
    /// The card does not answer (its tick counter stopped, or it was removed).
    NotResponding = -5, MC_ERR_NOT_RESPONDING, "the card does not respond";
    /// The card broke the protocol (corrupt ring indices, bad signature, torn status).
    Protocol = -6, MC_ERR_PROTOCOL, "the card broke the protocol";
    /// The command ring is full: nothing was queued.
    RingFull = -7, MC_ERR_RING_FULL, "the command ring is full";
    /// A wait ran out of time.
    Timeout = -8, MC_ERR_TIMEOUT, "timed out";
    /// The motion waited for was aborted by another command or a fault.
    Aborted = -9, MC_ERR_ABORTED, "the motion was aborted";
    /// The card has no such axis.
    BadAxis = -10, MC_ERR_BAD_AXIS, nack BadAxis, "no such axis";
    /// An argument is NaN or infinite.
    NotFinite = -11, MC_ERR_NOT_FINITE, nack NotFinite, "an argument is NaN or infinite";
    /// A limit is zero or negative.
    NonPositiveLimit = -12, MC_ERR_NON_POSITIVE_LIMIT, nack NonPositiveLimit, "a limit is zero or negative";
    /// The axis is disabled.
    AxisDisabled = -13, MC_ERR_AXIS_DISABLED, nack AxisDisabled, "the axis is disabled";
    /// The command is not allowed in the axis's current state.
    InvalidState = -14, MC_ERR_INVALID_STATE, nack InvalidState, "not allowed in the axis's current state";
    /// A configuration value is out of range.
    BadConfig = -15, MC_ERR_BAD_CONFIG, nack BadConfig, "a configuration value is out of range";
    /// No motion profile satisfies the request.
    Infeasible = -16, MC_ERR_INFEASIBLE, nack Infeasible, "no profile satisfies the request";
    /// A position beyond the card's range, or a velocity beyond its own (a jog above `jog_max_vel`).
    OutOfRange = -17, MC_ERR_OUT_OF_RANGE, nack OutOfRange, "a position or velocity out of range";
    /// The card configuration can only change while all axes are disabled.
    AxesEnabled = -18, MC_ERR_AXES_ENABLED, nack AxesEnabled, "all axes must be disabled first";
    /// The firmware does not know the command.
    UnknownCommand = -19, MC_ERR_UNKNOWN_COMMAND, nack UnknownOpcode, "unknown command";
    /// No such axes group.
    BadGroup = -22, MC_ERR_BAD_GROUP, nack BadGroup, "no such group";
    /// An axis already belongs to another group.
    AxisInOtherGroup = -23, MC_ERR_AXIS_IN_OTHER_GROUP, nack AxisInOtherGroup, "an axis already belongs to another group";
    /// The move needs an axis the group does not have.
    AxisNotInGroup = -24, MC_ERR_AXIS_NOT_IN_GROUP, nack AxisNotInGroup, "the move needs an axis the group does not have";
    /// An axis of the group is moving on its own.
    AxisBusy = -25, MC_ERR_AXIS_BUSY, nack AxisBusy, "an axis of the group is moving on its own";
    /// Single-axis motion on an axis of an enabled group.
    AxisGrouped = -26, MC_ERR_AXIS_GROUPED, nack AxisGrouped, "the axis belongs to an enabled group";
    /// The arc has zero length or zero radius.
    ZeroLengthArc = -27, MC_ERR_ZERO_LENGTH_ARC, nack ZeroLengthArc, "the arc has zero length or zero radius";
    /// The centre is not equidistant from start and end within the tolerance.
    CentreNotEquidistant = -28, MC_ERR_CENTRE_NOT_EQUIDISTANT, nack CentreNotEquidistant, "the centre is not equidistant from start and end";
    /// The radius is shorter than half the chord.
    RadiusTooSmall = -29, MC_ERR_RADIUS_TOO_SMALL, nack RadiusTooSmall, "the radius is shorter than half the chord";
    /// The three points of a border-point arc are on one line.
    CollinearPoints = -30, MC_ERR_COLLINEAR_POINTS, nack CollinearPoints, "the three points are on one line";
    /// The group's move queue is full: nothing was queued.
    QueueFull = -31, MC_ERR_QUEUE_FULL, nack QueueFull, "the move queue (the group's or the axis's) is full";
    /// The interpolator cannot run with the group's acc/dec mode.
    IncompatibleMode = -32, MC_ERR_INCOMPATIBLE_MODE, nack IncompatibleMode, "the interpolator cannot run with this acc/dec mode";
    /// The group is disabled (or not configured).
    GroupDisabled = -33, MC_ERR_GROUP_DISABLED, nack GroupDisabled, "the group is disabled";
    /// Filters can change only while they hold no distance.
    FilterBusy = -34, MC_ERR_FILTER_BUSY, nack FilterBusy, "the filter still holds distance";
    /// NURBS data or end without a begin, out of order, or missing.
    NurbsSequence = -35, MC_ERR_NURBS_SEQUENCE, nack NurbsSequence, "NURBS data out of sequence (no begin, a gap, or missing data)";
    /// NURBS degree outside 1..5.
    NurbsDegree = -36, MC_ERR_NURBS_DEGREE, nack NurbsDegree, "NURBS degree outside 1..5";
    /// NURBS on a group of fewer than 2 axes.
    NurbsDimension = -37, MC_ERR_NURBS_DIMENSION, nack NurbsDimension, "NURBS curves need a group of at least 2 axes";
    /// Too few or too many control points.
    NurbsCtrlCount = -38, MC_ERR_NURBS_CTRL_COUNT, nack NurbsCtrlCount, "too few or too many NURBS control points";
    /// The knot count is not n_ctrl + degree + 1.
    NurbsKnotCount = -39, MC_ERR_NURBS_KNOT_COUNT, nack NurbsKnotCount, "the knot count must be control points + degree + 1";
    /// The knots decrease.
    NurbsKnotsDecreasing = -40, MC_ERR_NURBS_KNOTS_DECREASING, nack NurbsKnotsDecreasing, "the knots decrease";
    /// An interior knot is repeated more than degree times.
    NurbsKnotMultiplicity = -41, MC_ERR_NURBS_KNOT_MULTIPLICITY, nack NurbsKnotMultiplicity, "an interior knot is repeated more than degree times";
    /// The end knots are not repeated degree + 1 times (or the domain is empty).
    NurbsNotClamped = -42, MC_ERR_NURBS_NOT_CLAMPED, nack NurbsNotClamped, "the knot vector is not clamped";
    /// A weight is not finite and positive.
    NurbsWeight = -43, MC_ERR_NURBS_WEIGHT, nack NurbsWeight, "a weight is not finite and positive";
    /// A control point is not finite.
    NurbsPoint = -44, MC_ERR_NURBS_POINT, nack NurbsPoint, "a control point is not finite";
    /// The curve does not start where the group's path is.
    NurbsStart = -45, MC_ERR_NURBS_START, nack NurbsStart, "the curve does not start where the group is";
    /// The curve has zero length.
    NurbsZeroLength = -46, MC_ERR_NURBS_ZERO_LENGTH, nack NurbsZeroLength, "the curve has zero length";
    /// A knot is not finite.
    NurbsKnot = -54, MC_ERR_NURBS_KNOT, nack NurbsKnot, "a knot is not finite";
    /// An operating-system call failed.
    Io = -20, MC_ERR_IO, "an operating-system call failed";
    /// The backend cannot do this (for example interrupts on a `pci:` card).
    Unsupported = -21, MC_ERR_UNSUPPORTED, "not supported by this card";
    /// The host watchdog tripped and is latched: [`crate::Card::reset_faults`] first.
    WatchdogTripped = -47, MC_ERR_WATCHDOG_TRIPPED, nack WatchdogTripped, "the host watchdog tripped: reset the card's faults first";
    /// An e-stop is latched: [`crate::Card::reset_faults`] first.
    EStopActive = -48, MC_ERR_ESTOP_ACTIVE, nack EStopActive, "an e-stop is latched: reset the card's faults first";
    /// The move would go further into an active limit switch.
    HardLimit = -49, MC_ERR_HARD_LIMIT, nack HardLimit, "the move goes further into an active limit switch";
    /// The move would go further beyond a soft limit.
    SoftLimit = -50, MC_ERR_SOFT_LIMIT, nack SoftLimit, "the move goes further beyond a soft limit";
    /// A reset was refused because its cause (alarm, encoder fault, e-stop input, missing
    /// heartbeat) is still present.
    CauseActive = -51, MC_ERR_CAUSE_ACTIVE, nack CauseActive, "the cause of the fault is still present";
    /// A watchdog timeout of zero or under 1.5 × the host's heartbeat period.
    WatchdogTimeout = -52, MC_ERR_WATCHDOG_TIMEOUT, nack WatchdogTimeout, "watchdog timeout is zero or under 1.5 x the host's heartbeat period";
    /// A stop category other than 0, 1 or 2.
    BadCategory = -53, MC_ERR_BAD_CATEGORY, nack BadCategory, "stop category must be 0, 1 or 2";
    /// A kinematic limit outside the range the card accepts
    /// ([`firmware_proto::limit_range`]: denormal, absurdly small or large).
    LimitRange = -55, MC_ERR_LIMIT_RANGE, nack LimitRange, "a limit is outside the range the card accepts (one count in 1e6 s to the whole position range in one servo tick)";
    /// The card planned a profile that failed its own check (shorter than |d|/vmax, off its
    /// target or beyond a limit) and refused it: nothing moved.
    PlanCheck = -56, MC_ERR_PLAN_CHECK, nack PlanCheck, "the planned profile failed the card's check; nothing moved";
    /// The card served the command after its deadline and refused it: it was not executed.
    Expired = -57, MC_ERR_EXPIRED, nack Expired, "the card served the command after its deadline; it was not executed";
    /// A stop ramp longer than the card's maximum stop time, or a maximum stop time out of
    /// range.
    StopTooLong = -58, MC_ERR_STOP_TOO_LONG, nack StopTooLong, "the stop ramp from max velocity is longer than the card's maximum stop time";
    /// The card's session belongs to another host.
    Session = -59, MC_ERR_SESSION, nack Session, "another host's session is attached";
    /// No host session is attached to the card (it was detached, for example by a raw
    /// `MC_OP_HOST_DETACH`): the card refuses motion, power, outputs, configuration and
    /// resets until a host attaches: close the card and open it again (a tool may send a raw
    /// `MC_OP_HOST_ATTACH`). It still takes stops, reads and the scope.
    NoSession = -108, MC_ERR_NO_SESSION, nack NoSession, "no host session is attached: the card refuses motion, power, outputs and configuration until a host attaches";
    /// The card went away (its `card-emu` process exited or was killed): every call on it
    /// fails with this.
    CardGone = -60, MC_ERR_CARD_GONE, "the card went away";
    /// The card was closed ([`crate::Card::close`]) while the call waited, or before it.
    Closed = -61, MC_ERR_CLOSED, "the card was closed";
    /// The wait was cancelled from another thread ([`crate::Card::cancel_waits`]).
    Cancelled = -62, MC_ERR_CANCELLED, "the wait was cancelled";
    /// The card's server refused this user (`emu:` access control).
    PermissionDenied = -63, MC_ERR_PERMISSION_DENIED, "the card's server refused this user";
    /// An override factor outside 0 to 2 (0 % to 200 %).
    OverrideRange = -64, MC_ERR_OVERRIDE_RANGE, nack OverrideRange, "the override factor is outside 0 to 2 (0 % to 200 %)";
    /// A homing method the axis cannot do: an unknown CiA 402 number, or an index method on an
    /// encoder without an index channel ([`crate::HomingSettings`]).
    HomingMethod = -65, MC_ERR_HOMING_METHOD, nack HomingMethod, "the axis cannot do this homing method";
    /// A move, jog or homing on an axis that is homing: wait for it, or halt it first.
    AxisHoming = -66, MC_ERR_AXIS_HOMING, nack AxisHoming, "the axis is homing";
    /// Homing ended without a home point (its switch, hard stop or index was not found in
    /// time or distance): the axis is at rest and not homed.
    HomingFailed = -67, MC_ERR_HOMING_FAILED, "homing failed: the axis stopped, not homed";
    /// A path segment's buffer mode or transition mode is not one the card knows.
    PathMode = -68, MC_ERR_PATH_MODE, nack PathMode, "unknown path buffer or transition mode";
    /// A path line of length zero.
    PathZeroLength = -69, MC_ERR_PATH_ZERO_LENGTH, nack PathZeroLength, "the path line has zero length";
    /// An output number beyond the card's outputs, or too many output actions before a segment.
    PathOutput = -70, MC_ERR_PATH_OUTPUT, nack PathOutput, "bad output number, or too many output actions before a segment";
    /// A path segment while group moves run, a group move while the path runs, or the path
    /// configuration changed while it runs.
    PathBusy = -71, MC_ERR_PATH_BUSY, nack PathBusy, "the group's path and its move queue do not mix: wait for the other to finish";
    /// A segment id that is not an integer in 0..2^32-1.
    PathId = -72, MC_ERR_PATH_ID, nack PathId, "a segment id must be an integer in 0..2^32-1";
    /// A NURBS path segment with a point of zero tangent (a cusp: split the curve there), or
    /// one needing more pieces than the path buffer holds (a looser fit tolerance, or split
    /// the curve).
    PathCurve = -73, MC_ERR_PATH_CURVE, nack PathCurve, "the NURBS path segment has a cusp or needs more pieces than the path buffer holds";
    /// The digital inputs' configuration: an input beyond the card's 16, or a debounce over
    /// 10,000 ticks ([`crate::IoSettings`]).
    IoConfig = -90, MC_ERR_IO_CONFIG, nack IoConfig, "bad digital input configuration (input number or debounce)";
    /// A compare or probe channel the card does not have.
    IoChannel = -91, MC_ERR_IO_CHANNEL, nack IoChannel, "no such compare or probe channel";
    /// A compare mode, direction, output, pulse width, low-water mark, pitch or count out of
    /// its range.
    CompareMode = -92, MC_ERR_COMPARE_MODE, nack CompareMode, "bad compare mode, direction, output, pulse width, pitch or count";
    /// The compare channel's table has no room for the positions: wait for low water.
    CompareFull = -93, MC_ERR_COMPARE_FULL, nack CompareFull, "the compare table is full";
    /// Compare table positions must be strictly monotonic in the channel's direction.
    CompareOrder = -94, MC_ERR_COMPARE_ORDER, nack CompareOrder, "compare positions must be strictly monotonic in the direction";
    /// The compare channel is armed (disarm it first), its table runs the other way, or its
    /// output is another armed channel's.
    CompareBusy = -95, MC_ERR_COMPARE_BUSY, nack CompareBusy, "the compare channel or its output is in use";
    /// A probe input beyond the inputs and the index, no edge, or a window whose low end is
    /// above its high end.
    ProbeInput = -96, MC_ERR_PROBE_INPUT, nack ProbeInput, "bad probe input, edge or window";
    /// Layout 1.7 (sync): a gear ratio that is not an integer numerator over a positive
    /// integer denominator, both of magnitude 1..2^31-1.
    GearRatio = -74, MC_ERR_GEAR_RATIO, nack GearRatio, "a gear ratio must be integer numerator / positive integer denominator, each of magnitude 1..2^31-1";
    /// A master the card does not have (axis or auxiliary encoder), the slave itself, an
    /// unknown master source, or a master axis disabled or in ErrorStop.
    SyncMaster = -75, MC_ERR_SYNC_MASTER, nack SyncMaster, "no such master, the slave itself, or a master axis disabled or in ErrorStop";
    /// A PT/PVT point not at least one servo period after the point before it, or a segment
    /// longer than the longest move.
    PvtTime = -76, MC_ERR_PVT_TIME, nack PvtTime, "a PT/PVT point must come at least one servo period, and at most 1e6 s (the longest move), after the one before";
    /// A PT/PVT point whose segment breaks the stream's velocity or acceleration limit (the
    /// error names the point).
    PvtLimit = -77, MC_ERR_PVT_LIMIT, nack PvtLimit, "the PT/PVT segment into this point breaks the velocity or acceleration limit";
    /// PT/PVT commands out of sequence: points without an open stream or after its last point,
    /// a start without points or on an axis that moved, a begin while a stream runs.
    PvtSequence = -78, MC_ERR_PVT_SEQUENCE, nack PvtSequence, "PT/PVT commands out of sequence";
    /// A cam table number, point count or flags out of range, points not strictly increasing
    /// in the master or not finite, a table not loaded, or one in use by a slave.
    CamTable = -79, MC_ERR_CAM_TABLE, nack CamTable, "bad cam table: number, points (master strictly increasing, finite), not loaded, or in use";
    /// Cam table data without an open table or out of order.
    CamSequence = -80, MC_ERR_CAM_SEQUENCE, nack CamSequence, "cam table data out of sequence";
    /// Layout 1.8: a scope signal the card does not know, or an axis or group it has not.
    ScopeSignal = -81, MC_ERR_SCOPE_SIGNAL, nack ScopeSignal, "unknown scope signal, or no such axis or group";
    /// Scope channels 0 or more than 16.
    ScopeChannels = -82, MC_ERR_SCOPE_CHANNELS, nack ScopeChannels, "a scope samples 1 to 16 channels";
    /// A scope divider 0 or above 65536.
    ScopeDivider = -83, MC_ERR_SCOPE_DIVIDER, nack ScopeDivider, "the scope divider must be 1..65536";
    /// A bad scope mode, trigger, edge, trigger channel or input, a level not finite, or a
    /// one-shot capture of no samples.
    ScopeTrigger = -84, MC_ERR_SCOPE_TRIGGER, nack ScopeTrigger, "bad scope mode or trigger (kind, edge, channel, input, level, or no samples after it)";
    /// More pre-trigger samples than the card keeps.
    ScopePretrigger = -85, MC_ERR_SCOPE_PRETRIGGER, nack ScopePretrigger, "more pre-trigger samples than the card keeps (1024)";
    /// A scope command its state does not allow.
    ScopeState = -86, MC_ERR_SCOPE_STATE, nack ScopeState, "the scope's state does not allow this (configure or arm while armed, trigger while not waiting, stop while idle, arm before configure)";
    /// Layout 1.8: a configuration read-back of a block kind the card does not know (a card
    /// older than the library, or a kind or index that is not an integer).
    ConfigKind = -106, MC_ERR_CONFIG_KIND, nack ConfigKind, "the card does not know that configuration block";
    /// Layout 1.9: a compensation table's point count (over 256), bound (not > 0), backlash
    /// (negative, or over twice the bound), ramp velocity or acceleration (outside the card's
    /// range) out of range.
    CompTable = -110, MC_ERR_COMP_TABLE, nack CompTable, "bad compensation table: point count, bound, backlash or ramp limits out of range";
    /// Compensation data without an open table, or out of order.
    CompSequence = -111, MC_ERR_COMP_SEQUENCE, nack CompSequence, "compensation table data out of sequence";
    /// Compensation positions that are not strictly increasing.
    CompOrder = -112, MC_ERR_COMP_ORDER, nack CompOrder, "compensation positions must be strictly increasing";
    /// A correction (with half the backlash) beyond the table's bound, or a table of one
    /// column whose reverse correction differs from its forward one.
    CompBound = -113, MC_ERR_COMP_BOUND, nack CompBound, "a compensation correction is beyond the table's bound";
    /// A compensation table changed on an axis that is not at rest.
    CompBusy = -114, MC_ERR_COMP_BUSY, nack CompBusy, "the axis is not at rest: its compensation cannot change";
    /// Layout 1.10: a modulo period of zero given to `set_modulo` (a period must be a positive
    /// length; `clear_modulo` makes an axis linear).
    ModuloZero = -116, MC_ERR_MODULO_ZERO, "a modulo period of zero: use clear_modulo to make the axis linear";
    /// A modulo period that is negative, not finite, or outside the card's range (1 count to
    /// 10^11 counts).
    ModuloRange = -117, MC_ERR_MODULO_RANGE, nack ModuloRange, "modulo period out of range (negative, not finite, under 1 count or over 1e11 counts)";
    /// A modulo period changed on an axis that is not at rest.
    ModuloBusy = -118, MC_ERR_MODULO_BUSY, nack ModuloBusy, "the axis is not at rest: its modulo period cannot change";
    /// An absolute move that does not fit the axis: on a modulo axis a target outside
    /// [0, modulo), on a linear axis a direction other than the shortest way.
    ModuloMove = -119, MC_ERR_MODULO_MOVE, nack ModuloMove, "the move does not fit the axis: a modulo axis takes targets in [0, modulo), a linear axis no direction";
    /// Layout 1.10: a handwheel input the card does not have.
    HandwheelInput = -120, MC_ERR_HANDWHEEL_INPUT, nack HandwheelInput, "the card has no such handwheel (auxiliary encoder) input";
    /// A handwheel ratio of 0 or beyond the maximum (10000 counts per detent), or a detent
    /// outside 1..=1024 auxiliary counts.
    HandwheelRatio = -121, MC_ERR_HANDWHEEL_RATIO, nack HandwheelRatio, "bad handwheel ratio (0 or beyond 10000 counts per detent) or detent (1 to 1024 counts)";
    /// A configuration file that does not parse, or a value in it that the card would refuse
    /// (the error names the key and its line); nothing of the file was applied.
    ConfigFile = -107, MC_ERR_CONFIG_FILE, "the configuration file does not parse or validate";
    /// A G-code program refused by the interpreter (the error names the line and what is
    /// wrong there); nothing after that line was queued.
    Gcode = -109, MC_ERR_GCODE, "the G-code program has an error (see the error's line)";
    /// A wait for the last motion of an axis (or the last move of a group) when this library
    /// has started none there since the card was opened: there is nothing to wait for (the
    /// axis or group may still move, by motion of another kind: a raw command, another host).
    NoMotion = -115, MC_ERR_NO_MOTION, "no motion to wait for: none was started there by this process since the card was opened";
    /// Layout 1.10: the axis is a slave of a formed gantry; it moves only with its master.
    GantrySlave = -125, MC_ERR_GANTRY_SLAVE, nack GantrySlave, "the axis is a gantry's slave: command its master";
    /// A gantry member already in use: in another gantry, a slave in a group, geared, cammed
    /// or streaming.
    GantryInUse = -126, MC_ERR_GANTRY_IN_USE, nack GantryInUse, "a gantry axis is already in use (another gantry, a group, gearing or a stream)";
    /// A gantry's axes: an index, master or slave out of range, the master among its slaves,
    /// a slave twice, no slave or too many.
    GantryAxes = -127, MC_ERR_GANTRY_AXES, nack GantryAxes, "bad gantry axes: out of range, master among the slaves, a slave twice, or a bad count";
    /// A gantry's yaw gains, skew limit or square offset out of range.
    GantryGains = -128, MC_ERR_GANTRY_GAINS, nack GantryGains, "gantry kp, ki, skew limit or offset out of range";
    /// The gantry (or its axes) is not in a state that takes the command.
    GantryState = -129, MC_ERR_GANTRY_STATE, nack GantryState, "the gantry or its axes are not in a state that takes this";
    /// Layout 1.11: a group home order that names an axis the group does not have (a group
    /// axis index at or beyond its axis count).
    HomeAxis = -122, MC_ERR_HOME_AXIS, nack HomeAxis, "the home order names an axis the group does not have";
    /// A group home order that names an axis in two stages (or twice in one).
    HomeTwice = -123, MC_ERR_HOME_TWICE, nack HomeTwice, "the home order names an axis twice";
    /// A group home order with an empty stage, or none at all when the group has no
    /// configured order.
    HomeStage = -124, MC_ERR_HOME_STAGE, nack HomeStage, "the home order has an empty stage (or no stages, and the group has none configured)";
    /// An arc whose plane of two group axes names one axis twice.
    PlaneAxes = -130, MC_ERR_PLANE_AXES, nack PlaneAxes, "an arc's plane names one group axis twice";
    /// Layout 1.11: a servo filter's slot (0..4) or kind out of range.
    FilterKind = -131, MC_ERR_FILTER_KIND, nack FilterKind, "bad servo filter slot (0..3) or kind";
    /// A servo filter's frequency not above 0 and below the Nyquist frequency (half the servo
    /// rate); also a servo rate at which a filter set would not be.
    FilterFreq = -132, MC_ERR_FILTER_FREQ, nack FilterFreq, "servo filter frequency must be above 0 and below half the servo rate";
    /// A servo filter's damping (0 < damping <= 10), depth (-120..0 dB) or raw coefficient
    /// out of range.
    FilterParam = -133, MC_ERR_FILTER_PARAM, nack FilterParam, "servo filter damping (0..10], depth (-120..0 dB) or raw coefficient out of range";
    /// The servo filter designed has a pole on or outside the unit circle (within the card's
    /// margin of it): it would be unstable.
    FilterUnstable = -134, MC_ERR_FILTER_UNSTABLE, nack FilterUnstable, "unstable servo filter: a pole is not inside the unit circle";
    /// PID+FF gains refused: a gain negative, a derivative cut-off or friction deadband not
    /// above 0.
    PidffGains = -135, MC_ERR_PIDFF_GAINS, nack PidffGains, "bad PID+FF gains: every gain >= 0, derivative cut-off and friction deadband > 0";
    /// Layout 1.11: an analog input or output the card does not have (inputs 0..=7, outputs
    /// 0..=3), or a spare DAC output the path-speed output drives.
    AnalogChannel = -136, MC_ERR_ANALOG_CHANNEL, nack AnalogChannel, "no such analog input or output (inputs 0..7, outputs 0..3), or a DAC the PSO drives";
    /// An analog input's cut-off below 0 or above half the servo rate (Nyquist).
    AnalogFilter = -137, MC_ERR_ANALOG_FILTER, nack AnalogFilter, "an analog filter cut-off below 0 or above half the servo rate";
    /// An analog threshold beyond ±10 V, or a hysteresis below 0 or above 20 V.
    AnalogThreshold = -138, MC_ERR_ANALOG_THRESHOLD, nack AnalogThreshold, "an analog threshold beyond +-10 V or a hysteresis outside 0..20 V";
    /// A path-speed output's output, gate, range (min > max, beyond ±10 V or a duty beyond
    /// 0..1), reference speed (<= 0) or PWM frequency out of range, the gate on the PWM's own
    /// output, or a PWM on an output a compare channel pulses.
    PsoConfig = -139, MC_ERR_PSO_CONFIG, nack PsoConfig, "bad path-speed output: output, gate, min > max, range, reference speed or PWM frequency";
    /// A path-speed output on a group that does not exist or is not configured.
    PsoGroup = -140, MC_ERR_PSO_GROUP, nack PsoGroup, "the path-speed output's group does not exist or is not configured";
    /// `name:NAME` or `serial:N` matches more than one card listed (`mcctl list`, `mc_list_cards`):
    /// open it by its URI instead (the message names them).
    Ambiguous = -150, MC_ERR_AMBIGUOUS, "more than one card has that name or serial: open it by its URI";
    /// Layout 1.12: a timed command for a tick the card has already run.
    TickPassed = -152, MC_ERR_TICK_PASSED, nack TickPassed, "the tick of the timed command has passed on the card";
    /// The card holds as many timed commands as it can (16).
    TimedFull = -153, MC_ERR_TIMED_FULL, nack TimedFull, "the card holds 16 timed commands already";
    /// A timing without its command, or of a command that cannot be timed (a session's, a
    /// timing's or a commit's).
    TimedAlone = -154, MC_ERR_TIMED_ALONE, nack TimedAlone, "a timed command without its command, or of one that cannot be timed";
    /// A tick more than 600,000 ticks ahead, or a tick or key that is not a whole number in
    /// range.
    TickFar = -155, MC_ERR_TICK_FAR, nack TickFar, "the tick is too far ahead (600000 ticks at most), or not a whole number";
    /// The commit reached the bus's master on or after its tick: nothing of its key runs.
    CommitLate = -156, MC_ERR_COMMIT_LATE, nack CommitLate, "the commit arrived on or after its tick: nothing of it runs on any card";
    /// A commit sent to a follower: commit on the bus's master.
    NotMaster = -157, MC_ERR_NOT_MASTER, nack NotMaster, "this card follows the sync bus: commit on its master";
    /// A timed command whose commit the card had not seen by its tick: not run.
    NotCommitted = -158, MC_ERR_NOT_COMMITTED, nack NotCommitted, "the timed command's commit did not come before its tick: not run";
    /// The card lost the sync bus's master: its timed commands are dropped, its motion halted.
    SyncLost = -159, MC_ERR_SYNC_LOST, nack SyncLost, "the card lost the sync bus's master";
    /// The command of a refused timing: not run.
    TimedRefused = -160, MC_ERR_TIMED_REFUSED, nack TimedRefused, "its timing was refused: the command does not run";
    /// A held timed command dropped (a cancel, or the host's detach).
    TimedCancelled = -161, MC_ERR_TIMED_CANCELLED, nack Cancelled, "the timed command was cancelled before its tick";
    /// Layout 1.12: a normal-vector arc's normal is zero, or no plane was set before it.
    ArcNormal = -147, MC_ERR_ARC_NORMAL, nack ArcNormal, "an arc's normal vector is zero (or no normal plane was set)";
    /// A normal-vector arc's plane names a group axis twice.
    ArcAxes = -148, MC_ERR_ARC_AXES, nack ArcAxes, "an arc's plane of three group axes names one axis twice";
    /// A normal-vector arc's centre, or its end (unless it rises along the normal), is off
    /// the plane through the start by more than the group's tolerance.
    ArcOffPlane = -149, MC_ERR_ARC_OFF_PLANE, nack ArcOffPlane, "the arc's centre or end is off its plane by more than the group's tolerance";
    /// Layout 1.13: a piece of a move-queue arc in a plane given by a normal vector alone or
    /// out of order (its two command entries go together, the move first).
    ArcPiece = -151, MC_ERR_ARC_PIECE, nack ArcPiece, "a piece of a normal-vector arc move came alone or out of order (its two entries go together)";
    /// Layout 1.12: a frequency sweep's frequencies (0.1 Hz <= from <= to <= a quarter of the
    /// servo rate), points (1..=256), cycles (1..=1000), settle time (0..=60 s) or mode out of
    /// range.
    FreqRange = -141, MC_ERR_FREQ_RANGE, nack FreqRange, "sweep frequencies must be 0.1 Hz <= from <= to <= a quarter of the servo rate, with 1..256 points, 1..1000 cycles and 0..60 s settling";
    /// A frequency sweep's amplitude not above 0, or (on the servo output) above the axis's
    /// DAC limit.
    FreqAmplitude = -142, MC_ERR_FREQ_AMPLITUDE, nack FreqAmplitude, "sweep amplitude must be above 0 (and within the DAC limit on the servo output)";
    /// The sweep's sine would break the axis's limits: its velocity (amplitude 2 pi f above the
    /// safety's max velocity), acceleration, following error at rest (2 amplitude above
    /// min_ferror) or soft limits.
    FreqLimits = -143, MC_ERR_FREQ_LIMITS, nack FreqLimits, "the sweep's sine would exceed the axis's velocity, acceleration, following error or soft limits";
    /// A sweep is running: another sweep, or that axis's own motion, refused.
    FreqBusy = -144, MC_ERR_FREQ_BUSY, nack FreqBusy, "a frequency sweep is running (stop it first)";
    /// Layout 1.12: a compare channel armed on the digital output the path-speed output's PWM
    /// holds.
    PsoOutput = -145, MC_ERR_PSO_OUTPUT, nack PsoOutput, "the output is the path-speed output's PWM: no compare channel on it";
    /// Layout 1.13: compare on a modulo (rotary) axis: a position off the turn (not in
    /// `[0, modulo)`), a series longer than a turn, each turn on a linear axis, or the period
    /// changed while a compare channel watches the axis.
    CompareTurn = -146, MC_ERR_COMPARE_TURN, nack CompareTurn, "compare on a rotary axis: positions must lie in [0, modulo) and a series within one turn (each turn: rotary axes only; no period change while a channel watches the axis)";
    /// Layout 1.14, paths across cards: path dimensions that do not name each group axis once
    /// (or more than 16), or a staging command on a group without dimensions.
    PathDims = -162, MC_ERR_PATH_DIMS, nack PathDims, "the path's dimensions must name each axis of the group exactly once (at most 16 dimensions)";
    /// A segment across cards whose two command entries did not come together.
    PathMore = -163, MC_ERR_PATH_MORE, nack PathMore, "a segment of more than 8 dimensions came without its second entry (its two entries go together)";
    /// A release of more segments than are staged, or of segments staged from where the
    /// group no longer is.
    PathRelease = -164, MC_ERR_PATH_RELEASE, nack PathRelease, "the release names more segments than are staged (or the group moved since they were staged)";
}

impl From<NurbsError> for ErrorKind {
    /// The kind of a curve fault: the kind of the nack the card gives for the same fault, so a
    /// curve refused by [`crate::Nurbs::new`] on the host and one refused by the card have one
    /// code.
    fn from(e: NurbsError) -> Self {
        card_firmware::host::nurbs_nack(e).into()
    }
}

/// What a command, or a refusal, is about: the card, one axis, or one axes group.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Target {
    /// A card-wide command (configuration, safety, sessions).
    Card,
    /// An axis.
    Axis(usize),
    /// An axes group.
    Group(usize),
    /// A gantry (layout 1.10).
    Gantry(usize),
}

impl std::fmt::Display for Target {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Target::Card => f.write_str("the card"),
            Target::Axis(a) => write!(f, "axis {a}"),
            Target::Group(g) => write!(f, "group {g}"),
            Target::Gantry(g) => write!(f, "gantry {g}"),
        }
    }
}

/// An SDK error. [`Error::kind`] gives the flat code.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
#[allow(missing_docs)] // fields are named for what they hold; the messages say the rest
pub enum Error {
    /// See [`ErrorKind::BadUri`].
    #[error("bad card URI '{0}': expected sim, emu:NAME, uio:/dev/uioN, pci:DDDD:BB:DD.F, name:NAME or serial:N (N a decimal number 1 to 2^64-1)")]
    BadUri(String),
    /// See [`ErrorKind::NotFound`].
    #[error("no card at '{uri}': {reason}")]
    NotFound { uri: String, reason: String },
    /// See [`ErrorKind::Ambiguous`]: `matches` are the URIs of the cards that match.
    #[error("'{uri}' matches {} cards: {}; open one by its URI", .matches.len(), .matches.join(", "))]
    Ambiguous { uri: String, matches: Vec<String> },
    /// See [`ErrorKind::Busy`]: `in_this_process` when this process has the card open
    /// already (a card is opened once per process: use the handle it returned, from any
    /// thread), else another process (or host) has it.
    #[error("card '{uri}' is {}", if *.in_this_process {
        "already open in this process: a card is opened once per process; use the handle that \
         open returned (from any thread), or close it first"
    } else {
        "in use by another process"
    })]
    Busy { uri: String, in_this_process: bool },
    /// See [`ErrorKind::PermissionDenied`].
    #[error("card '{uri}' refused this process: {reason}")]
    PermissionDenied { uri: String, reason: String },
    /// See [`ErrorKind::VersionMismatch`].
    #[error("card DPRAM layout is version {card_major}.{card_minor}, this library speaks {lib_major}.{lib_minor}: the major versions must match")]
    VersionMismatch {
        card_major: u16,
        card_minor: u16,
        lib_major: u16,
        lib_minor: u16,
    },
    /// See [`ErrorKind::NotResponding`].
    #[error("card not responding: {0}")]
    NotResponding(String),
    /// See [`ErrorKind::Protocol`].
    #[error("card protocol violation: {0}")]
    Protocol(String),
    /// See [`ErrorKind::RingFull`].
    #[error("command ring full ({0} entries): the command was not queued")]
    RingFull(u32),
    /// See [`ErrorKind::Timeout`].
    #[error("timed out after {0:?}")]
    Timeout(Duration),
    /// See [`ErrorKind::Aborted`].
    #[error("motion on {target} aborted by {by}")]
    Aborted { target: Target, by: String },
    /// See [`ErrorKind::HomingFailed`]: why (`None`: a code this library does not know), and
    /// the actual position where it failed (user units).
    #[error("homing of {target} failed at {at}: {}", failure_reason(*.error))]
    HomingFailed {
        target: Target,
        error: Option<firmware_proto::HomingError>,
        at: f64,
    },
    /// Gantry homing ended without squaring the bridge (kind [`ErrorKind::HomingFailed`]):
    /// the axis that failed and why (`None`: a halt, stop, power off or safety stop ended its
    /// homing, or a code this library does not know). The gantry is coupled where it stopped.
    #[error("homing of gantry {gantry} failed on axis {axis}: {}", gantry_failure(*.error))]
    GantryHomingFailed {
        gantry: usize,
        axis: usize,
        error: Option<firmware_proto::HomingError>,
    },
    /// See [`ErrorKind::HomingFailed`]: layout 1.11, a group homing failed as a whole: `axis`
    /// the member whose homing failed (`None`: the group's own halt, stop or disable ended
    /// it), `error` its homing error (`None`: a halt, stop or safety stop ended it). The
    /// group's other members were halted; the group is at rest.
    #[error("homing of group {group} failed{}: {}", .axis.map_or(String::new(), |a| format!(" on axis {a}")), gantry_failure(*.error))]
    GroupHomingFailed {
        group: usize,
        axis: Option<usize>,
        error: Option<firmware_proto::HomingError>,
    },
    /// See [`ErrorKind::BadAxis`].
    #[error("axis {axis} does not exist: the card has {count} axes")]
    BadAxis { axis: usize, count: usize },
    /// See [`ErrorKind::BadGroup`]: a group number the card does not have.
    #[error("group {group} does not exist: the card has {count} groups (0 to {})", count - 1)]
    BadGroup { group: usize, count: usize },
    /// See [`ErrorKind::NotFinite`].
    #[error("{what} is not a finite number ({value})")]
    NotFinite { what: &'static str, value: f64 },
    /// See [`ErrorKind::NonPositiveLimit`].
    #[error("{what} must be greater than zero, got {value}")]
    NonPositive { what: &'static str, value: f64 },
    /// The card refused a command.
    #[error("card refused {command} on {target}: {reason}")]
    Nack {
        command: &'static str,
        target: Target,
        code: NackCode,
        reason: &'static str,
    },
    /// The SDK refused a command before sending it, for the reason the card would give
    /// (`code`; nothing reached the card).
    #[error("{command} on {target} not sent: {reason}")]
    Refused {
        command: &'static str,
        target: Target,
        code: NackCode,
        reason: &'static str,
    },
    /// A PT/PVT point the card refused (`code`: the nack), `index` into the points given; the
    /// points before it were queued, it and those after it were not.
    #[error("PT/PVT point {index} on {target} refused: {reason}")]
    PvtPoint {
        target: Target,
        index: usize,
        code: NackCode,
        reason: &'static str,
    },
    /// See [`ErrorKind::CardGone`].
    #[error("card gone: {0}")]
    CardGone(String),
    /// See [`ErrorKind::Closed`].
    #[error("the card was closed")]
    Closed,
    /// See [`ErrorKind::Cancelled`].
    #[error("the wait was cancelled")]
    Cancelled,

    /// A NURBS curve that [`crate::Nurbs::new`] refuses (kind: see `From<NurbsError> for
    /// ErrorKind`).
    #[error("bad NURBS curve: {0}")]
    Nurbs(#[from] NurbsError),
    /// See [`ErrorKind::Io`].
    #[error("{context}: {source}")]
    Io {
        context: String,
        source: std::io::Error,
    },
    /// See [`ErrorKind::Unsupported`].
    #[error("not supported: {0}")]
    Unsupported(String),
    /// See [`ErrorKind::ModuloZero`]: `set_modulo(0)` on this axis (nothing was sent).
    #[error("set_modulo on axis {0}: a period of zero is no rotary axis; use clear_modulo to make the axis linear")]
    ModuloZero(usize),
    /// See [`ErrorKind::NoMotion`].
    #[error("nothing to wait for on {0}: no motion was started there through this library since the card was opened")]
    NoMotion(Target),
    /// A configuration the host refuses before any card sees it (see [`ErrorKind::BadConfig`]).
    #[error("bad configuration: {0}")]
    BadConfig(String),
    /// A configuration file that does not parse or validate (see [`ErrorKind::ConfigFile`]):
    /// the key (`axis.2.ffpiv.kp`; empty for a syntax error) and its line (1-based; 0 when the
    /// text has no place for it, as a key the file lacks).
    #[error("{}: {message}", config_place(path, key, *line))]
    ConfigFile {
        /// The file (or what the text came from).
        path: String,
        /// The key path, dotted.
        key: String,
        /// Its line, 1-based (0: none).
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// A G-code program the interpreter refuses (see [`ErrorKind::Gcode`]).
    #[error("G-code {0}")]
    Gcode(#[from] crate::gcode::GcodeError),
    /// The card refused a block of a configuration file that had passed the host's checks
    /// (its state changed meanwhile): the kind is the refusal's; `applied` lists the sections
    /// applied before it.
    #[error("{key}: {source} (applied before it: {applied})")]
    ConfigApply {
        /// The section the card refused.
        key: String,
        /// The sections applied before it (`none` if none).
        applied: String,
        /// The refusal.
        source: Box<Error>,
    },
    /// An error about a line of a file the host read (a PT/PVT point of `mcctl pvt`, …): the
    /// kind is the error's.
    #[error("{origin}:{line}: {source}")]
    AtLine {
        /// The file (or what the text came from).
        origin: String,
        /// Its line, 1-based.
        line: usize,
        /// The error.
        source: Box<Error>,
    },
}

fn gantry_failure(e: Option<firmware_proto::HomingError>) -> String {
    match e {
        Some(e) => failure_reason(Some(e)).into(),
        None => "its homing was ended by a halt, stop, power off or safety stop".into(),
    }
}

fn config_place(path: &str, key: &str, line: usize) -> String {
    match (key.is_empty(), line) {
        (true, 0) => path.to_string(),
        (true, l) => format!("{path}:{l}"),
        (false, 0) => format!("{path}: {key}"),
        (false, l) => format!("{path}:{l}: {key}"),
    }
}

impl Error {
    /// The flat code of this error.
    pub fn kind(&self) -> ErrorKind {
        match self {
            Error::BadUri(_) => ErrorKind::BadUri,
            Error::NotFound { .. } => ErrorKind::NotFound,
            Error::Ambiguous { .. } => ErrorKind::Ambiguous,
            Error::Busy { .. } => ErrorKind::Busy,
            Error::PermissionDenied { .. } => ErrorKind::PermissionDenied,
            Error::VersionMismatch { .. } => ErrorKind::VersionMismatch,
            Error::NotResponding(_) => ErrorKind::NotResponding,
            Error::Protocol(_) => ErrorKind::Protocol,
            Error::RingFull(_) => ErrorKind::RingFull,
            Error::Timeout(_) => ErrorKind::Timeout,
            Error::Aborted { .. } => ErrorKind::Aborted,
            Error::HomingFailed { .. }
            | Error::GantryHomingFailed { .. }
            | Error::GroupHomingFailed { .. } => ErrorKind::HomingFailed,
            Error::BadAxis { .. } => ErrorKind::BadAxis,
            Error::BadGroup { .. } => ErrorKind::BadGroup,
            Error::NotFinite { .. } => ErrorKind::NotFinite,
            Error::NonPositive { .. } => ErrorKind::NonPositiveLimit,
            Error::Nack { code, .. }
            | Error::Refused { code, .. }
            | Error::PvtPoint { code, .. } => (*code).into(),
            Error::CardGone(_) => ErrorKind::CardGone,
            Error::Closed => ErrorKind::Closed,
            Error::Cancelled => ErrorKind::Cancelled,
            Error::Nurbs(e) => (*e).into(),
            Error::Io { .. } => ErrorKind::Io,
            Error::Unsupported(_) => ErrorKind::Unsupported,
            Error::NoMotion(_) => ErrorKind::NoMotion,
            Error::ModuloZero(_) => ErrorKind::ModuloZero,
            Error::BadConfig(_) => ErrorKind::BadConfig,
            Error::ConfigFile { .. } => ErrorKind::ConfigFile,
            Error::Gcode(_) => ErrorKind::Gcode,
            Error::ConfigApply { source, .. } | Error::AtLine { source, .. } => source.kind(),
        }
    }

    pub(crate) fn io(context: impl Into<String>, source: impl Into<std::io::Error>) -> Self {
        Error::Io {
            context: context.into(),
            source: source.into(),
        }
    }
}

/// A description of each nack code: that of its [`ErrorKind`].
pub fn nack_reason(code: NackCode) -> &'static str {
    ErrorKind::from(code).description()
}

/// Result with the SDK's error.
pub type Result<T, E = Error> = std::result::Result<T, E>;

/// The name of a fault bit (as carried by a motion-aborted event), if it is one.
pub(crate) fn fault_name(code: i32) -> Option<&'static str> {
    use firmware_proto::Faults;
    let names = [
        (Faults::WATCHDOG, "the host watchdog"),
        (Faults::ESTOP, "an e-stop"),
        (Faults::HARD_LIMIT_POS, "the positive limit switch"),
        (Faults::HARD_LIMIT_NEG, "the negative limit switch"),
        (Faults::SOFT_LIMIT_POS, "the positive soft limit"),
        (Faults::SOFT_LIMIT_NEG, "the negative soft limit"),
        (Faults::FOLLOWING_ERROR, "a following error"),
        (Faults::AMP_ALARM, "an amplifier alarm"),
        (Faults::ENCODER, "an encoder fault"),
        (Faults::PROTOCOL, "a protocol error"),
        (
            Faults::STOP_TIMEOUT,
            "a stop that ran past the maximum stop time",
        ),
    ];
    names
        .iter()
        .find(|(bit, _)| bit.bits() as i32 == code)
        .map(|(_, n)| *n)
}

/// What a homing failure means, in words.
pub(crate) fn failure_reason(e: Option<firmware_proto::HomingError>) -> &'static str {
    use firmware_proto::HomingError;
    match e {
        Some(HomingError::LimitReached) => {
            "a limit switch the method does not reverse at: the switch is missing"
        }
        Some(HomingError::DistanceExceeded) => {
            "the maximum distance from the start, without the switch or hard stop"
        }
        Some(HomingError::Timeout) => "not homed within the timeout",
        Some(HomingError::NoIndex) => "no index pulse within the index distance",
        Some(HomingError::Plan) => "a motion of the method could not be planned",
        None => "a reason this library does not know",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_table_of_kinds_is_one_to_one() {
        use std::collections::HashSet;
        let kinds = ErrorKind::ALL;
        let codes: HashSet<i32> = kinds.iter().map(|k| k.code()).collect();
        let names: HashSet<&str> = kinds.iter().map(|k| k.c_name()).collect();
        let texts: HashSet<&str> = kinds.iter().map(|k| k.description()).collect();
        assert_eq!(codes.len(), kinds.len(), "a C code used twice");
        assert_eq!(names.len(), kinds.len(), "a C name used twice");
        assert_eq!(texts.len(), kinds.len(), "a description used twice");
        for &k in kinds {
            // -100..-103 are the C ABI's own codes (cffi/src/result.rs).
            let c = k.code();
            assert!(c < 0 && !(-103..=-100).contains(&c), "{k:?}: {c}");
            assert_eq!(ErrorKind::from_code(k.code()), Some(k));
            assert!(k.c_name().starts_with("MC_ERR_"), "{k:?}");
            assert_eq!(k.c_description().to_str().unwrap(), k.description());
            assert!(
                !k.description().is_empty() && !k.doc().trim().is_empty(),
                "{k:?}"
            );
        }
        assert_eq!(ErrorKind::from_code(0), None);
        assert_eq!(ErrorKind::from_code(-100), None);
        // Every nack of the card stands for its own kind.
        let from_nacks: HashSet<ErrorKind> =
            NackCode::ALL.iter().map(|&c| ErrorKind::from(c)).collect();
        assert_eq!(from_nacks.len(), NackCode::ALL.len());
        assert_eq!(
            ErrorKind::from(NackCode::UnknownOpcode),
            ErrorKind::UnknownCommand
        );
        assert_eq!(nack_reason(NackCode::BadAxis), "no such axis");
    }

    #[test]
    fn every_nurbs_fault_has_its_own_kind() {
        use NurbsError as N;
        let cases = [
            (N::BadDegree { degree: 9 }, ErrorKind::NurbsDegree),
            (N::BadDimension { dim: 1 }, ErrorKind::NurbsDimension),
            (
                N::ControlDataLength { len: 3, dim: 2 },
                ErrorKind::NurbsCtrlCount,
            ),
            (
                N::TooFewControlPoints { n_ctrl: 2, min: 3 },
                ErrorKind::NurbsCtrlCount,
            ),
            (
                N::TooManyControlPoints {
                    n_ctrl: 2000,
                    max: 1024,
                },
                ErrorKind::NurbsCtrlCount,
            ),
            (
                N::WeightCountMismatch {
                    weights: 2,
                    n_ctrl: 3,
                },
                ErrorKind::NurbsCtrlCount,
            ),
            (
                N::KnotCountMismatch {
                    knots: 5,
                    expected: 6,
                },
                ErrorKind::NurbsKnotCount,
            ),
            (N::NonFiniteKnot { index: 1 }, ErrorKind::NurbsKnot),
            (
                N::KnotsDecreasing { index: 3 },
                ErrorKind::NurbsKnotsDecreasing,
            ),
            (
                N::KnotMultiplicity {
                    index: 3,
                    multiplicity: 4,
                },
                ErrorKind::NurbsKnotMultiplicity,
            ),
            (N::NotClamped, ErrorKind::NurbsNotClamped),
            (N::EmptyDomain, ErrorKind::NurbsNotClamped),
            (N::BadWeight { index: 0 }, ErrorKind::NurbsWeight),
            (N::NonFiniteControlPoint { index: 0 }, ErrorKind::NurbsPoint),
            (N::NonFiniteParameter, ErrorKind::BadConfig),
            (N::ParameterOutOfRange, ErrorKind::BadConfig),
            (N::BadCircle, ErrorKind::BadConfig),
        ];
        for (e, kind) in cases {
            let err = Error::from(e);
            assert_eq!(err.kind(), kind, "{e:?}");
            assert!(err.to_string().contains(&e.to_string()), "{err}");
        }
        // A refused knot vector through `?`, as an application writes it.
        let bad = || -> Result<crate::Nurbs> {
            Ok(crate::Nurbs::new(
                2,
                2,
                &[0.0, 0.0, 1.0, 1.0, 2.0, 0.0],
                &[1.0; 3],
                &[0.0, 0.0, 0.0, 1.0, 0.5, 1.0],
            )?)
        };
        assert_eq!(
            bad().err().map(|e| e.kind()),
            Some(ErrorKind::NurbsKnotsDecreasing)
        );
    }
}
