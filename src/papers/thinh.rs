//! Thinh 2014 on the card: the feed-forward PIV law of Fig 5 with and without its
//! feed-forward, the acceleration mode of Fig 9, the blending mode of Fig 10 (the path's
//! time-shifted transition) and the step mode of Fig 11, and, beyond the paper, the following
//! error of the default axis over a speed sweep.
//!
//! Thinh gives gains without units (K_P 2.5, K_I 0.02, K_V 50, K_VFF 30) and no plant beyond
//! the motor's name, a Yaskawa SGMJV-02A (200 W, 0.637 N·m rated) on an SGDV drive, with a
//! 2048-pulse encoder. [`ThinhGains::to_ffpiv`] states the units we read them in;
//! [`thinh_plant`] is an axis on which they make the loop the card's default tuning makes.

use crate::{AxisSettings, AxisState, Card, Clock, EmuOptions, MotorParams, MoveLimits};
use crate::{Result, SafetySettings, SimOptions};
use card_emu::servo::ffpiv::FfpivGains;
use std::time::Duration;

/// Thinh's encoder: 2048 pulses per revolution (the SGDV's encoder output), 8192 counts
/// after quadrature.
pub const THINH_COUNTS_PER_REV: u32 = 8192;

/// Thinh's servo gains (§5), as printed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ThinhGains {
    /// K_P: velocity command per count of position error.
    pub kp: f64,
    /// K_I: on the velocity error.
    pub ki: f64,
    /// K_V: drive output per velocity error.
    pub kv: f64,
    /// K_VFF: drive output per reference velocity.
    pub kvff: f64,
}

/// K_P 2.5, K_I 0.02, K_V 50, K_VFF 30 (Thinh §5: the gains of Figs 9–11).
pub const THINH_GAINS: ThinhGains = ThinhGains {
    kp: 2.5,
    ki: 0.02,
    kv: 50.0,
    kvff: 30.0,
};

impl ThinhGains {
    /// Our FFPIV gains for Thinh's axis ([`THINH_COUNTS_PER_REV`] counts, 4 per encoder pulse),
    /// reading Thinh's gains in the units of a drive engineer's tuning screen: velocities in
    /// rpm, positions in encoder pulses, the drive output in mV of the ±10 V reference, time
    /// in ms.
    /// - K_P, rpm per pulse of error: `kp = K_P·2048/60` s⁻¹ = 85.3 s⁻¹;
    /// - K_I, per ms: `ki = K_I·1000` s⁻¹ = 20 s⁻¹ (the velocity PI's zero, 3.2 Hz);
    /// - K_V, mV per rpm: `kv = K_V·10⁻³·60/8192` V per count/s = 3.66·10⁻⁴;
    /// - K_VFF, mV per rpm of the reference, added to the output (Fig 5, `u = u_FF + u_PIV`):
    ///   our law feeds the velocity forward through K_V, so `kvff = K_VFF/K_V` = 0.6 (the units
    ///   cancel).
    ///
    /// No K_AFF is given: `kaff` is 0. The velocity filter is the card's default. Read so, the
    /// gains are within 10% of the card's default tuning (K_P 94 s⁻¹, K_V 3.95·10⁻⁴) but for
    /// K_I (63 s⁻¹) and K_VFF (1).
    pub fn to_ffpiv(&self) -> FfpivGains {
        let counts_per_rpm = THINH_COUNTS_PER_REV as f64 / 60.0; // counts/s per rpm
        let pulses_per_rev = THINH_COUNTS_PER_REV as f64 / 4.0;
        FfpivGains {
            kp: self.kp * pulses_per_rev / 60.0,
            ki: self.ki * 1000.0,
            kv: self.kv * 1e-3 / counts_per_rpm,
            kvff: self.kvff / self.kv,
            kaff: 0.0,
            ..FfpivGains::default()
        }
    }
}

/// The axis Thinh's gains are for: 8192 counts/rev; a drive in torque mode at 3 V per rated
/// torque (0.637 N·m, the SGMJV-02A's: 200 W at 3000 rpm; 3 V is the SGDV's default
/// torque-reference gain), so 0.212 N·m/V, limited to 2.23 N·m (its peak torque); the card's
/// default friction and damping. Thinh gives no inertia: J is set so that K_V's velocity loop
/// crosses over at 4·K_P, where the card's default tuning puts it (K_P = ω_c/4):
/// J = K_t·(counts/rad)·K_V/(4·K_P) = 3.0·10⁻⁴ kg·m² (the default axis has 5·10⁻⁴).
pub fn thinh_plant() -> MotorParams {
    let g = THINH_GAINS.to_ffpiv();
    let kt = 0.637 / 3.0;
    let counts_per_rad = THINH_COUNTS_PER_REV as f64 / std::f64::consts::TAU;
    let wc = 4.0 * g.kp;
    // ω_c = kv·(counts/s² per V) = kv·K_t·counts_per_rad/J.
    let inertia = g.kv * kt * counts_per_rad / wc;
    MotorParams {
        inertia,
        kt,
        amp_gain: 1.0,
        current_limit: 2.23 / kt,
        counts_per_rev: THINH_COUNTS_PER_REV,
        ..MotorParams::default_servo()
    }
}

/// The two axes of the Fig 5 experiment.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Fig5Axis {
    /// The default plant with the card's default tuning.
    Default,
    /// [`thinh_plant`] with [`THINH_GAINS`].
    Thinh,
}

impl Fig5Axis {
    /// The plant and its gains (before the feed-forward is chosen).
    pub fn setup(self) -> (MotorParams, FfpivGains) {
        match self {
            Self::Default => (MotorParams::default_servo(), FfpivGains::default()),
            Self::Thinh => (thinh_plant(), THINH_GAINS.to_ffpiv()),
        }
    }
}

/// Which feed-forward the FFPIV law gets.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FeedForward {
    /// Velocity (K_VFF 1) and acceleration feed-forward matched to the plant
    /// (K_AFF = volts per count/s², [`MotorParams::volts_per_accel`]).
    Full,
    /// Velocity feed-forward only (K_VFF 1, K_AFF 0).
    Velocity,
    /// Thinh's own: K_VFF 30 of K_V 50 (0.6), no acceleration feed-forward.
    Thinh,
    /// None: the PIV loop alone.
    None,
}

impl FeedForward {
    /// `g` with this feed-forward for `plant`.
    pub fn apply(self, g: FfpivGains, plant: &MotorParams) -> FfpivGains {
        let (kvff, kaff) = match self {
            Self::Full => (1.0, plant.volts_per_accel()),
            Self::Velocity => (1.0, 0.0),
            Self::Thinh => (THINH_GAINS.kvff / THINH_GAINS.kv, 0.0),
            Self::None => (0.0, 0.0),
        };
        FfpivGains { kvff, kaff, ..g }
    }
}

/// One point-to-point move of a run: relative distance, limits, then a dwell at rest.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Step {
    /// Counts, relative.
    pub distance: f64,
    /// S-curve limits.
    pub limits: MoveLimits,
    /// Time at rest after motion done before the next step, s.
    pub dwell: f64,
}

/// A traced run of one axis: every servo tick from the first command to the last step's end.
#[derive(Debug, Clone, Default)]
pub struct Tracking {
    /// Time since the first command, s.
    pub t: Vec<f64>,
    /// Commanded position, counts.
    pub cmd_pos: Vec<f64>,
    /// Commanded velocity, counts/s.
    pub cmd_vel: Vec<f64>,
    /// Actual (encoder) position, counts.
    pub act_pos: Vec<f64>,
    /// Actual velocity: the encoder's travel over the last 1 ms (10 ticks), counts/s (what a
    /// tuning application sampling at 1 kHz plots; a single tick's difference is quantised to
    /// 10,000 counts/s).
    pub act_vel: Vec<f64>,
    /// Following error the card reads, commanded − encoder, counts.
    pub ferr: Vec<f64>,
    /// Motor torque, N·m (the DAC's volts through the drive, within its current limit), each
    /// tick.
    pub torque: Vec<f64>,
    /// Largest |following error|, counts.
    pub peak: f64,
    /// Time of the largest |following error|, s.
    pub peak_at: f64,
    /// RMS of the following error over the ticks while a step moves (command to motion
    /// done), counts.
    pub rms: f64,
    /// The shaft's own error against its command at the tick's start, unquantised: the least
    /// and the largest `x − x_ref` while moving, counts. The loop holds the shaft on the
    /// reference with the encoder's half count of bias (`x_ref − floor(x)` averages 0).
    pub shaft: (f64, f64),
    /// Ticks on which the servo law asked for more than the DAC gives.
    pub saturated: usize,
    /// Per step: (profile time, motion done after the command), s.
    pub step_times: Vec<(f64, f64)>,
    /// Encoder position at the end, and the end the steps add up to, counts.
    pub end: (f64, f64),
}

impl Tracking {
    /// Ticks with |following error| > `bound`.
    pub fn ticks_over(&self, bound: f64) -> usize {
        self.ferr.iter().filter(|e| e.abs() > bound).count()
    }

    /// The largest |commanded − actual velocity| while the command moves, counts/s; with
    /// `cruise`, only over the second half of the ticks at the top commanded speed.
    pub fn velocity_error(&self, cruise: bool) -> f64 {
        let top = self.cmd_vel.iter().fold(0.0, |m: f64, v| m.max(v.abs()));
        let at_top: Vec<usize> = (0..self.cmd_vel.len())
            .filter(|&k| self.cmd_vel[k].abs() == top)
            .collect();
        let from = at_top.get(at_top.len() / 2).copied().unwrap_or(0);
        (0..self.cmd_vel.len())
            .filter(|&k| {
                self.cmd_vel[k] != 0.0 && (!cruise || (k >= from && self.cmd_vel[k].abs() == top))
            })
            .map(|k| (self.cmd_vel[k] - self.act_vel[k]).abs())
            .fold(0.0, f64::max)
    }

    /// The torque averaged over 1 ms (10 ticks) ending at each tick, N·m: what a tuning
    /// application sampling at 1 kHz plots.
    pub fn torque_1ms(&self) -> Vec<f64> {
        (0..self.torque.len())
            .map(|k| {
                let w = &self.torque[k.saturating_sub(AVG_TICKS - 1)..=k];
                w.iter().sum::<f64>() / w.len() as f64
            })
            .collect()
    }
}

/// Ticks in the 1 ms averages of [`Tracking`] at 10 kHz.
const AVG_TICKS: usize = 10;

/// What [`Tracking`] records of each tick of axis 0 of a 10 kHz card on `plant`.
struct Recorder {
    /// The encoder over the last 1 ms, for the actual velocity.
    history: std::collections::VecDeque<f64>,
    torque_per_volt: f64,
    max_torque: f64,
    ts: f64,
}

impl Recorder {
    fn new(plant: &MotorParams, start: f64, ts: f64) -> Self {
        Self {
            history: std::collections::VecDeque::from(vec![start; AVG_TICKS + 1]),
            torque_per_volt: plant.kt * plant.amp_gain,
            max_torque: plant.kt * plant.current_limit,
            ts,
        }
    }

    /// Appends the tick at time `t` whose status is `raw`; returns its following error.
    fn record(&mut self, r: &mut Tracking, t: f64, raw: &crate::proto::AxisStatus) -> f64 {
        let e = raw.cmd_pos - raw.act_pos;
        r.t.push(t);
        r.cmd_pos.push(raw.cmd_pos);
        r.cmd_vel.push(raw.cmd_vel);
        r.act_pos.push(raw.act_pos);
        self.history.pop_front();
        self.history.push_back(raw.act_pos);
        r.act_vel
            .push((raw.act_pos - self.history[0]) / (AVG_TICKS as f64 * self.ts));
        r.ferr.push(e);
        r.torque
            .push((raw.dac_v * self.torque_per_volt).clamp(-self.max_torque, self.max_torque));
        if raw.u_request.abs() > AxisSettings::default().dac_limit_v {
            r.saturated += 1;
        }
        if e.abs() > r.peak {
            r.peak = e.abs();
            r.peak_at = t;
        }
        e
    }
}

/// How long a step may take beyond its profile before the run gives up, s.
const STEP_SLACK: f64 = 2.0;

/// Run `steps` on axis 0 of a stepped single-axis card at 10 kHz with plant `plant` and FFPIV
/// gains `gains`, tracing every tick.
pub fn track_steps(plant: MotorParams, gains: FfpivGains, steps: &[Step]) -> Result<Tracking> {
    let mut emu = EmuOptions::new(1, 10_000);
    emu.motors[0] = plant;
    let card = Card::open_sim(SimOptions {
        clock: Clock::Stepped,
        emu,
    })?;
    let sim = card.sim().expect("stepped");
    let ts = 1.0 / card.info().servo_rate_hz as f64;
    let ax = card.axis(0)?;
    ax.configure(&AxisSettings {
        ffpiv: gains,
        ..AxisSettings::default()
    })?;
    // The runs without feed-forward lag by thousands of counts on purpose.
    ax.configure_safety(&SafetySettings {
        ferror: 1e6,
        min_ferror: 1e6,
        ..SafetySettings::default()
    })?;
    ax.enable()?;
    sim.step(100);
    let mut r = Tracking::default();
    let start = ax.status()?.actual_position;
    let mut rec = Recorder::new(&plant, start, ts);
    let mut goal = start;
    let (mut sq, mut n) = (0.0, 0usize);
    r.shaft = (f64::INFINITY, f64::NEG_INFINITY);
    let t0 = sim.time();
    let shaft = || sim.with_emulator(|e| e.motor(0).map_or(0.0, |m| m.position_counts()));
    for step in steps {
        goal += step.distance;
        let m = ax.move_relative(step.distance, &step.limits)?;
        let planned = ax.status()?.raw.planned_time;
        let issued = sim.time();
        let dwell_ticks = (step.dwell / ts).round() as u64;
        let mut done_for: Option<u64> = None;
        let limit = ((planned + STEP_SLACK) / ts) as u64 + dwell_ticks;
        for _ in 0..limit {
            let x = shaft(); // where the shaft is as the tick reads the encoder
            sim.step(1);
            let s = ax.status()?;
            let raw = &s.raw;
            let e = rec.record(&mut r, sim.time() - t0, raw);
            if done_for.is_none() {
                sq += e * e;
                n += 1;
                if raw.cmd_vel != 0.0 {
                    let d = x - raw.cmd_pos;
                    r.shaft = (r.shaft.0.min(d), r.shaft.1.max(d));
                }
                if s.state == AxisState::Standstill {
                    r.step_times.push((planned, sim.time() - issued));
                    done_for = Some(0);
                }
            }
            if let Some(k) = &mut done_for {
                if *k >= dwell_ticks {
                    break;
                }
                *k += 1;
            }
        }
        m.wait(Duration::ZERO)?;
    }
    r.rms = (sq / n.max(1) as f64).sqrt();
    r.end = (ax.status()?.actual_position, goal);
    Ok(r)
}

/// The S-curve of the Fig 5 runs: 200,000 counts at up to 2·10⁵ counts/s, 2·10⁶ counts/s²,
/// 10⁸ counts/s³ (20 revolutions of the default axis at 20 rev/s; 24 of Thinh's at 1,465 rpm).
pub const FIG5_DISTANCE: f64 = 200_000.0;
/// Limits of the Fig 5 runs.
pub const FIG5_LIMITS: MoveLimits = MoveLimits {
    velocity: 2e5,
    acceleration: 2e6,
    deceleration: 2e6,
    jerk: [1e8; 4],
};

/// Thinh Fig 5: the same S-curve move ([`FIG5_DISTANCE`], [`FIG5_LIMITS`]) on `axis` with
/// feed-forward `ff`.
pub fn thinh_fig5(axis: Fig5Axis, ff: FeedForward) -> Result<Tracking> {
    let (plant, gains) = axis.setup();
    track_steps(
        plant,
        ff.apply(gains, &plant),
        &[Step {
            distance: FIG5_DISTANCE,
            limits: FIG5_LIMITS,
            dwell: 0.0,
        }],
    )
}

/// The following error the PIV loop alone keeps at cruise: the integrator drives the velocity
/// error `K_P·e + K_VFF·v − v̂` to zero, so `e = (1 − K_VFF)·v/K_P`, counts.
pub fn cruise_error(gains: &FfpivGains, v: f64) -> f64 {
    (1.0 - gains.kvff) * v / gains.kp
}

/// The following error velocity feed-forward alone leaves at acceleration `a` without the
/// integrator's help: the velocity loop needs `e_v = a/ω_c` to make `a`, which the position
/// loop supplies as `K_P·e`: `e = a/(K_P·ω_c)`, `ω_c = K_V` × counts/s² per volt, counts. The
/// integrator takes over part of it as the acceleration lasts.
pub fn acceleration_error(gains: &FfpivGains, plant: &MotorParams, a: f64) -> f64 {
    let wc = gains.kv * plant.accel_per_volt();
    a / (gains.kp * wc)
}

/// What the law would lose to the velocity estimator's lag if it fed the raw reference
/// velocity forward (as it did before `v̂_ref`): on a ramp the estimate (a backward difference
/// over one tick `ts`, then a first-order low-pass) lags by `T/2 + T(1 − α)/α`; the loop
/// reads that as a velocity error `a·lag` and cancels it with a following error
/// `a·lag/K_P`, counts.
pub fn estimator_lag_error(gains: &FfpivGains, a: f64, ts: f64) -> f64 {
    let alpha = 1.0 - (-std::f64::consts::TAU * gains.vel_filter_hz * ts).exp();
    a * (ts / 2.0 + ts * (1.0 - alpha) / alpha) / gains.kp
}

/// Fig 9's acceleration mode on [`thinh_plant`] with [`THINH_GAINS`]: one S-curve to
/// 1,500 rpm (204,800 counts/s) at 10⁶ counts/s² with 100 ms jerk phases (10⁷ counts/s³),
/// 25 revolutions, then 50 ms at rest.
pub const FIG9_STEP: Step = Step {
    distance: 204_800.0,
    limits: MoveLimits {
        velocity: 204_800.0,
        acceleration: 1e6,
        deceleration: 1e6,
        jerk: [1e7; 4],
    },
    dwell: 0.05,
};

/// Thinh Fig 9 (acceleration motion mode): command and actual velocity and the torque of
/// [`FIG9_STEP`] on [`thinh_plant`] with [`THINH_GAINS`] and feed-forward `ff`
/// ([`FeedForward::Thinh`]: as in the paper).
pub fn thinh_fig9(ff: FeedForward) -> Result<Tracking> {
    let plant = thinh_plant();
    track_steps(
        plant,
        ff.apply(THINH_GAINS.to_ffpiv(), &plant),
        &[FIG9_STEP],
    )
}

/// Fig 11's step mode: quarter-turn steps (2048 counts) of 52 ms profiles (up to 1.2·10⁵
/// counts/s, 5·10⁶ counts/s², 5·10⁸ counts/s³), each followed by 20 ms at rest; forward four
/// times, then back twice.
pub fn fig11_steps() -> Vec<Step> {
    let limits = MoveLimits::new(120_000.0, 5e6, 5e8);
    [1.0, 1.0, 1.0, 1.0, -1.0, -1.0]
        .iter()
        .map(|d| Step {
            distance: d * 2048.0,
            limits,
            dwell: 0.02,
        })
        .collect()
}

/// Thinh Fig 11 (step motion mode): [`fig11_steps`] on [`thinh_plant`] with [`THINH_GAINS`]
/// and feed-forward `ff` ([`FeedForward::Thinh`]: as in the paper).
pub fn thinh_fig11(ff: FeedForward) -> Result<Tracking> {
    let plant = thinh_plant();
    track_steps(
        plant,
        ff.apply(THINH_GAINS.to_ffpiv(), &plant),
        &fig11_steps(),
    )
}

/// The speeds of [`ff_speed_sweep`], counts/s: 2 to 50 rev/s of the default axis, the last
/// its 3,000 rpm (the speed the card's watchdog tests run it at).
pub const SWEEP_SPEEDS: [f64; 5] = [2e4, 1e5, 2e5, 4e5, 5e5];
/// Acceleration and jerk of the sweep (those of Fig 5).
pub const SWEEP_ACCEL: (f64, f64) = (2e6, 1e8);

/// Beyond the paper: an S-curve at up to `v` counts/s ([`SWEEP_ACCEL`]) on the default axis
/// with the default tuning (full feed-forward, matched to the plant), with 100 ms at cruise.
pub fn ff_speed_sweep(v: f64) -> Result<Tracking> {
    ff_speed_sweep_on(MotorParams::default_servo(), v)
}

/// [`ff_speed_sweep`] on `plant` (the default axis without its Coulomb friction shows what
/// break-away from rest costs).
pub fn ff_speed_sweep_on(plant: MotorParams, v: f64) -> Result<Tracking> {
    let (a, j) = SWEEP_ACCEL;
    // Ramp up and down (each v/a + a/j at most), then 0.1 s at v.
    let distance = v * (v / a + a / j + 0.1);
    track_steps(
        plant,
        FfpivGains::default(),
        &[Step {
            distance,
            limits: MoveLimits::new(v, a, j),
            dwell: 0.0,
        }],
    )
}

/// Fig 10's speed segments: (distance, feed) of each, counts and counts/s: a quarter, a full
/// and a half turn of Thinh's axis at 4, 12 and 6·10⁴ counts/s (293 to 879 rpm).
pub const FIG10_SEGMENTS: [(f64, f64); 3] = [
    (2_048.0, 40_000.0),
    (8_192.0, 120_000.0),
    (4_096.0, 60_000.0),
];
/// Axis limits of the Fig 10 runs (those of Fig 11's steps, doubled in acceleration and jerk:
/// a time-shifted profile takes half of each), counts/s, /s², /s³.
pub const FIG10_LIMITS: (f64, f64, f64) = (120_000.0, 1e7, 1e9);

/// One run of Fig 10: the segments of [`FIG10_SEGMENTS`] joined by one transition.
#[derive(Debug, Clone, Default)]
pub struct Blending {
    /// Every tick from the first segment's queueing to the group's motion done (`end`: the
    /// encoder there, and where the segments add up to).
    pub trace: Tracking,
    /// That time, s.
    pub time: f64,
    /// Least commanded speed between the first time at the first feed and the last time at
    /// the last one (0: it stopped at a junction), counts/s.
    pub least_between: f64,
    /// Largest step of the 1 ms torque from one tick to the next, N·m.
    pub torque_step: f64,
}

/// Thinh Fig 10 (blending motion mode) on [`thinh_plant`] with [`THINH_GAINS`] and the full
/// feed-forward (so that the actual velocity shows the command's shape, as in the paper): the
/// [`FIG10_SEGMENTS`] on a one-axis group's path, joined by `transition`:
/// [`Transition::TimeShift`](crate::Transition::TimeShift) is the paper's (each segment a
/// rest-to-rest S-curve, the next one started while the one before decelerates);
/// [`Transition::None`](crate::Transition::None) stops at each junction;
/// [`Transition::MaxDeviation`](crate::Transition::MaxDeviation) is the card's own planner (one
/// axis: the segments are collinear, so the speed goes from one feed to the next without a blend).
/// The card's path planner runs at every servo tick here, as the time-shifted profiles and the
/// paper's interpolator do (its default, every 1 ms, plans the rest-to-rest stops a little softer).
pub fn thinh_fig10(transition: crate::Transition) -> Result<Blending> {
    use crate::{GroupSettings, GroupState, PathSettings, Segment};
    let plant = thinh_plant();
    let mut emu = EmuOptions::new(1, 10_000);
    emu.motors[0] = plant;
    let card = Card::open_sim(SimOptions {
        clock: Clock::Stepped,
        emu,
    })?;
    let sim = card.sim().expect("stepped");
    let ts = 1.0 / card.info().servo_rate_hz as f64;
    let ax = card.axis(0)?;
    ax.configure(&AxisSettings {
        ffpiv: FeedForward::Full.apply(THINH_GAINS.to_ffpiv(), &plant),
        ..AxisSettings::default()
    })?;
    ax.enable()?;
    let g = card.group(0)?;
    g.configure(&GroupSettings::new(&[0]))?;
    g.enable()?;
    let (v, a, j) = FIG10_LIMITS;
    g.configure_path(&PathSettings {
        plan_period: ts,
        chord_fit: true,
        ..PathSettings::uniform(1, v, a, j)
    })?;
    sim.step(100);
    let start = ax.status()?.actual_position;
    let mut x = start;
    let n = FIG10_SEGMENTS.len();
    let segs: Vec<Segment> = FIG10_SEGMENTS
        .iter()
        .enumerate()
        .map(|(i, &(d, f))| {
            x += d;
            let s = Segment::line(i as u32 + 1, &[x], f, 0.0).transition(transition);
            if i + 1 == n {
                s.last()
            } else {
                s
            }
        })
        .collect();
    g.stream_path(segs, |_| {}).map_err(|e| e.error)?;
    let mut r = Blending::default();
    let mut rec = Recorder::new(&plant, start, ts);
    let t0 = sim.time();
    for _ in 0..(10.0 / ts) as usize {
        sim.step(1);
        rec.record(&mut r.trace, sim.time() - t0, &ax.status()?.raw);
        if g.status()?.0 == GroupState::Standby {
            break;
        }
    }
    r.time = sim.time() - t0;
    r.torque_step = r
        .trace
        .torque_1ms()
        .windows(2)
        .fold(0.0, |m: f64, w| m.max((w[1] - w[0]).abs()));
    // between the first time at the first feed and the last time at the last one
    let v = &r.trace.cmd_vel;
    let (f0, f1) = (FIG10_SEGMENTS[0].1, FIG10_SEGMENTS[n - 1].1);
    let from = v.iter().position(|&x| x >= f0 * (1.0 - 1e-9));
    let to = v.iter().rposition(|&x| x >= f1 * (1.0 - 1e-9));
    r.least_between = match (from, to) {
        (Some(a), Some(b)) if a < b => v[a..=b].iter().fold(f64::INFINITY, |m, &x| m.min(x)),
        _ => 0.0,
    };
    r.trace.end = (ax.status()?.actual_position, x);
    Ok(r)
}
