//! Card configuration files (layout 1.8): every setting the card holds, in TOML.
//!
//! [`Card::save_config`] writes what the card holds, read back from the card
//! (`MC_OP_READ_CONFIG`), never the SDK's memory; [`Card::load_config`] checks a whole file
//! first, with the card's own checks (`card_emu::firmware::config` and the functions beside
//! each block's type), and applies nothing if any value is wrong: the error names the key
//! (`axis.2.ffpiv.kp`) and its line. Then it applies the sections that differ from what the
//! card holds, reads the card back and compares. [`Card::diff_config`] lists, key by key, where
//! a file and the card differ.
//!
//! The file is in the card's units (counts, seconds, volts, Hz, µs), with the names of the
//! register map's fields (`mc_dpram.h`) and of the SDK's settings:
//!
//! ```toml
//! [card]            # servo_rate_hz
//! [safety]          # watchdog_timeout_us, estop_input_category, max_stop_time_us
//! [io]              # polarity, rise_events, fall_events (bit i: input i), debounce (ticks)
//! [axis.N]          # scale, servo_law ("ffpiv" | "pdplus"), dac_limit_v, windows, jog limits
//! [axis.N.ffpiv]    # kp, ki, kv, kvff, kaff, vel_filter_hz
//! [axis.N.pdplus]   # kp, kd, kv, ka, kc, tau, ke, umax: only with servo_law = "pdplus"
//! [axis.N.filter]   # rapid_kind, rapid_tau, cutting_kind, cutting_tau, jog_kind, jog_tau
//! [axis.N.safety]   # soft/hard limits, alarm and encoder checks, following error, stop ramp
//! [axis.N.homing]   # method, index, move_to_home, velocities, limits
//! [group.N]         # axes, accdec, interpolator, tolerance: all four, or none (not configured)
//! [group.N.path]    # lookahead, low_water, accel, jerk, vmax, amax, jmax (one per group axis),
//!                   # plan_period (may be left out: 0, the card's default)
//! ```
//!
//! A file may name any subset of the sections and of the axes and groups: what it does not
//! name is left as the card holds it. Within a section every key is needed (but
//! `plan_period`, which files saved before it existed lack); an unknown key, a
//! value of the wrong type, an axis or group the card does not have, or a value the card would
//! refuse is an error. `save` writes every section, in a fixed order, each float in Rust's
//! shortest representation that reads back to the same bits: load, then save, gives the same
//! bytes.
//!
//! A group configuration cannot be removed (the card has no command for it): a configured
//! group the file leaves unconfigured stays configured.

use crate::card::{Card, SCALE_RANGE};
use crate::error::{nack_reason, Error, Result};
use card_firmware::host::validate_path_config;
use card_firmware::host::AxisSafetyConfig;
use card_firmware::host::HomingConfig;
use card_firmware::host::IoConfig;
use card_firmware::host::SafetyConfig;
use card_firmware::host::{decode_axis_filter, validate_axis_config, validate_group_config};
use firmware_proto::Mem as _;
use firmware_proto::{
    layout, raw, AxisConfig, AxisPdPlus, AxisState, ConfigKind, GroupState, NackCode, INPUTS,
    MAX_AXES, MAX_GROUPS,
};
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// The first lines of a saved file.
pub const CONFIG_HEADER: &str = "# motioncard card configuration (layout 1.8): what the card holds, in counts, seconds,\n# volts, Hz and microseconds. Written by `mcctl config save`; `mcctl config load` checks\n# all of it before it applies any.\n\n";

/// A card's configuration: every setting the card holds (see the module doc).
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Config {
    /// The servo rate.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub card: Option<CardSection>,
    /// The card-wide safety settings.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub safety: Option<SafetySection>,
    /// The digital inputs.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub io: Option<IoSection>,
    /// Axes by number (`"0"`…).
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub axis: BTreeMap<String, AxisSection>,
    /// Groups by number (`"0"`…).
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub group: BTreeMap<String, GroupSection>,
}

/// `[card]`: `mc_card_config`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CardSection {
    /// Servo rate, Hz.
    pub servo_rate_hz: u32,
}

/// `[safety]`: `mc_safety_config`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SafetySection {
    /// Watchdog timeout, µs.
    pub watchdog_timeout_us: u32,
    /// The stop category of the e-stop input (0, 1, 2).
    pub estop_input_category: u32,
    /// Maximum stop time, µs.
    pub max_stop_time_us: u32,
}

/// `[io]`: `mc_io_config`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct IoSection {
    /// Bit i: input i is active low.
    pub polarity: u32,
    /// Bit i: an event when input i becomes active.
    pub rise_events: u32,
    /// Bit i: an event when input i becomes inactive.
    pub fall_events: u32,
    /// Ticks each input must hold a new level (one per input).
    pub debounce: Vec<u16>,
}

/// A servo law.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ServoLaw {
    /// FFPIV (Thinh Fig 5).
    Ffpiv,
    /// PD+ (Yeh eq 2.12) with `[axis.N.pdplus]`.
    Pdplus,
}

/// `[axis.N]`: `mc_axis_config` (with the scale), and the axis's other blocks below it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AxisSection {
    /// Counts per user unit (kept by the card for hosts).
    pub scale: f64,
    /// The servo law.
    pub servo_law: ServoLaw,
    /// Output clamp, V.
    pub dac_limit_v: f64,
    /// In-position window, counts.
    pub in_pos_window: f64,
    /// In-velocity window, counts/s.
    pub in_vel_window: f64,
    /// Settle time, s.
    pub settle_time: f64,
    /// Largest jog velocity, counts/s.
    pub jog_max_vel: f64,
    /// Jog acceleration, counts/s².
    pub jog_accel: f64,
    /// Jog jerk, counts/s³.
    pub jog_jerk: f64,
    /// The FFPIV gains (`mc_ffpiv_gains`).
    pub ffpiv: FfpivSection,
    /// The PD+ law (`mc_axis_pdplus`): present exactly when `servo_law` is `pdplus`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pdplus: Option<PdPlusSection>,
    /// The acc/dec filters (`mc_axis_filter`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub filter: Option<FilterSection>,
    /// The axis's safety (`mc_axis_safety`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub safety: Option<AxisSafetySection>,
    /// Homing (`mc_axis_homing`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub homing: Option<HomingSection>,
}

/// `[axis.N.ffpiv]`: the FFPIV gains (`mc_ffpiv_gains`, Thinh Fig 5).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FfpivSection {
    /// Position gain K_P, 1/s.
    pub kp: f64,
    /// Velocity-loop integral gain K_I, 1/s.
    pub ki: f64,
    /// Velocity-loop gain K_V, V per count/s.
    pub kv: f64,
    /// Velocity feed-forward K_VFF, 0..2.
    pub kvff: f64,
    /// Acceleration feed-forward K_AFF, V per count/s².
    pub kaff: f64,
    /// Cut-off of the measured velocity's filter, Hz.
    pub vel_filter_hz: f64,
}

impl From<&firmware_proto::FfpivGains> for FfpivSection {
    fn from(g: &firmware_proto::FfpivGains) -> Self {
        Self {
            kp: g.kp,
            ki: g.ki,
            kv: g.kv,
            kvff: g.kvff,
            kaff: g.kaff,
            vel_filter_hz: g.vel_filter_hz,
        }
    }
}

impl FfpivSection {
    /// The card's block of these gains.
    pub fn gains(&self) -> firmware_proto::FfpivGains {
        firmware_proto::FfpivGains {
            kp: self.kp,
            ki: self.ki,
            kv: self.kv,
            kvff: self.kvff,
            kaff: self.kaff,
            vel_filter_hz: self.vel_filter_hz,
        }
    }
}

/// `[axis.N.pdplus]`: the PD+ gains (Yeh eq 2.12), the drive model (eq 2.2) and the drive
/// limit (`mc_axis_pdplus`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PdPlusSection {
    /// V/count.
    pub kp: f64,
    /// V per count/s.
    pub kd: f64,
    /// V per count/s of reference velocity.
    pub kv: f64,
    /// V per count/s² of reference acceleration.
    pub ka: f64,
    /// Drive model K_c, (rad/s)/V.
    pub kc: f64,
    /// Drive model τ, s.
    pub tau: f64,
    /// Drive model K_e, counts/rad.
    pub ke: f64,
    /// Drive limit, V.
    pub umax: f64,
}

impl From<&AxisPdPlus> for PdPlusSection {
    fn from(p: &AxisPdPlus) -> Self {
        Self {
            kp: p.gains.kp,
            kd: p.gains.kd,
            kv: p.gains.kv,
            ka: p.gains.ka,
            kc: p.drive.kc,
            tau: p.drive.tau,
            ke: p.drive.ke,
            umax: p.umax,
        }
    }
}

impl PdPlusSection {
    /// `base` with these gains, drive model and limit (the rest of the block as in `base`).
    pub fn onto(&self, base: AxisPdPlus) -> AxisPdPlus {
        let mut s = base;
        s.gains.kp = self.kp;
        s.gains.kd = self.kd;
        s.gains.kv = self.kv;
        s.gains.ka = self.ka;
        s.drive.kc = self.kc;
        s.drive.tau = self.tau;
        s.drive.ke = self.ke;
        s.umax = self.umax;
        s
    }
}

/// A filter kind.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
#[allow(missing_docs)]
pub enum FilterName {
    None,
    Linear,
    Exponential,
    Bell,
}

/// `[axis.N.filter]`: kind and time constant (s) per feed type.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
#[allow(missing_docs)]
pub struct FilterSection {
    pub rapid_kind: FilterName,
    pub rapid_tau: f64,
    pub cutting_kind: FilterName,
    pub cutting_tau: f64,
    pub jog_kind: FilterName,
    pub jog_tau: f64,
}

/// `[axis.N.safety]`, in counts and seconds.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
#[allow(missing_docs)]
pub struct AxisSafetySection {
    pub soft_limits: bool,
    pub hard_limits: bool,
    pub amp_alarm: bool,
    pub encoder_checks: bool,
    /// The stop category of a limit (0, 1, 2).
    pub limit_stop: u32,
    pub soft_limit_neg: f64,
    pub soft_limit_pos: f64,
    pub ferror: f64,
    pub min_ferror: f64,
    pub max_velocity: f64,
    pub stop_deceleration: f64,
    pub stop_jerk: f64,
    pub encoder_max_velocity: f64,
}

/// `[axis.N.homing]`, in counts and seconds.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
#[allow(missing_docs)]
pub struct HomingSection {
    /// The CiA 402 method.
    pub method: i32,
    /// The encoder has an index channel.
    pub index: bool,
    /// End at the home point.
    pub move_to_home: bool,
    pub search_vel: f64,
    pub creep_vel: f64,
    pub accel: f64,
    pub jerk: f64,
    pub home_offset: f64,
    pub timeout: f64,
    pub max_distance: f64,
    pub index_distance: f64,
    pub hard_stop_ferror: f64,
    pub hard_stop_dwell: f64,
}

/// A group's acc/dec mode.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
#[allow(missing_docs)]
pub enum AccDecName {
    Pre,
    Post,
    Both,
}

/// A group's arc interpolator.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
#[allow(missing_docs)]
pub enum InterpolatorName {
    Exact,
    ReferenceWord,
}

/// `[group.N]`: `mc_group_config` (all four keys, or none: not configured) and the path.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GroupSection {
    /// Card axes of the group's axes.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub axes: Option<Vec<u8>>,
    /// Acc/dec mode.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub accdec: Option<AccDecName>,
    /// Arc interpolator.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub interpolator: Option<InterpolatorName>,
    /// Geometry tolerance, counts.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tolerance: Option<f64>,
    /// The continuous path (`mc_group_path`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub path: Option<PathSection>,
}

/// `[group.N.path]`: the arrays hold one value per group axis slot (8).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
#[allow(missing_docs)]
pub struct PathSection {
    pub lookahead: u32,
    pub low_water: u32,
    pub accel: f64,
    pub jerk: f64,
    pub vmax: Vec<f64>,
    pub amax: Vec<f64>,
    pub jmax: Vec<f64>,
    /// The planner's period, s (0, or absent from a file: the card's default).
    #[serde(default)]
    pub plan_period: f64,
}

/// One key where a file and the card differ ([`Card::diff_config`]).
#[derive(Debug, Clone, PartialEq)]
pub struct ConfigDifference {
    /// The key, dotted (`axis.0.ffpiv.kp`).
    pub key: String,
    /// Its value in the file, as TOML.
    pub file: String,
    /// What the card holds, as TOML (`None`: the card has no such value, e.g. a group it
    /// holds unconfigured).
    pub card: Option<String>,
}

// ----- blocks <-> sections ---------------------------------------------------------------

fn filter_name(k: u32) -> FilterName {
    match k {
        raw::MC_FILTER_LINEAR => FilterName::Linear,
        raw::MC_FILTER_EXPONENTIAL => FilterName::Exponential,
        raw::MC_FILTER_BELL => FilterName::Bell,
        _ => FilterName::None,
    }
}

fn filter_raw(k: FilterName) -> u32 {
    match k {
        FilterName::None => raw::MC_FILTER_NONE,
        FilterName::Linear => raw::MC_FILTER_LINEAR,
        FilterName::Exponential => raw::MC_FILTER_EXPONENTIAL,
        FilterName::Bell => raw::MC_FILTER_BELL,
    }
}

impl AxisSection {
    fn from_blocks(
        c: &AxisConfig,
        pd: &AxisPdPlus,
        f: &raw::mc_axis_filter,
        s: &raw::mc_axis_safety,
        h: &raw::mc_axis_homing,
    ) -> Self {
        let g = &c.ffpiv;
        let pdplus = c.servo_law == raw::MC_SERVO_PDPLUS;
        let flag = |bits: u32, b: u32| bits & b != 0;
        Self {
            scale: c.scale,
            servo_law: if pdplus {
                ServoLaw::Pdplus
            } else {
                ServoLaw::Ffpiv
            },
            dac_limit_v: c.dac_limit_v,
            in_pos_window: c.in_pos_window,
            in_vel_window: c.in_vel_window,
            settle_time: c.settle_time,
            jog_max_vel: c.jog_max_vel,
            jog_accel: c.jog_accel,
            jog_jerk: c.jog_jerk,
            ffpiv: FfpivSection::from(g),
            pdplus: pdplus.then(|| PdPlusSection::from(pd)),
            filter: Some(FilterSection {
                rapid_kind: filter_name(f.kind[0]),
                rapid_tau: f.tau[0],
                cutting_kind: filter_name(f.kind[1]),
                cutting_tau: f.tau[1],
                jog_kind: filter_name(f.kind[2]),
                jog_tau: f.tau[2],
            }),
            safety: Some(AxisSafetySection {
                soft_limits: flag(s.flags, raw::MC_AXSAFE_SOFT_LIMITS),
                hard_limits: flag(s.flags, raw::MC_AXSAFE_HARD_LIMITS),
                amp_alarm: flag(s.flags, raw::MC_AXSAFE_AMP_ALARM),
                encoder_checks: flag(s.flags, raw::MC_AXSAFE_ENCODER),
                limit_stop: s.limit_category,
                soft_limit_neg: s.soft_limit_neg,
                soft_limit_pos: s.soft_limit_pos,
                ferror: s.ferror,
                min_ferror: s.min_ferror,
                max_velocity: s.max_velocity,
                stop_deceleration: s.stop_decel,
                stop_jerk: s.stop_jerk,
                encoder_max_velocity: s.encoder_max_velocity,
            }),
            homing: Some(HomingSection {
                method: h.method,
                index: flag(h.flags, raw::MC_HOMING_INDEX),
                move_to_home: flag(h.flags, raw::MC_HOMING_MOVE_TO_HOME),
                search_vel: h.search_vel,
                creep_vel: h.creep_vel,
                accel: h.accel,
                jerk: h.jerk,
                home_offset: h.home_offset,
                timeout: h.timeout,
                max_distance: h.max_distance,
                index_distance: h.index_distance,
                hard_stop_ferror: h.hard_stop_ferror,
                hard_stop_dwell: h.hard_stop_dwell,
            }),
        }
    }

    /// The axis configuration block and the PD+ block (zero without PD+).
    fn servo_blocks(&self) -> (AxisConfig, AxisPdPlus) {
        let cfg = AxisConfig {
            servo_law: match self.servo_law {
                ServoLaw::Ffpiv => raw::MC_SERVO_FFPIV,
                ServoLaw::Pdplus => raw::MC_SERVO_PDPLUS,
            },
            ffpiv: self.ffpiv.gains(),
            dac_limit_v: self.dac_limit_v,
            in_pos_window: self.in_pos_window,
            in_vel_window: self.in_vel_window,
            settle_time: self.settle_time,
            jog_max_vel: self.jog_max_vel,
            jog_accel: self.jog_accel,
            jog_jerk: self.jog_jerk,
            scale: self.scale,
            ..AxisConfig::default()
        };
        let pd = card_firmware::host::pdplus_block(None);
        (cfg, self.pdplus.map_or(pd, |p| p.onto(pd)))
    }
}

impl FilterSection {
    fn block(&self) -> raw::mc_axis_filter {
        raw::mc_axis_filter {
            kind: [
                filter_raw(self.rapid_kind),
                filter_raw(self.cutting_kind),
                filter_raw(self.jog_kind),
            ],
            tau: [self.rapid_tau, self.cutting_tau, self.jog_tau],
            ..Default::default()
        }
    }
}

impl AxisSafetySection {
    fn block(&self) -> raw::mc_axis_safety {
        let bit = |on: bool, b: u32| if on { b } else { 0 };
        raw::mc_axis_safety {
            flags: bit(self.soft_limits, raw::MC_AXSAFE_SOFT_LIMITS)
                | bit(self.hard_limits, raw::MC_AXSAFE_HARD_LIMITS)
                | bit(self.amp_alarm, raw::MC_AXSAFE_AMP_ALARM)
                | bit(self.encoder_checks, raw::MC_AXSAFE_ENCODER),
            limit_category: self.limit_stop,
            soft_limit_neg: self.soft_limit_neg,
            soft_limit_pos: self.soft_limit_pos,
            ferror: self.ferror,
            min_ferror: self.min_ferror,
            max_velocity: self.max_velocity,
            stop_decel: self.stop_deceleration,
            stop_jerk: self.stop_jerk,
            encoder_max_velocity: self.encoder_max_velocity,
            ..Default::default()
        }
    }
}

impl HomingSection {
    fn block(&self) -> raw::mc_axis_homing {
        let bit = |on: bool, b: u32| if on { b } else { 0 };
        raw::mc_axis_homing {
            method: self.method,
            flags: bit(self.index, raw::MC_HOMING_INDEX)
                | bit(self.move_to_home, raw::MC_HOMING_MOVE_TO_HOME),
            search_vel: self.search_vel,
            creep_vel: self.creep_vel,
            accel: self.accel,
            jerk: self.jerk,
            home_offset: self.home_offset,
            timeout: self.timeout,
            max_distance: self.max_distance,
            index_distance: self.index_distance,
            hard_stop_ferror: self.hard_stop_ferror,
            hard_stop_dwell: self.hard_stop_dwell,
            _reserved: [0.0; 5],
        }
    }
}

impl GroupSection {
    fn from_blocks(c: &raw::mc_group_config, p: &raw::mc_group_path) -> Self {
        let n = c.naxes as usize;
        let configured = (1..=MAX_AXES).contains(&n);
        let pre = c.accdec & raw::MC_ACCDEC_PRE != 0;
        let post = c.accdec & raw::MC_ACCDEC_POST != 0;
        Self {
            axes: configured.then(|| c.axes[..n].to_vec()),
            accdec: configured.then_some(match (pre, post) {
                (true, true) => AccDecName::Both,
                (false, true) => AccDecName::Post,
                _ => AccDecName::Pre,
            }),
            interpolator: configured.then_some(
                if c.interpolator == raw::MC_INTERP_REFERENCE_WORD {
                    InterpolatorName::ReferenceWord
                } else {
                    InterpolatorName::Exact
                },
            ),
            tolerance: configured.then_some(c.tolerance),
            path: Some(PathSection {
                lookahead: p.lookahead,
                low_water: p.low_water,
                accel: p.accel,
                jerk: p.jerk,
                vmax: p.vmax.to_vec(),
                amax: p.amax.to_vec(),
                jmax: p.jmax.to_vec(),
                plan_period: p.plan_period,
            }),
        }
    }

    /// The group configuration block, if the section configures the group (all four keys).
    fn config_block(&self) -> Option<raw::mc_group_config> {
        let (Some(axes), Some(accdec), Some(interp), Some(tol)) =
            (&self.axes, self.accdec, self.interpolator, self.tolerance)
        else {
            return None;
        };
        let mut b = raw::mc_group_config {
            naxes: axes.len() as u32,
            accdec: match accdec {
                AccDecName::Pre => raw::MC_ACCDEC_PRE,
                AccDecName::Post => raw::MC_ACCDEC_POST,
                AccDecName::Both => raw::MC_ACCDEC_PRE | raw::MC_ACCDEC_POST,
            },
            interpolator: match interp {
                InterpolatorName::Exact => raw::MC_INTERP_EXACT,
                InterpolatorName::ReferenceWord => raw::MC_INTERP_REFERENCE_WORD,
            },
            tolerance: tol,
            ..Default::default()
        };
        for (d, &a) in b.axes.iter_mut().zip(axes) {
            *d = a;
        }
        Some(b)
    }
}

impl PathSection {
    /// The block (the arrays' lengths are checked before).
    fn block(&self) -> raw::mc_group_path {
        let arr = |v: &[f64]| {
            let mut a = [0.0; MAX_AXES];
            for (d, x) in a.iter_mut().zip(v) {
                *d = *x;
            }
            a
        };
        raw::mc_group_path {
            lookahead: self.lookahead,
            low_water: self.low_water,
            accel: self.accel,
            jerk: self.jerk,
            vmax: arr(&self.vmax),
            amax: arr(&self.amax),
            jmax: arr(&self.jmax),
            plan_period: self.plan_period,
            _reserved: [0.0; 5],
        }
    }
}

impl IoSection {
    fn block(&self) -> raw::mc_io_config {
        let mut b = raw::mc_io_config {
            polarity: self.polarity,
            rise_events: self.rise_events,
            fall_events: self.fall_events,
            ..Default::default()
        };
        for (d, x) in b.debounce.iter_mut().zip(&self.debounce) {
            *d = *x;
        }
        b
    }
}

impl SafetySection {
    fn block(&self) -> raw::mc_safety_config {
        raw::mc_safety_config {
            watchdog_timeout_us: self.watchdog_timeout_us,
            estop_input_category: self.estop_input_category,
            max_stop_time_us: self.max_stop_time_us,
            ..Default::default()
        }
    }
}

// ----- text ------------------------------------------------------------------------------

impl Config {
    /// The file's text: [`CONFIG_HEADER`], then every section in a fixed order.
    pub fn to_toml(&self) -> String {
        let body = toml::to_string(self).expect("a configuration always serializes");
        format!("{CONFIG_HEADER}{body}")
    }

    /// Parse a file's text (`origin` names it in errors). Only the syntax and the types are
    /// checked here; [`Card::load_config`] checks the values against a card.
    pub fn parse(text: &str, origin: &str) -> Result<Config> {
        if text.len() > MAX_CONFIG_BYTES {
            return Err(too_big(origin, &format!("{} bytes", text.len())));
        }
        let doc = toml::de::DeTable::parse(text).map_err(|e| {
            let line = e.span().map_or(0, |s| line_of(text, s.start));
            file_error(origin, String::new(), line, e.message().to_string())
        })?;
        toml::from_str::<Config>(text).map_err(|e| {
            let (key, line) = match e.span() {
                Some(s) => (key_at(doc.get_ref(), s.start), line_of(text, s.start)),
                None => (String::new(), 0),
            };
            file_error(origin, key, line, e.message().trim().to_string())
        })
    }
}

/// The largest configuration file read or parsed, in bytes. The largest file
/// [`Card::save_config`] can write (8 axes with every section, PD+ included, 8 groups with
/// their path settings, every number at its longest) is under 32 KiB; a quarter of a MiB
/// leaves room for comments. Parsing takes about 100 times a file's size in memory: a larger
/// file is refused before it is read.
pub const MAX_CONFIG_BYTES: usize = 256 * 1024;

/// Text from a file (a value, a key) is echoed in an error up to this many characters, then
/// cut with an ellipsis.
pub const ECHO_CHARS: usize = 60;

fn too_big(origin: &str, size: &str) -> Error {
    file_error(
        origin,
        String::new(),
        0,
        format!(
            "{size} is more than a configuration file may hold ({MAX_CONFIG_BYTES} bytes: the \
             largest `config save` writes is under 32 KiB); nothing was parsed"
        ),
    )
}

fn read_file(path: &std::path::Path) -> Result<String> {
    use std::io::Read as _;
    let cannot = |e| Error::io(format!("{}: cannot read", path.display()), e);
    let origin = path.display().to_string();
    let f = std::fs::File::open(path).map_err(cannot)?;
    let meta = f.metadata().map_err(cannot)?;
    if meta.is_file() && meta.len() > MAX_CONFIG_BYTES as u64 {
        return Err(too_big(&origin, &format!("{} bytes", meta.len())));
    }
    // A pipe or a device says no size: read no more than the limit and one byte.
    let mut text = String::new();
    f.take(MAX_CONFIG_BYTES as u64 + 1)
        .read_to_string(&mut text)
        .map_err(cannot)?;
    if text.len() > MAX_CONFIG_BYTES {
        return Err(too_big(
            &origin,
            &format!("more than {MAX_CONFIG_BYTES} bytes"),
        ));
    }
    Ok(text)
}

/// `s` with every quoted run (between `"` or `` ` ``, `\` escaping) or, for a key, every
/// dotted part longer than [`ECHO_CHARS`] characters cut to that many and an ellipsis; and
/// the whole cut to eight times that.
fn cut_echoes(s: &str, quoted: bool) -> String {
    let mut out = String::new();
    let mut kept = 0usize;
    let (mut run, mut inside, mut escaped) = (0usize, false, false);
    for c in s.chars() {
        let delimiter = if quoted {
            (c == '"' || c == '`') && !escaped
        } else {
            c == '.'
        };
        escaped = quoted && inside && c == '\\' && !escaped;
        let keep = if delimiter {
            inside = quoted && !inside;
            run = 0;
            Some(c)
        } else if quoted && !inside {
            Some(c)
        } else {
            run += 1;
            match run {
                r if r <= ECHO_CHARS => Some(c),
                r if r == ECHO_CHARS + 1 => Some('…'),
                _ => None,
            }
        };
        if let Some(c) = keep {
            if kept == 8 * ECHO_CHARS {
                out.push('…');
                break;
            }
            out.push(c);
            kept += 1;
        }
    }
    out
}

fn file_error(origin: &str, key: String, line: usize, message: String) -> Error {
    Error::ConfigFile {
        path: origin.to_string(),
        key: cut_echoes(&key, false),
        line,
        message: cut_echoes(&message, true),
    }
}

fn line_of(text: &str, offset: usize) -> usize {
    text.as_bytes()[..offset.min(text.len())]
        .iter()
        .filter(|&&b| b == b'\n')
        .count()
        + 1
}

/// The dotted key whose key or value holds byte `at` (the deepest one).
fn key_at(t: &toml::de::DeTable<'_>, at: usize) -> String {
    fn walk(v: &toml::de::DeValue<'_>, at: usize, path: &mut Vec<String>) {
        match v {
            toml::de::DeValue::Table(t) => {
                for (k, v) in t.iter() {
                    let (ks, vs) = (k.span(), v.span());
                    if ks.contains(&at) || vs.contains(&at) || contains_deep(v.get_ref(), at) {
                        path.push(k.get_ref().to_string());
                        walk(v.get_ref(), at, path);
                        return;
                    }
                }
            }
            toml::de::DeValue::Array(a) => {
                for (i, v) in a.iter().enumerate() {
                    if v.span().contains(&at) {
                        path.push(i.to_string());
                        walk(v.get_ref(), at, path);
                        return;
                    }
                }
            }
            _ => {}
        }
    }
    fn contains_deep(v: &toml::de::DeValue<'_>, at: usize) -> bool {
        match v {
            toml::de::DeValue::Table(t) => t.iter().any(|(k, v)| {
                k.span().contains(&at) || v.span().contains(&at) || contains_deep(v.get_ref(), at)
            }),
            _ => false,
        }
    }
    let mut path = Vec::new();
    walk(&toml::de::DeValue::Table(t.clone()), at, &mut path);
    path.join(".")
}

/// The line of a dotted key in the text (its deepest part the text has; 0: none).
fn line_of_key(text: &str, key: &str) -> usize {
    let Ok(doc) = toml::de::DeTable::parse(text) else {
        return 0;
    };
    let mut table = doc.get_ref();
    let mut line = 0;
    for part in key.split('.') {
        let Some((k, v)) = table.iter().find(|(k, _)| k.get_ref().as_ref() == part) else {
            break;
        };
        line = line_of(text, k.span().start);
        match v.get_ref() {
            toml::de::DeValue::Table(t) => table = t,
            toml::de::DeValue::Array(a) => {
                // An array's element: the line of the element named next, if any.
                if let Some(i) = key.rsplit('.').next().and_then(|i| i.parse::<usize>().ok()) {
                    if let Some(e) = a.get(i) {
                        line = line_of(text, e.span().start);
                    }
                }
                break;
            }
            _ => break,
        }
    }
    line
}

// ----- checks ----------------------------------------------------------------------------

/// A refusal of the checks: the key (dotted) and what is wrong.
type Refusal = (String, String);

fn nack_text(c: NackCode) -> String {
    format!("the card would refuse it: {} ({c:?})", nack_reason(c))
}

/// The first leaf of `bad` whose value taken from `good` makes `check` pass (relative dotted
/// path), or `None` when no single value does.
fn blame<S: Serialize + DeserializeOwned>(
    bad: &S,
    good: &S,
    check: impl Fn(&S) -> std::result::Result<(), NackCode>,
) -> Option<String> {
    let bad_v = toml::Value::try_from(bad).ok()?;
    let good_v = toml::Value::try_from(good).ok()?;
    let mut leaves = Vec::new();
    collect_leaves(&bad_v, &mut Vec::new(), &mut leaves);
    for path in leaves {
        let Some(g) = get_path(&good_v, &path) else {
            continue;
        };
        let mut v = bad_v.clone();
        if let Some(slot) = get_path_mut(&mut v, &path) {
            *slot = g.clone();
        }
        if let Ok(s) = v.try_into::<S>() {
            if check(&s).is_ok() {
                return Some(path.join("."));
            }
        }
    }
    None
}

fn collect_leaves(v: &toml::Value, at: &mut Vec<String>, out: &mut Vec<Vec<String>>) {
    match v {
        toml::Value::Table(t) => {
            for (k, v) in t {
                at.push(k.clone());
                collect_leaves(v, at, out);
                at.pop();
            }
        }
        toml::Value::Array(a) => {
            for (i, v) in a.iter().enumerate() {
                at.push(i.to_string());
                collect_leaves(v, at, out);
                at.pop();
            }
        }
        _ => out.push(at.clone()),
    }
}

fn get_path<'a>(v: &'a toml::Value, path: &[String]) -> Option<&'a toml::Value> {
    path.iter().try_fold(v, |v, p| match v {
        toml::Value::Table(t) => t.get(p),
        toml::Value::Array(a) => a.get(p.parse::<usize>().ok()?),
        _ => None,
    })
}

fn get_path_mut<'a>(v: &'a mut toml::Value, path: &[String]) -> Option<&'a mut toml::Value> {
    path.iter().try_fold(v, |v, p| match v {
        toml::Value::Table(t) => t.get_mut(p),
        toml::Value::Array(a) => a.get_mut(p.parse::<usize>().ok()?),
        _ => None,
    })
}

/// Run `check` on a section; on a refusal name the key (through [`blame`] against `good`).
fn refuse<S: Serialize + DeserializeOwned>(
    prefix: &str,
    bad: &S,
    good: &S,
    check: impl Fn(&S) -> std::result::Result<(), NackCode>,
) -> std::result::Result<(), Refusal> {
    let Err(code) = check(bad) else {
        return Ok(());
    };
    let key = match blame(bad, good, &check) {
        Some(k) => format!("{prefix}.{k}"),
        None => prefix.to_string(),
    };
    Err((key, nack_text(code)))
}

/// The number in a section's key: `"3"` (canonical decimal) below `count`.
fn index_key(kind: &str, key: &str, count: usize) -> std::result::Result<usize, Refusal> {
    match key.parse::<usize>() {
        Ok(i) if i.to_string() == key && i < count => Ok(i),
        _ => Err((
            format!("{kind}.{key}"),
            format!(
                "no such {kind}: the card has {count} ({kind}.0 to {kind}.{})",
                count - 1
            ),
        )),
    }
}

/// What the checks need to know of the card.
struct Context<'a> {
    num_axes: usize,
    host_period_us: u32,
    card: &'a Config,
    axis_states: Vec<AxisState>,
    group_states: Vec<GroupState>,
}

/// The reference values the blame takes: the card's reset values (PD+: the die bonder's).
fn good_axis() -> AxisSection {
    // The reset blocks, with the PD+ section of the die bonder (the check of an FFPIV axis
    // drops it).
    AxisSection::from_blocks(
        &AxisConfig {
            servo_law: raw::MC_SERVO_PDPLUS,
            ..AxisConfig::default()
        },
        &crate::nurbs::die_bonder_pdplus(0),
        &card_firmware::host::FilterConfig::default().to_block(),
        &AxisSafetyConfig::default().to_block(),
        &firmware_proto::AxisHoming::default(),
    )
}

fn check(file: &Config, cx: &Context<'_>) -> std::result::Result<(), Refusal> {
    let card = cx.card;
    // Card: the servo rate, with every axis disabled to change it.
    let rate = file
        .card
        .or(card.card)
        .map_or(firmware_proto::SERVO_RATE_MIN_HZ, |c| c.servo_rate_hz);
    if let Some(c) = &file.card {
        let range = firmware_proto::SERVO_RATE_MIN_HZ..=firmware_proto::SERVO_RATE_MAX_HZ;
        if !range.contains(&c.servo_rate_hz) {
            return Err((
                "card.servo_rate_hz".into(),
                format!(
                    "{} Hz: the servo rate must lie in {}..={} Hz",
                    c.servo_rate_hz,
                    range.start(),
                    range.end()
                ),
            ));
        }
        if Some(*c) != card.card && cx.axis_states.iter().any(|s| *s != AxisState::Disabled) {
            return Err((
                "card.servo_rate_hz".into(),
                nack_text(NackCode::AxesEnabled),
            ));
        }
    }
    let ts = 1.0 / rate as f64;
    // Safety: the card-wide block, and every axis's stop ramp within the maximum stop time.
    let safety = file.safety.or(card.safety).map(|s| s.block());
    if let Some(s) = &file.safety {
        let good = SafetySection {
            watchdog_timeout_us: card_firmware::host::WATCHDOG_TIMEOUT_DEFAULT_US,
            estop_input_category: 1,
            max_stop_time_us: card_firmware::host::MAX_STOP_TIME_DEFAULT_US,
        };
        let period = cx.host_period_us;
        refuse("safety", s, &good, |s| {
            SafetyConfig::validate(&s.block(), period).map(|_| ())
        })?;
    }
    let max_stop = safety
        .and_then(|b| SafetyConfig::validate(&b, 0).ok())
        .map_or(f64::INFINITY, |c| c.max_stop_time());
    // I/O.
    if let Some(io) = &file.io {
        if io.debounce.len() != INPUTS {
            return Err((
                "io.debounce".into(),
                format!("{} values: one per input ({INPUTS})", io.debounce.len()),
            ));
        }
        let good = IoSection {
            polarity: 0,
            rise_events: 0,
            fall_events: 0,
            debounce: vec![0; INPUTS],
        };
        refuse("io", io, &good, |s| {
            IoConfig::validate(&s.block()).map(|_| ())
        })?;
    }
    // Axes.
    let good = good_axis();
    for (key, ax) in &file.axis {
        let a = index_key("axis", key, cx.num_axes)?;
        let p = format!("axis.{a}");
        match (ax.servo_law, &ax.pdplus) {
            (ServoLaw::Pdplus, None) => {
                return Err((
                    format!("{p}.servo_law"),
                    format!("servo_law = \"pdplus\" needs the table [{p}.pdplus]"),
                ))
            }
            (ServoLaw::Ffpiv, Some(_)) => {
                return Err((
                    format!("{p}.pdplus"),
                    "a PD+ table on an axis whose servo_law is \"ffpiv\"".into(),
                ))
            }
            _ => {}
        }
        let mut good = good.clone();
        if ax.servo_law == ServoLaw::Ffpiv {
            good.pdplus = None;
        }
        good.servo_law = ax.servo_law;
        refuse(&p, ax, &good, |s| {
            if !s.scale.is_finite() {
                return Err(NackCode::NotFinite);
            }
            if !SCALE_RANGE.contains(&s.scale.abs()) {
                return Err(NackCode::OutOfRange);
            }
            let (cfg, pd) = s.servo_blocks();
            validate_axis_config(&cfg, &pd).map(|_| ())
        })?;
        if ax.filter.is_some() {
            refuse(&p, ax, &good, |s| {
                let Some(f) = &s.filter else { return Ok(()) };
                decode_axis_filter(&f.block())?.validate(ts)
            })?;
        }
        if ax.safety.is_some() {
            refuse(&p, ax, &good, |s| {
                let Some(f) = &s.safety else { return Ok(()) };
                AxisSafetyConfig::from_block(&f.block())?.validate_on_card(rate, max_stop)
            })?;
        }
        if ax.homing.is_some() {
            refuse(&p, ax, &good, |s| {
                let Some(h) = &s.homing else { return Ok(()) };
                HomingConfig::validate(&h.block(), rate).map(|_| ())
            })?;
        }
    }
    // The axes the file leaves as they are: their stop ramps must fit a new maximum stop time.
    if file.safety.is_some() {
        for (key, ax) in &card.axis {
            let from_file = file.axis.get(key).and_then(|a| a.safety);
            if let Some(s) = from_file.or(ax.safety) {
                let c = AxisSafetyConfig::from_block(&s.block());
                if c.is_ok_and(|c| c.stop_time_from(c.max_velocity) > max_stop) {
                    return Err((
                        "safety.max_stop_time_us".into(),
                        format!(
                            "axis {key}'s stop ramp from its max_velocity does not fit: {}",
                            nack_text(NackCode::StopTooLong)
                        ),
                    ));
                }
            }
        }
    }
    // Groups: each configuration, its axes in no other group, the group disabled to change it.
    let mut owner = [None::<usize>; MAX_AXES];
    for (key, g) in &card.group {
        if file.group.get(key).is_some_and(|f| f.axes.is_some()) {
            continue;
        }
        for &a in g.axes.iter().flatten() {
            owner[a as usize % MAX_AXES] = key.parse().ok();
        }
    }
    for (key, g) in &file.group {
        let gi = index_key("group", key, MAX_GROUPS)?;
        let p = format!("group.{gi}");
        let parts = [
            g.axes.is_some(),
            g.accdec.is_some(),
            g.interpolator.is_some(),
            g.tolerance.is_some(),
        ];
        if parts.iter().any(|&x| x) && !parts.iter().all(|&x| x) {
            let missing = ["axes", "accdec", "interpolator", "tolerance"]
                .iter()
                .zip(parts)
                .find(|(_, x)| !x)
                .map_or("axes", |(n, _)| n);
            return Err((
                format!("{p}.{missing}"),
                "a group's configuration needs all of axes, accdec, interpolator and tolerance"
                    .into(),
            ));
        }
        let mut naxes = MAX_AXES;
        if let Some(block) = g.config_block() {
            let good = GroupSection {
                axes: g.axes.clone(),
                accdec: Some(AccDecName::Pre),
                interpolator: Some(InterpolatorName::Exact),
                tolerance: Some(1.0),
                path: None,
            };
            let n = cx.num_axes;
            let bad = GroupSection {
                path: None,
                ..g.clone()
            };
            if let Err(code) = validate_group_config(&block, n) {
                let key = match code {
                    NackCode::BadAxis | NackCode::BadConfig
                        if block.naxes == 0
                            || block.naxes as usize > MAX_AXES
                            || g.axes.iter().flatten().any(|&a| a as usize >= n) =>
                    {
                        format!("{p}.axes")
                    }
                    _ => match blame(&bad, &good, |s| {
                        s.config_block()
                            .map_or(Ok(()), |b| validate_group_config(&b, n).map(|_| ()))
                    }) {
                        Some(k) => format!("{p}.{k}"),
                        None => format!("{p}.axes"),
                    },
                };
                return Err((key, nack_text(code)));
            }
            naxes = block.naxes as usize;
            for &a in g.axes.iter().flatten() {
                if let Some(o) = owner[a as usize].filter(|&o| o != gi) {
                    return Err((
                        format!("{p}.axes"),
                        format!(
                            "axis {a} is in group {o}: {}",
                            nack_text(NackCode::AxisInOtherGroup)
                        ),
                    ));
                }
                owner[a as usize] = Some(gi);
            }
            let held = card.group.get(key).and_then(|c| c.config_block());
            if held != Some(block) && cx.group_states.get(gi) != Some(&GroupState::Disabled) {
                return Err((
                    format!("{p}.axes"),
                    format!(
                        "the group must be disabled to configure it: {}",
                        nack_text(NackCode::InvalidState)
                    ),
                ));
            }
        } else if let Some(c) = card.group.get(key).and_then(|c| c.axes.as_ref()) {
            naxes = c.len();
        }
        if let Some(path) = &g.path {
            for (name, v) in [
                ("vmax", &path.vmax),
                ("amax", &path.amax),
                ("jmax", &path.jmax),
            ] {
                if v.len() != MAX_AXES {
                    return Err((
                        format!("{p}.path.{name}"),
                        format!("{} values: one per group axis slot ({MAX_AXES})", v.len()),
                    ));
                }
            }
            let good = PathSection::from(&firmware_proto::GroupPath::default());
            refuse(&format!("{p}.path"), path, &good, |s| {
                validate_path_config(&s.block(), naxes, rate)
            })?;
        }
    }
    Ok(())
}

impl From<&raw::mc_group_path> for PathSection {
    fn from(p: &raw::mc_group_path) -> Self {
        GroupSection::from_blocks(&Default::default(), p)
            .path
            .expect("always a path")
    }
}

// ----- the card --------------------------------------------------------------------------

/// What [`Card::load_config`] did.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct LoadReport {
    /// The sections applied (those that differed from the card), in order.
    pub applied: Vec<String>,
}

impl Card {
    /// Every setting the card holds, read back from the card (layout 1.8).
    pub fn read_config(&self) -> Result<Config> {
        let mut cfg = Config {
            card: Some(CardSection {
                servo_rate_hz: self.servo_rate()?,
            }),
            ..Default::default()
        };
        let s = self.read_block(layout::SAFETY_CONFIG, ConfigKind::Safety, 0)?;
        cfg.safety = Some(SafetySection {
            watchdog_timeout_us: s.watchdog_timeout_us,
            estop_input_category: s.estop_input_category,
            max_stop_time_us: s.max_stop_time_us,
        });
        let io = self.read_block(layout::IO_CONFIG, ConfigKind::Io, 0)?;
        cfg.io = Some(IoSection {
            polarity: io.polarity,
            rise_events: io.rise_events,
            fall_events: io.fall_events,
            debounce: io.debounce.to_vec(),
        });
        for a in 0..self.info().axes {
            let (c, pd) = self.read_axis_config(a)?;
            let f = self.read_block(layout::AXIS_FILTER.at(a), ConfigKind::AxisFilter, a)?;
            let s = self.read_block(layout::AXIS_SAFETY.at(a), ConfigKind::AxisSafety, a)?;
            let h = self.read_block(layout::AXIS_HOMING.at(a), ConfigKind::AxisHoming, a)?;
            cfg.axis
                .insert(a.to_string(), AxisSection::from_blocks(&c, &pd, &f, &s, &h));
        }
        for g in 0..MAX_GROUPS {
            let c = self.read_block(layout::GROUP_CONFIG.at(g), ConfigKind::Group, g)?;
            let p = self.read_block(layout::GROUP_PATH.at(g), ConfigKind::GroupPath, g)?;
            cfg.group
                .insert(g.to_string(), GroupSection::from_blocks(&c, &p));
        }
        Ok(cfg)
    }

    /// The configuration file of what the card holds (read back from the card).
    pub fn save_config(&self) -> Result<String> {
        Ok(self.read_config()?.to_toml())
    }

    /// Check the whole file against this card (nothing is applied when any value is wrong:
    /// [`Error::ConfigFile`] names the key and its line), then apply the sections that differ
    /// from what the card holds, read the card back and compare. `origin` names the text in
    /// errors (a file name). A section the card refuses after the checks passed (its state
    /// changed meanwhile) is [`Error::ConfigApply`], which says what was applied before it.
    pub fn load_config(&self, text: &str, origin: &str) -> Result<LoadReport> {
        let file = Config::parse(text, origin)?;
        let held = self.check_config(&file, text, origin)?;
        let mut report = LoadReport::default();
        self.apply_config(&file, &held, &mut report)
            .map_err(|(key, e)| Error::ConfigApply {
                key,
                applied: if report.applied.is_empty() {
                    "none".into()
                } else {
                    report.applied.join(", ")
                },
                source: Box::new(e),
            })?;
        // The card now holds what the file says.
        let now = self.read_config()?;
        if let Some(d) = differences(&file, &now).into_iter().next() {
            return Err(Error::Protocol(format!(
                "{origin}: {} reads back as {} after the load, not {}",
                d.key,
                d.card.as_deref().unwrap_or("nothing"),
                d.file
            )));
        }
        Ok(report)
    }

    /// The keys where the file and the card differ, in key order (the file is checked first,
    /// as by [`Card::load_config`], but nothing is applied).
    pub fn diff_config(&self, text: &str, origin: &str) -> Result<Vec<ConfigDifference>> {
        let file = Config::parse(text, origin)?;
        let held = self.check_config(&file, text, origin)?;
        Ok(differences(&file, &held))
    }

    /// [`Card::save_config`] into the file `path` (created or replaced).
    pub fn save_config_file(&self, path: impl AsRef<std::path::Path>) -> Result<()> {
        let path = path.as_ref();
        let text = self.save_config()?;
        std::fs::write(path, text)
            .map_err(|e| Error::io(format!("{}: cannot write", path.display()), e))
    }

    /// [`Card::load_config`] of the file `path`.
    pub fn load_config_file(&self, path: impl AsRef<std::path::Path>) -> Result<LoadReport> {
        let path = path.as_ref();
        self.load_config(&read_file(path)?, &path.display().to_string())
    }

    /// [`Card::diff_config`] of the file `path`.
    pub fn diff_config_file(
        &self,
        path: impl AsRef<std::path::Path>,
    ) -> Result<Vec<ConfigDifference>> {
        let path = path.as_ref();
        self.diff_config(&read_file(path)?, &path.display().to_string())
    }

    /// The checks of [`Card::load_config`]: the card's configuration, or the error.
    fn check_config(&self, file: &Config, text: &str, origin: &str) -> Result<Config> {
        let held = self.read_config()?;
        let axis_states = self
            .axes()
            .iter()
            .map(|a| a.status().map(|s| s.state))
            .collect::<Result<Vec<_>>>()?;
        let group_states = (0..MAX_GROUPS)
            .map(|g| self.group(g)?.status().map(|s| s.0))
            .collect::<Result<Vec<_>>>()?;
        let cx = Context {
            num_axes: self.info().axes,
            host_period_us: self.window().read32(layout::HOST_PERIOD_US),
            card: &held,
            axis_states,
            group_states,
        };
        check(file, &cx).map_err(|(key, message)| {
            let line = line_of_key(text, &key);
            file_error(origin, key, line, message)
        })?;
        Ok(held)
    }

    /// Apply the sections of `file` that differ from `held`; on a refusal, the section.
    fn apply_config(
        &self,
        file: &Config,
        held: &Config,
        report: &mut LoadReport,
    ) -> std::result::Result<(), (String, Error)> {
        let mut done = |key: String| report.applied.push(key);
        if let Some(c) = file.card.filter(|c| Some(*c) != held.card) {
            self.set_servo_rate(c.servo_rate_hz)
                .map_err(|e| ("card".to_string(), e))?;
            done("card".into());
        }
        // A longer maximum stop time first, a shorter one after the axes' stop ramps.
        let safety = file.safety.filter(|s| Some(*s) != held.safety);
        let shorter = safety.is_some_and(|s| {
            held.safety
                .is_some_and(|h| s.max_stop_time_us < h.max_stop_time_us)
        });
        let apply_safety = |done: &mut dyn FnMut(String)| {
            if let Some(s) = safety {
                let b = s.block();
                self.apply_block(
                    layout::SAFETY_CONFIG,
                    |x| *x = b,
                    firmware_proto::Command::new(firmware_proto::Opcode::ApplySafetyConfig, 0),
                    "load configuration",
                    crate::Target::Card,
                )
                .map_err(|e| ("safety".to_string(), e))?;
                done("safety".into());
            }
            Ok(())
        };
        if !shorter {
            apply_safety(&mut done)?;
        }
        if let Some(io) = file.io.as_ref().filter(|io| Some(*io) != held.io.as_ref()) {
            self.configure_io(&io.block())
                .map_err(|e| ("io".to_string(), e))?;
            done("io".into());
        }
        for (key, ax) in &file.axis {
            let a: usize = key.parse().expect("checked");
            let was = held.axis.get(key);
            let axis = self.axis(a).map_err(|e| (format!("axis.{a}"), e))?;
            let (cfg, pd) = ax.servo_blocks();
            let was_scale = was.map(|w| w.scale);
            let servo = |s: &AxisSection| {
                let (c, p) = s.servo_blocks();
                (AxisConfig { scale: 0.0, ..c }, p)
            };
            if was.map(servo) != Some(servo(ax)) {
                let apply =
                    firmware_proto::Command::new(firmware_proto::Opcode::ApplyAxisConfig, a as u16);
                let _g = self.config_lock();
                let w = self.window();
                let saved = (
                    layout::AXIS_CONFIG.at(a).read(w),
                    layout::AXIS_PDPLUS.at(a).read(w),
                );
                self.write_block(layout::AXIS_PDPLUS.at(a), &pd);
                self.write_block(layout::AXIS_CONFIG.at(a), &cfg);
                let r = self.execute(apply, "load configuration", crate::Target::Axis(a));
                if r.is_err() {
                    self.write_block(layout::AXIS_CONFIG.at(a), &saved.0);
                    self.write_block(layout::AXIS_PDPLUS.at(a), &saved.1);
                }
                r.map_err(|e| (format!("axis.{a}"), e))?;
                done(format!("axis.{a}"));
            }
            if was_scale != Some(ax.scale) {
                axis.set_scale(ax.scale)
                    .map_err(|e| (format!("axis.{a}.scale"), e))?;
                done(format!("axis.{a}.scale"));
            }
            let subs: [(&str, bool, ConfigKind); 3] = [
                (
                    "filter",
                    ax.filter.is_some() && ax.filter != was.and_then(|w| w.filter),
                    ConfigKind::AxisFilter,
                ),
                (
                    "safety",
                    ax.safety.is_some() && ax.safety != was.and_then(|w| w.safety),
                    ConfigKind::AxisSafety,
                ),
                (
                    "homing",
                    ax.homing.is_some() && ax.homing != was.and_then(|w| w.homing),
                    ConfigKind::AxisHoming,
                ),
            ];
            for (name, differs, kind) in subs {
                if !differs {
                    continue;
                }
                let cmd = |op| firmware_proto::Command::new(op, a as u16);
                let t = crate::Target::Axis(a);
                let what = "load configuration";
                let r = match kind {
                    ConfigKind::AxisFilter => {
                        let b = ax.filter.expect("differs").block();
                        self.apply_block(
                            layout::AXIS_FILTER.at(a),
                            |x| *x = b,
                            cmd(firmware_proto::Opcode::ApplyAxisFilter),
                            what,
                            t,
                        )
                    }
                    ConfigKind::AxisSafety => {
                        let b = ax.safety.expect("differs").block();
                        self.apply_block(
                            layout::AXIS_SAFETY.at(a),
                            |x| *x = b,
                            cmd(firmware_proto::Opcode::ApplyAxisSafety),
                            what,
                            t,
                        )
                    }
                    _ => {
                        let b = ax.homing.expect("differs").block();
                        self.apply_block(
                            layout::AXIS_HOMING.at(a),
                            |x| *x = b,
                            cmd(firmware_proto::Opcode::ApplyAxisHoming),
                            what,
                            t,
                        )
                    }
                };
                r.map_err(|e| (format!("axis.{a}.{name}"), e))?;
                done(format!("axis.{a}.{name}"));
            }
        }
        if shorter {
            apply_safety(&mut done)?;
        }
        for (key, g) in &file.group {
            let gi: usize = key.parse().expect("checked");
            let was = held.group.get(key);
            let t = crate::Target::Group(gi);
            if let Some(b) = g.config_block() {
                if was.and_then(|w| w.config_block()) != Some(b) {
                    self.apply_block(
                        layout::GROUP_CONFIG.at(gi),
                        |x| *x = b,
                        firmware_proto::Command::new(
                            firmware_proto::Opcode::GroupConfigure,
                            gi as u16,
                        ),
                        "load configuration",
                        t,
                    )
                    .map_err(|e| (format!("group.{gi}"), e))?;
                    let mut axes = [0usize; MAX_AXES];
                    for (d, &a) in axes.iter_mut().zip(g.axes.iter().flatten()) {
                        *d = a as usize;
                    }
                    crate::card::lock(&self.inner().group_axes)[gi] =
                        Some((b.naxes as usize, axes));
                    done(format!("group.{gi}"));
                }
            }
            if let Some(p) = g
                .path
                .as_ref()
                .filter(|p| Some(*p) != was.and_then(|w| w.path.as_ref()))
            {
                let b = p.block();
                self.apply_block(
                    layout::GROUP_PATH.at(gi),
                    |x| *x = b,
                    firmware_proto::Command::new(firmware_proto::Opcode::ApplyGroupPath, gi as u16),
                    "load configuration",
                    t,
                )
                .map_err(|e| (format!("group.{gi}.path"), e))?;
                done(format!("group.{gi}.path"));
            }
        }
        Ok(())
    }
}

/// The keys of `file` whose values differ from `card`'s, in key order (an array is one key).
pub fn differences(file: &Config, card: &Config) -> Vec<ConfigDifference> {
    let (Ok(f), Ok(c)) = (toml::Value::try_from(file), toml::Value::try_from(card)) else {
        return Vec::new();
    };
    let mut leaves = Vec::new();
    collect_leaves(&f, &mut Vec::new(), &mut leaves);
    let mut out = Vec::new();
    // Arrays compare whole (one line for `debounce`, `vmax`…).
    let mut seen = std::collections::BTreeSet::new();
    for path in leaves {
        let path = match path.last().map(|p| p.parse::<usize>().is_ok()) {
            Some(true) => path[..path.len() - 1].to_vec(),
            _ => path,
        };
        if !seen.insert(path.clone()) {
            continue;
        }
        let fv = get_path(&f, &path).expect("a leaf of the file");
        let cv = get_path(&c, &path);
        if cv != Some(fv) {
            out.push(ConfigDifference {
                key: path.join("."),
                file: fv.to_string(),
                card: cv.map(|v| v.to_string()),
            });
        }
    }
    out
}
