//! Digital I/O, position compare and touch probes (layout 1.7), run by the card.
//!
//! - **Inputs**: [`Card::configure_io`] sets each input's polarity and debounce (ticks) and
//!   which debounced edges post an [`EventKind::Input`] event (axis: the input; code 1 rising,
//!   0 falling; value: the debounced word). [`Card::inputs`] reads the debounced word.
//!   Outputs: [`Card::set_outputs`] and [`Card::outputs`] (layout 1.6), and the compare pulses.
//! - **Compare** ([`Axis::compare`]): a channel pulses an output when the axis's actual
//!   position crosses a single position, a linear series, or a table streamed in
//!   ([`CompareChannel::push`], with the room left and a low-water event). The card finds each
//!   crossing's instant within the servo tick from the encoder's motion, so the pulse comes
//!   within a count of the position at any speed; every fire and every missed position is
//!   counted ([`CompareStatus`]) and reported ([`EventKind::Compare`]: code
//!   [`COMPARE_FIRED`], [`COMPARE_MISSED`] or [`COMPARE_LOW_WATER`], value the position in
//!   user units, or the positions queued).
//!   On a rotary axis (layout 1.13) compare is turn-aware: positions are places on the turn,
//!   in `[0, modulo)`, and fire at the axis's crossings on any turn, across the wrap;
//!   [`CompareChannel::arm_single_each_turn`] and [`CompareChannel::arm_series_each_turn`]
//!   fire on every turn, endless (a refusal that does not fit the turn: `CompareTurn`).
//! - **Touch probe** ([`Axis::touch_probe`], PLCopen MC_TouchProbe / MC_AbortTrigger): capture
//!   the axis's position at an input edge or at the encoder's index pulse, interpolated within
//!   the tick; optionally only inside a window; single shot or continuous
//!   ([`EventKind::Probe`]: code the capture number, value the position in user units).
//!
//! Positions are in the axis's user units (see [`Axis::set_scale`]); a negative scale turns the
//! direction over. The card checks every argument again and answers with its own error kinds
//! (`IoChannel`, `CompareMode`, `CompareFull`, `CompareOrder`, `CompareBusy`, `CompareTurn`, `ProbeInput`,
//! `IoConfig`).
//!
//! [`EventKind::Input`]: crate::EventKind::Input
//! [`EventKind::Compare`]: crate::EventKind::Compare
//! [`EventKind::Probe`]: crate::EventKind::Probe

use crate::card::{finite, Axis, Card};
use crate::error::{nack_reason, Error, Result, Target};
use firmware_proto::cmd::{self, CompareKind, IoCmd};
use firmware_proto::{layout, raw, Mem, NackCode, COMPARE_TABLE_MAX, PROBE_QUEUE};
use std::time::Duration;

/// The digital inputs' configuration, the card's `io_config` block: `polarity` (bit i: input
/// i is active low), `rise_events` / `fall_events` (bit i: an event on that debounced edge of
/// input i), `debounce[i]` (ticks input i must hold a new level, 0..=10,000). `Default` is the
/// boot state: active high, no debounce, no events.
pub use firmware_proto::raw::mc_io_config as IoSettings;

/// [`EventKind::Compare`](crate::EventKind::Compare) code: a position fired (value: the last
/// of the tick).
pub const COMPARE_FIRED: i32 = raw::MC_CMP_FIRED as i32;
/// [`EventKind::Compare`](crate::EventKind::Compare) code: a position was missed (passed
/// before it was armed, or inside the pulse before it).
pub const COMPARE_MISSED: i32 = raw::MC_CMP_MISSED as i32;
/// [`EventKind::Compare`](crate::EventKind::Compare) code: the table fell to its low-water
/// mark (value: positions queued).
pub const COMPARE_LOW_WATER: i32 = raw::MC_CMP_LOW_WATER as i32;
/// The card's digital inputs.
pub const INPUTS: usize = firmware_proto::INPUTS;
/// Compare channels per card.
pub const COMPARE_CHANNELS: usize = firmware_proto::COMPARE_CHANNELS;
/// Positions a compare channel's table holds.
pub const COMPARE_TABLE_LEN: usize = firmware_proto::COMPARE_TABLE_LEN;
/// Touch-probe channels per card.
pub const PROBE_CHANNELS: usize = firmware_proto::PROBE_CHANNELS;

impl Card {
    /// Write the inputs' configuration and have the card check and apply it (`IoConfig` for a
    /// bit beyond the 16 inputs or a debounce over 10,000 ticks; the block is put back then).
    /// The debounced word restarts from the inputs as they are.
    pub fn configure_io(&self, settings: &IoSettings) -> Result<()> {
        self.apply_block(
            layout::IO_CONFIG,
            |b| *b = *settings,
            IoCmd::ApplyConfig.command(0),
            "configure_io",
            Target::Card,
        )
    }

    /// The inputs' configuration the card holds (layout 1.8: read back from the card).
    pub fn io_settings(&self) -> Result<IoSettings> {
        self.read_block(layout::IO_CONFIG, firmware_proto::ConfigKind::Io, 0)
    }

    /// The debounced inputs, polarity applied: bit i = input i active.
    pub fn inputs(&self) -> Result<u32> {
        self.inner().link.check()?;
        Ok(self.window().read32(layout::INPUTS))
    }

    /// The inputs as the card sampled them at its last tick, polarity applied, not debounced.
    pub fn inputs_raw(&self) -> Result<u32> {
        self.inner().link.check()?;
        Ok(self.window().read32(layout::INPUTS_RAW))
    }
}

/// Which way a compare position is crossed to fire.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Direction {
    /// Increasing position.
    Positive,
    /// Decreasing position.
    Negative,
    /// Either way (a single position only).
    Either,
}

/// The state of a compare channel or a touch probe.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum IoState {
    /// Not armed.
    Idle,
    /// Armed: firing, or waiting for its trigger or for table positions.
    Armed,
    /// A single compare or a series fired (or missed) all its positions; a single-shot probe
    /// captured.
    Done,
}

impl IoState {
    fn from_raw(v: u32) -> Result<Self> {
        match v {
            raw::MC_IO_IDLE => Ok(Self::Idle),
            raw::MC_IO_ARMED => Ok(Self::Armed),
            raw::MC_IO_DONE => Ok(Self::Done),
            _ => Err(Error::Protocol(format!("unknown compare/probe state {v}"))),
        }
    }
}

/// A compare channel's status, positions in the axis's user units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CompareStatus {
    /// Idle, armed or done.
    pub state: IoState,
    /// Pulses fired since the arm.
    pub fires: u32,
    /// Positions missed since the arm.
    pub missed: u32,
    /// Positions still to come (a table's queue: its room is [`COMPARE_TABLE_LEN`] minus this;
    /// on every turn, endless: the positions of a turn).
    pub pending: u32,
    /// The output pulsed.
    pub output: u32,
    /// The next position.
    pub next: f64,
    /// The last position fired.
    pub last_fired: f64,
    /// When it fired: servo ticks since boot, with the fraction within the tick.
    pub last_fire_tick: f64,
    /// The last position missed.
    pub last_missed: f64,
}

/// One of the card's compare channels, watching an axis ([`Axis::compare`]).
#[derive(Clone)]
pub struct CompareChannel {
    axis: Axis,
    channel: usize,
}

/// The error of a channel the card does not have.
fn no_channel(what: &'static str) -> Error {
    let code = firmware_proto::NackCode::IoChannel;
    Error::Nack {
        command: what,
        target: Target::Card,
        code,
        reason: crate::nack_reason(code),
    }
}

/// A channel number the card might have: the card checks it (`IoChannel`).
/// A channel number as the command carries it (the card refuses one it does not have).
fn channel_arg(channel: usize) -> u8 {
    channel.min(u8::MAX as usize) as u8
}

impl Axis {
    /// Compare channel `channel` (0..[`COMPARE_CHANNELS`]) watching this axis.
    pub fn compare(&self, channel: usize) -> CompareChannel {
        CompareChannel {
            axis: self.clone(),
            channel,
        }
    }

    /// Touch-probe channel `channel` (0..[`PROBE_CHANNELS`]) capturing this axis.
    pub fn touch_probe(&self, channel: usize) -> TouchProbe {
        TouchProbe {
            axis: self.clone(),
            channel,
        }
    }
}

impl CompareChannel {
    /// The channel number.
    pub fn channel(&self) -> usize {
        self.channel
    }

    /// The direction in counts (`None`: either way).
    fn direction(&self, dir: Direction) -> Option<cmd::Direction> {
        let flip = self.axis.scale() < 0.0;
        match (dir, flip) {
            (Direction::Positive, false) | (Direction::Negative, true) => Some(cmd::Direction::Up),
            (Direction::Negative, false) | (Direction::Positive, true) => {
                Some(cmd::Direction::Down)
            }
            (Direction::Either, _) => None,
        }
    }

    /// `MC_OP_COMPARE_ARM`: `kind` in `dir`; output, pulse width, low water; position (or
    /// start), pitch, count in counts; on every turn (`MC_CMP_EACH_TURN`) or not.
    #[allow(clippy::too_many_arguments)]
    fn arm(
        &self,
        kind: CompareKind,
        dir: Direction,
        [output, pulse_us, low_water]: [u32; 3],
        [position, pitch, count]: [f64; 3],
        each_turn: bool,
        what: &'static str,
    ) -> Result<()> {
        let arm = cmd::CompareArm {
            channel: channel_arg(self.channel),
            kind,
            direction: self.direction(dir),
            output: output as f64,
            pulse_us: pulse_us as f64,
            low_water: low_water as f64,
            position,
            pitch,
            count,
            each_turn,
        };
        self.axis
            .run(self.axis.cmd(IoCmd::CompareArm(arm)), what)
            .map(|_| ())
    }

    /// Pulse `output` for `pulse_us` µs when the axis crosses `position` in `dir`. A position
    /// already behind the axis is reported missed. On a rotary axis (layout 1.13) the position
    /// is a place on the turn, in `[0, modulo)` (else `CompareTurn`), and fires at the axis's
    /// next crossing of it on any turn (nothing is behind on a turn).
    pub fn arm_single(
        &self,
        output: u32,
        pulse_us: u32,
        position: f64,
        dir: Direction,
    ) -> Result<()> {
        self.single(output, pulse_us, position, dir, false, "compare_single")
    }

    /// Layout 1.13, a rotary axis: pulse at every crossing of `position` (a place on the turn,
    /// in `[0, modulo)`) in `dir` (Either: both ways), on every turn, until [`Self::disarm`].
    /// The instant is as exact as on a linear axis, across the wrap and after any number of
    /// turns. A linear axis, or a position off the turn: `CompareTurn`.
    pub fn arm_single_each_turn(
        &self,
        output: u32,
        pulse_us: u32,
        position: f64,
        dir: Direction,
    ) -> Result<()> {
        self.single(
            output,
            pulse_us,
            position,
            dir,
            true,
            "compare_single_each_turn",
        )
    }

    /// Pulse at `start`, `start ± pitch`, … (`count` positions, `pitch` > 0 in user units,
    /// stepping in `dir`, which is Positive or Negative). On a rotary axis (layout 1.13) the
    /// positions are wrapped into the turn and must fit in one (`start` in `[0, modulo)`,
    /// `(count − 1)·pitch < modulo`, else `CompareTurn`); each fires at the axis's next
    /// crossing of it after the one before, so a series may run over the wrap.
    pub fn arm_series(
        &self,
        output: u32,
        pulse_us: u32,
        start: f64,
        pitch: f64,
        count: u32,
        dir: Direction,
    ) -> Result<()> {
        let each_turn = false;
        self.series(
            output,
            pulse_us,
            (start, pitch, count),
            dir,
            each_turn,
            "compare_series",
        )
    }

    /// Layout 1.13, a rotary axis: the series of [`Self::arm_series`] on every turn, endless
    /// until [`Self::disarm`]: `count` positions from `start` (in `[0, modulo)`), `pitch`
    /// apart in `dir` and wrapped into the turn, with `count·pitch <= modulo`; `count` 0 is a
    /// whole turn of pitches (`floor(modulo / pitch)`: a camera trigger every 10° is
    /// `arm_series_each_turn(out, 10, 0.0, 10.0, 0, Positive)`). The series is then a set of
    /// places: each fires at every crossing in `dir`, whichever the axis comes to (back and
    /// forth as well). A linear axis, or a series that does not fit the turn: `CompareTurn`.
    pub fn arm_series_each_turn(
        &self,
        output: u32,
        pulse_us: u32,
        start: f64,
        pitch: f64,
        count: u32,
        dir: Direction,
    ) -> Result<()> {
        let each_turn = true;
        let what = "compare_series_each_turn";
        self.series(
            output,
            pulse_us,
            (start, pitch, count),
            dir,
            each_turn,
            what,
        )
    }

    /// A single position, once or on every turn, in user units.
    fn single(
        &self,
        output: u32,
        pulse_us: u32,
        position: f64,
        dir: Direction,
        each_turn: bool,
        what: &'static str,
    ) -> Result<()> {
        finite("compare position", position)?;
        let p = position * self.axis.scale();
        let args = [p, 0.0, 0.0];
        self.arm(
            CompareKind::Single,
            dir,
            [output, pulse_us, 0],
            args,
            each_turn,
            what,
        )
    }

    /// A series `(start, pitch, count)`, once or on every turn, in user units.
    fn series(
        &self,
        output: u32,
        pulse_us: u32,
        (start, pitch, count): (f64, f64, u32),
        dir: Direction,
        each_turn: bool,
        what: &'static str,
    ) -> Result<()> {
        finite("compare start", start)?;
        finite("compare pitch", pitch)?;
        let s = self.axis.scale();
        let args = [start * s, pitch * s.abs(), count as f64];
        self.arm(
            CompareKind::Series,
            dir,
            [output, pulse_us, 0],
            args,
            each_turn,
            what,
        )
    }

    /// Fire at the positions of the table in order (queued before with [`Self::push`], or
    /// after), moving in `dir` (Positive or Negative); a compare event with code
    /// [`COMPARE_LOW_WATER`] when the queue falls to `low_water` (0: none). The table stays
    /// queued from one arm to the next until [`Self::disarm`]. On a rotary axis (layout 1.13)
    /// the positions are places on the turn (`[0, modulo)`, else `CompareTurn`), each fired
    /// once at the axis's next crossing of it after the one before; pushed while armed there
    /// they may come in any order (the same place twice: a turn later).
    pub fn arm_table(
        &self,
        output: u32,
        pulse_us: u32,
        low_water: u32,
        dir: Direction,
    ) -> Result<()> {
        self.arm(
            CompareKind::Table,
            dir,
            [output, pulse_us, low_water],
            [0.0; 3],
            false,
            "compare_table",
        )
    }

    /// Queue positions (user units, strictly monotonic in `dir`) in the channel's table, in
    /// entries of up to 12. All or nothing per entry: a full table is `CompareFull` (the
    /// positions of the entries before it stay queued). Returns the room left.
    pub fn push(&self, dir: Direction, positions: &[f64]) -> Result<usize> {
        for &p in positions {
            finite("compare position", p)?;
        }
        let s = self.axis.scale();
        let mut room = self.room()?;
        for chunk in positions.chunks(COMPARE_TABLE_MAX) {
            // A table runs one way: the card refuses either way (`CompareMode`).
            let direction = self.direction(dir).ok_or(Error::Refused {
                command: "compare_push",
                target: Target::Card,
                code: NackCode::CompareMode,
                reason: nack_reason(NackCode::CompareMode),
            })?;
            let table = cmd::CompareTable {
                channel: channel_arg(self.channel),
                direction,
                // At most COMPARE_TABLE_MAX positions (the chunk).
                positions: chunk.iter().map(|p| p * s).collect(),
            };
            let cmd = self.axis.cmd(IoCmd::CompareTable(table));
            let (_, v) = self
                .axis
                .card()
                .execute_value(cmd, "compare_push", Target::Card)?;
            room = v as usize;
        }
        Ok(room)
    }

    /// Free room in the table now.
    pub fn room(&self) -> Result<usize> {
        Ok(COMPARE_TABLE_LEN.saturating_sub(self.status()?.pending as usize))
    }

    /// Stop the channel, drop its table, end its pulse.
    pub fn disarm(&self) -> Result<()> {
        let disarm = cmd::CompareDisarm {
            channel: channel_arg(self.channel),
        };
        let cmd = self.axis.cmd(IoCmd::CompareDisarm(disarm));
        self.axis
            .card()
            .execute(cmd, "compare_disarm", Target::Card)
    }

    /// The channel's status, positions in user units.
    pub fn status(&self) -> Result<CompareStatus> {
        let card = self.axis.card();
        card.inner().link.check()?;
        let b = layout::COMPARE_STATUS
            .try_at(self.channel)
            .ok_or_else(|| no_channel("compare_status"))?
            .read(card.window());
        let s = self.axis.scale();
        Ok(CompareStatus {
            state: IoState::from_raw(b.state)?,
            fires: b.fires,
            missed: b.missed,
            pending: b.pending,
            output: b.output,
            next: b.next / s,
            last_fired: b.last_fired / s,
            last_fire_tick: b.last_fire_tick,
            last_missed: b.last_missed / s,
        })
    }
}

/// What a touch probe captures at.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ProbeTrigger {
    /// The input (0..16), or `None` for the axis's encoder index pulse.
    pub input: Option<u32>,
    /// Capture on a rising edge (the input becoming active).
    pub rising: bool,
    /// Capture on a falling edge.
    pub falling: bool,
    /// Keep capturing (a ring of the last 8 in the status, and an event each); else one.
    pub continuous: bool,
    /// Only edges with the position in `[lo, hi]` (user units) count.
    pub window: Option<(f64, f64)>,
    /// The capture halts the axis's motion, by the card in the tick it detects it: the
    /// axis's group halts along its path on its members' stop ramps (its queued path dropped),
    /// or the axis alone on its stop ramp; stop reason [`crate::StopReason::Probe`]. A
    /// probing move (G38) is made of this.
    pub halt: bool,
}

impl ProbeTrigger {
    /// A single capture at the rising edge of `input`.
    pub fn rising(input: u32) -> Self {
        Self {
            input: Some(input),
            rising: true,
            falling: false,
            continuous: false,
            window: None,
            halt: false,
        }
    }

    /// A single capture at the index pulse.
    pub fn index() -> Self {
        Self {
            input: None,
            ..Self::rising(0)
        }
    }
}

/// A touch-probe status, positions in user units.
#[derive(Debug, Clone, PartialEq)]
pub struct ProbeStatus {
    /// Idle, armed, or done (a single shot captured).
    pub state: IoState,
    /// Captures since the arm.
    pub captures: u32,
    /// Edges outside the window since the arm.
    pub outside: u32,
    /// The last captures, oldest first (up to 8).
    pub positions: Vec<f64>,
    /// When the last capture was: servo ticks since boot, with the fraction.
    pub last_tick: f64,
}

/// One of the card's touch-probe channels, capturing an axis ([`Axis::touch_probe`]).
#[derive(Clone)]
pub struct TouchProbe {
    axis: Axis,
    channel: usize,
}

impl TouchProbe {
    /// MC_TouchProbe: arm (again: a re-arm restarts the count).
    pub fn arm(&self, t: &ProbeTrigger) -> Result<()> {
        let s = self.axis.scale();
        let mut window = None;
        if let Some((a, b)) = t.window {
            finite("window", a)?;
            finite("window", b)?;
            window = Some(if s < 0.0 {
                (b * s, a * s)
            } else {
                (a * s, b * s)
            });
        }
        let arm = cmd::ProbeArm {
            channel: channel_arg(self.channel),
            // An input the card does not have is refused by it (`ProbeInput`).
            input: t.input.unwrap_or(raw::MC_PROBE_INDEX).min(u8::MAX as u32) as u8,
            rising: t.rising,
            falling: t.falling,
            continuous: t.continuous,
            window,
            halt: t.halt,
        };
        self.axis
            .run(self.axis.cmd(IoCmd::ProbeArm(arm)), "touch_probe")
            .map(|_| ())
    }

    /// MC_AbortTrigger.
    pub fn abort(&self) -> Result<()> {
        let abort = cmd::ProbeAbort {
            channel: channel_arg(self.channel),
        };
        let cmd = self.axis.cmd(IoCmd::ProbeAbort(abort));
        self.axis.card().execute(cmd, "abort_trigger", Target::Card)
    }

    /// The probe's status, positions in user units.
    pub fn status(&self) -> Result<ProbeStatus> {
        let card = self.axis.card();
        card.inner().link.check()?;
        let b = layout::PROBE_STATUS
            .try_at(self.channel)
            .ok_or_else(|| no_channel("probe_status"))?
            .read(card.window());
        let s = self.axis.scale();
        let n = (b.captures as usize).min(PROBE_QUEUE);
        let positions = (0..n)
            .map(|k| {
                let i = (b.captures as usize - n + k) % PROBE_QUEUE;
                b.position[i] / s
            })
            .collect();
        Ok(ProbeStatus {
            state: IoState::from_raw(b.state)?,
            captures: b.captures,
            outside: b.outside,
            positions,
            last_tick: b.last_tick,
        })
    }

    /// Wait for capture number `n` (1, 2, … since the arm) and give its position (user
    /// units), or `Timeout` (emulated time on a stepped card). A capture older than the last
    /// 8 is gone: `Protocol`.
    pub fn wait_capture(&self, n: u32, timeout: Duration) -> Result<f64> {
        self.axis.card().wait_window(timeout, || {
            let st = match self.status() {
                Ok(st) => st,
                Err(e) => return Some(Err(e)),
            };
            if st.captures < n {
                return None;
            }
            let back = (st.captures - n) as usize;
            Some(
                st.positions
                    .len()
                    .checked_sub(back + 1)
                    .map(|i| st.positions[i])
                    .ok_or_else(|| Error::Protocol(format!("capture {n} left the probe's queue"))),
            )
        })
    }
}

#[cfg(feature = "emulator")]
impl crate::Sim {
    /// Drive input `input`'s pin of the stepped card to `high` (it changes now, the end of
    /// the period the card samples next). A sensor on that input is removed.
    pub fn set_input(&self, input: usize, high: bool) {
        self.with_emulator(|e| e.inputs().set(input, high));
    }

    /// Drive input `input` from a sensor on an axis's travel (`None`: a level again).
    pub fn set_sensor(&self, input: usize, sensor: Option<card_emu::Sensor>) {
        self.with_emulator(|e| e.inputs().set_sensor(input, sensor));
    }

    /// Record the compare pulses, with where the shaft was at each one (`false`: stop).
    pub fn record_fires(&self, on: bool) {
        self.with_emulator(|e| e.record_fires(on));
    }

    /// The compare pulses recorded since the last call.
    pub fn take_fires(&self) -> Vec<card_emu::FireRecord> {
        self.with_emulator(|e| e.take_fires())
    }
}
