//! Host SDK for the motion card.
//!
//! Open a card by URI, take its axes, move them, read their status, wait for the card's
//! interrupts:
//!
//! ```no_run
//! use motioncard_sdk::{Card, MoveLimits};
//! use std::time::Duration;
//!
//! let card = Card::open("sim")?;                 // or emu:NAME, uio:/dev/uio0, pci:0000:03:00.0
//! let x = card.axis(0)?;
//! x.enable()?;
//! let mv = x.move_absolute(10_000.0, &MoveLimits::new(50_000.0, 1e6, 5e7))?;
//! let reached = mv.wait(Duration::from_secs(5))?;  // motion done: in position
//! println!("at {reached} counts, status {:?}", x.status()?.state);
//! # Ok::<(), motioncard_sdk::Error>(())
//! ```
//!
//! Every command is validated here first (NaN, non-positive limits, unknown axes get their
//! own [`ErrorKind`]) and again by the firmware, which answers each with exactly one ack or
//! nack. Waits block in `poll()` on the card's interrupt file descriptor, never in sleep loops.
#![deny(unsafe_op_in_unsafe_fn)]
#![warn(missing_docs)]

mod analog;
mod axis;
mod cam;
mod card;
mod cardset;
mod comp;
mod config;
mod device;
mod error;
mod fit;
mod freq;
mod gantry;
pub mod gcode;
mod group;
mod handwheel;
mod heartbeat;
mod homing;
mod io;
mod limits;
mod list;
mod lock;
mod modes;
mod nurbs;
mod path;
mod pvt;
#[cfg(feature = "emulator")]
mod replay;
pub mod report;
mod safety;
mod scope;
mod segment;
mod servo;
mod session;
mod setpath;
mod sync;
pub mod trace;

pub use analog::{
    AnalogInput, AnalogInputSettings, Pso, PsoOutput, PsoState, PsoStatus, ADC_LSB, ANALOG_INPUTS,
    ANALOG_OUTPUTS, ANALOG_RANGE, PSO_PWM_HZ_MAX,
};
pub use axis::MoveDirection;
pub use cam::CamSettings;
#[cfg(feature = "emulator")]
pub use card::Sim;
pub use card::{
    Axis, AxisSettings, Card, CardEvent, CardInfo, Motion, MoveLimits, Outcome, Status,
    ACK_TIMEOUT, EVENT_QUEUE_CAP, SCALE_RANGE,
};
#[cfg(feature = "emulator")]
pub use card_emu::{
    AnalogSource, Clock, EmuOptions, EndStops, FireRecord, HomeSwitch, IndexPulse, MotorParams,
    Noise, Sensor, Switches,
};
pub use cardset::{
    BusRole, BusState, BusStatus, CardSet, SyncScope, TimedCommands, Timing, TimingScope,
};
pub use comp::{CompPoint, Compensation, COMP_POINTS_MAX};
pub use config::{
    AccDecName, AnalogInputSection, AxisSafetySection, AxisSection, BiquadName, BiquadSection,
    CardSection, Config, ConfigDifference, FfpivSection, FilterName, FilterSection, GantrySection,
    GroupSection, HomingSection, InterpolatorName, IoSection, LoadReport, PathSection,
    PdPlusSection, PidffSection, PsoOutputName, PsoSection, SafetySection, ServoLaw, CONFIG_HEADER,
    ECHO_CHARS, MAX_CONFIG_BYTES,
};
#[cfg(feature = "emulator")]
pub use device::SimOptions;
pub use device::{sim_watchdog_from_env, SIM_WATCHDOG_ENV};
pub use error::{nack_reason, Error, ErrorKind, Result, Target};
pub use firmware_proto::{
    AxisState, EventKind, Faults, GroupState, GroupStatus, Io, MotionFlags, NackCode, StopCategory,
    StopReason, AXIS_QUEUE_LEN, OVERRIDE_MAX,
};
pub use firmware_proto::{Edge, ScopeMode, ScopeSample, ScopeState, Source, SCOPE_CHANNELS};
pub use firmware_proto::{
    GearRatio, PvtEvent, SyncEvent, AUX_ENCODERS, CAM_MAX_POINTS, CAM_TABLES, PVT_LEN,
};
pub use freq::{
    find_resonances, sweep_duration, sweep_frequencies, Bode, FreqMode, FreqPoint, FreqProgress,
    FreqResponse, FreqSweep, Phasor, Resonance, FREQ_POINTS_MAX, PEAK_DB,
};
pub use gantry::{
    Gantry, GantryConfig, GantryHoming, GantryPhase, GantrySide, GantryStatus, GANTRIES_MAX,
};
pub use group::{
    AccDec, ArcSpec, FeedType, FilterKind, FilterSettings, Group, GroupHoming, GroupMotion,
    GroupSettings, Interpolator, MoveOptions, NormalArc, PathLimits, Plane,
};
pub use handwheel::{Handwheel, HANDWHEEL_DETENT_MAX, HANDWHEEL_RATIO_MAX};
pub use heartbeat::HEARTBEAT_PERIOD_US;
pub use homing::{HomingError, HomingFlags, HomingSettings};
pub use io::{
    CompareChannel, CompareStatus, Direction, IoSettings, IoState, ProbeStatus, ProbeTrigger,
    TouchProbe, COMPARE_CHANNELS, COMPARE_FIRED, COMPARE_LOW_WATER, COMPARE_MISSED,
    COMPARE_TABLE_LEN, INPUTS, PROBE_CHANNELS,
};
pub use list::{CardListing, ListingError, SyncRole, SyncState, PCI_IDS, UIO_NAME};
pub use modes::{BufferMode, MoveKind, VelocityLimits};
#[cfg(feature = "emulator")]
pub use nurbs::die_bonder_plant;
pub use nurbs::{
    clamped_uniform_knots, die_bonder_pdplus, split_nurbs, Nurbs, NurbsError, NurbsFeed,
    PdPlusSettings, NURBS_MAX_CTRL, NURBS_MAX_DEGREE, NURBS_MAX_DIM, NURBS_MAX_KNOTS,
};
pub use path::{GroupPath, PathProgress, PathSettings, PathStreamer, PauseState, StreamError};
pub use pvt::{pvt_time_reason, PvtLimits, PvtMode, PvtPoint};
#[cfg(feature = "emulator")]
pub use replay::{replay, ReplayReport, TraceHeader, MAX_TICKS_PER_SECOND};
pub use safety::{
    CardSafetySettings, SafetySettings, SafetyStatus, StopInfo, WATCHDOG_TIMEOUT_DEFAULT,
};
pub use scope::{
    Capture, Scope, ScopeEvent, ScopeSettings, ScopeStatus, ScopeTrigger, Signal, SignalOwner,
    SCOPE_DIVIDER_MAX, SCOPE_PRETRIGGER_MAX, SCOPE_RING_LEN,
};
pub use segment::{Geometry, OutputAt, PathBuffer, PathItem, Segment, Transition};
pub use servo::{BiquadKind, BiquadSpec, PidffSettings, ServoFilter, BIQUADS};
pub use session::{STALE_MIN, STALE_TICKS};
pub use setpath::{PathPart, SetPath, SetPathProgress};
pub use sync::{gear_ratio, Master, SyncLimits};
pub use trace::TRACE_ENV;

/// The card's S-curve planner, and the time-optimal planner from any state
/// (`card_firmware::host::plan`), for previewing a move on the host (`mcctl plan`).
pub mod plan {
    pub use card_firmware::host::plan::*;
}

/// Raw protocol types, for tools and tests that talk to the card below the typed API.
pub mod proto {
    pub use firmware_proto::{
        move_flags, path_flags, raw, AxisStatus, Command, Event, Faults, Io, MoveFlags, Opcode,
        OUTPUTS, PATH_LEN,
    };
}
