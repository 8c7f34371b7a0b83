//! The sections of a configuration file (see the config module): their types, as serde reads
//! and writes them, and the card's blocks each one stands for.

use firmware_proto::{raw, AxisConfig, AxisPdPlus, AxisPidff, MAX_AXES};
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
    /// Layout 1.10: formed gantries by number (`"0"`…); formed last when a file is loaded.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub gantry: BTreeMap<String, GantrySection>,
    /// Layout 1.11: the analog inputs by number (`"0"`…).
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub analog_input: BTreeMap<String, AnalogInputSection>,
    /// Layout 1.11: the path-speed output (after the groups: it runs on one).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pso: Option<PsoSection>,
}

/// `[analog_input.N]` (layout 1.11): an analog input's filter and threshold
/// ([`crate::AnalogInputSettings`]), volts and Hz.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AnalogInputSection {
    /// The first-order filter's cut-off, Hz (0: none; at most half the servo rate).
    pub cutoff_hz: f64,
    /// The threshold, V (within ±10 V).
    pub threshold: f64,
    /// The hysteresis, V (0..=20).
    pub hysteresis: f64,
    /// An event going above.
    pub rise_event: bool,
    /// An event going below again.
    pub fall_event: bool,
}

impl AnalogInputSection {
    /// The SDK's settings.
    pub fn settings(&self) -> crate::AnalogInputSettings {
        crate::AnalogInputSettings {
            cutoff_hz: self.cutoff_hz,
            threshold: self.threshold,
            hysteresis: self.hysteresis,
            rise_event: self.rise_event,
            fall_event: self.fall_event,
        }
    }

    /// The command that sets input `input` to these settings.
    pub(crate) fn command(&self, input: usize) -> firmware_proto::cmd::AnalogInput {
        firmware_proto::cmd::AnalogInput {
            input: input.min(u8::MAX as usize) as u8,
            cutoff_hz: self.cutoff_hz,
            threshold: self.threshold,
            hysteresis: self.hysteresis,
            rise_event: self.rise_event,
            fall_event: self.fall_event,
        }
    }
}

impl From<&crate::AnalogInputSettings> for AnalogInputSection {
    fn from(s: &crate::AnalogInputSettings) -> Self {
        Self {
            cutoff_hz: s.cutoff_hz,
            threshold: s.threshold,
            hysteresis: s.hysteresis,
            rise_event: s.rise_event,
            fall_event: s.fall_event,
        }
    }
}

/// Where the path-speed output goes, or none.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum PsoOutputName {
    /// Not running (`[pso]` holds no other key): a PSO the card runs is stopped.
    Off,
    /// A spare DAC output (`channel` 0..4): `min` and `max` in volts.
    Dac,
    /// A PWM on digital output `channel` (0..16) at `pwm_hz`: `min` and `max` are duties.
    Pwm,
}

/// `[pso]` (layout 1.11): the path-speed output ([`crate::Pso`]) in counts: `v_ref` is the
/// group's tangential speed of full output in counts/s. With `output = "off"` no other key;
/// else all of them, `pwm_hz` with a PWM only.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PsoSection {
    /// Off, a DAC or a PWM.
    pub output: PsoOutputName,
    /// The group whose speed it follows.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub group: Option<u32>,
    /// The spare DAC or the digital output.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub channel: Option<u32>,
    /// The PWM's frequency, Hz (`output = "pwm"` only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pwm_hz: Option<f64>,
    /// The digital output that gates it (M62–M65).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gate: Option<u32>,
    /// The output at rest (V, or duty).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub min: Option<f64>,
    /// The output at `v_ref` and beyond (V, or duty).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max: Option<f64>,
    /// The tangential speed of full output, counts/s (> 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub v_ref: Option<f64>,
    /// The speed filter's cut-off, Hz (0: none; at most half the servo rate).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub filter_hz: Option<f64>,
}

impl PsoSection {
    /// The section of the PSO the card runs (`None`: off).
    pub fn from_status(s: &crate::PsoStatus) -> Self {
        let Some(p) = s.settings.filter(|_| s.state != crate::PsoState::Off) else {
            return Self::off();
        };
        let (output, channel, pwm_hz) = match p.output {
            crate::PsoOutput::Dac(d) => (PsoOutputName::Dac, d, None),
            crate::PsoOutput::Pwm { output, hz } => (PsoOutputName::Pwm, output, Some(hz)),
        };
        Self {
            output,
            group: Some(s.group as u32),
            channel: Some(channel as u32),
            pwm_hz,
            gate: Some(p.gate as u32),
            min: Some(p.min),
            max: Some(p.max),
            v_ref: Some(p.v_ref),
            filter_hz: Some(p.filter_hz),
        }
    }

    /// `output = "off"`.
    pub fn off() -> Self {
        Self {
            output: PsoOutputName::Off,
            group: None,
            channel: None,
            pwm_hz: None,
            gate: None,
            min: None,
            max: None,
            v_ref: None,
            filter_hz: None,
        }
    }

    /// The keys the output needs (the rest must be absent), each with whether it is present.
    pub(crate) fn keys(&self) -> [(&'static str, bool, bool); 8] {
        let on = self.output != PsoOutputName::Off;
        let pwm = self.output == PsoOutputName::Pwm;
        [
            ("group", on, self.group.is_some()),
            ("channel", on, self.channel.is_some()),
            ("pwm_hz", pwm, self.pwm_hz.is_some()),
            ("gate", on, self.gate.is_some()),
            ("min", on, self.min.is_some()),
            ("max", on, self.max.is_some()),
            ("v_ref", on, self.v_ref.is_some()),
            ("filter_hz", on, self.filter_hz.is_some()),
        ]
    }

    /// The group and the PSO's settings in counts (`None`: off; the keys checked before: a
    /// missing one is 0).
    pub(crate) fn settings(&self) -> Option<(usize, crate::Pso)> {
        let idx = |x: Option<u32>| x.map_or(0, |x| x as usize);
        let output = match self.output {
            PsoOutputName::Off => return None,
            PsoOutputName::Dac => crate::PsoOutput::Dac(idx(self.channel)),
            PsoOutputName::Pwm => crate::PsoOutput::Pwm {
                output: idx(self.channel),
                hz: self.pwm_hz.unwrap_or(0.0),
            },
        };
        let num = |x: Option<f64>| x.unwrap_or(0.0);
        Some((
            idx(self.group),
            crate::Pso {
                output,
                gate: idx(self.gate),
                min: num(self.min),
                max: num(self.max),
                v_ref: num(self.v_ref),
                filter_hz: num(self.filter_hz),
            },
        ))
    }

    /// The card's command of the settings (the indices saturated to a byte: the decoding
    /// refuses what the card does not have).
    pub(crate) fn command(p: &crate::Pso) -> firmware_proto::cmd::Pso {
        let arg = |x: usize| x.min(u8::MAX as usize) as u8;
        firmware_proto::cmd::Pso {
            output: match p.output {
                crate::PsoOutput::Dac(d) => firmware_proto::cmd::PsoOutput::Dac(arg(d)),
                crate::PsoOutput::Pwm { output, hz } => firmware_proto::cmd::PsoOutput::Pwm {
                    output: arg(output),
                    hz,
                },
            },
            gate: arg(p.gate),
            min: p.min,
            max: p.max,
            v_ref: p.v_ref,
            filter_hz: p.filter_hz,
        }
    }
}

/// A servo-output filter's kind in `[axis.N.biquad.K]`, or an empty slot.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum BiquadName {
    /// The slot is empty (no other key).
    None,
    /// A notch: `freq_hz`, `damping`, `depth_db`.
    Notch,
    /// A second-order low-pass: `freq_hz`, `damping`.
    Lowpass,
    /// A first-order lead/lag: `freq_hz` (the zero), `freq2_hz` (the pole).
    LeadLag,
    /// The coefficients as given: `b0`, `b1`, `b2`, `a1`, `a2` (a0 = 1).
    Raw,
}

/// `[axis.N.biquad.K]` (layout 1.11): the servo-output filter in slot K (0..4,
/// [`crate::Axis::set_servo_filter`]); the keys of its kind, no others.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
#[allow(missing_docs)]
pub struct BiquadSection {
    /// The kind, or `"none"`: the slot is empty.
    pub kind: BiquadName,
    /// Notch: the centre; low-pass: the corner; lead/lag: the zero's frequency, Hz.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub freq_hz: Option<f64>,
    /// Notch, low-pass: the damping ratio (a notch's width), (0, 10].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub damping: Option<f64>,
    /// Notch: the gain at the centre, dB (-120..=0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub depth_db: Option<f64>,
    /// Lead/lag: the pole's frequency, Hz.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub freq2_hz: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub b0: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub b1: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub b2: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub a1: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub a2: Option<f64>,
}

impl BiquadSection {
    /// An empty slot.
    pub fn none() -> Self {
        Self {
            kind: BiquadName::None,
            freq_hz: None,
            damping: None,
            depth_db: None,
            freq2_hz: None,
            b0: None,
            b1: None,
            b2: None,
            a1: None,
            a2: None,
        }
    }

    /// The section of a filter as set (`None`: an empty slot): the keys of its kind.
    pub fn from_spec(spec: Option<&crate::BiquadSpec>) -> Self {
        use crate::BiquadKind as K;
        let Some(s) = spec else {
            return Self::none();
        };
        let c = s.coeffs;
        let e = Self::none();
        match s.kind {
            K::Notch => Self {
                kind: BiquadName::Notch,
                freq_hz: Some(s.freq_hz),
                damping: Some(s.damping),
                depth_db: Some(s.depth_db),
                ..e
            },
            K::LowPass => Self {
                kind: BiquadName::Lowpass,
                freq_hz: Some(s.freq_hz),
                damping: Some(s.damping),
                ..e
            },
            K::LeadLag => Self {
                kind: BiquadName::LeadLag,
                freq_hz: Some(s.freq_hz),
                freq2_hz: Some(s.freq2_hz),
                ..e
            },
            K::Raw => Self {
                kind: BiquadName::Raw,
                b0: Some(c[0]),
                b1: Some(c[1]),
                b2: Some(c[2]),
                a1: Some(c[3]),
                a2: Some(c[4]),
                ..e
            },
        }
    }

    /// Each key, whether the kind needs it and whether the section has it.
    pub fn keys(&self) -> [(&'static str, bool, bool); 9] {
        use BiquadName as N;
        let k = self.kind;
        let raw = k == N::Raw;
        [
            (
                "freq_hz",
                matches!(k, N::Notch | N::Lowpass | N::LeadLag),
                self.freq_hz.is_some(),
            ),
            (
                "damping",
                matches!(k, N::Notch | N::Lowpass),
                self.damping.is_some(),
            ),
            ("depth_db", k == N::Notch, self.depth_db.is_some()),
            ("freq2_hz", k == N::LeadLag, self.freq2_hz.is_some()),
            ("b0", raw, self.b0.is_some()),
            ("b1", raw, self.b1.is_some()),
            ("b2", raw, self.b2.is_some()),
            ("a1", raw, self.a1.is_some()),
            ("a2", raw, self.a2.is_some()),
        ]
    }

    /// The filter (`None`: the slot empty); a key missing is 0 (the keys are checked before).
    pub fn spec(&self) -> Option<crate::BiquadSpec> {
        use crate::BiquadKind as K;
        let kind = match self.kind {
            BiquadName::None => return None,
            BiquadName::Notch => K::Notch,
            BiquadName::Lowpass => K::LowPass,
            BiquadName::LeadLag => K::LeadLag,
            BiquadName::Raw => K::Raw,
        };
        let n = |x: Option<f64>| x.unwrap_or(0.0);
        Some(crate::BiquadSpec {
            kind,
            freq_hz: n(self.freq_hz),
            damping: n(self.damping),
            depth_db: n(self.depth_db),
            freq2_hz: n(self.freq2_hz),
            coeffs: [self.b0, self.b1, self.b2, self.a1, self.a2].map(n),
        })
    }
}

/// `[gantry.N]` (layout 1.10): a formed gantry ([`crate::Card::gantry_at`]), the skew limit
/// and the offsets in the master's user units (the file's `scale`). Read back from the card's
/// `gantry_status`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GantrySection {
    /// The master axis.
    pub master: u8,
    /// The slave axes (1 to 4).
    pub slaves: Vec<u8>,
    /// Proportional gain of the yaw loop, 1/s².
    pub kp: f64,
    /// Integral gain of the yaw loop, 1/s³.
    pub ki: f64,
    /// The skew beyond which every member stops (> 0).
    pub skew_limit: f64,
    /// Each slave's square offset, in the order of `slaves` (empty: 0 for each).
    #[serde(default)]
    pub offsets: Vec<f64>,
}

impl GantrySection {
    /// The SDK's settings of the section.
    pub fn config(&self) -> crate::GantryConfig {
        crate::GantryConfig {
            kp: self.kp,
            ki: self.ki,
            skew_limit: self.skew_limit,
            offsets: self.offsets.clone(),
        }
    }

    /// The section of a formed gantry's status block (`None`: not formed), in user units of
    /// `scale` (each length the shortest decimal that the card holds as the same count, as
    /// `modulo`'s).
    pub(crate) fn from_block(b: &raw::mc_gantry_status, scale: f64) -> Option<Self> {
        if b.phase == raw::MC_GANTRY_NONE {
            return None;
        }
        let n = (b.nslaves as usize).min(b.slave.len());
        Some(Self {
            master: b.master as u8,
            slaves: b.slave[..n].iter().map(|&a| a as u8).collect(),
            kp: b.kp,
            ki: b.ki,
            skew_limit: user_length(b.skew_limit, scale.abs()),
            offsets: b.offset[..n]
                .iter()
                .map(|&o| user_length(o, scale))
                .collect(),
        })
    }
}

/// `counts` in user units of `scale`: the shortest decimal `x` with `x·scale == counts`
/// (else the quotient).
pub(crate) fn user_length(counts: f64, scale: f64) -> f64 {
    let m = counts / scale;
    if !m.is_finite() || counts == 0.0 {
        return m;
    }
    (0..17)
        .filter_map(|k| format!("{m:.k$e}").parse::<f64>().ok())
        .find(|x| x * scale == counts)
        .unwrap_or(m)
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
    /// Layout 1.11: PID + feed-forward (Kim §5) with `[axis.N.pidff]`.
    Pidff,
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
    /// Layout 1.11: the PID+FF gains (`mc_axis_pidff`): present exactly when `servo_law` is
    /// `pidff`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pidff: Option<PidffSection>,
    /// The acc/dec filters (`mc_axis_filter`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub filter: Option<FilterSection>,
    /// The axis's safety (`mc_axis_safety`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub safety: Option<AxisSafetySection>,
    /// Homing (`mc_axis_homing`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub homing: Option<HomingSection>,
    /// Leadscrew compensation (layout 1.9): absent, the card's table is left as it is (and
    /// read back absent when the card holds none).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub compensation: Option<CompensationSection>,
    /// Layout 1.11: the servo output's filters by slot (`"0"` to `"3"`); a slot the file does
    /// not name is left as the card holds it, `kind = "none"` empties one.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub biquad: BTreeMap<String, BiquadSection>,
    /// Layout 1.10: the modulo period of a rotary axis, user units (in the file's `scale`);
    /// `0` makes the axis linear (and is read back for one). Absent, the card's period is left
    /// as it is.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub modulo: Option<f64>,
}

/// The period of `counts` (as the card holds it, 1/65536 count) in user units of `scale`: the
/// shortest decimal that the card would hold as the same period, so that `360` written with a
/// scale of 10000/360 reads back as `360`, not `360.00000000000006`.
pub(crate) fn user_modulo(counts: f64, scale: f64) -> f64 {
    if counts == 0.0 {
        return 0.0;
    }
    let m = counts / scale;
    if !m.is_finite() {
        return m;
    }
    let held = firmware_proto::modulo_subcounts(counts);
    (0..17)
        .filter_map(|k| format!("{m:.k$e}").parse::<f64>().ok())
        .find(|x| firmware_proto::modulo_subcounts(x * scale) == held)
        .unwrap_or(m)
}

/// `[axis.N.compensation]`: the pitch-error table and backlash ([`crate::Compensation`]),
/// user units.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CompensationSection {
    /// Backlash (>= 0).
    pub backlash: f64,
    /// The largest |correction ± backlash/2| allowed.
    pub bound: f64,
    /// The ramp that takes up a jump of the correction: velocity, user units/s.
    pub ramp_velocity: f64,
    /// Its acceleration, user units/s².
    pub ramp_acceleration: f64,
    /// A correction per direction (else the reverse one equals the forward one).
    #[serde(default)]
    pub bidirectional: bool,
    /// The points: `[position, forward correction, reverse correction]`, positions strictly
    /// increasing.
    #[serde(default)]
    pub points: Vec<[f64; 3]>,
}

impl From<&crate::Compensation> for CompensationSection {
    fn from(c: &crate::Compensation) -> Self {
        Self {
            backlash: c.backlash,
            bound: c.bound,
            ramp_velocity: c.ramp_velocity,
            ramp_acceleration: c.ramp_acceleration,
            bidirectional: c.bidirectional,
            points: c
                .points
                .iter()
                .map(|p| [p.position, p.forward, p.reverse])
                .collect(),
        }
    }
}

impl From<&CompensationSection> for crate::Compensation {
    fn from(c: &CompensationSection) -> Self {
        Self {
            points: c
                .points
                .iter()
                .map(|p| crate::CompPoint {
                    position: p[0],
                    forward: p[1],
                    reverse: p[2],
                })
                .collect(),
            bidirectional: c.bidirectional,
            backlash: c.backlash,
            bound: c.bound,
            ramp_velocity: c.ramp_velocity,
            ramp_acceleration: c.ramp_acceleration,
        }
    }
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

/// `[axis.N.pidff]` (layout 1.11): the PID + feed-forward gains (`mc_axis_pidff`), volts,
/// counts and seconds.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PidffSection {
    /// Proportional, V/count.
    pub kp: f64,
    /// Integral, V/(count·s).
    pub ki: f64,
    /// Derivative, V per count/s.
    pub kd: f64,
    /// Velocity feed-forward, V per count/s.
    pub kvff: f64,
    /// Acceleration feed-forward, V per count/s².
    pub kaff: f64,
    /// Coulomb friction feed-forward, V.
    pub friction: f64,
    /// |v_ref| up to which the friction feed-forward is 0, counts/s.
    pub friction_deadband: f64,
    /// The derivative filter's cut-off, Hz.
    pub d_filter_hz: f64,
}

impl From<&AxisPidff> for PidffSection {
    fn from(p: &AxisPidff) -> Self {
        Self {
            kp: p.kp,
            ki: p.ki,
            kd: p.kd,
            kvff: p.kvff,
            kaff: p.kaff,
            friction: p.friction,
            friction_deadband: p.friction_deadband,
            d_filter_hz: p.d_filter_hz,
        }
    }
}

impl PidffSection {
    /// The register map's block.
    pub fn block(&self) -> AxisPidff {
        AxisPidff {
            kp: self.kp,
            ki: self.ki,
            kd: self.kd,
            kvff: self.kvff,
            kaff: self.kaff,
            friction: self.friction,
            friction_deadband: self.friction_deadband,
            d_filter_hz: self.d_filter_hz,
            _reserved: [0.0; 8],
        }
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
    /// Layout 1.11: the group's home order, stages of group axis indices (`[[2], [0, 1]]`: Z
    /// first, then X and Y together); `Group::home` with an empty order takes it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub home_order: Option<Vec<Vec<u8>>>,
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

/// One key where a file and the card differ ([`Card::diff_config`](crate::Card::diff_config)).
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
    pub(super) fn from_blocks(
        c: &AxisConfig,
        pd: &AxisPdPlus,
        pid: &AxisPidff,
        f: &raw::mc_axis_filter,
        s: &raw::mc_axis_safety,
        h: &raw::mc_axis_homing,
    ) -> Self {
        let g = &c.ffpiv;
        let pdplus = c.servo_law == raw::MC_SERVO_PDPLUS;
        let pidff = c.servo_law == raw::MC_SERVO_PIDFF;
        let flag = |bits: u32, b: u32| bits & b != 0;
        Self {
            scale: c.scale,
            servo_law: if pdplus {
                ServoLaw::Pdplus
            } else if pidff {
                ServoLaw::Pidff
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
            pidff: pidff.then(|| PidffSection::from(pid)),
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
            compensation: None,
            biquad: BTreeMap::new(),
            modulo: Some(user_modulo(c.modulo, c.scale)),
        }
    }

    /// The axis configuration block, the PD+ block (zero without PD+) and the PID+FF block
    /// (zero without PID+FF).
    pub(super) fn servo_blocks(&self) -> (AxisConfig, AxisPdPlus, AxisPidff) {
        let cfg = AxisConfig {
            servo_law: match self.servo_law {
                ServoLaw::Ffpiv => raw::MC_SERVO_FFPIV,
                ServoLaw::Pdplus => raw::MC_SERVO_PDPLUS,
                ServoLaw::Pidff => raw::MC_SERVO_PIDFF,
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
        let pid = self
            .pidff
            .map_or(card_firmware::host::pidff_block(None), |p| p.block());
        (cfg, self.pdplus.map_or(pd, |p| p.onto(pd)), pid)
    }
}

impl FilterSection {
    pub(super) fn block(&self) -> raw::mc_axis_filter {
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
    pub(super) fn block(&self) -> raw::mc_axis_safety {
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
    pub(super) fn block(&self) -> raw::mc_axis_homing {
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
    pub(super) fn from_blocks(c: &raw::mc_group_config, p: &raw::mc_group_path) -> Self {
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
            home_order: (configured && c.home_stages > 0).then(|| {
                let n = (c.home_stages as usize).min(c.home_order.len());
                c.home_order[..n]
                    .iter()
                    .map(|&m| (0..8u8).filter(|i| m >> i & 1 == 1).collect())
                    .collect()
            }),
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
    pub(super) fn config_block(&self) -> Option<raw::mc_group_config> {
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
        if let Some(order) = &self.home_order {
            // What the block cannot hold is made a value the card refuses for the same
            // fault: more stages than it holds (BadConfig), an index beyond 7 (HomeAxis),
            // an index twice in a stage (HomeTwice).
            b.home_stages = order.len() as u32;
            for (d, stage) in b.home_order.iter_mut().zip(order) {
                let mut m = 0u16;
                for &i in stage {
                    if i >= 8 {
                        m |= 0x100;
                    } else if m >> i & 1 == 1 {
                        m |= 0x200;
                    } else {
                        m |= 1 << i;
                    }
                }
                *d = match m {
                    m if m & 0x100 != 0 => 0xFF,
                    m if m & 0x200 != 0 => 0,
                    m => m as u8,
                };
            }
        }
        Some(b)
    }
}

impl PathSection {
    /// The block (the arrays' lengths are checked before).
    pub(super) fn block(&self) -> raw::mc_group_path {
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
    pub(super) fn block(&self) -> raw::mc_io_config {
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
    pub(super) fn block(&self) -> raw::mc_safety_config {
        raw::mc_safety_config {
            watchdog_timeout_us: self.watchdog_timeout_us,
            estop_input_category: self.estop_input_category,
            max_stop_time_us: self.max_stop_time_us,
            ..Default::default()
        }
    }
}

impl From<&raw::mc_group_path> for PathSection {
    fn from(p: &raw::mc_group_path) -> Self {
        GroupSection::from_blocks(&Default::default(), p)
            .path
            .expect("always a path")
    }
}
