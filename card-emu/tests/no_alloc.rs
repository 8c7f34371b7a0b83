//! The servo tick never touches the heap: a counting global allocator (only in this test
//! binary) records every allocation, reallocation and deallocation made on this thread while
//! armed.
//!
//! The first test arms it around the pure per-tick functions of `motion/` and `servo/`. The
//! others drive a whole card — [`Firmware`] with its plant, fault injector and a host on the
//! command and event rings, as the emulator's step does — through every kind of motion and
//! fault, and arm it around each call of [`Firmware::tick`] only. Serving commands is not
//! counted: it may allocate (planning a NURBS curve builds scratch tables, and the first curve
//! in each of a group's slots makes the slot's storage, kept for the card's life), and so may
//! the host and the plant; the configuration read-back (layout 1.8) is the exception, counted
//! around `Firmware::serve_commands` too, since a card serves it while it moves.

use card_emu::firmware::Firmware;
use card_emu::motion::nurbs::{clamped_uniform_knots, split_curve, Nurbs, Point};
use card_emu::motion::nurbs_interp::{InterpConfig, Interpolator};
use card_emu::motion::path_speed::PathSpeedPlanner;
use card_emu::motion::saturation::{AxisSample, SaturationAwareFeed};
use card_emu::plant::faults::{Direction, FaultInjector};
use card_emu::plant::{EndStops, HomeSwitch, Motor, MotorParams, Switches};
use card_emu::presets::{die_bonder_preset, die_bonder_volts};
use card_emu::servo::pdplus::{DriveModelExt, PdPlus};
use firmware_proto::layout;
use firmware_proto::mem::HeapWindow;
use firmware_proto::ring::{CmdProducer, EvtConsumer, CMD_RING, EVT_RING};
use firmware_proto::PvtEvent;
use firmware_proto::{
    move_flags, raw, AxisState, Command, ConfigKind, Event, EventKind, GroupState, Mem, NackCode,
    Opcode, MAX_AXES,
};
use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::sync::Arc;

struct Counting;

thread_local! {
    static ARMED: Cell<bool> = const { Cell::new(false) };
    /// Allocations, reallocations, deallocations while armed.
    static COUNTS: Cell<[usize; 3]> = const { Cell::new([0; 3]) };
}

fn count(i: usize) {
    // `try_with`: the allocator also runs while thread-locals are torn down.
    let _ = ARMED.try_with(|a| {
        if a.get() {
            let _ = COUNTS.try_with(|c| {
                let mut v = c.get();
                v[i] += 1;
                c.set(v);
            });
        }
    });
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        count(0);
        // SAFETY: forwarded unchanged; the caller upholds `alloc`'s contract.
        unsafe { System.alloc(layout) }
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        count(0);
        // SAFETY: as above.
        unsafe { System.alloc_zeroed(layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        count(1);
        // SAFETY: as above.
        unsafe { System.realloc(ptr, layout, new_size) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        count(2);
        // SAFETY: as above.
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

/// Run `f` armed: its result and the (alloc, realloc, dealloc) counts it made.
fn counted<R>(f: impl FnOnce() -> R) -> (R, [usize; 3]) {
    COUNTS.with(|c| c.set([0; 3]));
    ARMED.with(|a| a.set(true));
    let r = f();
    ARMED.with(|a| a.set(false));
    (r, COUNTS.with(|c| c.get()))
}

/// The counter itself sees what it must: a tick that boxed something would fail the tests.
#[test]
fn the_counter_sees_alloc_realloc_and_dealloc() {
    let (_, n) = counted(|| {
        let mut v: Vec<u64> = Vec::with_capacity(1);
        v.extend([1, 2, 3]);
        drop(v);
    });
    assert_eq!(n, [1, 1, 1]);
}

#[test]
fn per_tick_functions_do_not_allocate() {
    let n = 200;
    let ctrl: Vec<f64> = (0..n)
        .flat_map(|i| {
            let t = i as f64 / 8.0;
            [30_000.0 * t.cos(), 20_000.0 * (1.3 * t).sin()]
        })
        .collect();
    let knots = clamped_uniform_knots(n, 4).unwrap();
    let w: Vec<f64> = (0..n).map(|i| 1.0 + 0.5 * ((i % 3) as f64)).collect();
    let curve = Nurbs::new(4, 2, &ctrl, &w, &knots).unwrap();
    let preset = die_bonder_preset();
    let sat = SaturationAwareFeed::new(&preset.axes, preset.ts).unwrap();
    let cfg = InterpConfig {
        feed: 300_000.0,
        ..InterpConfig::default()
    };
    let mut a = Interpolator::new(curve.clone(), cfg).unwrap();
    let mut b = Interpolator::with_actuator_limits(curve.clone(), cfg, &sat, 0.8).unwrap();
    let mut c = Interpolator::new(curve.clone(), cfg).unwrap();
    let mut pd = PdPlus::new(preset.axes[0].gains, preset.ts).unwrap();
    let mut planner = PathSpeedPlanner::new(1e-3, 1e7, 1e10).unwrap();
    let (ticks, heap) = counted(|| {
        let mut n = 0usize;
        let mut theta = Point::zeros();
        let mut w_a = Point::zeros();
        while !(a.is_done() && b.is_done() && c.is_done()) && n < 200_000 {
            let _ = curve.eval(0.37);
            let _ = a.tick();
            let _ = c.advance(250_000.0);
            if let Ok((t, _)) = b.tick_guarded(&sat, &theta, &w_a) {
                // crude "plant": follow the reference with one tick of lag
                w_a = (t.pos - theta) / 1e-3;
                theta = t.pos;
                let _ = pd.update(t.pos[0], t.vel[0], t.acc[0], theta[0]);
                let _ = preset.axes[0].plant.step(1e-3, theta[0], w_a[0], 0.1);
            }
            let st = [AxisSample::default(); 2];
            let _ = sat.limit_feed(1e5, 2e5, &Point::x(), &st);
            let _ = planner.next(1e5, 1e6);
            n += 1;
        }
        n
    });
    println!("{ticks} ticks, (alloc, realloc, dealloc) = {heap:?}");
    assert!(a.is_done() && b.is_done() && c.is_done());
    assert_eq!(heap, [0; 3]);

    // A path of two curves run through their joint: the continuation, the planning over both
    // and the take-over of the step that crosses the joint.
    let pieces = split_curve(4, 2, &ctrl, &w, &knots, 120).unwrap();
    assert_eq!(pieces.len(), 2);
    let mut first = Interpolator::new(pieces[0].clone(), cfg).unwrap();
    let mut second = Interpolator::new(pieces[1].clone(), cfg).unwrap();
    let (handed, heap) = counted(|| {
        let mut n = 0;
        loop {
            let next = first.continuation(&second);
            assert!(next.is_some());
            let t = first.tick_into(next).unwrap();
            n += 1;
            if t.done {
                let t = second.take_over(&first).unwrap();
                assert!(t.feed > 0.0);
                break;
            }
            assert!(n < 200_000);
        }
        while !second.is_done() {
            let _ = second.tick();
        }
        true
    });
    assert!(handed);
    assert_eq!(heap, [0; 3], "heap use across a joint");

    // A curve planned into storage made once: planning only uses scratch tables, and what it
    // keeps is in the storage already.
    let mut slot = Interpolator::with_capacity();
    slot.load(4, 2, &ctrl, &w, &knots, cfg, None).unwrap();
    let (_, heap) = counted(|| {
        while !slot.is_done() {
            let _ = slot.tick();
        }
    });
    assert_eq!(heap, [0; 3], "heap use by a curve in made-once storage");
}

// ---- The whole firmware tick ----

/// A card as the emulator's step runs it: firmware, plant, fault injector, and a host on the
/// rings. Only `Firmware::tick` is counted.
struct Rig {
    window: Arc<HeapWindow>,
    fw: Firmware<Arc<HeapWindow>>,
    cmds: CmdProducer<Arc<HeapWindow>>,
    events: EvtConsumer<Arc<HeapWindow>>,
    motors: [Motor; MAX_AXES],
    faults: FaultInjector,
    dac: [f64; MAX_AXES],
    seq: u32,
    /// Every event the host took, in order.
    log: Vec<Event>,
    ticks: u64,
    /// (alloc, realloc, dealloc) inside `Firmware::tick`, summed.
    heap: [usize; 3],
    /// The host stopped beating (a hung host: the watchdog trips).
    silent: bool,
}

impl Rig {
    /// 8 axes of the default plant at 10 kHz.
    fn new() -> Self {
        Self::with_motors([MotorParams::default_servo(); MAX_AXES], 10_000)
    }

    fn with_motors(motors: [MotorParams; MAX_AXES], rate_hz: u32) -> Self {
        let window = Arc::new(HeapWindow::new());
        let fw = Firmware::boot(window.clone(), MAX_AXES, rate_hz);
        window.write32(layout::IRQ_MASK, u32::MAX);
        let mut rig = Self {
            cmds: CmdProducer::attach(window.clone(), CMD_RING),
            events: EvtConsumer::attach(window.clone(), EVT_RING),
            window,
            fw,
            motors: motors.map(Motor::new),
            faults: FaultInjector::default(),
            dac: [0.0; MAX_AXES],
            seq: 0,
            log: Vec::new(),
            ticks: 0,
            heap: [0; 3],
            silent: false,
        };
        // A host in command: attached (the session gate refuses motion without one), and
        // beating every servo period (`step`).
        rig.ok(Opcode::HostAttach, 0, 1, &[]);
        rig
    }

    fn drain(&mut self) {
        while let Ok(Some(e)) = self.events.pop::<Event>() {
            self.log.push(e);
        }
    }

    /// Send a command and return its reply: Ok (ack) or the nack's code.
    fn send(
        &mut self,
        op: Opcode,
        target: usize,
        flags: u32,
        args: &[f64],
    ) -> Result<(), NackCode> {
        self.seq += 1;
        let mut c = Command::new(op, target as u16).with_args(args);
        c.seq = self.seq;
        c.flags = flags;
        self.cmds.push(&c).expect("command ring full");
        self.fw.serve_commands();
        self.drain();
        let seq = self.seq;
        let reply = self
            .log
            .iter()
            .rev()
            .find(|e| e.seq == seq && matches!(e.kind(), Some(EventKind::Ack | EventKind::Nack)))
            .copied()
            .unwrap_or_else(|| panic!("no reply to {op:?}"));
        match reply.kind() {
            Some(EventKind::Ack) => Ok(()),
            _ => Err(NackCode::from_raw(reply.code).expect("a known nack code")),
        }
    }

    fn ok(&mut self, op: Opcode, target: usize, flags: u32, args: &[f64]) -> u32 {
        let r = self.send(op, target, flags, args);
        assert_eq!(r, Ok(()), "{op:?} {target} {flags:#x} {args:?}");
        self.seq
    }

    /// One servo period: serve, encoders and inputs in, firmware tick (counted), plant.
    fn step(&mut self) {
        if !self.silent {
            let hb = self.window.read32(layout::HEARTBEAT);
            self.window.write32(layout::HEARTBEAT, hb.wrapping_add(1));
        }
        self.fw.serve_commands();
        let mut enc = [0i64; MAX_AXES];
        let inputs = self.faults.sense(&self.motors, &mut enc);
        self.fw.set_inputs(inputs);
        let fw = &mut self.fw;
        let dac = &mut self.dac;
        let ((), heap) = counted(|| fw.tick(&enc, dac));
        for (sum, n) in self.heap.iter_mut().zip(heap) {
            *sum += n;
        }
        let ts = self.fw.ts();
        for (i, (m, u)) in self.motors.iter_mut().zip(self.dac).enumerate() {
            self.faults.step_motor(i, m, u, ts);
        }
        let _ = self.fw.take_irq();
        self.ticks += 1;
        self.drain();
    }

    /// Step until `done` holds (at most `max` ticks); whether it did.
    fn run_until(&mut self, max: u64, done: impl Fn(&Self) -> bool) -> bool {
        for _ in 0..max {
            if done(self) {
                return true;
            }
            self.step();
        }
        done(self)
    }

    fn run(&mut self, n: u64) {
        for _ in 0..n {
            self.step();
        }
    }

    fn axis_state(&self, a: usize) -> AxisState {
        self.fw.axis(a).unwrap().state
    }

    fn group_state(&self, g: usize) -> GroupState {
        self.fw.group(g).unwrap().state
    }

    fn got(&self, kind: EventKind, seq: u32) -> bool {
        self.log
            .iter()
            .any(|e| e.kind() == Some(kind) && e.seq == seq)
    }

    fn power_on(&mut self, axes: impl IntoIterator<Item = usize>) {
        for a in axes {
            self.ok(Opcode::PowerOn, a, 0, &[]);
        }
    }

    /// Configure and enable group `g` over `axes` (tolerance 1 count).
    fn group(&mut self, g: usize, axes: &[u8], accdec: u32, interp: u32) {
        let mut block = raw::mc_group_config {
            naxes: axes.len() as u32,
            accdec,
            interpolator: interp,
            tolerance: 1.0,
            ..Default::default()
        };
        block.axes[..axes.len()].copy_from_slice(axes);
        layout::GROUP_CONFIG.at(g).write(&self.window, &block);
        self.ok(Opcode::GroupConfigure, g, 0, &[]);
        self.ok(Opcode::GroupEnable, g, 0, &[]);
    }

    /// Send a NURBS transfer to group `g`: the reply to its end.
    fn nurbs(
        &mut self,
        g: usize,
        flags: u32,
        curve: &Nurbs,
        motion: [f64; 5],
    ) -> Result<u32, NackCode> {
        let n_ctrl = curve.n_ctrl();
        let mut stream = Vec::new();
        for i in 0..n_ctrl {
            let p = curve.control_point(i).unwrap();
            stream.extend_from_slice(&p.as_slice()[..curve.dim()]);
        }
        stream.extend((0..n_ctrl).map(|i| curve.weight(i).unwrap()));
        stream.extend_from_slice(curve.knots());
        let mut header = vec![
            curve.degree() as f64,
            n_ctrl as f64,
            curve.knots().len() as f64,
        ];
        header.extend_from_slice(&motion);
        self.send(Opcode::NurbsBegin, g, flags, &header)?;
        for (k, chunk) in stream.chunks(firmware_proto::NURBS_DATA_MAX).enumerate() {
            let mut args = vec![
                (k * firmware_proto::NURBS_DATA_MAX) as f64,
                chunk.len() as f64,
            ];
            args.extend_from_slice(chunk);
            self.send(Opcode::NurbsData, g, 0, &args)?;
        }
        self.send(Opcode::NurbsEnd, g, 0, &[]).map(|()| self.seq)
    }

    /// The test's verdict: ticks ran, and none of them touched the heap.
    fn assert_no_heap(&self, what: &str) {
        assert!(self.ticks > 0);
        println!(
            "{what}: {} ticks, (alloc, realloc, dealloc) in Firmware::tick = {:?}",
            self.ticks, self.heap
        );
        assert_eq!(self.heap, [0; 3], "{what}: the tick used the heap");
    }
}

/// Move limits: v, a, d, j1, j3, j5, j7.
const MOVE: [f64; 7] = [2e5, 2e6, 2e6, 1e8, 1e8, 1e8, 1e8];
/// Group move limits: v, a, d, j.
const PATH: [f64; 4] = [1e5, 1e6, 1e6, 1e8];

fn move_args(target: f64) -> Vec<f64> {
    let mut a = vec![target];
    a.extend_from_slice(&MOVE);
    a
}

fn path_args(target: &[f64]) -> Vec<f64> {
    let mut a = PATH.to_vec();
    a.extend_from_slice(target);
    a
}

/// A two-axis curve from (0, 0), `n` control points.
fn curve(n: usize, scale: f64) -> Nurbs {
    let ctrl: Vec<f64> = (0..n)
        .flat_map(|i| {
            let t = i as f64;
            [scale * t, 0.5 * scale * (0.6 * t).sin()]
        })
        .collect();
    let w: Vec<f64> = (0..n).map(|i| 1.0 + 0.25 * ((i % 3) as f64)).collect();
    Nurbs::new(3, 2, &ctrl, &w, &clamped_uniform_knots(n, 3).unwrap()).unwrap()
}

/// The same curve in pieces of at most `max_ctrl` control points (a path).
fn path(n: usize, scale: f64, max_ctrl: usize) -> Vec<Nurbs> {
    let c = curve(n, scale);
    let ctrl: Vec<f64> = (0..n)
        .flat_map(|i| {
            let p = c.control_point(i).unwrap();
            [p[0], p[1]]
        })
        .collect();
    let w: Vec<f64> = (0..n).map(|i| c.weight(i).unwrap()).collect();
    split_curve(3, 2, &ctrl, &w, c.knots(), max_ctrl).unwrap()
}

/// feed, accel, jerk, chord tolerance, saturation budget.
const NURBS_MOTION: [f64; 5] = [1.5e5, 2e6, 1e8, 1.0, 0.8];

#[test]
fn single_axis_moves_halts_stops_and_power_off_do_not_touch_the_heap() {
    let mut r = Rig::new();
    r.power_on(0..4);
    // A complete S-curve move.
    let m = r.ok(Opcode::MoveAbsolute, 0, 0, &move_args(50_000.0));
    assert!(r.run_until(20_000, |r| r.got(EventKind::MotionDone, m)));
    assert!((r.fw.axis(0).unwrap().reference().pos - 50_000.0).abs() < 1e-6);
    // Halt, stop (and its release), power off, each mid-move.
    for a in 1..4 {
        r.ok(Opcode::MoveAbsolute, a, 0, &move_args(-80_000.0));
    }
    r.run(1_000);
    assert_eq!(r.axis_state(1), AxisState::DiscreteMotion);
    let h = r.ok(Opcode::Halt, 1, 0, &[2e6, 1e8]);
    let s = r.ok(Opcode::Stop, 2, 0, &[2e6, 1e8]);
    r.ok(Opcode::PowerOff, 3, 0, &[]);
    assert!(r.run_until(20_000, |r| r.got(EventKind::MotionDone, h)));
    assert!(r.run_until(20_000, |r| r.got(EventKind::MotionDone, s)));
    assert_eq!(r.axis_state(2), AxisState::Stopping);
    r.ok(Opcode::StopRelease, 2, 0, &[]);
    r.run(100);
    assert_eq!(r.axis_state(2), AxisState::Standstill);
    assert_eq!(r.axis_state(3), AxisState::Disabled);
    r.assert_no_heap("single axis");
}

#[test]
fn group_paths_and_every_filter_kind_do_not_touch_the_heap() {
    let mut r = Rig::new();
    // Rapid: none on the reference-word group's axes; bell, linear, exponential elsewhere.
    for a in 5..7 {
        let at = layout::AXIS_FILTER.at(a);
        let mut f = at.read(&r.window);
        f.kind[0] = raw::MC_FILTER_NONE;
        at.write(&r.window, &f);
        r.ok(Opcode::ApplyAxisFilter, a, 0, &[]);
    }
    r.power_on(0..7);
    let (pre, post) = (raw::MC_ACCDEC_PRE, raw::MC_ACCDEC_POST);
    r.group(0, &[0, 1], pre, raw::MC_INTERP_EXACT);
    r.group(1, &[2, 3, 4], pre | post, raw::MC_INTERP_EXACT);
    r.group(2, &[5, 6], post, raw::MC_INTERP_REFERENCE_WORD);
    let buf = move_flags::BUFFERED;
    let by_centre = raw::MC_CIRC_BY_CENTRE << move_flags::CIRC_MODE_SHIFT;
    let xy = raw::MC_PLANE_XY << move_flags::PLANE_SHIFT;
    let ccw = move_flags::CIRC_CCW;
    let ft = |f: u32| f << move_flags::FEED_TYPE_SHIFT;
    // Group 0: line, arc by its centre, synchronised point-to-point.
    r.ok(
        Opcode::GroupMoveLinear,
        0,
        0,
        &path_args(&[20_000.0, 10_000.0]),
    );
    let mut arc = path_args(&[20_000.0, 30_000.0, 20_000.0, 20_000.0]);
    arc.truncate(8);
    r.ok(
        Opcode::GroupMoveCircular,
        0,
        buf | by_centre | xy | ccw,
        &arc,
    );
    let ptp0 = r.ok(Opcode::GroupMovePtp, 0, buf, &path_args(&[0.0, -5_000.0]));
    // Group 1: a helix (rapid: bell), then lines at the cutting (linear) and jog
    // (exponential) feed types.
    let helix = path_args(&[10_000.0, 10_000.0, 10_000.0, 0.0, 7_000.0]);
    r.ok(
        Opcode::GroupMoveCircular,
        1,
        by_centre | xy | ccw | ft(0),
        &helix,
    );
    r.ok(
        Opcode::GroupMoveLinear,
        1,
        buf | ft(1),
        &path_args(&[0.0, 0.0, 0.0]),
    );
    let jog = r.ok(
        Opcode::GroupMoveLinear,
        1,
        buf | ft(2),
        &path_args(&[-3e3, 4e3, 1e3]),
    );
    // Group 2: Kim's reference-word arc (rapid: no filter).
    let mut rw = path_args(&[20_000.0, 0.0, 10_000.0, 0.0]);
    rw.truncate(8);
    let rw = r.ok(Opcode::GroupMoveCircular, 2, by_centre | xy | ccw, &rw);
    assert_eq!(r.group_state(0), GroupState::Moving);
    let done = |r: &Rig| {
        [ptp0, jog, rw]
            .iter()
            .all(|&s| r.got(EventKind::GroupMotionDone, s))
    };
    assert!(r.run_until(200_000, done));
    r.run(100);
    for g in 0..3 {
        assert_eq!(r.group_state(g), GroupState::Standby, "group {g}");
    }
    let p = r.fw.axis(1).unwrap().reference().pos;
    assert!((p + 5_000.0).abs() < 1e-6, "group 0 ended at y = {p}");
    r.assert_no_heap("group paths");
}

#[test]
fn nurbs_curves_paths_and_their_aborts_do_not_touch_the_heap() {
    let mut r = Rig::new();
    r.power_on(0..4);
    r.group(0, &[0, 1], raw::MC_ACCDEC_PRE, raw::MC_INTERP_EXACT);
    r.group(1, &[2, 3], raw::MC_ACCDEC_PRE, raw::MC_INTERP_EXACT);
    let buf = move_flags::BUFFERED;
    // One curve, run to its end.
    let one = r.nurbs(0, 0, &curve(12, 2_000.0), NURBS_MOTION).unwrap();
    assert!(r.run_until(100_000, |r| r.got(EventKind::GroupMotionDone, one)));
    r.run(200);
    assert_eq!(r.group_state(0), GroupState::Standby);
    // A path of queued curves run through their joints; then it runs dry: the next piece
    // comes only once the group has stopped at the end of the last one.
    let (x0, y0) = (
        r.fw.axis(0).unwrap().reference().pos,
        r.fw.axis(1).unwrap().reference().pos,
    );
    let shift = |c: &Nurbs| {
        let n = c.n_ctrl();
        let ctrl: Vec<f64> = (0..n)
            .flat_map(|i| {
                let p = c.control_point(i).unwrap();
                [p[0] + x0, p[1] + y0]
            })
            .collect();
        let w: Vec<f64> = (0..n).map(|i| c.weight(i).unwrap()).collect();
        Nurbs::new(c.degree(), 2, &ctrl, &w, c.knots()).unwrap()
    };
    let pieces: Vec<Nurbs> = path(40, 1_500.0, 12).iter().map(shift).collect();
    assert!(pieces.len() >= 4);
    let mut seqs = Vec::new();
    for p in &pieces[..pieces.len() - 1] {
        seqs.push(r.nurbs(0, buf, p, NURBS_MOTION).unwrap());
    }
    let last_queued = *seqs.last().unwrap();
    assert!(r.run_until(200_000, |r| r.got(EventKind::GroupMotionDone, last_queued)));
    assert_eq!(r.group_state(0), GroupState::Standby);
    let dry = r
        .nurbs(0, buf, &pieces[pieces.len() - 1], NURBS_MOTION)
        .unwrap();
    assert!(r.run_until(100_000, |r| r.got(EventKind::GroupMotionDone, dry)));
    // A path halted mid-curve (the halt runs on into the next pieces), and a curve stopped
    // mid-curve on the other group.
    let back: Vec<Nurbs> = path(40, 1_500.0, 12).iter().map(shift).collect();
    let end = |r: &Rig| {
        [
            r.fw.axis(0).unwrap().reference().pos,
            r.fw.axis(1).unwrap().reference().pos,
        ]
    };
    let at = end(&r);
    let offset = |c: &Nurbs, from: [f64; 2], to: [f64; 2]| {
        let n = c.n_ctrl();
        let ctrl: Vec<f64> = (0..n)
            .flat_map(|i| {
                let p = c.control_point(i).unwrap();
                [p[0] - from[0] + to[0], p[1] - from[1] + to[1]]
            })
            .collect();
        let w: Vec<f64> = (0..n).map(|i| c.weight(i).unwrap()).collect();
        Nurbs::new(c.degree(), 2, &ctrl, &w, c.knots()).unwrap()
    };
    let start = back[0].control_point(0).unwrap();
    for p in &back[..4] {
        r.nurbs(0, buf, &offset(p, [start[0], start[1]], at), NURBS_MOTION)
            .unwrap();
    }
    let stopped = r.nurbs(1, 0, &curve(12, 2_000.0), NURBS_MOTION).unwrap();
    r.run(300);
    assert_eq!(r.group_state(0), GroupState::Moving);
    let halt = r.ok(Opcode::GroupHalt, 0, 0, &[1e6, 1e8]);
    let stop = r.ok(Opcode::GroupStop, 1, 0, &[1e6, 1e8]);
    assert!(r.got(EventKind::GroupMotionAborted, stopped));
    assert!(
        r.run_until(100_000, |r| r.got(EventKind::GroupMotionDone, halt)
            && r.got(EventKind::GroupMotionDone, stop))
    );
    r.ok(Opcode::GroupStopRelease, 1, 0, &[]);
    r.run(100);
    assert_eq!(r.group_state(1), GroupState::Standby);
    // A path whose member faults mid-curve: the group drops its curves in the tick.
    let at = end(&r);
    for p in &back[..3] {
        r.nurbs(0, buf, &offset(p, [start[0], start[1]], at), NURBS_MOTION)
            .unwrap();
    }
    r.run(300);
    r.faults.set_alarm(1, true);
    assert!(r.run_until(1_000, |r| r.group_state(0) == GroupState::ErrorStop));
    assert_eq!(r.fw.group(0).unwrap().status(0).queued, 0);
    r.assert_no_heap("NURBS");
}

#[test]
fn saturation_aware_nurbs_does_not_touch_the_heap() {
    let preset = die_bonder_volts();
    let mut motors = [MotorParams::default_servo(); MAX_AXES];
    for (a, m) in motors.iter_mut().enumerate().take(2) {
        let p = preset.axes[a].plant;
        *m = MotorParams::die_bonder(p.kc, p.tau);
    }
    // Yeh's die bonder on the card, as in the paper: 1 kHz.
    let mut r = Rig::with_motors(motors, 1_000);
    for a in 0..2 {
        let m = preset.axes[a];
        let w = &r.window;
        let block = raw::mc_axis_pdplus {
            gains: m.gains,
            drive: m.plant,
            umax: m.umax,
            ..Default::default()
        };
        layout::AXIS_PDPLUS.at(a).write(w, &block);
        let mut cfg = layout::AXIS_CONFIG.at(a).read(w);
        cfg.servo_law = raw::MC_SERVO_PDPLUS;
        layout::AXIS_CONFIG.at(a).write(w, &cfg);
        r.ok(Opcode::ApplyAxisConfig, a, 0, &[]);
    }
    r.power_on(0..2);
    r.group(0, &[0, 1], raw::MC_ACCDEC_PRE, raw::MC_INTERP_EXACT);
    let sat = move_flags::NURBS_SATURATION;
    let fast = [4e5, 2e7, 1e10, 1.0, 0.8];
    let m = r.nurbs(0, sat, &curve(16, 3_000.0), fast).unwrap();
    r.run(20);
    assert_eq!(r.group_state(0), GroupState::Moving);
    assert!(r.run_until(100_000, |r| r.got(EventKind::GroupMotionDone, m)));
    r.assert_no_heap("saturation-aware NURBS");
}

/// Start a group line on [0, 1] and single-axis moves on 2..8, so every fault below catches
/// motion of both kinds.
fn moving(r: &mut Rig) {
    r.power_on(0..MAX_AXES);
    r.group(0, &[0, 1], raw::MC_ACCDEC_PRE, raw::MC_INTERP_EXACT);
    r.ok(
        Opcode::GroupMoveLinear,
        0,
        0,
        &path_args(&[60_000.0, -40_000.0]),
    );
    for a in 2..MAX_AXES {
        r.ok(Opcode::MoveAbsolute, a, 0, &move_args(60_000.0));
    }
    r.run(500);
    assert_eq!(r.group_state(0), GroupState::Moving);
    assert_eq!(r.axis_state(7), AxisState::DiscreteMotion);
}

#[test]
fn faults_do_not_touch_the_heap() {
    type Fault = fn(&mut Rig);
    let faults: [(&str, Fault); 7] = [
        ("hard limit", |r| {
            r.faults.trip_limit(1, Direction::Negative, true)
        }),
        ("soft limit", |r| {
            let at = layout::AXIS_SAFETY.at(0);
            let mut b = at.read(&r.window);
            b.flags = raw::MC_AXSAFE_ALL;
            b.soft_limit_neg = -1e5;
            b.soft_limit_pos = 30_000.0;
            at.write(&r.window, &b);
            r.ok(Opcode::ApplyAxisSafety, 0, 0, &[]);
        }),
        ("following error", |r| r.faults.stall(1, true)),
        ("amplifier alarm", |r| r.faults.set_alarm(0, true)),
        ("encoder loss", |r| {
            let m = r.motors[1];
            r.faults.lose_encoder(1, true, &m);
        }),
        ("e-stop", |r| r.faults.set_estop(true)),
        ("watchdog", |r| {
            // The attach armed it; the host falls silent.
            r.silent = true;
        }),
    ];
    for (what, fault) in faults {
        let mut r = Rig::new();
        // Soft limits hold once the axis is homed: MC_SetPosition where it is.
        r.ok(Opcode::SetPosition, 0, 0, &[0.0]);
        moving(&mut r);
        fault(&mut r);
        let tripped = r.run_until(200_000, |r| r.group_state(0) == GroupState::ErrorStop);
        assert!(tripped, "{what}: the group did not stop in error");
        r.run(5_000);
        assert!(
            (0..MAX_AXES).any(|a| r.axis_state(a) == AxisState::ErrorStop),
            "{what}: no axis in ErrorStop"
        );
        r.assert_no_heap(what);
    }
}

#[test]
fn homing_does_not_touch_the_heap() {
    let mut r = Rig::new();
    r.power_on(0..5);
    let home = |r: &mut Rig, a: usize, method: i32, index_distance: f64| {
        let at = layout::AXIS_HOMING.at(a);
        let mut b = at.read(&r.window);
        b.method = method;
        b.index_distance = index_distance;
        at.write(&r.window, &b);
        r.ok(Opcode::ApplyAxisHoming, a, 0, &[]);
        r.ok(Opcode::Home, a, 0, &[0.0])
    };
    r.ok(Opcode::SetPosition, 0, 0, &[123.0]);
    // A home switch above 3,000.5 counts (method 20: its edge), a hard stop (-3), an index that
    // never comes (34 on a plant without latch pulses: no index), and a search halted.
    r.faults
        .set_switches(1, Switches::default().with_home(HomeSwitch::Above(3_000.5)));
    r.motors[2].end_stops = EndStops {
        neg: -2_000.5,
        pos: f64::INFINITY,
    };
    let switch = home(&mut r, 1, 20, 12_000.0);
    let stop = home(&mut r, 2, -3, 12_000.0);
    let index = home(&mut r, 3, 34, 2_000.0);
    let halted = home(&mut r, 4, 19, 12_000.0);
    r.run(2_000);
    assert_eq!(r.axis_state(4), AxisState::Homing);
    r.ok(Opcode::Halt, 4, 0, &[2e6, 1e8]);
    assert!(r.got(EventKind::MotionAborted, halted));
    assert!(
        r.run_until(200_000, |r| r.got(EventKind::MotionDone, switch)
            && r.got(EventKind::MotionDone, stop)
            && r.got(EventKind::HomingFailed, index))
    );
    r.assert_no_heap("homing");
}

/// The continuous path's engine: pushes (corner blends, smoothing blends and their rebuilds,
/// arcs, NURBS curves, dwells, outputs), ticks, a halt and a clear, all in storage made once.
#[test]
fn continuous_path_push_tick_halt_and_clear_do_not_touch_the_heap() {
    use card_emu::motion::path::{
        BlendSpeed, CurveSegment, Geom, OutputAction, OutputAt, Path, PathLimits, Segment,
        Transition, MAX_AXES,
    };
    let mut curve = Nurbs::with_capacity();
    let lim = PathLimits {
        naxes: 2,
        ts: 1e-4,
        vmax: [1e5; MAX_AXES],
        amax: [1e6; MAX_AXES],
        jmax: [1e8; MAX_AXES],
        accel: 0.0,
        jerk: 0.0,
        // planned every 1 ms, as the card does at 10 kHz (steps followed tick by tick)
        plan_ticks: 10,
    };
    let mut p = Path::with_capacity(4096);
    let mut events = 0usize;
    let (_, heap) = counted(|| {
        p.reset([0.0; MAX_AXES], lim, 256).unwrap();
        let seg = |id: u32, geom: Geom, tr: Transition| Segment {
            id,
            geom,
            feed: 5e4,
            transition: tr,
            blend: BlendSpeed::Low,
            last: false,
        };
        let mut end = [0.0; MAX_AXES];
        // 400 chords of a circle of radius 20,000 (smoothed), then a square corner, an arc,
        // a dwell, an output and a time-shifted chain
        for i in 1..=400u32 {
            let th = i as f64 * 100.0 / 20_000.0;
            end[0] = 20_000.0 * th.sin();
            end[1] = 20_000.0 - 20_000.0 * th.cos();
            p.push(seg(i, Geom::Line { end }, Transition::MaxDeviation(1.0)))
                .unwrap();
        }
        let corner = [end[0], end[1] + 5_000.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0];
        p.push(seg(
            401,
            Geom::Line { end: corner },
            Transition::MaxDeviation(5.0),
        ))
        .unwrap();
        let mut arc_end = corner;
        arc_end[0] += 4_000.0;
        p.push(seg(
            402,
            Geom::Arc {
                u: 0,
                v: 1,
                centre: [corner[0] + 2_000.0, corner[1]],
                ccw: false,
                end: arc_end,
            },
            Transition::CornerDistance(50.0),
        ))
        .unwrap();
        p.push(seg(403, Geom::Dwell { time: 0.01 }, Transition::Exact))
            .unwrap();
        p.push_output(OutputAction {
            bit: 3,
            on: true,
            at: OutputAt::Distance(100.0),
        })
        .unwrap();
        let mut last = arc_end;
        last[1] -= 3_000.0;
        p.push(seg(
            404,
            Geom::Line { end: last },
            Transition::MaxDeviation(5.0),
        ))
        .unwrap();
        // a time-shifted chain, held and resumed in it
        for i in 1..=4u32 {
            last[i as usize % 2] += if i > 2 { -2_000.0 } else { 2_000.0 };
            let mut s = seg(
                404 + i,
                Geom::Line { end: last },
                Transition::TimeShift(50.0),
            );
            s.last = i == 4;
            p.push(s).unwrap();
        }
        while p.current_id().is_some_and(|id| id < 406) {
            p.tick(1.0, &mut |_| events += 1);
        }
        for _ in 0..300 {
            p.tick(0.0, &mut |_| events += 1);
        }
        for _ in 0..2_000_000 {
            p.tick(1.0, &mut |_| events += 1);
            if p.queued() == 0 && !p.is_moving() {
                break;
            }
        }
        assert_eq!(p.queued(), 0);
        // a rational cubic from there, in pieces
        let c0 = p.end();
        let ctrl = [
            c0[0],
            c0[1],
            c0[0] + 3_000.0,
            c0[1],
            c0[0] + 4_000.0,
            c0[1] + 3_000.0,
            c0[0] + 7_000.0,
            c0[1] + 2_000.0,
        ];
        let knots = [0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0];
        curve
            .set(3, 2, &ctrl, &[1.0, 2.0, 1.0, 1.0], &knots)
            .unwrap();
        let pieces = p
            .push_curve(&CurveSegment {
                id: 450,
                curve: &curve,
                feed: 5e4,
                transition: Transition::MaxDeviation(5.0),
                blend: BlendSpeed::Low,
                last: false,
                tolerance: 0.5,
            })
            .unwrap();
        assert!(pieces > 1);
        for _ in 0..2_000_000 {
            p.tick(1.0, &mut |_| events += 1);
            if p.queued() == 0 && !p.is_moving() {
                break;
            }
        }
        let last = p.end();
        // again, halted in the middle and cleared
        for i in 1..=50u32 {
            end[0] = last[0] + i as f64 * 100.0;
            end[1] = last[1] + (i as f64 * 0.3).sin() * 20.0;
            p.push(seg(
                500 + i,
                Geom::Line { end },
                Transition::MaxDeviation(1.0),
            ))
            .unwrap();
        }
        for _ in 0..500 {
            p.tick(1.0, &mut |_| events += 1);
        }
        p.halt(f64::INFINITY, f64::INFINITY);
        while p.is_moving() {
            p.tick(1.0, &mut |_| events += 1);
        }
        p.clear(&mut |_| events += 1).unwrap();
    });
    assert!(events > 800, "{events} events");
    assert_eq!(heap, [0; 3], "heap use by the continuous path");
}

/// Layout 1.7: debounced inputs with edge events, compare series and a streamed table firing
/// (and missing) at speed, touch probes on an input and on the index, in ticks that allocate
/// nothing (the tables were made at boot).
#[test]
fn digital_io_compare_and_probes_do_not_touch_the_heap() {
    use card_emu::firmware::io::DigitalInputs;
    let mut r = Rig::new();
    r.power_on(0..1);
    let mut cfg = raw::mc_io_config {
        rise_events: 0xFFFF,
        fall_events: 0xFFFF,
        ..Default::default()
    };
    cfg.debounce[1] = 3;
    layout::IO_CONFIG.write(&r.window, &cfg);
    r.ok(Opcode::ApplyIoConfig, 0, 0, &[]);
    let series = raw::MC_CMP_MODE_SERIES | raw::MC_CMP_DIR_POS;
    r.ok(
        Opcode::CompareArm,
        0,
        series,
        &[0.0, 0.0, 5.0, 0.0, 100.0, 7.0, 20_000.0],
    );
    let table = raw::MC_CMP_MODE_TABLE | raw::MC_CMP_DIR_POS;
    let mut next = -500.0; // the first ones behind the axis: missed
    let mut push = |r: &mut Rig| {
        let mut args = vec![1.0, 12.0];
        for _ in 0..12 {
            args.push(next);
            next += 53.0;
        }
        r.ok(Opcode::CompareTable, 0, raw::MC_CMP_DIR_POS, &args);
    };
    push(&mut r);
    r.ok(Opcode::CompareArm, 0, table, &[1.0, 1.0, 5.0, 6.0]);
    let probe = raw::MC_PROBE_RISING | raw::MC_PROBE_FALLING | raw::MC_PROBE_CONTINUOUS;
    r.ok(Opcode::ProbeArm, 0, probe, &[0.0, 1.0, 0.0, 0.0]);
    r.ok(Opcode::ProbeArm, 0, probe, &[1.0, 16.0, 0.0, 0.0]);
    r.ok(Opcode::MoveVelocity, 0, 0, &[5e5, 5e6, 5e6, 5e8]);
    for k in 0..3_000u32 {
        let mut pins = DigitalInputs {
            levels: if (k / 7) % 2 == 0 { 0b11 } else { 0 },
            ..DigitalInputs::default()
        };
        pins.edge_at[0] = 0.3;
        r.fw.set_digital_inputs(pins);
        if k % 50 == 0 {
            push(&mut r);
        }
        r.step();
    }
    let fired = r.window.read32(layout::COMPARE_STATUS.at(0).offset() + 8);
    let table_fired = r.window.read32(layout::COMPARE_STATUS.at(1).offset() + 8);
    let missed = r.window.read32(layout::COMPARE_STATUS.at(1).offset() + 12);
    let captures = r.window.read32(layout::PROBE_STATUS.at(0).offset() + 8);
    assert!(
        fired > 1000 && table_fired > 100 && missed > 0,
        "{fired} {table_fired} {missed}"
    );
    assert!(captures > 100, "{captures}"); // (this rig latches no index pulses)
    assert!(r.log.iter().any(|e| e.kind() == Some(EventKind::Input)));
    r.assert_no_heap("digital I/O, compare and probes");
}

/// Layout 1.7 (sync): electronic gearing. GearIn on a commanded master, an actual master and
/// an auxiliary encoder (the catch-up, in gear), GearInPos to its point, GearOut, a halt of a
/// geared slave, and a master lost (disabled): every tick of them without the heap.
#[test]
fn gearing_does_not_touch_the_heap() {
    let mut r = Rig::new();
    r.power_on(0..7);
    let lim = [2e4, 2e5, 2e7];
    let gear = |master: f64, num: f64, den: f64| [master, num, den, lim[0], lim[1], lim[2]];
    r.ok(Opcode::MoveVelocity, 0, 0, &[10_000.0, 2e5, 2e5, 2e7]);
    r.run(2_000);
    let commanded = r.ok(Opcode::GearIn, 1, 0, &gear(0.0, 1.0, 2.0));
    let actual = r.ok(Opcode::GearIn, 2, 1, &gear(0.0, -3.0, 4.0));
    let aux = r.ok(Opcode::GearIn, 3, 2, &gear(1.0, 7.0, 9.0));
    let m = r.fw.axis(0).unwrap().reference().pos;
    let mut args = gear(0.0, 1.0, 1.0).to_vec();
    args.extend([m + 20_000.0, 10_000.0]);
    let pos = r.ok(Opcode::GearInPos, 4, 0, &args);
    let lost = r.ok(Opcode::GearIn, 5, 0, &gear(0.0, 1.0, 1.0));
    let halted = r.ok(Opcode::GearIn, 6, 0, &gear(0.0, 1.0, 1.0));
    assert!(r.run_until(40_000, |r| [commanded, actual, pos]
        .iter()
        .all(|&s| r.got(EventKind::Sync, s))));
    assert!(r.got(EventKind::Sync, aux));
    assert!(r
        .fw
        .axis(1)
        .unwrap()
        .motion_flags()
        .contains(firmware_proto::MotionFlags::IN_SYNC));
    let out = r.ok(Opcode::GearOut, 1, 0, &[]);
    r.ok(Opcode::Halt, 6, 0, &[2e6, 1e8]);
    assert!(r.got(EventKind::MotionAborted, halted));
    assert!(r.run_until(20_000, |r| r.got(EventKind::InVelocity, out)));
    r.ok(Opcode::Halt, 0, 0, &[2e6, 1e8]);
    r.ok(Opcode::PowerOff, 0, 0, &[]);
    assert!(r.run_until(20_000, |r| r.got(EventKind::MotionAborted, lost)));
    assert!(r.run_until(20_000, |r| r.axis_state(5) == AxisState::Standstill));
    r.assert_no_heap("gearing");
}

/// Layout 1.10: the handwheel. Selected from rest, turned beyond the reach and back,
/// reselected, its input handed over, let go, halted: every tick without the heap.
#[test]
fn the_handwheel_does_not_touch_the_heap() {
    let mut r = Rig::new();
    r.power_on(0..2);
    let first = r.ok(Opcode::Handwheel, 0, 0, &[0.0, 100.0, 4.0]);
    let mut m = 0i64;
    let mut turn = |r: &mut Rig, ticks: usize, by: i64| {
        for _ in 0..ticks {
            m += by;
            r.fw.set_aux_encoders([m, 0]);
            r.step();
        }
    };
    turn(&mut r, 3_000, 7);
    turn(&mut r, 1_000, -3);
    r.ok(Opcode::Handwheel, 0, 0, &[0.0, 10.0, 4.0]);
    turn(&mut r, 500, 1);
    r.ok(Opcode::Handwheel, 1, 0, &[0.0, 1.0, 4.0]);
    turn(&mut r, 1_000, 1);
    assert!(r.run_until(20_000, |r| r.got(EventKind::MotionDone, first)));
    r.ok(Opcode::HandwheelOff, 1, 0, &[]);
    let halted = r.ok(Opcode::Handwheel, 1, 0, &[0.0, 100.0, 4.0]);
    turn(&mut r, 500, 5);
    r.ok(Opcode::Halt, 1, 0, &[2e6, 1e8]);
    assert!(r.got(EventKind::MotionAborted, halted));
    assert!(r.run_until(20_000, |r| r.axis_state(1) == AxisState::Standstill));
    r.assert_no_heap("handwheel");
}

/// Layout 1.7 (sync): PT/PVT streams. PVT and PT to their last points, a stream that runs dry,
/// a halted one, and a refill on the low-water event: every tick without the heap (the
/// buffers are made by the first MC_OP_PVT_BEGIN of each axis, in the command manager).
#[test]
fn pvt_streams_do_not_touch_the_heap() {
    let mut r = Rig::new();
    r.power_on(0..4);
    let points = |from: usize, n: usize| -> Vec<f64> {
        let mut a = vec![n as f64];
        for k in from..from + n {
            let t = (k + 1) as f64 * 0.01;
            a.extend([t, 100.0 * (k + 1) as f64, 10_000.0]);
        }
        a
    };
    for a in 0..4 {
        let flags = if a == 1 { firmware_proto::PVT_PT } else { 0 };
        r.ok(Opcode::PvtBegin, a, flags, &[2e4, 1e7, 2.0]);
        r.ok(Opcode::PvtPoints, a, 0, &points(0, 4));
    }
    let mut last = points(4, 1);
    last[3] = 0.0;
    r.ok(Opcode::PvtPoints, 0, firmware_proto::PVT_LAST, &last);
    r.ok(
        Opcode::PvtPoints,
        1,
        firmware_proto::PVT_LAST,
        &points(4, 1),
    );
    let start = r.ok(Opcode::PvtStart, 0, 0, &[15.0]);
    r.run(20);
    r.ok(Opcode::Halt, 3, 0, &[2e6, 1e8]);
    // Low water on axis 2: more points while it runs; then it runs dry.
    assert!(r.run_until(1_000, |r| r.log.iter().any(|e| e.kind()
        == Some(EventKind::Pvt)
        && e.code == PvtEvent::LowWater as i32)));
    r.ok(Opcode::PvtPoints, 2, 0, &points(4, 4));
    assert!(r.run_until(20_000, |r| r.got(EventKind::MotionDone, start)
        && (0..4).all(|a| r.axis_state(a) == AxisState::Standstill)));
    assert!(r
        .log
        .iter()
        .any(|e| e.kind() == Some(EventKind::Pvt) && e.code == PvtEvent::Starved as i32));
    r.assert_no_heap("pvt");
}

/// Layout 1.7 (sync): camming. Periodic cubic and linear tables (built in the command
/// manager), a slave on each, a switch at the end of a cycle, a table that ends, and a cam-out:
/// every tick without the heap.
#[test]
fn camming_does_not_touch_the_heap() {
    let mut r = Rig::new();
    r.power_on(0..4);
    let table = |r: &mut Rig, t: f64, flags: u32, pts: &[(f64, f64)]| {
        r.ok(Opcode::CamTable, 0, flags, &[t, pts.len() as f64]);
        for (k, chunk) in pts.chunks(5).enumerate() {
            let mut a = vec![t, (k * 5) as f64, chunk.len() as f64];
            for &(m, s) in chunk {
                a.extend([m, s]);
            }
            r.ok(Opcode::CamData, 0, 0, &a);
        }
    };
    let wave: Vec<(f64, f64)> = (0..=16)
        .map(|i| {
            let m = i as f64 * 1_000.0;
            (
                m,
                0.5 * m + 300.0 * (m / 16_000.0 * std::f64::consts::TAU).sin(),
            )
        })
        .collect();
    let cubic_periodic = firmware_proto::CAM_CUBIC | firmware_proto::CAM_PERIODIC;
    table(&mut r, 0.0, cubic_periodic, &wave);
    table(&mut r, 1.0, cubic_periodic, &wave);
    table(
        &mut r,
        2.0,
        0,
        &[(0.0, 0.0), (5_000.0, 2_000.0), (8_000.0, 2_500.0)],
    );
    r.ok(Opcode::MoveVelocity, 0, 0, &[10_000.0, 2e5, 2e5, 2e7]);
    r.run(2_000);
    let cam = |t: f64| [0.0, t, 0.0, 0.0, 1.0, 1.0, 2e4, 2e5, 2e7];
    let a = r.ok(Opcode::CamIn, 1, 0, &cam(0.0));
    let b = r.ok(Opcode::CamIn, 2, 0, &cam(2.0));
    let c = r.ok(Opcode::CamIn, 3, 1, &cam(0.0));
    assert!(r.run_until(20_000, |r| [a, b, c]
        .iter()
        .all(|&s| r.got(EventKind::Sync, s))));
    let sw = r.ok(
        Opcode::CamIn,
        1,
        firmware_proto::CAM_AT_CYCLE_END,
        &cam(1.0),
    );
    assert!(r.run_until(40_000, |r| r.got(EventKind::Sync, sw)));
    let out = r.ok(Opcode::CamOut, 3, 0, &[]);
    assert!(r.run_until(20_000, |r| r.got(EventKind::InVelocity, out)));
    r.assert_no_heap("camming");
}

/// Layout 1.8: the scope. 16 channels of every kind of signal, a pre-trigger history, a level
/// trigger during a move, a full ring (nobody drains it) counting lost samples, a one-shot
/// end, a re-arm in continuous mode and a stop: every tick without the heap (the scope and its
/// history are made by the first MC_OP_SCOPE_CONFIGURE, in the command manager).
#[test]
fn the_scope_does_not_touch_the_heap() {
    use firmware_proto::{raw, Signal, Source};
    let mut r = Rig::new();
    r.power_on(0..2);
    let mut c = raw::mc_scope_config {
        n_channels: 16,
        divider: 1,
        mode: raw::MC_SCOPE_ONE_SHOT,
        trigger: raw::MC_SCOPE_TRIG_LEVEL,
        edge: raw::MC_SCOPE_RISING,
        level: 100.0,
        pre_trigger: 1024,
        post_trigger: 6000,
        ..Default::default()
    };
    for (k, s) in c.source.iter_mut().enumerate() {
        let sig = Signal::ALL[k % Signal::ALL.len()];
        let index = match sig.owner() {
            firmware_proto::SignalOwner::Card => 0,
            _ => (k % 2) as u16,
        };
        *s = Source { signal: sig, index }.to_raw();
    }
    layout::SCOPE_CONFIG.write(&*r.window, &c);
    r.ok(Opcode::ScopeConfigure, 0, 0, &[]);
    let arm = r.ok(Opcode::ScopeArm, 0, 0, &[]);
    r.run(2000);
    r.ok(Opcode::MoveAbsolute, 0, 0, &move_args(50_000.0));
    assert!(r.run_until(20_000, |r| r.got(EventKind::Scope, arm)
        && r.log.iter().any(|e| e.kind() == Some(EventKind::Scope)
            && e.code == firmware_proto::ScopeEvent::Done as i32)));
    let st = layout::SCOPE_STATUS.read(&*r.window);
    assert_eq!(st.samples, firmware_proto::SCOPE_RING_LEN as u64);
    assert_eq!(st.samples + st.lost, 1024 + 6000);
    c.mode = raw::MC_SCOPE_CONTINUOUS;
    c.trigger = raw::MC_SCOPE_TRIG_COMMAND;
    layout::SCOPE_CONFIG.write(&*r.window, &c);
    r.ok(Opcode::ScopeConfigure, 0, 0, &[]);
    r.ok(Opcode::ScopeArm, 0, 0, &[]);
    r.run(100);
    r.ok(Opcode::ScopeTrigger, 0, 0, &[]);
    r.run(100);
    r.ok(Opcode::ScopeStop, 0, 0, &[]);
    r.run(10);
    r.assert_no_heap("scope");
}

/// Layout 1.8: `MC_OP_READ_CONFIG` of every block kind and index, served while axes and a
/// group move, touches the heap neither in the command manager nor in the ticks around it.
#[test]
fn the_configuration_read_back_does_not_touch_the_heap() {
    let mut r = Rig::new();
    r.power_on(0..4);
    r.group(0, &[0, 1], raw::MC_ACCDEC_PRE, raw::MC_INTERP_EXACT);
    let mut args = PATH.to_vec();
    args.extend_from_slice(&[40_000.0, 30_000.0]);
    let g = r.ok(Opcode::GroupMoveLinear, 0, 0, &args);
    let m = r.ok(Opcode::MoveAbsolute, 2, 0, &move_args(50_000.0));
    r.run(500);
    assert_eq!(r.axis_state(2), AxisState::DiscreteMotion);
    let mut served = [0usize; 3];
    let mut n = 0;
    for &kind in ConfigKind::ALL {
        let count = if kind.per_axis() {
            MAX_AXES
        } else if kind.per_group() {
            firmware_proto::MAX_GROUPS
        } else {
            1
        };
        for i in 0..count {
            r.seq += 1;
            let mut c =
                Command::new(Opcode::ReadConfig, 0).with_args(&[kind as u32 as f64, i as f64]);
            c.seq = r.seq;
            r.cmds.push(&c).expect("command ring full");
            let fw = &mut r.fw;
            let (_, heap) = counted(|| fw.serve_commands());
            for (sum, k) in served.iter_mut().zip(heap) {
                *sum += k;
            }
            r.drain();
            let seq = r.seq;
            assert!(r.got(EventKind::Ack, seq), "{kind:?} {i}");
            n += 1;
            r.step();
        }
    }
    println!("{n} read-backs, (alloc, realloc, dealloc) in Firmware::serve_commands = {served:?}");
    assert_eq!(served, [0; 3], "the read-back used the heap");
    assert!(r.run_until(20_000, |r| r.got(EventKind::MotionDone, m)));
    assert!(r.run_until(20_000, |r| r.got(EventKind::GroupMotionDone, g)));
    r.assert_no_heap("read-back");
}
