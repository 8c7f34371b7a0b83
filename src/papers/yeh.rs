//! Yeh 2008 on the card: the die bonder of Table 1 along a NURBS path with sharp corners, with
//! and without the saturation-aware feed of eq 3.3–3.10.

use super::T;
use crate::{Card, Clock, EmuOptions, GroupSettings, GroupState, MoveOptions, Result, SimOptions};

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
    use crate::{die_bonder_pdplus, die_bonder_plant, NurbsFeed};
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
        ax.configure_pdplus(&die_bonder_pdplus(a))?;
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
    let curve = card_emu::presets::die_bonder_path();
    let f = NurbsFeed {
        feed: DIE_BONDER_FEED,
        accel: 4e7,
        jerk: 4e10,
        chord_tolerance: None, // one count
        saturation: saturation.then_some(0.8),
    };
    let m = g.move_nurbs(&curve, &f, MoveOptions::default())?;
    let mut r = DieBonder {
        umax: die_bonder_pdplus(0).umax,
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
