//! Electronic gearing (layout 1.7): PLCopen MC_GearIn, MC_GearInPos and MC_GearOut, one
//! [`Gear`] per slave axis, stepped by `Firmware::tick` after the groups and before the servo
//! loops (as homing is).
//!
//! **The ratio is exact.** The slave's position in gear is
//!
//! ```text
//! x = x_a + q + r / den',   (q, r) = divmod(num · (m − m_a), den'),   den' = den · units per count
//! ```
//!
//! with `m` the master's count this tick, `(m_a, x_a)` the anchor (the master and the slave
//! where the coupling was taken, or the sync point of MC_GearInPos), `q` and `r` integers
//! (i128). Nothing is summed tick by tick, so nothing drifts: after 10⁹ master counts the slave
//! is exactly where the ratio says (its integer part exact, its fraction rounded once). An
//! encoder master (the master axis's encoder, or an auxiliary encoder) counts in counts; a
//! commanded master in 1/65536 count ([`COMMANDED_SUBCOUNTS`]), its `f64` position rounded
//! there.
//!
//! **Engaging.** The slave's reference is `x = g(m) + d`, `g` the geared position above and `d`
//! the difference still to close, which goes to 0 within the slave's limits:
//!
//! - MC_GearIn anchors `g` where the slave is (`d = 0`), and `d` takes the slave's velocity and
//!   acceleration from its own to the master's times the ratio along a time-optimal
//!   jerk-limited trajectory (`otg::Trajectory::to_position` to `d = 0` at rest), whose
//!   velocity limits are shifted by the master's velocity (`vmax − r·v_m`, `−vmax − r·v_m`), so
//!   that at a constant master velocity the slave's velocity, acceleration and jerk stay within
//!   its own `vmax`, `amax`, `jerk`. `InGear` when `d`'s trajectory ends.
//! - MC_GearInPos anchors `g` at the sync point (`g(M) = S`) and closes `d` along a quintic in
//!   the master's position, `u = (m − m_0)/(M − m_0)`, with the slave's velocity and acceleration
//!   at the start and 0, 0, 0 at the sync point: the slave reaches `S` exactly when the master
//!   reaches `M`, whatever the master does on the way. The quintic is checked against the
//!   slave's limits at the master's present velocity before it is taken (1001 samples of its
//!   velocity, acceleration and jerk), else `Infeasible`. `InSync` at `u = 1`.
//!
//! The master's velocity (and acceleration) are the master axis's commanded ones, or, for an
//! encoder, the filtered velocity of the axis / the last tick's difference of an auxiliary
//! encoder.
//!
//! **Latency.** A commanded-position master is followed in the same tick: a master axis that
//! runs its own trajectory takes this tick's reference before the gear step
//! (`advance_commanded_masters`), a group's axis took it in the group's step before, so the
//! slave's reference of tick k is the ratio applied to the master's reference of tick k,
//! exactly (a master driven by homing or a PT/PVT stream, or one that is itself a slave later in
//! the axis order, is followed one tick late: those set its reference after the gear step). An
//! actual-position master (its encoder, or an auxiliary encoder) is the count latched at the
//! tick's start: the slave's reference of tick k is the ratio applied to the master's position
//! sensed at tick k, which the slave's servo reaches one tick later, so at a master velocity v
//! the slave trails the ratio line by ratio · v · Ts (one tick of the master's travel, on top of
//! the slave's own following error).
//!
//! **Leaving.** MC_GearOut puts the slave into velocity mode at its velocity (PLCopen: the slave
//! keeps moving; ContinuousMotion, `InVelocity` with the GearOut's seq), its acceleration ramped
//! to 0 within the gear's `amax` and `jerk`. A halt, stop, power off or safety stop ends the
//! state, and with it the coupling. A master axis that becomes disabled or faults (ErrorStop):
//! the slave stops on its stop ramp (Stopping, then Standstill), reported `MasterLost`.
//!
//! No allocation, no panic, no clock; time is the tick count.
#![forbid(unsafe_code)]

use crate::firmware::axis::{Axis, TickReport};
use crate::firmware::nack::{check_ranges, plan_nack};
use crate::firmware::Firmware;
use crate::math;
use crate::motion::cam::CamTable;
use crate::motion::otg::{OtgLimits, Trajectory};
use crate::servo::ffpiv::Reference;
use firmware_proto::cmd;
use firmware_proto::{
    layout, raw, AxisState, EventKind, GearRatio, MasterSource, Mem, NackCode, Opcode, SyncEvent,
    AUX_ENCODERS, COMMANDED_SUBCOUNTS, MAX_AXES, MAX_MOVE_TIME,
};

/// Samples of the quintic checked against the slave's limits (MC_GearInPos).
const QUINTIC_SAMPLES: usize = 1000;
/// The slack on that check (rounding).
const LIMIT_SLACK: f64 = 1.0 + 1e-9;

/// The auxiliary encoder inputs as the card samples them, with their velocity and
/// acceleration over the last tick.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct AuxInputs {
    /// Counts (this tick's, once [`AuxInputs::sense`] ran).
    pub count: [i64; AUX_ENCODERS],
    /// Counts per second over the last tick.
    pub vel: [f64; AUX_ENCODERS],
    /// Counts per second² over the last tick.
    pub acc: [f64; AUX_ENCODERS],
    /// The servo period of the last tick, s (an actual-lead master leads by it).
    pub ts: f64,
    latest: [i64; AUX_ENCODERS],
    primed: bool,
}

impl AuxInputs {
    /// The counts the encoder interface latched for the next tick.
    pub fn set(&mut self, counts: [i64; AUX_ENCODERS]) {
        self.latest = counts;
    }

    /// Take the latched counts as this tick's (sample time `ts`).
    pub fn sense(&mut self, ts: f64) {
        self.ts = ts;
        for k in 0..AUX_ENCODERS {
            let v = if self.primed {
                self.latest[k].wrapping_sub(self.count[k]) as f64 / ts
            } else {
                0.0
            };
            self.acc[k] = if self.primed {
                (v - self.vel[k]) / ts
            } else {
                0.0
            };
            self.vel[k] = v;
            self.count[k] = self.latest[k];
        }
        self.primed = true;
    }
}

/// What a slave follows.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Master {
    /// Commanded or actual position of an axis, or an auxiliary encoder.
    pub source: MasterSource,
    /// The axis or the auxiliary encoder.
    pub index: usize,
}

impl Master {
    /// Master units per count.
    fn per_count(&self) -> i128 {
        match self.source {
            MasterSource::Commanded | MasterSource::ActualLead => COMMANDED_SUBCOUNTS,
            _ => 1,
        }
    }

    /// This tick's sample of the master, from the axes and the auxiliary inputs.
    pub fn sample(&self, axes: &[Axis], aux: &AuxInputs) -> MasterSample {
        match self.source {
            MasterSource::Aux => MasterSample {
                count: aux.count.get(self.index).copied().unwrap_or(0) as i128,
                vel: aux.vel.get(self.index).copied().unwrap_or(0.0),
                acc: aux.acc.get(self.index).copied().unwrap_or(0.0),
                lost: false,
            },
            _ => {
                let Some(a) = axes.get(self.index) else {
                    return MasterSample {
                        lost: true,
                        ..Default::default()
                    };
                };
                let lost = matches!(a.state, AxisState::Disabled | AxisState::ErrorStop);
                if self.source == MasterSource::Commanded {
                    let r = a.reference();
                    // A modulo master's turns added back (layout 1.10): the count runs on
                    // across its wrap, in integers.
                    MasterSample {
                        count: math::round(r.pos * COMMANDED_SUBCOUNTS as f64) as i128
                            + a.turn_subcounts(),
                        vel: r.vel,
                        acc: r.acc,
                        lost,
                    }
                } else if self.source == MasterSource::ActualLead {
                    // The encoder a servo period ahead, where the slave's servo meets it.
                    let vel = a.velocity_estimate();
                    let led = a.encoder() as f64 + vel * aux.ts;
                    MasterSample {
                        count: math::round(led * COMMANDED_SUBCOUNTS as f64) as i128,
                        vel,
                        acc: 0.0,
                        lost,
                    }
                } else {
                    MasterSample {
                        count: a.encoder() as i128,
                        vel: a.velocity_estimate(),
                        acc: 0.0,
                        lost,
                    }
                }
            }
        }
    }
}

/// A master this tick: its count (master units), velocity and acceleration (counts/s, /s²),
/// and whether it is lost (an axis disabled or in ErrorStop).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct MasterSample {
    /// Master units (see [`Master`]).
    pub count: i128,
    /// Counts per second.
    pub vel: f64,
    /// Counts per second².
    pub acc: f64,
    /// Disabled or in ErrorStop.
    pub lost: bool,
}

/// The slave's own limits while it engages: velocity, acceleration (both ways), jerk.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SyncLimits {
    /// Counts/s.
    pub vmax: f64,
    /// Counts/s².
    pub amax: f64,
    /// Counts/s³.
    pub jerk: f64,
}

/// How the difference to the geared position closes.
#[derive(Debug, Clone, Copy, PartialEq)]
#[allow(clippy::large_enum_variant)] // inline on purpose: the firmware never allocates
enum Phase {
    /// MC_GearIn: `d(t)` along a trajectory to 0, `t` into it.
    CatchUp { traj: Trajectory, t: f64 },
    /// MC_GearInPos: `d(u)` a quintic in `u = (m − m_0)/span` (coefficients `c`).
    ToSyncPoint { m0: i128, span: i128, c: [f64; 6] },
    /// In gear: `d = 0`.
    Locked,
}

/// A cam coupling (cam.rs): slave = `s_off + s_scale · table((m − m_off) / m_scale)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CamLaw {
    /// The table (0..CAM_TABLES).
    pub table: usize,
    /// Master offset, counts.
    pub m_off: f64,
    /// Slave offset, counts.
    pub s_off: f64,
    /// Master scale (nonzero).
    pub m_scale: f64,
    /// Slave scale (nonzero).
    pub s_scale: f64,
}

/// How the slave follows: a ratio, or a cam table.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Law {
    /// Electronic gearing at an exact ratio.
    Gear(GearRatio),
    /// Camming.
    Cam(CamLaw),
}

/// The cam tables the card holds (`None`: not loaded).
pub type CamTables = [Option<CamTable>];

/// Where the law puts the slave this tick.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
struct LawState {
    pos: f64,
    vel: f64,
    acc: f64,
    /// The cam's cycle (periodic), or 1 once past the end of a table that is not.
    cycle: i64,
}

/// One coupling.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Run {
    seq: u32,
    master: Master,
    law: Law,
    /// The anchor (gearing): master units and slave position with `g(anchor_m) = anchor_x`.
    anchor_m: i128,
    anchor_x: f64,
    lim: SyncLimits,
    phase: Phase,
    /// The cam's cycle last tick.
    cycle: i64,
    /// A cam table to switch to at the end of the cycle: (its command, the law).
    next: Option<(u32, CamLaw)>,
}

impl Run {
    fn per_count(&self) -> i128 {
        self.master.per_count()
    }

    /// The slave's position, velocity and acceleration by the law at master `m` (`None`: a
    /// cam table that is not there).
    fn law_state(&self, m: &MasterSample, tables: &CamTables) -> Option<LawState> {
        match self.law {
            Law::Gear(ratio) => {
                let r = ratio.as_f64();
                Some(LawState {
                    pos: self.anchor_x + ratio.distance(m.count - self.anchor_m, self.per_count()),
                    vel: r * m.vel,
                    acc: r * m.acc,
                    cycle: 0,
                })
            }
            Law::Cam(c) => {
                let t = tables.get(c.table)?.as_ref()?;
                let x = m.count as f64 / self.per_count() as f64;
                let u = (x - c.m_off) / c.m_scale;
                let e = t.eval(u);
                let du = m.vel / c.m_scale;
                let past_end = !t.periodic() && u >= t.master_range().1;
                Some(LawState {
                    pos: c.s_off + c.s_scale * e.s,
                    vel: c.s_scale * e.ds * du,
                    acc: c.s_scale * (e.dds * du * du + e.ds * m.acc / c.m_scale),
                    cycle: if t.periodic() {
                        e.cycle
                    } else {
                        past_end as i64
                    },
                })
            }
        }
    }

    /// A cam crossed the end of a cycle into `cycle`: the next table (if one waits) takes
    /// over from the boundary, the slave's position continuous. Its command's seq.
    fn switch_cam(&mut self, cycle: i64, tables: &CamTables) -> Option<u32> {
        let (Law::Cam(c), Some((seq, mut n))) = (self.law, self.next) else {
            return None;
        };
        let old = tables.get(c.table)?.as_ref()?;
        let new = tables.get(n.table)?.as_ref()?;
        let ((m0, mn), (p, r)) = (old.master_range(), old.period());
        let s0 = old.eval(m0).s;
        let (u_b, s_b) = if old.periodic() {
            let k = cycle.max(self.cycle) as f64;
            (m0 + k * p, s0 + k * r)
        } else {
            (mn, old.eval(mn).s)
        };
        let x_b = c.m_off + c.m_scale * u_b;
        let pos_b = c.s_off + c.s_scale * s_b;
        let (n0, _) = new.master_range();
        n.m_off = x_b - n.m_scale * n0;
        n.s_off = pos_b - n.s_scale * new.eval(n0).s;
        self.law = Law::Cam(n);
        self.next = None;
        Some(seq)
    }
}

/// What a tick tells the command manager.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct SyncReport {
    /// The gear command `seq` is in gear (or in sync): (seq, event, slave position).
    pub locked: Option<(u32, SyncEvent, f64)>,
    /// The master of gear command `seq` was lost: (seq, master number).
    pub lost: Option<(u32, usize)>,
    /// A cam switched tables at the end of a cycle: (the switch's command, slave position).
    pub switched: Option<(u32, f64)>,
    /// A cam that is not periodic passed its table's end: (seq, slave position).
    pub cam_end: Option<(u32, f64)>,
    /// The slave's state changed from this one.
    pub state_from: Option<AxisState>,
}

/// An MC_GearIn or MC_GearInPos command, decoded.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GearCommand {
    /// The master.
    pub master: Master,
    /// The ratio, or the cam.
    pub law: Law,
    /// The slave's limits while engaging.
    pub lim: SyncLimits,
    /// MC_GearInPos: the master and slave positions that meet (counts).
    pub sync_at: Option<(f64, f64)>,
}

impl GearCommand {
    /// Check `MC_OP_GEAR_IN` (`sync_at: None`) or `_POS` (the master's and the slave's sync
    /// positions) for slave `slave` on a card of `num_axes` axes at `rate_hz`, after decoding
    /// (which found every argument finite, the master source known and its number an integer
    /// of its range). Nothing on the card changes.
    pub fn gear(
        g: &cmd::GearIn,
        sync_at: Option<(f64, f64)>,
        slave: usize,
        num_axes: usize,
        rate_hz: u32,
    ) -> Result<Self, NackCode> {
        let source = g.master.source;
        let index = g.master.index as usize;
        if source != MasterSource::Aux && index >= num_axes {
            return Err(NackCode::SyncMaster);
        }
        if source != MasterSource::Aux && index == slave {
            return Err(NackCode::SyncMaster);
        }
        let ratio = GearRatio::from_args(g.numerator, g.denominator).ok_or(NackCode::GearRatio)?;
        let lim = SyncLimits {
            vmax: g.limits.vmax,
            amax: g.limits.amax,
            jerk: g.limits.jerk,
        };
        check_ranges(rate_hz, &[(1, lim.vmax), (2, lim.amax), (3, lim.jerk)])?;
        if let Some((m, s)) = sync_at {
            if m.abs() > firmware_proto::MAX_POSITION || s.abs() > firmware_proto::MAX_POSITION {
                return Err(NackCode::OutOfRange);
            }
        }
        Ok(Self {
            master: Master { source, index },
            law: Law::Gear(ratio),
            lim,
            sync_at,
        })
    }
}

/// One axis's gearing as a slave.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Gear {
    run: Option<Run>,
}

impl Gear {
    /// Is the axis coupled (engaging or in gear)?
    pub fn engaged(&self) -> bool {
        self.run.is_some()
    }

    /// The ratio of the coupling, if any.
    pub fn ratio(&self) -> Option<GearRatio> {
        match self.run?.law {
            Law::Gear(r) => Some(r),
            Law::Cam(_) => None,
        }
    }

    /// The coupling's offset (gearing): where the ratio line puts the slave when the master
    /// is at 0, in slave counts, so that in gear `slave = offset + ratio · master` (counts;
    /// the anchor of MC_GearIn is where the slave and the master were at the engagement, of
    /// MC_GearInPos the sync point). `None` for a cam or no coupling.
    pub fn offset(&self) -> Option<f64> {
        let run = self.run?;
        match run.law {
            Law::Gear(r) => Some(run.anchor_x + r.distance(-run.anchor_m, run.master.per_count())),
            Law::Cam(_) => None,
        }
    }

    /// The cam table the axis follows, if any.
    pub fn cam_table(&self) -> Option<usize> {
        match self.run?.law {
            Law::Cam(c) => Some(c.table),
            Law::Gear(_) => None,
        }
    }

    /// MC_CamIn with `MC_CAM_AT_CYCLE_END` (command `seq`) on a slave that cams: the table
    /// `law` takes over at the end of the current cycle. `InvalidState` if it does not cam.
    pub fn queue_cam(&mut self, seq: u32, law: CamLaw) -> Result<(), NackCode> {
        match &mut self.run {
            Some(r) if matches!(r.law, Law::Cam(_)) => {
                r.next = Some((seq, law));
                Ok(())
            }
            _ => Err(NackCode::InvalidState),
        }
    }

    /// The master of the coupling, if any.
    pub fn master(&self) -> Option<Master> {
        self.run.map(|r| r.master)
    }

    /// MC_GearIn / MC_GearInPos (command `seq`) on `slave`, whose master is `m` now. Planned
    /// from the slave's commanded state; nothing changes if it is refused. Returns the old
    /// state.
    pub fn start(
        &mut self,
        slave: &mut Axis,
        seq: u32,
        cmd: &GearCommand,
        m: &MasterSample,
        tables: &CamTables,
    ) -> Result<Option<AxisState>, NackCode> {
        if m.lost {
            return Err(NackCode::SyncMaster);
        }
        match slave.state {
            AxisState::Standstill | AxisState::DiscreteMotion | AxisState::ContinuousMotion => {}
            // A new coupling on a coupled slave; not on one a PT/PVT stream drives.
            AxisState::SynchronizedMotion if self.run.is_some() => {}
            AxisState::Disabled => return Err(NackCode::AxisDisabled),
            AxisState::Homing => return Err(NackCode::AxisHoming),
            _ => return Err(NackCode::InvalidState),
        }
        let x = slave.reference();
        let lim = cmd.lim;
        let per_count = cmd.master.per_count();
        let mut run = Run {
            seq,
            master: cmd.master,
            law: cmd.law,
            anchor_m: m.count,
            anchor_x: x.pos,
            lim,
            phase: Phase::Locked,
            cycle: 0,
            next: None,
        };
        let st = run.law_state(m, tables).ok_or(NackCode::CamTable)?;
        run.cycle = st.cycle;
        // The difference's velocity and acceleration at the start.
        let (dv0, da0) = (x.vel - st.vel, x.acc - st.acc);
        let run = match cmd.sync_at {
            None => {
                let l = OtgLimits {
                    vmax: lim.vmax - st.vel,
                    vmin: -lim.vmax - st.vel,
                    amax: lim.amax,
                    amin: -lim.amax,
                    jmax: lim.jerk,
                };
                if l.vmax <= 0.0 || l.vmin >= 0.0 {
                    // The master runs faster than the slave may follow.
                    return Err(NackCode::Infeasible);
                }
                let d0 = x.pos - st.pos;
                let traj = Trajectory::to_position(d0, dv0, da0, 0.0, 0.0, &l)
                    .and_then(|t| t.verify(&l).map(|()| t))
                    .map_err(plan_nack)?;
                if !traj.duration().is_finite() || traj.duration() > MAX_MOVE_TIME {
                    return Err(NackCode::Infeasible);
                }
                run.phase = Phase::CatchUp { traj, t: 0.0 };
                run
            }
            Some((master_at, slave_at)) => {
                let Law::Gear(ratio) = cmd.law else {
                    return Err(NackCode::InvalidState);
                };
                let r = ratio.as_f64();
                let anchor_m = math::round(master_at * per_count as f64) as i128;
                run.anchor_m = anchor_m;
                run.anchor_x = slave_at;
                let geared = run.law_state(m, tables).map_or(0.0, |s| s.pos);
                let span = anchor_m - m.count;
                let span_counts = span as f64 / per_count as f64;
                // The time to the sync point at the master's present velocity.
                let t_sync = span_counts / m.vel;
                if !(t_sync.is_finite() && t_sync > 0.0 && t_sync <= MAX_MOVE_TIME) {
                    return Err(NackCode::Infeasible);
                }
                let d0 = x.pos - geared;
                let c = quintic(d0, dv0 * t_sync, da0 * t_sync * t_sync);
                check_quintic(&c, t_sync, r * m.vel, &lim)?;
                run.phase = Phase::ToSyncPoint {
                    m0: m.count,
                    span,
                    c,
                };
                run
            }
        };
        let changed = slave.begin_sync(seq)?;
        self.run = Some(run);
        Ok(changed)
    }

    /// MC_GearOut (command `seq`): velocity mode at the slave's velocity. Returns the old
    /// state.
    pub fn gear_out(
        &mut self,
        slave: &mut Axis,
        seq: u32,
        rate_hz: u32,
    ) -> Result<Option<AxisState>, NackCode> {
        let run = match self.run {
            Some(r) if slave.state == AxisState::SynchronizedMotion => r,
            _ => return Err(NackCode::InvalidState),
        };
        let changed = slave.leave_sync(seq, run.lim.amax, run.lim.jerk, rate_hz)?;
        self.run = None;
        Ok(changed)
    }

    /// One tick: drive `slave` from its master `m` (sampled this tick).
    pub fn tick(
        &mut self,
        slave: &mut Axis,
        m: &MasterSample,
        tables: &CamTables,
        ts: f64,
        max_stop_time: f64,
    ) -> SyncReport {
        let mut report = SyncReport::default();
        let Some(mut run) = self.run.take() else {
            return report;
        };
        if slave.state != AxisState::SynchronizedMotion {
            // A halt, stop, power off or safety stop ended it (and reported its end).
            return report;
        }
        if m.lost {
            report.lost = Some((run.seq, run.master.index));
            report.state_from = slave.sync_stop(max_stop_time, false);
            return report;
        }
        let Some(mut st) = run.law_state(m, tables) else {
            // A table that is not there (it cannot be reloaded while in use): as a lost master.
            report.lost = Some((run.seq, run.master.index));
            report.state_from = slave.sync_stop(max_stop_time, false);
            return report;
        };
        if st.cycle != run.cycle {
            if let Some(seq) = run.switch_cam(st.cycle, tables) {
                st = run.law_state(m, tables).unwrap_or(st);
                report.switched = Some((seq, st.pos));
            } else if st.cycle == 1 && !matches!(run.law, Law::Gear(_)) {
                if let Law::Cam(c) = run.law {
                    if tables
                        .get(c.table)
                        .and_then(|t| t.as_ref())
                        .is_some_and(|t| !t.periodic())
                    {
                        report.cam_end = Some((run.seq, st.pos));
                    }
                }
            }
            run.cycle = st.cycle;
        }
        let (mut pos, mut vel, mut acc) = (st.pos, st.vel, st.acc);
        let per_count = run.per_count() as f64;
        let engaged = match run.law {
            Law::Gear(_) => SyncEvent::InGear,
            Law::Cam(_) => SyncEvent::InSync,
        };
        match &mut run.phase {
            Phase::CatchUp { traj, t } => {
                *t += ts;
                if *t >= traj.duration() {
                    run.phase = Phase::Locked;
                    report.locked = Some((run.seq, engaged, pos));
                } else {
                    let d = traj.sample(*t);
                    pos += d.pos;
                    vel += d.vel;
                    acc += d.acc;
                }
            }
            Phase::ToSyncPoint { m0, span, c } => {
                let u = (m.count - *m0) as f64 / *span as f64;
                if u >= 1.0 {
                    run.phase = Phase::Locked;
                    report.locked = Some((run.seq, SyncEvent::InSync, pos));
                } else {
                    let u = u.max(0.0);
                    let span_counts = *span as f64 / per_count;
                    let du = m.vel / span_counts;
                    let (p, p1, p2, _) = poly(c, u);
                    pos += p;
                    vel += p1 * du;
                    acc += p2 * du * du + p1 * m.acc / span_counts;
                }
            }
            Phase::Locked => {}
        }
        slave.drive(Reference { pos, vel, acc });
        if report.locked.is_some() {
            slave.set_in_sync(true);
        }
        self.run = Some(run);
        report
    }
}

/// The quintic `p(u)`, `u ∈ [0, 1]`, with `p(0) = d0`, `p'(0) = d1`, `p''(0) = d2` and
/// `p(1) = p'(1) = p''(1) = 0`: its coefficients, constant first.
pub fn quintic(d0: f64, d1: f64, d2: f64) -> [f64; 6] {
    let (c0, c1, c2) = (d0, d1, d2 / 2.0);
    // c3 + c4 + c5 = a, 3c3 + 4c4 + 5c5 = b, 6c3 + 12c4 + 20c5 = c.
    let a = -(c0 + c1 + c2);
    let b = -(c1 + 2.0 * c2);
    let c = -(2.0 * c2);
    [
        c0,
        c1,
        c2,
        10.0 * a - 4.0 * b + c / 2.0,
        -15.0 * a + 7.0 * b - c,
        6.0 * a - 3.0 * b + c / 2.0,
    ]
}

/// `p(u)` and its first three derivatives.
fn poly(c: &[f64; 6], u: f64) -> (f64, f64, f64, f64) {
    let p = c[0] + u * (c[1] + u * (c[2] + u * (c[3] + u * (c[4] + u * c[5]))));
    let p1 = c[1] + u * (2.0 * c[2] + u * (3.0 * c[3] + u * (4.0 * c[4] + u * 5.0 * c[5])));
    let p2 = 2.0 * c[2] + u * (6.0 * c[3] + u * (12.0 * c[4] + u * 20.0 * c[5]));
    let p3 = 6.0 * c[3] + u * (24.0 * c[4] + u * 60.0 * c[5]);
    (p, p1, p2, p3)
}

/// Is the slave within `lim` along the quintic `c` run over `t_sync` s, on top of the geared
/// velocity `vg` (a master at constant velocity)? Else `Infeasible`.
fn check_quintic(c: &[f64; 6], t_sync: f64, vg: f64, lim: &SyncLimits) -> Result<(), NackCode> {
    for k in 0..=QUINTIC_SAMPLES {
        let u = k as f64 / QUINTIC_SAMPLES as f64;
        let (_, p1, p2, p3) = poly(c, u);
        let v = vg + p1 / t_sync;
        let a = p2 / (t_sync * t_sync);
        let j = p3 / (t_sync * t_sync * t_sync);
        if !(v.abs() <= lim.vmax * LIMIT_SLACK
            && a.abs() <= lim.amax * LIMIT_SLACK
            && j.abs() <= lim.jerk * LIMIT_SLACK)
        {
            return Err(NackCode::Infeasible);
        }
    }
    Ok(())
}

/// Every slave's master, sampled this tick (before any slave is driven).
pub fn sample_masters(
    gears: &[Gear; MAX_AXES],
    axes: &[Axis],
    aux: &AuxInputs,
) -> [MasterSample; MAX_AXES] {
    core::array::from_fn(|i| {
        gears[i]
            .master()
            .map_or(MasterSample::default(), |m| m.sample(axes, aux))
    })
}

// ---- The command manager's and the control loop's side (Firmware's fields are the parent's) ----
impl<M: Mem + Clone> Firmware<M> {
    /// The auxiliary encoder counts for the next tick, as the encoder interface latches them.
    pub fn set_aux_encoders(&mut self, counts: [i64; AUX_ENCODERS]) {
        self.aux.set(counts);
    }

    /// One axis's gearing (for inspection by tests).
    pub fn gear(&self, i: usize) -> Option<&Gear> {
        self.gears[..self.num_axes].get(i)
    }

    /// MC_GearIn, MC_GearInPos or MC_CamIn (command `seq`, checked: `cmd`) on axis `ax` (one of
    /// the card's, not in an enabled group, no latch): the old state and whether it took the
    /// axis over, or the nack. `at_cycle_end`, `relative`: MC_CamIn's flags.
    pub(super) fn execute_gear(
        &mut self,
        seq: u32,
        ax: usize,
        mut cmd: GearCommand,
        at_cycle_end: bool,
        relative: bool,
    ) -> Result<(Option<AxisState>, bool), NackCode> {
        if let (Law::Cam(law), true) = (cmd.law, at_cycle_end) {
            // MC_CamTableSelect at the end of the cycle: nothing is taken over now.
            if self.cam_table(law.table).is_none() {
                return Err(NackCode::CamTable);
            }
            return self.gears[ax].queue_cam(seq, law).map(|()| (None, false));
        }
        let m = cmd.master.sample(&self.axes[..self.num_axes], &self.aux);
        let tables = self.cams.as_ref().map_or(&[][..], |s| s.tables());
        if let (Law::Cam(law), true) = (&mut cmd.law, relative) {
            // StartMode relative: the table's position here is moved onto the slave's.
            let t = tables
                .get(law.table)
                .and_then(Option::as_ref)
                .ok_or(NackCode::CamTable)?;
            let x = m.count as f64 / cmd.master.per_count() as f64;
            let here = law.s_off + law.s_scale * t.eval((x - law.m_off) / law.m_scale).s;
            law.s_off += self.axes[ax].reference().pos - here;
            if law.s_off.is_nan() || law.s_off.abs() > firmware_proto::MAX_POSITION {
                return Err(NackCode::OutOfRange);
            }
        }
        self.gears[ax]
            .start(&mut self.axes[ax], seq, &cmd, &m, tables)
            .map(|s| (s, true))
    }

    /// MC_GearOut, MC_CamOut (command `seq`) on axis `ax`: the old state; it takes the axis
    /// over.
    pub(super) fn execute_gear_out(
        &mut self,
        seq: u32,
        ax: usize,
    ) -> Result<(Option<AxisState>, bool), NackCode> {
        let rate = self.servo_rate_hz;
        self.gears[ax]
            .gear_out(&mut self.axes[ax], seq, rate)
            .map(|s| (s, true))
    }

    /// The gearing step of a tick (after the groups, before homing and the servo loops): the
    /// auxiliary encoders are sensed, every master sampled, then every slave driven.
    /// `None` when no slave is coupled: then the step is nothing but the auxiliary encoders'
    /// (each slave's step returns at once without a coupling), and there is nothing to post.
    pub(super) fn gear_tick(&mut self, ts: f64) -> Option<[SyncReport; MAX_AXES]> {
        self.aux.sense(ts);
        if !self.gears[..self.num_axes].iter().any(Gear::engaged) {
            return None;
        }
        Some(self.gear_step(ts))
    }

    /// Run [`Axis::reference_into`] now for every axis that is the commanded-position master
    /// of an engaged coupling (and no slave itself: a slave takes its reference from the gear
    /// step): its slaves then follow the master's reference of this tick. What it returned
    /// (powered, and the report so far) goes to the servo half in the tick's axis loop.
    pub(super) fn advance_commanded_masters(
        &mut self,
        ts: f64,
    ) -> [Option<(bool, TickReport)>; MAX_AXES] {
        let n = self.num_axes;
        let mut early: [Option<(bool, TickReport)>; MAX_AXES] = Default::default();
        if !self.gears[..n].iter().any(Gear::engaged) {
            return early;
        }
        let mut masters = [false; MAX_AXES];
        for g in &self.gears[..n] {
            if let Some(m) = g.master() {
                if m.source == MasterSource::Commanded && m.index < n {
                    masters[m.index] = true;
                }
            }
        }
        for (i, axis) in self.axes[..n].iter_mut().enumerate() {
            if masters[i] && !self.gears[i].engaged() {
                let mut r = TickReport::default();
                let powered = axis.reference_into(ts, &mut r);
                early[i] = Some((powered, r));
            }
        }
        early
    }

    /// The slaves' step, some coupled.
    #[inline(never)]
    fn gear_step(&mut self, ts: f64) -> [SyncReport; MAX_AXES] {
        let n = self.num_axes;
        let samples = sample_masters(&self.gears, &self.axes[..n], &self.aux);
        let max_stop_time = self.safety.config().max_stop_time();
        let tables = self.cams.as_ref().map_or(&[][..], |s| s.tables());
        core::array::from_fn(|i| match (self.axes[..n].get_mut(i), samples.get(i)) {
            (Some(axis), Some(m)) => self.gears[i].tick(axis, m, tables, ts, max_stop_time),
            _ => SyncReport::default(),
        })
    }

    /// Post the events of a gearing step (after the status was published).
    pub(super) fn post_sync_events(&mut self, reports: &Option<[SyncReport; MAX_AXES]>) {
        let Some(reports) = reports else { return };
        for (i, r) in reports[..self.num_axes].iter().enumerate() {
            let axis = i as u16;
            if let Some((seq, what, pos)) = r.locked {
                self.post_axis_event(EventKind::Sync, seq, axis, what as i32, pos);
            }
            if let Some((seq, master)) = r.lost {
                self.post_axis_event(
                    EventKind::Sync,
                    seq,
                    axis,
                    SyncEvent::MasterLost as i32,
                    master as f64,
                );
                self.post_axis_event(
                    EventKind::MotionAborted,
                    seq,
                    axis,
                    Opcode::Halt as i32,
                    0.0,
                );
            }
            for (seq, what, pos) in [
                r.switched.map(|(s, p)| (s, SyncEvent::CamSwitch, p)),
                r.cam_end.map(|(s, p)| (s, SyncEvent::CamEnd, p)),
            ]
            .into_iter()
            .flatten()
            {
                self.post_axis_event(EventKind::Sync, seq, axis, what as i32, pos);
            }
            if let Some(old) = r.state_from {
                let e = super::state_event(axis, old, self.axes[i].state, self.tick);
                self.post(e);
            }
        }
    }

    /// Publish the synchronised-motion status block (layout 1.7).
    pub(super) fn publish_sync(&self) {
        let mut b = raw::mc_sync_status {
            aux_count: self.aux.count,
            ..Default::default()
        };
        for (i, g) in self.gears[..self.num_axes].iter().enumerate() {
            b.gear_ratio[i] = g.ratio().map_or(0.0, |r| r.as_f64());
        }
        (b.pvt_queued, b.pvt_free) = self.pvt_status();
        layout::SYNC_STATUS.write(&self.mem, &b);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quintic_meets_its_ends() {
        let c = quintic(3.0, -2.0, 5.0);
        let (p, p1, p2, _) = poly(&c, 0.0);
        assert_eq!((p, p1, p2), (3.0, -2.0, 5.0));
        let (p, p1, p2, _) = poly(&c, 1.0);
        assert!(p.abs() < 1e-12 && p1.abs() < 1e-12 && p2.abs() < 1e-12);
        // The smoothstep.
        assert_eq!(quintic(1.0, 0.0, 0.0), [1.0, 0.0, 0.0, -10.0, 15.0, -6.0]);
    }

    #[test]
    fn quintic_limits_are_checked() {
        let lim = SyncLimits {
            vmax: 1000.0,
            amax: 1e4,
            jerk: 1e6,
        };
        // 100 counts over 1 s from rest, master at 0: within.
        let c = quintic(-100.0, 0.0, 0.0);
        assert_eq!(check_quintic(&c, 1.0, 0.0, &lim), Ok(()));
        // The same in 10 ms: far beyond.
        assert_eq!(
            check_quintic(&c, 0.01, 0.0, &lim),
            Err(NackCode::Infeasible)
        );
        // A geared velocity above vmax.
        assert_eq!(
            check_quintic(&quintic(0.0, 0.0, 0.0), 1.0, 1001.0, &lim),
            Err(NackCode::Infeasible)
        );
    }

    #[test]
    fn aux_velocity_over_a_tick() {
        let mut aux = AuxInputs::default();
        aux.set([10, 0]);
        aux.sense(1e-3);
        assert_eq!(aux.vel, [0.0, 0.0]);
        aux.set([20, -5]);
        aux.sense(1e-3);
        assert_eq!(aux.count, [20, -5]);
        assert_eq!(aux.vel, [10_000.0, -5_000.0]);
    }

    #[test]
    fn commands_are_checked() {
        let ok = [1.0, 3.0, 7.0, 1e4, 1e5, 1e7, 0.0, 0.0];
        // Decoded as the card decodes an entry, then checked.
        let d = |a: &[f64], f: u32| {
            let mut args = [0.0; firmware_proto::CMD_ARGS];
            args[..a.len()].copy_from_slice(a);
            let g = <cmd::GearIn as cmd::Args>::decode(f, &args).map_err(|e| e.nack)?;
            GearCommand::gear(&g, None, 0, 2, 10_000)
        };
        assert!(d(&ok, 0).is_ok());
        assert_eq!(d(&ok, 7).unwrap_err(), NackCode::SyncMaster);
        let mut a = ok;
        a[0] = 0.0; // the slave itself
        assert_eq!(d(&a, 0).unwrap_err(), NackCode::SyncMaster);
        assert!(d(&a, 2).is_ok(), "aux 0 is not the slave");
        a[0] = 2.0;
        assert_eq!(d(&a, 2).unwrap_err(), NackCode::SyncMaster);
        for (i, bad, code) in [
            (1, 0.5, NackCode::GearRatio),
            (2, 0.0, NackCode::GearRatio),
            (2, -1.0, NackCode::GearRatio),
            (1, 1e300, NackCode::GearRatio),
            (3, f64::NAN, NackCode::NotFinite),
            (4, f64::INFINITY, NackCode::NotFinite),
            (5, -1.0, NackCode::NonPositiveLimit),
            (3, 1e300, NackCode::LimitRange),
            (4, 1e-320, NackCode::LimitRange),
        ] {
            let mut a = ok;
            a[i] = bad;
            assert_eq!(d(&a, 0).unwrap_err(), code, "arg {i} = {bad}");
        }
    }
}
