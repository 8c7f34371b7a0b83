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

use crate::firmware::safety::IndexLatch;
use crate::firmware::Firmware;
use crate::plant::aux::AuxEncoder;
use crate::plant::faults::FaultInjector;
use crate::plant::io::{encoder_span, FireRecord, InputBank};
use crate::plant::{IndexChannel, IndexPulse, Motor, MotorParams};
use firmware_proto::window::MappedWindow;
use firmware_proto::{AUX_ENCODERS, MAX_AXES};
use nix::sys::eventfd::{EfdFlags, EventFd};
use nix::time::{clock_gettime, clock_nanosleep, ClockId, ClockNanosleepFlags};
use std::os::fd::{AsFd, BorrowedFd};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::thread::JoinHandle;

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

/// The card: firmware, plant, interrupt line.
pub struct Emulator {
    window: Arc<MappedWindow>,
    fw: Firmware<Arc<MappedWindow>>,
    motors: [Motor; MAX_AXES],
    index: [IndexChannel; MAX_AXES],
    latch: [IndexLatch; MAX_AXES],
    dac: [f64; MAX_AXES],
    irq: EventFd,
    time: f64,
    faults: FaultInjector,
    /// The digital input pins (layout 1.7).
    inputs: InputBank,
    /// The shafts and DAC outputs at the start of the period just run, to replay it.
    period_start: [Motor; MAX_AXES],
    period_dac: [f64; MAX_AXES],
    /// The compare pulses recorded (when recording).
    fires: Option<Vec<FireRecord>>,
    /// Each encoder's lowest and highest count over the period just run.
    spans: [Option<(i64, i64)>; MAX_AXES],
    /// Layout 1.7 (sync): the auxiliary encoders.
    aux: [AuxEncoder; AUX_ENCODERS],
}

impl Emulator {
    /// Boot a card in `window`.
    pub fn new(window: Arc<MappedWindow>, opts: &EmuOptions) -> std::io::Result<Self> {
        let irq = EventFd::from_value_and_flags(0, EfdFlags::EFD_CLOEXEC | EfdFlags::EFD_NONBLOCK)?;
        let fw = Firmware::boot(window.clone(), opts.axes, opts.servo_rate_hz);
        Ok(Self {
            window,
            fw,
            motors: opts.motors.map(Motor::new),
            index: core::array::from_fn(|i| {
                IndexChannel::new(opts.index[i], opts.motors[i].counts_per_rev)
            }),
            latch: [IndexLatch::default(); MAX_AXES],
            dac: [0.0; MAX_AXES],
            irq,
            time: 0.0,
            faults: FaultInjector::default(),
            inputs: InputBank::default(),
            period_start: opts.motors.map(Motor::new),
            period_dac: [0.0; MAX_AXES],
            fires: None,
            spans: [None; MAX_AXES],
            aux: [AuxEncoder::default(); AUX_ENCODERS],
        })
    }

    /// A card in a fresh memfd window.
    pub fn create(name: &str, opts: &EmuOptions) -> std::io::Result<Self> {
        Self::new(Arc::new(MappedWindow::create(name)?), opts)
    }

    /// Serve the command channel now (between ticks). Returns the commands served.
    pub fn serve(&mut self) -> usize {
        let n = self.fw.serve_commands();
        self.raise_irq();
        n
    }

    /// One servo period.
    pub fn step(&mut self) {
        self.fw.serve_commands();
        let mut enc = [0i64; MAX_AXES];
        // [faults] encoders and switch inputs as the card sees them, through injected faults
        let mut inputs = self.faults.sense(&self.motors, &mut enc);
        // The encoder interface's index latch: the pulse comes from the shaft, the count it
        // captures is the counter's (with any corruption injected into the counter).
        for (i, ch) in self.index.iter_mut().enumerate() {
            let f = self.faults.get(i).copied().unwrap_or_default();
            let before = ch.latches;
            ch.sample(self.motors[i].encoder(), f.encoder_lost.is_none());
            if ch.latches != before {
                self.latch[i] = IndexLatch {
                    count: ch.count.wrapping_add(f.encoder_offset),
                    latches: ch.latches,
                };
            }
        }
        inputs.index = self.latch;
        self.fw.set_inputs(inputs);
        self.fw.set_digital_inputs(self.inputs.sample(&self.motors));
        self.fw.set_encoder_spans(self.spans);
        self.fw.set_aux_encoders(self.aux.map(|a| a.count));
        let ts = self.fw.ts();
        self.fw.tick(&enc, &mut self.dac);
        self.record_period_fires(ts);
        for a in &mut self.aux {
            a.step(ts);
        }
        let start = self.motors;
        for (i, (m, u)) in self.motors.iter_mut().zip(self.dac).enumerate() {
            self.faults.step_motor(i, m, u, ts);
        }
        let (faults, dac) = (&self.faults, self.dac);
        self.inputs
            .after_period(&start, &self.motors, ts, |a, m, dt| {
                faults.step_motor(a, m, dac[a], dt)
            });
        // The encoder interface's extreme counts of the period (through the encoder's faults).
        for (i, span) in self.spans.iter_mut().enumerate() {
            let f = faults.get(i).copied().unwrap_or_default();
            *span = Some(match f.encoder_lost {
                Some(frozen) => (frozen, frozen),
                None => {
                    let (lo, hi) = encoder_span(&start[i], &self.motors[i], ts, |m, dt| {
                        faults.step_motor(i, m, dac[i], dt)
                    });
                    (
                        lo.wrapping_add(f.encoder_offset),
                        hi.wrapping_add(f.encoder_offset),
                    )
                }
            });
        }
        self.period_start = start;
        self.period_dac = dac;
        self.time += ts;
        self.raise_irq();
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

    /// The digital input pins: levels the test sets, or sensors on an axis's travel.
    pub fn inputs(&mut self) -> &mut InputBank {
        &mut self.inputs
    }

    /// The digital outputs now (bit i = output i), compare pulses included.
    pub fn outputs(&self) -> u32 {
        self.fw.outputs()
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

    fn raise_irq(&mut self) {
        if self.fw.take_irq() {
            // A full counter (2^64 − 2 unread interrupts) cannot happen; nothing else fails.
            let _ = self.irq.write(1);
        }
    }

    /// Emulated time since boot, s.
    pub fn time(&self) -> f64 {
        self.time
    }

    /// The interrupt line: an eventfd that becomes readable when the card raises an interrupt.
    pub fn irq_fd(&self) -> BorrowedFd<'_> {
        self.irq.as_fd()
    }

    /// The DPRAM window.
    pub fn window(&self) -> &Arc<MappedWindow> {
        &self.window
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

fn run_realtime(emu: &mut Emulator, stop: &AtomicBool, busy_poll: bool) {
    let mut period = 1_000_000_000i128 / emu.fw.servo_rate_hz() as i128;
    let mut next = now_ns() + period;
    while !stop.load(Ordering::Relaxed) {
        emu.serve();
        let now = now_ns();
        if now >= next {
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
