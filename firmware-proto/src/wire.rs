//! Encodings of what crosses the window: commands, events, status payloads, and the code enums.
//!
//! Each entry is moved as 64-bit words (`to_words` / `from_words`); decoding never fails, and the
//! meaning of a decoded value (is the opcode known, is the axis in range) is checked by whoever
//! acts on it.

use crate::raw;

// The code enums whose variants are the header's defines, generated from it.
pub use crate::codes::{
    AxisState, ConfigKind, EventKind, GroupState, HomingError, NackCode, Opcode, StopCategory,
    StopReason,
};

/// Arguments per command.
pub const CMD_ARGS: usize = raw::MC_CMD_ARGS as usize;
/// Words per command entry.
pub const CMD_WORDS: usize = crate::layout::CMD_BYTES / 8;
/// Words per event entry.
pub const EVT_WORDS: usize = crate::layout::EVT_BYTES / 8;
/// Values per NURBS data entry.
pub const NURBS_DATA_MAX: usize = raw::MC_NURBS_DATA_MAX as usize;
/// Axes whose limits one `GroupPtpLimits` entry stages.
pub const PTP_LIMITS_MAX: usize = raw::MC_PTP_LIMITS_MAX as usize;
/// Words of a status payload.
pub const STATUS_WORDS: usize = crate::layout::STATUS_WORDS;

impl ConfigKind {
    /// Is the index an axis (else a group, or 0 for a card-wide block)?
    pub fn per_axis(self) -> bool {
        matches!(
            self,
            Self::Axis | Self::AxisFilter | Self::AxisSafety | Self::AxisHoming
        )
    }

    /// Is the index a group?
    pub fn per_group(self) -> bool {
        matches!(self, Self::Group | Self::GroupPath)
    }
}

/// A group's status, published under a seqlock like the axes': the header's
/// `mc_group_status_payload` (its fields are listed there).
pub type GroupStatus = raw::mc_group_status_payload;

impl raw::mc_group_status_payload {
    /// The payload as words, in place (its checksum word as it is, not computed).
    #[inline]
    pub fn as_words(&self) -> &[u64; STATUS_WORDS] {
        crate::block::as_words(self)
    }

    /// Encode as words, with the checksum in the last word.
    #[inline]
    pub fn to_words(&self) -> [u64; STATUS_WORDS] {
        let mut w = crate::block::to_words(self);
        w[STATUS_WORDS - 1] = status_checksum(&w);
        w
    }

    /// Decode; `None` when the checksum does not match. The checksum field of the result is
    /// 0: it has been checked.
    pub fn from_words(w: &[u64; STATUS_WORDS]) -> Option<Self> {
        if status_checksum(w) != w[STATUS_WORDS - 1] {
            return None;
        }
        let mut s: Self = crate::block::from_words(w);
        s.checksum = 0;
        Some(s)
    }

    /// The state, if known.
    pub fn state(&self) -> Option<GroupState> {
        GroupState::from_raw(self.state)
    }
}

/// Flags of the group move commands: the shifts of the multi-bit fields, and the single-bit
/// flags of [`MoveFlags`] as plain words for code that tests a raw [`Command::flags`].
pub mod move_flags {
    use super::MoveFlags;
    use crate::raw;
    /// Targets are relative to the start of the move.
    pub const RELATIVE: u32 = MoveFlags::RELATIVE.bits();
    /// Queue behind the moves already queued.
    pub const BUFFERED: u32 = MoveFlags::BUFFERED.bits();
    /// Shift of the 2-bit circle mode (`MC_CIRC_BY_*`).
    pub const CIRC_MODE_SHIFT: u32 = raw::MC_CIRC_MODE_SHIFT;
    /// Counter-clockwise (else clockwise).
    pub const CIRC_CCW: u32 = MoveFlags::CIRC_CCW.bits();
    /// Shift of the 2-bit plane (`MC_PLANE_*`).
    pub const PLANE_SHIFT: u32 = raw::MC_CIRC_PLANE_SHIFT;
    /// `MC_PLANE_AXES`: shifts of the 3-bit group axes u and v of the plane.
    pub const CIRC_U_SHIFT: u32 = raw::MC_CIRC_U_SHIFT;
    /// See [`CIRC_U_SHIFT`].
    pub const CIRC_V_SHIFT: u32 = raw::MC_CIRC_V_SHIFT;
    /// Helical targets are distances even in an absolute move.
    pub const CIRC_HELIX_RELATIVE: u32 = MoveFlags::CIRC_HELIX_RELATIVE.bits();
    /// Saturation-aware feed for a NURBS move (Yeh §3.4).
    pub const NURBS_SATURATION: u32 = MoveFlags::NURBS_SATURATION.bits();
    /// Shift of the 2-bit feed type (`MC_FEED_*`).
    pub const FEED_TYPE_SHIFT: u32 = raw::MC_FEED_TYPE_SHIFT;
    /// Point-to-point: every axis also within the limits staged for it.
    pub const PTP_AXIS_LIMITS: u32 = MoveFlags::PTP_AXIS_LIMITS.bits();
}

/// The flags of the path opcodes (`MC_OP_PATH_LINE`, `_ARC`, `_DWELL`, `_OUTPUT`). Lines and arcs
/// also take [`move_flags::RELATIVE`] and the circle bits of [`move_flags`].
pub mod path_flags {
    use crate::raw;
    /// Shift of the 3-bit PLCopen buffer mode (`MC_PATH_ABORTING` … `MC_PATH_BLEND_HIGH`).
    pub const BUFFER_SHIFT: u32 = raw::MC_PATH_BUFFER_SHIFT;
    /// Shift of the 2-bit transition mode (`MC_TM_*`).
    pub const TRANSITION_SHIFT: u32 = raw::MC_PATH_TRANSITION_SHIFT;
    /// The last segment of a program: its stop is the end, not starvation.
    pub const LAST: u32 = raw::MC_PATH_LAST;
    /// The buffer mode of a segment's flags.
    pub fn buffer(flags: u32) -> u32 {
        (flags >> BUFFER_SHIFT) & 7
    }
    /// The transition mode of a segment's flags.
    pub fn transition(flags: u32) -> u32 {
        (flags >> TRANSITION_SHIFT) & 3
    }
}

/// `MC_SET_POSITION_RELATIVE`: MC_SetPosition moves the position by its argument (else the
/// position becomes it).
pub const SET_POSITION_RELATIVE: u32 = raw::MC_SET_POSITION_RELATIVE;

bitflags::bitflags! {
    /// `mc_axis_homing.flags` (`MC_HOMING_*`).
    #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
    pub struct HomingFlags: u32 {
        /// The encoder has an index channel (the index methods need it).
        const INDEX = raw::MC_HOMING_INDEX;
        /// End at the home point (else where the axis came to rest after finding it).
        const MOVE_TO_HOME = raw::MC_HOMING_MOVE_TO_HOME;
    }
}

impl StopReason {
    /// A stop made by the safety layer (not by a command or the end of a move).
    pub fn is_safety(self) -> bool {
        self as u32 >= raw::MC_STOP_WATCHDOG
    }
}

/// A command entry.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Command {
    /// Sequence number, echoed by the ack or nack.
    pub seq: u32,
    /// Raw opcode ([`Opcode`] when known).
    pub opcode: u16,
    /// Axis number.
    pub axis: u16,
    /// Flags (per opcode).
    pub flags: u32,
    /// The host time (`host.host_time_ms`) after which the card refuses the command with
    /// [`NackCode::Expired`]; 0: no deadline.
    pub deadline_ms: u32,
    /// Arguments.
    pub args: [f64; CMD_ARGS],
}

impl Command {
    /// A command with all arguments zero.
    pub fn new(opcode: Opcode, axis: u16) -> Self {
        Self {
            seq: 0,
            opcode: opcode as u16,
            axis,
            flags: 0,
            deadline_ms: 0,
            args: [0.0; CMD_ARGS],
        }
    }

    /// With the first arguments set.
    pub fn with_args(mut self, args: &[f64]) -> Self {
        for (dst, src) in self.args.iter_mut().zip(args) {
            *dst = *src;
        }
        self
    }

    /// Encode as words.
    pub fn to_words(&self) -> [u64; CMD_WORDS] {
        let mut w = [0u64; CMD_WORDS];
        w[0] = self.seq as u64 | (self.opcode as u64) << 32 | (self.axis as u64) << 48;
        w[1] = self.flags as u64 | (self.deadline_ms as u64) << 32;
        for (dst, a) in w[2..].iter_mut().zip(self.args.iter()) {
            *dst = a.to_bits();
        }
        w
    }

    /// Decode from words (any bit pattern decodes).
    pub fn from_words(w: &[u64; CMD_WORDS]) -> Self {
        let mut args = [0.0; CMD_ARGS];
        for (dst, src) in args.iter_mut().zip(w[2..].iter()) {
            *dst = f64::from_bits(*src);
        }
        Self {
            seq: w[0] as u32,
            opcode: (w[0] >> 32) as u16,
            axis: (w[0] >> 48) as u16,
            flags: w[1] as u32,
            deadline_ms: (w[1] >> 32) as u32,
            args,
        }
    }
}

/// An event entry.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Event {
    /// The command's seq for ack and nack, else 0.
    pub seq: u32,
    /// Raw kind ([`EventKind`] when known).
    pub kind: u16,
    /// Axis number (or 0xFFFF for card-wide events).
    pub axis: u16,
    /// Kind-specific code.
    pub code: i32,
    /// Servo tick at which it was raised.
    pub tick: u64,
    /// Kind-specific value.
    pub value: f64,
}

impl Event {
    /// Encode as words.
    pub fn to_words(&self) -> [u64; EVT_WORDS] {
        [
            self.seq as u64 | (self.kind as u64) << 32 | (self.axis as u64) << 48,
            self.code as u32 as u64,
            self.tick,
            self.value.to_bits(),
        ]
    }

    /// Decode from words (any bit pattern decodes).
    pub fn from_words(w: &[u64; EVT_WORDS]) -> Self {
        Self {
            seq: w[0] as u32,
            kind: (w[0] >> 32) as u16,
            axis: (w[0] >> 48) as u16,
            code: w[1] as u32 as i32,
            tick: w[2],
            value: f64::from_bits(w[3]),
        }
    }

    /// The kind, if known.
    pub fn kind(&self) -> Option<EventKind> {
        EventKind::from_raw(self.kind)
    }
}

bitflags::bitflags! {
    /// Fault bits of [`AxisStatus::faults`] (`MC_FAULT_*`). Decoded with
    /// `from_bits_retain`: a bit this layout does not name is kept, not dropped.
    #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
    pub struct Faults: u32 {
        /// The servo output hit the DAC limit this tick.
        const DAC_SATURATED = raw::MC_FAULT_DAC_SATURATED;
        /// The host watchdog tripped.
        const WATCHDOG = raw::MC_FAULT_WATCHDOG;
        /// An e-stop (command or input) stopped the axis.
        const ESTOP = raw::MC_FAULT_ESTOP;
        /// At or beyond the positive limit switch.
        const HARD_LIMIT_POS = raw::MC_FAULT_HARD_LIMIT_POS;
        /// At or beyond the negative limit switch.
        const HARD_LIMIT_NEG = raw::MC_FAULT_HARD_LIMIT_NEG;
        /// Beyond the positive soft limit.
        const SOFT_LIMIT_POS = raw::MC_FAULT_SOFT_LIMIT_POS;
        /// Beyond the negative soft limit.
        const SOFT_LIMIT_NEG = raw::MC_FAULT_SOFT_LIMIT_NEG;
        /// Following error beyond its limit.
        const FOLLOWING_ERROR = raw::MC_FAULT_FOLLOWING_ERROR;
        /// The amplifier's alarm input.
        const AMP_ALARM = raw::MC_FAULT_AMP_ALARM;
        /// Encoder loss or jump.
        const ENCODER = raw::MC_FAULT_ENCODER;
        /// The host broke the protocol (corrupt ring indices).
        const PROTOCOL = raw::MC_FAULT_PROTOCOL;
        /// A stop ran past the card's maximum stop time: its power was removed.
        const STOP_TIMEOUT = raw::MC_FAULT_STOP_TIMEOUT;
    }

    /// Bits of [`AxisStatus::io`] (`MC_IO_*`): the card's inputs for the axis and its
    /// drive-enable output.
    #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
    pub struct Io: u32 {
        /// Positive limit switch.
        const LIMIT_POS = raw::MC_IO_LIMIT_POS;
        /// Negative limit switch.
        const LIMIT_NEG = raw::MC_IO_LIMIT_NEG;
        /// Home switch.
        const HOME = raw::MC_IO_HOME;
        /// Amplifier alarm.
        const AMP_ALARM = raw::MC_IO_AMP_ALARM;
        /// Encoder line-break detector.
        const ENCODER_FAULT = raw::MC_IO_ENCODER_FAULT;
        /// The card's e-stop input (the same on every axis).
        const ESTOP = raw::MC_IO_ESTOP;
        /// Output: the amplifier is enabled.
        const DRIVE_ENABLE = raw::MC_IO_DRIVE_ENABLE;
    }

    /// Bits of [`AxisStatus::motion_flags`] (`MC_MOTION_*`, layout 1.5).
    #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
    pub struct MotionFlags: u32 {
        /// Velocity mode at its (overridden) velocity.
        const IN_VELOCITY = raw::MC_MOTION_IN_VELOCITY;
        /// Held still by a 0 % override, in its motion state.
        const PAUSED = raw::MC_MOTION_PAUSED;
        /// The position was set by homing or MC_SetPosition.
        const HOMED = raw::MC_MOTION_HOMED;
        /// The motion running is one that was buffered.
        const BUFFERED_ACTIVE = raw::MC_MOTION_BUFFERED_ACTIVE;
        /// Layout 1.7 (sync): the slave follows its master (InGear, InSync).
        const IN_SYNC = raw::MC_MOTION_IN_SYNC;
    }

    /// The single-bit flags of the group move commands (`MC_MOVE_*`, `MC_CIRC_CCW`, ...) in
    /// [`Command::flags`]; the multi-bit fields (circle mode, plane, feed type) are shifted in
    /// with the shifts of [`move_flags`].
    #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
    pub struct MoveFlags: u32 {
        /// Targets are relative to the start of the move.
        const RELATIVE = raw::MC_MOVE_RELATIVE;
        /// Queue behind the moves already queued.
        const BUFFERED = raw::MC_MOVE_BUFFERED;
        /// Counter-clockwise (else clockwise).
        const CIRC_CCW = raw::MC_CIRC_CCW;
        /// Helical targets are distances even in an absolute move.
        const CIRC_HELIX_RELATIVE = raw::MC_CIRC_HELIX_RELATIVE;
        /// Saturation-aware feed for a NURBS move (Yeh §3.4); `MC_OP_NURBS_BEGIN` only (the bit
        /// is the circle mode's in an arc).
        const NURBS_SATURATION = raw::MC_NURBS_SATURATION;
        /// Point-to-point: every axis also within the limits staged for it.
        const PTP_AXIS_LIMITS = raw::MC_PTP_AXIS_LIMITS;
    }

    /// `mc_axis_safety.flags` (`MC_AXSAFE_*`): the checks an axis makes.
    #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
    pub struct AxisSafetyFlags: u32 {
        /// Enforce the soft limits.
        const SOFT_LIMITS = raw::MC_AXSAFE_SOFT_LIMITS;
        /// Honour the limit switch inputs.
        const HARD_LIMITS = raw::MC_AXSAFE_HARD_LIMITS;
        /// Honour the amplifier alarm input.
        const AMP_ALARM = raw::MC_AXSAFE_AMP_ALARM;
        /// Honour encoder loss and jumps.
        const ENCODER = raw::MC_AXSAFE_ENCODER;
    }

    /// Card-wide safety latches, `mc_safety_status.faults` (`MC_CARD_FAULT_*`).
    #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
    pub struct CardFaults: u32 {
        /// The host watchdog tripped.
        const WATCHDOG = raw::MC_CARD_FAULT_WATCHDOG;
        /// The host's e-stop command.
        const ESTOP_COMMAND = raw::MC_CARD_FAULT_ESTOP_COMMAND;
        /// The card's e-stop input.
        const ESTOP_INPUT = raw::MC_CARD_FAULT_ESTOP_INPUT;
    }
}

// The header's catch-all agrees with the named flags, and the single-bit move flags stay clear
// of the multi-bit fields (but the NURBS flag, whose opcode has no circle mode).
const _: () = {
    assert!(AxisSafetyFlags::all().bits() == raw::MC_AXSAFE_ALL);
    let fields = 3 << raw::MC_CIRC_MODE_SHIFT
        | 3 << raw::MC_CIRC_PLANE_SHIFT
        | 3 << raw::MC_FEED_TYPE_SHIFT
        | 7 << raw::MC_CIRC_U_SHIFT
        | 7 << raw::MC_CIRC_V_SHIFT;
    assert!(
        MoveFlags::all()
            .difference(MoveFlags::NURBS_SATURATION)
            .bits()
            & fields
            == 0
    );
};

/// What the card publishes about an axis each tick: the header's `mc_axis_status_payload`
/// (its fields are listed there), moved under the axis's seqlock as [`STATUS_WORDS`] words.
pub type AxisStatus = raw::mc_axis_status_payload;

impl raw::mc_axis_status_payload {
    /// The payload as words, in place (its checksum word as it is, not computed).
    #[inline]
    pub fn as_words(&self) -> &[u64; STATUS_WORDS] {
        crate::block::as_words(self)
    }

    /// Encode as words, with the checksum in the last word.
    #[inline]
    pub fn to_words(&self) -> [u64; STATUS_WORDS] {
        let mut w = crate::block::to_words(self);
        w[STATUS_WORDS - 1] = status_checksum(&w);
        w
    }

    /// Decode from words; `None` when the checksum does not match (a torn or corrupted copy).
    /// The checksum field of the result is 0: it has been checked.
    pub fn from_words(w: &[u64; STATUS_WORDS]) -> Option<Self> {
        if status_checksum(w) != w[STATUS_WORDS - 1] {
            return None;
        }
        let mut s: Self = crate::block::from_words(w);
        s.checksum = 0;
        Some(s)
    }

    /// The state, if known.
    pub fn state(&self) -> Option<AxisState> {
        AxisState::from_raw(self.state)
    }

    /// The fault bits as a set (bits this layout does not name are kept).
    pub fn faults(&self) -> Faults {
        Faults::from_bits_retain(self.faults)
    }

    /// The input and drive-enable bits as a set (bits this layout does not name are kept).
    pub fn io(&self) -> Io {
        Io::from_bits_retain(self.io)
    }

    /// The motion bits as a set (bits this layout does not name are kept).
    pub fn motion(&self) -> MotionFlags {
        MotionFlags::from_bits_retain(self.motion_flags)
    }

    /// The stop reason, if known.
    pub fn stop_reason(&self) -> Option<StopReason> {
        StopReason::from_raw(self.stop_reason)
    }
}

/// The checksum of a status payload: a position-dependent mix of the words before the last,
/// `acc ← rotl(acc, 7) ^ w[i]·(0x9E37_79B9_7F4A_7C15 ^ i)` from `acc = MC_STATUS_CHECK`.
///
/// A rotation distributes over `^`, so after the `n` words the seed is rotated by `7n` and
/// word `i`'s product by `7(n − 1 − i)`: computed that way (the same value), the terms are
/// independent instead of a chain of `n` rotate-xor steps (the card publishes 12 a tick).
#[inline]
pub fn status_checksum(w: &[u64; STATUS_WORDS]) -> u64 {
    const N: usize = STATUS_WORDS - 1;
    w[..N].iter().enumerate().fold(
        (raw::MC_STATUS_CHECK as u64).rotate_left(checksum_rotation(N)),
        |acc, (i, &x)| acc ^ checksum_term(i, x),
    )
}

/// The checksum of a status payload whose word `i` (one before the checksum) changed from
/// `old` to `new`, from `checksum`, the payload's checksum before: word `i` enters
/// [`status_checksum`] as a term of its own, xored in, so the other words need not be read.
#[inline]
pub fn status_checksum_after(checksum: u64, i: usize, old: u64, new: u64) -> u64 {
    debug_assert!(i < STATUS_WORDS - 1);
    checksum ^ checksum_term(i, old) ^ checksum_term(i, new)
}

/// Word `i`'s term of [`status_checksum`].
#[inline(always)]
fn checksum_term(i: usize, x: u64) -> u64 {
    x.wrapping_mul(0x9E37_79B9_7F4A_7C15 ^ i as u64)
        .rotate_left(checksum_rotation(STATUS_WORDS - 2 - i))
}

#[inline(always)]
fn checksum_rotation(k: usize) -> u32 {
    (7 * k % 64) as u32
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn command_round_trip() {
        let mut c = Command::new(Opcode::MoveAbsolute, 7).with_args(&[1.5, -2.0, f64::NAN]);
        c.seq = 0xDEAD_BEEF;
        c.flags = 3;
        c.deadline_ms = 0xFFFF_FFFE;
        let d = Command::from_words(&c.to_words());
        assert_eq!(d.deadline_ms, 0xFFFF_FFFE);
        assert_eq!(d.seq, c.seq);
        assert_eq!(d.opcode, Opcode::MoveAbsolute as u16);
        assert_eq!(d.axis, 7);
        assert_eq!(d.flags, 3);
        assert_eq!(d.args[0], 1.5);
        assert!(d.args[2].is_nan());
    }

    #[test]
    fn event_round_trip_keeps_negative_codes() {
        let e = Event {
            seq: 9,
            kind: EventKind::Nack as u16,
            axis: 0xFFFF,
            code: -5,
            tick: u64::MAX,
            value: -0.25,
        };
        assert_eq!(Event::from_words(&e.to_words()), e);
    }

    #[test]
    fn status_checksum_detects_any_single_word_change() {
        let s = AxisStatus {
            cmd_pos: 1.0,
            act_pos: 2.0,
            state: 3,
            tick: 99,
            encoder: -4,
            stop_reason: 23,
            io: 0x101,
            faults: (Faults::WATCHDOG | Faults::from_bits_retain(1 << 31)).bits(),
            ..Default::default()
        };
        let w = s.to_words();
        assert_eq!(AxisStatus::from_words(&w), Some(s));
        assert_eq!(s.io(), Io::from_bits_retain(0x101));
        assert!(s.faults().contains(Faults::WATCHDOG));
        for i in 0..STATUS_WORDS {
            let mut bad = w;
            bad[i] ^= 1 << (i % 64);
            assert_eq!(AxisStatus::from_words(&bad), None, "word {i}");
        }
    }

    /// The checksum as the header defines it, one rotate-xor step a word, against the
    /// rearranged sum `status_checksum` computes.
    #[test]
    fn status_checksum_is_the_chain_of_rotate_xor_steps() {
        let chain = |w: &[u64; STATUS_WORDS]| {
            w[..STATUS_WORDS - 1]
                .iter()
                .enumerate()
                .fold(raw::MC_STATUS_CHECK as u64, |acc, (i, x)| {
                    acc.rotate_left(7) ^ x.wrapping_mul(0x9E37_79B9_7F4A_7C15 ^ i as u64)
                })
        };
        let mut x = 0x1234_5678_9ABC_DEF0u64;
        for _ in 0..1000 {
            let mut w = [0u64; STATUS_WORDS];
            for v in &mut w {
                // xorshift64
                x ^= x << 13;
                x ^= x >> 7;
                x ^= x << 17;
                *v = x;
            }
            assert_eq!(status_checksum(&w), chain(&w), "{w:x?}");
        }
        assert_eq!(
            status_checksum(&[0; STATUS_WORDS]),
            chain(&[0; STATUS_WORDS])
        );
        assert_eq!(
            status_checksum(&[u64::MAX; STATUS_WORDS]),
            chain(&[u64::MAX; STATUS_WORDS])
        );
    }

    /// The checksum after one word changed, from the one before, against the whole sum.
    #[test]
    fn status_checksum_after_one_word_is_the_whole_sum() {
        let mut x = 0x0F1E_2D3C_4B5A_6978u64;
        let mut next = || {
            // xorshift64
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            x
        };
        let mut w = [0u64; STATUS_WORDS];
        for v in &mut w {
            *v = next();
        }
        let mut sum = status_checksum(&w);
        for k in 0..1000 {
            let i = k % (STATUS_WORDS - 1);
            let new = next();
            sum = status_checksum_after(sum, i, w[i], new);
            w[i] = new;
            assert_eq!(sum, status_checksum(&w), "word {i}, step {k}");
        }
    }

    #[test]
    fn every_named_flag_is_its_own_single_bit() {
        fn check<F: bitflags::Flags<Bits = u32>>(what: &str) {
            let mut seen = 0u32;
            for (name, f) in F::all().iter_names() {
                let b = f.bits();
                assert_eq!(b.count_ones(), 1, "{what}::{name} = {b:#x}");
                assert_eq!(seen & b, 0, "{what}::{name} overlaps another flag");
                seen |= b;
            }
            assert_eq!(seen, F::all().bits(), "{what}");
        }
        check::<Faults>("Faults");
        check::<Io>("Io");
        check::<MoveFlags>("MoveFlags");
        check::<AxisSafetyFlags>("AxisSafetyFlags");
        check::<CardFaults>("CardFaults");
        check::<MotionFlags>("MotionFlags");
        check::<HomingFlags>("HomingFlags");
        assert_eq!(Faults::all().iter().count(), 12);
        assert_eq!(Io::all().iter().count(), 7);
    }

    #[test]
    fn codes_match_the_header() {
        assert_eq!(Opcode::from_raw(raw::MC_OP_HALT as u16), Some(Opcode::Halt));
        assert_eq!(Opcode::from_raw(0), None);
        // layout 1.10: the plane of two axes' one, the handwheel's two, the gantries' five,
        // the modulo's three; layout 1.11: group homing's three, the filters' four, PID+FF's
        // one, analog I/O's and the PSO's five; layout 1.12: the sweep's four, the PSO's
        // output, the normal arcs' three, the timed commands' ten
        assert_eq!(NackCode::ALL.len(), 131);
        assert_eq!(ConfigKind::ALL.len(), 9);
        assert_eq!(Opcode::from_raw(49), Some(Opcode::Home));
        assert_eq!(HomingError::from_raw(4), Some(HomingError::NoIndex));
        assert!(!StopReason::HomingFailed.is_safety());
        assert_eq!(Opcode::from_raw(34), Some(Opcode::EStop));
        assert_eq!(StopReason::from_raw(23), Some(StopReason::FollowingError));
        assert!(StopReason::Watchdog.is_safety() && !StopReason::Halt.is_safety());
        assert!(StopReason::HostChanged.is_safety() && StopReason::StopTimeout.is_safety());
        assert!(!StopReason::HostDetach.is_safety());
        assert!(StopReason::GantrySkew.is_safety() && StopReason::Gantry.is_safety());
        let mut codes: Vec<i32> = NackCode::ALL.iter().map(|c| *c as i32).collect();
        codes.dedup();
        assert_eq!(codes.len(), NackCode::ALL.len());
        assert_eq!(AxisState::from_raw(7), Some(AxisState::ErrorStop));
    }
}
