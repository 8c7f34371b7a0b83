//! The papers' experiments, run on a stepped emulated card: Kim here, Shin, Thinh and Yeh in
//! their own modules, re-exported. The tests in `tests/papers.rs`
//! assert on these runs; `cargo run --release --example papers` prints them as tables and plots
//! them.

use crate::{
    AccDec, ArcSpec, Card, Clock, EmuOptions, FilterKind, FilterSettings, Group, GroupSettings,
    GroupState, Interpolator, MoveOptions, PathLimits, Plane, Result, SimOptions,
};
use card_emu::motion::arc::{exponential_filter_radial_error, linear_filter_radial_error};
use card_emu::motion::filters::exponential_pole;
use std::time::Duration;

mod shin;
mod thinh;
mod yeh;
pub use shin::*;
pub use thinh::*;
pub use yeh::*;

const T: Duration = Duration::from_secs(120);

/// Feed limits for constant-feed (post-interpolation acc/dec) moves: the S-curve limits are
/// unused, so they are set out of the way.
pub fn constant_feed(v: f64) -> PathLimits {
    PathLimits::new(v, 1e12, 1e15)
}

/// A stepped card whose axes 0 and 1 form group 0 with post-interpolation filters of
/// `kind`/`tau` for every feed type.
pub fn filtered_group(
    emu: EmuOptions,
    kind: FilterKind,
    tau: f64,
    interp: Interpolator,
) -> Result<(Card, Group)> {
    let card = Card::open_sim(SimOptions {
        clock: Clock::Stepped,
        emu,
    })?;
    for a in 0..2 {
        let ax = card.axis(a)?;
        ax.set_filters(&FilterSettings::all(kind, tau))?;
        ax.enable()?;
    }
    let g = card.group(0)?;
    g.configure(&GroupSettings {
        accdec: AccDec::Post,
        interpolator: interp,
        ..GroupSettings::new(&[0, 1])
    })?;
    g.enable()?;
    Ok((card, g))
}

fn cmd(card: &Card, a: usize) -> Result<(f64, f64)> {
    let s = card.axis(a)?.status()?.raw;
    Ok((s.cmd_pos, s.cmd_vel))
}

/// One run of Kim Fig 7.
#[derive(Debug, Clone)]
pub struct Fig7 {
    /// Time of each tick, s.
    pub t: Vec<f64>,
    /// Commanded position, pulses.
    pub pos: Vec<f64>,
    /// Commanded velocity, pulses/s.
    pub vel: Vec<f64>,
    /// Commanded position at the end.
    pub final_cmd: f64,
    /// Encoder position at motion done.
    pub final_act: f64,
    /// The correction the group's snap to the programmed end made when it came to rest: what
    /// the filter and the position sums lost or invented, counts.
    pub snap: f64,
}

/// Kim Fig 7: the 81,920-pulse X move (20 turns of Kim's 4096-pulse encoder) at 10 rev/s,
/// through a `kind` acc/dec filter of 100 ms, sampled at 1 kHz.
pub fn kim_fig7(kind: FilterKind) -> Result<Fig7> {
    let mut emu = EmuOptions::new(2, 1000);
    emu.motors[0].counts_per_rev = 4096;
    let (card, g) = filtered_group(emu, kind, KIM_FIG7_TAU, Interpolator::Exact)?;
    let sim = card.sim().expect("stepped");
    let m = g.move_linear(
        &[81_920.0, 0.0],
        &constant_feed(KIM_FIG7_FEED),
        MoveOptions::default(),
    )?;
    let mut r = Fig7 {
        t: vec![],
        pos: vec![],
        vel: vec![],
        final_cmd: 0.0,
        final_act: 0.0,
        snap: f64::NAN,
    };
    while g.status()?.0 == GroupState::Moving {
        sim.step(1);
        let (p, v) = cmd(&card, 0)?;
        r.t.push(sim.time());
        r.pos.push(p);
        r.vel.push(v);
    }
    r.final_act = m
        .wait(T)
        .and_then(|_| card.axis(0)?.status())
        .map(|s| s.actual_position)?;
    r.final_cmd = cmd(&card, 0)?.0;
    r.snap = g.status()?.1.snap_last;
    Ok(r)
}

/// Kim Fig 7 feed, pulses/s (10 rev/s).
pub const KIM_FIG7_FEED: f64 = 40_960.0;
/// Kim Fig 7 filter time constant, s.
pub const KIM_FIG7_TAU: f64 = 0.1;

/// Kim eq 10–14: the targets of the four axes (x, y, z, w) of the synchronised point-to-point
/// move, counts (Kim's 4096-pulse encoders: 20, 5 and 1.25 turns, and a fraction).
pub const SYNC_TARGETS: [f64; 4] = [81_920.0, -20_480.0, 5_120.0, 1_000.5];
/// Its limits: 10 rev/s, and the S-curve's acceleration and jerk (counts).
pub const SYNC_LIMITS: PathLimits = PathLimits {
    velocity: 40_960.0,
    acceleration: 4e5,
    deceleration: 4e5,
    jerk: 4e7,
};
/// The slow z axis of the per-axis-limits run: scaled to x's distance (16×) each of its limits
/// is below x's, so z alone sets the time.
pub const SYNC_SLOW_Z: PathLimits = PathLimits {
    velocity: 1_500.0,
    acceleration: 2e4,
    deceleration: 2e4,
    jerk: 2e6,
};
/// Time constant of the post-interpolation filters of the synchronised runs, s.
pub const SYNC_TAU: f64 = 0.05;

/// How the synchronised point-to-point move is shaped.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SyncShape {
    /// Pre-interpolation S-curve, every axis within [`SYNC_LIMITS`].
    SCurve,
    /// Pre-interpolation S-curve, each axis within its own limits: z [`SYNC_SLOW_Z`], the
    /// others [`SYNC_LIMITS`].
    SCurveOwnLimits,
    /// Constant feed (10 rev/s on x), then a post-interpolation filter of this kind
    /// ([`SYNC_TAU`]) on every axis.
    Filter(FilterKind),
}

/// One run of the synchronised point-to-point move. Ticks count from the command.
#[derive(Debug, Clone, Default)]
pub struct SyncPtp {
    /// Per axis: the first tick its commanded position or velocity left the start.
    pub start: [u64; 4],
    /// Per axis: the first tick from which it is at rest on its target for good (commanded
    /// position equal to the target, commanded velocity 0).
    pub end: [u64; 4],
    /// Per axis: the largest |commanded velocity|, counts/s.
    pub peak_vel: [f64; 4],
    /// The correction of the group's snap to the programmed end when it came to rest, counts.
    pub snap: f64,
    /// Servo period, s.
    pub ts: f64,
}

impl SyncPtp {
    /// Every axis started on one tick and ended on one tick.
    pub fn synchronised(&self) -> bool {
        self.start.iter().all(|t| *t == self.start[0]) && self.end.iter().all(|t| *t == self.end[0])
    }

    /// From the first start to the last end, s.
    pub fn duration(&self) -> f64 {
        let first = self.start.iter().min().copied().unwrap_or(0);
        let last = self.end.iter().max().copied().unwrap_or(0);
        last.saturating_sub(first) as f64 * self.ts
    }
}

/// Kim eq 10–14 on the card: the four axes of [`SYNC_TARGETS`] in one synchronised
/// point-to-point move at 1 kHz, shaped by `shape`; each tick's commanded positions and
/// velocities give each axis's start and end tick.
pub fn kim_sync_ptp(shape: SyncShape) -> Result<SyncPtp> {
    let mut emu = EmuOptions::new(4, 1000);
    for m in emu.motors.iter_mut().take(4) {
        m.counts_per_rev = 4096;
    }
    let card = Card::open_sim(SimOptions {
        clock: Clock::Stepped,
        emu,
    })?;
    let sim = card.sim().expect("stepped");
    let axes = [0, 1, 2, 3];
    let post = match shape {
        SyncShape::Filter(kind) => Some(kind),
        _ => None,
    };
    for &a in &axes {
        let ax = card.axis(a)?;
        if let Some(kind) = post {
            ax.set_filters(&FilterSettings::all(kind, SYNC_TAU))?;
        }
        ax.enable()?;
    }
    let g = card.group(0)?;
    g.configure(&GroupSettings {
        accdec: if post.is_some() {
            AccDec::Post
        } else {
            AccDec::Pre
        },
        ..GroupSettings::new(&axes)
    })?;
    g.enable()?;
    let o = MoveOptions::default();
    let m = match shape {
        SyncShape::SCurve => g.move_ptp(&SYNC_TARGETS, &SYNC_LIMITS, o)?,
        SyncShape::SCurveOwnLimits => g.move_ptp_axes(
            &SYNC_TARGETS,
            &[SYNC_LIMITS, SYNC_LIMITS, SYNC_SLOW_Z, SYNC_LIMITS],
            o,
        )?,
        SyncShape::Filter(_) => {
            g.move_ptp(&SYNC_TARGETS, &constant_feed(SYNC_LIMITS.velocity), o)?
        }
    };
    let mut trace = Vec::new();
    while g.status()?.0 == GroupState::Moving {
        sim.step(1);
        let mut row = [(0.0, 0.0); 4];
        for (r, &a) in row.iter_mut().zip(&axes) {
            *r = cmd(&card, a)?;
        }
        trace.push(row);
    }
    m.wait(T)?;
    let mut r = SyncPtp {
        snap: g.status()?.1.snap_last,
        ts: 1e-3,
        ..Default::default()
    };
    for a in 0..4 {
        let moving = |row: &[(f64, f64); 4]| row[a].0 != 0.0 || row[a].1 != 0.0;
        let at_rest = |row: &[(f64, f64); 4]| row[a].0 == SYNC_TARGETS[a] && row[a].1 == 0.0;
        r.start[a] = trace.iter().position(moving).map_or(0, |k| k as u64 + 1);
        r.end[a] = trace
            .iter()
            .rposition(|row| !at_rest(row))
            .map_or(0, |k| k as u64 + 2);
        r.peak_vel[a] = trace.iter().map(|row| row[a].1.abs()).fold(0.0, f64::max);
    }
    Ok(r)
}

/// The sweep of Kim §4: (radius counts, Ω rad/s, servo rate Hz, time constant s): 20
/// combinations, every one of the four varied (feeds 20,000–150,000 counts/s, ΩT from
/// 2.5e-4 to 1.2e-2 rad per tick, 8 to 400 linear-filter taps).
pub const RADIAL_CASES: [(f64, f64, u32, f64); 20] = [
    (5_000.0, 4.0, 1000, 0.030),
    (5_000.0, 8.0, 2000, 0.020),
    (20_000.0, 3.0, 1000, 0.050),
    (20_000.0, 6.0, 5000, 0.015),
    (50_000.0, 2.0, 2000, 0.060),
    (50_000.0, 2.5, 1000, 0.020),
    (8_000.0, 10.0, 5000, 0.012),
    (8_000.0, 2.5, 10_000, 0.040),
    (12_000.0, 7.0, 2000, 0.025),
    (30_000.0, 4.0, 4000, 0.035),
    (3_000.0, 12.0, 1000, 0.008),
    (100_000.0, 1.5, 1000, 0.080),
    (2_000.0, 15.0, 2000, 0.010),
    (15_000.0, 5.0, 8000, 0.045),
    (40_000.0, 3.5, 3000, 0.028),
    (60_000.0, 1.2, 1000, 0.100),
    (16_000.0, 9.0, 20_000, 0.018),
    (10_000.0, 6.5, 1500, 0.034),
    (70_000.0, 1.8, 6000, 0.055),
    (4_000.0, 20.0, 10_000, 0.006),
];

/// Kim §4: run three laps of a circle of radius `r` at angular rate `omega` through the filter,
/// and return (measured steady-state ΔR over the middle of the third lap, closed form: the
/// corrected eq 28 for the linear filter, eq 32 for the exponential one).
pub fn radial_error(
    kind: FilterKind,
    r: f64,
    omega: f64,
    rate: u32,
    tau: f64,
    interp: Interpolator,
) -> Result<(f64, f64)> {
    let ts = 1.0 / rate as f64;
    let (card, g) = filtered_group(EmuOptions::new(2, rate), kind, tau, interp)?;
    let sim = card.sim().expect("stepped");
    let v = omega * r;
    g.move_linear(&[r, 0.0], &constant_feed(v), MoveOptions::default())?
        .wait(T)?;
    let lap = ArcSpec::Centre {
        end: [r, 0.0],
        centre: [0.0, 0.0],
        ccw: true,
    };
    let laps = (0..3)
        .map(|_| {
            g.move_circular(
                &lap,
                Plane::XY,
                &[],
                &constant_feed(v),
                MoveOptions::buffered(),
            )
        })
        .collect::<Result<Vec<_>>>()?;
    laps[1].wait(T)?;
    // Skip the first quarter of lap 3: the joint between laps disturbs the filter briefly.
    let lap_ticks = (std::f64::consts::TAU / (omega * ts)) as u64;
    sim.step(lap_ticks / 4);
    let (mut sum, mut n) = (0.0, 0.0);
    for _ in 0..lap_ticks / 2 {
        sim.step(1);
        let (x, y) = (cmd(&card, 0)?.0, cmd(&card, 1)?.0);
        sum += x.hypot(y);
        n += 1.0;
    }
    let formula = match kind {
        FilterKind::Linear => linear_filter_radial_error(r, v, ts, (tau / ts).round() as usize),
        _ => exponential_filter_radial_error(r, v, ts, exponential_pole(tau, ts)),
    };
    Ok((r - sum / n, formula))
}
