//! The emulated card: firmware + plant + interrupt line, and the clocks that drive it.
//!
//! One [`Emulator::step`] is one servo period: serve the command channel, read the encoders,
//! run the firmware's control loop, hold the DAC outputs over the period while the plant
//! evolves, raise the interrupt. Three clocks drive it:
//! - **stepped**: whoever owns the emulator calls `step` (tests: identical on every machine);
//! - **free-running**: a thread steps as fast as the CPU allows;
//! - **real-time**: a thread steps on absolute deadlines of the servo period
//!   (`clock_nanosleep(TIMER_ABSTIME)`), serving commands between ticks, optionally
//!   busy-polling the command ring instead of sleeping (lowest command latency).
//!
//! Each host that takes the card gets a window and an interrupt line of its own ([`Lessor`]):
//! between two ticks the card moves onto a new memfd holding a copy of its window (mapped over
//! the old one in place, [`MappedWindow::renew`]) and a new eventfd. A past host that kept the
//! old descriptors or mappings writes into memory the card no longer reads, and waits on an
//! eventfd the card no longer raises.

use super::bus::{Bus, BusLink, Wake};
use super::server::{LeaseFds, LeaseSource};
use crate::firmware::safety::IndexLatch;
use crate::firmware::Firmware;
use crate::plant::analog::AnalogBank;
use crate::plant::aux::AuxEncoder;
use crate::plant::faults::FaultInjector;
use crate::plant::io::{encoder_span_from, FireRecord, InputBank};
use crate::plant::leadscrew::Leadscrew;
use crate::plant::{IndexChannel, IndexPulse, Motor, MotorParams, Reading};
use firmware_proto::window::MappedWindow;
use firmware_proto::{AUX_ENCODERS, MAX_AXES};
use nix::sys::eventfd::{EfdFlags, EventFd};
use nix::time::{clock_gettime, clock_nanosleep, ClockId, ClockNanosleepFlags};
use std::os::fd::{AsFd, OwnedFd};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex, MutexGuard, PoisonError};
use std::thread::JoinHandle;
use std::time::Duration;

/// How the card is built.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EmuOptions {
    /// Axes (1..=8).
    pub axes: usize,
    /// Servo rate, Hz (1,000..=20,000).
    pub servo_rate_hz: u32,
    /// The plant of each axis.
    pub motors: [MotorParams; MAX_AXES],
    /// The index channel of each axis's encoder (default: a pulse per motor revolution at
    /// count 0 and its multiples).
    pub index: [IndexPulse; MAX_AXES],
    /// The card's watchdog timeout at boot, µs (until a host sets its own): the firmware's
    /// default (100 ms), or longer on a card set up for debugging a host under gdb or
    /// valgrind (the SDK's `MOTIONCARD_SIM_WATCHDOG_MS`, `card-emu --watchdog-timeout-ms`).
    pub watchdog_timeout_us: u32,
    /// The board's serial number in `card_info` (layout 1.12; 0: none).
    pub serial: u64,
}

impl EmuOptions {
    /// `axes` axes with the default plant at `servo_rate_hz`.
    pub fn new(axes: usize, servo_rate_hz: u32) -> Self {
        Self {
            axes,
            servo_rate_hz,
            ..Self::default()
        }
    }
}

impl Default for EmuOptions {
    fn default() -> Self {
        Self {
            axes: MAX_AXES,
            servo_rate_hz: 10_000,
            motors: [MotorParams::default_servo(); MAX_AXES],
            index: [IndexPulse::default(); MAX_AXES],
            watchdog_timeout_us: crate::firmware::safety::WATCHDOG_TIMEOUT_DEFAULT_US,
            serial: 0,
        }
    }
}

/// What drives the emulator's time.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Clock {
    /// The owner calls [`Emulator::step`].
    Stepped,
    /// A thread steps as fast as it can.
    FreeRunning,
    /// A thread steps on the servo period's absolute deadlines.
    RealTime,
}

impl std::str::FromStr for Clock {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "stepped" => Ok(Clock::Stepped),
            "free" | "free-running" => Ok(Clock::FreeRunning),
            "realtime" | "real-time" => Ok(Clock::RealTime),
            _ => Err(format!(
                "unknown clock '{s}': expected stepped, free-running or realtime"
            )),
        }
    }
}

/// What the card's thread holds while it ticks or serves commands: the interrupt line. A
/// [`Lessor`] takes it between two ticks to move the card onto a new window and line.
struct Gate {
    irq: Mutex<EventFd>,
    /// Lessors waiting for the gate: the card's thread lets them in before it takes the gate
    /// again (a free-running or busy-polling thread would otherwise take it back at once).
    waiting: AtomicUsize,
}

impl Gate {
    fn new() -> std::io::Result<Self> {
        Ok(Self {
            irq: Mutex::new(new_irq()?),
            waiting: AtomicUsize::new(0),
        })
    }

    /// The card's thread, before a tick or a command service.
    #[inline]
    fn enter(&self) -> MutexGuard<'_, EventFd> {
        while self.waiting.load(Ordering::Acquire) != 0 {
            std::thread::yield_now();
        }
        self.irq.lock().unwrap_or_else(PoisonError::into_inner)
    }
}

fn new_irq() -> std::io::Result<EventFd> {
    Ok(EventFd::from_value_and_flags(
        0,
        EfdFlags::EFD_CLOEXEC | EfdFlags::EFD_NONBLOCK,
    )?)
}

/// The card's side of a lease (`card_emu::emu::server`): a window and an interrupt line of
/// its own for each new host. Cloned from [`Emulator::lessor`]; it works whether the card is
/// stepped, driven by a [`Runner`], or not running at all.
#[derive(Clone)]
pub struct Lessor {
    name: String,
    window: Arc<MappedWindow>,
    gate: Arc<Gate>,
}

impl Lessor {
    /// Who the card is (its identity and `card_info`), read from the window it runs on now
    /// without writing there or waiting for the card; `leased`: a host holds it.
    pub fn record(&self, leased: bool) -> firmware_proto::emu_link::CardRecord {
        firmware_proto::emu_link::CardRecord::read(&*self.window, leased)
    }

    /// Move the card onto a new window and interrupt line and return descriptors of both for
    /// the next host (the window's memfd, sealed, and the eventfd).
    ///
    /// Between two ticks (the card's thread waits meanwhile): the window is copied into a new
    /// memfd, which is mapped over the card's mapping in place ([`MappedWindow::renew`]: the
    /// firmware's ring indices, status blocks and everything else carry on as they were), and
    /// the card raises its interrupt on a new eventfd from then on. The old memfd and eventfd
    /// are closed here; a past host that kept them holds memory the card no longer reads and
    /// an eventfd the card no longer raises. On an error nothing changed.
    pub fn renew(&self) -> std::io::Result<(OwnedFd, OwnedFd)> {
        // Made (its memory allocated) before the gate is taken: the card waits only for the
        // copy and the remap.
        let memfd = MappedWindow::memfd(&self.name)?;
        let window = memfd.as_fd().try_clone_to_owned()?;
        let irq = new_irq()?;
        let irq_out = irq.as_fd().try_clone_to_owned()?;
        struct Waiting<'a>(&'a AtomicUsize);
        impl Drop for Waiting<'_> {
            fn drop(&mut self) {
                self.0.fetch_sub(1, Ordering::Release);
            }
        }
        self.gate.waiting.fetch_add(1, Ordering::AcqRel);
        let waiting = Waiting(&self.gate.waiting);
        let mut line = self.gate.irq.lock().unwrap_or_else(PoisonError::into_inner);
        let old_window = self.window.renew(memfd)?;
        let old_irq = std::mem::replace(&mut *line, irq);
        drop(line);
        drop(waiting);
        // Closed with the card running again: freeing the old window's memory takes a while.
        drop((old_window, old_irq));
        Ok((window, irq_out))
    }
}

/// The served card's: a new window and interrupt line for each host ([`Lessor::renew`]).
impl LeaseSource for Lessor {
    fn next_lease(&self) -> std::io::Result<LeaseFds> {
        let (window, irq) = self.renew()?;
        Ok(LeaseFds { window, irq })
    }

    fn record(&self, leased: bool) -> firmware_proto::emu_link::CardRecord {
        self.record(leased)
    }
}

/// The card: firmware, plant, interrupt line.
pub struct Emulator {
    name: String,
    window: Arc<MappedWindow>,
    fw: Box<Firmware<Arc<MappedWindow>>>,
    motors: [Motor; MAX_AXES],
    index: [IndexChannel; MAX_AXES],
    latch: [IndexLatch; MAX_AXES],
    dac: [f64; MAX_AXES],
    gate: Arc<Gate>,
    time: f64,
    faults: FaultInjector,
    /// The digital input pins (layout 1.7).
    inputs: InputBank,
    /// Each shaft's reading at the end of the period just run (the next one starts from it).
    readings: [Reading; MAX_AXES],
    /// The shafts and DAC outputs at the start of the period just run, to replay it.
    period_start: [Motor; MAX_AXES],
    period_dac: [f64; MAX_AXES],
    /// The compare pulses recorded (when recording).
    fires: Option<Vec<FireRecord>>,
    /// Each encoder's lowest and highest count over the period just run.
    spans: [Option<(i64, i64)>; MAX_AXES],
    /// Layout 1.7 (sync): the auxiliary encoders.
    aux: [AuxEncoder; AUX_ENCODERS],
    /// Layout 1.9: each axis's leadscrew between motor and load, if modelled.
    leadscrews: [Option<Leadscrew>; MAX_AXES],
    /// Layout 1.11: what drives the analog input pins.
    analog: AnalogBank,
    /// Layout 1.12: this card's end of a sync bus, if it is on one.
    bus: Option<BusEnd>,
}

/// A card's end of the sync bus.
enum BusEnd {
    /// It drives the bus's clock.
    Master(Arc<Bus>),
    /// It runs on the master's ticks.
    Follower(BusLink),
}

/// The stack the firmware is booted on (see `Emulator::named`).
const BOOT_STACK: usize = 64 << 20;

impl Emulator {
    /// Boot a card in `window`.
    pub fn new(window: Arc<MappedWindow>, opts: &EmuOptions) -> std::io::Result<Self> {
        Self::named("card", window, opts)
    }

    fn named(name: &str, window: Arc<MappedWindow>, opts: &EmuOptions) -> std::io::Result<Self> {
        let gate = Arc::new(Gate::new()?);
        // The firmware's state is large (its queues and stores inline, as on a card): it is
        // built on a thread of its own stack and kept boxed, so that opening cards from a
        // thread of the default 2 MiB stack never overflows it.
        let mut fw = std::thread::scope(|s| {
            std::thread::Builder::new()
                .name("card-emu-boot".into())
                .stack_size(BOOT_STACK)
                .spawn_scoped(s, || {
                    Box::new(Firmware::boot(
                        window.clone(),
                        opts.axes,
                        opts.servo_rate_hz,
                    ))
                })
                .map(|t| t.join())
        })?
        .map_err(|_| std::io::Error::other("the firmware's boot panicked"))?;
        fw.set_boot_watchdog_timeout(opts.watchdog_timeout_us)
            .map_err(|_| std::io::Error::other("a watchdog timeout of 0"))?;
        fw.set_card_name(name, opts.serial);
        Ok(Self {
            name: name.to_string(),
            window,
            fw,
            motors: opts.motors.map(Motor::new),
            readings: opts.motors.map(|p| Motor::new(p).reading()),
            index: core::array::from_fn(|i| {
                IndexChannel::new(opts.index[i], opts.motors[i].counts_per_rev)
            }),
            latch: [IndexLatch::default(); MAX_AXES],
            dac: [0.0; MAX_AXES],
            gate,
            time: 0.0,
            faults: FaultInjector::default(),
            inputs: InputBank::default(),
            period_start: opts.motors.map(Motor::new),
            period_dac: [0.0; MAX_AXES],
            fires: None,
            spans: [None; MAX_AXES],
            aux: [AuxEncoder::default(); AUX_ENCODERS],
            leadscrews: Default::default(),
            analog: AnalogBank::default(),
            bus: None,
        })
    }

    /// A card in a fresh memfd window.
    pub fn create(name: &str, opts: &EmuOptions) -> std::io::Result<Self> {
        Self::named(name, Arc::new(MappedWindow::create(name)?), opts)
    }

    /// Serve the command channel now (between ticks). Returns the commands served.
    pub fn serve(&mut self) -> usize {
        let gate = Arc::clone(&self.gate);
        let irq = gate.enter();
        let n = self.fw.serve_commands();
        self.raise_irq(&irq);
        n
    }

    /// One servo period.
    pub fn step(&mut self) {
        let gate = Arc::clone(&self.gate);
        let irq = gate.enter();
        self.period();
        self.raise_irq(&irq);
    }

    /// One servo period, with the gate held.
    fn period(&mut self) {
        // Layout 1.12: a follower takes the commits the master published before this tick.
        if let Some(BusEnd::Follower(link)) = &mut self.bus {
            let snap = link.read();
            for c in link.take_commits(&snap) {
                self.fw.bus_commit(c);
            }
        }
        self.fw.serve_commands();
        let mut enc = [0i64; MAX_AXES];
        // The shafts' readings at the period's start (the encoder readings below and the
        // period's span take them): the end of the period before's, unless a shaft was moved.
        for (r, m) in self.readings.iter_mut().zip(&self.motors) {
            *r = r.again(m);
        }
        let counts: [i64; MAX_AXES] = core::array::from_fn(|i| self.readings[i].count);
        // [faults] encoders and switch inputs as the card sees them, through injected faults
        let mut inputs = self.faults.sense_counts(&self.readings, &mut enc);
        // The encoder interface's index latch: the pulse comes from the shaft, the count it
        // captures is the counter's (with any corruption injected into the counter).
        for (i, ch) in self.index.iter_mut().enumerate() {
            let f = self.faults.get(i);
            let before = ch.latches;
            ch.sample(counts[i], f.is_none_or(|f| f.encoder_lost.is_none()));
            if ch.latches != before {
                self.latch[i] = IndexLatch {
                    count: ch.count.wrapping_add(f.map_or(0, |f| f.encoder_offset)),
                    latches: ch.latches,
                };
            }
        }
        inputs.index = self.latch;
        self.fw.set_inputs(inputs);
        self.fw.set_digital_inputs(self.inputs.sample(&self.motors));
        self.fw.set_encoder_spans(self.spans);
        self.fw.set_aux_encoders(self.aux.map(|a| a.count));
        self.fw.set_analog_inputs(self.analog.sample(&self.motors));
        let ts = self.fw.ts();
        self.fw.tick(&enc, &mut self.dac);
        self.record_period_fires(ts);
        for a in &mut self.aux {
            a.step(ts);
        }
        // The period's start (the compare pulses above replayed the period before from the
        // old one).
        self.period_start = self.motors;
        let start = &self.period_start;
        for (i, (m, u)) in self.motors.iter_mut().zip(self.dac).enumerate() {
            self.faults.step_motor(i, m, u, ts);
        }
        let (faults, dac) = (&self.faults, self.dac);
        self.inputs
            .after_period(start, &self.motors, ts, |a, m, dt| {
                faults.step_motor(a, m, dac[a], dt)
            });
        // The encoder interface's extreme counts of the period (through the encoder's faults).
        for (i, span) in self.spans.iter_mut().enumerate() {
            // The next period's start reads the same, unless the shaft is moved in between.
            self.readings[i] = self.motors[i].reading();
            let (lost, offset) = faults
                .get(i)
                .map_or((None, 0), |f| (f.encoder_lost, f.encoder_offset));
            *span = Some(match lost {
                Some(frozen) => (frozen, frozen),
                None => {
                    let ends = (counts[i], self.readings[i].count);
                    let (lo, hi) =
                        encoder_span_from(ends, &start[i], &self.motors[i], ts, |m, dt| {
                            faults.step_motor(i, m, dac[i], dt)
                        });
                    (lo.wrapping_add(offset), hi.wrapping_add(offset))
                }
            });
        }
        self.period_dac = dac;
        self.time += ts;
        if let Some(BusEnd::Master(bus)) = &self.bus {
            // Layout 1.12: the tick and its commits to the followers, who then run it.
            bus.publish(self.fw.tick_count(), &self.fw.take_commits());
            self.fw.lead_bus(bus.followers());
        }
        for (ls, m) in self.leadscrews.iter_mut().zip(&self.motors) {
            if let Some(ls) = ls {
                ls.follow(m.load_position_counts());
            }
        }
    }

    /// Drive a sync bus (layout 1.12): this card's ticks become its followers' ([`Bus::join`]
    /// in this process, `bus::serve` for other processes). Refused on a follower.
    pub fn lead_bus(&mut self) -> std::io::Result<Arc<Bus>> {
        match &self.bus {
            Some(BusEnd::Master(b)) => return Ok(b.clone()),
            Some(BusEnd::Follower(l)) => {
                return Err(std::io::Error::other(format!(
                    "this card follows the bus of '{}': it cannot drive one",
                    l.master()
                )))
            }
            None => {}
        }
        let bus = Arc::new(Bus::new(&self.name)?);
        bus.publish(self.fw.tick_count(), &[]);
        self.bus = Some(BusEnd::Master(bus.clone()));
        Ok(bus)
    }

    /// Follow the bus `link` leads to (layout 1.12): this card takes the master's tick count
    /// and from now on runs one tick per master tick (its `Runner` waits for them; a stepped
    /// card is stepped after its master). Only a card at rest that no host commands, and is on
    /// no bus yet, joins.
    pub fn follow_bus(&mut self, link: BusLink) -> std::io::Result<()> {
        if self.bus.is_some() {
            return Err(std::io::Error::other("this card is on a sync bus already"));
        }
        let snap = link.read();
        if !snap.alive {
            return Err(std::io::Error::other(format!(
                "the sync bus of '{}' has ended",
                link.master()
            )));
        }
        let gate = Arc::clone(&self.gate);
        let irq = gate.enter();
        if !self.fw.join_bus(link.master(), snap.tick) {
            return Err(std::io::Error::other(
                "a card that moves or that a host commands cannot join a sync bus",
            ));
        }
        self.raise_irq(&irq);
        self.bus = Some(BusEnd::Follower(link));
        Ok(())
    }

    /// The master of this follower is gone: the firmware halts everything and the card goes
    /// on on its own clock (`Firmware::lose_bus`).
    pub fn lose_bus(&mut self) {
        let gate = Arc::clone(&self.gate);
        let irq = gate.enter();
        self.fw.lose_bus();
        self.raise_irq(&irq);
    }

    /// Does this card follow a bus whose master it has not lost?
    pub fn follows(&self) -> bool {
        matches!(self.bus, Some(BusEnd::Follower(_))) && !self.fw.bus_lost()
    }

    /// The compare pulses the firmware fired in the period just ended: where the shaft was
    /// at each one's instant (the period replayed from its start on a copy).
    fn record_period_fires(&mut self, ts: f64) {
        let Some(rec) = self.fires.as_mut() else {
            return;
        };
        for f in self.fw.io().fires() {
            let a = usize::from(f.axis).min(MAX_AXES - 1);
            let mut m = self.period_start[a];
            let dt = f.frac * ts;
            self.faults.step_motor(a, &mut m, self.period_dac[a], dt);
            rec.push(FireRecord {
                channel: f.channel.into(),
                output: f.output.into(),
                axis: a,
                position: f.position,
                time: self.time - ts + dt,
                shaft: m.position_counts(),
                velocity: m.omega * m.params.counts_per_rad(),
            });
        }
    }

    /// Layout 1.9: put a leadscrew (pitch error, backlash) between axis `axis`'s motor and its
    /// load, or take it away (`None`). The nut starts where the motor is now, mid-band.
    pub fn set_leadscrew(&mut self, axis: usize, screw: Option<Leadscrew>) {
        if let (Some(slot), Some(m)) = (self.leadscrews.get_mut(axis), self.motors.get(axis)) {
            *slot = screw.map(|mut s| {
                s.follow(m.load_position_counts());
                s
            });
        }
    }

    /// Where axis `axis`'s load is, counts of its encoder: past the leadscrew if one is
    /// modelled, else the motor's load position.
    pub fn load_position(&self, axis: usize) -> Option<f64> {
        let m = self.motors.get(axis)?;
        Some(match self.leadscrews.get(axis).and_then(Option::as_ref) {
            Some(s) => s.load(),
            None => m.load_position_counts(),
        })
    }

    /// The digital input pins: levels the test sets, or sensors on an axis's travel.
    pub fn inputs(&mut self) -> &mut InputBank {
        &mut self.inputs
    }

    /// The digital outputs now (bit i = output i), compare pulses included.
    pub fn outputs(&self) -> u32 {
        self.fw.outputs()
    }

    /// Layout 1.11: the analog input pins (what each is wired to, its noise).
    pub fn analog(&mut self) -> &mut AnalogBank {
        &mut self.analog
    }

    /// Layout 1.11: the spare DAC outputs now, V (the PSO's or the host's).
    pub fn analog_outputs(&self) -> [f64; firmware_proto::ANALOG_OUTPUTS] {
        self.fw.analog().outputs()
    }

    /// Layout 1.11: the PSO's PWM, if it runs one: (digital output, duty 0..1 of the tick just
    /// run, frequency Hz).
    pub fn pwm(&self) -> Option<(usize, f64, f64)> {
        self.fw.analog().pwm()
    }

    /// Record the compare pulses from now on (`false`: stop, and drop what was recorded).
    pub fn record_fires(&mut self, on: bool) {
        self.fires = on.then(Vec::new);
    }

    /// The compare pulses recorded since the last call.
    pub fn take_fires(&mut self) -> Vec<FireRecord> {
        self.fires.as_mut().map(std::mem::take).unwrap_or_default()
    }

    /// `n` servo periods.
    pub fn step_n(&mut self, n: u64) {
        for _ in 0..n {
            self.step();
        }
    }

    fn raise_irq(&mut self, irq: &EventFd) {
        if self.fw.take_irq() {
            // A full counter (2^64 − 2 unread interrupts) cannot happen; nothing else fails.
            let _ = irq.write(1);
        }
    }

    /// Emulated time since boot, s.
    pub fn time(&self) -> f64 {
        self.time
    }

    /// The interrupt line now: a new descriptor of the eventfd that becomes readable when the
    /// card raises an interrupt (until a [`Lessor`] gives the card a new one).
    pub fn irq_fd(&self) -> std::io::Result<OwnedFd> {
        let irq = self.gate.irq.lock().unwrap_or_else(PoisonError::into_inner);
        irq.as_fd().try_clone_to_owned()
    }

    /// The DPRAM window. Its addresses stay the card's when a [`Lessor`] renews it; in-process
    /// writers (tests) do not race a renewal.
    pub fn window(&self) -> &Arc<MappedWindow> {
        &self.window
    }

    /// What a server hands each new host: a window and an interrupt line of its own.
    pub fn lessor(&self) -> Lessor {
        Lessor {
            name: self.name.clone(),
            window: self.window.clone(),
            gate: self.gate.clone(),
        }
    }

    /// The firmware.
    pub fn firmware(&self) -> &Firmware<Arc<MappedWindow>> {
        &self.fw
    }

    /// An axis's plant, to inspect or to inject faults and disturbances.
    pub fn motor_mut(&mut self, axis: usize) -> Option<&mut Motor> {
        self.motors.get_mut(axis)
    }

    /// An axis's plant.
    pub fn motor(&self, axis: usize) -> Option<&Motor> {
        self.motors.get(axis)
    }

    /// An auxiliary encoder (layout 1.7): set its velocity or jump it.
    pub fn aux_mut(&mut self, k: usize) -> Option<&mut AuxEncoder> {
        self.aux.get_mut(k)
    }

    /// An axis's encoder index channel and its latch.
    pub fn index_channel(&self, axis: usize) -> Option<&IndexChannel> {
        self.index.get(axis)
    }

    /// The fault injector: switches, alarms, encoder faults, actuator faults, e-stop input.
    pub fn faults(&mut self) -> &mut FaultInjector {
        &mut self.faults
    }

    /// Lose (or restore) the encoder signal of `axis`: the count freezes where it is now.
    pub fn lose_encoder(&mut self, axis: usize, lost: bool) {
        if let Some(m) = self.motors.get(axis) {
            let m = *m;
            self.faults.lose_encoder(axis, lost, &m);
        }
    }
}

/// A thread driving an emulator on a free-running or real-time clock.
pub struct Runner {
    stop: Arc<AtomicBool>,
    thread: Option<JoinHandle<Emulator>>,
}

impl Runner {
    /// Start driving `emu`. `busy_poll` keeps serving the command ring between real-time ticks
    /// instead of sleeping.
    pub fn spawn(mut emu: Emulator, clock: Clock, busy_poll: bool) -> std::io::Result<Self> {
        let stop = Arc::new(AtomicBool::new(false));
        let flag = stop.clone();
        let thread = std::thread::Builder::new()
            .name("card-emu".into())
            .spawn(move || {
                match clock {
                    Clock::Stepped => {}
                    // Layout 1.12: a follower's ticks are the master's, whatever its clock.
                    _ if emu.follows() => run_follower(&mut emu, &flag, busy_poll),
                    Clock::FreeRunning => {
                        while !flag.load(Ordering::Relaxed) {
                            emu.step();
                        }
                    }
                    Clock::RealTime => run_realtime(&mut emu, &flag, busy_poll),
                }
                emu
            })?;
        Ok(Self {
            stop,
            thread: Some(thread),
        })
    }

    /// Stop the thread and take the emulator back.
    pub fn stop(mut self) -> Option<Emulator> {
        self.halt()
    }

    fn halt(&mut self) -> Option<Emulator> {
        self.stop.store(true, Ordering::Relaxed);
        self.thread.take().and_then(|t| t.join().ok())
    }
}

impl Drop for Runner {
    fn drop(&mut self) {
        self.halt();
    }
}

fn now_ns() -> i128 {
    let t = clock_gettime(ClockId::CLOCK_MONOTONIC)
        .unwrap_or_else(|_| nix::sys::time::TimeSpec::new(0, 0));
    t.tv_sec() as i128 * 1_000_000_000 + t.tv_nsec() as i128
}

/// A follower's clock (layout 1.12): a tick for each of the master's, woken by the bus; the
/// master lost (its end, its connection's hang-up, no tick within the loss timeout), the card
/// halts and goes on on its own real-time clock.
fn run_follower(emu: &mut Emulator, stop: &AtomicBool, busy_poll: bool) {
    let timeout = super::bus::loss_timeout(emu.fw.servo_rate_hz());
    let mut last = std::time::Instant::now();
    while !stop.load(Ordering::Relaxed) {
        emu.serve();
        let Some(BusEnd::Follower(link)) = &emu.bus else {
            break;
        };
        // Short waits, so that commands are served between the master's ticks too.
        let woken = link.wait(Duration::from_millis(1));
        let snap = link.read();
        if woken == Wake::HungUp || !snap.alive || last.elapsed() > timeout {
            emu.lose_bus();
            break;
        }
        if emu.fw.tick_count() < snap.tick {
            last = std::time::Instant::now();
            while emu.fw.tick_count() < snap.tick && !stop.load(Ordering::Relaxed) {
                emu.step();
            }
            if let Some(BusEnd::Follower(link)) = &emu.bus {
                link.ack(emu.fw.tick_count());
            }
        }
    }
    run_realtime(emu, stop, busy_poll);
}

fn run_realtime(emu: &mut Emulator, stop: &AtomicBool, busy_poll: bool) {
    let mut period = 1_000_000_000i128 / emu.fw.servo_rate_hz() as i128;
    let mut next = now_ns() + period;
    while !stop.load(Ordering::Relaxed) {
        emu.serve();
        let now = now_ns();
        if now >= next {
            if let Some(BusEnd::Master(bus)) = &emu.bus {
                // Layout 1.12: the followers run each tick before the master runs the next.
                bus.await_followers(emu.fw.tick_count(), stop);
            }
            emu.step();
            let p = 1_000_000_000i128 / emu.fw.servo_rate_hz() as i128;
            if p != period || now - next > 2 * period {
                // New servo rate, or the OS stalled this thread: restart the deadline grid.
                // Emulated time pauses with the thread, as a real card's would not stall at
                // all; running the missed ticks back to back would age the host's heartbeat
                // (a wall-clock thread) by many ticks at once and trip the watchdog falsely.
                period = p;
                next = now + period;
            } else {
                next += period;
            }
        } else if busy_poll {
            std::hint::spin_loop();
        } else {
            let ts = nix::sys::time::TimeSpec::new(
                (next / 1_000_000_000) as _,
                (next % 1_000_000_000) as _,
            );
            let _ = clock_nanosleep(
                ClockId::CLOCK_MONOTONIC,
                ClockNanosleepFlags::TIMER_ABSTIME,
                &ts,
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use firmware_proto::ring::{CmdProducer, CMD_RING};
    use firmware_proto::{layout, Command, Mem, Opcode};

    fn host(fds: (OwnedFd, OwnedFd)) -> (MappedWindow, OwnedFd) {
        (MappedWindow::from_fd(fds.0).unwrap(), fds.1)
    }

    fn raised(irq: &OwnedFd) -> bool {
        nix::unistd::read(irq, &mut [0u8; 8]).is_ok()
    }

    /// A renewal between two ticks: the new host's window carries on from the old one (tick,
    /// ring indices), the card ticks and raises its interrupt there only, and the past host's
    /// window and eventfd are left behind.
    #[test]
    fn each_lease_gets_a_window_and_an_interrupt_line_of_its_own() {
        let mut emu = Emulator::create("lessor-unit", &EmuOptions::new(2, 10_000)).unwrap();
        let lessor = emu.lessor();
        let (a, a_irq) = host(lessor.renew().unwrap());
        a.write32(layout::IRQ_MASK, u32::MAX); // every event raises the interrupt
        let mut cmds = CmdProducer::attach(&a, CMD_RING);
        let mut attach = Command::new(Opcode::HostAttach, 0);
        attach.flags = 1; // (a session of its own: the card moves nothing outside one)
        cmds.push(&attach).unwrap();
        cmds.push(&Command::new(Opcode::PowerOn, 0)).unwrap();
        emu.step_n(5);
        assert!(raised(&a_irq), "the ack raised A's line");
        let tick = a.read64(layout::TICK);
        assert_eq!(tick, emu.firmware().tick_count());
        let head = a.read32(layout::CMD_HEAD);

        let (b, b_irq) = host(lessor.renew().unwrap());
        assert_eq!(b.read64(layout::TICK), tick, "a copy of the window");
        assert_eq!(b.read32(layout::CMD_HEAD), head);
        // A writes over everything it kept; neither the card nor B sees it.
        for off in (0..firmware_proto::DPRAM_SIZE).step_by(8) {
            a.write64(off, u64::MAX);
        }
        let mut cmds = CmdProducer::attach(&b, CMD_RING);
        attach.flags = 2;
        cmds.push(&attach).unwrap();
        cmds.push(&Command::new(Opcode::PowerOn, 1)).unwrap();
        emu.step_n(5);
        assert_eq!(b.read64(layout::TICK), tick + 5);
        assert_eq!(a.read64(layout::TICK), u64::MAX);
        assert_eq!(emu.window().read64(layout::TICK), tick + 5);
        assert!(raised(&b_irq), "the ack raised B's line");
        assert!(!raised(&a_irq), "A's line is no longer the card's");
        assert_eq!(b.read32(layout::safety_status::PROTOCOL_ERRORS), 0);
        assert_eq!(
            emu.firmware().axis(1).unwrap().state,
            firmware_proto::AxisState::Standstill
        );
    }

    /// A renewal waits for the tick under way and is not starved by a thread that steps or
    /// serves without pause (free-running, busy-polling); the card's time goes on in the new
    /// window.
    #[test]
    fn a_running_card_is_renewed_between_two_ticks() {
        for (clock, busy) in [(Clock::FreeRunning, false), (Clock::RealTime, true)] {
            let emu = Emulator::create("lessor-run", &EmuOptions::new(2, 10_000)).unwrap();
            let lessor = emu.lessor();
            let runner = Runner::spawn(emu, clock, busy).unwrap();
            let mut last = 0;
            for _ in 0..20 {
                let (w, _irq) = host(lessor.renew().unwrap());
                let t = w.read64(layout::TICK);
                assert!(t >= last, "{clock:?}: tick {t} after {last}");
                last = t;
            }
            let emu = runner.stop().unwrap();
            assert!(emu.firmware().tick_count() >= last);
            assert_eq!(
                emu.window().read32(layout::safety_status::PROTOCOL_ERRORS),
                0
            );
        }
    }
}
