//! The SDK's one error type.

use card_emu::motion::nurbs::NurbsError;
use firmware_proto::NackCode;
use std::time::Duration;

/// What went wrong, as a flat code: one-to-one with the C ABI's result codes.
///
/// Deliberately not `#[non_exhaustive]`: the C ABI (`cffi/`) matches it exhaustively, so a new
/// kind does not compile until it has its own `MC_ERR_` code.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ErrorKind {
    /// The URI is not one of `sim`, `emu:NAME`, `uio:/dev/uioN`, `pci:DDDD:BB:DD.F`.
    BadUri,
    /// No card at that URI.
    NotFound,
    /// Another process has the card open.
    Busy,
    /// The card's DPRAM layout major version differs from this library's.
    VersionMismatch,
    /// The card does not answer (its tick counter stopped, or it was removed).
    NotResponding,
    /// The card broke the protocol (corrupt ring indices, bad signature, torn status).
    Protocol,
    /// The command ring is full: nothing was queued.
    RingFull,
    /// A wait ran out of time.
    Timeout,
    /// The motion waited for was aborted by another command or a fault.
    Aborted,
    /// The card has no such axis.
    BadAxis,
    /// An argument is NaN or infinite.
    NotFinite,
    /// A limit is zero or negative.
    NonPositiveLimit,
    /// The axis is disabled.
    AxisDisabled,
    /// The command is not allowed in the axis's current state.
    InvalidState,
    /// A configuration value is out of range.
    BadConfig,
    /// No motion profile satisfies the request.
    Infeasible,
    /// A position is beyond the card's range.
    OutOfRange,
    /// The card configuration can only change while all axes are disabled.
    AxesEnabled,
    /// The firmware does not know the command.
    UnknownCommand,
    /// No such axes group.
    BadGroup,
    /// An axis already belongs to another group.
    AxisInOtherGroup,
    /// The move needs an axis the group does not have.
    AxisNotInGroup,
    /// An axis of the group is moving on its own.
    AxisBusy,
    /// Single-axis motion on an axis of an enabled group.
    AxisGrouped,
    /// The arc has zero length or zero radius.
    ZeroLengthArc,
    /// The centre is not equidistant from start and end within the tolerance.
    CentreNotEquidistant,
    /// The radius is shorter than half the chord.
    RadiusTooSmall,
    /// The three points of a border-point arc are on one line.
    CollinearPoints,
    /// The group's move queue is full: nothing was queued.
    QueueFull,
    /// The interpolator cannot run with the group's acc/dec mode.
    IncompatibleMode,
    /// The group is disabled (or not configured).
    GroupDisabled,
    /// Filters can change only while they hold no distance.
    FilterBusy,
    /// NURBS data or end without a begin, out of order, or missing.
    NurbsSequence,
    /// NURBS degree outside 1..5.
    NurbsDegree,
    /// NURBS on a group of fewer than 2 axes.
    NurbsDimension,
    /// Too few or too many control points.
    NurbsCtrlCount,
    /// The knot count is not n_ctrl + degree + 1.
    NurbsKnotCount,
    /// The knots decrease.
    NurbsKnotsDecreasing,
    /// An interior knot is repeated more than degree times.
    NurbsKnotMultiplicity,
    /// The end knots are not repeated degree + 1 times (or the domain is empty).
    NurbsNotClamped,
    /// A weight is not finite and positive.
    NurbsWeight,
    /// A control point is not finite.
    NurbsPoint,
    /// The curve does not start where the group's path is.
    NurbsStart,
    /// The curve has zero length.
    NurbsZeroLength,
    /// A knot is not finite.
    NurbsKnot,
    /// An operating-system call failed.
    Io,
    /// The backend cannot do this (for example interrupts on a `pci:` card).
    Unsupported,
    /// The host watchdog tripped and is latched: [`crate::Card::reset_faults`] first.
    WatchdogTripped,
    /// An e-stop is latched: [`crate::Card::reset_faults`] first.
    EStopActive,
    /// The move would go further into an active limit switch.
    HardLimit,
    /// The move would go further beyond a soft limit.
    SoftLimit,
    /// A reset was refused because its cause (alarm, encoder fault, e-stop input, missing
    /// heartbeat) is still present.
    CauseActive,
    /// A watchdog timeout of zero or under 1.5 × the host's heartbeat period.
    WatchdogTimeout,
    /// A stop category other than 0, 1 or 2.
    BadCategory,
    /// A kinematic limit outside the range the card accepts
    /// ([`firmware_proto::limit_range`]: denormal, absurdly small or large).
    LimitRange,
    /// The card planned a profile that failed its own check (shorter than |d|/vmax, off its
    /// target or beyond a limit) and refused it: nothing moved.
    PlanCheck,
    /// The card served the command after its deadline and refused it: it was not executed.
    Expired,
    /// A stop ramp longer than the card's maximum stop time, or a maximum stop time out of
    /// range.
    StopTooLong,
    /// The card's session belongs to another host.
    Session,
    /// The card went away (its `card-emu` process exited or was killed): every call on it
    /// fails with this.
    CardGone,
    /// The card was closed ([`crate::Card::close`]) while the call waited, or before it.
    Closed,
    /// The wait was cancelled from another thread ([`crate::Card::cancel_waits`]).
    Cancelled,
    /// The card's server refused this user (`emu:` access control).
    PermissionDenied,
}

impl From<NackCode> for ErrorKind {
    fn from(c: NackCode) -> Self {
        match c {
            NackCode::UnknownOpcode => ErrorKind::UnknownCommand,
            NackCode::BadAxis => ErrorKind::BadAxis,
            NackCode::NotFinite => ErrorKind::NotFinite,
            NackCode::NonPositiveLimit => ErrorKind::NonPositiveLimit,
            NackCode::AxisDisabled => ErrorKind::AxisDisabled,
            NackCode::InvalidState => ErrorKind::InvalidState,
            NackCode::BadConfig => ErrorKind::BadConfig,
            NackCode::Infeasible => ErrorKind::Infeasible,
            NackCode::OutOfRange => ErrorKind::OutOfRange,
            NackCode::AxesEnabled => ErrorKind::AxesEnabled,
            NackCode::BadGroup => ErrorKind::BadGroup,
            NackCode::AxisInOtherGroup => ErrorKind::AxisInOtherGroup,
            NackCode::AxisNotInGroup => ErrorKind::AxisNotInGroup,
            NackCode::AxisBusy => ErrorKind::AxisBusy,
            NackCode::AxisGrouped => ErrorKind::AxisGrouped,
            NackCode::ZeroLengthArc => ErrorKind::ZeroLengthArc,
            NackCode::CentreNotEquidistant => ErrorKind::CentreNotEquidistant,
            NackCode::RadiusTooSmall => ErrorKind::RadiusTooSmall,
            NackCode::CollinearPoints => ErrorKind::CollinearPoints,
            NackCode::QueueFull => ErrorKind::QueueFull,
            NackCode::IncompatibleMode => ErrorKind::IncompatibleMode,
            NackCode::GroupDisabled => ErrorKind::GroupDisabled,
            NackCode::FilterBusy => ErrorKind::FilterBusy,
            NackCode::NurbsSequence => ErrorKind::NurbsSequence,
            NackCode::NurbsDegree => ErrorKind::NurbsDegree,
            NackCode::NurbsDimension => ErrorKind::NurbsDimension,
            NackCode::NurbsCtrlCount => ErrorKind::NurbsCtrlCount,
            NackCode::NurbsKnotCount => ErrorKind::NurbsKnotCount,
            NackCode::NurbsKnotsDecreasing => ErrorKind::NurbsKnotsDecreasing,
            NackCode::NurbsKnotMultiplicity => ErrorKind::NurbsKnotMultiplicity,
            NackCode::NurbsNotClamped => ErrorKind::NurbsNotClamped,
            NackCode::NurbsWeight => ErrorKind::NurbsWeight,
            NackCode::NurbsPoint => ErrorKind::NurbsPoint,
            NackCode::NurbsStart => ErrorKind::NurbsStart,
            NackCode::NurbsZeroLength => ErrorKind::NurbsZeroLength,
            NackCode::NurbsKnot => ErrorKind::NurbsKnot,
            NackCode::WatchdogTripped => ErrorKind::WatchdogTripped,
            NackCode::EStopActive => ErrorKind::EStopActive,
            NackCode::HardLimit => ErrorKind::HardLimit,
            NackCode::SoftLimit => ErrorKind::SoftLimit,
            NackCode::CauseActive => ErrorKind::CauseActive,
            NackCode::WatchdogTimeout => ErrorKind::WatchdogTimeout,
            NackCode::BadCategory => ErrorKind::BadCategory,
            NackCode::LimitRange => ErrorKind::LimitRange,
            NackCode::PlanCheck => ErrorKind::PlanCheck,
            NackCode::Expired => ErrorKind::Expired,
            NackCode::StopTooLong => ErrorKind::StopTooLong,
            NackCode::Session => ErrorKind::Session,
        }
    }
}

impl From<NurbsError> for ErrorKind {
    /// The kind of a curve fault: the kind of the nack the card gives for the same fault, so a
    /// curve refused by [`crate::Nurbs::new`] on the host and one refused by the card have one
    /// code.
    fn from(e: NurbsError) -> Self {
        card_emu::firmware::group::nurbs_nack(e).into()
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
}

impl std::fmt::Display for Target {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Target::Card => f.write_str("the card"),
            Target::Axis(a) => write!(f, "axis {a}"),
            Target::Group(g) => write!(f, "group {g}"),
        }
    }
}

/// An SDK error. [`Error::kind`] gives the flat code.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
#[allow(missing_docs)] // fields are named for what they hold; the messages say the rest
pub enum Error {
    /// See [`ErrorKind::BadUri`].
    #[error("bad card URI '{0}': expected sim, emu:NAME, uio:/dev/uioN or pci:DDDD:BB:DD.F")]
    BadUri(String),
    /// See [`ErrorKind::NotFound`].
    #[error("no card at '{uri}': {reason}")]
    NotFound { uri: String, reason: String },
    /// See [`ErrorKind::Busy`].
    #[error("card '{uri}' is in use by another process")]
    Busy { uri: String },
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
    /// See [`ErrorKind::BadAxis`].
    #[error("axis {axis} does not exist: the card has {count} axes")]
    BadAxis { axis: usize, count: usize },
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
    /// A configuration the host refuses before any card sees it (see [`ErrorKind::BadConfig`]).
    #[error("bad configuration: {0}")]
    BadConfig(String),
}

impl Error {
    /// The flat code of this error.
    pub fn kind(&self) -> ErrorKind {
        match self {
            Error::BadUri(_) => ErrorKind::BadUri,
            Error::NotFound { .. } => ErrorKind::NotFound,
            Error::Busy { .. } => ErrorKind::Busy,
            Error::PermissionDenied { .. } => ErrorKind::PermissionDenied,
            Error::VersionMismatch { .. } => ErrorKind::VersionMismatch,
            Error::NotResponding(_) => ErrorKind::NotResponding,
            Error::Protocol(_) => ErrorKind::Protocol,
            Error::RingFull(_) => ErrorKind::RingFull,
            Error::Timeout(_) => ErrorKind::Timeout,
            Error::Aborted { .. } => ErrorKind::Aborted,
            Error::BadAxis { .. } => ErrorKind::BadAxis,
            Error::NotFinite { .. } => ErrorKind::NotFinite,
            Error::NonPositive { .. } => ErrorKind::NonPositiveLimit,
            Error::Nack { code, .. } | Error::Refused { code, .. } => (*code).into(),
            Error::CardGone(_) => ErrorKind::CardGone,
            Error::Closed => ErrorKind::Closed,
            Error::Cancelled => ErrorKind::Cancelled,
            Error::Nurbs(e) => (*e).into(),
            Error::Io { .. } => ErrorKind::Io,
            Error::Unsupported(_) => ErrorKind::Unsupported,
            Error::BadConfig(_) => ErrorKind::BadConfig,
        }
    }

    pub(crate) fn io(context: impl Into<String>, source: impl Into<std::io::Error>) -> Self {
        Error::Io {
            context: context.into(),
            source: source.into(),
        }
    }
}

/// A description of each nack code.
pub fn nack_reason(code: NackCode) -> &'static str {
    match code {
        NackCode::UnknownOpcode => "unknown command",
        NackCode::BadAxis => "no such axis",
        NackCode::NotFinite => "an argument is NaN or infinite",
        NackCode::NonPositiveLimit => "a limit is zero or negative",
        NackCode::AxisDisabled => "the axis is disabled",
        NackCode::InvalidState => "not allowed in the axis's current state",
        NackCode::BadConfig => "a configuration value is out of range",
        NackCode::Infeasible => "no profile satisfies the request",
        NackCode::OutOfRange => "position out of range",
        NackCode::AxesEnabled => "all axes must be disabled first",
        NackCode::BadGroup => "no such group",
        NackCode::AxisInOtherGroup => "an axis already belongs to another group",
        NackCode::AxisNotInGroup => "the move needs an axis the group does not have",
        NackCode::AxisBusy => "an axis of the group is moving on its own",
        NackCode::AxisGrouped => "the axis belongs to an enabled group",
        NackCode::ZeroLengthArc => "the arc has zero length or zero radius",
        NackCode::CentreNotEquidistant => "the centre is not equidistant from start and end",
        NackCode::RadiusTooSmall => "the radius is shorter than half the chord",
        NackCode::CollinearPoints => "the three points are on one line",
        NackCode::QueueFull => "the group's move queue is full",
        NackCode::IncompatibleMode => "the interpolator cannot run with this acc/dec mode",
        NackCode::GroupDisabled => "the group is disabled",
        NackCode::FilterBusy => "the filter still holds distance",
        NackCode::NurbsSequence => "NURBS data out of sequence (no begin, a gap, or missing data)",
        NackCode::NurbsDegree => "NURBS degree outside 1..5",
        NackCode::NurbsDimension => "NURBS curves need a group of at least 2 axes",
        NackCode::NurbsCtrlCount => "too few or too many NURBS control points",
        NackCode::NurbsKnotCount => "the knot count must be control points + degree + 1",
        NackCode::NurbsKnotsDecreasing => "the knots decrease",
        NackCode::NurbsKnotMultiplicity => "an interior knot is repeated more than degree times",
        NackCode::NurbsNotClamped => "the knot vector is not clamped",
        NackCode::NurbsWeight => "a weight is not finite and positive",
        NackCode::NurbsPoint => "a control point is not finite",
        NackCode::NurbsStart => "the curve does not start where the group is",
        NackCode::NurbsZeroLength => "the curve has zero length",
        NackCode::NurbsKnot => "a knot is not finite",
        NackCode::WatchdogTripped => "the host watchdog tripped: reset the card's faults first",
        NackCode::EStopActive => "an e-stop is latched: reset the card's faults first",
        NackCode::HardLimit => "the move goes further into an active limit switch",
        NackCode::SoftLimit => "the move goes further beyond a soft limit",
        NackCode::CauseActive => "the cause of the fault is still present",
        NackCode::WatchdogTimeout => {
            "watchdog timeout is zero or under 1.5 x the host's heartbeat period"
        }
        NackCode::BadCategory => "stop category must be 0, 1 or 2",
        NackCode::LimitRange => {
            "a limit is outside the range the card accepts (one count in 1e6 s to the whole \
             position range in one servo tick)"
        }
        NackCode::PlanCheck => "the planned profile failed the card's check; nothing moved",
        NackCode::Expired => "the card served the command after its deadline; it was not executed",
        NackCode::StopTooLong => {
            "the stop ramp from max velocity is longer than the card's maximum stop time"
        }
        NackCode::Session => "another host's session is attached",
    }
}

/// Result with the SDK's error.
pub type Result<T, E = Error> = std::result::Result<T, E>;

/// The name of a fault bit (as carried by a motion-aborted event), if it is one.
pub(crate) fn fault_name(code: i32) -> Option<&'static str> {
    use firmware_proto::fault;
    let names = [
        (fault::WATCHDOG, "the host watchdog"),
        (fault::ESTOP, "an e-stop"),
        (fault::HARD_LIMIT_POS, "the positive limit switch"),
        (fault::HARD_LIMIT_NEG, "the negative limit switch"),
        (fault::SOFT_LIMIT_POS, "the positive soft limit"),
        (fault::SOFT_LIMIT_NEG, "the negative soft limit"),
        (fault::FOLLOWING_ERROR, "a following error"),
        (fault::AMP_ALARM, "an amplifier alarm"),
        (fault::ENCODER, "an encoder fault"),
        (fault::PROTOCOL, "a protocol error"),
        (
            fault::STOP_TIMEOUT,
            "a stop that ran past the maximum stop time",
        ),
    ];
    names
        .iter()
        .find(|(bit, _)| *bit as i32 == code)
        .map(|(_, n)| *n)
}

#[cfg(test)]
mod tests {
    use super::*;

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
