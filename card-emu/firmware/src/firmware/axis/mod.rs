//! One axis of the firmware: PLCopen state machine, profile execution (moves from any state,
//! PLCopen Aborting and Buffered, velocity mode, override), in-position detection, the servo
//! loop and the move statistics the card publishes; its position frame (the encoder count plus
//! the offset homing and MC_SetPosition set) and the hooks the homing methods drive it through.

// The position frame: the card works in `encoder + pos_offset`. Homing and MC_SetPosition move
// the offset, never the count, so the raw count the status publishes and the safety layer's
// encoder checks (which see raw counts) only ever see the shaft.
//
// Layout 1.9, leadscrew compensation: `encoder + pos_offset` is the motor's position; the
// axis's position (`act_pos`, the commanded and target positions, soft limits, in-position,
// following error) is the load's, the motor's less the correction in force. The servo follows
// `cmd + correction` (`comp_ref`, published as `comp_pos`). Homing runs with the correction
// taken out (the table is used only while homed and not homing), so its switch and index
// positions (`position_of_count`) are the motor's, which is then the load's.
//
// Layout 1.10, rotary (modulo) axes: with a period m (held as `modulo_q`, an integer in
// 1/65536 count) the frame is `encoder - turns·m + pos_offset`, the turn count `turns` an
// integer beside it, computed in i128 (`frame_position`): the position within the turn never
// grows, and nothing is summed, so it does not drift. Whenever the commanded position leaves
// [0, m) on the axis's own motion the frame moves by whole turns (`wrap_frame`): the commanded,
// actual and target positions, the running trajectory, the queued targets and the PD+ state
// move by the same multiple of m, so nothing the servo sees jumps. Velocity mode's cruise on a
// modulo axis is an integer too (`Motion::Cruise`: a start and a step per tick in 2^-32 count
// and the tick count), not a time summed tick by tick. While homing or in SynchronizedMotion
// (a group, a coupling, a PT/PVT stream sets the reference) the frame stands still and only the
// published positions wrap; it catches up at the first tick of the axis's own motion. A linear
// axis (`modulo_q == 0`) pays one branch in `sense` and one in `reference_into`.

use crate::firmware::axis_safety::AxisSafety;
use crate::firmware::nack::plan_nack;
use crate::firmware::rate_hz;
use crate::math;
use crate::motion::comp::{CompParams, CompPoint, CompState};
use crate::motion::otg::{OtgLimits, Trajectory};
use crate::motion::scurve::{bounded_stop_limits, plan_stop, Limits, Profile};
use crate::servo::biquad::ServoFilters;
use crate::servo::ffpiv::{gains_valid, Ffpiv, Reference, ServoTerms};
use crate::servo::pdplus::{AxisModel, PdPlus};
use crate::servo::pidff::{Pidff, PidffGains};
use firmware_proto::cmd::MoveDirection;
use firmware_proto::{
    AxisState, AxisStatus, Faults, Io, MotionFlags, NackCode, StopReason, AXIS_QUEUE_LEN,
    OVERRIDE_MAX,
};
use heapless::{Deque, Vec};

/// The validated copy of an axis's configuration: the block as the host wrote it (its fields
/// are the header's `mc_axis_config`) and, when its servo law is PD+, the PD+ law.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct AxisConfig {
    /// The configuration block: servo law, FFPIV gains, DAC clamp, in-position windows.
    pub block: firmware_proto::AxisConfig,
    /// The PD+ law (Yeh eq 2.12) and its drive model, when selected instead of FFPIV.
    pub pdplus: Option<AxisModel>,
    /// Layout 1.11: the PID+FF gains, when that law is selected.
    pub pidff: Option<PidffGains>,
}

impl core::ops::Deref for AxisConfig {
    type Target = firmware_proto::AxisConfig;
    fn deref(&self) -> &Self::Target {
        &self.block
    }
}

impl AxisConfig {
    /// Check every field of the block (not finite: `NotFinite`; out of range: `BadConfig`);
    /// the card never runs with a configuration it has not checked.
    pub fn validate(&self) -> Result<(), NackCode> {
        let b = &self.block;
        let g = &b.ffpiv;
        let fin = [
            g.kp,
            g.ki,
            g.kv,
            g.kvff,
            g.kaff,
            g.vel_filter_hz,
            b.dac_limit_v,
            b.in_pos_window,
            b.in_vel_window,
            b.settle_time,
            b.jog_max_vel,
            b.jog_accel,
            b.jog_jerk,
        ];
        if fin.iter().any(|x| !x.is_finite()) {
            return Err(NackCode::NotFinite);
        }
        let dac_ok = b.dac_limit_v > 0.0 && b.dac_limit_v <= 10.0;
        if !gains_valid(g)
            || !dac_ok
            || b.in_pos_window <= 0.0
            || b.in_vel_window <= 0.0
            || !(0.0..=10.0).contains(&b.settle_time)
            || b.jog_max_vel <= 0.0
            || b.jog_accel <= 0.0
            || b.jog_jerk <= 0.0
        {
            return Err(NackCode::BadConfig);
        }
        Ok(())
    }
}

/// The servo law an axis runs besides its FFPIV state (kept whatever the law: it is the
/// velocity estimator): one match a tick.
#[derive(Debug, Clone, Copy, PartialEq)]
#[allow(clippy::large_enum_variant)] // inline on purpose: the firmware never allocates
enum Law {
    /// FFPIV (Thinh Fig 5).
    Ffpiv,
    /// PD+ (Yeh eq 2.12).
    PdPlus(PdPlus),
    /// PID + feed-forward (layout 1.11, Kim §5).
    Pidff(Pidff),
}

/// What the axis's profile is doing.
#[derive(Debug, Clone, Copy, PartialEq)]
#[allow(clippy::large_enum_variant)] // stored inline on purpose: the firmware never allocates
enum Motion {
    /// Holding the commanded position.
    Hold,
    /// Running a trajectory; `t` is the time into it, `seg` the segment it was last sampled in
    /// (where the next sample's search starts). Moves and halts end in Standstill once in
    /// position; a stop stays in Stopping until released; velocity mode runs on at the
    /// trajectory's end velocity.
    Run {
        traj: Trajectory,
        t: f64,
        seg: usize,
    },
    /// Layout 1.10: velocity mode at its velocity on a modulo axis, in integers: the commanded
    /// position is `(base + k · step) / 2^32` counts (`k` ticks since `base`, `step` the
    /// velocity times the period rounded to 2^-32 count), `vel` the commanded velocity.
    Cruise {
        base: i128,
        step: i128,
        k: u64,
        vel: f64,
    },
}

/// Sub-counts of a cruise's position (`Motion::Cruise`): 2^32 a count.
const CRUISE_SUB: f64 = 4_294_967_296.0;

/// What the running motion is for: what a retarget or an override plans towards again.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Goal {
    /// A stop ramp, or nothing: no replanning.
    None,
    /// A position move (MC_MoveAbsolute/Relative/Additive) to `target` within `lim` (before
    /// the override).
    Position { target: f64, lim: Limits },
    /// Velocity mode (MC_MoveVelocity, jog) at `vel` (before the override), accelerating
    /// within `lim.amax`/`lim.dmax`/`lim.j1`.
    Velocity { vel: f64, lim: Limits },
}

/// Which of PLCopen's single-axis position moves.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MoveKind {
    /// MC_MoveAbsolute: the argument is the target.
    Absolute,
    /// MC_MoveRelative: a distance from the commanded position (buffered: from the target of
    /// the move before it).
    Relative,
    /// MC_MoveAdditive: a distance from the target of the last move.
    Additive,
}

/// A move waiting in the axis's queue (PLCopen Buffered): its target is fixed when queued.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Queued {
    seq: u32,
    goal: Goal,
}

/// How a motion command was taken.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Started {
    /// It runs from this tick (Aborting, or Buffered on an axis with nothing to wait for).
    Now,
    /// It waits in the axis's queue (Buffered).
    Queued,
}

/// Things the axis tells the command manager after a tick.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct TickReport {
    /// The motion started by command `seq` reached its target and is in position:
    /// raise motion done with (seq, actual position).
    pub done: Option<(u32, f64)>,
    /// A buffered move `seq` started (PLCopen Active): (seq, target or velocity).
    pub active: Option<(u32, f64)>,
    /// Velocity mode of command `seq` reached its velocity (PLCopen InVelocity).
    pub in_velocity: Option<(u32, f64)>,
    /// Buffered moves dropped because the one due to start could not be planned from where
    /// the axis is (its seq first): each gets its motion-aborted event.
    pub dropped: Dropped,
    /// The state changed from this one.
    pub state_from: Option<AxisState>,
}

impl TickReport {
    /// Nothing to tell (the default).
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.done.is_none()
            && self.active.is_none()
            && self.in_velocity.is_none()
            && self.dropped.is_empty()
            && self.state_from.is_none()
    }
}

/// The seqs of the buffered moves a command or a fault dropped.
pub type Dropped = Vec<u32, AXIS_QUEUE_LEN>;

/// One axis.
#[derive(Debug, Clone)]
pub struct Axis {
    /// PLCopen state.
    pub state: AxisState,
    /// Active configuration.
    pub config: AxisConfig,
    /// Safety configuration and state (safety.rs).
    pub safety: AxisSafety,
    motion: Motion,
    goal: Goal,
    queue: Deque<Queued, AXIS_QUEUE_LEN>,
    /// The velocity override factor (MC_SetOverride), 0..=OVERRIDE_MAX.
    override_factor: f64,
    in_velocity: bool,
    buffered_active: bool,
    servo: Ffpiv,
    /// A gantry's member: the servo reads the count at its middle while moving
    /// ([`Axis::set_mid_count`]).
    mid_count: bool,
    cmd: Reference,
    cmd_jerk: f64,
    prev_cmd_acc: f64,
    raw_vel: f64,
    u_request: f64,
    /// The servo law's terms of the tick (the scope's `MC_SIG_SERVO_*`); 0 while unpowered.
    servo_terms: ServoTerms,
    law: Law,
    /// Layout 1.11: the biquad filters on the law's output, and that output of the tick (the
    /// chain's input; 0 while unpowered).
    filters: ServoFilters,
    law_out: f64,
    target: f64,
    act_pos: f64,
    encoder: i64,
    /// Position = encoder count + this (set by homing and MC_SetPosition).
    pos_offset: f64,
    /// The position was set by homing or MC_SetPosition (`MC_MOTION_HOMED`).
    homed: bool,
    /// The limit switches a homing method watches itself (the safety layer does not trip on
    /// them); empty outside Homing.
    homing_limits: Io,
    ferr: f64,
    dac_v: f64,
    faults: Faults,
    last_seq: u32,
    motion_seq: u32,
    move_count: u32,
    settled_for: f64,
    awaiting_done: bool,
    stop_released: bool,
    /// A stop (halt, stop, safety stop, starvation) in progress: seconds since it began.
    stop_elapsed: Option<f64>,
    stats: MoveStats,
    /// Layout 1.7 (sync): a geared slave follows its master (`MC_MOTION_IN_SYNC`).
    in_sync: bool,
    /// Layout 1.9: the leadscrew compensation's state (the table is the firmware's:
    /// `firmware::comp`). `act_pos` is the motor's position less its correction.
    comp: CompState,
    /// The servo's reference: `cmd` plus the correction (the motor's frame).
    comp_ref: Reference,
    /// Layout 1.10: the modulo period in 1/65536 count (0: a linear axis), the same in counts,
    /// and the whole turns the frame has moved by (see the module's head).
    modulo_q: i64,
    modulo: f64,
    turns: i64,
    /// The direction of the last motion planned (+1 or −1): `MC_MOVE_DIR_CURRENT` at rest.
    last_dir: f64,
    /// Layout 1.12: a frequency sweep's sine of the tick (`firmware::freq`), on the position
    /// reference (counts) or on the servo output (V); 0 and 0 without a sweep.
    inject: Injection,
}

/// Layout 1.12: what a frequency sweep adds to an axis's servo loop this tick.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Injection {
    /// Added to the position reference the servo law sees (not to its velocity or
    /// acceleration, nor to the published commanded position), counts.
    pub reference: f64,
    /// Added to the servo output after the filters, before the DAC clamp, V.
    pub output: f64,
}

#[derive(Debug, Clone, Copy, PartialEq, Default)]
struct MoveStats {
    peak_vel: f64,
    peak_acc: f64,
    peak_dec: f64,
    peak_jerk: f64,
    max_ferr: f64,
    planned_time: f64,
    elapsed: f64,
    move_time: f64,
}

impl Default for Axis {
    fn default() -> Self {
        Self::new()
    }
}

impl Axis {
    /// A disabled axis at position 0.
    pub fn new() -> Self {
        Self {
            state: AxisState::Disabled,
            config: AxisConfig::default(),
            safety: AxisSafety::new(),
            motion: Motion::Hold,
            goal: Goal::None,
            queue: Deque::new(),
            override_factor: 1.0,
            in_velocity: false,
            buffered_active: false,
            servo: Ffpiv::default(),
            mid_count: false,
            cmd: Reference {
                pos: 0.0,
                vel: 0.0,
                acc: 0.0,
            },
            cmd_jerk: 0.0,
            prev_cmd_acc: 0.0,
            raw_vel: 0.0,
            u_request: 0.0,
            servo_terms: ServoTerms::default(),
            law: Law::Ffpiv,
            filters: ServoFilters::default(),
            law_out: 0.0,
            target: 0.0,
            act_pos: 0.0,
            encoder: 0,
            pos_offset: 0.0,
            homed: false,
            homing_limits: Io::empty(),
            ferr: 0.0,
            dac_v: 0.0,
            faults: Faults::empty(),
            last_seq: 0,
            motion_seq: 0,
            move_count: 0,
            settled_for: 0.0,
            awaiting_done: false,
            stop_released: false,
            stop_elapsed: None,
            stats: MoveStats::default(),
            in_sync: false,
            comp: CompState::new(),
            comp_ref: Reference {
                pos: 0.0,
                vel: 0.0,
                acc: 0.0,
            },
            modulo_q: 0,
            modulo: 0.0,
            turns: 0,
            last_dir: 1.0,
            inject: Injection::default(),
        }
    }

    /// The commanded reference.
    pub fn reference(&self) -> Reference {
        self.cmd
    }

    /// Record the seq of an accepted command.
    pub fn accepted(&mut self, seq: u32) {
        self.last_seq = seq;
    }

    fn set_state(&mut self, s: AxisState, report: &mut Option<AxisState>) {
        if self.state != s {
            report.get_or_insert(self.state);
            self.state = s;
        }
        if s != AxisState::Homing {
            self.homing_limits = Io::empty();
        }
        if s != AxisState::SynchronizedMotion {
            self.in_sync = false;
        }
    }

    /// MC_Power.
    pub fn power(&mut self, on: bool) -> Result<Option<AxisState>, NackCode> {
        let mut changed = None;
        if on {
            match self.state {
                AxisState::Disabled => {
                    self.cmd = Reference {
                        pos: self.act_pos,
                        vel: 0.0,
                        acc: 0.0,
                    };
                    self.target = self.act_pos;
                    self.servo.reset_integral();
                    match &mut self.law {
                        Law::PdPlus(pd) => pd.reset(self.act_pos),
                        Law::Pidff(pid) => pid.reset(),
                        Law::Ffpiv => {}
                    }
                    self.motion = Motion::Hold;
                    self.set_state(AxisState::Standstill, &mut changed);
                }
                AxisState::ErrorStop => return Err(NackCode::InvalidState),
                _ => {}
            }
        } else {
            self.motion = Motion::Hold;
            self.goal = Goal::None;
            self.in_velocity = false;
            self.awaiting_done = false;
            self.stop_elapsed = None;
            // [safety] ErrorStop is left only by MC_Reset: power off removes power, keeps the state.
            if self.state == AxisState::ErrorStop {
                self.safety.powered = false;
                return Ok(None);
            }
            if self.state != AxisState::Disabled {
                self.safety.stop_reason = StopReason::PowerOff;
            }
            self.set_state(AxisState::Disabled, &mut changed);
        }
        Ok(changed)
    }

    /// The seq of the command whose motion is still waiting for its motion-done (or, in
    /// velocity mode, still in command), if any: an Aborting command aborts it.
    pub fn pending_motion(&self) -> Option<u32> {
        self.awaiting_done.then_some(self.motion_seq)
    }

    /// Drop every buffered move (an Aborting command, a halt or stop, power off, a fault):
    /// their seqs, for their motion-aborted events.
    pub fn drain_queue(&mut self) -> Dropped {
        let mut out = Dropped::new();
        while let Some(q) = self.queue.pop_front() {
            let _ = out.push(q.seq); // never full: the queue holds at most as many
        }
        out
    }

    /// The target of the last position move (queued ones included): where MC_MoveAdditive
    /// (and a buffered MC_MoveRelative) count from. In velocity mode, or with no move yet, the
    /// commanded position.
    pub fn last_target(&self) -> f64 {
        let last = self.queue.back().map(|q| q.goal).unwrap_or(self.goal);
        match last {
            Goal::Position { target, .. } => target,
            _ if self.queue.is_empty() && self.goal == Goal::None => self.target,
            _ => self.cmd.pos,
        }
    }

    fn check_can_move(&self) -> Result<(), NackCode> {
        match self.state {
            AxisState::Standstill | AxisState::DiscreteMotion | AxisState::ContinuousMotion => {
                Ok(())
            }
            AxisState::Disabled => Err(NackCode::AxisDisabled),
            AxisState::Homing => Err(NackCode::AxisHoming),
            _ => Err(NackCode::InvalidState),
        }
    }

    /// The target a position move names: `arg` is the target (absolute) or a distance from the
    /// commanded position (relative; buffered: from the last target) or from the last target
    /// (additive). `OutOfRange` beyond the position range.
    pub fn move_target(&self, kind: MoveKind, arg: f64, buffered: bool) -> Result<f64, NackCode> {
        self.move_target_dir(kind, arg, buffered, MoveDirection::Shortest)
    }

    /// [`Axis::move_target`] with an absolute move's direction (layout 1.10): on a modulo axis
    /// the target is in [0, m) (else `ModuloMove`) and the move goes the way `dir` names, from
    /// the commanded position (buffered: the last target) to the target's place in the turn; a
    /// target within the in-position window of the start is no turn at all. On a linear axis a
    /// direction other than `Shortest` is refused (`ModuloMove`).
    pub fn move_target_dir(
        &self,
        kind: MoveKind,
        arg: f64,
        buffered: bool,
        dir: MoveDirection,
    ) -> Result<f64, NackCode> {
        if kind == MoveKind::Absolute {
            if self.modulo_q != 0 {
                return self.modulo_target(arg, buffered, dir);
            }
            if dir != MoveDirection::Shortest {
                return Err(NackCode::ModuloMove);
            }
        }
        let target = match kind {
            MoveKind::Absolute => arg,
            MoveKind::Relative if !buffered => self.cmd.pos + arg,
            MoveKind::Relative | MoveKind::Additive => self.last_target() + arg,
        };
        if !target.is_finite() || target.abs() > crate::MAX_POSITION {
            return Err(NackCode::OutOfRange);
        }
        Ok(target)
    }

    /// An absolute move's target in the frame on a modulo axis (see [`Axis::move_target_dir`]).
    #[inline(never)]
    fn modulo_target(&self, arg: f64, buffered: bool, dir: MoveDirection) -> Result<f64, NackCode> {
        let m = self.modulo;
        if !arg.is_finite() {
            return Err(NackCode::OutOfRange);
        }
        if !(0.0..m).contains(&arg) {
            return Err(NackCode::ModuloMove);
        }
        let from = if buffered {
            self.last_target()
        } else {
            self.cmd.pos
        };
        // The way forward to the target, in [0, m).
        let mut fwd = arg - self.wrap(from);
        if fwd < 0.0 {
            fwd += m;
        }
        if fwd >= m {
            fwd -= m;
        }
        let back = fwd - m;
        let w = self.config.in_pos_window;
        let positive = match dir {
            // A tie (half a turn, to the rounding of the host's unit conversion) goes positive.
            MoveDirection::Shortest => fwd <= m / 2.0 * (1.0 + 1e-12),
            MoveDirection::Positive => true,
            MoveDirection::Negative => false,
            MoveDirection::Current => {
                let v = self.cmd.vel;
                if v != 0.0 {
                    v > 0.0
                } else {
                    self.last_dir > 0.0
                }
            }
        };
        // Where the axis is (within the window) is no turn whichever way is named.
        let d = if positive && fwd <= m - w || !positive && fwd < w {
            fwd
        } else {
            back
        };
        Ok(from + d)
    }

    /// `x` wrapped into [0, m) on a modulo axis (`x` itself on a linear one).
    #[inline]
    pub fn wrap(&self, x: f64) -> f64 {
        if self.modulo_q == 0 {
            return x;
        }
        let m = self.modulo;
        let mut r = x - math::floor(x / m) * m;
        if r >= m {
            r -= m;
        }
        if r < 0.0 {
            r += m;
            if r >= m {
                r = 0.0;
            }
        }
        r
    }

    /// Velocity mode at `vel` on a modulo axis: cruise in integers from the commanded position
    /// (out of line: a linear axis's tick does not carry its i128s).
    #[inline(never)]
    fn start_cruise(&mut self, vel: f64, ts: f64) {
        self.motion = Motion::Cruise {
            base: math::round(self.cmd.pos * CRUISE_SUB) as i128,
            step: math::round(vel * ts * CRUISE_SUB) as i128,
            k: 0,
            vel,
        };
    }

    /// One tick of the cruise: the commanded position `(base + k · step) / 2^32`.
    #[inline(never)]
    fn cruise_step(&mut self) {
        if let Motion::Cruise { base, step, k, vel } = &mut self.motion {
            *k += 1;
            let q = *base + *step * *k as i128;
            self.cmd = Reference {
                pos: q as f64 / CRUISE_SUB,
                vel: *vel,
                acc: 0.0,
            };
        }
    }

    /// The modulo period, counts (0: linear).
    pub fn modulo(&self) -> f64 {
        self.modulo
    }

    /// Is this a modulo axis?
    #[inline]
    pub fn is_modulo(&self) -> bool {
        self.modulo_q != 0
    }

    /// The frame's whole turns in 1/65536 count (`turns · m`; 0 on a linear axis): a
    /// commanded-position master's count runs on across its wrap (gear.rs).
    #[inline]
    pub fn turn_subcounts(&self) -> i128 {
        self.turns as i128 * self.modulo_q as i128
    }

    /// The whole turns the frame has moved by since the period was set (see the module's head).
    pub fn turns(&self) -> i64 {
        self.turns
    }

    /// `MC_OP_SET_MODULO`, checked by the caller (at rest; 0 or in range, in 1/65536 count):
    /// the new period. The position stays where it is (the old turns folded into the offset),
    /// then the frame is wrapped into the new period at once.
    pub fn set_modulo(&mut self, modulo_q: i64) {
        if self.turns != 0 {
            // Back to an unwrapped frame: the turns folded into the offset, rounded once.
            let d = self.turns as f64 * self.modulo;
            self.turns = 0;
            self.pos_offset -= d;
        }
        self.modulo_q = modulo_q;
        self.modulo = modulo_q as f64 / firmware_proto::COMMANDED_SUBCOUNTS as f64;
        self.act_pos = self.frame_position(self.encoder) + self.pos_offset - self.comp.applied().0;
        self.wrap_frame();
    }

    /// The frame's position of the raw count `count`, before the offset: `count − turns · m`,
    /// in integers (exact for any count; rounded once, within the turn, to a double).
    #[inline(never)]
    fn frame_position(&self, count: i64) -> f64 {
        let sub = firmware_proto::COMMANDED_SUBCOUNTS;
        let q = count as i128 * sub - self.turns as i128 * self.modulo_q as i128;
        q as f64 / sub as f64
    }

    /// Move the frame by whole turns when the commanded position left [0, m) on the axis's own
    /// motion (a modulo axis; not while homing or in SynchronizedMotion, whose references come
    /// from outside in the frame they started in).
    #[inline(never)]
    fn wrap_frame(&mut self) {
        if self.modulo_q == 0
            || matches!(
                self.state,
                AxisState::Homing | AxisState::SynchronizedMotion
            )
        {
            return;
        }
        let m = self.modulo;
        let p = self.cmd.pos;
        if (0.0..m).contains(&p) || !p.is_finite() {
            return;
        }
        let mut j = math::floor(p / m) as i64;
        if j == 0 {
            j = if p < 0.0 { -1 } else { 1 };
        }
        self.shift_turns(j);
    }

    /// The frame moves by `j` whole turns: every position the axis holds moves by `−j · m`.
    fn shift_turns(&mut self, j: i64) {
        let sub = firmware_proto::COMMANDED_SUBCOUNTS;
        let dq = j as i128 * self.modulo_q as i128;
        let d = dq as f64 / sub as f64;
        self.turns += j;
        self.act_pos = self.frame_position(self.encoder) + self.pos_offset - self.comp.applied().0;
        self.cmd.pos -= d;
        self.comp_ref.pos -= d;
        self.target -= d;
        match &mut self.motion {
            Motion::Run { traj, .. } => traj.shift(-d),
            Motion::Cruise { base, .. } => *base -= dq << 16,
            Motion::Hold => {}
        }
        if let Goal::Position { target, .. } = &mut self.goal {
            *target -= d;
        }
        for q in self.queue.iter_mut() {
            if let Goal::Position { target, .. } = &mut q.goal {
                *target -= d;
            }
        }
        if let Law::PdPlus(pd) = &mut self.law {
            pd.shift(-d);
        }
    }

    /// Is the axis running a motion a buffered move has to wait for (a move or halt not yet
    /// done, velocity mode not yet at its velocity)?
    fn busy(&self) -> bool {
        self.awaiting_done && !(matches!(self.goal, Goal::Velocity { .. }) && self.in_velocity)
    }

    /// MC_MoveAbsolute, MC_MoveRelative, MC_MoveAdditive (`kind`) within `limits` (checked
    /// against the card's ranges at `rate_hz` by the caller). Aborting (`buffered = false`):
    /// planned now from the commanded state, time-optimal, running from this tick; the caller
    /// drops the queue. Buffered: queued behind the motion in progress (else run now).
    pub fn start_move(
        &mut self,
        seq: u32,
        kind: MoveKind,
        arg: f64,
        limits: &Limits,
        buffered: bool,
        rate_hz: u32,
    ) -> Result<(Option<AxisState>, Started), NackCode> {
        let dir = MoveDirection::Shortest;
        self.start_move_dir(seq, kind, arg, limits, buffered, rate_hz, dir)
    }

    /// [`Axis::start_move`] with an absolute move's direction on a modulo axis (layout 1.10,
    /// see [`Axis::move_target_dir`]).
    #[allow(clippy::too_many_arguments)]
    pub fn start_move_dir(
        &mut self,
        seq: u32,
        kind: MoveKind,
        arg: f64,
        limits: &Limits,
        buffered: bool,
        rate_hz: u32,
        dir: MoveDirection,
    ) -> Result<(Option<AxisState>, Started), NackCode> {
        self.check_can_move()?;
        let target = self.move_target_dir(kind, arg, buffered, dir)?;
        let goal = Goal::Position {
            target,
            lim: *limits,
        };
        if buffered && self.busy() {
            // The plan is made when it starts; what can be checked now is checked now.
            self.queue
                .push_back(Queued { seq, goal })
                .map_err(|_| NackCode::QueueFull)?;
            return Ok((None, Started::Queued));
        }
        let changed = self.run_goal(seq, goal, rate_hz)?;
        self.buffered_active = false;
        Ok((changed, Started::Now))
    }

    /// MC_MoveVelocity (and jog): velocity mode at the signed `vel`, reached within `lim`'s
    /// acceleration, deceleration and jerk from the commanded state. Aborting.
    pub fn start_velocity(
        &mut self,
        seq: u32,
        vel: f64,
        lim: &Limits,
        rate_hz: u32,
    ) -> Result<Option<AxisState>, NackCode> {
        self.check_can_move()?;
        let changed = self.run_goal(seq, Goal::Velocity { vel, lim: *lim }, rate_hz)?;
        self.buffered_active = false;
        Ok(changed)
    }

    /// MC_SetOverride: the new velocity factor, planned from the commanded state towards the
    /// goal in progress (a position move or velocity mode). Refused (`OverrideRange`) outside
    /// 0..=OVERRIDE_MAX; a factor the running goal cannot be planned with is refused with the
    /// planner's nack and changes nothing.
    pub fn set_override(&mut self, factor: f64, rate_hz: u32) -> Result<(), NackCode> {
        if !factor.is_finite() {
            return Err(NackCode::NotFinite);
        }
        if !(0.0..=OVERRIDE_MAX).contains(&factor) {
            return Err(NackCode::OverrideRange);
        }
        let old = self.override_factor;
        self.override_factor = factor;
        let replan = self.awaiting_done
            && matches!(
                self.state,
                AxisState::DiscreteMotion | AxisState::ContinuousMotion
            )
            && self.goal != Goal::None;
        if replan {
            match self.plan(&self.goal, rate_hz) {
                Ok(traj) => {
                    self.motion = Motion::Run {
                        traj,
                        t: 0.0,
                        seg: 0,
                    }
                }
                Err(e) => {
                    self.override_factor = old;
                    return Err(e);
                }
            }
            self.in_velocity = false;
        }
        Ok(())
    }

    /// Plan `goal` from the commanded state with the override in force. From rest, a position
    /// move is the card's rest-to-rest S-curve with its four jerks; from motion, the
    /// time-optimal trajectory from any state with one jerk (the smallest). A 0 % override
    /// plans a stop where the axis then waits.
    fn plan(&self, goal: &Goal, rate_hz: u32) -> Result<Trajectory, NackCode> {
        self.plan_scaled(goal, rate_hz, self.override_factor)
    }

    /// [`Axis::plan`] with the velocity factor `k` instead of the override in force.
    fn plan_scaled(&self, goal: &Goal, rate_hz: u32, k: f64) -> Result<Trajectory, NackCode> {
        let c = self.cmd;
        let traj = match *goal {
            Goal::None => return Err(NackCode::InvalidState),
            Goal::Position { lim, .. } | Goal::Velocity { lim, .. } if k == 0.0 => {
                let dir = if c.vel != 0.0 { c.vel.signum() } else { 1.0 };
                let l = OtgLimits::along(dir, &lim);
                Trajectory::to_velocity(c.pos, c.vel, c.acc, 0.0, &l)
            }
            Goal::Position { target, lim } => {
                let eff = Limits {
                    vmax: lim.vmax * k,
                    ..lim
                };
                eff.check_range(rate_hz).map_err(plan_nack)?;
                if c.vel == 0.0 && c.acc == 0.0 {
                    Profile::plan_checked(c.pos, target - c.pos, 0.0, 0.0, &eff, rate_hz)
                        .map(|p| Trajectory::from_profile(&p))
                } else {
                    let dir = if target != c.pos {
                        (target - c.pos).signum()
                    } else {
                        c.vel.signum()
                    };
                    let l = OtgLimits::along(dir, &eff);
                    // Above a lowered limit: down to it first (replanned from there when the
                    // ramp ends), rather than dipping below it.
                    match Trajectory::slow_to_limit(c.pos, c.vel, c.acc, target, &l) {
                        Some(ramp) => Ok(ramp),
                        None => Trajectory::to_position(c.pos, c.vel, c.acc, target, 0.0, &l),
                    }
                    .and_then(|t| t.verify(&l).map(|()| t))
                }
            }
            Goal::Velocity { vel, lim } => {
                let v = vel * k;
                let dir = if v != 0.0 { v.signum() } else { c.vel.signum() };
                let top = *firmware_proto::limit_range(1, rate_hz).end();
                let l = OtgLimits {
                    vmax: top,
                    vmin: -top,
                    ..OtgLimits::along(dir, &lim)
                };
                Trajectory::to_velocity(c.pos, c.vel, c.acc, v, &l)
                    .and_then(|t| t.verify(&l).map(|()| t))
            }
        }
        .map_err(plan_nack)?;
        if !traj.duration().is_finite() || traj.duration() > crate::MAX_MOVE_TIME {
            return Err(NackCode::Infeasible);
        }
        Ok(traj)
    }

    /// Plan `goal` and run it from this tick as the motion of command `seq`.
    fn run_goal(
        &mut self,
        seq: u32,
        goal: Goal,
        rate_hz: u32,
    ) -> Result<Option<AxisState>, NackCode> {
        let traj = self.plan(&goal, rate_hz)?;
        let state = match goal {
            Goal::Position { .. } => AxisState::DiscreteMotion,
            _ => AxisState::ContinuousMotion,
        };
        // MC_MOVE_DIR_CURRENT at rest: the way the last motion went.
        let way = match goal {
            Goal::Position { target, .. } => target - self.cmd.pos,
            Goal::Velocity { vel, .. } => vel,
            Goal::None => 0.0,
        };
        if way != 0.0 {
            self.last_dir = way.signum();
        }
        self.begin_motion(seq, traj.duration());
        self.take_goal(goal, traj);
        let mut changed = None;
        self.set_state(state, &mut changed);
        Ok(changed)
    }

    /// Run `traj` from this tick towards `goal` (its target is the axis's target).
    fn take_goal(&mut self, goal: Goal, traj: Trajectory) {
        if let Goal::Position { target, .. } = goal {
            self.target = target;
        }
        self.goal = goal;
        self.in_velocity = false;
        self.motion = Motion::Run {
            traj,
            t: 0.0,
            seg: 0,
        };
        self.stop_elapsed = None;
    }

    /// Start the next buffered move, if any, now that the motion before it is done (or, in
    /// velocity mode, at its velocity). A move that cannot be planned from here (its limits
    /// no longer fit the state) is aborted: `Err(seq)`. A state it changes (velocity mode's
    /// ContinuousMotion to DiscreteMotion) goes into `state_from`.
    fn start_next(
        &mut self,
        rate_hz: u32,
        state_from: &mut Option<AxisState>,
    ) -> Option<Result<(u32, f64), u32>> {
        let q = self.queue.pop_front()?;
        Some(match self.run_goal(q.seq, q.goal, rate_hz) {
            Ok(changed) => {
                if let Some(old) = changed {
                    state_from.get_or_insert(old);
                }
                self.buffered_active = true;
                let value = match q.goal {
                    Goal::Position { target, .. } => target,
                    Goal::Velocity { vel, .. } => vel,
                    Goal::None => 0.0,
                };
                Ok((q.seq, value))
            }
            Err(_) => Err(q.seq),
        })
    }

    /// MC_Halt (`stop = false`) or MC_Stop: a jerk-limited stop from the current commanded
    /// state within `dmax` and `jerk`, or along the axis's stop ramp when that one would take
    /// longer than `max_time` s (see [`bounded_stop_limits`]). The caller drops the queue.
    pub fn start_stop(
        &mut self,
        seq: u32,
        stop: bool,
        dmax: f64,
        jerk: f64,
        max_time: f64,
    ) -> Result<Option<AxisState>, NackCode> {
        match (self.state, stop) {
            (AxisState::Disabled, _) => return Err(NackCode::AxisDisabled),
            (AxisState::ErrorStop, _) => return Err(NackCode::InvalidState),
            (AxisState::Stopping, false) => return Err(NackCode::InvalidState),
            _ => {}
        }
        let mut changed = None;
        let planned = self.run_bounded_stop(dmax, jerk, max_time)?;
        self.begin_motion(seq, planned);
        self.safety.stop_reason = if stop {
            StopReason::Stop
        } else {
            StopReason::Halt
        };
        // A halt ends velocity mode as a discrete motion (PLCopen: Halt is DiscreteMotion).
        let state = if stop {
            self.stop_released = false;
            AxisState::Stopping
        } else {
            AxisState::DiscreteMotion
        };
        if self.state != AxisState::Standstill || stop {
            self.set_state(state, &mut changed);
        }
        Ok(changed)
    }

    fn run_profile_now(&mut self, p: &Profile) {
        self.motion = Motion::Run {
            traj: Trajectory::from_profile(p),
            t: 0.0,
            seg: 0,
        };
    }

    fn begin_motion(&mut self, seq: u32, planned: f64) {
        self.safety.stop_reason = StopReason::None;
        self.motion_seq = seq;
        self.move_count = self.move_count.wrapping_add(1);
        self.stats = MoveStats {
            planned_time: planned,
            ..Default::default()
        };
        self.awaiting_done = true;
        self.settled_for = 0.0;
    }

    /// MC_Stop with Execute falling: leave Stopping once at rest.
    pub fn release_stop(&mut self) -> Result<(), NackCode> {
        if self.state != AxisState::Stopping {
            return Err(NackCode::InvalidState);
        }
        self.stop_released = true;
        Ok(())
    }

    /// MC_Reset: only from ErrorStop.
    pub fn reset(&mut self) -> Result<Option<AxisState>, NackCode> {
        if self.state != AxisState::ErrorStop {
            return Err(NackCode::InvalidState);
        }
        let mut changed = None;
        self.faults = Faults::empty();
        self.cmd = Reference {
            pos: self.act_pos,
            vel: 0.0,
            acc: 0.0,
        };
        self.motion = Motion::Hold;
        self.goal = Goal::None;
        self.stop_elapsed = None;
        self.servo.reset_integral();
        // [safety] clear the latches; an axis whose drive was disabled by the stop goes to Disabled.
        let powered = self.safety.reset();
        self.set_state(
            if powered {
                AxisState::Standstill
            } else {
                AxisState::Disabled
            },
            &mut changed,
        );
        Ok(changed)
    }

    /// One servo tick: sensors in, DAC volts out.
    pub fn tick(&mut self, encoder: i64, ts: f64) -> (f64, TickReport) {
        self.sense(encoder, ts);
        self.control(ts)
    }

    /// Read this tick's encoder: actual position, raw and filtered velocity.
    #[inline] // called from the generic tick, instantiated in the crate that runs it
    pub fn sense(&mut self, encoder: i64, ts: f64) {
        self.raw_vel = encoder.wrapping_sub(self.encoder) as f64 / ts;
        self.encoder = encoder;
        // The load's position: the motor's less the correction in force (0 without
        // compensation, and then the subtraction changes nothing).
        let frame = if self.modulo_q == 0 {
            encoder as f64
        } else {
            self.frame_position(encoder)
        };
        self.act_pos = frame + self.pos_offset - self.comp.applied().0;
        self.servo.measure(encoder, &self.config.ffpiv, ts);
    }

    /// Actual position (counts) and velocity over the last tick (counts/s, unfiltered: the
    /// `w_a[k]` of Yeh eq 3.3).
    pub fn actual(&self) -> (f64, f64) {
        (self.act_pos, self.raw_vel)
    }

    /// Select the servo law of the configuration at sample time `ts` (on apply, or when the
    /// servo rate changes).
    ///
    /// Layout 1.11: a switch to PID+FF or FFPIV is bumpless (their integrators take over the
    /// output of the tick: at rest the DAC does not step); PID+FF retuned keeps its
    /// integrator's term (volts). PD+ has no integrator to take anything over.
    pub fn apply_config(&mut self, cfg: AxisConfig, ts: f64) {
        self.config = cfg;
        let was_ffpiv = self.law == Law::Ffpiv;
        self.law = if let Some(m) = cfg.pdplus {
            match PdPlus::new(m.gains, ts) {
                Ok(mut pd) => {
                    pd.reset(self.act_pos);
                    Law::PdPlus(pd)
                }
                Err(_) => Law::Ffpiv,
            }
        } else if let Some(g) = cfg.pidff {
            match self.law {
                Law::Pidff(mut pid) => {
                    pid.retune(g, ts);
                    Law::Pidff(pid)
                }
                _ => {
                    let mut pid = Pidff::new(g, ts);
                    pid.transfer(self.law_out);
                    Law::Pidff(pid)
                }
            }
        } else {
            if !was_ffpiv {
                self.servo.transfer(self.law_out, &cfg.ffpiv);
            }
            Law::Ffpiv
        };
    }

    /// Layout 1.12: set this tick's sweep injection (`Injection::default()`: none).
    pub fn set_injection(&mut self, inject: Injection) {
        self.inject = inject;
    }

    /// Layout 1.12: the sweep injection in force.
    pub fn injection(&self) -> Injection {
        self.inject
    }

    /// Layout 1.12: at rest, holding its position, nothing driving it (what a sweep needs
    /// and keeps).
    pub fn holding(&self) -> bool {
        self.state == AxisState::Standstill
            && self.motion == Motion::Hold
            && self.goal == Goal::None
            && self.is_powered()
    }

    /// Layout 1.11: the biquad filters on the servo output.
    pub fn filters(&self) -> &ServoFilters {
        &self.filters
    }

    /// Set or clear the filters (`f` on the chain, with the law's output of the tick).
    pub fn with_filters<R>(&mut self, f: impl FnOnce(&mut ServoFilters, f64) -> R) -> R {
        f(&mut self.filters, self.law_out)
    }

    /// The servo law's output of the tick, the filters' input, V.
    pub fn law_output(&self) -> f64 {
        self.law_out
    }

    /// The PID+FF law's Coulomb friction feed-forward of the tick, V (0 under another law).
    pub fn friction_term(&self) -> f64 {
        match &self.law {
            Law::Pidff(pid) => pid.friction(),
            _ => 0.0,
        }
    }

    /// The servo loop and the motion bookkeeping of one tick, after [`Axis::sense`].
    pub fn control(&mut self, ts: f64) -> (f64, TickReport) {
        let mut report = TickReport::default();
        let volts = self.control_into(ts, &mut report, None);
        (volts, report)
    }

    /// [`Axis::control`] with its report written into `report` (a default one: nothing to
    /// tell) rather than returned: the firmware's tick keeps its reports in place. `comp`: the
    /// axis's compensation table and settings, if it has one (layout 1.9).
    pub fn control_into(
        &mut self,
        ts: f64,
        report: &mut TickReport,
        comp: Option<(&[CompPoint], &CompParams)>,
    ) -> f64 {
        if self.reference_into(ts, report) {
            self.servo_into(ts, report, comp)
        } else {
            0.0
        }
    }

    /// The first half of [`Axis::control_into`]: this tick's reference from the axis's own
    /// trajectory (and the state changes that come with it). `false`: the axis is unpowered
    /// (its reference follows the actual position, its output is 0 V) and
    /// [`Axis::servo_into`] must not run. The firmware runs it early for an axis that is the
    /// commanded-position master of a geared slave, so that the slave follows this tick's
    /// reference, not the last one's.
    pub fn reference_into(&mut self, ts: f64, report: &mut TickReport) -> bool {
        if self.state == AxisState::Disabled
            || (self.state == AxisState::ErrorStop && !self.safety.powered)
        {
            // The commanded position follows the actual one, so enabling never jumps.
            self.cmd = Reference {
                pos: self.act_pos,
                vel: 0.0,
                acc: 0.0,
            };
            self.cmd_jerk = 0.0;
            self.prev_cmd_acc = 0.0;
            // The correction stays as it was (the motor does not follow a reference now): on
            // power the reference is the motor's position, no jump.
            let c = self.comp.applied().0;
            self.comp_ref = Reference {
                pos: self.act_pos + c,
                vel: 0.0,
                acc: 0.0,
            };
            self.ferr = 0.0;
            self.dac_v = 0.0;
            self.servo_terms = ServoTerms::default();
            self.law_out = 0.0;
            if self.filters.any() {
                // Unpowered, the chain's input is 0: it starts from rest when powered.
                self.filters.settle(0.0);
            }
            self.faults.remove(Faults::DAC_SATURATED);
            if self.modulo_q != 0 {
                self.wrap_frame();
            }
            return false;
        }

        // Trajectory generator.
        if let Motion::Run { traj, t, seg } = &mut self.motion {
            *t += ts;
            let s = traj.sample_from(*t, seg);
            self.cmd = Reference {
                pos: s.pos,
                vel: s.vel,
                acc: s.acc,
            };
            if *t >= traj.duration() {
                let end = traj.end();
                if let Goal::Velocity { .. } = self.goal {
                    // Velocity mode runs on at its velocity (the sample continues it). Homing's
                    // searches are its own business: no InVelocity for them.
                    if !self.in_velocity {
                        self.in_velocity = true;
                        if self.state != AxisState::Homing {
                            report.in_velocity = Some((self.motion_seq, end.vel));
                        }
                    }
                    if self.modulo_q != 0 && self.state != AxisState::Homing {
                        // A modulo axis cruises in integers from here (no time summed).
                        self.start_cruise(end.vel, ts);
                    }
                } else if let (Goal::Position { .. }, true) = (self.goal, end.vel != 0.0) {
                    // The ramp down to a lowered velocity limit ended: on to the target. (If
                    // that cannot be planned, the starvation stop below takes over next tick.)
                    let goal = self.goal;
                    match self.plan(&goal, rate_hz(ts)) {
                        Ok(traj) => {
                            self.motion = Motion::Run {
                                traj,
                                t: 0.0,
                                seg: 0,
                            }
                        }
                        Err(_) => self.goal = Goal::None,
                    }
                } else if end.vel != 0.0 || end.acc != 0.0 {
                    // [safety] the profile ends moving and nothing follows it (a queue ran
                    // dry): a planned stop from where it ended, never a jump to rest.
                    let stop = crate::firmware::axis_safety::starvation_stop(&self.safety, &end);
                    self.target = stop.map_or(end.pos, |p| p.end_pos());
                    self.motion = match stop {
                        Some(p) => Motion::Run {
                            traj: Trajectory::from_profile(&p),
                            t: 0.0,
                            seg: 0,
                        },
                        None => Motion::Hold,
                    };
                    self.goal = Goal::None;
                    self.safety.stop_reason = StopReason::Starvation;
                    self.stop_elapsed = Some(0.0);
                } else {
                    self.cmd = Reference {
                        pos: end.pos,
                        vel: 0.0,
                        acc: 0.0,
                    };
                    self.motion = Motion::Hold;
                }
            }
        } else if let Motion::Cruise { .. } = self.motion {
            self.cruise_step();
        }
        if self.modulo_q != 0 {
            self.wrap_frame();
        }
        if let Some(t) = &mut self.stop_elapsed {
            *t += ts;
        }
        // Jerk of the reference, whoever set it (own profile or a group).
        self.cmd_jerk = (self.cmd.acc - self.prev_cmd_acc) / ts;
        self.prev_cmd_acc = self.cmd.acc;
        if self.state == AxisState::Stopping && self.motion == Motion::Hold && self.stop_released {
            self.set_state(AxisState::Standstill, &mut report.state_from);
        }
        true
    }

    /// The second half of [`Axis::control_into`], after [`Axis::reference_into`] returned
    /// `true`: the servo loop on this tick's reference, the move's statistics, in-position.
    pub fn servo_into(
        &mut self,
        ts: f64,
        report: &mut TickReport,
        comp: Option<(&[CompPoint], &CompParams)>,
    ) -> f64 {
        let vel = self.servo.velocity();

        // Leadscrew compensation (layout 1.9): the servo follows the commanded position plus
        // the correction; the table is in use once the axis is homed and not homing.
        let (r, motor) = if comp.is_none() && self.comp.idle() {
            (self.cmd, self.act_pos)
        } else {
            self.compensate(comp, ts)
        };
        self.comp_ref = r;

        // Servo loop. Layout 1.12: a sweep's sine on the reference's position only (FFPIV and
        // PID+FF see it as the measured position less the sine, which is the same in their
        // position error and leaves their velocity estimate and the standstill rounding of
        // the reference alone; PD+ differentiates the measured position, so it takes it on
        // the reference).
        let inj = self.inject.reference;
        self.ferr = r.pos + inj - motor;
        let limit = self.config.dac_limit_v;
        let (u, terms) = match &mut self.law {
            Law::Ffpiv => {
                // A stop wants the axis at rest soonest, not on a count's edge: the edge's
                // toggling count reads as motion to the at-rest test for a few ticks.
                let stopping = matches!(self.state, AxisState::ErrorStop | AxisState::Stopping);
                self.servo.set_mid_count(self.mid_count && !stopping);
                let u = self
                    .servo
                    .update(&r, motor - inj, &self.config.ffpiv, ts, limit);
                (u, self.servo.terms())
            }
            // Yeh eq 2.12: u = kp e + kd ė + kv v_ref + ka a_ref.
            Law::PdPlus(pd) => (pd.update(r.pos + inj, r.vel, r.acc, motor), pd.terms()),
            Law::Pidff(pid) => (pid.update(&r, motor - inj, limit), pid.terms()),
        };
        self.servo_terms = terms;
        self.law_out = u;
        // Layout 1.11: the biquad filters, when any is set (one branch when none is).
        let u = if self.filters.any() {
            self.filters.run(u)
        } else {
            u
        } + self.inject.output;
        self.u_request = u;
        let u = u.clamp(-limit, limit);
        let (volts, saturated) = super::dac::Dac::output(u);
        self.dac_v = volts;
        if saturated || u.abs() >= limit {
            self.faults.insert(Faults::DAC_SATURATED);
        } else {
            self.faults.remove(Faults::DAC_SATURATED);
        }

        // Statistics (of its own moves, and of the group motions it takes part in), then
        // in-position of its own moves.
        let grouped = self.state == AxisState::SynchronizedMotion;
        if self.awaiting_done || grouped {
            let st = &mut self.stats;
            st.elapsed += ts;
            st.peak_vel = st.peak_vel.max(self.cmd.vel.abs());
            let dir = (self.target - self.cmd.pos).signum();
            let along = self.cmd.acc
                * if self.cmd.vel != 0.0 {
                    self.cmd.vel.signum()
                } else {
                    dir
                };
            st.peak_acc = st.peak_acc.max(along);
            st.peak_dec = st.peak_dec.max(-along);
            st.peak_jerk = st.peak_jerk.max(self.cmd_jerk.abs());
            st.max_ferr = st.max_ferr.max(self.ferr.abs());
        }
        // Homing says itself when it is done (homing.rs); a geared slave is never done (gear.rs).
        if self.awaiting_done
            && !matches!(
                self.state,
                AxisState::Homing | AxisState::SynchronizedMotion
            )
        {
            let st = &mut self.stats;
            let in_pos = self.motion == Motion::Hold
                && self.comp.settled()
                && (self.target - self.act_pos).abs() <= self.config.in_pos_window
                && vel.abs() <= self.config.in_vel_window;
            if in_pos {
                self.settled_for += ts;
                if self.settled_for + 1e-12 >= self.config.settle_time {
                    self.awaiting_done = false;
                    st.move_time = st.elapsed;
                    if self.safety.stop_reason == StopReason::None {
                        self.safety.stop_reason = StopReason::Done;
                    }
                    report.done = Some((self.motion_seq, self.wrap(self.act_pos)));
                    self.goal = Goal::None;
                    if self.state == AxisState::DiscreteMotion {
                        // PLCopen Buffered: the next move starts once this one is done.
                        match self.start_next(rate_hz(ts), &mut report.state_from) {
                            Some(Ok(active)) => report.active = Some(active),
                            Some(Err(seq)) => {
                                let _ = report.dropped.push(seq);
                                report.dropped.extend(self.drain_queue());
                                self.set_state(AxisState::Standstill, &mut report.state_from)
                            }
                            None => self.set_state(AxisState::Standstill, &mut report.state_from),
                        }
                    }
                }
            } else {
                self.settled_for = 0.0;
            }
        }
        // A move buffered behind velocity mode starts once the velocity is reached.
        if report.in_velocity.is_some() {
            match self.start_next(rate_hz(ts), &mut report.state_from) {
                Some(Ok(active)) => report.active = Some(active),
                Some(Err(seq)) => {
                    let _ = report.dropped.push(seq);
                    report.dropped.extend(self.drain_queue());
                }
                None => {}
            }
        }
        volts
    }

    /// Set the commanded reference from outside (an axes group drives this axis).
    pub fn drive(&mut self, r: Reference) {
        self.cmd = r;
        self.target = r.pos;
    }

    /// A group move starts driving this axis: SynchronizedMotion. The axis counts it as a
    /// motion of its own in its statistics (move count, peaks, following error, stop reason).
    pub fn join_group_motion(&mut self) -> Option<AxisState> {
        let mut changed = None;
        if self.state == AxisState::Standstill {
            self.set_state(AxisState::SynchronizedMotion, &mut changed);
            self.safety.stop_reason = StopReason::None;
            self.move_count = self.move_count.wrapping_add(1);
            self.stats = MoveStats::default();
        }
        changed
    }

    /// The group is at rest again: Standstill; the motion's statistics are complete (its
    /// stop reason Done unless a halt or stop of the group set one).
    pub fn leave_group_motion(&mut self) -> Option<AxisState> {
        let mut changed = None;
        if self.state == AxisState::SynchronizedMotion {
            self.set_state(AxisState::Standstill, &mut changed);
            if self.safety.stop_reason == StopReason::None {
                self.safety.stop_reason = StopReason::Done;
            }
            self.stats.move_time = self.stats.elapsed;
        }
        changed
    }

    /// A halt or stop of its group ends the group motion this axis takes part in.
    pub fn group_stopping(&mut self, reason: StopReason) {
        if self.state == AxisState::SynchronizedMotion {
            self.safety.stop_reason = reason;
        }
    }

    /// The group was disabled or faulted: hold where the reference is.
    pub fn release_from_group(&mut self) -> Option<AxisState> {
        self.cmd.vel = 0.0;
        self.cmd.acc = 0.0;
        self.leave_group_motion()
    }

    /// Layout 1.10: its gantry no longer drives this slave (dissolved, or its homing begins):
    /// from SynchronizedMotion to Standstill, holding where the reference is. Returns the old
    /// state if it changed.
    pub fn release_from_gantry(&mut self) -> Option<AxisState> {
        let mut changed = None;
        if self.state == AxisState::SynchronizedMotion {
            self.cmd.vel = 0.0;
            self.cmd.acc = 0.0;
            self.target = self.cmd.pos;
            self.awaiting_done = false;
            self.set_state(AxisState::Standstill, &mut changed);
        }
        changed
    }

    /// Issue 35 part 1: a gantry's member (from the formation to the dissolution) reads its
    /// encoder's count at its middle while its reference moves, under FFPIV
    /// (`Ffpiv::set_mid_count`): the sides' shafts are held on the same count edge. Not in a
    /// stop (`servo_into`).
    pub fn set_mid_count(&mut self, on: bool) {
        self.mid_count = on;
    }

    /// Within the in-position windows of `target` (position and velocity)?
    pub fn in_position_at(&self, target: f64) -> bool {
        (target - self.act_pos).abs() <= self.config.in_pos_window
            && self.servo.velocity().abs() <= self.config.in_vel_window
    }

    /// The servo law's terms of the last tick.
    pub fn servo_terms(&self) -> ServoTerms {
        self.servo_terms
    }

    /// The status block to publish.
    #[inline]
    pub fn status(&self, tick: u64) -> AxisStatus {
        let st = &self.stats;
        AxisStatus {
            cmd_pos: self.cmd.pos,
            cmd_vel: self.cmd.vel,
            cmd_acc: self.cmd.acc,
            act_pos: self.act_pos,
            act_vel: self.servo.velocity(),
            ferr: self.ferr,
            dac_v: self.dac_v,
            target: self.target,
            state: self.state as u32,
            faults: (self.faults | self.safety.faults).bits(),
            last_seq: self.last_seq,
            move_count: self.move_count,
            tick,
            encoder: self.encoder,
            peak_vel: st.peak_vel,
            peak_acc: st.peak_acc,
            peak_dec: st.peak_dec,
            peak_jerk: st.peak_jerk,
            max_ferr: st.max_ferr,
            planned_time: st.planned_time,
            move_time: st.move_time,
            u_request: self.u_request,
            stop_reason: self.safety.stop_reason as u32,
            io: self.safety.io.bits(),
            motion_flags: self.motion_flags().bits(),
            queued: self.queue.len() as u32,
            override_factor: self.override_factor,
            comp_pos: self.comp_ref.pos,
            ..Default::default()
        }
    }

    /// [`Axis::status`] with a modulo axis's positions wrapped into [0, m) (layout 1.10).
    #[inline(never)]
    pub fn wrap_status(&self, s: &mut AxisStatus) {
        s.cmd_pos = self.wrap(s.cmd_pos);
        s.act_pos = self.wrap(s.act_pos);
        s.target = self.wrap(s.target);
        s.comp_pos = self.wrap(s.comp_pos);
    }

    /// Layout 1.9: the compensation's step of this tick. Returns the servo's reference and the
    /// motor's position (the load's position `act_pos` is set for the new correction).
    #[inline(never)]
    fn compensate(
        &mut self,
        comp: Option<(&[CompPoint], &CompParams)>,
        ts: f64,
    ) -> (Reference, f64) {
        let motor = self.act_pos + self.comp.applied().0;
        let in_use = comp.filter(|_| self.homed && self.state != AxisState::Homing);
        let (c, cv, ca) = self
            .comp
            .step(in_use, self.cmd.pos, self.cmd.vel, self.cmd.acc, ts);
        self.act_pos = motor - c;
        let r = Reference {
            pos: self.cmd.pos + c,
            vel: self.cmd.vel + cv,
            acc: self.cmd.acc + ca,
        };
        (r, motor)
    }

    /// Layout 1.9: the compensation table or its settings changed (the ramp's limits: the new
    /// settings').
    pub fn compensation_changed(&mut self, limits: Option<OtgLimits>) {
        self.comp.changed(limits);
    }

    /// The correction in force, counts (0 without compensation).
    pub fn correction(&self) -> f64 {
        self.comp.applied().0
    }

    /// The position in the load's frame of an encoder count: the motor's position there
    /// less the correction in force (compare and probe positions, layout 1.9).
    pub(crate) fn load_position_of_count(&self, count: i64) -> f64 {
        if self.modulo_q != 0 {
            return self.frame_position(count) + self.pos_offset - self.comp.applied().0;
        }
        count as f64 + self.pos_offset - self.comp.applied().0
    }

    /// The motion bits of the status.
    #[inline]
    pub fn motion_flags(&self) -> MotionFlags {
        let mut f = MotionFlags::empty();
        let homing = self.state == AxisState::Homing;
        // Homing and the handwheel (SynchronizedMotion) are not scaled by the override.
        let moving = self.awaiting_done
            && self.goal != Goal::None
            && !homing
            && self.state != AxisState::SynchronizedMotion;
        f.set(MotionFlags::IN_VELOCITY, self.in_velocity && !homing);
        f.set(MotionFlags::HOMED, self.homed);
        f.set(MotionFlags::PAUSED, moving && self.override_factor == 0.0);
        f.set(MotionFlags::BUFFERED_ACTIVE, moving && self.buffered_active);
        f.set(MotionFlags::IN_SYNC, self.in_sync);
        f
    }

    /// The velocity override factor in force.
    pub fn override_factor(&self) -> f64 {
        self.override_factor
    }
}

// ---- Safety hooks: what safety.rs needs from an axis (the rules live there) ----
impl Axis {
    /// Enter ErrorStop. `ramp`: the stop profile of a category 1 or 2 stop, run with the drive
    /// powered; `None`: category 0, the drive loses power now. Returns the old state if it
    /// changed.
    pub(crate) fn enter_error_stop(&mut self, ramp: Option<Profile>) -> Option<AxisState> {
        let mut changed = None;
        self.awaiting_done = false;
        self.goal = Goal::None;
        self.in_velocity = false;
        match ramp {
            Some(profile) => {
                self.target = profile.end_pos();
                self.run_profile_now(&profile);
                self.safety.powered = true;
                self.stop_elapsed = Some(0.0);
            }
            None => {
                self.remove_power();
                self.stop_elapsed = None;
            }
        }
        self.set_state(AxisState::ErrorStop, &mut changed);
        changed
    }

    /// Category 0 (or the end of a category 1 stop): the drive loses power now.
    pub(crate) fn remove_power(&mut self) {
        self.motion = Motion::Hold;
        self.safety.powered = false;
        self.dac_v = 0.0;
    }

    /// Seconds since the stop in progress began (`None`: no stop in progress).
    pub(crate) fn stop_elapsed(&self) -> Option<f64> {
        self.stop_elapsed
    }

    /// The stop in progress ended (or was cut).
    pub(crate) fn end_stop_clock(&mut self) {
        self.stop_elapsed = None;
    }

    /// Is a profile (move or stop ramp) still running?
    pub(crate) fn profile_running(&self) -> bool {
        matches!(self.motion, Motion::Run { .. } | Motion::Cruise { .. })
    }

    /// Does a goal of its own drive the axis (a position move, velocity mode or jog, or a
    /// homing method's search), as opposed to a stop ramp, holding or settling?
    pub(crate) fn has_goal(&self) -> bool {
        !matches!(self.goal, Goal::None)
    }

    /// Does the drive get the servo output this tick?
    pub(crate) fn is_powered(&self) -> bool {
        match self.state {
            AxisState::Disabled => false,
            AxisState::ErrorStop => self.safety.powered,
            _ => true,
        }
    }

    /// The filtered measured velocity, counts/s.
    pub(crate) fn measured_velocity(&self) -> f64 {
        self.servo.velocity()
    }

    /// The following error of the last tick, counts.
    pub(crate) fn following_error(&self) -> f64 {
        self.ferr
    }

    /// The encoder's position is no longer known (an encoder fault): not homed.
    pub(crate) fn lose_home(&mut self) {
        self.homed = false;
    }

    /// Run `profile` from now, as a queue would (tests of the starvation rule).
    #[cfg(test)]
    pub(crate) fn run_profile(&mut self, seq: u32, profile: Profile) {
        self.target = profile.end_pos();
        self.begin_motion(seq, profile.duration());
        self.run_profile_now(&profile);
        self.state = AxisState::DiscreteMotion;
    }
}

// ---- Homing hooks: what homing.rs needs from an axis (the methods live there) ----
impl Axis {
    /// The position was set by homing or MC_SetPosition (`MC_MOTION_HOMED`): soft limits hold.
    pub fn homed(&self) -> bool {
        self.homed
    }

    /// The limit switches the homing in progress watches itself (empty outside Homing).
    pub fn homing_limits(&self) -> Io {
        self.homing_limits
    }

    /// The position (in the axis's frame) of the raw encoder count `count`.
    pub(crate) fn position_of_count(&self, count: i64) -> f64 {
        if self.modulo_q != 0 {
            return self.frame_position(count) + self.pos_offset;
        }
        count as f64 + self.pos_offset
    }

    /// Is a motion of its own (a move, halt or homing) still waiting for its end?
    pub(crate) fn busy_with_motion(&self) -> bool {
        self.awaiting_done || self.profile_running()
    }

    /// MC_Home accepted: PLCopen Homing from Standstill, as the motion of command `seq`; not
    /// homed until it ends. `limits`: the limit switches the method watches itself.
    pub(crate) fn begin_homing(
        &mut self,
        seq: u32,
        limits: Io,
    ) -> Result<Option<AxisState>, NackCode> {
        match self.state {
            AxisState::Standstill => {}
            AxisState::Disabled => return Err(NackCode::AxisDisabled),
            AxisState::Homing => return Err(NackCode::AxisHoming),
            _ => return Err(NackCode::InvalidState),
        }
        let mut changed = None;
        self.begin_motion(seq, 0.0);
        self.goal = Goal::None;
        self.in_velocity = false;
        self.buffered_active = false;
        self.homed = false;
        self.stop_elapsed = None;
        self.target = self.cmd.pos;
        self.set_state(AxisState::Homing, &mut changed);
        self.homing_limits = limits;
        Ok(changed)
    }

    /// Velocity mode at the signed `vel` within `lim` (acceleration, deceleration, jerk),
    /// planned from the commanded state; the override does not scale it. Stays in Homing.
    pub(crate) fn homing_velocity(
        &mut self,
        vel: f64,
        lim: &Limits,
        rate_hz: u32,
    ) -> Result<(), NackCode> {
        self.homing_goal(Goal::Velocity { vel, lim: *lim }, rate_hz)
    }

    /// A position move to `target` within `lim` from the commanded state (the override does
    /// not scale it). Stays in Homing.
    pub(crate) fn homing_move(
        &mut self,
        target: f64,
        lim: &Limits,
        rate_hz: u32,
    ) -> Result<(), NackCode> {
        self.homing_goal(Goal::Position { target, lim: *lim }, rate_hz)
    }

    /// Plan `goal` without the override and run it; the axis stays in Homing.
    fn homing_goal(&mut self, goal: Goal, rate_hz: u32) -> Result<(), NackCode> {
        let traj = self.plan_scaled(&goal, rate_hz, 1.0)?;
        self.take_goal(goal, traj);
        Ok(())
    }

    /// A jerk-limited stop from the commanded state within `dmax` and `jerk`, or along the
    /// axis's stop ramp when that one would take longer than `max_time` s (see
    /// [`bounded_stop_limits`]), run from now; its planned time. The state is the caller's:
    /// MC_Halt and MC_Stop change it, homing's stops stay in Homing.
    pub(crate) fn run_bounded_stop(
        &mut self,
        dmax: f64,
        jerk: f64,
        max_time: f64,
    ) -> Result<f64, NackCode> {
        let c = &self.safety.config;
        let (dmax, jerk) = bounded_stop_limits(
            (self.cmd.vel, self.cmd.acc),
            (dmax, jerk),
            (c.stop_decel, c.stop_jerk),
            max_time,
        );
        let profile =
            plan_stop(self.cmd.pos, self.cmd.vel, self.cmd.acc, dmax, jerk).map_err(plan_nack)?;
        self.target = profile.end_pos();
        self.goal = Goal::None;
        self.in_velocity = false;
        self.run_profile_now(&profile);
        self.stop_elapsed = Some(0.0);
        Ok(profile.duration())
    }

    /// Stop commanding motion where the axis is (a stalled axis against a hard stop): the
    /// reference jumps back to the actual position, at rest, and the integrator forgets what it
    /// wound up pushing.
    pub(crate) fn hold_at_actual(&mut self) {
        self.cmd = Reference {
            pos: self.act_pos,
            vel: 0.0,
            acc: 0.0,
        };
        self.prev_cmd_acc = 0.0;
        self.target = self.act_pos;
        self.motion = Motion::Hold;
        self.goal = Goal::None;
        self.in_velocity = false;
        self.stop_elapsed = None;
        self.servo.reset_integral();
        match &mut self.law {
            Law::PdPlus(pd) => pd.reset(self.act_pos),
            Law::Pidff(pid) => pid.reset(),
            Law::Ffpiv => {}
        }
    }

    /// Move the position frame by `delta` counts without moving the axis: the actual and
    /// commanded positions (and the target) all move by it, the following error does not, and
    /// the raw encoder count stays what the shaft says. At rest only (no profile running).
    pub(crate) fn shift_position(&mut self, delta: f64) {
        debug_assert!(!self.profile_running());
        self.pos_offset += delta;
        self.act_pos += delta;
        // The table's frame moved under the axis: a jump of its correction is ramped.
        self.comp.changed(None);
        self.cmd.pos += delta;
        self.target += delta;
        if let Law::PdPlus(pd) = &mut self.law {
            pd.shift(delta);
        }
    }

    /// MC_SetPosition's mark: the position is known (or, false, no longer).
    pub(crate) fn set_homed(&mut self, homed: bool) {
        self.homed = homed;
    }

    /// Homing ended, at rest: Standstill, homed or not (`Failed` the stop reason). Returns the
    /// old state if it changed, and the actual position.
    pub(crate) fn end_homing(&mut self, homed: bool) -> (Option<AxisState>, f64) {
        let mut changed = None;
        self.awaiting_done = false;
        self.goal = Goal::None;
        self.in_velocity = false;
        self.homed = homed;
        self.stats.move_time = self.stats.elapsed;
        self.safety.stop_reason = if homed {
            StopReason::Done
        } else {
            StopReason::HomingFailed
        };
        self.set_state(AxisState::Standstill, &mut changed);
        (changed, self.act_pos)
    }
}

// ---- Synchronised-motion hooks: what gear.rs needs from an axis (the coupling lives there) ----
impl Axis {
    /// The raw encoder count of the last tick.
    pub fn encoder(&self) -> i64 {
        self.encoder
    }

    /// The filtered measured velocity, counts/s.
    pub fn velocity_estimate(&self) -> f64 {
        self.servo.velocity()
    }

    /// MC_GearIn accepted (command `seq`): SynchronizedMotion from Standstill or any motion of
    /// its own (Aborting: the caller drops the queue); the reference is set from outside
    /// ([`Axis::drive`]) from the next tick on. Returns the old state.
    pub(crate) fn begin_sync(&mut self, seq: u32) -> Result<Option<AxisState>, NackCode> {
        let mut changed = None;
        self.begin_motion(seq, 0.0);
        self.motion = Motion::Hold;
        self.goal = Goal::None;
        self.in_velocity = false;
        self.buffered_active = false;
        self.in_sync = false;
        self.set_state(AxisState::SynchronizedMotion, &mut changed);
        Ok(changed)
    }

    /// The coupling is in gear (or was left).
    pub(crate) fn set_in_sync(&mut self, on: bool) {
        self.in_sync = on && self.state == AxisState::SynchronizedMotion;
    }

    /// MC_GearOut (command `seq`): velocity mode at the commanded velocity, the acceleration
    /// ramped to 0 within `amax` and `jerk` (the override does not scale it). Returns the old
    /// state.
    pub(crate) fn leave_sync(
        &mut self,
        seq: u32,
        amax: f64,
        jerk: f64,
        rate_hz: u32,
    ) -> Result<Option<AxisState>, NackCode> {
        let vel = self.cmd.vel;
        let goal = Goal::Velocity {
            vel,
            lim: Limits {
                vmax: vel.abs(),
                amax,
                dmax: amax,
                ..Limits::symmetric(0.0, 0.0, jerk)
            },
        };
        let traj = self.plan_scaled(&goal, rate_hz, 1.0)?;
        self.begin_motion(seq, traj.duration());
        self.take_goal(goal, traj);
        let mut changed = None;
        self.set_state(AxisState::ContinuousMotion, &mut changed);
        Ok(changed)
    }

    /// The master was lost (or, `starved`, a PT/PVT stream ran dry): stop on the axis's stop
    /// ramp (bounded by `max_time`), Stopping until at rest, then Standstill. Returns the old
    /// state.
    pub(crate) fn sync_stop(&mut self, max_time: f64, starved: bool) -> Option<AxisState> {
        let c = self.safety.config;
        let mut changed = None;
        if self
            .run_bounded_stop(c.stop_decel, c.stop_jerk, max_time)
            .is_err()
        {
            // No ramp can be planned from here (it always can from a verified state): hold.
            self.hold_at_actual();
        }
        self.awaiting_done = false;
        self.stop_released = true;
        self.safety.stop_reason = if starved {
            StopReason::Starvation
        } else {
            StopReason::Halt
        };
        self.set_state(AxisState::Stopping, &mut changed);
        changed
    }

    /// A PT/PVT stream reached its last point at `target` (at rest): DiscreteMotion, holding
    /// there, motion done (with the start's seq) once in position, then Standstill. Returns
    /// the old state.
    pub(crate) fn end_stream(&mut self, target: f64) -> Option<AxisState> {
        let mut changed = None;
        self.target = target;
        self.motion = Motion::Hold;
        self.goal = Goal::None;
        self.settled_for = 0.0;
        self.set_state(AxisState::DiscreteMotion, &mut changed);
        changed
    }
}

// ---- Handwheel hooks: what handwheel.rs needs from an axis (the wheel lives there) ----
impl Axis {
    /// MC_OP_HANDWHEEL accepted (command `seq`): SynchronizedMotion from Standstill or any
    /// motion of its own (Aborting: the caller drops the queue), running to `target` within
    /// `lim` from the commanded state (the override does not scale it). Returns the old state.
    pub(crate) fn begin_handwheel(
        &mut self,
        seq: u32,
        target: f64,
        lim: &Limits,
        rate_hz: u32,
    ) -> Result<Option<AxisState>, NackCode> {
        let goal = Goal::Position { target, lim: *lim };
        let c = self.cmd;
        let traj = if c.vel == 0.0 && c.acc == 0.0 && target == c.pos {
            None
        } else {
            Some(self.plan_scaled(&goal, rate_hz, 1.0)?)
        };
        self.begin_motion(seq, traj.map_or(0.0, |t| t.duration()));
        self.buffered_active = false;
        match traj {
            Some(traj) => self.take_goal(goal, traj),
            None => {
                self.target = target;
                self.goal = goal;
                self.in_velocity = false;
                self.motion = Motion::Hold;
                self.stop_elapsed = None;
            }
        }
        let mut changed = None;
        self.set_state(AxisState::SynchronizedMotion, &mut changed);
        Ok(changed)
    }

    /// The handwheel's target moved: run to `target` within `lim` from the commanded state
    /// (time-optimal, jerk-limited). Nothing changes if it cannot be planned.
    pub(crate) fn handwheel_target(
        &mut self,
        target: f64,
        lim: &Limits,
        rate_hz: u32,
    ) -> Result<(), NackCode> {
        let goal = Goal::Position { target, lim: *lim };
        let traj = self.plan_scaled(&goal, rate_hz, 1.0)?;
        self.take_goal(goal, traj);
        Ok(())
    }

    /// The handwheel let go of the axis (deselected, or its input handed over): the axis goes
    /// on to the target as a DiscreteMotion, motion done with the handwheel's seq once in
    /// position, then Standstill. Returns the old state.
    pub(crate) fn end_handwheel(&mut self) -> Option<AxisState> {
        let mut changed = None;
        self.settled_for = 0.0;
        self.set_state(AxisState::DiscreteMotion, &mut changed);
        changed
    }
}

#[cfg(test)]
mod modulo_tests;
#[cfg(test)]
mod tests;
