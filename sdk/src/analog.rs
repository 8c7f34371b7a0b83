//! Analog I/O and the path-speed output (layout 1.11), run by the card.
//!
//! - **Analog inputs** (8): a 16-bit ±10 V ADC sampled every servo tick ([`ADC_LSB`] ≈
//!   0.305 mV), a first-order low-pass filter per input and a threshold with hysteresis
//!   ([`Card::configure_analog_input`]): an input goes above at `value >= threshold` and
//!   below again at `value <= threshold - hysteresis`, and posts an [`EventKind::Analog`]
//!   event (axis: the input; code 1 above, 0 below; value: the filtered volts) when its
//!   settings ask for it. [`Card::analog_input`] reads the sample, the filtered value and the
//!   state of the last tick.
//! - **Spare DAC outputs** (4): [`Card::set_analog_output`] (volts, clamped to the DAC's
//!   ±10 V range and quantised to its 12 bits; NaN refused), read back by
//!   [`Card::analog_output`].
//! - **Path-speed output** ([`Group::pso`], PSO): laser power or a dispenser's flow that
//!   follows the group's ACTUAL tangential speed `v` (from its axes' velocity estimates, so it
//!   follows the feed the machine makes through a corner, not the one programmed):
//!   `clamp(min + (max − min)·v/v_ref, min, max)` every tick, on a spare DAC (volts) or as the
//!   duty of a PWM on a digital output, while the gate output is on. Gate it from the path with
//!   [`OutputAt`](crate::OutputAt) outputs (G-code M62–M65) or [`Card::set_outputs`]. `v_ref`
//!   is in the group's user units (its first axis's scale) per second.
//!
//! The card checks every argument again and answers with its own error kinds
//! (`AnalogChannel`, `AnalogFilter`, `AnalogThreshold`, `PsoConfig`, `PsoGroup`, `NotFinite`);
//! a refused command changes nothing.
//!
//! [`EventKind::Analog`]: crate::EventKind::Analog

use crate::card::Card;
use crate::error::{Error, Result, Target};
use crate::group::Group;
use firmware_proto::cmd::{self, IoCmd};
use firmware_proto::{layout, raw, NackCode};

/// The card's analog inputs.
pub const ANALOG_INPUTS: usize = firmware_proto::ANALOG_INPUTS;
/// The card's spare DAC outputs.
pub const ANALOG_OUTPUTS: usize = firmware_proto::ANALOG_OUTPUTS;
/// The ADC's step, V (20 V / 65536).
pub const ADC_LSB: f64 = raw::MC_ADC_LSB;
/// The ADC's and the DACs' range, ±V.
pub const ANALOG_RANGE: f64 = raw::MC_ANALOG_RANGE;
/// The highest PWM frequency of the path-speed output, Hz.
pub const PSO_PWM_HZ_MAX: f64 = raw::MC_PSO_PWM_HZ_MAX;

/// An analog input's filter and threshold. `Default`: the boot state (no filter, threshold
/// 0 V, no hysteresis, no events).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct AnalogInputSettings {
    /// The first-order filter's cut-off, Hz (0: none; at most half the servo rate).
    pub cutoff_hz: f64,
    /// The threshold, V (within ±10 V).
    pub threshold: f64,
    /// The hysteresis, V (0..=20): below again at `threshold - hysteresis`.
    pub hysteresis: f64,
    /// Post [`EventKind::Analog`](crate::EventKind::Analog) going above.
    pub rise_event: bool,
    /// Post it going below again.
    pub fall_event: bool,
}

/// An analog input as the card sampled it at its last tick.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AnalogInput {
    /// The ADC's sample, V (a multiple of [`ADC_LSB`]).
    pub sample: f64,
    /// The filtered value, V.
    pub value: f64,
    /// Above the threshold.
    pub above: bool,
    /// The settings the card holds.
    pub settings: AnalogInputSettings,
}

/// Where the path-speed output goes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PsoOutput {
    /// A spare DAC output (`0..ANALOG_OUTPUTS`): `min` and `max` in volts.
    Dac(usize),
    /// A PWM on a digital output (`0..16`) at `hz`: `min` and `max` are duties 0..=1.
    Pwm {
        /// The digital output.
        output: usize,
        /// Frequency, Hz (1..=[`PSO_PWM_HZ_MAX`]).
        hz: f64,
    },
}

/// The path-speed output's settings ([`Group::pso`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pso {
    /// Its output.
    pub output: PsoOutput,
    /// The digital output (0..16) whose level switches it on (the path's M62–M65 outputs).
    pub gate: usize,
    /// The output at rest (V, or duty).
    pub min: f64,
    /// The output at `v_ref` and beyond (V, or duty).
    pub max: f64,
    /// The tangential speed of full output, the group's user units per second (> 0).
    pub v_ref: f64,
    /// The cut-off of the speed filter, Hz (0: none; at most half the servo rate): the axes'
    /// velocity estimates step by a count per tick, which the filter smooths; it lags by
    /// about 1/(2π·filter_hz).
    pub filter_hz: f64,
}

/// The path-speed output's state.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PsoState {
    /// Not configured.
    Off,
    /// Configured, the gate off: the output is 0.
    Closed,
    /// The gate on: the output follows the speed.
    On,
}

/// The path-speed output as the card ran it at its last tick.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PsoStatus {
    /// Off, closed or on.
    pub state: PsoState,
    /// The group (0 while off).
    pub group: usize,
    /// The settings (`v_ref` in counts/s: the group's scale is the host's).
    pub settings: Option<Pso>,
    /// The group's actual tangential speed of the tick, counts/s.
    pub speed_counts: f64,
    /// The output of the tick: V, or the PWM's duty.
    pub value: f64,
}

/// The error of an analog channel the card does not have.
fn no_channel(what: &'static str) -> Error {
    let code = NackCode::AnalogChannel;
    Error::Nack {
        command: what,
        target: Target::Card,
        code,
        reason: crate::nack_reason(code),
    }
}

/// A channel number as the command carries it (the card refuses one it does not have).
fn channel_arg(channel: usize) -> u8 {
    channel.min(u8::MAX as usize) as u8
}

impl Card {
    /// The analog I/O status block of the last tick.
    fn analog_status(&self) -> Result<raw::mc_analog_status> {
        self.inner().link.check()?;
        Ok(layout::ANALOG_STATUS.read(self.window()))
    }

    /// Set analog input `input`'s filter and threshold (`AnalogChannel`, `AnalogFilter`,
    /// `AnalogThreshold`, `NotFinite`). The filter keeps its value; the threshold state is
    /// taken again from it, without an event.
    pub fn configure_analog_input(&self, input: usize, s: &AnalogInputSettings) -> Result<()> {
        let c = IoCmd::AnalogInput(cmd::AnalogInput {
            input: channel_arg(input),
            cutoff_hz: s.cutoff_hz,
            threshold: s.threshold,
            hysteresis: s.hysteresis,
            rise_event: s.rise_event,
            fall_event: s.fall_event,
        });
        let mut c = c.command(0);
        if input > u8::MAX as usize {
            c.args[0] = input as f64;
        }
        self.execute(c, "configure_analog_input", Target::Card)
    }

    /// Analog input `input` as the card sampled it at its last tick.
    pub fn analog_input(&self, input: usize) -> Result<AnalogInput> {
        if input >= ANALOG_INPUTS {
            return Err(no_channel("analog_input"));
        }
        let b = self.analog_status()?;
        Ok(AnalogInput {
            sample: b.input_raw[input],
            value: b.input[input],
            above: b.above & (1 << input) != 0,
            settings: AnalogInputSettings {
                cutoff_hz: b.cutoff_hz[input],
                threshold: b.threshold[input],
                hysteresis: b.hysteresis[input],
                rise_event: b.rise_events & (1 << input) != 0,
                fall_event: b.fall_events & (1 << input) != 0,
            },
        })
    }

    /// Set spare DAC output `output` to `volts` (clamped to ±10 V and quantised by the 12-bit
    /// DAC): the volts it puts out. `AnalogChannel` for an output the card does not have or
    /// one the path-speed output drives, `NotFinite` for NaN.
    pub fn set_analog_output(&self, output: usize, volts: f64) -> Result<f64> {
        let mut c = IoCmd::AnalogOutput(cmd::AnalogOutput {
            output: channel_arg(output),
            volts,
        })
        .command(0);
        if output > u8::MAX as usize {
            c.args[0] = output as f64;
        }
        self.execute_value(c, "set_analog_output", Target::Card)
            .map(|(_, v)| v)
    }

    /// Spare DAC output `output` now, V.
    pub fn analog_output(&self, output: usize) -> Result<f64> {
        if output >= ANALOG_OUTPUTS {
            return Err(no_channel("analog_output"));
        }
        Ok(self.analog_status()?.output[output])
    }

    /// Stop the path-speed output: its output goes to 0 (0 V, or duty 0).
    pub fn pso_off(&self) -> Result<()> {
        self.execute(IoCmd::PsoOff.command(0), "pso_off", Target::Card)
    }

    /// The path-speed output's state, speed and value of the last tick.
    pub fn pso_status(&self) -> Result<PsoStatus> {
        let b = self.analog_status()?;
        let state = match b.pso_state {
            raw::MC_PSO_OFF => PsoState::Off,
            raw::MC_PSO_CLOSED => PsoState::Closed,
            raw::MC_PSO_ON => PsoState::On,
            v => return Err(Error::Protocol(format!("unknown PSO state {v}"))),
        };
        let settings = (state != PsoState::Off).then_some(Pso {
            output: if b.pso_flags & raw::MC_PSO_PWM != 0 {
                PsoOutput::Pwm {
                    output: b.pso_output as usize,
                    hz: b.pso_pwm_hz,
                }
            } else {
                PsoOutput::Dac(b.pso_output as usize)
            },
            gate: b.pso_gate as usize,
            min: b.pso_min,
            max: b.pso_max,
            v_ref: b.pso_v_ref,
            filter_hz: b.pso_filter_hz,
        });
        Ok(PsoStatus {
            state,
            group: b.pso_group as usize,
            settings,
            speed_counts: b.pso_speed,
            value: b.pso_value,
        })
    }
}

impl Card {
    /// Run the card's path-speed output on group `group` ([`Group::pso`]; `v_ref` in counts/s
    /// here). A group the card does not have, or one not configured: `PsoGroup`.
    pub fn pso_counts(&self, group: usize, p: &Pso) -> Result<()> {
        let arg = |x: usize| x.min(u8::MAX as usize) as u8;
        let output = match p.output {
            PsoOutput::Dac(d) => cmd::PsoOutput::Dac(arg(d)),
            PsoOutput::Pwm { output, hz } => cmd::PsoOutput::Pwm {
                output: arg(output),
                hz,
            },
        };
        let c = IoCmd::Pso(cmd::Pso {
            output,
            gate: arg(p.gate),
            min: p.min,
            max: p.max,
            v_ref: p.v_ref,
            filter_hz: p.filter_hz,
        })
        .command(group.min(u16::MAX as usize) as u16);
        self.execute(c, "pso", Target::Group(group))
    }
}

impl Group {
    /// Run the card's path-speed output on this group (configured; else `PsoGroup`):
    /// `clamp(min + (max − min)·v/v_ref, min, max)` from the group's actual tangential speed
    /// `v`, while output `gate` is on; `v_ref` in the group's user units per second. It
    /// replaces a path-speed output running (whose output goes to 0 first). `PsoConfig` for an
    /// argument out of range, `NotFinite` for NaN.
    pub fn pso(&self, p: &Pso) -> Result<()> {
        // A group not configured has no scale: the card refuses it (`PsoGroup`).
        let scale = self.path_scale_pub().unwrap_or(1.0);
        let counts = Pso {
            v_ref: p.v_ref * scale,
            ..*p
        };
        self.card_pub().pso_counts(self.index(), &counts)
    }
}
