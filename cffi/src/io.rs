//! Digital inputs, position compare ("EQU" outputs) and touch probes (PLCopen MC_TouchProbe,
//! MC_AbortTrigger), layout 1.7. The same thin skin as [`crate::api`]: check the pointers, look
//! the handle up, call the SDK, write the outputs, all inside `guard`.

use crate::api::{axis_of, ms};
use crate::codes::{
    MC_IO_STATE_ARMED, MC_IO_STATE_DONE, MC_IO_STATE_IDLE, MC_PROBE_EDGE_FALLING,
    MC_PROBE_EDGE_RISING, MC_PROBE_INPUT_INDEX,
};
use crate::ffi::{read_in, read_slice, Out};
use crate::registry::{self, mc_card};
use crate::result::{guard, mc_result, unknown};
use motioncard_sdk::{
    CompareStatus, Direction, IoSettings, IoState, ProbeStatus, ProbeTrigger, COMPARE_TABLE_LEN,
};

/// The digital inputs' configuration: the card's `mc_io_config` register block. `polarity`
/// bit i: input i is active low; `rise_events` / `fall_events` bit i: an `MC_EVENT_INPUT` on
/// that debounced edge of input i; `debounce[i]`: the ticks input i must hold a new level
/// before the debounced word takes it (0..10000). Start from `mc_io_settings_default`.
#[allow(non_camel_case_types)]
pub type mc_io_settings = firmware_proto::raw::mc_io_config;

/// Compare direction: fire crossing upwards (increasing position).
pub const MC_COMPARE_POSITIVE: u32 = 1;
/// Compare direction: fire crossing downwards.
pub const MC_COMPARE_NEGATIVE: u32 = 2;
/// Compare direction: either way (`mc_compare_single` only).
pub const MC_COMPARE_EITHER: u32 = 3;

/// A compare channel's status (`mc_compare_get_status`), positions in the axis's user units.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[allow(non_camel_case_types)]
pub struct mc_compare_info {
    /// `MC_IO_STATE_` value.
    pub state: u32,
    /// Pulses fired since the arm.
    pub fires: u32,
    /// Positions missed since the arm.
    pub missed: u32,
    /// Positions still to come (a table's queue).
    pub pending: u32,
    /// The output pulsed.
    pub output: u32,
    /// The next position.
    pub next: f64,
    /// The last position fired.
    pub last_fired: f64,
    /// When: servo ticks since boot, with the fraction within the tick.
    pub last_fire_tick: f64,
    /// The last position missed.
    pub last_missed: f64,
}

/// What a touch probe captures at (`mc_touch_probe`).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[allow(non_camel_case_types)]
pub struct mc_probe_trigger {
    /// The input (0..15), or `MC_PROBE_INPUT_INDEX`.
    pub input: u32,
    /// `MC_PROBE_EDGE_` bits (one or both).
    pub edges: u32,
    /// Nonzero: keep capturing (the last `MC_PROBE_QUEUE` in the status); 0: one capture.
    pub continuous: u32,
    /// Nonzero: only edges with the position in `[window_lo, window_hi]` count.
    pub use_window: u32,
    /// The window, user units.
    pub window_lo: f64,
    /// The window, user units.
    pub window_hi: f64,
    /// Nonzero: the capture halts the axis's motion, by the card in the tick it sees it (its
    /// group along the path on the members' stop ramps, or the axis on its stop ramp; stop
    /// reason `MC_STOP_PROBE`): a probing move.
    pub halt: u32,
}

/// A touch probe's status (`mc_probe_get_status`), positions in user units.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[allow(non_camel_case_types)]
pub struct mc_probe_info {
    /// `MC_IO_STATE_` value.
    pub state: u32,
    /// Captures since the arm.
    pub captures: u32,
    /// Edges outside the window since the arm.
    pub outside: u32,
    /// How many of `positions` hold captures (up to `MC_PROBE_QUEUE`).
    pub count: u32,
    /// The last captures, oldest first.
    pub positions: [f64; 8],
    /// When the last capture was: servo ticks since boot, with the fraction.
    pub last_tick: f64,
}

fn state_code(s: IoState) -> u32 {
    match s {
        IoState::Idle => MC_IO_STATE_IDLE,
        IoState::Armed => MC_IO_STATE_ARMED,
        IoState::Done => MC_IO_STATE_DONE,
    }
}

fn direction(d: u32, either: bool) -> Result<Direction, crate::result::Failure> {
    match d {
        MC_COMPARE_POSITIVE => Ok(Direction::Positive),
        MC_COMPARE_NEGATIVE => Ok(Direction::Negative),
        MC_COMPARE_EITHER if either => Ok(Direction::Either),
        _ => Err(unknown("compare direction", d)),
    }
}

/// Arm compare channel `channel` of `axis` with `f`, given the direction `direction_`
/// (`either`: `MC_COMPARE_EITHER` allowed). Blocks until the card answers.
fn arm(
    card: mc_card,
    axis: u32,
    channel: u32,
    direction_: u32,
    either: bool,
    f: impl FnOnce(&motioncard_sdk::CompareChannel, Direction) -> motioncard_sdk::Result<()>,
) -> mc_result {
    guard(|| {
        let d = direction(direction_, either)?;
        let (_, a) = axis_of(card, axis)?;
        Ok(f(&a.compare(channel as usize), d)?)
    })
}

impl From<&CompareStatus> for mc_compare_info {
    fn from(s: &CompareStatus) -> Self {
        Self {
            state: state_code(s.state),
            fires: s.fires,
            missed: s.missed,
            pending: s.pending,
            output: s.output,
            next: s.next,
            last_fired: s.last_fired,
            last_fire_tick: s.last_fire_tick,
            last_missed: s.last_missed,
        }
    }
}

impl From<&ProbeStatus> for mc_probe_info {
    fn from(s: &ProbeStatus) -> Self {
        let mut positions = [0.0; 8];
        for (p, v) in positions.iter_mut().zip(&s.positions) {
            *p = *v;
        }
        Self {
            state: state_code(s.state),
            captures: s.captures,
            outside: s.outside,
            count: s.positions.len().min(8) as u32,
            positions,
            last_tick: s.last_tick,
        }
    }
}

/// The inputs' configuration the card loads at boot: all active high, no debounce, no events.
/// Never blocks.
#[no_mangle]
pub unsafe extern "C" fn mc_io_settings_default(settings: *mut mc_io_settings) -> mc_result {
    guard(|| {
        let out = Out::new(settings, "settings")?;
        // SAFETY: checked non-NULL; valid for writes by the caller's contract.
        unsafe { out.write(IoSettings::default()) };
        Ok(())
    })
}

/// Write the inputs' configuration and have the card apply it: a bit beyond the 16 inputs or a
/// debounce over 10000 ticks is `MC_ERR_IO_CONFIG`. Blocks until the card answers.
#[no_mangle]
pub unsafe extern "C" fn mc_configure_io(
    card: mc_card,
    settings: *const mc_io_settings,
) -> mc_result {
    guard(|| {
        // SAFETY: the caller gives NULL or a readable mc_io_settings.
        let s = unsafe { read_in(settings, "settings") }?;
        Ok(registry::get(card)?.card.configure_io(&s)?)
    })
}

/// The debounced inputs, polarity applied (bit i = input i active). Never blocks.
#[no_mangle]
pub unsafe extern "C" fn mc_get_inputs(card: mc_card, inputs: *mut u32) -> mc_result {
    guard(|| {
        let out = Out::new(inputs, "inputs")?;
        let v = registry::get(card)?.card.inputs()?;
        // SAFETY: checked non-NULL; valid for writes by the caller's contract.
        unsafe { out.write(v) };
        Ok(())
    })
}

/// Arm compare channel `channel` on `axis`: pulse `output` for `pulse_us` µs when the actual
/// position crosses `position` (user units) in `direction` (`MC_COMPARE_`). A position behind
/// the axis is reported missed. `MC_ERR_COMPARE_BUSY` if the channel is armed or its output is
/// another armed channel's. Blocks until the card answers.
#[no_mangle]
pub extern "C" fn mc_compare_single(
    card: mc_card,
    axis: u32,
    channel: u32,
    output: u32,
    pulse_us: u32,
    position: f64,
    direction_: u32,
) -> mc_result {
    arm(card, axis, channel, direction_, true, |c, d| {
        c.arm_single(output, pulse_us, position, d)
    })
}

/// Layout 1.13, a rotary axis: pulse `output` at every crossing of `position` (a place on the
/// turn, 0 <= position < modulo, user units) in `direction`, on every turn, until
/// `mc_compare_disarm`. A linear axis or a position off the turn: `MC_ERR_COMPARE_TURN`.
/// Blocks until the card answers.
#[no_mangle]
pub extern "C" fn mc_compare_single_each_turn(
    card: mc_card,
    axis: u32,
    channel: u32,
    output: u32,
    pulse_us: u32,
    position: f64,
    direction_: u32,
) -> mc_result {
    arm(card, axis, channel, direction_, true, |c, d| {
        c.arm_single_each_turn(output, pulse_us, position, d)
    })
}

/// Arm a linear series: `count` positions from `start`, `pitch` (> 0, user units) apart in
/// `direction` (`MC_COMPARE_POSITIVE` or `_NEGATIVE`). On a rotary axis (layout 1.13) the
/// positions wrap into the turn and must fit one (`MC_ERR_COMPARE_TURN`), each fired at the
/// next crossing after the one before. Blocks until the card answers.
#[no_mangle]
pub extern "C" fn mc_compare_series(
    card: mc_card,
    axis: u32,
    channel: u32,
    output: u32,
    pulse_us: u32,
    start: f64,
    pitch: f64,
    count: u32,
    direction_: u32,
) -> mc_result {
    arm(card, axis, channel, direction_, false, |c, d| {
        c.arm_series(output, pulse_us, start, pitch, count, d)
    })
}

/// Layout 1.13, a rotary axis: the series of `mc_compare_series` on every turn, endless until
/// `mc_compare_disarm`: `count` positions from `start` (0 <= start < modulo), `pitch` apart in
/// `direction`, wrapped into the turn, with count * pitch <= modulo; `count` 0: a whole turn of
/// pitches (floor(modulo / pitch)). Each place fires at every crossing, whichever the axis
/// comes to (back and forth as well). A linear axis or a series that does not fit the turn:
/// `MC_ERR_COMPARE_TURN`. Blocks until the card answers.
#[no_mangle]
pub extern "C" fn mc_compare_series_each_turn(
    card: mc_card,
    axis: u32,
    channel: u32,
    output: u32,
    pulse_us: u32,
    start: f64,
    pitch: f64,
    count: u32,
    direction_: u32,
) -> mc_result {
    arm(card, axis, channel, direction_, false, |c, d| {
        c.arm_series_each_turn(output, pulse_us, start, pitch, count, d)
    })
}

/// Arm the channel's table (positions queued before with `mc_compare_push`, or after), in
/// `direction`; an `MC_EVENT_COMPARE` with code `MC_COMPARE_LOW_WATER` when the queue falls to
/// `low_water` (0: none). Blocks until the card answers.
#[no_mangle]
pub extern "C" fn mc_compare_table(
    card: mc_card,
    axis: u32,
    channel: u32,
    output: u32,
    pulse_us: u32,
    low_water: u32,
    direction_: u32,
) -> mc_result {
    arm(card, axis, channel, direction_, false, |c, d| {
        c.arm_table(output, pulse_us, low_water, d)
    })
}

/// Queue `n` positions (user units, strictly monotonic in `direction`) in the channel's table
/// and write the room left to `*room` (may be NULL). More than `MC_COMPARE_TABLE_LEN` at once
/// is `MC_ERR_COMPARE_FULL` before anything is sent; a table that fills up is
/// `MC_ERR_COMPARE_FULL` (the entries of 12 before it stay queued); out of order
/// `MC_ERR_COMPARE_ORDER`. Blocks until the card answers each entry.
#[no_mangle]
pub unsafe extern "C" fn mc_compare_push(
    card: mc_card,
    axis: u32,
    channel: u32,
    direction_: u32,
    positions: *const f64,
    n: usize,
    room: *mut usize,
) -> mc_result {
    guard(|| {
        let out = Out::optional(room);
        let d = direction(direction_, false)?;
        if n > COMPARE_TABLE_LEN {
            return Err(motioncard_sdk::Error::Nack {
                command: "compare_push",
                target: motioncard_sdk::Target::Card,
                code: motioncard_sdk::NackCode::CompareFull,
                reason: motioncard_sdk::nack_reason(motioncard_sdk::NackCode::CompareFull),
            }
            .into());
        }
        // SAFETY: the caller gives NULL (n = 0) or `n` readable doubles; n is bounded above.
        let p = unsafe { read_slice(positions, n, "positions") }?;
        let (_, a) = axis_of(card, axis)?;
        let left = a.compare(channel as usize).push(d, &p)?;
        if let Some(out) = out {
            // SAFETY: non-NULL; valid for writes by the caller's contract.
            unsafe { out.write(left) };
        }
        Ok(())
    })
}

/// Disarm the channel, drop its table, end its pulse. Blocks until the card answers.
#[no_mangle]
pub extern "C" fn mc_compare_disarm(card: mc_card, axis: u32, channel: u32) -> mc_result {
    guard(|| {
        let (_, a) = axis_of(card, axis)?;
        Ok(a.compare(channel as usize).disarm()?)
    })
}

/// The channel's status, positions in `axis`'s user units. Never blocks.
#[no_mangle]
pub unsafe extern "C" fn mc_compare_get_status(
    card: mc_card,
    axis: u32,
    channel: u32,
    status: *mut mc_compare_info,
) -> mc_result {
    guard(|| {
        let out = Out::new(status, "status")?;
        let (_, a) = axis_of(card, axis)?;
        let s = a.compare(channel as usize).status()?;
        // SAFETY: checked non-NULL; valid for writes by the caller's contract.
        unsafe { out.write((&s).into()) };
        Ok(())
    })
}

/// MC_TouchProbe: arm probe `channel` to capture `axis`'s position at `trigger` (a re-arm
/// restarts it). A bad input, no edge, or a window with `window_lo > window_hi` is
/// `MC_ERR_PROBE_INPUT`. Blocks until the card answers.
#[no_mangle]
pub unsafe extern "C" fn mc_touch_probe(
    card: mc_card,
    axis: u32,
    channel: u32,
    trigger: *const mc_probe_trigger,
) -> mc_result {
    guard(|| {
        // SAFETY: the caller gives NULL or a readable mc_probe_trigger.
        let t = unsafe { read_in(trigger, "trigger") }?;
        if t.edges & !(MC_PROBE_EDGE_RISING | MC_PROBE_EDGE_FALLING) != 0 {
            return Err(unknown("probe edges", t.edges));
        }
        let (_, a) = axis_of(card, axis)?;
        let trig = ProbeTrigger {
            input: (t.input != MC_PROBE_INPUT_INDEX).then_some(t.input),
            rising: t.edges & MC_PROBE_EDGE_RISING != 0,
            falling: t.edges & MC_PROBE_EDGE_FALLING != 0,
            continuous: t.continuous != 0,
            window: (t.use_window != 0).then_some((t.window_lo, t.window_hi)),
            halt: t.halt != 0,
        };
        Ok(a.touch_probe(channel as usize).arm(&trig)?)
    })
}

/// MC_AbortTrigger. Blocks until the card answers.
#[no_mangle]
pub extern "C" fn mc_abort_trigger(card: mc_card, axis: u32, channel: u32) -> mc_result {
    guard(|| {
        let (_, a) = axis_of(card, axis)?;
        Ok(a.touch_probe(channel as usize).abort()?)
    })
}

/// The probe's status, positions in `axis`'s user units. Never blocks.
#[no_mangle]
pub unsafe extern "C" fn mc_probe_get_status(
    card: mc_card,
    axis: u32,
    channel: u32,
    status: *mut mc_probe_info,
) -> mc_result {
    guard(|| {
        let out = Out::new(status, "status")?;
        let (_, a) = axis_of(card, axis)?;
        let s = a.touch_probe(channel as usize).status()?;
        // SAFETY: checked non-NULL; valid for writes by the caller's contract.
        unsafe { out.write((&s).into()) };
        Ok(())
    })
}

/// Wait up to `timeout_ms` (emulated time on a stepped sim) for capture number `n` (1, 2, …
/// since the arm) and write its position (user units). `MC_ERR_TIMEOUT` if it does not come.
/// Blocks.
#[no_mangle]
pub unsafe extern "C" fn mc_probe_wait(
    card: mc_card,
    axis: u32,
    channel: u32,
    n: u32,
    timeout_ms: u32,
    position: *mut f64,
) -> mc_result {
    guard(|| {
        let out = Out::new(position, "position")?;
        let (_, a) = axis_of(card, axis)?;
        let p = a
            .touch_probe(channel as usize)
            .wait_capture(n, ms(timeout_ms))?;
        // SAFETY: checked non-NULL; valid for writes by the caller's contract.
        unsafe { out.write(p) };
        Ok(())
    })
}

/// Stepped sim: drive input `input`'s pin to `high` (nonzero) now. `MC_ERR_UNSUPPORTED` on any
/// other card. Never blocks.
#[no_mangle]
pub extern "C" fn mc_sim_set_input(card: mc_card, input: u32, high: u32) -> mc_result {
    guard(|| {
        #[cfg(feature = "emulator")]
        {
            crate::api::sim_of(card)?.set_input(input as usize, high != 0);
            Ok(())
        }
        #[cfg(not(feature = "emulator"))]
        {
            let _ = (card, input, high);
            Err(crate::api::no_emulator())
        }
    })
}

/// Stepped sim: drive input `input` from a sensor on `axis`'s travel that is active at and
/// above (`active_above` nonzero) or at and below shaft position `at` (counts): a part a touch
/// probe hits. `MC_ERR_UNSUPPORTED` on any other card. Never blocks.
#[no_mangle]
pub extern "C" fn mc_sim_set_sensor(
    card: mc_card,
    input: u32,
    axis: u32,
    at: f64,
    active_above: u32,
) -> mc_result {
    guard(|| {
        #[cfg(feature = "emulator")]
        {
            let s = motioncard_sdk::Sensor {
                axis: axis as usize,
                at,
                active_above: active_above != 0,
            };
            crate::api::sim_of(card)?.set_sensor(input as usize, Some(s));
            Ok(())
        }
        #[cfg(not(feature = "emulator"))]
        {
            let _ = (card, input, axis, at, active_above);
            Err(crate::api::no_emulator())
        }
    })
}
