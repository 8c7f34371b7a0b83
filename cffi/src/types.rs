//! The plain structs of the C ABI and their conversions from the SDK's types.
//!
//! Enumerations cross as `uint32_t` fields with `MC_` constants (a C enum holding a value the
//! library does not know would be undefined behaviour in C++). The constants that are the
//! card's codes are generated from the register map (`crate::codes`); those here are the C
//! ABI's own (the emulated card's options, the feed types, `MC_GROUP_ACCDEC_BOTH`,
//! `MC_EVENT_CARD_WIDE`).

use crate::codes::{
    MC_ARC_BY_BORDER, MC_ARC_BY_CENTRE, MC_ARC_BY_RADIUS, MC_ARC_PLANE_XY, MC_ARC_PLANE_YZ,
    MC_ARC_PLANE_ZX, MC_FILTER_KIND_BELL, MC_FILTER_KIND_EXPONENTIAL, MC_FILTER_KIND_LINEAR,
    MC_FILTER_KIND_NONE, MC_GROUP_ACCDEC_POST, MC_GROUP_ACCDEC_PRE, MC_GROUP_INTERP_EXACT,
    MC_GROUP_INTERP_REFERENCE_WORD, MC_GROUP_MAX_AXES, MC_STOP_CATEGORY_0, MC_STOP_CATEGORY_1,
    MC_STOP_CATEGORY_2,
};
use crate::result::{unknown, Failure};
use motioncard_sdk::ErrorKind;
#[cfg(feature = "emulator")]
use motioncard_sdk::{die_bonder_plant, Clock, EmuOptions, SimOptions};
use motioncard_sdk::{
    AccDec, ArcSpec, CardEvent, CardInfo, FeedType, FilterKind, FilterSettings, GroupSettings,
    GroupState, GroupStatus, Interpolator, MoveLimits, MoveOptions, NurbsFeed, PathLimits, Plane,
    SafetySettings, SafetyStatus, Status, StopCategory, StopInfo,
};

/// `mc_event.axis` of an event about the whole card.
pub const MC_EVENT_CARD_WIDE: u32 = 0xFFFF;

/// What the card says about itself (`mc_card_info`).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[allow(non_camel_case_types)]
pub struct mc_card_info {
    /// Firmware version, `major << 16 | minor << 8 | patch`.
    pub firmware_version: u32,
    /// DPRAM layout major version.
    pub layout_major: u16,
    /// DPRAM layout minor version.
    pub layout_minor: u16,
    /// Axes on the card (axis numbers 0 .. axes-1).
    pub axes: u32,
    /// Servo rate, Hz.
    pub servo_rate_hz: u32,
    /// `MC_CARD_CAP_` bits.
    pub capabilities: u32,
}

impl From<CardInfo> for mc_card_info {
    fn from(i: CardInfo) -> Self {
        Self {
            firmware_version: i.firmware_version,
            layout_major: i.layout.0,
            layout_minor: i.layout.1,
            axes: i.axes as u32,
            servo_rate_hz: i.servo_rate_hz,
            capabilities: i.capabilities,
        }
    }
}

/// Limits of a point-to-point move, in user units (see `mc_set_scale`). Every value must be
/// finite and greater than zero.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[allow(non_camel_case_types)]
pub struct mc_move_limits {
    /// Maximum velocity.
    pub velocity: f64,
    /// Maximum acceleration.
    pub acceleration: f64,
    /// Maximum deceleration.
    pub deceleration: f64,
    /// Jerk of the seven-segment phases 1, 3 (acceleration) and 5, 7 (deceleration).
    pub jerk: [f64; 4],
}

impl From<mc_move_limits> for MoveLimits {
    fn from(l: mc_move_limits) -> Self {
        MoveLimits {
            velocity: l.velocity,
            acceleration: l.acceleration,
            deceleration: l.deceleration,
            jerk: l.jerk,
        }
    }
}

impl From<MoveLimits> for mc_move_limits {
    fn from(l: MoveLimits) -> Self {
        Self {
            velocity: l.velocity,
            acceleration: l.acceleration,
            deceleration: l.deceleration,
            jerk: l.jerk,
        }
    }
}

/// Servo gains and in-position windows of an axis (counts, seconds, volts): the card's
/// `mc_axis_config` register block, the same struct as in the register map. Start from
/// `mc_axis_settings_default`; `mc_configure` selects FFPIV whatever `servo_law` holds.
#[allow(non_camel_case_types)]
pub type mc_axis_settings = firmware_proto::raw::mc_axis_config;

/// Everything the card publishes about an axis, in counts and seconds (no scale applied): the
/// card's `mc_axis_status_payload`, the same struct as in the register map (`state` is an
/// `MC_AXIS_STATE_` value, `faults` `MC_AXIS_FAULT_` bits, `stop_reason` an
/// `MC_STOP_REASON_` value, `io` `MC_IO_` bits; `checksum` is 0: the library checked it).
#[allow(non_camel_case_types)]
pub type mc_raw_status = firmware_proto::raw::mc_axis_status_payload;

/// A consistent snapshot of an axis's status, in user units (see `mc_set_scale`), with
/// everything the card published in counts in `raw`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[allow(non_camel_case_types)]
pub struct mc_status {
    /// `MC_AXIS_STATE_` value.
    pub state: u32,
    /// `MC_AXIS_FAULT_` bits.
    pub faults: u32,
    /// Commanded position.
    pub command_position: f64,
    /// Commanded velocity.
    pub command_velocity: f64,
    /// Commanded acceleration.
    pub command_acceleration: f64,
    /// Actual position.
    pub actual_position: f64,
    /// Actual velocity.
    pub actual_velocity: f64,
    /// Following error (commanded − actual).
    pub following_error: f64,
    /// DAC output, volts.
    pub dac_volts: f64,
    /// The same snapshot in counts, with the card's per-move statistics.
    pub raw: mc_raw_status,
    /// Why the last motion ended (`MC_STOP_REASON_` value; a newer card may report one this
    /// library has no constant for).
    pub stop_reason: u32,
    /// The axis's limit switch, home, amplifier alarm, encoder fault and e-stop inputs and its
    /// drive-enable output (`MC_IO_` bits).
    pub io: u32,
}

impl From<&Status> for mc_status {
    fn from(s: &Status) -> Self {
        let r = &s.raw;
        Self {
            state: s.state as u32,
            faults: s.faults.bits(),
            command_position: s.command_position,
            command_velocity: s.command_velocity,
            command_acceleration: s.command_acceleration,
            actual_position: s.actual_position,
            actual_velocity: s.actual_velocity,
            following_error: s.following_error,
            dac_volts: s.dac_volts,
            raw: *r,
            stop_reason: s.stop_reason().map_or(r.stop_reason, |r| r as u32),
            io: s.io().bits(),
        }
    }
}

/// An event from the card, in user units.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[allow(non_camel_case_types)]
pub struct mc_event {
    /// `MC_EVENT_` value.
    pub kind: u32,
    /// Axis, or `MC_EVENT_CARD_WIDE`.
    pub axis: u32,
    /// Seq of the command it concerns (motion events: the command that started the motion;
    /// compare with `mc_motion.seq`).
    pub seq: u32,
    /// Kind-specific code.
    pub code: i32,
    /// Servo tick at which the card raised it.
    pub tick: u64,
    /// Kind-specific value (positions in user units).
    pub value: f64,
}

impl From<&CardEvent> for mc_event {
    fn from(e: &CardEvent) -> Self {
        Self {
            kind: e.kind as u32,
            axis: e.axis as u32,
            seq: e.seq,
            code: e.code,
            tick: e.tick,
            value: e.value,
        }
    }
}

/// A motion started by `mc_move_absolute`, `mc_move_relative`, `mc_halt` or `mc_stop`; wait for
/// it with `mc_motion_wait`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[allow(non_camel_case_types)]
pub struct mc_motion {
    /// The axis.
    pub axis: u32,
    /// The seq of the command that started it (events about it carry the same seq).
    pub seq: u32,
}

/// Clock of an emulated card (`mc_sim_options.clock`): paced to the servo rate in real time,
/// as `mc_open("sim")`.
pub const MC_SIM_CLOCK_REAL_TIME: u32 = 0;
/// As fast as the host can compute the ticks. The card's watchdog counts card time, which then
/// runs far ahead of the library's heartbeat: raise the timeout (`mc_set_watchdog_timeout`) and
/// clear a trip (`mc_reset_faults`) before enabling axes.
pub const MC_SIM_CLOCK_FREE_RUNNING: u32 = 1;
/// Time advances only in `mc_sim_step` and in waits (as `mc_open_sim_stepped`).
pub const MC_SIM_CLOCK_STEPPED: u32 = 2;

/// Plant of an emulated card (`mc_sim_options.plant`): the default servo motor on every axis.
pub const MC_SIM_PLANT_DEFAULT: u32 = 0;
/// Yeh's die bonder (Table 1): its X plant on axis 0, its Y plant on the other axes. Pair it
/// with `mc_pdplus_settings_die_bonder` and a 1000 Hz servo rate, as in the paper.
pub const MC_SIM_PLANT_DIE_BONDER: u32 = 1;

/// How `mc_open_sim` builds an emulated card. Start from `mc_sim_options_default`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[allow(non_camel_case_types)]
pub struct mc_sim_options {
    /// `MC_SIM_CLOCK_` value.
    pub clock: u32,
    /// Axes, 1..8.
    pub axes: u32,
    /// Servo rate, 1000..20000 Hz.
    pub servo_rate_hz: u32,
    /// `MC_SIM_PLANT_` value.
    pub plant: u32,
}

/// The `MC_SIM_CLOCK_` value of a clock.
#[cfg(feature = "emulator")]
pub(crate) fn clock_code(c: Clock) -> u32 {
    match c {
        Clock::RealTime => MC_SIM_CLOCK_REAL_TIME,
        Clock::FreeRunning => MC_SIM_CLOCK_FREE_RUNNING,
        Clock::Stepped => MC_SIM_CLOCK_STEPPED,
    }
}

#[cfg(feature = "emulator")]
impl mc_sim_options {
    /// The SDK's options; the axes and servo rate are checked by `Card::open_sim`.
    pub(crate) fn to_sdk(self) -> Result<SimOptions, Failure> {
        let clock = match self.clock {
            MC_SIM_CLOCK_REAL_TIME => Clock::RealTime,
            MC_SIM_CLOCK_FREE_RUNNING => Clock::FreeRunning,
            MC_SIM_CLOCK_STEPPED => Clock::Stepped,
            v => return Err(unknown("clock", v)),
        };
        let mut emu = EmuOptions::new(self.axes as usize, self.servo_rate_hz);
        match self.plant {
            MC_SIM_PLANT_DEFAULT => {}
            MC_SIM_PLANT_DIE_BONDER => {
                for (i, m) in emu.motors.iter_mut().enumerate() {
                    *m = die_bonder_plant(i.min(1));
                }
            }
            v => return Err(unknown("plant", v)),
        }
        Ok(SimOptions { clock, emu })
    }
}

#[cfg(feature = "emulator")]
impl From<SimOptions> for mc_sim_options {
    /// The clock, axes and rate of the SDK's options (the plant as `MC_SIM_PLANT_DEFAULT`).
    fn from(o: SimOptions) -> Self {
        Self {
            clock: clock_code(o.clock),
            axes: o.emu.axes as u32,
            servo_rate_hz: o.emu.servo_rate_hz,
            plant: MC_SIM_PLANT_DEFAULT,
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Axes groups, filters, PD+, NURBS
// ---------------------------------------------------------------------------------------------

/// Most axes in a group, as a length.
const MAX_AXES: usize = MC_GROUP_MAX_AXES as usize;

/// Acc/dec mode (`mc_group_settings.accdec`), besides `MC_GROUP_ACCDEC_PRE` and
/// `MC_GROUP_ACCDEC_POST`: both, the S-curve, then the filters.
pub const MC_GROUP_ACCDEC_BOTH: u32 = MC_GROUP_ACCDEC_PRE | MC_GROUP_ACCDEC_POST;

/// Feed type (`mc_move_options.feed_type`), which selects each axis's acc/dec filter: cutting
/// feed (G01/G02/G03). 0, so a zeroed `mc_move_options` is the default.
pub const MC_FEED_TYPE_CUTTING: u32 = 0;
/// Rapid traverse (G00).
pub const MC_FEED_TYPE_RAPID: u32 = 1;
/// Jog.
pub const MC_FEED_TYPE_JOG: u32 = 2;

/// A group's configuration (`mc_group_configure`). Start from `mc_group_settings_new`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[allow(non_camel_case_types)]
pub struct mc_group_settings {
    /// Card axes of the group's X, Y, Z, … axes; the first `naxes` are used.
    pub axes: [u32; 8],
    /// Axes in the group, 1..8.
    pub naxes: u32,
    /// `MC_GROUP_ACCDEC_` value.
    pub accdec: u32,
    /// `MC_GROUP_INTERP_` value.
    pub interpolator: u32,
    /// Geometry tolerance (centre equidistance, radius against chord), in user units of the
    /// group's first axis.
    pub tolerance: f64,
}

impl mc_group_settings {
    pub(crate) fn to_sdk(self) -> Result<GroupSettings, Failure> {
        let n = self.naxes as usize;
        if n == 0 || n > MAX_AXES {
            return Err(Failure::new(
                ErrorKind::BadAxis.code(),
                format!("naxes = {n}: a group has 1 to {MAX_AXES} axes"),
            ));
        }
        let axes: Vec<usize> = self.axes[..n].iter().map(|&a| a as usize).collect();
        let accdec = match self.accdec {
            MC_GROUP_ACCDEC_PRE => AccDec::Pre,
            MC_GROUP_ACCDEC_POST => AccDec::Post,
            MC_GROUP_ACCDEC_BOTH => AccDec::Both,
            v => return Err(unknown("acc/dec mode", v)),
        };
        let interpolator = match self.interpolator {
            MC_GROUP_INTERP_EXACT => Interpolator::Exact,
            MC_GROUP_INTERP_REFERENCE_WORD => Interpolator::ReferenceWord,
            v => return Err(unknown("interpolator", v)),
        };
        Ok(GroupSettings {
            axes,
            accdec,
            interpolator,
            tolerance: self.tolerance,
        })
    }
}

impl From<&GroupSettings> for mc_group_settings {
    /// The SDK's settings of at most 8 axes.
    fn from(s: &GroupSettings) -> Self {
        let mut axes = [0u32; 8];
        for (d, a) in axes.iter_mut().zip(&s.axes) {
            *d = *a as u32;
        }
        Self {
            axes,
            naxes: s.axes.len().min(MAX_AXES) as u32,
            accdec: match s.accdec {
                AccDec::Pre => MC_GROUP_ACCDEC_PRE,
                AccDec::Post => MC_GROUP_ACCDEC_POST,
                AccDec::Both => MC_GROUP_ACCDEC_BOTH,
            },
            interpolator: match s.interpolator {
                Interpolator::Exact => MC_GROUP_INTERP_EXACT,
                Interpolator::ReferenceWord => MC_GROUP_INTERP_REFERENCE_WORD,
            },
            tolerance: s.tolerance,
        }
    }
}

/// Limits of the tangential feed of a group move, in user units of the group's first axis.
/// Every value must be finite and greater than zero.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[allow(non_camel_case_types)]
pub struct mc_path_limits {
    /// Feed (path velocity).
    pub velocity: f64,
    /// Tangential acceleration.
    pub acceleration: f64,
    /// Tangential deceleration.
    pub deceleration: f64,
    /// Tangential jerk.
    pub jerk: f64,
}

impl From<mc_path_limits> for PathLimits {
    fn from(l: mc_path_limits) -> Self {
        PathLimits {
            velocity: l.velocity,
            acceleration: l.acceleration,
            deceleration: l.deceleration,
            jerk: l.jerk,
        }
    }
}

impl From<PathLimits> for mc_path_limits {
    fn from(l: PathLimits) -> Self {
        Self {
            velocity: l.velocity,
            acceleration: l.acceleration,
            deceleration: l.deceleration,
            jerk: l.jerk,
        }
    }
}

/// How a group move is queued. All zero (`{0}`) is the default: absolute targets, the group
/// must be at rest, cutting feed.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[allow(non_camel_case_types)]
pub struct mc_move_options {
    /// Non-zero: targets relative to where the previous move ends.
    pub relative: u32,
    /// Non-zero: queue behind the moves already queued (PLCopen Buffered); else the group
    /// must be at rest.
    pub buffered: u32,
    /// `MC_FEED_TYPE_` value.
    pub feed_type: u32,
}

impl mc_move_options {
    pub(crate) fn to_sdk(self) -> Result<MoveOptions, Failure> {
        Ok(MoveOptions {
            relative: self.relative != 0,
            buffered: self.buffered != 0,
            feed_type: match self.feed_type {
                MC_FEED_TYPE_CUTTING => FeedType::Cutting,
                MC_FEED_TYPE_RAPID => FeedType::Rapid,
                MC_FEED_TYPE_JOG => FeedType::Jog,
                v => return Err(unknown("feed type", v)),
            },
        })
    }
}

/// An arc in the coordinates of its plane (user units): the end point, and per `mode`
/// (`MC_ARC_BY_`) the centre, the radius (`aux[0]`) or a point on the arc.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[allow(non_camel_case_types)]
pub struct mc_arc {
    /// `MC_ARC_BY_` value.
    pub mode: u32,
    /// Non-zero: counter-clockwise; zero: clockwise (ignored by `MC_ARC_BY_BORDER`).
    pub ccw: u32,
    /// End point.
    pub end: [f64; 2],
    /// The centre (`MC_ARC_BY_CENTRE`), the radius in `aux[0]` (`MC_ARC_BY_RADIUS`), or a
    /// point on the arc (`MC_ARC_BY_BORDER`).
    pub aux: [f64; 2],
}

impl mc_arc {
    pub(crate) fn to_sdk(self) -> Result<ArcSpec, Failure> {
        let ccw = self.ccw != 0;
        Ok(match self.mode {
            MC_ARC_BY_CENTRE => ArcSpec::Centre {
                end: self.end,
                centre: self.aux,
                ccw,
            },
            MC_ARC_BY_RADIUS => ArcSpec::Radius {
                end: self.end,
                radius: self.aux[0],
                ccw,
            },
            MC_ARC_BY_BORDER => ArcSpec::Border {
                end: self.end,
                via: self.aux,
            },
            v => return Err(unknown("arc mode", v)),
        })
    }
}

/// The plane of an `MC_ARC_PLANE_` value.
pub(crate) fn plane_of(v: u32) -> Result<Plane, Failure> {
    match v {
        MC_ARC_PLANE_XY => Ok(Plane::XY),
        MC_ARC_PLANE_YZ => Ok(Plane::YZ),
        MC_ARC_PLANE_ZX => Ok(Plane::ZX),
        v => Err(unknown("plane", v)),
    }
}

/// A group move started by `mc_group_move_linear`, `_ptp`, `_circular`, `_nurbs`,
/// `mc_group_halt` or `mc_group_stop`; wait for it with `mc_group_motion_wait`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[allow(non_camel_case_types)]
pub struct mc_group_motion {
    /// The group.
    pub group: u32,
    /// The seq of the command that started it (`MC_EVENT_GROUP_` events carry the same seq).
    pub seq: u32,
}

/// A consistent snapshot of a group's status. Path quantities are in counts of the group's
/// first axis (no scale applied), as the card publishes them.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[allow(non_camel_case_types)]
pub struct mc_group_status {
    /// `MC_GROUP_STATE_` value.
    pub state: u32,
    /// Moves waiting in the queue.
    pub queued: u32,
    /// Seq of the move being interpolated (0: none).
    pub active_seq: u32,
    /// Group moves started since boot.
    pub move_count: u32,
    /// Distance along the active move, counts.
    pub path_pos: f64,
    /// Length of the active move, counts.
    pub path_len: f64,
    /// Tangential velocity before the filters, counts/s.
    pub feed: f64,
    /// Tangential acceleration before the filters, counts/s².
    pub feed_acc: f64,
    /// Servo tick of this snapshot.
    pub tick: u64,
    /// At the group's last coming to rest, the largest |programmed end − commanded position|
    /// over its axes: the correction its snap to the end made, counts (what the interpolation
    /// and the filters lost, plus the rounding of the sums).
    pub snap_last: f64,
    /// The largest `snap_last` since the group was enabled, counts.
    pub snap_max: f64,
    /// Segments in the group's path buffer not finished yet (`mc_group_path_push`).
    pub path_queued: u32,
    /// Free segments in the path buffer (`MC_PATH_SEGMENTS` - `path_queued`).
    pub path_free: u32,
    /// Id of the segment running (valid while `path_flags` has `MC_PATH_STATUS_RUNNING`).
    pub path_id: u32,
    /// `MC_PATH_STATUS_` bits.
    pub path_flags: u32,
    /// Path segments ended since the group was enabled (wrapping).
    pub path_done: u32,
}

impl From<(GroupState, GroupStatus)> for mc_group_status {
    fn from((state, s): (GroupState, GroupStatus)) -> Self {
        Self {
            state: state as u32,
            queued: s.queued,
            active_seq: s.active_seq,
            move_count: s.move_count,
            path_pos: s.path_pos,
            path_len: s.path_len,
            feed: s.feed,
            feed_acc: s.feed_acc,
            tick: s.tick,
            snap_last: s.snap_last,
            snap_max: s.snap_max,
            path_queued: s.path_queued,
            path_free: s.path_free,
            path_id: s.path_id,
            path_flags: s.path_flags,
            path_done: s.path_done,
        }
    }
}

/// One acc/dec filter: kind and time constant.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[allow(non_camel_case_types)]
pub struct mc_filter {
    /// `MC_FILTER_KIND_` value.
    pub kind: u32,
    /// Time constant, s.
    pub tau: f64,
}

/// An axis's post-interpolation acc/dec filters, one per feed type.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[allow(non_camel_case_types)]
pub struct mc_filter_settings {
    /// Rapid traverse (`MC_FEED_TYPE_RAPID`).
    pub rapid: mc_filter,
    /// Cutting feed (`MC_FEED_TYPE_CUTTING`).
    pub cutting: mc_filter,
    /// Jog (`MC_FEED_TYPE_JOG`).
    pub jog: mc_filter,
}

pub(crate) fn filter_kind(v: u32) -> Result<FilterKind, Failure> {
    match v {
        MC_FILTER_KIND_NONE => Ok(FilterKind::None),
        MC_FILTER_KIND_LINEAR => Ok(FilterKind::Linear),
        MC_FILTER_KIND_EXPONENTIAL => Ok(FilterKind::Exponential),
        MC_FILTER_KIND_BELL => Ok(FilterKind::Bell),
        v => Err(unknown("filter kind", v)),
    }
}

fn filter_code(k: FilterKind) -> u32 {
    match k {
        FilterKind::None => MC_FILTER_KIND_NONE,
        FilterKind::Linear => MC_FILTER_KIND_LINEAR,
        FilterKind::Exponential => MC_FILTER_KIND_EXPONENTIAL,
        FilterKind::Bell => MC_FILTER_KIND_BELL,
    }
}

impl mc_filter_settings {
    pub(crate) fn to_sdk(self) -> Result<FilterSettings, Failure> {
        let f = |c: mc_filter| Ok::<_, Failure>((filter_kind(c.kind)?, c.tau));
        Ok(FilterSettings {
            rapid: f(self.rapid)?,
            cutting: f(self.cutting)?,
            jog: f(self.jog)?,
        })
    }
}

impl From<FilterSettings> for mc_filter_settings {
    fn from(s: FilterSettings) -> Self {
        let f = |(kind, tau): (FilterKind, f64)| mc_filter {
            kind: filter_code(kind),
            tau,
        };
        Self {
            rapid: f(s.rapid),
            cutting: f(s.cutting),
            jog: f(s.jog),
        }
    }
}

/// The PD+ servo law of an axis (Yeh eq 2.12) and its drive model (Yeh eq 2.2), in counts,
/// seconds and volts: the card's `mc_axis_pdplus` register block, the same struct as in the
/// register map (`gains`: `u = kp·e + kd·ė + kv·v_ref + ka·a_ref`; `drive`: `dw/dt = −w/tau +
/// (kc/tau)·u`, `dθ/dt = ke·w`; `umax`, at most the axis's `dac_limit_v`).
#[allow(non_camel_case_types)]
pub type mc_pdplus_settings = firmware_proto::raw::mc_axis_pdplus;

/// How a NURBS curve is followed, in user units of the group's first axis.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[allow(non_camel_case_types)]
pub struct mc_nurbs_feed {
    /// Feed along the curve.
    pub feed: f64,
    /// Tangential acceleration limit.
    pub accel: f64,
    /// Tangential jerk limit.
    pub jerk: f64,
    /// Chord error tolerance (the feed is lowered where the curvature needs it), in the user
    /// units of the group's first axis; 0: the default, one encoder count (1 µm on a 1 µm/count
    /// scale).
    pub chord_tolerance: f64,
    /// Saturation-aware feed (Yeh §3.4): the fraction of each axis's PD+ `umax` the look-ahead
    /// may plan with, in (0, 1]; needs PD+ on every group axis (`MC_ERR_INCOMPATIBLE_MODE`
    /// otherwise). 0: not saturation-aware.
    pub saturation_budget: f64,
}

/// One NURBS curve of a path (`mc_group_move_nurbs_path`), described as the arguments of
/// `mc_group_move_nurbs`: `n_ctrl` control points of `dim` values in `ctrl`, `n_ctrl` weights,
/// `n_knots` knots. The arrays are read during the call only.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
#[allow(non_camel_case_types)]
pub struct mc_nurbs_curve {
    /// Degree, 1..5.
    pub degree: u32,
    /// Dimension: the group's axis count.
    pub dim: u32,
    /// `n_ctrl * dim` doubles, point after point, in group axis order and user units.
    pub ctrl: *const f64,
    /// Control points.
    pub n_ctrl: usize,
    /// `n_ctrl` weights, finite and positive.
    pub weights: *const f64,
    /// `n_knots` knots, clamped and non-decreasing.
    pub knots: *const f64,
    /// `n_ctrl + degree + 1`.
    pub n_knots: usize,
}

impl Default for mc_nurbs_curve {
    /// No curve: NULL arrays, zero counts.
    fn default() -> Self {
        Self {
            degree: 0,
            dim: 0,
            ctrl: std::ptr::null(),
            n_ctrl: 0,
            weights: std::ptr::null(),
            knots: std::ptr::null(),
            n_knots: 0,
        }
    }
}

impl From<NurbsFeed> for mc_nurbs_feed {
    fn from(f: NurbsFeed) -> Self {
        Self {
            feed: f.feed,
            accel: f.accel,
            jerk: f.jerk,
            chord_tolerance: f.chord_tolerance.unwrap_or(0.0),
            saturation_budget: f.saturation.unwrap_or(0.0),
        }
    }
}

impl From<mc_nurbs_feed> for NurbsFeed {
    fn from(f: mc_nurbs_feed) -> Self {
        NurbsFeed {
            feed: f.feed,
            accel: f.accel,
            jerk: f.jerk,
            chord_tolerance: (f.chord_tolerance != 0.0).then_some(f.chord_tolerance),
            saturation: (f.saturation_budget != 0.0).then_some(f.saturation_budget),
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Safety
// ---------------------------------------------------------------------------------------------

/// The stop category of an `MC_STOP_CATEGORY_` value; any other value is
/// `MC_ERR_BAD_CATEGORY`, the code the card gives for one.
pub(crate) fn stop_category(v: u32) -> Result<StopCategory, Failure> {
    match v {
        MC_STOP_CATEGORY_0 => Ok(StopCategory::Cat0),
        MC_STOP_CATEGORY_1 => Ok(StopCategory::Cat1),
        MC_STOP_CATEGORY_2 => Ok(StopCategory::Cat2),
        v => Err(Failure::new(
            ErrorKind::BadCategory.code(),
            format!("unknown stop category {v}: expected MC_STOP_CATEGORY_0, _1 or _2"),
        )),
    }
}

/// The card-wide safety state (`mc_get_safety_status`). Flags are 0 or 1.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[allow(non_camel_case_types)]
pub struct mc_safety_status {
    /// The host watchdog tripped; latched until `mc_reset_faults`.
    pub watchdog_tripped: u32,
    /// The host's e-stop (`mc_estop`) is latched.
    pub estop_command: u32,
    /// The e-stop input tripped; latched until reset with the input released.
    pub estop_input: u32,
    /// The watchdog is watching: a session is attached (armed by its open, disarmed by its
    /// close). Outside a session the card takes no motion (`MC_ERR_NO_SESSION`).
    pub watchdog_armed: u32,
    /// Servo tick at which the card last saw the heartbeat change.
    pub last_heartbeat_tick: u64,
    /// Servo tick of the last watchdog trip (0: never).
    pub watchdog_trip_tick: u64,
    /// The tick of the last heartbeat the card saw before that trip.
    pub trip_heartbeat_tick: u64,
    /// Protocol errors (corrupt ring indices) the card detected since boot.
    pub protocol_errors: u32,
    /// The session id of the program attached to the card (this one's while it is open).
    pub session: u32,
    /// Programs that opened the card while another's session was still open, since boot (each
    /// stopped the motion the vanished program left).
    pub host_changes: u32,
    /// Heartbeats that came later than the declared period after the one before, since this
    /// program opened the card: how close it runs to its watchdog.
    pub late_heartbeats: u32,
    /// The longest gap between two heartbeats the card saw since this program opened it, µs.
    pub max_heartbeat_gap_us: u32,
    /// Servo tick of the last open (this program's, while it is open).
    pub attach_tick: u64,
}

impl From<SafetyStatus> for mc_safety_status {
    fn from(s: SafetyStatus) -> Self {
        Self {
            watchdog_tripped: s.watchdog_tripped.into(),
            estop_command: s.estop_command.into(),
            estop_input: s.estop_input.into(),
            watchdog_armed: s.watchdog_armed.into(),
            last_heartbeat_tick: s.last_heartbeat_tick,
            watchdog_trip_tick: s.watchdog_trip_tick,
            trip_heartbeat_tick: s.trip_heartbeat_tick,
            protocol_errors: s.protocol_errors,
            session: s.session,
            host_changes: s.host_changes,
            late_heartbeats: s.late_heartbeats,
            max_heartbeat_gap_us: u32::try_from(s.max_heartbeat_gap.as_micros())
                .unwrap_or(u32::MAX),
            attach_tick: s.attach_tick,
        }
    }
}

/// An axis's safety configuration (`mc_configure_safety`), in user units (see `mc_set_scale`).
/// Start from `mc_safety_settings_default`. Flags: non-zero is on.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[allow(non_camel_case_types)]
pub struct mc_safety_settings {
    /// Enforce `soft_limit_neg` .. `soft_limit_pos` (off by default).
    pub soft_limits: u32,
    /// Honour the limit switch inputs.
    pub hard_limits: u32,
    /// Honour the amplifier alarm input.
    pub amp_alarm: u32,
    /// Honour encoder loss and jumps.
    pub encoder_checks: u32,
    /// The stop a hard or soft limit makes (`MC_STOP_CATEGORY_`).
    pub limit_stop: u32,
    /// Negative soft limit (used when `soft_limits` is on; 0 in the defaults).
    pub soft_limit_neg: f64,
    /// Positive soft limit (used when `soft_limits` is on; 0 in the defaults).
    pub soft_limit_pos: f64,
    /// Following-error limit at `max_velocity` (LinuxCNC FERROR); the limit at velocity v is
    /// `max(ferror * |v| / max_velocity, min_ferror)`.
    pub ferror: f64,
    /// Following-error limit at rest (LinuxCNC MIN_FERROR).
    pub min_ferror: f64,
    /// The velocity `ferror` applies at.
    pub max_velocity: f64,
    /// Deceleration of category 1 and 2 stops.
    pub stop_deceleration: f64,
    /// Jerk of those stops.
    pub stop_jerk: f64,
    /// Fastest physically possible encoder velocity: a larger change in one tick is a fault.
    pub encoder_max_velocity: f64,
}

impl mc_safety_settings {
    pub(crate) fn to_sdk(self) -> Result<SafetySettings, Failure> {
        Ok(SafetySettings {
            soft_limits: (self.soft_limits != 0)
                .then_some((self.soft_limit_neg, self.soft_limit_pos)),
            hard_limits: self.hard_limits != 0,
            amp_alarm: self.amp_alarm != 0,
            encoder_checks: self.encoder_checks != 0,
            limit_stop: stop_category(self.limit_stop)?,
            ferror: self.ferror,
            min_ferror: self.min_ferror,
            max_velocity: self.max_velocity,
            stop_deceleration: self.stop_deceleration,
            stop_jerk: self.stop_jerk,
            encoder_max_velocity: self.encoder_max_velocity,
        })
    }
}

impl From<SafetySettings> for mc_safety_settings {
    fn from(s: SafetySettings) -> Self {
        let (neg, pos) = s.soft_limits.unwrap_or((0.0, 0.0));
        Self {
            soft_limits: s.soft_limits.is_some().into(),
            hard_limits: s.hard_limits.into(),
            amp_alarm: s.amp_alarm.into(),
            encoder_checks: s.encoder_checks.into(),
            limit_stop: s.limit_stop as u32,
            soft_limit_neg: neg,
            soft_limit_pos: pos,
            ferror: s.ferror,
            min_ferror: s.min_ferror,
            max_velocity: s.max_velocity,
            stop_deceleration: s.stop_deceleration,
            stop_jerk: s.stop_jerk,
            encoder_max_velocity: s.encoder_max_velocity,
        }
    }
}

/// How an axis's last safety stop went, measured by the card (`mc_get_stop_info`).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[allow(non_camel_case_types)]
pub struct mc_stop_info {
    /// Why the last motion ended (`MC_STOP_REASON_` value).
    pub reason: u32,
    /// 1 when the axis has come to rest after its last safety stop (`rest_tick` is valid), 0
    /// while it is still stopping or when there was none.
    pub at_rest: u32,
    /// Servo tick at which the last safety stop began (0: none since boot).
    pub stop_tick: u64,
    /// Servo tick at which the axis came to rest after it (0 while still stopping).
    pub rest_tick: u64,
    /// Planned duration of the stop's deceleration ramp, s (0 for category 0).
    pub ramp_time: f64,
}

impl From<StopInfo> for mc_stop_info {
    fn from(i: StopInfo) -> Self {
        Self {
            reason: i.reason as u32,
            at_rest: i.rest_tick.is_some().into(),
            stop_tick: i.stop_tick,
            rest_tick: i.rest_tick.unwrap_or(0),
            ramp_time: i.ramp_time.as_secs_f64(),
        }
    }
}

#[cfg(test)]
mod axis_tests {
    use super::*;

    #[test]
    fn limits_and_settings_round_trip() {
        let l = MoveLimits::new(1.0, 2.0, 3.0)
            .deceleration(4.0)
            .decel_jerk(5.0);
        assert_eq!(MoveLimits::from(mc_move_limits::from(l)), l);
    }
}

#[cfg(all(test, feature = "emulator"))]
mod sim_tests {
    use super::*;
    use motioncard_sdk::ErrorKind;

    #[test]
    fn sim_options_round_trip_and_unknown_values_are_refused() {
        let d = mc_sim_options::from(SimOptions::default());
        assert_eq!(
            d,
            mc_sim_options {
                clock: MC_SIM_CLOCK_REAL_TIME,
                axes: 8,
                servo_rate_hz: 10_000,
                plant: MC_SIM_PLANT_DEFAULT
            }
        );
        assert_eq!(d.to_sdk().unwrap(), SimOptions::default());
        for c in [Clock::RealTime, Clock::FreeRunning, Clock::Stepped] {
            let o = mc_sim_options {
                clock: clock_code(c),
                ..d
            };
            assert_eq!(o.to_sdk().unwrap().clock, c);
        }
        let bonder = mc_sim_options {
            plant: MC_SIM_PLANT_DIE_BONDER,
            axes: 3,
            ..d
        }
        .to_sdk()
        .unwrap();
        assert_eq!(bonder.emu.motors[0], die_bonder_plant(0));
        assert_eq!(bonder.emu.motors[1], die_bonder_plant(1));
        assert_eq!(bonder.emu.motors[7], die_bonder_plant(1));
        for bad in [
            mc_sim_options { clock: 3, ..d },
            mc_sim_options { plant: 2, ..d },
        ] {
            assert_eq!(
                bad.to_sdk().unwrap_err().code,
                ErrorKind::BadConfig.code(),
                "{bad:?}"
            );
        }
    }
}

#[cfg(test)]
mod group_tests {
    use super::*;
    use motioncard_sdk::proto::raw;

    #[test]
    fn both_is_pre_and_post() {
        assert_eq!(
            MC_GROUP_ACCDEC_BOTH,
            raw::MC_ACCDEC_PRE | raw::MC_ACCDEC_POST
        );
    }

    #[test]
    fn group_types_round_trip_and_unknown_values_are_refused() {
        let s = GroupSettings {
            accdec: AccDec::Both,
            interpolator: Interpolator::ReferenceWord,
            ..GroupSettings::new(&[3, 1, 2])
        };
        let c = mc_group_settings::from(&s);
        assert_eq!(c.naxes, 3);
        assert_eq!(c.to_sdk().unwrap(), s);
        for (field, v) in [(0, 0), (0, 4), (1, 2)] {
            let mut bad = c;
            match field {
                0 => bad.accdec = v,
                _ => bad.interpolator = v,
            }
            assert_eq!(
                bad.to_sdk().unwrap_err().code,
                ErrorKind::BadConfig.code(),
                "{bad:?}"
            );
        }
        for n in [0, 9, u32::MAX] {
            let bad = mc_group_settings { naxes: n, ..c };
            assert_eq!(
                bad.to_sdk().unwrap_err().code,
                ErrorKind::BadAxis.code(),
                "naxes {n}"
            );
        }

        for f in [
            FilterSettings::shin_table1(),
            FilterSettings::shin_table1_z(),
        ] {
            assert_eq!(mc_filter_settings::from(f).to_sdk().unwrap(), f);
        }
        let mut f = mc_filter_settings::from(FilterSettings::shin_table1());
        f.jog.kind = 4;
        assert_eq!(f.to_sdk().unwrap_err().code, ErrorKind::BadConfig.code());

        // A zeroed mc_move_options is the SDK's default.
        assert_eq!(
            mc_move_options::default().to_sdk().unwrap(),
            MoveOptions::default()
        );
        let o = mc_move_options {
            relative: 7,
            buffered: 1,
            feed_type: MC_FEED_TYPE_JOG,
        };
        assert_eq!(
            o.to_sdk().unwrap(),
            MoveOptions {
                relative: true,
                buffered: true,
                feed_type: FeedType::Jog
            }
        );
        let bad = mc_move_options { feed_type: 3, ..o };
        assert_eq!(bad.to_sdk().unwrap_err().code, ErrorKind::BadConfig.code());

        let arc = |mode| mc_arc {
            mode,
            ccw: 1,
            end: [1.0, 2.0],
            aux: [3.0, 4.0],
        };
        assert_eq!(
            arc(MC_ARC_BY_CENTRE).to_sdk().unwrap(),
            ArcSpec::Centre {
                end: [1.0, 2.0],
                centre: [3.0, 4.0],
                ccw: true
            }
        );
        assert_eq!(
            arc(MC_ARC_BY_RADIUS).to_sdk().unwrap(),
            ArcSpec::Radius {
                end: [1.0, 2.0],
                radius: 3.0,
                ccw: true
            }
        );
        assert_eq!(
            arc(MC_ARC_BY_BORDER).to_sdk().unwrap(),
            ArcSpec::Border {
                end: [1.0, 2.0],
                via: [3.0, 4.0]
            }
        );
        assert_eq!(
            arc(3).to_sdk().unwrap_err().code,
            ErrorKind::BadConfig.code()
        );
        assert_eq!(plane_of(MC_ARC_PLANE_ZX).unwrap(), Plane::ZX);
        assert_eq!(plane_of(3).unwrap_err().code, ErrorKind::BadConfig.code());

        let feed = mc_nurbs_feed {
            feed: 1.0,
            accel: 2.0,
            jerk: 3.0,
            chord_tolerance: 4.0,
            saturation_budget: 0.0,
        };
        assert_eq!(NurbsFeed::from(feed).saturation, None);
        assert_eq!(NurbsFeed::from(feed).chord_tolerance, Some(4.0));
        let default_chord = mc_nurbs_feed {
            chord_tolerance: 0.0,
            ..feed
        };
        assert_eq!(NurbsFeed::from(default_chord).chord_tolerance, None);
        let aware = mc_nurbs_feed {
            saturation_budget: 0.8,
            ..feed
        };
        assert_eq!(NurbsFeed::from(aware).saturation, Some(0.8));
        for f in [
            NurbsFeed::new(1.0, 2.0, 3.0),
            NurbsFeed {
                saturation: Some(0.5),
                ..NurbsFeed::new(1.0, 2.0, 3.0)
            },
        ] {
            assert_eq!(NurbsFeed::from(mc_nurbs_feed::from(f)), f);
        }
    }
}

#[cfg(test)]
mod safety_tests {
    use super::*;
    use crate::codes::MC_STOP_REASON_SOFT_LIMIT_NEG;
    use motioncard_sdk::StopReason;

    #[test]
    fn stop_categories_round_trip() {
        for c in StopCategory::ALL {
            assert_eq!(stop_category(*c as u32).unwrap(), *c);
        }
    }

    #[test]
    fn safety_types_round_trip_and_unknown_categories_are_refused() {
        let d = SafetySettings::default();
        let c = mc_safety_settings::from(d);
        assert_eq!((c.soft_limits, c.hard_limits), (0, 1));
        assert_eq!(c.to_sdk().unwrap(), d);
        let s = SafetySettings {
            soft_limits: Some((-5.0, 7.0)),
            hard_limits: false,
            amp_alarm: false,
            encoder_checks: false,
            limit_stop: StopCategory::Cat2,
            ..d
        };
        let c = mc_safety_settings::from(s);
        assert_eq!(c.limit_stop, MC_STOP_CATEGORY_2);
        assert_eq!(c.to_sdk().unwrap(), s);
        // Any non-zero flag is on.
        let on = mc_safety_settings {
            hard_limits: 7,
            soft_limits: 0xFFFF_FFFF,
            ..c
        }
        .to_sdk()
        .unwrap();
        assert!(on.hard_limits && on.soft_limits == Some((-5.0, 7.0)));
        for v in [3, 4, u32::MAX] {
            let bad = mc_safety_settings { limit_stop: v, ..c };
            assert_eq!(
                bad.to_sdk().unwrap_err().code,
                ErrorKind::BadCategory.code(),
                "{v}"
            );
            assert_eq!(
                stop_category(v).unwrap_err().code,
                ErrorKind::BadCategory.code()
            );
        }
        let info = mc_stop_info::from(StopInfo {
            reason: StopReason::SoftLimitNeg,
            stop_tick: 10,
            rest_tick: None,
            ramp_time: std::time::Duration::from_millis(20),
        });
        assert_eq!(
            info,
            mc_stop_info {
                reason: MC_STOP_REASON_SOFT_LIMIT_NEG,
                at_rest: 0,
                stop_tick: 10,
                rest_tick: 0,
                ramp_time: 0.02
            }
        );
    }
}
