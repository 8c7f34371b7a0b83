//! The papers' experiments, run on a stepped emulated card. The tests in `tests/papers.rs`
//! assert on these runs; `cargo run --release --example papers` prints them as tables and plots
//! them.

use crate::{
    AccDec, ArcSpec, Card, Clock, EmuOptions, FeedType, FilterKind, FilterSettings, Group,
    GroupSettings, GroupState, Interpolator, MotorParams, MoveOptions, PathLimits, Plane, Result,
    SimOptions,
};
use card_emu::circle::{exponential_filter_radial_error, linear_filter_radial_error};
use card_emu::filters::exponential_pole;
use std::time::Duration;

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
    Ok(r)
}

/// Kim Fig 7 feed, pulses/s (10 rev/s).
pub const KIM_FIG7_FEED: f64 = 40_960.0;
/// Kim Fig 7 filter time constant, s.
pub const KIM_FIG7_TAU: f64 = 0.1;

/// The sweep of Kim §4: (radius counts, Ω rad/s, servo rate Hz, time constant s).
pub const RADIAL_CASES: [(f64, f64, u32, f64); 12] = [
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

/// One run of Shin's corner test.
#[derive(Debug, Clone, Default)]
pub struct Corner {
    /// Largest distance of the commanded path from the programmed corner (filter rounding), µm.
    pub command_rounding: f64,
    /// Largest distance of the table from its command near the corner (tracking), µm.
    pub tracking: f64,
    /// Largest distance of the table from the programmed corner, µm.
    pub total: f64,
    /// Commanded path near the corner (x, y), µm.
    pub command: Vec<(f64, f64)>,
    /// Table path near the corner, µm.
    pub table: Vec<(f64, f64)>,
    /// Commanded velocity of X and Y over the whole run: (t s, vx µm/s, vy µm/s).
    pub velocity: Vec<(f64, f64, f64)>,
}

/// Corner leg length, µm (1 count = 1 µm).
pub const CORNER_LEG: f64 = 20_000.0;
/// Shin's feed: 1 m/min in µm/s.
pub const CORNER_FEED: f64 = 1_000_000.0 / 60.0;

fn corner_distance(p: (f64, f64), l: f64) -> f64 {
    let d1 = if p.0 <= l {
        p.1.abs()
    } else {
        (p.0 - l).hypot(p.1)
    };
    let d2 = if p.1 >= 0.0 {
        (p.0 - l).abs()
    } else {
        (p.0 - l).hypot(p.1)
    };
    d1.min(d2)
}

/// Shin's corner test: along X to (L, 0), then along Y, at 1 m/min, through `kind` filters of
/// time constant `tau`, on axes with the plant `plant` (1 count = 1 µm).
pub fn shin_corner(plant: MotorParams, kind: FilterKind, tau: f64) -> Result<Corner> {
    let mut emu = EmuOptions::new(2, 10_000);
    emu.motors[0] = plant;
    emu.motors[1] = plant;
    let (card, g) = filtered_group(emu, kind, tau, Interpolator::Exact)?;
    let sim = card.sim().expect("stepped");
    let l = CORNER_LEG;
    let o = MoveOptions {
        buffered: true,
        feed_type: FeedType::Cutting,
        ..Default::default()
    };
    g.move_linear(&[l, 0.0], &constant_feed(CORNER_FEED), o)?;
    let last = g.move_linear(&[l, l], &constant_feed(CORNER_FEED), o)?;
    let mut r = Corner::default();
    while g.status()?.0 == GroupState::Moving {
        sim.step(1);
        let ((cx, vx), (cy, vy)) = (cmd(&card, 0)?, cmd(&card, 1)?);
        let c = (cx, cy);
        r.velocity.push((sim.time(), vx, vy));
        let load = sim.with_emulator(|e| {
            (
                e.motor(0).map_or(0.0, |m| m.load_position_counts()),
                e.motor(1).map_or(0.0, |m| m.load_position_counts()),
            )
        });
        if (c.0 - l).abs() < 3_000.0 && c.1 < 3_000.0 {
            r.command_rounding = r.command_rounding.max(corner_distance(c, l));
            r.tracking = r.tracking.max((load.0 - c.0).hypot(load.1 - c.1));
            r.total = r.total.max(corner_distance(load, l));
            r.command.push(c);
            r.table.push(load);
        }
    }
    last.wait(T)?;
    Ok(r)
}

/// One run of Yeh's die-bonder experiment on the card.
#[derive(Debug, Clone, Default)]
pub struct DieBonder {
    /// Largest |u| the PD+ law asked for, per axis, V (before the DAC clamp).
    pub max_u: [f64; 2],
    /// The drive limit Umax, V.
    pub umax: f64,
    /// Ticks on which some axis asked for more than Umax.
    pub ticks_over: usize,
    /// Largest distance of the actual position from the commanded path, counts.
    pub contour: f64,
    /// Worst |chord/Ts − V|/V over the ticks at the commanded feed V.
    pub feed_fluctuation: f64,
    /// Motion time, s.
    pub time: f64,
    /// (t, feed counts/s) per tick.
    pub feed: Vec<(f64, f64)>,
    /// (t, u_x, u_y) per tick, V.
    pub u: Vec<(f64, f64, f64)>,
    /// Commanded and actual path.
    pub path: Vec<((f64, f64), (f64, f64))>,
}

/// Feed of the die-bonder runs, counts/s.
pub const DIE_BONDER_FEED: f64 = 400_000.0;

/// Yeh's die bonder (Table 1 plant and PD+ gains, 1 ms sampling) along a path with two sharp
/// corners, with (`saturation`) or without the saturation-aware feed.
pub fn yeh_die_bonder(saturation: bool) -> Result<DieBonder> {
    use crate::{die_bonder_plant, NurbsFeed, PdPlusSettings};
    let mut emu = EmuOptions::new(2, 1000);
    emu.motors[0] = die_bonder_plant(0);
    emu.motors[1] = die_bonder_plant(1);
    let card = Card::open_sim(SimOptions {
        clock: Clock::Stepped,
        emu,
    })?;
    let sim = card.sim().expect("stepped");
    for a in 0..2 {
        let ax = card.axis(a)?;
        ax.configure_pdplus(&PdPlusSettings::die_bonder(a))?;
        // The experiment shows what a clipped drive does to the path: without the
        // saturation-aware feed the axes fall far behind, which the card's following-error
        // check would (rightly) stop. Open its limit so the run can show it.
        ax.configure_safety(&crate::SafetySettings {
            ferror: 1e9,
            min_ferror: 1e9,
            ..Default::default()
        })?;
        ax.enable()?;
    }
    let g = card.group(0)?;
    g.configure(&GroupSettings::new(&[0, 1]))?;
    g.enable()?;
    let curve = card_emu::yeh::die_bonder_path();
    let f = NurbsFeed {
        feed: DIE_BONDER_FEED,
        accel: 4e7,
        jerk: 4e10,
        chord_tolerance: 1.0,
        saturation: saturation.then_some(0.8),
    };
    let m = g.move_nurbs(&curve, &f, MoveOptions::default())?;
    let mut r = DieBonder {
        umax: PdPlusSettings::die_bonder(0).umax,
        ..Default::default()
    };
    let mut prev: Option<(f64, f64)> = None;
    let t0 = sim.time();
    while g.status()?.0 == GroupState::Moving {
        sim.step(1);
        let (x, y) = (card.axis(0)?.status()?.raw, card.axis(1)?.status()?.raw);
        let t = sim.time() - t0;
        r.max_u[0] = r.max_u[0].max(x.u_request.abs());
        r.max_u[1] = r.max_u[1].max(y.u_request.abs());
        if x.u_request.abs() > r.umax + 1e-9 || y.u_request.abs() > r.umax + 1e-9 {
            r.ticks_over += 1;
        }
        r.u.push((t, x.u_request, y.u_request));
        let c = (x.cmd_pos, y.cmd_pos);
        if let Some(p) = prev {
            let v = (c.0 - p.0).hypot(c.1 - p.1) * 1000.0;
            r.feed.push((t, v));
        }
        prev = Some(c);
        r.path.push((c, (x.act_pos, y.act_pos)));
    }
    m.wait(T)?;
    r.time = sim.time() - t0;
    // Feed fluctuation in the middle of the long straight side (x 20,000..40,000 along the
    // top), where the planner cruises at the commanded feed.
    for (k, &(_, v)) in r.feed.iter().enumerate() {
        let (c, _) = r.path[k + 1];
        if c.0 > 20_000.0 && c.0 < 40_000.0 && c.1 > 19_000.0 {
            r.feed_fluctuation = r
                .feed_fluctuation
                .max((v - DIE_BONDER_FEED).abs() / DIE_BONDER_FEED);
        }
    }
    // Contour error: distance of each actual point from the commanded polyline nearby.
    let cmd: Vec<(f64, f64)> = r.path.iter().map(|p| p.0).collect();
    for (k, &(_, a)) in r.path.iter().enumerate() {
        let lo = k.saturating_sub(400);
        let hi = (k + 400).min(cmd.len() - 1);
        let mut best = f64::INFINITY;
        for i in lo..hi {
            best = best.min(segment_distance(a, cmd[i], cmd[i + 1]));
        }
        if lo < hi {
            r.contour = r.contour.max(best);
        }
    }
    Ok(r)
}

fn segment_distance(p: (f64, f64), a: (f64, f64), b: (f64, f64)) -> f64 {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let l2 = dx * dx + dy * dy;
    let t = if l2 > 0.0 {
        (((p.0 - a.0) * dx + (p.1 - a.1) * dy) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p.0 - a.0 - t * dx).hypot(p.1 - a.1 - t * dy)
}
