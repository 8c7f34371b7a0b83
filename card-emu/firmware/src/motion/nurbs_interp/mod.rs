//! Speed-controlled NURBS interpolation (Yeh & Sun 2008, "NURBS Interpolation for Motion
//! Systems with Actuator Saturation", eq 3.1 and its Newton corrections, with the papers'
//! README corrections of eq 2.2 and eq 3.6): each servo tick the parameter advances by the
//! step that covers the feed's distance along the curve, under a chord-error cap and a
//! look-ahead profile of the speed the curve allows, with the jerk-limited path speed of
//! [`super::path_speed`] and optionally the saturation-aware feed of [`super::saturation`].
//!
//! Units: positions in encoder counts, time in seconds, speeds in counts/s.
//!
//! [`Interpolator::advance`], [`Interpolator::tick`] and [`Interpolator::tick_guarded`]
//! allocate nothing and never panic; construction (profile tables, arc length) allocates once.
//! An interpolator made with [`Interpolator::with_capacity`] has room for the largest curve
//! and profile, and [`Interpolator::load`] plans a curve into it in place: the firmware keeps
//! its curves that way, in storage allocated at boot.

pub use super::interp_error::{InterpError, MAX_CORRECTIONS};
use super::nurbs::{Nurbs, NurbsError, Point, MAX_DIM};
use super::path_speed::PathSpeedPlanner;
use super::pos_finite;
pub use super::saturation::GUARD_MARGIN;
use super::saturation::{AxisSample, FeedDecision, SaturationAwareFeed};
use crate::math;
use crate::ram::FixedVec;

/// Capacity of the look-ahead feed profile (samples along the curve).
pub const MAX_PROFILE: usize = 8192;
/// Interpolator settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InterpConfig {
    /// Sample time Ts, s.
    pub ts: f64,
    /// Commanded feed V, counts/s.
    pub feed: f64,
    /// Tangential acceleration limit, counts/s².
    pub accel: f64,
    /// Tangential jerk limit, counts/s³.
    pub jerk: f64,
    /// Chord-error tolerance δ, counts (1 µm = 1 count on a 1 µm/count scale).
    pub chord_tol: f64,
    /// Newton corrections after the eq 3.1 predictor (0 = plain Taylor).
    pub max_corrections: u32,
}

impl Default for InterpConfig {
    fn default() -> Self {
        Self {
            ts: 1e-3,
            feed: 100_000.0,
            accel: 1e7,
            jerk: 1e10,
            chord_tol: 1.0,
            max_corrections: 3,
        }
    }
}

impl InterpConfig {
    /// Checks every field.
    pub fn validate(&self) -> Result<(), InterpError> {
        if !(pos_finite(self.ts) && self.ts <= 1.0) {
            return Err(InterpError::BadSampleTime);
        }
        if !pos_finite(self.feed) {
            return Err(InterpError::BadFeed);
        }
        if !pos_finite(self.accel) {
            return Err(InterpError::BadAccel);
        }
        if !pos_finite(self.jerk) {
            return Err(InterpError::BadJerk);
        }
        if !pos_finite(self.chord_tol) {
            return Err(InterpError::BadChordTolerance);
        }
        if self.max_corrections > MAX_CORRECTIONS {
            return Err(InterpError::BadCorrections);
        }
        Ok(())
    }
}

/// Largest feed whose one-sample chord error ρ − √(ρ² − (V·Ts/2)²) stays ≤ δ:
/// V ≤ (2/Ts)·√(ρ² − (ρ−δ)²) (= 2ρ/Ts when δ ≥ ρ; ∞ for ρ = ∞).
pub fn chord_feed_limit(rho: f64, ts: f64, tol: f64) -> f64 {
    if rho.is_nan() || rho <= 0.0 {
        return 0.0;
    }
    if rho.is_infinite() {
        return f64::INFINITY;
    }
    if tol >= rho {
        return 2.0 * rho / ts;
    }
    2.0 / ts * math::sqrt(tol * (2.0 * rho - tol))
}

/// Radius of curvature from C' and C'' (any dimension): ρ = |C'|³ / √(|C'|²|C''|² − (C'·C'')²).
pub fn radius_of_curvature(d1: &Point, d2: &Point) -> f64 {
    let n1 = d1.norm_squared();
    if n1 <= 0.0 || !n1.is_finite() {
        return 0.0;
    }
    let dd = d1.dot(d2);
    let perp2 = (d2.norm_squared() - dd * dd / n1).max(0.0);
    if perp2 == 0.0 {
        return f64::INFINITY;
    }
    // κ = |C''_⊥| / |C'|²
    n1 / math::sqrt(perp2)
}

/// One interpolation sample (the reference for the servo loops).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tick {
    /// Curve parameter u_{k}.
    pub u: f64,
    /// θ_d\[k\] = C(u_k), counts.
    pub pos: Point,
    /// w_d\[k\] = (θ_d\[k\]-θ_d\[k-1\])/Ts, counts/s.
    pub vel: Point,
    /// α_d\[k\] = (w_d\[k\]-w_d\[k-1\])/Ts, counts/s².
    pub acc: Point,
    /// |θ_d\[k\]-θ_d\[k-1\]|/Ts, counts/s.
    pub feed: f64,
    /// The end of the curve has been reached (pos == C(u_end)).
    pub done: bool,
    /// Newton corrections used in this step.
    pub corrections: u32,
}

#[derive(Debug, Clone, Copy, Default, PartialEq)]
struct ProfileSample {
    /// Arc length from the start, counts.
    s: f64,
    /// Local limit: feed, chord error (and actuator speed cap), counts/s.
    raw: f64,
    /// `raw` after the backward pass (reachable with the deceleration limit, 0 at the end).
    cap: f64,
    /// Curve parameter of the sample.
    u: f64,
    /// ds/du = |C'(u)| at the sample.
    ds_du: f64,
}

/// Samples per block of the block-minimum table used to skip the look-ahead scan.
const BLOCK: usize = 32;
/// Blocks of the largest profile.
const BLOCKS: usize = MAX_PROFILE.div_ceil(BLOCK);

#[derive(Clone, Copy)]
struct Step {
    u: f64,
    c: Point,
    d1: Point,
    d2: Point,
    chord: f64,
    landed: bool,
    corrections: u32,
}

/// Speed-controlled NURBS interpolator (Yeh eq 3.1 predictor + Newton corrector), with a
/// look-ahead feed profile (chord-error and optional actuator limits), a jerk-limited path
/// speed planner and the optional saturation-aware feed of §3.4.
///
/// Per tick: [`advance`](Self::advance) (fixed feed, no limits), [`tick`](Self::tick)
/// (planner + limits) or [`tick_guarded`](Self::tick_guarded) (planner + limits + Yeh's
/// saturation check). Each returns θ_d\[k\], w_d\[k\], α_d\[k\] for the servo loops.
#[derive(Clone)]
pub struct Interpolator {
    curve: Nurbs,
    cfg: InterpConfig,
    /// The look-ahead profile (at most `MAX_PROFILE` samples).
    profile: FixedVec<ProfileSample, MAX_PROFILE>,
    /// Smallest `raw` of each `BLOCK` samples of the profile.
    blocks: FixedVec<f64, BLOCKS>,
    length: f64,
    slow: Option<(f64, f64)>,
    planner: PathSpeedPlanner,
    u_end: f64,
    u: f64,
    pos: Point,
    d1: Point,
    d2: Point,
    prev_vel: Point,
    /// Arc length from the start to the current point (table + Hermite), counts.
    s: f64,
    done: bool,
    hint: usize,
    /// Profile index with `profile[hint_u].u ≤ u` (for the arc position).
    hint_u: usize,
    /// C(u_end) and the unit tangents at both ends (for joining the next curve).
    end_pos: Point,
    start_tan: Point,
    end_tan: Point,
    /// The last step as planned (counts), the point and the speed command before it.
    last_plan: f64,
    before_pos: Point,
    before_vel: Point,
    /// Knot span of the last evaluation (the curve is walked along: the span search is skipped).
    span: core::cell::Cell<usize>,
}

/// The curve queued after the one running, when the motion may run into it without stopping
/// (see [`Interpolator::continuation`]): its length and look-ahead profile extend the running
/// curve's, with the speed at the joint capped.
#[derive(Clone, Copy)]
pub struct Continuation<'a> {
    next: &'a Interpolator,
    joint_cap: f64,
}

impl Continuation<'_> {
    /// Speed allowed through the joint, counts/s.
    pub fn joint_cap(&self) -> f64 {
        self.joint_cap
    }
}

/// 5-point Gauss–Legendre nodes on [−1, 1] (also used by `path`'s blends).
pub(super) const GL_X: [f64; 5] = [
    0.0,
    -0.538_469_310_105_683_1,
    0.538_469_310_105_683_1,
    -0.906_179_845_938_664,
    0.906_179_845_938_664,
];
/// 5-point Gauss–Legendre weights.
pub(super) const GL_W: [f64; 5] = [
    0.568_888_888_888_888_9,
    0.478_628_670_499_366_5,
    0.478_628_670_499_366_5,
    0.236_926_885_056_189_1,
    0.236_926_885_056_189_1,
];

/// 5-point Gauss–Legendre of |C'| on [a, b].
fn gl5(curve: &Nurbs, a: f64, b: f64) -> f64 {
    let h = 0.5 * (b - a);
    let m = 0.5 * (a + b);
    GL_X.iter()
        .zip(GL_W.iter())
        .map(|(x, w)| w * curve.eval_clamped(m + h * x).1.norm())
        .sum::<f64>()
        * h
}

/// Adaptive Gauss–Legendre arc length of `curve` on [a, b]: an interval is accepted when
/// its two halves agree with the whole within its share of 1e-11 of the estimate (never below
/// the rounding floor); depth ≤ 30 and at most 4096 accepted pieces, fixed stack.
pub fn arc_length(curve: &Nurbs, a: f64, b: f64) -> f64 {
    if b.partial_cmp(&a) != Some(core::cmp::Ordering::Greater) {
        return 0.0;
    }
    let whole0 = gl5(curve, a, b);
    if !whole0.is_finite() {
        // The derivative overflows (a knot span of 1e-300, say): no refinement helps, and
        // splitting non-finite pieces down to the limits below took seconds per call. The
        // caller refuses a curve whose length is not finite.
        return whole0;
    }
    // Rounding floor: the length of a piece cannot be resolved below the rounding of the
    // coordinates it is computed from. Relative to the estimate alone, a piece where the curve
    // stands still (coincident control points) never converged: its estimate is rounding
    // noise, and every call split it to the limits below (5 s for one curve).
    let scale = curve
        .eval_clamped(a)
        .0
        .amax()
        .max(curve.eval_clamped(b).0.amax());
    let floor = 64.0 * f64::EPSILON * whole0.abs().max(scale);
    let mut stack = [(0.0f64, 0.0f64, 0.0f64, 0.0f64, 0u32); 64];
    let mut top = 1;
    stack[0] = (a, b, whole0, 1e-11 * whole0.abs(), 0);
    let mut total = 0.0;
    let mut pieces = 0u32;
    while top > 0 {
        top -= 1;
        let (lo, hi, whole, tol, depth) = stack[top];
        let mid = 0.5 * (lo + hi);
        let l = gl5(curve, lo, mid);
        let r = gl5(curve, mid, hi);
        if !(l + r).is_finite() {
            return l + r;
        }
        let done = (l + r - whole).abs() <= tol.max(floor)
            || depth >= 30
            || pieces >= 4096
            || top + 2 > stack.len();
        if done {
            total += l + r;
            pieces += 1;
        } else {
            stack[top] = (mid, hi, r, 0.5 * tol, depth + 1);
            stack[top + 1] = (lo, mid, l, 0.5 * tol, depth + 1);
            top += 2;
        }
    }
    total
}

/// Share of the planning budget kept for tangential deceleration; the rest bounds the
/// speed-and-curvature part `kv·w + ka·v²κ` of the drive.
pub const DECEL_SHARE: f64 = 0.5;

/// Actuator limits used when building the look-ahead profile.
#[derive(Clone, Copy)]
struct ActuatorPlan<'a> {
    sat: &'a SaturationAwareFeed,
    budget: f64,
}

impl ActuatorPlan<'_> {
    /// Largest V with kv·V·|T_j| + ka·V²·|k_j| ≤ (1−DECEL_SHARE)·budget·Umax on every axis
    /// (steady PD+ drive without tangential acceleration), so that a tangential deceleration
    /// of DECEL_SHARE·budget·Umax/ka still fits everywhere.
    fn speed_cap(&self, t: &Point, k: &Point) -> f64 {
        let mut cap = f64::INFINITY;
        for (j, ax) in self.sat.axes[..self.sat.dim].iter().enumerate() {
            let b = (1.0 - DECEL_SHARE) * self.budget * ax.umax;
            let qa = ax.gains.ka * k[j].abs();
            let qb = ax.gains.kv * t[j].abs();
            // positive root of qa V² + qb V - b = 0
            cap = cap.min(smallest_positive_root(qa, qb, -b));
        }
        cap
    }

    /// Largest tangential deceleration (≥ 0) at speed V within budget·Umax on every axis.
    fn decel(&self, t: &Point, k: &Point, v: f64, amax: f64) -> f64 {
        let mut a_lo = -amax;
        let mut a_hi = amax;
        for (j, ax) in self.sat.axes[..self.sat.dim].iter().enumerate() {
            let g = &ax.gains;
            let tj = t[j];
            if g.ka <= 0.0 || tj == 0.0 {
                continue;
            }
            let b = self.budget * ax.umax;
            let base = g.kv * v * tj + g.ka * v * v * k[j];
            // -b ≤ base + ka·a·T_j ≤ b
            let m_lo = (-b - base) / (g.ka * tj);
            let m_hi = (b - base) / (g.ka * tj);
            let (lo, hi) = if tj > 0.0 { (m_lo, m_hi) } else { (m_hi, m_lo) };
            a_lo = a_lo.max(lo);
            a_hi = a_hi.min(hi);
        }
        if a_lo > a_hi {
            0.0
        } else {
            (-a_lo).max(0.0)
        }
    }
}

fn smallest_positive_root(a: f64, b: f64, c: f64) -> f64 {
    let mut best = f64::INFINITY;
    if a == 0.0 {
        if b != 0.0 {
            let r = -c / b;
            if r > 0.0 {
                best = r;
            }
        }
        return best;
    }
    let disc = b * b - 4.0 * a * c;
    if disc < 0.0 {
        return best;
    }
    let sq = math::sqrt(disc);
    // numerically stable pair
    let q = -0.5 * (b + b.signum() * sq);
    for r in [q / a, if q != 0.0 { c / q } else { f64::NAN }] {
        if r > 0.0 && r < best {
            best = r;
        }
    }
    best
}

fn unit_tangent_and_curvature(d1: &Point, d2: &Point) -> (Point, Point) {
    let n1 = d1.norm_squared();
    if n1 <= 0.0 || !n1.is_finite() {
        return (Point::zeros(), Point::zeros());
    }
    let t = d1 / math::sqrt(n1);
    // curvature vector d²C/ds² = (C'' - (C''·T)T)/|C'|²
    let k = (d2 - t * d2.dot(&t)) / n1;
    (t, k)
}

impl Interpolator {
    /// Interpolator with the chord-error / tangential-acceleration look-ahead profile.
    pub fn new(curve: Nurbs, cfg: InterpConfig) -> Result<Self, InterpError> {
        Self::build(curve, cfg, None)
    }

    /// Like [`new`](Self::new), but the look-ahead also keeps the steady-state PD+ drive
    /// `kv·w + ka·α` of every axis within `budget·Umax` (budget in (0, 1]): speed caps use
    /// `(1 − DECEL_SHARE)·budget·Umax` for `kv·v + ka·v²κ`, and the planner brakes with at
    /// most `DECEL_SHARE·budget·Umax/ka` (worst axis; `cfg.accel` still bounds speeding up,
    /// which the per-tick guard trims). The rest of Umax is for the feedback terms; the
    /// exact |u| ≤ Umax check is [`tick_guarded`](Self::tick_guarded)'s.
    ///
    /// Yeh's §3.4 alone is reactive: at a sharp corner an axis may have to stop faster than
    /// Umax allows, and no feed then exists; this look-ahead keeps it feasible.
    pub fn with_actuator_limits(
        curve: Nurbs,
        cfg: InterpConfig,
        sat: &SaturationAwareFeed,
        budget: f64,
    ) -> Result<Self, InterpError> {
        let act = actuator_plan(&curve, sat, budget)?;
        Self::build(curve, cfg, Some(act))
    }

    /// An interpolator with room for the largest curve ([`MAX_CTRL`](super::nurbs::MAX_CTRL)
    /// control points) and the largest profile ([`MAX_PROFILE`] samples), allocated once and
    /// not touched until used, holding no motion: it is done, at rest at (0, 0), until
    /// [`load`](Self::load) plans a curve into it.
    pub fn with_capacity() -> Self {
        let mut ip = Self::shell(
            Nurbs::with_capacity(),
            FixedVec::with_capacity(MAX_PROFILE),
            FixedVec::with_capacity(BLOCKS),
        );
        ip.done = true;
        ip
    }

    /// Plan the curve [`Nurbs::new`] would build from `degree`, `dim`, `ctrl`, `weights` and
    /// `knots` into this interpolator's storage: [`set_curve`](Self::set_curve), then
    /// [`plan_curve`](Self::plan_curve).
    #[allow(clippy::too_many_arguments)]
    pub fn load(
        &mut self,
        degree: usize,
        dim: usize,
        ctrl: &[f64],
        weights: &[f64],
        knots: &[f64],
        cfg: InterpConfig,
        limits: Option<(&SaturationAwareFeed, f64)>,
    ) -> Result<(), InterpError> {
        self.set_curve(degree, dim, ctrl, weights, knots)?;
        self.plan_curve(cfg, limits)
    }

    /// Hold the curve [`Nurbs::new`] would build from the same arguments, in this
    /// interpolator's storage (no allocation when it has the room, see
    /// [`with_capacity`](Self::with_capacity)), not planned yet: no motion (done, at rest)
    /// until [`plan_curve`](Self::plan_curve).
    pub fn set_curve(
        &mut self,
        degree: usize,
        dim: usize,
        ctrl: &[f64],
        weights: &[f64],
        knots: &[f64],
    ) -> Result<(), NurbsError> {
        self.done = true;
        self.profile.clear();
        self.blocks.clear();
        self.length = 0.0;
        self.curve.set(degree, dim, ctrl, weights, knots)
    }

    /// Plan the curve held, as [`new`](Self::new) (`limits` None) or
    /// [`with_actuator_limits`](Self::with_actuator_limits) (`limits` = the feed model and the
    /// budget) would: the profile goes into this interpolator's storage. On an error there is
    /// no motion (done, at rest).
    pub fn plan_curve(
        &mut self,
        cfg: InterpConfig,
        limits: Option<(&SaturationAwareFeed, f64)>,
    ) -> Result<(), InterpError> {
        self.done = true;
        let act = match limits {
            Some((sat, budget)) => Some(actuator_plan(&self.curve, sat, budget)?),
            None => None,
        };
        self.plan(cfg, act)
    }

    /// An interpolator of `curve` with the given (empty) profile storage, not planned.
    fn shell(
        curve: Nurbs,
        profile: FixedVec<ProfileSample, MAX_PROFILE>,
        blocks: FixedVec<f64, BLOCKS>,
    ) -> Self {
        let cfg = InterpConfig::default();
        Self {
            curve,
            cfg,
            profile,
            blocks,
            length: 0.0,
            slow: None,
            planner: PathSpeedPlanner::unplanned(),
            u_end: 0.0,
            u: 0.0,
            pos: Point::zeros(),
            d1: Point::zeros(),
            d2: Point::zeros(),
            prev_vel: Point::zeros(),
            s: 0.0,
            done: false,
            hint: 0,
            hint_u: 0,
            end_pos: Point::zeros(),
            start_tan: Point::zeros(),
            end_tan: Point::zeros(),
            last_plan: 0.0,
            before_pos: Point::zeros(),
            before_vel: Point::zeros(),
            span: core::cell::Cell::new(0),
        }
    }

    fn build(
        curve: Nurbs,
        cfg: InterpConfig,
        act: Option<ActuatorPlan<'_>>,
    ) -> Result<Self, InterpError> {
        let mut ip = Self::shell(curve, FixedVec::new(), FixedVec::new());
        ip.plan(cfg, act)?;
        Ok(ip)
    }

    /// Plan this interpolator's curve: the look-ahead profile (into its storage) and the
    /// start, at rest.
    fn plan(
        &mut self,
        cfg: InterpConfig,
        act: Option<ActuatorPlan<'_>>,
    ) -> Result<(), InterpError> {
        self.done = true;
        cfg.validate()?;
        let mut planner = PathSpeedPlanner::new(cfg.ts, cfg.accel, cfg.jerk)?;
        if let Some(a) = act {
            // braking may use DECEL_SHARE of the budget on any axis (the speed caps leave it)
            planner =
                planner.with_decel(cfg.accel.min(a.sat.safe_path_decel(DECEL_SHARE * a.budget)))?;
        }
        build_profile(
            &self.curve,
            &cfg,
            planner.decel_limit(),
            act,
            &mut self.profile,
        )?;
        self.blocks.clear();
        for c in self.profile.chunks(BLOCK) {
            // BLOCKS blocks of BLOCK hold the largest profile
            let _ = self
                .blocks
                .push(c.iter().fold(f64::INFINITY, |m, x| m.min(x.raw)));
        }
        let length = self.profile.last().map_or(0.0, |p| p.s);
        if !(length.is_finite() && length > 0.0) {
            return Err(InterpError::ZeroLengthCurve);
        }
        let curve = &self.curve;
        let (u0, u_end) = curve.domain();
        let (pos, d1, d2) = curve.eval(u0)?;
        let (end_pos, e1, _) = curve.eval(u_end)?;
        let unit = |d: Point| {
            let n = d.norm();
            if n > 0.0 {
                d / n
            } else {
                Point::zeros()
            }
        };
        self.cfg = cfg;
        self.length = length;
        self.planner = planner;
        self.u_end = u_end;
        self.end_pos = end_pos;
        self.start_tan = unit(d1);
        self.end_tan = unit(e1);
        self.span = core::cell::Cell::new(0);
        self.start_at(u0, pos, d1, d2);
        Ok(())
    }

    /// Back to the start of the curve, at rest.
    pub fn reset(&mut self) {
        let (u0, _) = self.curve.domain();
        let (pos, d1, d2) = self.curve.eval_clamped(u0);
        self.start_at(u0, pos, d1, d2);
        self.planner.rest();
    }

    /// The motion state at the curve's start `u0` (point `pos`, derivatives `d1`, `d2`),
    /// nothing run yet.
    fn start_at(&mut self, u0: f64, pos: Point, d1: Point, d2: Point) {
        self.u = u0;
        self.pos = pos;
        self.d1 = d1;
        self.d2 = d2;
        self.prev_vel = Point::zeros();
        self.s = 0.0;
        self.done = false;
        self.hint = 0;
        self.hint_u = 0;
        self.slow = None;
        self.last_plan = 0.0;
        self.before_pos = pos;
        self.before_vel = Point::zeros();
    }

    /// The curve.
    pub fn curve(&self) -> &Nurbs {
        &self.curve
    }
    /// Settings.
    pub fn config(&self) -> &InterpConfig {
        &self.cfg
    }
    /// Arc length of the whole curve (adaptive Gauss–Legendre), counts.
    pub fn length(&self) -> f64 {
        self.length
    }
    /// Arc length from the start of the curve to the current point, counts.
    pub fn travelled(&self) -> f64 {
        self.s
    }
    /// Current parameter.
    pub fn u(&self) -> f64 {
        self.u
    }
    /// Current reference position θ_d\[k\].
    pub fn position(&self) -> Point {
        self.pos
    }
    /// Current reference speed command w_d\[k\].
    pub fn velocity(&self) -> Point {
        self.prev_vel
    }
    /// End reached.
    pub fn is_done(&self) -> bool {
        self.done
    }
    /// The path-speed planner's state.
    pub fn planner(&self) -> &PathSpeedPlanner {
        &self.planner
    }
    /// Look-ahead speed limit at path length `s` (counts/s).
    pub fn profile_cap(&self, s: f64) -> f64 {
        let mut h = 0;
        cap_at(&self.profile, s, &mut h)
    }
    /// The length of the last step as it was planned, counts; more than the step taken when
    /// the curve ended inside it (the rest belongs to the next curve, see
    /// [`take_over`](Self::take_over)).
    pub fn last_planned_step(&self) -> f64 {
        self.last_plan
    }

    /// The next curve as a continuation of this one, or None when the motion must stop at the
    /// joint: the next curve has other tangential limits or sample time, does not start where
    /// this one ends (within 1e-6 counts), or turns there. Through a joint whose tangents differ
    /// by an angle θ the speed is capped at A·Ts/θ (the change of the velocity direction in one
    /// tick stays within the acceleration limit), and at both curves' local limits.
    pub fn continuation<'a>(&self, next: &'a Interpolator) -> Option<Continuation<'a>> {
        let (a, b) = (&self.planner, &next.planner);
        if self.curve.dim() != next.curve.dim()
            || a.ts != b.ts
            || a.amax != b.amax
            || a.dmax != b.dmax
            || a.jmax != b.jmax
            || (self.end_pos - next.pos).norm() > 1e-6
        {
            return None;
        }
        // turning back (or a zero tangent): no speed through the joint
        if self.end_tan.dot(&next.start_tan) <= 0.0 {
            return None;
        }
        // the angle from its chord: accurate for small angles, unlike acos
        let theta = 2.0 * math::asin((0.5 * (self.end_tan - next.start_tan).norm()).min(1.0));
        let turn = if theta > 0.0 {
            a.amax.min(a.dmax) * a.ts / theta
        } else {
            f64::INFINITY
        };
        let own = self.profile.last().map_or(0.0, |p| p.raw);
        let theirs = next.profile.first().map_or(0.0, |p| p.raw);
        let cap = turn
            .min(own)
            .min(theirs)
            .min(self.cfg.feed)
            .min(next.cfg.feed);
        (cap > 0.0).then_some(Continuation {
            next,
            joint_cap: cap,
        })
    }

    /// Hermite arc length s(u) from the profile table (s and ds/du at the samples), moving
    /// `hint_u` along; `precise` integrates the partial sample interval instead (5-point
    /// Gauss–Legendre inside one interval, which holds no knot).
    fn arc_at(&mut self, u: f64, precise: bool) -> f64 {
        let p = &self.profile;
        let n = p.len();
        if n < 2 || u >= self.u_end {
            return self.length;
        }
        let mut i = self.hint_u.min(n - 2);
        while i > 0 && p[i].u > u {
            i -= 1;
        }
        while i + 2 < n && p[i + 1].u <= u {
            i += 1;
        }
        self.hint_u = i;
        let (a, b) = (p[i], p[i + 1]);
        let h = b.u - a.u;
        if h <= 0.0 || u <= a.u {
            return a.s;
        }
        if precise {
            return a.s + gl5(&self.curve, a.u, u.min(b.u));
        }
        let t = ((u - a.u) / h).clamp(0.0, 1.0);
        let (t2, t3) = (t * t, t * t * t);
        (2.0 * t3 - 3.0 * t2 + 1.0) * a.s
            + (t3 - 2.0 * t2 + t) * h * a.ds_du
            + (-2.0 * t3 + 3.0 * t2) * b.s
            + (t3 - t2) * h * b.ds_du
    }

    /// Solves |C(u) − c0| = len for u ≥ u0 in this curve: Yeh eq 3.1 predictor from u0 (with
    /// C'(u0) = `d1`, C''(u0) = `d2`) for a step of `guess`, then safeguarded Newton corrections on
    /// f(u) = |C(u) − c0| − len, f'(u) = ⟨C(u)−c0, C'(u)⟩/|C(u)−c0|. Lands on C(u_end) when
    /// the end is closer than `len`.
    #[allow(clippy::too_many_arguments)]
    fn solve(&self, u0: f64, c0: Point, d1: &Point, d2: &Point, len: f64, guess: f64) -> Step {
        let ue = self.u_end;
        let mut st = Step {
            u: u0,
            c: c0,
            d1: *d1,
            d2: *d2,
            chord: 0.0,
            landed: false,
            corrections: 0,
        };
        if len.is_nan() || len <= 0.0 || u0 >= ue {
            st.landed = u0 >= ue;
            if st.landed {
                st.c = self.end_pos;
                st.chord = (self.end_pos - c0).norm();
            }
            return st;
        }
        let n1 = d1.norm_squared();
        // Yeh eq 3.1: u_{i+1} = u_i + V Ts/‖D‖ − ½ ⟨D, D²⟩ V² Ts² / ‖D‖⁴
        let mut du = if guess <= 0.0 {
            0.0
        } else if n1 > 0.0 {
            let du2 = guess / math::sqrt(n1) - 0.5 * d1.dot(d2) * guess * guess / (n1 * n1);
            if du2 > 0.0 {
                du2
            } else {
                guess / math::sqrt(n1) // Yeh eq 3.2 (first order) when the second-order term dominates
            }
        } else {
            f64::NAN
        };
        if !(du.is_finite() && du >= 0.0) {
            // |C'| = 0 here: C(u) ≈ C0 + ½C''Δu² gives Δu = √(2 len/|C''|)
            let n2 = d2.norm();
            du = if n2 > 0.0 {
                math::sqrt(2.0 * guess / n2)
            } else {
                1e-6 * (ue - u0)
            };
        }
        self.newton(u0, c0, len, u0 + du)
    }

    /// Newton on f(u) = |C(u) − c0| − len for u in (u0, u_end] from `u_start` (see `solve`).
    fn newton(&self, u0: f64, c0: Point, len: f64, u_start: f64) -> Step {
        let ue = self.u_end;
        let mut st;
        let mut u = u_start;
        let mut lo = u0;
        let mut hi = f64::NAN;
        // 1e-12 relative, but not below what the coordinates resolve
        let tol = (1e-12 * len).max(8.0 * f64::EPSILON * c0.amax());
        let mut corrections = 0;
        loop {
            if u.is_nan() || u >= ue {
                u = ue;
            }
            let (c, e1, e2) = self.eval(u);
            let chord = c - c0;
            let dist = chord.norm();
            let f = dist - len;
            st = Step {
                u,
                c,
                d1: e1,
                d2: e2,
                chord: dist,
                landed: false,
                corrections,
            };
            if u >= ue && f <= 0.0 {
                st.landed = true;
                return st;
            }
            if f.abs() <= tol || corrections >= self.cfg.max_corrections {
                return st;
            }
            if f < 0.0 {
                lo = u;
            } else {
                hi = u;
            }
            // Newton on f(u) = |C(u) - c0| - len, kept inside the bracket (lo, hi);
            // bisection / expansion when the Newton step leaves it.
            let fp = if dist > 0.0 {
                chord.dot(&e1) / dist
            } else {
                0.0
            };
            let upper = if hi.is_finite() { hi } else { ue };
            let mut un = u - f / fp;
            if !(fp > 0.0 && un.is_finite() && un > lo && un < upper) {
                un = if hi.is_finite() {
                    0.5 * (lo + hi)
                } else {
                    (u + 2.0 * (u - u0).max(1e-12 * (ue - u0))).min(ue)
                };
            }
            corrections += 1;
            u = un;
        }
    }

    /// C, C', C'' at `u` (clamped into the domain), starting the span search at the last one.
    fn eval(&self, u: f64) -> (Point, Point, Point) {
        let mut h = self.span.get();
        let r = self.curve.eval_hinted(u, &mut h);
        self.span.set(h);
        r
    }

    /// The step onto the end of the curve.
    fn land_step(&self) -> Step {
        let (c, d1, d2) = self.curve.eval_clamped(self.u_end);
        Step {
            u: self.u_end,
            c,
            d1,
            d2,
            chord: (c - self.pos).norm(),
            landed: true,
            corrections: 0,
        }
    }

    /// A step of chord `len` from the current point.
    fn solve_step(&self, len: f64) -> Step {
        self.solve(self.u, self.pos, &self.d1, &self.d2, len, len)
    }

    /// A step of chord `len` from the current point, starting from `near`, a step of another
    /// length (one Newton step ahead of it: d|C(u) − C0|/du = ⟨C − C0, C'⟩/|C − C0|).
    fn solve_step_near(&self, near: &Step, len: f64) -> Step {
        let chord = near.c - self.pos;
        let fp = if near.chord > 0.0 {
            chord.dot(&near.d1) / near.chord
        } else {
            0.0
        };
        let u = near.u + (len - near.chord) / fp;
        if near.landed || !(fp > 0.0 && u.is_finite() && u > self.u) {
            return self.solve_step(len);
        }
        if len.is_nan() || len <= 0.0 {
            return self.solve_step(len);
        }
        self.newton(self.u, self.pos, len, u)
    }

    fn commit(&mut self, st: &Step) -> Tick {
        let ts = self.cfg.ts;
        let vel = (st.c - self.pos) / ts;
        let acc = (vel - self.prev_vel) / ts;
        self.before_pos = self.pos;
        self.before_vel = self.prev_vel;
        self.u = st.u;
        self.pos = st.c;
        self.d1 = st.d1;
        self.d2 = st.d2;
        self.prev_vel = vel;
        if st.landed {
            self.done = true;
            self.s = self.length;
        } else {
            self.s = self.arc_at(st.u, false);
        }
        Tick {
            u: st.u,
            pos: st.c,
            vel,
            acc,
            feed: st.chord / ts,
            done: self.done,
            corrections: st.corrections,
        }
    }

    fn hold(&mut self) -> Tick {
        let acc = -self.prev_vel / self.cfg.ts;
        self.before_pos = self.pos;
        self.before_vel = self.prev_vel;
        self.prev_vel = Point::zeros();
        self.last_plan = 0.0;
        Tick {
            u: self.u,
            pos: self.pos,
            vel: Point::zeros(),
            acc,
            feed: 0.0,
            done: true,
            corrections: 0,
        }
    }

    /// One sample at feed `v` (counts/s) with no planner and no limits: the chord
    /// |C(u_{k+1}) − C(u_k)| equals `v·Ts` (to 1e-12 relative when corrections are allowed),
    /// except the last step, which lands on C(u_end). After the end, holds it.
    pub fn advance(&mut self, v: f64) -> Result<Tick, InterpError> {
        if !(v.is_finite() && v >= 0.0) {
            return Err(InterpError::BadFeed);
        }
        if self.done {
            return Ok(self.hold());
        }
        self.last_plan = v * self.cfg.ts;
        let st = self.solve_step(v * self.cfg.ts);
        Ok(self.commit(&st))
    }

    /// Continues the motion of `prev`, the curve before this one, which ended inside its last
    /// step: this tick's point is where this curve is at the planned step's chord length from
    /// the point `prev` started the step at, so the feed stays what was planned across the
    /// joint; the path-speed planner carries on from `prev`'s state.
    pub fn take_over(&mut self, prev: &Interpolator) -> Result<Tick, InterpError> {
        if prev.curve.dim() != self.curve.dim() {
            return Err(InterpError::DimensionMismatch {
                expected: self.curve.dim(),
                got: prev.curve.dim(),
            });
        }
        self.planner.continue_from(&prev.planner);
        self.slow = None;
        let len = prev.last_plan;
        let c0 = prev.before_pos;
        let guess = (len - (prev.pos - c0).norm()).max(0.0);
        let st = self.solve(self.u, c0, &self.d1, &self.d2, len, guess);
        self.pos = c0;
        self.prev_vel = prev.before_vel;
        self.last_plan = len;
        Ok(self.commit(&st))
    }

    /// Speed limits for this tick: (target for the planner, hard ceiling).
    ///
    /// The target is the commanded feed, lowered to the local chord-error limit and to any
    /// limit ahead that the planner must start slowing for now (distance to it ≤ its
    /// jerk-limited slowing distance); the ceiling is the local limit (chord error here and
    /// the backward-passed profile). With a continuation, the joint's speed cap and the next
    /// curve's profile are limits ahead too.
    fn limits(&mut self, next: Option<&Continuation<'_>>) -> (f64, f64) {
        let cfg = self.cfg;
        let cap_here = cap_at(&self.profile, self.s, &mut self.hint);
        let chord_here = chord_feed_limit(
            radius_of_curvature(&self.d1, &self.d2),
            cfg.ts,
            cfg.chord_tol,
        );
        let ceiling = cfg.feed.min(chord_here).min(cap_here);
        if matches!(self.slow, Some((sc, _)) if self.s >= sc) {
            self.slow = None;
        }
        let mut target = match self.slow {
            Some((_, c)) => ceiling.min(c),
            None => ceiling,
        };
        // Check the tracker's next state against every lower limit within reach: if from
        // that state a limit could no longer be met, slow for it from now on (latched until
        // it is passed). The lowest violated limit wins.
        let pl = self.planner;
        let (jp, dp) = pl.plan_limits();
        let v = pl.v;
        for _ in 0..3 {
            let (step, vn, an) = pl.track_step(target);
            // the speed reached before the acceleration is back to zero
            let vmax = v
                .max(vn)
                .max(vn + math::powi(an.max(0.0), 2) / (2.0 * pl.jmax));
            let reach = PathSpeedPlanner::stopping_distance(vmax, an.max(pl.a).max(0.0), dp, jp)
                + 2.0 * vmax * cfg.ts;
            let mut worst: Option<(f64, f64)> = None;
            let here = self.s;
            // only limits below both the speed and the target matter
            let below = vmax.min(target);
            // Bounds of the slowing distance to c first, the exact one only between them. With
            // vf the speed once a⁺ is back to zero (≤ vf·a⁺/J of path): at least (vf² − c²)/2D
            // (deceleration ≤ D), at most (vf + c)/2 · ((vf − c)/D + D/J) more (the ramps into
            // and out of the deceleration, or a triangle whose time 2√((vf − c)/J) is no more).
            let (jm, dm) = (pl.jmax, pl.dmax);
            let ap = an.max(0.0);
            let vf = vn + ap * ap / (2.0 * jm);
            let rising = vf * ap / jm;
            let mut consider = |s_abs: f64, raw: f64| {
                if raw < vmax && raw < target && worst.is_none_or(|(_, c)| raw < c) {
                    let dist = s_abs - here - step;
                    let lower = (vf * vf - raw * raw) / (2.0 * dm);
                    let upper = rising + 0.5 * (vf + raw) * ((vf - raw) / dm + dm / jm);
                    let violated = dist < lower
                        || (dist < upper && dist < pl.slowing_distance_from(vn, an, raw));
                    if violated {
                        worst = Some((s_abs, raw));
                    }
                }
            };
            scan(
                &self.profile,
                &self.blocks,
                self.hint + 1,
                0.0,
                here + reach,
                below,
                &mut consider,
            );
            if let Some(c) = next {
                if self.length <= here + reach {
                    consider(self.length, c.joint_cap);
                    let n = c.next;
                    scan(
                        &n.profile,
                        &n.blocks,
                        0,
                        self.length,
                        here + reach,
                        below,
                        &mut consider,
                    );
                }
            }
            match worst {
                Some((sc, c)) => {
                    self.slow = Some((sc, c));
                    target = target.min(c);
                }
                None => break,
            }
        }
        (target, ceiling)
    }

    /// Smallest target speed, so the path is always finished: stepping from it to rest takes
    /// at most J·Ts/2 of acceleration and 10 % of the deceleration limit.
    fn creep(&self) -> f64 {
        let ts = self.cfg.ts;
        (0.5 * self.cfg.jerk * ts * ts)
            .min(0.1 * self.planner.dmax * ts)
            .min(self.cfg.feed)
    }

    /// Path length (in steps' chords) to the point where the motion must be at rest: the end
    /// of this curve, or of the next one with a continuation. Near the end the arc length is
    /// integrated exactly, and the chords still to come are shorter than the arc by about
    /// c³κ²/24 each (about κ²Ts²v²·R/48 over a stop).
    fn rest_distance(&mut self, next: Option<&Continuation<'_>>) -> f64 {
        let pl = self.planner;
        let ts = self.cfg.ts;
        let mut r = (self.length - self.s).max(0.0);
        // (the stop is decided with PLAN_MARGIN on the limits: 5 % covers it)
        let near = 1.05
            * PathSpeedPlanner::stopping_distance(pl.v, pl.a.max(0.0), pl.dmax, pl.jmax)
            + 4.0 * pl.v * ts
            + 1.0;
        if r <= near && !self.done {
            r = (self.length - self.arc_at(self.u, true)).max(0.0);
            let rho = radius_of_curvature(&self.d1, &self.d2);
            if rho.is_finite() && rho > 0.0 {
                let k = pl.v * ts / rho;
                r -= (k * k / 48.0 * r).min(0.5 * r);
            }
        }
        match next {
            Some(c) => r + c.next.length,
            // the chords to the end are at least the straight distance to it
            None => r.max((self.end_pos - self.pos).norm()),
        }
    }

    /// The planner's mean speed for this tick, the speed after the local caps, the ceiling a
    /// saturation guard may raise it to, and the step.
    fn planned_step(&mut self, next: Option<&Continuation<'_>>) -> (f64, f64, f64, Step) {
        let (planned, v, ceiling, land) = self.plan_speed(next);
        let (v, ceiling, st) = self.step_at(v, ceiling, land);
        (planned, v, ceiling, st)
    }

    /// The planner's mean speed for this tick, the speed after the local caps, the ceiling,
    /// and whether this step lands on the curve's end.
    fn plan_speed(&mut self, next: Option<&Continuation<'_>>) -> (f64, f64, f64, bool) {
        let (target, ceiling) = self.limits(next);
        let remaining = self.rest_distance(next);
        let planned = self.planner.next(target.max(self.creep()), remaining);
        let ts = self.cfg.ts;
        let v = planned.min(ceiling);
        let lands = self.planner.lands() && next.is_none();
        let to_end = (self.end_pos - self.pos).norm();
        // What the coordinates resolve: a step below it is no step.
        let resolution = 8.0 * f64::EPSILON * self.pos.amax().max(1.0);
        // The stop ends at the curve's end within this tick: land on it when the planned step
        // reaches it within 1e-9·J·Ts³ (a change of the step's jerk of 1e-9·J) or the
        // resolution of the coordinates.
        let slack = (1e-9 * self.cfg.jerk * ts * ts * ts).max(resolution);
        // (at the end point but not at the end of a closed curve: the arc left decides)
        let at_end = to_end <= resolution && self.length - self.arc_at(self.u, true) <= 1e-6;
        let land = at_end || (lands && v * ts + slack >= to_end);
        (planned, v, ceiling, land)
    }

    /// The step at speed `v` (or onto the end), lowered for the chord error at its far end:
    /// (speed, ceiling, step).
    fn step_at(&mut self, mut v: f64, mut ceiling: f64, land: bool) -> (f64, f64, Step) {
        let ts = self.cfg.ts;
        let mut st = if land {
            let st = self.land_step();
            v = st.chord / ts;
            st
        } else {
            self.solve_step(v * ts)
        };
        if !st.landed {
            // chord-error cap at the far end of the step as well
            let cap_next =
                chord_feed_limit(radius_of_curvature(&st.d1, &st.d2), ts, self.cfg.chord_tol);
            ceiling = ceiling.min(cap_next);
            if v > cap_next {
                v = cap_next.max(self.creep().min(v));
                st = self.solve_step_near(&st, v * ts);
            }
        }
        self.last_plan = v * ts;
        (v, ceiling, st)
    }

    /// After a step: the planner rests when the step ended this curve (unless a continuation
    /// takes the motion on), and follows a step shorter or longer than planned.
    fn after_step(&mut self, t: &Tick, planned: f64, continuing: bool) {
        if t.done {
            if !continuing {
                self.planner.rest();
            }
        } else {
            self.planner.resync(t.feed, planned);
        }
    }

    /// One sample with the path-speed planner (jerk-limited ramps, stop at the end) and
    /// the look-ahead / chord-error caps. Holds the end point once reached.
    pub fn tick(&mut self) -> Result<Tick, InterpError> {
        self.tick_into(None)
    }

    /// Like [`tick`](Self::tick), with the next curve of the path (see
    /// [`continuation`](Self::continuation)): the motion does not stop at this curve's end;
    /// the step that crosses it ends short (`done`), and [`take_over`](Self::take_over) on the
    /// next curve takes the rest of it.
    pub fn tick_into(&mut self, next: Option<Continuation<'_>>) -> Result<Tick, InterpError> {
        if self.done {
            return Ok(self.hold());
        }
        let (planned, _, _, st) = self.planned_step(next.as_ref());
        let t = self.commit(&st);
        self.after_step(&t, planned, next.is_some());
        Ok(t)
    }

    /// One sample with Yeh's saturation-aware feed (§3.4): the planned feed is checked
    /// against eq 3.5–3.6 on every axis with the actual axis state `theta_a` = θ_a\[k\] and
    /// `w_a` = w_a\[k\] (measured this tick, or predicted with [`AxisSample::predicted`]) and
    /// lowered (eq 3.8–3.10) — or raised when an axis cannot slow down that fast — before
    /// the step is taken. The axis speed command is the exact chord over Ts; its direction
    /// starts as the tangent (eq 3.7) and is refined with the chord of the candidate step.
    pub fn tick_guarded(
        &mut self,
        sat: &SaturationAwareFeed,
        theta_a: &Point,
        w_a: &Point,
    ) -> Result<(Tick, FeedDecision), InterpError> {
        self.tick_guarded_into(sat, theta_a, w_a, None)
    }

    /// [`tick_guarded`](Self::tick_guarded) with the next curve of the path (see
    /// [`tick_into`](Self::tick_into)).
    pub fn tick_guarded_into(
        &mut self,
        sat: &SaturationAwareFeed,
        theta_a: &Point,
        w_a: &Point,
        next: Option<Continuation<'_>>,
    ) -> Result<(Tick, FeedDecision), InterpError> {
        let dim = self.curve.dim();
        if sat.dim() != dim {
            return Err(InterpError::DimensionMismatch {
                expected: dim,
                got: sat.dim(),
            });
        }
        if theta_a.iter().any(|x| !x.is_finite()) || w_a.iter().any(|x| !x.is_finite()) {
            return Err(InterpError::NonFiniteInput);
        }
        let mut states = [AxisSample::default(); MAX_DIM];
        for (j, s) in states.iter_mut().enumerate().take(dim) {
            *s = AxisSample {
                theta_d_prev: self.pos[j],
                w_d_prev: self.prev_vel[j],
                theta_a: theta_a[j],
                w_a: w_a[j],
            };
        }
        if self.done {
            let t = self.hold();
            let dec = FeedDecision {
                feasible: true,
                max_drive_ratio: sat.drive_ratio_for(&Point::zeros(), &states[..dim]),
                ..FeedDecision::default()
            };
            return Ok((t, dec));
        }
        let (planned, v0, ceiling0, land) = self.plan_speed(next.as_ref());
        // Step 1–2 (eq 3.7): direction of the axis speed command, first the tangent
        let n = self.d1.norm();
        let tangent = if n > 0.0 { self.d1 / n } else { Point::zeros() };
        // The feed Yeh's check allows along the tangent, then the step at it (the chord-error
        // cap at the step's far end may lower it further), then the check along the chord.
        let first = sat.limit_feed(v0, ceiling0, &tangent, &states[..dim])?;
        let (_, ceiling, mut st) = self.step_at(first.feed, ceiling0, land);
        let v_plan = v0.min(ceiling);
        let mut dir = if st.chord > 0.0 {
            (st.c - self.pos) / st.chord
        } else {
            tangent
        };
        let mut dec = sat.limit_feed(v_plan, ceiling, &dir, &states[..dim])?;
        let ts = self.cfg.ts;
        let settled = |a: f64, b: f64| (a - b).abs() <= 1e-9 * (1.0 + b);
        for _ in 0..8 {
            if !settled(st.chord / ts, dec.feed) {
                st = self.solve_step_near(&st, dec.feed * ts);
            }
            if st.chord <= 0.0 {
                break;
            }
            let new_dir = (st.c - self.pos) / st.chord;
            let moved = (new_dir - dir).amax();
            dir = new_dir;
            if moved < 1e-9 {
                break;
            }
            let before = dec.feed;
            dec = sat.limit_feed(v_plan, ceiling, &dir, &states[..dim])?;
            if settled(dec.feed, before) {
                break;
            }
        }
        if !st.landed && !settled(st.chord / ts, dec.feed) {
            st = self.solve_step_near(&st, dec.feed * ts);
        }
        self.last_plan = if land { st.chord } else { dec.feed * ts };
        let t = self.commit(&st);
        dec.max_drive_ratio = sat.drive_ratio_for(&t.vel, &states[..dim]);
        // restore toward the commanded feed at the planner's tangential acc/jerk
        self.after_step(&t, planned, next.is_some());
        Ok((t, dec))
    }
}

/// Calls `f(offset + s, raw)` for the samples of `p` from index `from` up to path length
/// `until` whose limit is below `vmax` (blocks whose minimum is not are skipped).
fn scan(
    p: &[ProfileSample],
    blocks: &[f64],
    from: usize,
    offset: f64,
    until: f64,
    vmax: f64,
    f: &mut impl FnMut(f64, f64),
) {
    let mut i = from;
    while let Some(smp) = p.get(i) {
        if offset + smp.s > until {
            break;
        }
        if i.is_multiple_of(BLOCK) && blocks.get(i / BLOCK).is_some_and(|&m| m >= vmax) {
            i += BLOCK; // nothing in this block is below the speed
            continue;
        }
        if smp.raw < vmax {
            f(offset + smp.s, smp.raw);
        }
        i += 1;
    }
}

/// Profile cap at path length `s` (v² interpolated linearly); `hint` is a moving index.
fn cap_at(p: &[ProfileSample], s: f64, hint: &mut usize) -> f64 {
    let n = p.len();
    if n == 0 {
        return 0.0;
    }
    let mut i = (*hint).min(n - 1);
    while i > 0 && p[i].s > s {
        i -= 1;
    }
    while i + 1 < n && p[i + 1].s <= s {
        i += 1;
    }
    *hint = i;
    if i + 1 >= n {
        return p[n - 1].cap;
    }
    let (a, b) = (p[i], p[i + 1]);
    let ds = b.s - a.s;
    if ds <= 0.0 || s <= a.s {
        return a.cap;
    }
    // interpolate v² (exact for constant deceleration between the samples)
    let t = ((s - a.s) / ds).clamp(0.0, 1.0);
    let sq = |c: f64| if c.is_finite() { c * c } else { f64::INFINITY };
    math::sqrt(sq(a.cap) + t * (sq(b.cap) - sq(a.cap)))
}

/// The actuator limits of a look-ahead: a budget in (0, 1] and a model of the curve's axes.
fn actuator_plan<'a>(
    curve: &Nurbs,
    sat: &'a SaturationAwareFeed,
    budget: f64,
) -> Result<ActuatorPlan<'a>, InterpError> {
    if !(pos_finite(budget) && budget <= 1.0) {
        return Err(InterpError::BadBudget);
    }
    if sat.dim() != curve.dim() {
        return Err(InterpError::DimensionMismatch {
            expected: curve.dim(),
            got: sat.dim(),
        });
    }
    Ok(ActuatorPlan { sat, budget })
}

/// The look-ahead profile of `curve`, written into `samples` (at most `MAX_PROFILE` of them),
/// with no other storage: the parameters of the samples go into `samples` first.
fn build_profile(
    curve: &Nurbs,
    cfg: &InterpConfig,
    dmax: f64,
    act: Option<ActuatorPlan<'_>>,
    samples: &mut FixedVec<ProfileSample, MAX_PROFILE>,
) -> Result<(), InterpError> {
    let knots = curve.knots();
    let p = curve.degree();
    let spans = || {
        knots[p..knots.len() - p]
            .windows(2)
            .filter(|w| w[1] > w[0])
            .map(|w| (w[0], w[1]))
    };
    let n_spans = spans().count();
    let Some((_, u_last)) = spans().next_back() else {
        return Err(InterpError::ZeroLengthCurve);
    };
    let per_span = ((MAX_PROFILE - 1) / n_spans).clamp(1, 512);
    samples.clear();
    let at = |u: f64| ProfileSample {
        s: 0.0,
        raw: 0.0,
        cap: 0.0,
        u,
        ds_du: 0.0,
    };
    // n_spans · per_span + 1 ≤ MAX_PROFILE (a curve has at most MAX_CTRL spans)
    for (a, b) in spans() {
        for i in 0..per_span {
            if samples
                .push(at(a + (b - a) * i as f64 / per_span as f64))
                .is_err()
            {
                return Err(InterpError::ZeroLengthCurve);
            }
        }
    }
    if samples.push(at(u_last)).is_err() {
        return Err(InterpError::ZeroLengthCurve);
    }
    // local limits at sample points and midpoints
    let local = |u: f64| -> (f64, Point, Point, f64) {
        let (_, d1, d2) = curve.eval_clamped(u);
        let mut cap = cfg.feed.min(chord_feed_limit(
            radius_of_curvature(&d1, &d2),
            cfg.ts,
            cfg.chord_tol,
        ));
        let (t, k) = unit_tangent_and_curvature(&d1, &d2);
        if let Some(a) = act {
            cap = cap.min(a.speed_cap(&t, &k));
        }
        (cap, t, k, d1.norm())
    };
    let n = samples.len();
    let mut s = 0.0;
    let mut prev_mid_cap = f64::INFINITY;
    for i in 0..n {
        let u = samples[i].u;
        let (cap, _, _, ds_du) = local(u);
        let mut c = cap.min(prev_mid_cap);
        if i + 1 < n {
            let (mid_cap, _, _, _) = local(0.5 * (u + samples[i + 1].u));
            c = c.min(mid_cap);
            prev_mid_cap = mid_cap;
        }
        if i > 0 {
            s += arc_length(curve, samples[i - 1].u, u);
        }
        samples[i] = ProfileSample {
            s,
            raw: c,
            cap: c,
            u,
            ds_du,
        };
    }
    // Backward pass: v_i² ≤ v_{i+1}² + 2·d_i·Δs with d_i the tangential deceleration
    // available (the planner's limit, and the actuator budget when given). The final stop
    // is the planner's (jerk-limited, on the remaining length), not part of this table.
    for i in (0..n.saturating_sub(1)).rev() {
        let ds = samples[i + 1].s - samples[i].s;
        let v_next = samples[i + 1].cap;
        // the tangent and curvature at the sample, as `local` found them (evaluated again
        // rather than kept: a table of them would be 1 MB)
        let tk = act.map(|_| {
            let (_, d1, d2) = curve.eval_clamped(samples[i].u);
            unit_tangent_and_curvature(&d1, &d2)
        });
        let decel_at = |v: f64| match (act, &tk) {
            (Some(a), Some((t, k))) => a.decel(t, k, v, dmax),
            _ => dmax,
        };
        let d0 = decel_at(v_next);
        let vc = math::sqrt(v_next * v_next + 2.0 * d0 * ds);
        let d = d0.min(decel_at(vc));
        let v = math::sqrt(v_next * v_next + 2.0 * d * ds);
        if v < samples[i].cap {
            samples[i].cap = v;
        }
    }
    if samples.iter().any(|x| !(x.s.is_finite() && x.cap >= 0.0)) {
        return Err(InterpError::ZeroLengthCurve);
    }
    Ok(())
}

#[cfg(test)]
mod tests;
