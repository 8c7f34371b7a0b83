//! Command garbage (see the parent module): the sources of garbage bytes, garbage numbers,
//! opcodes, flags and targets, plausible commands through the typed commands with one or two
//! arguments broken, NURBS transfers, and [`garbage_unit`].

use firmware_proto::cmd::{
    AnalogInput, AnalogOutput, ArcFlags, ArcGeometry, Args, AxisCmd, CamData, CamIn, CamTable,
    CardCmd, CircularMove, CircularNormalMove, CircularPlane, Cmd, CompData, CompHeader,
    CompPointArgs, CompRead, CompareArm, CompareDisarm, CompareKind, CompareTable, CurveSize,
    Direction, EStop, FeedLimits, GearIn, GearInPos, GroupCmd, GroupOverride, Handwheel, IoCmd,
    Jog, LinearMove, Master, MoveKind, MoveLimits, MoveOpts, NurbsBegin, NurbsData, Override,
    PathArc, PathArcNormal, PathArcPlane, PathDwell, PathFlags, PathLine, PathNurbs, PathOutput,
    PositionMove, ProbeAbort, ProbeArm, Pso, PsoOutput, PtpLimits, PtpMove, PvtBegin, PvtPoint,
    PvtPoints, PvtStart, ReadConfig, SetOutputs, SetScale, StopRamp, SyncCmd, SyncLimits,
    VelocityMove,
};
use firmware_proto::ring::Entry;
use firmware_proto::wire::{move_flags, CMD_ARGS, CMD_WORDS};
use firmware_proto::{
    raw, Command, ConfigKind, MasterSource, Opcode, StopCategory, CAM_AT_CYCLE_END, CAM_CUBIC,
    CAM_DATA_MAX, CAM_PERIODIC, CAM_RELATIVE, COMPARE_TABLE_MAX, MAX_AXES, MAX_GROUPS,
    NURBS_DATA_MAX, PVT_POINTS_MAX,
};

// ---------------------------------------------------------------------------------------------
// Sources of garbage

/// A stream of garbage bytes.
pub trait Source {
    /// The next byte (0 once exhausted).
    fn u8(&mut self) -> u8;
    /// Little-endian u16.
    fn u16(&mut self) -> u16 {
        u16::from_le_bytes([self.u8(), self.u8()])
    }
    /// Little-endian u32.
    fn u32(&mut self) -> u32 {
        u32::from_le_bytes([self.u8(), self.u8(), self.u8(), self.u8()])
    }
    /// Little-endian u64.
    fn u64(&mut self) -> u64 {
        self.u32() as u64 | (self.u32() as u64) << 32
    }
}

/// A fuzzer's input.
pub struct Bytes<'a> {
    data: &'a [u8],
    pos: usize,
}

impl<'a> Bytes<'a> {
    pub fn new(data: &'a [u8]) -> Self {
        Self { data, pos: 0 }
    }

    /// Everything read.
    pub fn is_empty(&self) -> bool {
        self.pos >= self.data.len()
    }
}

impl Source for Bytes<'_> {
    fn u8(&mut self) -> u8 {
        let b = self.data.get(self.pos).copied().unwrap_or(0);
        self.pos = self.pos.saturating_add(1);
        b
    }
}

/// The tests' seeded generator ([`Rng`](super::super::rng::Rng)) as a [`Source`] for the sweep: its
/// words handed out byte by byte.
#[derive(Debug, Clone)]
pub struct RngSource {
    rng: super::super::rng::Rng,
    buf: u64,
    left: u32,
}

impl RngSource {
    /// Seeded.
    pub fn new(seed: u64) -> Self {
        Self {
            rng: super::super::rng::Rng::new(seed),
            buf: 0,
            left: 0,
        }
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.rng.next_u64()
    }
}

impl Source for RngSource {
    fn u8(&mut self) -> u8 {
        if self.left == 0 {
            self.buf = self.next_u64();
            self.left = 8;
        }
        let b = self.buf as u8;
        self.buf >>= 8;
        self.left -= 1;
        b
    }
    fn u64(&mut self) -> u64 {
        self.next_u64()
    }
}

// ---------------------------------------------------------------------------------------------
// Garbage values and commands

/// A command entry as raw words: any opcode, axis, flags, reserved and argument bits. The
/// harness writes the seq (the low half of word 0) when it pushes the entry.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RawCmd(pub [u64; CMD_WORDS]);

impl RawCmd {
    /// An entry from its fields (raw opcode: any value).
    pub fn new(op: u16, axis: u16, flags: u32, args: &[f64; CMD_ARGS]) -> Self {
        let mut c = Command::new(Opcode::Nop, axis);
        c.opcode = op;
        c.flags = flags;
        c.args = *args;
        Self(c.to_words())
    }

    /// The entry as the card decodes it.
    pub fn command(&self) -> Command {
        Command::from_words(&self.0)
    }

    pub(super) fn with_seq(mut self, seq: u32) -> Self {
        self.0[0] = (self.0[0] & !0xFFFF_FFFF) | seq as u64;
        self
    }
}

impl Entry<CMD_WORDS> for RawCmd {
    fn encode(&self) -> [u64; CMD_WORDS] {
        self.0
    }
    fn decode(words: &[u64; CMD_WORDS]) -> Self {
        Self(*words)
    }
}

const MANTISSA: u64 = (1 << 52) - 1;
const SIGN: u64 = 1 << 63;

/// A positive magnitude, log-uniform over 10^lo..10^hi.
fn magnitude<S: Source>(s: &mut S, lo: f64, hi: f64) -> f64 {
    10f64.powf(lo + (hi - lo) * s.u16() as f64 / 65535.0)
}

/// A position-like value, counts: small, moderate or large, either sign.
fn position<S: Source>(s: &mut S) -> f64 {
    let scale = [1.0, 10.0, 1000.0, 1e6][(s.u8() % 4) as usize];
    s.u16() as i16 as f64 * scale
}

/// One garbage argument: NaN (any payload), ±inf, ±0, subnormal, huge, raw bits, small
/// integers, or positive and negative magnitudes from 1e-3 to 1e13.
pub fn garbage_f64<S: Source>(s: &mut S) -> f64 {
    let sign = if s.u8() & 1 == 1 { SIGN } else { 0 };
    match s.u8() % 16 {
        0 => f64::from_bits(sign | 0x7FF0_0000_0000_0000 | (s.u64() & MANTISSA).max(1)),
        1 => f64::INFINITY,
        2 => f64::NEG_INFINITY,
        3 => 0.0,
        4 => -0.0,
        5 => f64::from_bits(sign | (s.u64() & MANTISSA).max(1)),
        6 => {
            let v = [
                f64::MAX,
                f64::MIN_POSITIVE,
                1e300,
                f64::EPSILON,
                crate::MAX_POSITION,
                2.0 * crate::MAX_POSITION,
                crate::MAX_MOVE_TIME,
                1e-300,
            ][(s.u8() % 8) as usize];
            f64::from_bits(v.to_bits() | sign)
        }
        7 => f64::from_bits(s.u64()),
        8 | 9 => s.u8() as i8 as f64,
        10 => -magnitude(s, -3.0, 13.0),
        11 => position(s),
        _ => magnitude(s, -3.0, 13.0),
    }
}

/// Group layout of `Card::new` (in the parent module): (card axes, accdec, interpolator, enabled).
pub const GROUPS: [(&[u8], u32, u32, bool); 3] = [
    (&[0, 1], raw::MC_ACCDEC_PRE, raw::MC_INTERP_EXACT, true),
    (&[2, 3, 4], raw::MC_ACCDEC_POST, raw::MC_INTERP_EXACT, true),
    (
        &[5, 6],
        raw::MC_ACCDEC_POST,
        raw::MC_INTERP_REFERENCE_WORD,
        false,
    ),
];

/// Axes of the card.
pub const AXES: usize = MAX_AXES;

/// Opcodes whose axis field is a group: 16..31 (the group and NURBS block of the header),
/// but for the axis filter.
pub(super) fn is_group_op(op: Opcode) -> bool {
    (raw::MC_OP_GROUP_CONFIGURE..raw::MC_OP_APPLY_SAFETY_CONFIG).contains(&(op as u32))
        && op != Opcode::ApplyAxisFilter
}

/// An axis or group number: mostly valid, sometimes just out of range, sometimes anything.
pub(super) fn target_index<S: Source>(s: &mut S, group: bool) -> u16 {
    let k = s.u8();
    match k >> 5 {
        0..=5 if group => (k % MAX_GROUPS as u8) as u16,
        0..=5 => (k % AXES as u8) as u16,
        6 => [
            AXES as u16,
            MAX_GROUPS as u16,
            0x00FF,
            0x0100,
            0x8000,
            0xFFFF,
        ][(k % 6) as usize],
        _ => s.u16(),
    }
}

fn garbage_flags<S: Source>(s: &mut S) -> u32 {
    match s.u8() % 4 {
        0 => 0,
        1 => s.u16() as u32 & 0x3FF,
        2 => 1 << (s.u8() % 32),
        _ => s.u32(),
    }
}

/// The gaps and edges of the opcode space (none of them an opcode: tested below).
const OPCODE_GAPS: [u16; 21] = [
    0, 38, 39, 46, 47, 51, 55, 63, 70, 79, 94, 107, 111, 114, 123, 130, 135, 256, 0x7FFF, 0x8000,
    0xFFFF,
];

fn pick_opcode<S: Source>(s: &mut S) -> u16 {
    let k = s.u8();
    if k < 232 {
        Opcode::ALL[k as usize % Opcode::ALL.len()] as u16
    } else if usize::from(k) < 232 + OPCODE_GAPS.len() {
        OPCODE_GAPS[usize::from(k) - 232]
    } else {
        s.u16()
    }
}

/// What the card refuses to decode that a plausible draw asked for: written over the encoded
/// entry, since no command type holds it (an e-stop category 3, a block kind 0 or 10, compare
/// and probe flags the card refuses).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Overwrite {
    /// `args[i]` is this.
    Arg(usize, f64),
    /// The flags word is this.
    Flags(u32),
}

/// A command a well-behaved host could send: typed, and the field a type cannot hold that the
/// draw asked for (`None` mostly).
#[derive(Debug, Clone, PartialEq)]
pub struct Plausible {
    /// The command.
    pub cmd: Cmd,
    /// Written over its entry.
    pub over: Option<Overwrite>,
}

impl Plausible {
    fn typed(cmd: impl Into<Cmd>) -> Self {
        Self {
            cmd: cmd.into(),
            over: None,
        }
    }

    /// The entry for `target`.
    pub fn entry(&self, target: u16) -> Command {
        let mut c = self.cmd.command(target);
        match self.over {
            Some(Overwrite::Arg(i, x)) => c.args[i] = x,
            Some(Overwrite::Flags(f)) => c.flags = f,
            None => {}
        }
        c
    }
}

/// The limits of a group move or a PTP axis: v, a, d, j.
fn feed_limits<S: Source>(s: &mut S) -> FeedLimits {
    FeedLimits {
        vmax: magnitude(s, 2.0, 6.5),
        amax: magnitude(s, 3.0, 8.5),
        dmax: magnitude(s, 3.0, 8.5),
        jerk: magnitude(s, 5.0, 11.0),
    }
}

/// `N` positions.
fn positions<S: Source, const N: usize>(s: &mut S) -> [f64; N] {
    core::array::from_fn(|_| position(s))
}

/// A command a well-behaved host could send for `op`, made through the typed commands
/// (`firmware_proto::cmd`). The bytes are read in the order of its arguments, then its flags
/// (the feed type first, drawn for every opcode), so an input means what it meant when the
/// harness wrote arguments by hand.
pub fn plausible<S: Source>(s: &mut S, op: Opcode) -> Plausible {
    use Opcode as O;
    let feed = |s: &mut S| s.u8() % 3;
    let path_flags = |s: &mut S, relative_and_ccw: u8| {
        let mode = s.u8() % 3;
        let buffer = s.u8() % 7;
        let transition = s.u8() % 4;
        let bits = s.u8() & relative_and_ccw;
        (
            PathFlags {
                relative: bits & 1 != 0,
                buffer,
                transition,
                last: false,
            },
            mode,
            bits & move_flags::CIRC_CCW as u8 != 0,
        )
    };
    match op {
        O::MoveAbsolute | O::MoveRelative | O::MoveAdditive => {
            let position = position(s);
            let l = feed_limits(s);
            let mut j = [l.jerk; 3];
            for x in j.iter_mut() {
                if s.u8() & 1 != 0 {
                    *x = magnitude(s, 5.0, 11.0);
                }
            }
            let limits = MoveLimits {
                vmax: l.vmax,
                amax: l.amax,
                dmax: l.dmax,
                j1: l.jerk,
                j3: j[0],
                j5: j[1],
                j7: j[2],
            };
            feed(s);
            let buffered = s.u8() as u32 & move_flags::BUFFERED != 0;
            let kind = match op {
                O::MoveAbsolute => MoveKind::Absolute,
                O::MoveRelative => MoveKind::Relative,
                _ => MoveKind::Additive,
            };
            let m = PositionMove {
                position,
                limits,
                buffered,
                // The generator's byte stream unchanged: the shortest way (the only one a
                // linear axis takes).
                direction: firmware_proto::cmd::MoveDirection::Shortest,
            };
            Plausible::typed(AxisCmd::Move(kind, m))
        }
        O::Halt | O::Stop | O::GroupHalt | O::GroupStop => {
            let r = StopRamp {
                dmax: magnitude(s, 3.0, 8.5),
                jerk: magnitude(s, 5.0, 11.0),
            };
            feed(s);
            match op {
                O::Halt => Plausible::typed(AxisCmd::Halt(r)),
                O::Stop => Plausible::typed(AxisCmd::Stop(r)),
                O::GroupHalt => Plausible::typed(GroupCmd::Halt(r)),
                _ => Plausible::typed(GroupCmd::Stop(r)),
            }
        }
        O::EStop => {
            let k = s.u8() % 4;
            feed(s);
            let category = StopCategory::from_raw(k as u32).unwrap_or(StopCategory::Cat0);
            let mut p = Plausible::typed(CardCmd::EStop(EStop { category }));
            if StopCategory::from_raw(k as u32).is_none() {
                p.over = Some(Overwrite::Arg(0, k as f64));
            }
            p
        }
        O::MoveVelocity => {
            let v = magnitude(s, 2.0, 6.5);
            let velocity = if s.u8() & 1 == 0 { v } else { -v };
            let m = VelocityMove {
                velocity,
                amax: magnitude(s, 3.0, 8.5),
                dmax: magnitude(s, 3.0, 8.5),
                jerk: magnitude(s, 5.0, 11.0),
            };
            feed(s);
            Plausible::typed(AxisCmd::MoveVelocity(m))
        }
        O::Jog => {
            let v = magnitude(s, 2.0, 5.0);
            let velocity = if s.u8() & 1 == 0 { v } else { -v };
            feed(s);
            Plausible::typed(AxisCmd::Jog(Jog { velocity }))
        }
        O::SetOverride | O::GroupSetOverride => {
            let feed_factor = (s.u8() % 21) as f64 / 10.0;
            let rapid = (s.u8() % 21) as f64 / 10.0;
            feed(s);
            if op == O::SetOverride {
                Plausible::typed(AxisCmd::SetOverride(Override {
                    factor: feed_factor,
                }))
            } else {
                Plausible::typed(GroupCmd::SetOverride(GroupOverride {
                    feed: feed_factor,
                    rapid,
                }))
            }
        }
        O::GroupMoveLinear | O::GroupMovePtp => {
            let limits = feed_limits(s);
            let all: [f64; CMD_ARGS - 4] = positions(s);
            let targets = core::array::from_fn(|k| all[k]);
            let feed_type = feed(s);
            let bits = s.u8() & 3;
            let line = LinearMove {
                limits,
                targets,
                opts: MoveOpts {
                    relative: bits & 1 != 0,
                    buffered: bits & 2 != 0,
                    feed_type,
                },
            };
            if op == O::GroupMoveLinear {
                Plausible::typed(GroupCmd::MoveLinear(line))
            } else {
                let ptp = PtpMove {
                    line,
                    axis_limits: false,
                };
                Plausible::typed(GroupCmd::MovePtp(ptp))
            }
        }
        O::GroupMoveCircular => {
            let limits = feed_limits(s);
            // End point, then centre, radius or border point, then helical targets.
            let mut a: [f64; CMD_ARGS - 4] = positions(s);
            if s.u8() & 1 == 0 {
                a[2] = (a[0] * a[0] + a[1] * a[1]).sqrt() * (0.5 + s.u8() as f64 / 64.0);
            }
            let feed_type = feed(s);
            let mode = s.u8() % 3;
            let plane = s.u8() % 4;
            let axes = (s.u8() % 8, s.u8() % 8);
            let bits = s.u8() & (3 | move_flags::CIRC_CCW as u8);
            let m = CircularMove {
                limits,
                arc: ArcGeometry {
                    end: [a[0], a[1]],
                    aux: [a[2], a[3]],
                    helix: core::array::from_fn(|k| a[4 + k]),
                    flags: ArcFlags {
                        mode,
                        plane,
                        axes,
                        ccw: bits & move_flags::CIRC_CCW as u8 != 0,
                        helix_relative: false,
                    },
                },
                opts: MoveOpts {
                    relative: bits & 1 != 0,
                    buffered: bits & 2 != 0,
                    feed_type,
                },
            };
            Plausible::typed(GroupCmd::MoveCircular(m))
        }
        O::PathLine | O::PathArc => {
            let id = s.u16() as f64;
            let feed_v = magnitude(s, 2.0, 6.5);
            let tolerance = if s.u8() & 1 == 0 {
                0.0
            } else {
                magnitude(s, -1.0, 3.0)
            };
            let a: [f64; CMD_ARGS - 3] = positions(s);
            feed(s);
            let relative_and_ccw = 1 | move_flags::CIRC_CCW as u8;
            let (flags, mode, ccw) = path_flags(s, relative_and_ccw);
            if op == O::PathLine {
                Plausible::typed(GroupCmd::PathLine(PathLine {
                    id,
                    feed: feed_v,
                    tolerance,
                    targets: core::array::from_fn(|k| a[k]),
                    flags,
                }))
            } else {
                let arc = ArcGeometry {
                    end: [a[0], a[1]],
                    aux: [a[2], a[3]],
                    helix: core::array::from_fn(|k| a[4 + k]),
                    flags: ArcFlags {
                        mode,
                        plane: 0,
                        axes: (0, 0),
                        ccw,
                        helix_relative: false,
                    },
                };
                Plausible::typed(GroupCmd::PathArc(PathArc {
                    id,
                    feed: feed_v,
                    tolerance,
                    arc,
                    flags,
                }))
            }
        }
        O::PathArcPlane => {
            // mostly three distinct axes of a small group, sometimes one twice
            let axes = core::array::from_fn(|k| ((k as u8 + s.u8() % 2) % 4) as f64);
            let normal = core::array::from_fn(|_| s.u8() as f64 - 128.0);
            feed(s);
            Plausible::typed(GroupCmd::PathArcPlane(PathArcPlane { axes, normal }))
        }
        O::PathArcNormal => {
            let id = s.u16() as f64;
            let feed_v = magnitude(s, 2.0, 6.5);
            let tolerance = magnitude(s, -1.0, 3.0);
            let a: [f64; CMD_ARGS - 3] = positions(s);
            feed(s);
            let (flags, _, rise) = path_flags(s, 1 | move_flags::CIRC_CCW as u8);
            Plausible::typed(GroupCmd::PathArcNormal(PathArcNormal {
                id,
                feed: feed_v,
                tolerance,
                centre: [a[0], a[1], a[2]],
                end: [a[3], a[4], a[5]],
                helix: core::array::from_fn(|k| a[6 + k]),
                rise,
                helix_relative: false,
                flags,
            }))
        }
        // Layout 1.13: a normal-vector arc move's two entries (each refused alone; a pair when
        // drawn one after the other for one group).
        O::GroupMoveCircularNormal => {
            let limits = feed_limits(s);
            let a: [f64; 6] = positions(s);
            let turns = f64::from(s.u8() % 3);
            let feed_type = feed(s);
            let bits = s.u8() & 7;
            Plausible::typed(GroupCmd::MoveCircularNormal(CircularNormalMove {
                limits,
                centre: [a[0], a[1], a[2]],
                end: [a[3], a[4], a[5]],
                turns,
                rise: bits & 4 != 0,
                helix_relative: false,
                opts: MoveOpts {
                    relative: bits & 1 != 0,
                    buffered: bits & 2 != 0,
                    feed_type,
                },
            }))
        }
        O::GroupCircularPlane => {
            let axes = core::array::from_fn(|k| ((k as u8 + s.u8() % 2) % 4) as f64);
            let normal = core::array::from_fn(|_| s.u8() as f64 - 128.0);
            let helix = positions(s);
            feed(s);
            Plausible::typed(GroupCmd::CircularPlane(CircularPlane {
                plane: PathArcPlane { axes, normal },
                helix,
            }))
        }
        O::PathDwell => {
            let id = s.u16() as f64;
            let seconds = magnitude(s, -4.0, 0.0);
            feed(s);
            Plausible::typed(GroupCmd::PathDwell(PathDwell {
                id,
                seconds,
                last: false,
            }))
        }
        O::PathOutput => {
            let output = (s.u8() % 20) as f64;
            let on = (s.u8() % 3) as f64;
            let distance = magnitude(s, 0.0, 5.0);
            feed(s);
            let when = s.u8() % 4;
            Plausible::typed(GroupCmd::PathOutput(PathOutput {
                output,
                on,
                distance,
                when,
            }))
        }
        O::SetOutputs => {
            let mask = s.u16() as u32;
            let value = s.u16() as u32;
            feed(s);
            Plausible::typed(IoCmd::SetOutputs(SetOutputs { mask, value }))
        }
        // Layout 1.7: compare and probe channels (one past the last now and then).
        O::CompareArm => {
            let channel = s.u8() % 5;
            let output = (s.u8() % 17) as f64;
            let pulse_us = (1 + s.u16() % 2000) as f64;
            let low_water = (s.u8() % 64) as f64;
            let position = position(s);
            let pitch = magnitude(s, 0.0, 4.0).round();
            let count = (1 + s.u16() % 5000) as f64;
            feed(s);
            let bits = (s.u8() & 0x1F) as u32;
            let kind = match bits & raw::MC_CMP_MODE_MASK {
                raw::MC_CMP_MODE_SERIES => CompareKind::Series,
                raw::MC_CMP_MODE_TABLE => CompareKind::Table,
                _ => CompareKind::Single,
            };
            let direction = match (bits & raw::MC_CMP_DIR_POS, bits & raw::MC_CMP_DIR_NEG) {
                (0, 0) => None,
                (_, 0) => Some(Direction::Up),
                (0, _) => Some(Direction::Down),
                _ => None,
            };
            let arm = CompareArm {
                channel,
                kind,
                direction,
                output,
                pulse_us,
                low_water,
                position,
                pitch,
                count,
                each_turn: bits & raw::MC_CMP_EACH_TURN != 0 && kind != CompareKind::Table,
            };
            let mut p = Plausible::typed(IoCmd::CompareArm(arm));
            if CompareArm::decode(bits, &[0.0; CMD_ARGS]).is_err() {
                p.over = Some(Overwrite::Flags(bits)); // flags the card refuses
            }
            p
        }
        O::CompareTable => {
            let channel = s.u8() % 5;
            let n = 1 + s.u8() as usize % 13;
            let mut p = position(s);
            let mut all = [0.0; CMD_ARGS - 2];
            for x in all.iter_mut() {
                *x = p;
                p += magnitude(s, 0.0, 3.0);
            }
            feed(s);
            let bits = [4, 8, 12, 0][(s.u8() % 4) as usize];
            let table = CompareTable {
                channel,
                direction: if bits == raw::MC_CMP_DIR_NEG {
                    Direction::Down
                } else {
                    Direction::Up
                },
                positions: all[..n.min(COMPARE_TABLE_MAX)].iter().copied().collect(),
            };
            let mut p = Plausible::typed(IoCmd::CompareTable(table));
            if n > COMPARE_TABLE_MAX {
                p.over = Some(Overwrite::Arg(1, n as f64)); // a count the card refuses
            } else if bits != raw::MC_CMP_DIR_POS && bits != raw::MC_CMP_DIR_NEG {
                p.over = Some(Overwrite::Flags(bits)); // no direction, or both
            }
            p
        }
        // Layout 1.11: analog I/O (one channel past the last now and then) and the PSO.
        O::AnalogInput => {
            let a = AnalogInput {
                input: s.u8() % 9,
                cutoff_hz: [0.0, 50.0, 5000.0, 6000.0][usize::from(s.u8() % 4)],
                threshold: magnitude(s, -2.0, 1.1),
                hysteresis: magnitude(s, -3.0, 0.5),
                rise_event: s.u8() & 1 != 0,
                fall_event: s.u8() & 1 != 0,
            };
            feed(s);
            Plausible::typed(IoCmd::AnalogInput(a))
        }
        O::AnalogOutput => {
            let o = AnalogOutput {
                output: s.u8() % 5,
                volts: magnitude(s, -3.0, 1.3) * if s.u8() & 1 != 0 { -1.0 } else { 1.0 },
            };
            feed(s);
            Plausible::typed(IoCmd::AnalogOutput(o))
        }
        O::Pso => {
            let pwm = s.u8() & 1 != 0;
            let output = if pwm {
                PsoOutput::Pwm {
                    output: s.u8() % 17,
                    hz: magnitude(s, 0.0, 5.1),
                }
            } else {
                PsoOutput::Dac(s.u8() % 5)
            };
            let hi = if pwm { 1.0 } else { 10.0 };
            let p = Pso {
                output,
                gate: s.u8() % 17,
                min: hi * f64::from(s.u8() % 3) / 4.0,
                max: hi * f64::from(s.u8() % 5) / 4.0,
                v_ref: magnitude(s, 2.0, 6.0),
                filter_hz: [0.0, 200.0, 6000.0][usize::from(s.u8() % 3)],
            };
            feed(s);
            Plausible::typed(IoCmd::Pso(p))
        }
        O::PsoOff => {
            feed(s);
            Plausible::typed(IoCmd::PsoOff)
        }
        O::CompareDisarm | O::ProbeAbort => {
            let channel = s.u8() % 5;
            feed(s);
            if op == O::CompareDisarm {
                Plausible::typed(IoCmd::CompareDisarm(CompareDisarm { channel }))
            } else {
                Plausible::typed(IoCmd::ProbeAbort(ProbeAbort { channel }))
            }
        }
        O::ProbeArm => {
            let channel = s.u8() % 5;
            let input = s.u8() % 18;
            let lo = position(s);
            let hi = lo + magnitude(s, 0.0, 5.0);
            feed(s);
            let bits = (s.u8() & 0x3F) as u32;
            let arm = ProbeArm {
                channel,
                input,
                rising: bits & raw::MC_PROBE_RISING != 0,
                falling: bits & raw::MC_PROBE_FALLING != 0,
                continuous: bits & raw::MC_PROBE_CONTINUOUS != 0,
                window: (bits & raw::MC_PROBE_WINDOW != 0).then_some((lo, hi)),
                halt: bits & raw::MC_PROBE_HALT != 0,
            };
            let mut p = Plausible::typed(IoCmd::ProbeArm(arm));
            let mut args = [0.0; CMD_ARGS];
            args[1] = 1.0;
            if ProbeArm::decode(bits, &args).is_err() {
                p.over = Some(Overwrite::Flags(bits)); // no edge, or a bit it does not know
            }
            p
        }
        O::GearIn | O::GearInPos => {
            // Layout 1.7 (sync): master, ratio, limits, then the sync point.
            let index = s.u8() % 3;
            let n = 1 + (s.u8() % 16) as i32;
            let numerator = if s.u8() & 1 == 0 { n } else { -n } as f64;
            let denominator = (1 + s.u8() % 16) as f64;
            let limits = SyncLimits {
                vmax: magnitude(s, 2.0, 6.5),
                amax: magnitude(s, 3.0, 8.5),
                jerk: magnitude(s, 5.0, 11.0),
            };
            let master_position = position(s);
            let slave_position = position(s);
            feed(s);
            let source = MasterSource::from_raw((s.u8() % 4) as u32).unwrap_or(MasterSource::Aux);
            let gear = GearIn {
                master: Master { source, index },
                numerator,
                denominator,
                limits,
            };
            if op == O::GearIn {
                Plausible::typed(SyncCmd::GearIn(gear))
            } else {
                Plausible::typed(SyncCmd::GearInPos(GearInPos {
                    gear,
                    master_position,
                    slave_position,
                }))
            }
        }
        O::PvtBegin => {
            let vmax = magnitude(s, 2.0, 6.5);
            let amax = magnitude(s, 3.0, 8.5);
            let low_water = (s.u8() % 8) as f64;
            feed(s);
            let pt = s.u8() % 2 == 1;
            Plausible::typed(SyncCmd::PvtBegin(PvtBegin {
                vmax,
                amax,
                low_water,
                pt,
                other_flags: 0,
            }))
        }
        O::PvtPoints => {
            // Layout 1.7 (sync): count, then time, position, velocity of each.
            let n = 1 + (s.u8() % 4) as usize;
            let mut t = 0.0;
            let mut all = [PvtPoint {
                time: 0.0,
                position: 0.0,
                velocity: 0.0,
            }; PVT_POINTS_MAX];
            for p in all.iter_mut() {
                t += magnitude(s, -3.0, 0.0);
                p.time = t;
                p.position = position(s);
                p.velocity = magnitude(s, 0.0, 4.0);
            }
            feed(s);
            let last = s.u8() % 2 == 1;
            Plausible::typed(SyncCmd::PvtPoints(PvtPoints {
                points: all[..n].iter().copied().collect(),
                last,
            }))
        }
        O::PvtStart => {
            let mask = (s.u8() % 4) as u32;
            feed(s);
            Plausible::typed(SyncCmd::PvtStart(PvtStart { mask }))
        }
        O::GantryForm => {
            // Layout 1.10: a master and one slave of the first four axes.
            let master = s.u8() % 4;
            let axis = (master + 1 + s.u8() % 3) % 4;
            feed(s);
            let slave = firmware_proto::cmd::GantrySlave { axis, offset: 0.0 };
            Plausible::typed(SyncCmd::GantryForm(firmware_proto::cmd::GantryForm {
                master,
                kp: 1e6,
                ki: 0.0,
                skew_limit: 100.0,
                slaves: core::iter::once(slave).collect(),
            }))
        }
        O::ReadConfig => {
            // Layout 1.8: a block kind (0 and 10 are none) and an index (axes, groups).
            let k = s.u8() % 11;
            let index = (s.u8() % 10) as u16;
            feed(s);
            let kind = ConfigKind::from_raw(k as u32).unwrap_or(ConfigKind::Card);
            let mut p = Plausible::typed(CardCmd::ReadConfig(ReadConfig { kind, index }));
            if ConfigKind::from_raw(k as u32).is_none() {
                p.over = Some(Overwrite::Arg(0, k as f64));
            }
            p
        }
        O::SetScale => {
            let sign = if s.u8() & 1 == 0 { 1.0 } else { -1.0 };
            let scale = sign * magnitude(s, -10.0, 13.0);
            feed(s);
            Plausible::typed(CardCmd::SetScale(SetScale { scale }))
        }
        O::CamTable => {
            let table = s.u8() % 5;
            let points = (s.u8() % 12) as u16;
            feed(s);
            let bits = s.u8() % 4;
            Plausible::typed(SyncCmd::CamTable(CamTable {
                table,
                points,
                cubic: bits as u32 & CAM_CUBIC != 0,
                periodic: bits as u32 & CAM_PERIODIC != 0,
            }))
        }
        // Layout 1.11: a servo filter of any kind in any slot, its numbers around the plausible
        // (some refused: a frequency beyond Nyquist, a damping or depth out of range).
        O::ServoFilterSet => {
            let kinds = firmware_proto::cmd::BiquadKind::ALL;
            let spec = firmware_proto::cmd::BiquadSpec {
                kind: kinds[s.u8() as usize % kinds.len()],
                freq_hz: magnitude(s, 0.0, 4.0),
                damping: magnitude(s, -2.0, 1.0),
                depth_db: -magnitude(s, 0.0, 2.0),
                freq2_hz: magnitude(s, 0.0, 4.0),
                coeffs: [
                    magnitude(s, -1.0, 0.0),
                    magnitude(s, -1.0, 0.0),
                    magnitude(s, -1.0, 0.0),
                    -magnitude(s, -1.0, 0.0),
                    magnitude(s, -2.0, 0.0),
                ],
            };
            let slot = s.u8() % firmware_proto::cmd::BIQUADS as u8;
            feed(s);
            Plausible::typed(AxisCmd::ServoFilterSet(
                firmware_proto::cmd::ServoFilterSet { slot, spec },
            ))
        }
        // Layout 1.9: leadscrew compensation, a table's header, its points (rising positions,
        // small corrections), a read-back.
        O::CompTable => {
            let points = u16::from(s.u8() % 8);
            let header = CompHeader {
                points,
                bound: magnitude(s, 0.0, 3.0),
                backlash: magnitude(s, -1.0, 1.0),
                ramp_vel: magnitude(s, 2.0, 5.0),
                ramp_acc: magnitude(s, 3.0, 7.0),
                bidir: s.u8() & 1 == 1,
            };
            feed(s);
            Plausible::typed(AxisCmd::CompTable(header))
        }
        O::CompData => {
            let first = u16::from(s.u8() % 8);
            let count = 1 + s.u8() % firmware_proto::cmd::COMP_DATA_MAX as u8;
            let mut x = position(s);
            let mut point = [CompPointArgs::default(); firmware_proto::cmd::COMP_DATA_MAX];
            for p in point.iter_mut().take(usize::from(count)) {
                x += magnitude(s, 0.0, 4.0);
                *p = CompPointArgs {
                    position: x,
                    forward: magnitude(s, -1.0, 1.0),
                    reverse: -magnitude(s, -1.0, 1.0),
                };
            }
            feed(s);
            Plausible::typed(AxisCmd::CompData(CompData {
                first,
                count,
                point,
            }))
        }
        O::Handwheel => {
            let ratio = [1, 10, 100, -10][usize::from(s.u8() % 4)];
            let h = Handwheel {
                input: s.u8() % 3,
                ratio,
                detent: 1 + u16::from(s.u8() % 8),
            };
            feed(s);
            Plausible::typed(AxisCmd::Handwheel(h))
        }
        O::HandwheelOff => {
            feed(s);
            Plausible::typed(AxisCmd::HandwheelOff)
        }
        // Layout 1.12: a sweep of either mode around the plausible (some refused: beyond a
        // quarter of the servo rate, an amplitude beyond the axis's limits), and its stop.
        O::FreqStart => {
            let mode = if s.u8() & 1 == 0 {
                firmware_proto::cmd::FreqMode::Reference
            } else {
                firmware_proto::cmd::FreqMode::Output
            };
            let from_hz = magnitude(s, -1.0, 3.0);
            let start = firmware_proto::cmd::FreqStart {
                mode,
                from_hz,
                to_hz: from_hz * (1.0 + magnitude(s, -1.0, 1.0)),
                points: 1 + u16::from(s.u8() % 8),
                amplitude: magnitude(s, -1.0, 3.0),
                cycles: 1 + u16::from(s.u8() % 4),
                settle_s: magnitude(s, -3.0, 0.0),
            };
            feed(s);
            Plausible::typed(AxisCmd::FreqStart(start))
        }
        O::FreqStop => {
            feed(s);
            Plausible::typed(AxisCmd::FreqStop)
        }
        O::CompRead => {
            feed(s);
            Plausible::typed(AxisCmd::CompRead(CompRead {
                first: u16::from(s.u8()),
            }))
        }
        O::CamData => {
            let table = s.u8() % 5;
            let first = (s.u8() % 12) as u16;
            let n = 1 + (s.u8() % 5) as usize;
            let mut m = 0.0;
            let mut all = [(0.0, 0.0); CAM_DATA_MAX];
            for p in all.iter_mut() {
                m += magnitude(s, 0.0, 4.0);
                *p = (m, position(s));
            }
            feed(s);
            Plausible::typed(SyncCmd::CamData(CamData {
                table,
                first,
                points: all[..n].iter().copied().collect(),
            }))
        }
        O::CamIn => {
            let index = s.u8() % 3;
            let table = (s.u8() % 5) as f64;
            let master_offset = position(s);
            let slave_offset = position(s);
            let master_scale = 1.0 + (s.u8() % 4) as f64;
            let slave_scale = 1.0 + (s.u8() % 4) as f64;
            let limits = SyncLimits {
                vmax: magnitude(s, 2.0, 6.5),
                amax: magnitude(s, 3.0, 8.5),
                jerk: magnitude(s, 5.0, 11.0),
            };
            feed(s);
            let source = MasterSource::from_raw((s.u8() % 4) as u32).unwrap_or(MasterSource::Aux);
            let bits = s.u8() as u32;
            Plausible::typed(SyncCmd::CamIn(CamIn {
                master: Master { source, index },
                table,
                master_offset,
                slave_offset,
                master_scale,
                slave_scale,
                limits,
                at_cycle_end: bits & CAM_AT_CYCLE_END != 0,
                relative: bits & CAM_RELATIVE != 0,
            }))
        }
        O::NurbsData => {
            let offset = (s.u8() % 64) as u32;
            let n = 1 + (s.u8() % 12) as usize;
            let values: [f64; NURBS_DATA_MAX] = positions(s);
            feed(s);
            Plausible::typed(GroupCmd::NurbsData(NurbsData {
                offset,
                values: values[..n].iter().copied().collect(),
            }))
        }
        O::PathNurbs => {
            let degree = 1 + s.u8() % 5;
            let n_ctrl = degree + 1 + s.u8() % 8;
            let id = s.u16() as f64;
            let feed_v = magnitude(s, 2.0, 6.5);
            let tolerance = magnitude(s, -1.0, 3.0);
            let fit_tolerance = magnitude(s, -2.0, 1.0);
            feed(s);
            let (flags, _, _) = path_flags(s, 1 | move_flags::CIRC_CCW as u8);
            Plausible::typed(GroupCmd::PathNurbs(PathNurbs {
                id,
                feed: feed_v,
                tolerance,
                size: CurveSize {
                    degree: degree as f64,
                    n_ctrl: n_ctrl as f64,
                    n_knots: (n_ctrl + degree + 1) as f64,
                },
                fit_tolerance,
                flags,
            }))
        }
        O::NurbsBegin => {
            let degree = 1 + s.u8() % 5;
            let n_ctrl = degree + 1 + s.u8() % 8;
            let l = feed_limits(s);
            let chord_tolerance = magnitude(s, -2.0, 1.0);
            let budget = s.u8() as f64 / 255.0;
            let feed_type = feed(s);
            let buffered = s.u8() as u32 & move_flags::BUFFERED != 0;
            Plausible::typed(GroupCmd::NurbsBegin(NurbsBegin {
                size: CurveSize {
                    degree: degree as f64,
                    n_ctrl: n_ctrl as f64,
                    n_knots: (n_ctrl + degree + 1) as f64,
                },
                feed: l.vmax,
                accel: l.amax,
                jerk: l.dmax,
                chord_tolerance,
                budget,
                buffered,
                saturation: false,
                feed_type,
            }))
        }
        O::GroupPtpLimits => {
            feed(s);
            // Zeros: no axis counted (the card refuses it, BadConfig).
            let zero = FeedLimits::from_array([0.0; 4]);
            let limits = core::iter::once(zero).collect();
            let mut p = Plausible::typed(GroupCmd::PtpLimits(PtpLimits { first: 0, limits }));
            p.over = Some(Overwrite::Arg(1, 0.0));
            p
        }
        // Layout 1.12: a timing a few ticks ahead (of whatever entry follows it), a commit.
        O::AtTick => Plausible::typed(CardCmd::AtTick(firmware_proto::cmd::AtTick {
            tick: u64::from(s.u8()),
            key: u32::from(s.u8() % 3),
        })),
        O::SyncCommit => Plausible::typed(CardCmd::SyncCommit(firmware_proto::cmd::SyncCommit {
            key: 1 + u32::from(s.u8() % 2),
            tick: u64::from(s.u8()),
        })),
        _ => {
            feed(s);
            let cmd = Cmd::decode(op as u16, 0, &[0.0; CMD_ARGS])
                .expect("an opcode without arguments decodes from zeros");
            Plausible::typed(cmd)
        }
    }
}

/// A NURBS transfer: a plausible begin, the data entries of a clamped curve starting at the
/// origin (where a fresh card's groups are), an end; then a few mutations (broken values,
/// wrong offsets or counts, entries dropped or repeated, a missing begin or end).
fn nurbs_transfer<S: Source>(s: &mut S, out: &mut Vec<RawCmd>) {
    let g = target_index(s, true);
    let n = GROUPS.get(g as usize).map_or(2, |gr| gr.0.len());
    let degree = 1 + (s.u8() % 5) as usize;
    let n_ctrl = degree + 1 + (s.u8() % 6) as usize;
    let n_knots = n_ctrl + degree + 1;
    let Cmd::Group(GroupCmd::NurbsBegin(mut begin)) = plausible(s, Opcode::NurbsBegin).cmd else {
        unreachable!("a NURBS begin is one")
    };
    begin.size = CurveSize {
        degree: degree as f64,
        n_ctrl: n_ctrl as f64,
        n_knots: n_knots as f64,
    };
    begin.saturation = s.u8() < 32;
    let mut header = [0.0; CMD_ARGS];
    let flags = begin.encode(&mut header);
    // The stream: control points, weights, knots.
    let mut stream = Vec::with_capacity(n_ctrl * (n + 1) + n_knots);
    for i in 0..n_ctrl * n {
        stream.push(if i < n { 0.0 } else { position(s) });
    }
    for _ in 0..n_ctrl {
        stream.push(if s.u8() < 192 {
            1.0
        } else {
            magnitude(s, -2.0, 2.0)
        });
    }
    let inner = n_ctrl - degree;
    for k in 0..n_knots {
        stream.push(if k <= degree {
            0.0
        } else if k >= n_ctrl {
            1.0
        } else {
            (k - degree) as f64 / inner as f64
        });
    }
    // One transfer in eight is left intact: accepting a curve plans its look-ahead profile
    // (milliseconds), which would otherwise dominate the sweep.
    let mutations = [0, 1, 1, 2, 2, 3, 3, 3][(s.u8() % 8) as usize];
    for _ in 0..mutations {
        match s.u8() % 3 {
            0 => {
                let k = s.u16() as usize % CMD_ARGS;
                header[k] = garbage_f64(s);
            }
            _ => {
                let k = s.u16() as usize % stream.len();
                stream[k] = garbage_f64(s);
            }
        }
    }
    let mut entries = nurbs_entries(g, flags, &header, &stream, |_| 1 + s.u8() as usize % 12);
    if s.u8() < 64 {
        // the curve as a path segment
        let Cmd::Group(GroupCmd::PathNurbs(mut path)) = plausible(s, Opcode::PathNurbs).cmd else {
            unreachable!("a path NURBS is one")
        };
        // The header's sizes, as the mutations left them.
        path.size = CurveSize {
            degree: header[0],
            n_ctrl: header[1],
            n_knots: header[2],
        };
        entries[0] = RawCmd(GroupCmd::PathNurbs(path).command(g).to_words());
    }
    match s.u8() % 8 {
        0 if entries.len() > 1 => {
            let k = s.u16() as usize % entries.len();
            entries.remove(k);
        }
        1 => {
            let k = s.u16() as usize % entries.len();
            entries.insert(k, entries[k]);
        }
        2 => {
            // An offset or count field broken.
            let k = s.u16() as usize % entries.len();
            let mut c = entries[k].command();
            c.args[(s.u8() & 1) as usize] = garbage_f64(s);
            entries[k] = RawCmd(c.to_words());
        }
        _ => {}
    }
    out.extend(entries);
}

/// The entries of a NURBS transfer to group `g`: begin (`flags`, `header`), the data entries
/// of `stream` (`count(offset)` values each, at most 12), end.
pub fn nurbs_entries(
    g: u16,
    flags: u32,
    header: &[f64; CMD_ARGS],
    stream: &[f64],
    mut count: impl FnMut(usize) -> usize,
) -> Vec<RawCmd> {
    let mut entries = vec![RawCmd::new(Opcode::NurbsBegin as u16, g, flags, header)];
    let mut off = 0;
    while off < stream.len() {
        let n = count(off).clamp(1, firmware_proto::NURBS_DATA_MAX);
        let n = n.min(stream.len() - off);
        let data = NurbsData {
            offset: off as u32,
            values: stream[off..off + n].iter().copied().collect(),
        };
        entries.push(RawCmd(GroupCmd::NurbsData(data).command(g).to_words()));
        off += n;
    }
    entries.push(RawCmd(GroupCmd::NurbsEnd.command(g).to_words()));
    entries
}

/// One unit of command garbage (usually one entry; a NURBS transfer is several).
pub fn garbage_unit<S: Source>(s: &mut S, out: &mut Vec<RawCmd>) {
    match s.u8() {
        // Fully random words.
        0..=31 => {
            let mut w = [0u64; CMD_WORDS];
            for x in w.iter_mut() {
                *x = s.u64();
            }
            out.push(RawCmd(w));
        }
        // A continuation sequence.
        32..=47 => nurbs_transfer(s, out),
        // A (mostly) valid opcode with random axis, flags and argument bits.
        48..=127 => {
            let op = pick_opcode(s);
            let group = Opcode::from_raw(op).is_some_and(is_group_op);
            let axis = target_index(s, group);
            let flags = garbage_flags(s);
            let mut a = [0.0; CMD_ARGS];
            for x in a.iter_mut() {
                *x = garbage_f64(s);
            }
            out.push(RawCmd::new(op, axis, flags, &a));
        }
        // A plausible command with zero, one or two arguments (or the flags) broken.
        _ => {
            let op = Opcode::ALL[s.u8() as usize % Opcode::ALL.len()];
            let axis = target_index(s, is_group_op(op));
            let mut c = plausible(s, op).entry(axis);
            let broken = [0, 1, 1, 1, 2, 2, 2, 3][(s.u8() % 8) as usize];
            for _ in 0..broken {
                match s.u8() % 8 {
                    0 => c.flags ^= 1 << (s.u8() % 32),
                    // Mostly the arguments the opcode reads.
                    1..=5 => c.args[(s.u8() % 8) as usize] = garbage_f64(s),
                    _ => c.args[s.u8() as usize % CMD_ARGS] = garbage_f64(s),
                }
            }
            out.push(RawCmd(c.to_words()));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The gaps are gaps: a new opcode that lands on one must move it.
    #[test]
    fn opcode_gaps_are_no_opcodes() {
        for g in OPCODE_GAPS {
            assert_eq!(Opcode::from_raw(g), None, "{g} is an opcode");
        }
        let last = Opcode::ALL.iter().map(|&o| o as u16).max().unwrap();
        assert!(OPCODE_GAPS.contains(&(last + 1)), "the edge after {last}");
    }

    /// Every opcode has plausible commands, made through its type: an entry that decodes (a
    /// typed index may still be one past the card's) decodes back to the same entry, and one a
    /// draw wrote over (a value no type holds) does not decode.
    #[test]
    fn plausible_commands_go_through_their_types() {
        let mut s = RngSource::new(33);
        let mut overwritten = 0;
        for _ in 0..200 {
            for &op in Opcode::ALL {
                let p = plausible(&mut s, op);
                assert_eq!(p.cmd.opcode(), op);
                let e = p.entry(3);
                let back = Cmd::from_command(&e);
                match p.over {
                    None => {
                        if let Ok(c) = back {
                            assert_eq!(c.command(3).to_words(), e.to_words(), "{op:?}");
                        }
                    }
                    Some(_) => {
                        overwritten += 1;
                        assert!(back.is_err(), "{op:?} {:?} decoded", p.over);
                    }
                }
            }
        }
        assert!(overwritten > 0);
    }
}
