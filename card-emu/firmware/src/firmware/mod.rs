//! The firmware: boot, the command manager and the control loop (Thinh Fig 6–7).
//!
//! It is pure and deterministic: [`Firmware::serve_commands`] reads the command ring and
//! answers every command with exactly one ack or nack; [`Firmware::tick`] takes the encoder
//! readings, runs profiles and servo loops, and returns the DAC voltages. Time is the tick
//! count; nothing reads a clock, calls the OS, allocates or panics.
#![forbid(unsafe_code)]

pub mod analog;
pub mod axis;
pub mod axis_safety;
pub mod cam;
pub mod comp;
pub mod compare;
pub mod config;
pub mod dac;
mod exec;
pub mod freq;
pub mod gantry;
pub mod gear;
pub mod group;
mod group_home;
pub mod handwheel;
pub mod homing;
pub mod io;
pub mod nack;
pub mod outbox;
pub mod probe;
pub mod pvt;
pub mod quiet;
pub mod safety;
pub mod scope;
#[cfg(test)]
mod tests_arc_pair;
#[cfg(test)]
mod tests_timed;
#[cfg(test)]
mod tests_wide;
pub mod timed;

use self::axis::{Axis, AxisConfig, TickReport};
use self::gear::{AuxInputs, Gear};
use self::group::{filter_bank, FilterConfig, Group, Outbox};
use self::homing::{Homing, HomingInputs, HomingReport};
use self::io::{DigitalInputs, IoUnit};
use self::safety::{Inputs, Safety};
use crate::math;
use crate::ram::Lazy;
use firmware_proto::layout;
use firmware_proto::ring::{CmdConsumer, EvtProducer, CMD_RING, EVT_RING};
use firmware_proto::{
    raw, seqlock, AxisState, Command, Event, EventKind, Mem, NackCode, MAX_AXES, MAX_GROUPS,
};
use firmware_proto::{ScopeEvent, ScopeProducer, Signal};

/// Firmware version reported in the identity block: major << 16 | minor << 8 | patch.
pub const FW_VERSION: u32 = 1 << 16;

/// Commands served per call of [`Firmware::serve_commands`], so a flood cannot starve the loop.
pub const MAX_CMDS_PER_SERVE: usize = 16;

/// Event slots kept free for asynchronous events: a command is only taken from the ring when
/// its ack and this many events still fit, so acks are never lost; a path's segment events
/// are not posted into them either, so the answers of commands timed to a tick always fit.
pub const EVENT_RESERVE: u32 = 4 * MAX_AXES as u32;

/// The servo rate of a sample time, Hz (the steps that get only `ts` plan with the card's
/// ranges at its rate).
pub(crate) fn rate_hz(ts: f64) -> u32 {
    math::round(1.0 / ts) as u32
}

/// The card's firmware over a DPRAM window `M`.
pub struct Firmware<M: Mem + Clone> {
    mem: M,
    cmds: CmdConsumer<M>,
    events: EvtProducer<M>,
    axes: [Axis; MAX_AXES],
    homing: [Homing; MAX_AXES],
    /// Layout 1.7 (sync): each axis's gearing as a slave, and the auxiliary encoders.
    gears: [Gear; MAX_AXES],
    aux: AuxInputs,
    /// Layout 1.10: each axis's handwheel.
    handwheels: handwheel::Handwheels,
    /// Layout 1.7 (sync): the cam tables, made on the first MC_OP_CAM_TABLE.
    cams: Lazy<cam::CamStore>,
    /// Layout 1.9: the compensation tables, made on the first MC_OP_COMP_TABLE.
    comp: Lazy<comp::CompStore>,
    /// Layout 1.10: the gantries (gantry.rs), and those whose status block must be cleared.
    gantries: [Option<gantry::Gantry>; gantry::MAX_GANTRIES],
    gantry_dirty: u8,
    /// Layout 1.11: each gantry's last `MC_EV_GANTRY_HOMED` (code, value), for a group homing.
    gantry_homed: [Option<(i32, f64)>; gantry::MAX_GANTRIES],
    /// Layout 1.7 (sync): each axis's PT/PVT stream, made on its first MC_OP_PVT_BEGIN.
    pvt: pvt::PvtStreams,
    groups: [Group; MAX_GROUPS],
    /// What each group's status block holds (a block whose content stands still gets only
    /// its tick rewritten: quiet.rs).
    group_blocks: [quiet::GroupBlock; MAX_GROUPS],
    filters: group::FilterBank,
    outbox: Outbox,
    /// The digital outputs (layout 1.6), bit i = output i.
    outputs: u32,
    /// Digital inputs, position compare and touch probes (layout 1.7).
    io: IoUnit,
    /// Layout 1.11: analog inputs, spare DACs and the path-speed output.
    analog: analog::AnalogUnit,
    /// Layout 1.12: the frequency sweep in progress, and its end's event to post.
    sweep: Option<freq::Sweep>,
    sweep_event: Option<Event>,
    num_axes: usize,
    /// Layout 1.8: each axis's scale, counts per user unit, kept for hosts (not used here).
    scales: [f64; MAX_AXES],
    servo_rate_hz: u32,
    tick: u64,
    irq_pending: bool,
    events_lost: u32,
    cmds_accepted: u32,
    safety: Safety,
    /// Layout 1.8: the scope, made on the first MC_OP_SCOPE_CONFIGURE, and its ring.
    scope: Lazy<scope::Scope>,
    scope_ring: ScopeProducer<M>,
    /// Layout 1.12: the sync bus and the timed commands held (timed.rs).
    timing: timed::Timing,
    /// Layout 1.13: the second entry of the `MC_OP_GROUP_MOVE_CIRCULAR_NORMAL` being executed
    /// (taken with it, see `answer_arc_pair`; None: it came alone).
    second: Option<Command>,
}

impl<M: Mem + Clone> Firmware<M> {
    /// Initialise the window (identity, rings, status) and start.
    pub fn boot(mem: M, num_axes: usize, servo_rate_hz: u32) -> Self {
        let num_axes = num_axes.clamp(1, MAX_AXES);
        let servo_rate_hz = servo_rate_hz.clamp(
            firmware_proto::SERVO_RATE_MIN_HZ,
            firmware_proto::SERVO_RATE_MAX_HZ,
        );
        mem.write32(layout::CARD_STATE, raw::MC_CARD_BOOTING);
        for off in [
            layout::CMD_HEAD,
            layout::CMD_TAIL,
            layout::EVT_HEAD,
            layout::EVT_TAIL,
            layout::SCOPE_HEAD,
            layout::SCOPE_TAIL,
        ] {
            mem.write32(off, 0);
        }
        let safety = Safety::boot(&mem);
        let mut fw = Self {
            safety,
            cmds: CmdConsumer::attach(mem.clone(), CMD_RING),
            events: EvtProducer::attach(mem.clone(), EVT_RING),
            scope_ring: ScopeProducer::attach(mem.clone(), firmware_proto::SCOPE_RING),
            scope: Lazy::new(),
            mem,
            axes: core::array::from_fn(|_| Axis::new()),
            homing: [Homing::default(); MAX_AXES],
            gears: [Gear::default(); MAX_AXES],
            aux: AuxInputs::default(),
            handwheels: [None; MAX_AXES],
            pvt: core::array::from_fn(|_| Lazy::new()),
            cams: Lazy::new(),
            comp: Lazy::new(),
            gantries: Default::default(),
            gantry_dirty: 0,
            gantry_homed: [None; gantry::MAX_GANTRIES],
            groups: core::array::from_fn(Group::new),
            group_blocks: [quiet::GroupBlock::default(); MAX_GROUPS],
            filters: filter_bank(),
            outbox: Outbox::default(),
            outputs: 0,
            io: IoUnit::new(),
            analog: analog::AnalogUnit::new(),
            sweep: None,
            sweep_event: None,
            num_axes,
            scales: [1.0; MAX_AXES],
            servo_rate_hz,
            tick: 0,
            irq_pending: false,
            events_lost: 0,
            cmds_accepted: 0,
            timing: timed::Timing::new(),
            second: None,
        };
        layout::CARD_CONFIG.write(
            &fw.mem,
            &raw::mc_card_config {
                servo_rate_hz,
                ..Default::default()
            },
        );
        for a in 0..MAX_AXES {
            fw.write_axis_config(a, &AxisConfig::default());
            fw.write_axis_filter(a, &FilterConfig::default());
            // Layout 1.11: the default PID+FF tuning (the law is FFPIV until selected), no
            // servo filter.
            layout::AXIS_PIDFF
                .at(a)
                .write(&fw.mem, &firmware_proto::AxisPidff::default());
            layout::SERVO_FILTERS
                .at(a)
                .write(&fw.mem, &fw.axes[a].filters().block());
            layout::AXIS_HOMING
                .at(a)
                .write(&fw.mem, &fw.homing[a].config().block);
        }
        for (g, group) in fw.groups.iter().enumerate() {
            layout::GROUP_PATH.at(g).write(&fw.mem, group.path_config());
        }
        layout::IO_CONFIG.write(&fw.mem, &fw.io.config().to_block());
        layout::FREQ_STATUS.write(&fw.mem, &raw::mc_freq_status::default());
        fw.publish();
        fw.mem.store32(
            layout::CARD_STATE,
            raw::MC_CARD_RUNNING,
            core::sync::atomic::Ordering::Release,
        );
        fw
    }

    /// Write the identity block. The card owns it: it is republished every tick, so a stray
    /// write by a host (or anything else mapping the window) cannot lock the next host out.
    fn publish_identity(&self) {
        let m = &self.mem;
        m.write32(layout::MAGIC, firmware_proto::MAGIC);
        m.write32(
            layout::LAYOUT,
            firmware_proto::LAYOUT_MAJOR as u32 | (firmware_proto::LAYOUT_MINOR as u32) << 16,
        );
        m.write32(layout::FW_VERSION, FW_VERSION);
        m.write32(
            layout::CAPABILITIES,
            raw::MC_CAP_SCURVE | raw::MC_CAP_FFPIV | raw::MC_CAP_EVENT_IRQ,
        );
        m.write32(layout::NUM_AXES, self.num_axes as u32);
        m.write32(layout::SERVO_RATE_HZ, self.servo_rate_hz);
        m.write32(layout::CMD_RING_LEN, CMD_RING.len);
        m.write32(layout::EVT_RING_LEN, EVT_RING.len);
    }

    /// Sample time, s.
    pub fn ts(&self) -> f64 {
        1.0 / self.servo_rate_hz as f64
    }

    /// Servo rate, Hz.
    pub fn servo_rate_hz(&self) -> u32 {
        self.servo_rate_hz
    }

    /// Servo ticks since boot.
    pub fn tick_count(&self) -> u64 {
        self.tick
    }

    /// Axes on this card.
    pub fn num_axes(&self) -> usize {
        self.num_axes
    }

    /// One axis (for inspection by tests and benches).
    pub fn axis(&self, i: usize) -> Option<&Axis> {
        self.axes[..self.num_axes].get(i)
    }

    /// The board's watchdog timeout at boot, µs ([`Safety::set_boot_watchdog_timeout`]).
    pub fn set_boot_watchdog_timeout(&mut self, us: u32) -> Result<(), firmware_proto::NackCode> {
        self.safety.set_boot_watchdog_timeout(&self.mem, us)
    }

    /// The safety layer (watchdog, latches, configuration).
    pub fn safety(&self) -> &Safety {
        &self.safety
    }

    /// One axis's homing (its configuration, and whether it runs).
    pub fn homing(&self, i: usize) -> Option<&Homing> {
        self.homing[..self.num_axes].get(i)
    }

    /// The card's inputs (limit, home and alarm switches, encoder fault, e-stop) for the next
    /// tick, as the FPGA samples them.
    pub fn set_inputs(&mut self, inputs: Inputs) {
        self.safety.set_inputs(inputs);
    }

    /// The digital input pins for the next tick, with their edges' instants (layout 1.7).
    pub fn set_digital_inputs(&mut self, inputs: DigitalInputs) {
        self.io.set_inputs(inputs);
    }

    /// The lowest and highest count of each encoder over the period the next tick ends, as
    /// the encoder interface tracks them (layout 1.7's compare sees a crossing undone within
    /// the tick).
    pub fn set_encoder_spans(&mut self, spans: io::EncoderSpans) {
        self.io.set_spans(spans);
    }

    /// The analog input pins for the next tick, V (layout 1.11).
    pub fn set_analog_inputs(&mut self, volts: [f64; firmware_proto::ANALOG_INPUTS]) {
        self.analog.set_pins(volts);
    }

    /// Analog inputs, spare DACs and the PSO (layout 1.11).
    pub fn analog(&self) -> &analog::AnalogUnit {
        &self.analog
    }

    /// Digital inputs, compare channels and probes.
    pub fn io(&self) -> &IoUnit {
        &self.io
    }

    /// Post an event of this tick about `axis` (or a channel).
    fn post_axis_event(&mut self, kind: EventKind, seq: u32, axis: u16, code: i32, value: f64) {
        self.post(Event {
            seq,
            kind: kind as u16,
            axis,
            code,
            tick: self.tick,
            value,
        });
    }

    fn post_safety_events(&mut self) {
        for k in 0..self.safety.events.len() {
            if let Some(e) = self.safety.events.get(k) {
                self.post(e);
            }
        }
        self.safety.events.clear();
        self.mem
            .write32(layout::SAFETY_EVENTS_LOST, self.safety.events.lost());
    }

    /// Was an interrupt raised since the last call? Clears the flag.
    pub fn take_irq(&mut self) -> bool {
        let raised = core::mem::take(&mut self.irq_pending);
        if raised {
            let n = self.mem.read32(layout::IRQ_COUNT).wrapping_add(1);
            self.mem.write32(layout::IRQ_COUNT, n);
        }
        raised
    }

    /// The command manager: answer up to [`MAX_CMDS_PER_SERVE`] waiting commands. Returns how
    /// many were served.
    pub fn serve_commands(&mut self) -> usize {
        let mut served = 0;
        while served < MAX_CMDS_PER_SERVE {
            // Never take a command whose ack might not fit.
            match self.events.free() {
                Ok(free) if free > EVENT_RESERVE => {}
                _ => break,
            }
            let cmd: Command = match self.cmds.pop() {
                Ok(Some(c)) => c,
                Ok(None) => break,
                Err(e) => {
                    // The host's head is beyond anything it could have written: drop what is
                    // there rather than act on garbage, stop the axes, and tell the host.
                    self.cmds.resync();
                    let head = match e {
                        firmware_proto::RingError::Corrupt { head, .. } => head,
                        firmware_proto::RingError::Full => 0,
                    };
                    // [safety] category 1 stop of every axis, protocol-error event
                    self.safety.protocol_error(
                        &self.mem,
                        self.tick,
                        &mut self.axes[..self.num_axes],
                        raw::MC_PROTO_CMD_RING as i32,
                        head,
                    );
                    self.post_safety_events();
                    break;
                }
            };
            served += 1;
            if cmd.opcode == firmware_proto::Opcode::AtTick as u16 {
                // Layout 1.12: a timed command, the entry after this one (timed.rs).
                self.take_timed(&cmd);
                continue;
            }
            if let Some(second) = second_entry(cmd.opcode) {
                // Layout 1.13: a move and its second entry, published together; layout 1.14:
                // a path segment and its MC_OP_PATH_MORE.
                served += usize::from(self.answer_pair(&cmd, second as u16));
                continue;
            }
            self.answer(&cmd);
        }
        served
    }

    /// Take one command off the ring: execute it (unless expired), then its ack or nack and the
    /// events it raised. Out of line: commands come seldom next to ticks, and the frame of
    /// `execute` (every command's locals) is large; [`Firmware::serve_commands`] with an empty
    /// ring should not touch it.
    #[inline(never)]
    fn answer(&mut self, cmd: &Command) {
        self.cmds_accepted = self.cmds_accepted.wrapping_add(1);
        self.mem.write32(layout::CMDS_ACCEPTED, self.cmds_accepted);
        if self.expired(cmd) {
            self.reply(cmd, Err(NackCode::Expired));
        } else {
            self.answer_taken(cmd);
        }
    }

    /// A command of two entries (`c`, taken) and its second entry (opcode `second`): taken too
    /// when it is the next entry, of the same group, and then answered with the command's
    /// outcome (the group checks the two as one). Layout 1.13:
    /// `MC_OP_GROUP_MOVE_CIRCULAR_NORMAL` and its `MC_OP_GROUP_CIRCULAR_PLANE`
    /// (`group/normal.rs`: without it the move is refused, `MC_NACK_ARC_PIECE`); layout 1.14:
    /// a path segment and its `MC_OP_PATH_MORE` (`group/wide.rs`: whether the segment needs one
    /// is the group's to say). A next entry that is not the second stays in the ring, served on
    /// its own. Whether the second entry was taken.
    #[inline(never)]
    fn answer_pair(&mut self, c: &Command, second: u16) -> bool {
        // (a corrupt ring reads as nothing here: the next pop finds it and stops the axes)
        let second = match self.cmds.peek::<Command>() {
            Ok(Some(n)) if n.opcode == second && n.axis == c.axis => {
                let _ = self.cmds.pop::<Command>();
                Some(n)
            }
            _ => None,
        };
        let taken = 1 + u32::from(second.is_some());
        self.cmds_accepted = self.cmds_accepted.wrapping_add(taken);
        self.mem.write32(layout::CMDS_ACCEPTED, self.cmds_accepted);
        let outcome = if self.expired(c) {
            Err(NackCode::Expired)
        } else {
            self.second = second;
            let r = self.execute(c);
            self.second = None;
            r
        };
        self.reply(c, outcome);
        if let Some(n) = second {
            self.reply(&n, outcome);
        }
        second.is_some()
    }

    /// Execute a command taken off the ring (now, or a timed one on its tick) and answer it.
    fn answer_taken(&mut self, cmd: &Command) {
        let outcome = self.execute(cmd);
        self.reply(cmd, outcome);
    }

    /// The ack or nack of `cmd`, after the status it left, then the events it raised.
    fn reply(&mut self, cmd: &Command, outcome: Result<f64, NackCode>) {
        let reply = match outcome {
            Ok(value) => Event {
                seq: cmd.seq,
                kind: EventKind::Ack as u16,
                axis: cmd.axis,
                code: 0,
                tick: self.tick,
                value,
            },
            Err(code) => Event {
                seq: cmd.seq,
                kind: EventKind::Nack as u16,
                axis: cmd.axis,
                code: code as i32,
                tick: self.tick,
                value: 0.0,
            },
        };
        if reply.kind == EventKind::Ack as u16 {
            // The status first, then the events about it: a host that has the ack reads
            // the state the command left (see `tick`).
            self.publish();
        }
        self.post(reply);
        self.post_outbox();
        self.post_safety_events(); // [safety] events of the command (e-stop)
    }

    /// Has the command's deadline passed? The host's clock is read after the command was
    /// taken from the ring (its tail published): a host that gives up on a command first
    /// advances its clock past the deadline, then looks whether the card took it, so either
    /// the host sees it taken or the card sees it expired (a store-load pair of SeqCst fences).
    fn expired(&self, c: &Command) -> bool {
        if c.deadline_ms == 0 {
            return false;
        }
        core::sync::atomic::fence(core::sync::atomic::Ordering::SeqCst);
        let now = self
            .mem
            .load32(layout::HOST_TIME_MS, core::sync::atomic::Ordering::SeqCst);
        now != 0 && (now.wrapping_sub(c.deadline_ms) as i32) > 0
    }

    /// An axes group (for inspection by tests and benches).
    pub fn group(&self, g: usize) -> Option<&Group> {
        self.groups.get(g)
    }

    fn post_outbox(&mut self) {
        for i in 0..self.outbox.len() {
            if let Some(e) = self.outbox.get(i) {
                self.post(e);
            }
        }
        self.outbox.clear();
        let lost = self.outbox.lost().wrapping_add(self.io.events_lost());
        self.mem.write32(layout::OUTBOX_LOST, lost);
    }

    fn write_axis_config(&self, a: usize, c: &AxisConfig) {
        layout::AXIS_CONFIG.at(a).write(&self.mem, &c.block);
    }

    fn write_axis_filter(&self, a: usize, c: &FilterConfig) {
        layout::AXIS_FILTER.at(a).write(&self.mem, &c.to_block());
    }

    fn post(&mut self, e: Event) {
        // A path's segment starts and ends (thousands a second; the group status counts them
        // too) leave the reserve to the answers and the other events: a host that drains late
        // loses some of them (counted), never an answer to a command timed to a tick.
        let chatty =
            e.kind == EventKind::SegmentStart as u16 || e.kind == EventKind::SegmentEnd as u16;
        let full = chatty && !matches!(self.events.free(), Ok(free) if free > EVENT_RESERVE);
        if full || self.events.push(&e).is_err() {
            self.events_lost = self.events_lost.wrapping_add(1);
            self.mem.write32(layout::EVENTS_LOST, self.events_lost);
            return;
        }
        let mask = self.mem.read32(layout::IRQ_MASK);
        if e.kind < 32 && mask & (1 << e.kind) != 0 {
            self.irq_pending = true;
        }
    }

    /// The control loop: one servo tick. `encoders` are the counts of each axis; the DAC
    /// voltages are written to `dac`.
    pub fn tick(&mut self, encoders: &[i64; MAX_AXES], dac: &mut [f64; MAX_AXES]) {
        self.tick += 1;
        // Layout 1.12: the commands timed to this tick, first (timed.rs).
        self.run_timed();
        let ts = self.ts();
        // Sensors first, so a group's interpolator sees this tick's measurements.
        for (axis, enc) in self.axes[..self.num_axes].iter_mut().zip(encoders) {
            axis.sense(*enc, ts);
        }
        for g in self.groups.iter_mut() {
            g.tick(
                &mut self.axes,
                &mut self.filters,
                ts,
                self.tick,
                &mut self.outbox,
            );
            // Outputs a path sets or clears at a segment's start, end or distance.
            let (set, clear) = g.take_path_outputs();
            self.outputs = (self.outputs & !clear) | set;
        }
        // The commanded-position masters of geared slaves take this tick's reference first,
        // so that their slaves follow it in the same tick (gear.rs).
        let mut early = self.advance_commanded_masters(ts);
        // Geared slaves follow their masters (gear.rs).
        let synced = self.gear_tick(ts);
        // Handwheels drive their axes from the auxiliary encoders just sensed (handwheel.rs).
        self.handwheel_tick();
        // PT/PVT streams drive their axes (pvt.rs).
        let streamed = self.pvt_tick();
        // Digital inputs, compare and probes on the motion just sensed (io.rs).
        self.io.tick(
            self.tick,
            encoders,
            &self.safety.inputs().index,
            &self.axes[..self.num_axes],
        );
        // Layout 1.11: the analog inputs, and the PSO on its group's speed of this tick, gated
        // by the outputs the path just set (analog.rs).
        let members = match self.analog.pso() {
            Some(p) => self.groups[p.group]
                .config
                .map_or(([0; MAX_AXES], 0), |c| (c.axes, c.naxes)),
            None => ([0; MAX_AXES], 0),
        };
        self.analog.tick(
            self.tick,
            &self.axes[..self.num_axes],
            &members.0[..members.1],
            self.outputs,
        );
        // Layout 1.9: a capture of a probe armed with MC_PROBE_HALT halts its axis's motion.
        let (halts, seq) = self.io.halts();
        if halts != 0 {
            self.halt_motion(
                seq,
                halts,
                firmware_proto::StopReason::Probe,
                firmware_proto::Opcode::ProbeArm,
            );
        }
        // Homing methods look at this tick's inputs and drive their axes (homing.rs).
        let homed = self.homing_tick(ts);
        // Gantries: the slaves follow their masters' references of this tick (gantry.rs).
        let follow = self.gantry_tick(ts, &mut early, &homed, dac);
        // Groups home their axes stage by stage (group_home.rs).
        if self.groups.iter().any(|g| g.homing().is_some()) {
            self.group_home_tick(&homed);
        }
        // Layout 1.12: the sweep's sine of this tick on its axis (freq.rs).
        if let Some(sw) = &mut self.sweep {
            let inj = sw.injection();
            self.axes[sw.axis].set_injection(inj);
        }
        // The reports with something to tell, in axis order (most ticks: none).
        let mut reports: heapless::Vec<(usize, TickReport), MAX_AXES> = heapless::Vec::new();
        let mut report = TickReport::default();
        let tables = self.comp.as_ref();
        for (i, axis) in self.axes[..self.num_axes].iter_mut().enumerate() {
            let comp = tables.and_then(|t| t.table(i));
            let powered = match early.get_mut(i).and_then(Option::take) {
                Some((powered, r)) => {
                    report = r;
                    powered
                }
                None => axis.reference_into(ts, &mut report),
            };
            dac[i] = if powered {
                if let Some(r) = follow.as_ref().and_then(|f| f[i]) {
                    axis.drive(r);
                }
                axis.servo_into(ts, &mut report, comp)
            } else {
                0.0
            };
            if !report.is_empty() {
                // One an axis: never full.
                let _ = reports.push((i, core::mem::take(&mut report)));
            }
        }
        for d in dac[self.num_axes..].iter_mut() {
            *d = 0.0;
        }
        // [safety] nothing moves with nobody in command: the session gate's backstop (safety.rs)
        if !self.safety.in_command() {
            let driven = self.driven_axes();
            self.safety.stop_unattended(
                &self.mem,
                self.tick,
                &mut self.axes[..self.num_axes],
                &driven,
            );
        }
        // [safety] watchdog, e-stop, limits, following error, input faults (safety.rs)
        let evt_ring_ok = self.events.free().is_ok();
        self.safety.tick(
            &self.mem,
            self.tick,
            self.servo_rate_hz,
            &mut self.axes[..self.num_axes],
            encoders,
            dac,
            evt_ring_ok,
        );
        // [safety] a gantry stops as one (gantry.rs)
        self.gantry_trips(dac);
        // [safety] a group stop still running at the maximum stop time: its members lose power
        let max_time = self.safety.config().max_stop_time();
        for g in &mut self.groups {
            if let (Some(elapsed), Some(cfg)) = (g.stop_overdue(max_time), g.config) {
                for &a in &cfg.axes[..cfg.naxes] {
                    if self.axes[a].state == AxisState::SynchronizedMotion {
                        self.safety.stop_overran(
                            &self.mem,
                            self.tick,
                            a,
                            &mut self.axes[a],
                            elapsed,
                        );
                        dac[a] = 0.0;
                    }
                }
            }
        }
        // [safety] a member that tripped stops the rest of its moving group the same way
        for g in &self.groups {
            if let Some(members) = g.moving_members() {
                self.safety.trip_group(
                    &self.mem,
                    self.tick,
                    &mut self.axes[..self.num_axes],
                    members,
                    dac,
                );
            }
        }
        // [safety] layout 1.11: so does a member of a homing group (group_home.rs)
        for g in &self.groups {
            if let (Some(_), Some(cfg)) = (g.homing(), g.config.as_ref()) {
                self.safety.trip_group(
                    &self.mem,
                    self.tick,
                    &mut self.axes[..self.num_axes],
                    &cfg.axes[..cfg.naxes],
                    dac,
                );
            }
        }
        // Layout 1.12: the sweep measures what went out (freq.rs).
        if self.sweep.is_some() {
            self.sweep_tick(dac);
        }
        // The status first, then the events about it: a host that takes motion done (or a
        // state change) and then reads the status sees this tick's, never the one before.
        self.publish();
        // The scope samples what was just published (scope.rs).
        let scoped = self.scope_tick();
        self.post_safety_events();
        self.post_outbox();
        self.post_scope_events(&scoped);
        if let Some(e) = self.sweep_event.take() {
            self.post(e);
        }
        for i in 0..self.io.events_len() {
            if let Some(e) = self.io.event(i) {
                self.post(e);
            }
        }
        for i in 0..self.analog.events_len() {
            if let Some(e) = self.analog.event(i) {
                self.post(e);
            }
        }
        self.post_sync_events(&synced);
        self.post_pvt_events(&streamed);
        match &homed {
            None => {
                for (i, report) in &reports {
                    self.post_axis_events(*i, report, &HomingReport::default());
                }
            }
            Some(homed) => {
                let none = TickReport::default();
                let mut reports = reports.iter().peekable();
                for (i, h) in homed[..self.num_axes].iter().enumerate() {
                    let report = reports.next_if(|(j, _)| *j == i).map_or(&none, |(_, r)| r);
                    self.post_axis_events(i, report, h);
                }
            }
        }
    }

    /// The events of axis `i`'s tick, from its report and its homing step's.
    fn post_axis_events(&mut self, i: usize, report: &TickReport, h: &HomingReport) {
        let axis = i as u16;
        let done = h.done.or(report.done);
        if let Some((seq, pos)) = done {
            self.post_axis_event(EventKind::MotionDone, seq, axis, 0, pos);
        }
        for &seq in &report.dropped {
            self.post_axis_event(
                EventKind::MotionAborted,
                seq,
                axis,
                NackCode::Infeasible as i32,
                0.0,
            );
        }
        if let Some((seq, value)) = report.active {
            self.post_axis_event(EventKind::MotionActive, seq, axis, 0, value);
        }
        if let Some((seq, value)) = report.in_velocity {
            self.post_axis_event(EventKind::InVelocity, seq, axis, 0, value);
        }
        if let Some((seq, why, at)) = h.failed {
            self.post_axis_event(EventKind::HomingFailed, seq, axis, why as i32, at);
        }
        // The homing step ran before the servo loop: its state change came first.
        if let Some(old) = h.state_from.or(report.state_from) {
            let e = state_event(axis, old, self.axes[i].state, self.tick);
            self.post(e);
        }
    }

    /// The homing methods' step (homing.rs); `None` when no axis homes (each axis's step
    /// returns at once then, with nothing to report).
    fn homing_tick(&mut self, ts: f64) -> Option<[HomingReport; MAX_AXES]> {
        if !self.homing[..self.num_axes].iter().any(Homing::active) {
            return None;
        }
        Some(self.homing_step(ts))
    }

    /// Some axis homes.
    #[inline(never)]
    fn homing_step(&mut self, ts: f64) -> [HomingReport; MAX_AXES] {
        let inputs = *self.safety.inputs();
        let max_stop_time = self.safety.config().max_stop_time();
        let mut homed = [HomingReport::default(); MAX_AXES];
        for (i, (axis, homing)) in self.axes[..self.num_axes]
            .iter_mut()
            .zip(self.homing.iter_mut())
            .enumerate()
        {
            let inp = HomingInputs {
                io: inputs.axis[i],
                index: inputs.index[i],
                ts,
                rate_hz: self.servo_rate_hz,
                max_stop_time,
            };
            homed[i] = homing.tick(axis, &inp);
        }
        homed
    }

    /// The axes something drives on: a goal of their own (a move, velocity mode, jog), a
    /// homing method, a coupling or PT/PVT stream, or a group moving and not stopping. An axis
    /// on a stop ramp (a halt, stop or safety stop), settling or at rest is not driven.
    fn driven_axes(&self) -> [bool; MAX_AXES] {
        let mut driven = [false; MAX_AXES];
        for (i, (d, axis)) in driven
            .iter_mut()
            .zip(&self.axes[..self.num_axes])
            .enumerate()
        {
            *d = match axis.state {
                AxisState::Homing => true,
                AxisState::DiscreteMotion | AxisState::ContinuousMotion => axis.has_goal(),
                AxisState::SynchronizedMotion => {
                    self.gears[i].engaged()
                        || self.handwheel_drives(i)
                        || self.pvt[i].as_ref().is_some_and(|s| s.running())
                        || self.groups.iter().any(|g| {
                            g.moving_members().is_some_and(|m| m.contains(&i)) && !g.stopping()
                        })
                }
                _ => false,
            };
        }
        driven
    }

    /// Publish the tick counter, the loss counters and every axis's status.
    fn publish(&mut self) {
        self.publish_identity();
        self.mem.write64(layout::TICK, self.tick);
        // Layout 1.4: this card's refused accesses to the window (release builds; a debug
        // build panics on the access).
        self.mem
            .write32(layout::BAD_ACCESSES, self.mem.bad_accesses());
        for i in 0..self.num_axes {
            let ax = &self.axes[i];
            let mut st = ax.status(self.tick);
            if ax.is_modulo() {
                ax.wrap_status(&mut st);
            }
            seqlock::write_axis_status(&self.mem, i, &st);
        }
        for (g, (group, block)) in self.groups.iter().zip(&mut self.group_blocks).enumerate() {
            block.publish(&self.mem, g, &group.status(self.tick), self.tick);
        }
        self.mem.write32(layout::OUTPUTS, self.outputs());
        self.io.publish(&self.mem, self.tick);
        self.analog.publish(&self.mem, self.tick);
        self.publish_sync();
        self.publish_gantries();
        self.publish_card_info();
    }

    /// The digital outputs (bit i = output i): the host's and the path's, the compare
    /// channels' pulses, and the PSO's PWM while its duty is above 0.
    pub fn outputs(&self) -> u32 {
        self.outputs | self.io.pulse_outputs() | self.analog.pwm_outputs()
    }
}

/// Layout 1.8: the scope's commands, sampling and events.
impl<M: Mem + Clone> Firmware<M> {
    /// Take this tick's sample if the scope wants one; what it did.
    fn scope_tick(&mut self) -> scope::SampleReport {
        let tick = self.tick;
        let Some(sc) = self.scope.as_mut() else {
            return Default::default();
        };
        if !sc.samples_at(tick) {
            return Default::default();
        }
        let mut s = firmware_proto::ScopeSample {
            tick,
            ..Default::default()
        };
        let (inputs, inputs_raw) = self.io.inputs();
        let outputs = self.outputs | self.io.pulse_outputs() | self.analog.pwm_outputs();
        let analog = &self.analog;
        let sweep = self.sweep.as_ref();
        let swept = |i: usize, hz: bool| match sweep {
            Some(s) if s.axis == i => freq::signal(s, hz),
            _ => 0.0,
        };
        let mut axis_cache: [Option<firmware_proto::AxisStatus>; MAX_AXES] = [None; MAX_AXES];
        let mut group_cache: [Option<firmware_proto::GroupStatus>; MAX_GROUPS] = [None; MAX_GROUPS];
        for (v, src) in s.value.iter_mut().zip(sc.sources()) {
            let i = (src.index as usize).min(MAX_AXES - 1);
            let g = (src.index as usize).min(MAX_GROUPS - 1);
            let axes = &self.axes;
            // The status as published: a modulo axis's positions wrapped (layout 1.10).
            let mut ax = || {
                *axis_cache[i].get_or_insert_with(|| {
                    let mut st = axes[i].status(tick);
                    if axes[i].is_modulo() {
                        axes[i].wrap_status(&mut st);
                    }
                    st
                })
            };
            let groups = &self.groups;
            let mut gr = || *group_cache[g].get_or_insert_with(|| groups[g].status(tick));
            *v = match src.signal {
                Signal::CmdPos => ax().cmd_pos,
                Signal::CmdVel => ax().cmd_vel,
                Signal::CmdAcc => ax().cmd_acc,
                Signal::ActPos => ax().act_pos,
                Signal::ActVel => ax().act_vel,
                Signal::Ferr => ax().ferr,
                Signal::Dac => ax().dac_v,
                Signal::URequest => ax().u_request,
                Signal::Encoder => ax().encoder as f64,
                Signal::ServoP => self.axes[i].servo_terms().p,
                Signal::ServoI => self.axes[i].servo_terms().i,
                Signal::ServoD => self.axes[i].servo_terms().d,
                Signal::ServoFf => self.axes[i].servo_terms().ff,
                Signal::GantrySkew => gantry::skew_of(&self.gantries, i),
                Signal::CompPos => ax().comp_pos,
                Signal::FilterIn => self.axes[i].law_output(),
                Signal::FilterOut => ax().u_request,
                Signal::ServoFriction => self.axes[i].friction_term(),
                Signal::FreqInject => swept(i, false),
                Signal::FreqHz => swept(i, true),
                Signal::PathSpeed => gr().feed,
                Signal::PathAcc => gr().feed_acc,
                Signal::PathPos => gr().path_pos,
                Signal::Inputs => inputs as f64,
                Signal::Outputs => outputs as f64,
                Signal::InputsRaw => inputs_raw as f64,
                Signal::Ain0 => analog.input(0),
                Signal::Ain1 => analog.input(1),
                Signal::Ain2 => analog.input(2),
                Signal::Ain3 => analog.input(3),
                Signal::Ain4 => analog.input(4),
                Signal::Ain5 => analog.input(5),
                Signal::Ain6 => analog.input(6),
                Signal::Ain7 => analog.input(7),
                Signal::Aout0 => analog.output(0),
                Signal::Aout1 => analog.output(1),
                Signal::Aout2 => analog.output(2),
                Signal::Aout3 => analog.output(3),
                Signal::Pso => analog.pso_tick().value,
            };
        }
        let faults = if sc.wants_faults() {
            self.axes[..self.num_axes]
                .iter()
                .fold(0, |f, a| f | a.status(tick).faults)
                & !0xFF
        } else {
            0
        };
        let ring = &mut self.scope_ring;
        let report = sc.on_sample(&s, inputs, faults, &mut |x| ring.push(x).is_ok());
        layout::SCOPE_STATUS.write(&self.mem, &sc.status());
        report
    }

    fn post_scope_events(&mut self, r: &scope::SampleReport) {
        let Some(seq) = self.scope.as_ref().map(|s| s.arm_seq()) else {
            return;
        };
        let codes = [
            (ScopeEvent::Triggered, r.triggered),
            (ScopeEvent::Lost, r.lost),
            (ScopeEvent::Done, r.done),
        ];
        for (code, value) in codes {
            if let Some(v) = value {
                self.post_axis_event(EventKind::Scope, seq, 0, code as i32, v as f64);
            }
        }
    }
}

fn state_event(axis: u16, old: AxisState, new: AxisState, tick: u64) -> Event {
    Event {
        seq: 0,
        kind: EventKind::StateChanged as u16,
        axis,
        code: new as i32,
        tick,
        value: old as u32 as f64,
    }
}

/// The second entry a command of two entries takes with it, if `op` is the first.
fn second_entry(op: u16) -> Option<firmware_proto::Opcode> {
    use firmware_proto::Opcode as O;
    match op {
        x if x == O::GroupMoveCircularNormal as u16 => Some(O::GroupCircularPlane),
        x if x == O::PathLine as u16 || x == O::PathArc as u16 => Some(O::PathMore),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::motion::scurve::Limits;
    use firmware_proto::mem::HeapWindow;
    use firmware_proto::Opcode;
    use std::sync::Arc;

    fn boot() -> (Arc<HeapWindow>, Firmware<Arc<HeapWindow>>) {
        let w = Arc::new(HeapWindow::new());
        let fw = Firmware::boot(w.clone(), 2, 10_000);
        (w, fw)
    }

    fn tick(fw: &mut Firmware<Arc<HeapWindow>>) {
        fw.tick(&[0; MAX_AXES], &mut [0.0; MAX_AXES]);
    }

    /// Release builds: accesses out of range or misaligned through the card's window handle
    /// are counted, and the count is in the card control block after the next tick.
    #[test]
    #[cfg(not(debug_assertions))]
    fn bad_window_accesses_are_published() {
        let (w, mut fw) = boot();
        tick(&mut fw);
        assert_eq!(w.read32(layout::BAD_ACCESSES), 0);
        assert_eq!(w.read32(firmware_proto::DPRAM_SIZE), 0); // out of range
        w.write64(layout::BAD_ACCESSES, 1); // misaligned (148 is not 8-aligned)
        w.read64(firmware_proto::DPRAM_SIZE - 4); // straddles the end
        tick(&mut fw);
        assert_eq!(w.read32(layout::BAD_ACCESSES), 3);
        assert_eq!(
            w.read32(layout::BAD_ACCESSES + 4),
            0,
            "the bad store touched nothing"
        );
    }

    fn marker(n: u32) -> Event {
        Event {
            seq: n,
            kind: EventKind::StateChanged as u16,
            axis: 0,
            code: 0,
            tick: 0,
            value: 0.0,
        }
    }

    /// The host's view of the event ring: every event waiting.
    fn drain(w: &Arc<HeapWindow>) -> Vec<Event> {
        let mut rx = firmware_proto::ring::EvtConsumer::attach(w.clone(), EVT_RING);
        let mut out = Vec::new();
        while let Ok(Some(e)) = rx.pop::<Event>() {
            out.push(e);
        }
        out
    }

    /// More events than the outbox holds, raised before the firmware posts them: the first
    /// `CAP` reach the event ring in order, the rest are counted in `card.outbox_lost`.
    #[test]
    fn outbox_overflow_is_counted_in_the_window() {
        let (w, mut fw) = boot();
        tick(&mut fw);
        drain(&w);
        assert_eq!(w.read32(layout::OUTBOX_LOST), 0);
        let n = Outbox::CAP as u32 + 3;
        for k in 0..n {
            fw.outbox.push(marker(1000 + k));
        }
        assert_eq!(fw.outbox.len(), Outbox::CAP);
        tick(&mut fw);
        assert_eq!(w.read32(layout::OUTBOX_LOST), 3);
        assert_eq!(w.read32(layout::EVENTS_LOST), 0);
        let seqs: Vec<u32> = drain(&w)
            .iter()
            .map(|e| e.seq)
            .filter(|&s| s >= 1000)
            .collect();
        assert_eq!(seqs, (1000..1000 + Outbox::CAP as u32).collect::<Vec<_>>());
        // The count is cumulative; a tick with room loses nothing more.
        fw.outbox.push(marker(1));
        tick(&mut fw);
        assert_eq!(w.read32(layout::OUTBOX_LOST), 3);
    }

    /// The same for the safety layer's event buffer: counted in `card.safety_events_lost`.
    #[test]
    fn safety_event_overflow_is_counted_in_the_window() {
        use super::outbox::SafetyEvents;
        let (w, mut fw) = boot();
        tick(&mut fw);
        drain(&w);
        assert_eq!(w.read32(layout::SAFETY_EVENTS_LOST), 0);
        let n = SafetyEvents::CAP as u32 + 5;
        for k in 0..n {
            fw.safety.events.push(marker(1000 + k));
        }
        assert_eq!(fw.safety.events.len(), SafetyEvents::CAP);
        tick(&mut fw);
        assert_eq!(w.read32(layout::SAFETY_EVENTS_LOST), 5);
        assert_eq!(w.read32(layout::EVENTS_LOST), 0);
        let seqs: Vec<u32> = drain(&w)
            .iter()
            .map(|e| e.seq)
            .filter(|&s| s >= 1000)
            .collect();
        assert_eq!(
            seqs,
            (1000..1000 + SafetyEvents::CAP as u32).collect::<Vec<_>>()
        );
    }

    /// A host that never takes events: the card stops taking commands once an ack and
    /// [`EVENT_RESERVE`] more events might not fit (no ack is lost), and the asynchronous
    /// events that then find the ring full are counted in `card.events_lost`.
    #[test]
    fn event_ring_overflow_is_counted_in_the_window() {
        let (w, mut fw) = boot();
        let mut tx = firmware_proto::ring::CmdProducer::attach(w.clone(), CMD_RING);
        let mut seq = 0;
        loop {
            while tx.free().is_ok_and(|f| f > 0) {
                seq += 1;
                let mut c = Command::new(Opcode::Nop, 0);
                c.seq = seq;
                tx.push(&c).unwrap();
            }
            if fw.serve_commands() == 0 {
                break;
            }
        }
        let accepted = w.read32(layout::CMDS_ACCEPTED);
        assert_eq!(accepted, EVT_RING.len - EVENT_RESERVE, "commands taken");
        assert_eq!(w.read32(layout::EVENTS_LOST), 0);
        // Asynchronous events beyond the reserve.
        for k in 0..EVENT_RESERVE + 7 {
            fw.outbox.push(marker(1000 + k));
        }
        tick(&mut fw);
        assert_eq!(w.read32(layout::EVENTS_LOST), 7);
        assert_eq!(w.read32(layout::OUTBOX_LOST), 0);
        let events = drain(&w);
        assert_eq!(events.len(), EVT_RING.len as usize, "the ring was full");
        let acks = events
            .iter()
            .filter(|e| e.kind == EventKind::Ack as u16)
            .count();
        assert_eq!(acks as u32, accepted, "every command taken was acked");
    }

    fn command(op: Opcode, axis: u16, flags: u32, args: &[f64]) -> Command {
        let mut c = Command::new(op, axis).with_args(args);
        c.flags = flags;
        c
    }

    fn attach(fw: &mut Firmware<Arc<HeapWindow>>, session: u32) {
        let c = command(Opcode::HostAttach, 0, session, &[]);
        assert_eq!(fw.execute(&c), Ok(0.0));
    }

    /// Every opcode with the arguments of a valid command where it matters (a move that could
    /// run, an e-stop of category 1), else zeros.
    fn any_command(op: Opcode) -> Command {
        let args: &[f64] = match op {
            Opcode::MoveAbsolute | Opcode::MoveRelative | Opcode::MoveAdditive => {
                &[1000.0, 1e5, 1e6, 1e6, 1e8, 1e8, 1e8, 1e8]
            }
            Opcode::MoveVelocity => &[1e4, 1e6, 1e6, 1e8],
            Opcode::Jog => &[1e4],
            Opcode::SetOverride => &[1.5],
            Opcode::EStop => &[1.0],
            Opcode::SetOutputs => &[1.0, 1.0],
            _ => &[],
        };
        command(op, 0, 0, args)
    }

    /// The session gate: with no session attached, every opcode the allowlist does not name is
    /// refused with `NoSession` and changes nothing (axis, group and outputs as they were); the
    /// allowlist is exactly the commands that stop, read, observe or stage data. With a session
    /// attached no command meets the gate.
    #[test]
    fn without_a_session_only_the_allowlist_is_taken() {
        use firmware_proto::Opcode as O;
        let allowed: std::collections::HashSet<Opcode> = Opcode::ALL
            .iter()
            .copied()
            .filter(|&op| safety::allowed_without_session(op))
            .collect();
        let want: std::collections::HashSet<Opcode> = [
            O::Nop,
            O::PowerOff,
            O::Halt,
            O::Stop,
            O::GroupStop,
            O::GroupHalt,
            O::GroupDisable,
            O::EStop,
            O::CompareDisarm,
            O::ProbeAbort,
            O::HostAttach,
            O::HostDetach,
            O::ReadConfig,
            O::ProbeArm,
            O::ScopeConfigure,
            O::ScopeArm,
            O::ScopeTrigger,
            O::ScopeStop,
            O::NurbsBegin,
            O::NurbsData,
            O::GroupPtpLimits,
            O::PvtPoints,
            O::CamTable,
            O::CamData,
            // Layout 1.9: the compensation table read back (a read, nothing moves).
            O::CompRead,
            // Layout 1.12: dropping held timed commands (it only stops what would run).
            O::TimedCancel,
        ]
        .into_iter()
        .collect();
        assert_eq!(
            allowed, want,
            "the allowlist changed: name a new opcode here on purpose"
        );
        let (_w, mut fw) = boot();
        let snapshot = |fw: &Firmware<Arc<HeapWindow>>| {
            let t = fw.tick_count();
            (
                fw.axes
                    .iter()
                    .map(|a| a.status(t).to_words())
                    .collect::<Vec<_>>(),
                fw.groups
                    .iter()
                    .map(|g| g.status(t).to_words())
                    .collect::<Vec<_>>(),
                fw.outputs(),
            )
        };
        for &op in Opcode::ALL {
            if op == Opcode::HostAttach {
                continue; // it would begin a session
            }
            let before = snapshot(&fw);
            let r = fw.execute(&any_command(op));
            if safety::allowed_without_session(op) {
                assert_ne!(r, Err(NackCode::NoSession), "{op:?}");
            } else {
                assert_eq!(r, Err(NackCode::NoSession), "{op:?}");
                assert!(
                    before == snapshot(&fw),
                    "{op:?} was refused but changed the card"
                );
            }
        }
        // A session: the gate lets everything through (to the command's own checks).
        let (_w, mut fw) = boot();
        attach(&mut fw, 9);
        for &op in Opcode::ALL {
            let r = fw.execute(&any_command(op));
            assert_ne!(r, Err(NackCode::NoSession), "{op:?}");
        }
        assert_eq!(
            fw.safety.session(),
            9,
            "the detach of another session was refused"
        );
    }

    /// An attach arms the watchdog at once: a host that attaches and never beats trips it
    /// exactly the timeout later (10 kHz: 1,000 ticks), as one that beat and fell silent.
    #[test]
    fn an_attach_arms_the_watchdog() {
        use firmware_proto::layout::safety_status as ss;
        let (w, mut fw) = boot();
        tick(&mut fw);
        assert!(!fw.safety.watchdog_armed());
        attach(&mut fw, 5);
        let at = fw.tick_count();
        assert!(fw.safety.watchdog_armed() && fw.safety.in_command());
        assert_eq!(w.read32(ss::WATCHDOG_ARMED), 1);
        assert_eq!(w.read64(ss::LAST_HEARTBEAT_TICK), at);
        while w.read32(ss::FAULTS) == 0 {
            assert!(fw.tick_count() < at + 2_000, "never tripped");
            tick(&mut fw);
        }
        assert_eq!(w.read64(ss::WATCHDOG_TRIP_TICK) - at, 1_000);
        assert_eq!(w.read64(ss::TRIP_HEARTBEAT_TICK), at);
        // A detach disarms it; beats after it do not arm it again.
        let c = command(Opcode::HostDetach, 0, 5, &[]);
        assert_eq!(fw.execute(&c), Ok(0.0));
        assert!(!fw.safety.watchdog_armed() && !fw.safety.in_command());
        for k in 0..10 {
            w.write32(layout::HEARTBEAT, 100 + k);
            tick(&mut fw);
        }
        assert!(!fw.safety.watchdog_armed());
        assert_eq!(w.read32(ss::WATCHDOG_ARMED), 0);
    }

    /// The backstop: motion found running with nobody in command (started past the gate, as
    /// a hole in it would) is stopped on the next tick, category 1 on the stop ramp, reason
    /// `NoSession`, and its drive is disabled once at rest. With a session it runs on.
    #[test]
    fn motion_with_nobody_in_command_is_stopped_by_the_card() {
        use crate::firmware::axis::MoveKind;
        use firmware_proto::{AxisState, StopCategory, StopReason};
        let lim = Limits::symmetric(1e5, 1e6, 1e8);
        // An ideal plant: each encoder reads its axis's commanded position.
        let tick = |fw: &mut Firmware<Arc<HeapWindow>>| {
            let mut enc = [0i64; MAX_AXES];
            for (e, a) in enc.iter_mut().zip(&fw.axes) {
                *e = a.reference().pos.round() as i64;
            }
            fw.tick(&enc, &mut [0.0; MAX_AXES]);
        };
        let start = |fw: &mut Firmware<Arc<HeapWindow>>| {
            for a in 0..2 {
                fw.axes[a].power(true).unwrap();
            }
            fw.axes[0].start_velocity(11, 5e4, &lim, 10_000).unwrap();
            fw.axes[1]
                .start_move(12, MoveKind::Relative, 1e6, &lim, false, 10_000)
                .unwrap();
        };
        // With a session: it runs.
        let (_w, mut fw) = boot();
        attach(&mut fw, 3);
        start(&mut fw);
        for _ in 0..100 {
            tick(&mut fw);
        }
        assert_eq!(fw.axes[0].state, AxisState::ContinuousMotion);
        assert_eq!(fw.axes[1].state, AxisState::DiscreteMotion);
        // Without one (never attached, or detached): stopped on the first tick.
        let (_w, mut fw) = boot();
        start(&mut fw);
        tick(&mut fw);
        for a in 0..2 {
            let ax = &fw.axes[a];
            assert_eq!(ax.state, AxisState::ErrorStop, "axis {a}");
            assert_eq!(ax.safety.stop_reason, StopReason::NoSession, "axis {a}");
            let stop = ax.safety.stop.expect("a safety stop");
            assert_eq!(stop.category, StopCategory::Cat1, "axis {a}");
            assert!(ax.is_powered(), "axis {a}: a ramp, not a power cut");
        }
        for _ in 0..20_000 {
            tick(&mut fw);
        }
        for a in 0..2 {
            let ax = &fw.axes[a];
            assert_eq!(ax.reference().vel, 0.0, "axis {a}");
            assert!(!ax.is_powered(), "axis {a}: disabled at rest");
            assert!(ax.safety.stop.is_some_and(|s| s.at_rest), "axis {a}");
        }
    }

    /// Debug builds: the same access panics at once.
    #[test]
    #[cfg(debug_assertions)]
    #[should_panic(expected = "DPRAM access out of range or misaligned")]
    fn bad_window_access_panics_in_debug_builds() {
        let (w, _fw) = boot();
        w.write64(layout::BAD_ACCESSES, 1);
    }
}
