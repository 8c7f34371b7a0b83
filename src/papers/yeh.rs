//! Yeh 2008 on the card: the die bonder of Table 1 along a NURBS path with sharp corners, with
//! and without the saturation-aware feed of eq 3.3–3.10, in the paper's units (µm, mm/s).
//!
//! | what | here |
//! | --- | --- |
//! | scale of the die bonder (not in the paper: an assumption) | [`DIE_BONDER_UM_PER_COUNT`] |
//! | Fig 5–7: with and without the saturation-aware feed, per-axis following error against the paper's 100 µm | [`yeh_die_bonder`], [`YEH_FOLLOWING_BOUND_UM`] |
//! | Umax swept with the saturation-aware feed | [`yeh_umax_sweep`] |
//! | plain eq 3.2 / eq 3.1 parameter updates against the card's (eq 3.1 + Newton) | [`taylor_feed_fluctuation`], [`card_feed_fluctuation`], [`yeh_feed_fluctuation`] |

use super::T;
use crate::{
    Card, Clock, EmuOptions, GroupSettings, GroupState, MoveOptions, Nurbs, Result, SimOptions,
};

/// Micrometres per encoder count of the die bonder.
///
/// Yeh gives no lead, gear or scale. What the paper does give: K_e = 1591.5494 in Table 1,
/// which is 10000/(2π), i.e. the AC servo's encoder gives 10,000 counts (pulses) per motor
/// revolution (Fig 6 plots speeds in pulse/ms); the machine is "biaxial" (X, Y) and its
/// following errors are stated in µm ("limited to 100 µm", §4), so we take both axes as linear.
/// Between counts and µm sits the lead of the screw (or belt pulley) per motor revolution,
/// which the paper does not state (Fig 4, a photograph, is missing from our copy). We assume a 10 mm lead, direct-coupled: 10 mm / 10,000 counts = 1 µm/count, the
/// linear scale the rest of this project uses (Shin's corner, the SDK's default chord
/// tolerance). With it the die-bonder path ([`card_emu::presets::die_bonder_path`], 20,000 ×
/// 60,000 counts) is 20 mm × 60 mm, the feed [`DIE_BONDER_FEED`] is 400 mm/s, and X's drive
/// limit (1 DU held: K_c·K_e = 3.99e6 counts/s of motor speed) is 3.99 m/s — plausible for a
/// die bonder's arm. Every µm figure below scales with this number: another lead scales them by
/// lead / 10 mm.
pub const DIE_BONDER_UM_PER_COUNT: f64 = 1.0;

/// Yeh §4: "the following errors for each axis are limited to 100 µm" — the bound the paper
/// states for its algorithm (the solid lines of Fig 5); it gives no number for the run
/// without it, only that the contour deteriorates.
pub const YEH_FOLLOWING_BOUND_UM: f64 = 100.0;

/// Counts to µm on the die bonder ([`DIE_BONDER_UM_PER_COUNT`]).
pub fn um(counts: f64) -> f64 {
    counts * DIE_BONDER_UM_PER_COUNT
}

/// Counts/s to mm/s on the die bonder ([`DIE_BONDER_UM_PER_COUNT`]).
pub fn mm_per_s(counts_per_s: f64) -> f64 {
    counts_per_s * DIE_BONDER_UM_PER_COUNT / 1000.0
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
    /// Largest |commanded − actual position| per axis (the following error Yeh bounds by
    /// 100 µm), counts; [`um`] converts.
    pub following: [f64; 2],
    /// Worst |chord/Ts − V|/V over the ticks at the commanded feed V.
    pub feed_fluctuation: f64,
    /// Mean and least feed over the ticks on the two corner spans of the path (where it is
    /// curved: see [`corner_boxes`]), counts/s.
    pub corner_feed: (f64, f64),
    /// Motion time, s.
    pub time: f64,
    /// With the saturation-aware feed: the time of the look-ahead's own plan, s — the card's
    /// interpolator (same code, same settings) run on the host by its plan alone, without the
    /// per-tick guard of eq 3.6–3.10 that the card adds from the axes' measured state.
    pub planned_time: Option<f64>,
    /// (t, feed counts/s) per tick.
    pub feed: Vec<(f64, f64)>,
    /// (t, u_x, u_y) per tick, V.
    pub u: Vec<(f64, f64, f64)>,
    /// Commanded and actual path, counts.
    pub path: Vec<((f64, f64), (f64, f64))>,
}

/// Feed of the die-bonder runs, counts/s (400 mm/s at [`DIE_BONDER_UM_PER_COUNT`]).
pub const DIE_BONDER_FEED: f64 = 400_000.0;

/// Tangential acceleration and jerk limits of the die-bonder runs, counts/s², counts/s³.
pub const DIE_BONDER_ACCEL_JERK: (f64, f64) = (4e7, 4e10);

/// The fraction of Umax the look-ahead of the saturation-aware runs plans with
/// ([`crate::NurbsFeed::saturation`]); the per-tick guard keeps |u| ≤ Umax itself.
pub const DIE_BONDER_BUDGET: f64 = 0.8;

/// Yeh's die bonder (Table 1 plant and PD+ gains, 1 ms sampling) along a path with two sharp
/// corners, with (`saturation`) or without the saturation-aware feed, at the preset's drive
/// limit (Umax = 10 V = 1 DU).
pub fn yeh_die_bonder(saturation: bool) -> Result<DieBonder> {
    die_bonder_run(saturation, crate::die_bonder_pdplus(0).umax)
}

/// A stepped 1 kHz card whose axes 0 and 1 are the die bonder's X and Y (plant and PD+ of
/// Table 1, drive limit `umax` V on both), grouped, following-error check opened.
fn die_bonder_card(umax: f64) -> Result<(Card, crate::Group)> {
    use crate::{die_bonder_pdplus, die_bonder_plant};
    let mut emu = EmuOptions::new(2, 1000);
    emu.motors[0] = die_bonder_plant(0);
    emu.motors[1] = die_bonder_plant(1);
    let card = Card::open_sim(SimOptions {
        clock: Clock::Stepped,
        emu,
    })?;
    for a in 0..2 {
        let ax = card.axis(a)?;
        ax.configure_pdplus(&crate::PdPlusSettings {
            umax,
            ..die_bonder_pdplus(a)
        })?;
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
    Ok((card, g))
}

/// The two corner spans of the die-bonder path, where it is curved, as boxes
/// `(x_min, x_max, y_min)` in counts: a cubic B-spline span is straight when its four control
/// points are, and only spans 2–3 (left corner) and 8–9 (right) of the twelve are not. The
/// boxes reach from the start of span 2 (8) to the end of span 3 (9).
pub fn corner_boxes() -> [(f64, f64, f64); 2] {
    let c = card_emu::presets::die_bonder_path();
    let p = |u: f64| c.point(u).expect("in the domain");
    let (a, b) = (p(2.0 / 12.0), p(4.0 / 12.0));
    let (d, e) = (p(8.0 / 12.0), p(10.0 / 12.0));
    [(a[0], b[0], a[1]), (d[0], e[0], e[1])]
}

fn die_bonder_run(saturation: bool, umax: f64) -> Result<DieBonder> {
    use crate::NurbsFeed;
    let (card, g) = die_bonder_card(umax)?;
    let sim = card.sim().expect("stepped");
    let curve = card_emu::presets::die_bonder_path();
    let f = NurbsFeed {
        feed: DIE_BONDER_FEED,
        accel: DIE_BONDER_ACCEL_JERK.0,
        jerk: DIE_BONDER_ACCEL_JERK.1,
        chord_tolerance: None, // one count
        saturation: saturation.then_some(DIE_BONDER_BUDGET),
    };
    let m = g.move_nurbs(&curve, &f, MoveOptions::default())?;
    let mut r = DieBonder {
        umax,
        planned_time: if saturation { planned_time(umax) } else { None },
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
    // Following error per axis, over the ticks until the group reports the motion done.
    for &(c, a) in &r.path {
        r.following[0] = r.following[0].max((c.0 - a.0).abs());
        r.following[1] = r.following[1].max((c.1 - a.1).abs());
    }
    // Feed fluctuation in the middle of the long straight side (x 20,000..40,000 along the
    // top), where the planner cruises at the commanded feed; the feed on the corner spans.
    let boxes = corner_boxes();
    let (mut sum, mut n, mut least) = (0.0, 0usize, f64::INFINITY);
    for (k, &(_, v)) in r.feed.iter().enumerate() {
        let (c, _) = r.path[k + 1];
        if c.0 > 20_000.0 && c.0 < 40_000.0 && c.1 > 19_000.0 {
            r.feed_fluctuation = r
                .feed_fluctuation
                .max((v - DIE_BONDER_FEED).abs() / DIE_BONDER_FEED);
        }
        if boxes
            .iter()
            .any(|&(x0, x1, y0)| c.0 >= x0 && c.0 <= x1 && c.1 >= y0)
        {
            sum += v;
            n += 1;
            least = least.min(v);
        }
    }
    r.corner_feed = if n > 0 {
        (sum / n as f64, least)
    } else {
        (f64::NAN, f64::NAN)
    };
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

/// The look-ahead's plan of the saturation-aware run at drive limit `umax` (V, both axes): the
/// card's NURBS interpolator with the firmware's settings (three Newton corrections, one-count
/// chord tolerance) and the die bonder's axis models, stepped by its plan alone; None if the
/// models are refused.
fn planned_time(umax: f64) -> Option<f64> {
    use card_emu::motion::nurbs_interp::{InterpConfig, Interpolator};
    use card_emu::motion::saturation::SaturationAwareFeed;
    let mut p = card_emu::presets::die_bonder_volts();
    for a in p.axes.iter_mut() {
        a.umax = umax;
    }
    let sat = SaturationAwareFeed::new(&p.axes, p.ts).ok()?;
    let cfg = InterpConfig {
        ts: p.ts,
        feed: DIE_BONDER_FEED,
        accel: DIE_BONDER_ACCEL_JERK.0,
        jerk: DIE_BONDER_ACCEL_JERK.1,
        chord_tol: 1.0,
        max_corrections: 3,
    };
    let curve = card_emu::presets::die_bonder_path();
    let mut ip = Interpolator::with_actuator_limits(curve, cfg, &sat, DIE_BONDER_BUDGET).ok()?;
    let mut ticks = 0u32;
    while !ip.is_done() && ticks < 1_000_000 {
        ip.tick().ok()?;
        ticks += 1;
    }
    Some(ticks as f64 * p.ts)
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

// ---------------------------------------------------------------------------------------------
// Umax sweep
// ---------------------------------------------------------------------------------------------

/// The drive limits of the sweep, as fractions of the preset's Umax (10 V = 1 DU): below 0.3
/// the arm's feed-forward alone (kv·w + ka·α) leaves little room, above 1 the DAC clips.
pub const YEH_UMAX_FRACTIONS: [f64; 8] = [0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0];

/// The die bonder with the saturation-aware feed at each drive limit `fraction`·10 V: Umax
/// reaches the card as the PD+ block's `umax` of both axes (the per-tick guard keeps the
/// predicted |u_a| ≤ Umax, eq 3.6–3.10; the look-ahead plans its speed caps and braking with
/// [`DIE_BONDER_BUDGET`]·Umax).
pub fn yeh_umax_sweep(fractions: &[f64]) -> Result<Vec<DieBonder>> {
    let full = crate::die_bonder_pdplus(0).umax;
    fractions
        .iter()
        .map(|f| die_bonder_run(true, f * full))
        .collect()
}

// ---------------------------------------------------------------------------------------------
// Plain eq 3.1 / 3.2 against the card's Newton-corrected step
// ---------------------------------------------------------------------------------------------

/// Yeh's parameter update without corrections.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Taylor {
    /// Eq 3.2: `u_{i+1} = u_i + V·Ts/‖D_i^u‖`.
    FirstOrder,
    /// Eq 3.1: `u_{i+1} = u_i + V·Ts/‖D_i^u‖ − ½·⟨D_i^u, D_i^{u²}⟩·V²·Ts²/‖D_i^u‖⁴`.
    SecondOrder,
}

/// Feed fluctuation |chord/Ts − V|/V over the steps of a run at constant commanded feed V.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Fluctuation {
    /// Largest.
    pub max: f64,
    /// Root mean square.
    pub rms: f64,
    /// Steps measured.
    pub steps: usize,
}

impl Fluctuation {
    fn of(feeds: impl Iterator<Item = f64>, v: f64) -> Self {
        let (mut max, mut sq, mut n) = (0.0f64, 0.0, 0usize);
        for f in feeds {
            let e = (f - v).abs() / v;
            max = max.max(e);
            sq += e * e;
            n += 1;
        }
        Self {
            max,
            rms: if n > 0 { (sq / n as f64).sqrt() } else { 0.0 },
            steps: n,
        }
    }
}

/// Interpolate `curve` at the constant feed `v` (counts/s, sample time `ts` s) with Yeh's plain
/// parameter update `order` (eq 3.2 or eq 3.1, no corrections), from the start to the last
/// step before the end (the final, shorter step onto the end is not counted), and measure
/// |‖C(u_{i+1}) − C(u_i)‖/Ts − V|/V. An offline model of the paper's update, not the card's
/// code.
pub fn taylor_feed_fluctuation(curve: &Nurbs, v: f64, ts: f64, order: Taylor) -> Fluctuation {
    let (mut u, end) = curve.domain();
    let mut feeds = Vec::new();
    let (mut c, mut d1, mut d2) = curve.eval_clamped(u);
    let s = v * ts;
    while u < end {
        let n1 = d1.norm_squared();
        let mut du = s / n1.sqrt(); // Yeh eq 3.2
        if order == Taylor::SecondOrder {
            du -= 0.5 * d1.dot(&d2) * s * s / (n1 * n1); // Yeh eq 3.1
        }
        if !(du.is_finite() && du > 0.0) {
            break;
        }
        u += du;
        if u >= end {
            break;
        }
        let (cn, e1, e2) = curve.eval_clamped(u);
        feeds.push((cn - c).norm() / ts);
        (c, d1, d2) = (cn, e1, e2);
    }
    Fluctuation::of(feeds.into_iter(), v)
}

/// Sample time of the fluctuation runs, s (Yeh's 1 ms).
pub const YEH_TS: f64 = 1e-3;

/// A curved path of the fluctuation comparison: the rational quadratic NURBS circle of radius
/// 5,000 counts (5 mm) through the origin (nine control points, double knots at the quarters).
/// Its parametric speed ‖C'(u)‖ varies by √2 around each quarter, so a step in u is not a fixed
/// step in length; it is only C¹ in u: C'' jumps at the double knots.
pub fn yeh_test_circle() -> Nurbs {
    Nurbs::circle([-5_000.0, 0.0], 5_000.0).expect("a valid circle")
}

/// A curved path of the fluctuation comparison, C² in u: the cubic B-spline (uniform knots,
/// unit weights) whose 30 control points lie every 4,000 counts (4 mm) along x on a sine of
/// amplitude 5,000 counts (5 mm), 0.6 rad per control point, from the origin: 116 mm long
/// in x, radius of curvature above 8 mm.
pub fn yeh_test_sine() -> Nurbs {
    let n = 30;
    let ctrl: Vec<f64> = (0..n)
        .flat_map(|i| {
            let t = i as f64;
            [4_000.0 * t, 5_000.0 * (0.6 * t).sin()]
        })
        .collect();
    let knots = crate::clamped_uniform_knots(n, 3).expect("30 > 3");
    Nurbs::new(3, 2, &ctrl, &[1.0; 30], &knots).expect("a valid curve")
}

/// Feeds of the fluctuation comparison, counts/s (50, 100, 150 mm/s): all below the feed at
/// which the one-count chord tolerance binds on either curve (2·√(2ρδ − δ²)/Ts ≈ 2.0e5
/// counts/s on the 5 mm circle, more on the sine), so the card cruises at the feed.
pub const YEH_FLUCTUATION_FEEDS: [f64; 3] = [50_000.0, 100_000.0, 150_000.0];

/// The card's feed fluctuation on `curve` at feed `v` (counts/s): the curve sent with
/// `move_nurbs` to the stepped 1 kHz die-bonder card (no saturation awareness, one-count chord
/// tolerance), each tick's commanded chord measured over the cruise (from the end of the
/// jerk-limited ramp up, `V/a + a/j` plus 5 ticks, to the same before the end). The card's
/// interpolator steps by eq 3.1 and then Newton-corrects the step until the chord is V·Ts.
pub fn card_feed_fluctuation(curve: &Nurbs, v: f64) -> Result<Fluctuation> {
    let (card, g) = die_bonder_card(crate::die_bonder_pdplus(0).umax)?;
    let sim = card.sim().expect("stepped");
    let (accel, jerk) = (5e6, 5e9);
    let m = g.move_nurbs(
        curve,
        &crate::NurbsFeed::new(v, accel, jerk),
        MoveOptions::default(),
    )?;
    let pos = |card: &Card| -> Result<(f64, f64)> {
        Ok((
            card.axis(0)?.status()?.raw.cmd_pos,
            card.axis(1)?.status()?.raw.cmd_pos,
        ))
    };
    let mut pts = vec![pos(&card)?];
    while g.status()?.0 == GroupState::Moving {
        sim.step(1);
        pts.push(pos(&card)?);
    }
    m.wait(T)?;
    let feeds: Vec<f64> = pts
        .windows(2)
        .map(|w| (w[1].0 - w[0].0).hypot(w[1].1 - w[0].1) / YEH_TS)
        .collect();
    let moving = feeds.iter().rposition(|f| *f > 0.0).unwrap_or(0);
    let ramp = ((v / accel + accel / jerk) / YEH_TS) as usize + 5;
    let cruise = feeds
        .get(ramp..moving.saturating_sub(ramp))
        .unwrap_or_default();
    Ok(Fluctuation::of(cruise.iter().copied(), v))
}

/// One feed of the fluctuation comparison.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FluctuationRow {
    /// Commanded feed, counts/s.
    pub feed: f64,
    /// Plain eq 3.2 (offline).
    pub eq32: Fluctuation,
    /// Plain eq 3.1 (offline).
    pub eq31: Fluctuation,
    /// The card (eq 3.1 + Newton corrections), at cruise.
    pub card: Fluctuation,
}

/// Plain eq 3.2, plain eq 3.1 and the card on `curve` ([`yeh_test_circle`],
/// [`yeh_test_sine`]) at each of `feeds`.
pub fn yeh_feed_fluctuation(curve: &Nurbs, feeds: &[f64]) -> Result<Vec<FluctuationRow>> {
    feeds
        .iter()
        .map(|&v| {
            Ok(FluctuationRow {
                feed: v,
                eq32: taylor_feed_fluctuation(curve, v, YEH_TS, Taylor::FirstOrder),
                eq31: taylor_feed_fluctuation(curve, v, YEH_TS, Taylor::SecondOrder),
                card: card_feed_fluctuation(curve, v)?,
            })
        })
        .collect()
}
