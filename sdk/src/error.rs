//! The SDK's one error type.

use firmware_proto::NackCode;
use std::time::Duration;

/// What went wrong, as a flat code: one-to-one with the C ABI's result codes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
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
            NackCode::WatchdogTripped => ErrorKind::WatchdogTripped,
            NackCode::EStopActive => ErrorKind::EStopActive,
            NackCode::HardLimit => ErrorKind::HardLimit,
            NackCode::SoftLimit => ErrorKind::SoftLimit,
            NackCode::CauseActive => ErrorKind::CauseActive,
            NackCode::WatchdogTimeout => ErrorKind::WatchdogTimeout,
            NackCode::BadCategory => ErrorKind::BadCategory,
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
    #[error("motion on axis {axis} aborted by {by}")]
    Aborted { axis: usize, by: String },
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
    #[error("card refused {command} on axis {axis}: {reason}")]
    Nack {
        command: &'static str,
        axis: usize,
        code: NackCode,
        reason: &'static str,
    },
    /// See [`ErrorKind::Io`].
    #[error("{context}: {source}")]
    Io {
        context: String,
        source: std::io::Error,
    },
    /// See [`ErrorKind::Unsupported`].
    #[error("not supported: {0}")]
    Unsupported(String),
}

impl Error {
    /// The flat code of this error.
    pub fn kind(&self) -> ErrorKind {
        match self {
            Error::BadUri(_) => ErrorKind::BadUri,
            Error::NotFound { .. } => ErrorKind::NotFound,
            Error::Busy { .. } => ErrorKind::Busy,
            Error::VersionMismatch { .. } => ErrorKind::VersionMismatch,
            Error::NotResponding(_) => ErrorKind::NotResponding,
            Error::Protocol(_) => ErrorKind::Protocol,
            Error::RingFull(_) => ErrorKind::RingFull,
            Error::Timeout(_) => ErrorKind::Timeout,
            Error::Aborted { .. } => ErrorKind::Aborted,
            Error::BadAxis { .. } => ErrorKind::BadAxis,
            Error::NotFinite { .. } => ErrorKind::NotFinite,
            Error::NonPositive { .. } => ErrorKind::NonPositiveLimit,
            Error::Nack { code, .. } => (*code).into(),
            Error::Io { .. } => ErrorKind::Io,
            Error::Unsupported(_) => ErrorKind::Unsupported,
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
        NackCode::WatchdogTripped => "the host watchdog tripped: reset the card's faults first",
        NackCode::EStopActive => "an e-stop is latched: reset the card's faults first",
        NackCode::HardLimit => "the move goes further into an active limit switch",
        NackCode::SoftLimit => "the move goes further beyond a soft limit",
        NackCode::CauseActive => "the cause of the fault is still present",
        NackCode::WatchdogTimeout => {
            "watchdog timeout is zero or under 1.5 x the host's heartbeat period"
        }
        NackCode::BadCategory => "stop category must be 0, 1 or 2",
    }
}

/// Result with the SDK's error.
pub type Result<T, E = Error> = std::result::Result<T, E>;
