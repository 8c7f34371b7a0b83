//! The spindle on a card axis, coolant on card outputs, and spindle-synchronised motion
//! (G33, G33.1) on the card's camming: the part of a run that is not the group's path.
//!
//! **The spindle** ([`SpindleSettings`]) is a card axis outside the group, in revolutions: its
//! scale is its encoder's counts per revolution, and its whole revolutions are its index (home
//! it on its index pulse, or set its position, once). M3 turns it forward (positive velocity,
//! LinuxCNC's M3), M4 backward, in velocity mode within its acceleration and jerk; M5 halts it;
//! an S while it turns changes its speed. An S above the largest speed runs at the largest,
//! with a message (as LinuxCNC clamps it). The run goes on once the spindle is at its speed
//! (or at rest): nothing is cut by a spindle still speeding up.
//!
//! **Coolant**: M7/M8/M9 set the mist and flood outputs, when they are given.
//!
//! **G33 and G33.1.** The card cannot couple a group's member to a master while the group is
//! enabled (`exec/sync.rs`), so a thread leaves the group: with the motion before it ended, the
//! group is disabled, each axis that moves along the line is cammed to the spindle's *encoder*
//! through one cam table ([`ThreadPlan`]), and the group is enabled again at the end (where
//! the axes stand). The table gives the distance `s` (mm) along the line as a function of `u`,
//! the spindle's revolutions (in its direction of turning) from an *anchor*, a whole
//! revolution of the spindle (its index) ahead of it when the pass starts:
//!
//! ```text
//! s(u) = 0                          u ≤ u_s = k − R/2          (waits at the start)
//!        p·R·(x³ − x⁴/2)            x = (u − u_s)/R ∈ [0, 1]    (ramp-in: ds/du = p·(3x² − 2x³))
//!        p·(u − k)                  the thread: the lead exact
//!        L − p·R·(…)                ramp-out to the end, mirrored (G33)
//! ```
//!
//! with `p` the pitch, `L` the line's length, `R` the ramp's revolutions (the least that keeps
//! every axis within its path limits at the programmed speed: acceleration `1.5·p·ω²/R`, jerk
//! `6·p·ω³/R²`, each times the axis's share of the line) and `k = ⌈R/2⌉` whole revolutions.
//! On the thread the tool is at `start + p·(turns from the index − k − anchor)`: a whole
//! number of pitches from the same helix on every pass, so passes cut the same thread
//! whenever they start (LinuxCNC waits for the index pulse for this). The lead is exact from
//! `p·R/2` after the start to `p·R/2` before the end (G33); within those the tool speeds up or
//! slows down along the line, on the spindle's angle, within the axes' limits.
//!
//! G33.1 (rigid tapping): the thread's linear part runs on past the end; when the spindle
//! passes the end's angle it is reversed (within its own acceleration and jerk), the axes
//! follow it down past the end by what the spindle takes to stop (as in LinuxCNC) and back up
//! along the same helix, the ramp brings them to rest at the start, the coupling ends, and the
//! spindle is given its original direction again. The axes then follow the spindle's
//! acceleration at the reversal (`p·α`): it must be within their limits, with what is left for
//! the ramps.

use super::{GcodeError, SpindleDir};
use crate::{
    AxisState, CamSettings, Error, Group, Master, MotionFlags, MoveLimits, Result, Status,
    SyncLimits, VelocityLimits, CAM_MAX_POINTS, CAM_TABLES,
};
use firmware_proto::OUTPUTS;

/// A spindle on a card axis (see the module's doc).
#[derive(Debug, Clone, PartialEq)]
pub struct SpindleSettings {
    /// The card axis: enabled, not one of the group's, its user unit a revolution (its scale
    /// the encoder's counts per revolution; whole revolutions are its index).
    pub axis: usize,
    /// The largest speed, rpm: a larger S runs at this, with a message.
    pub max_rpm: f64,
    /// Acceleration and deceleration, rev/s².
    pub acceleration: f64,
    /// Jerk, rev/s³.
    pub jerk: f64,
    /// The cam table a thread (G33, G33.1) loads and follows (0..[`CAM_TABLES`]; the last by
    /// default).
    pub cam_table: usize,
}

impl SpindleSettings {
    /// Card axis `axis` up to `max_rpm`, within `acceleration` (rev/s²) and `jerk` (rev/s³),
    /// threads on the last cam table.
    pub fn new(axis: usize, max_rpm: f64, acceleration: f64, jerk: f64) -> Self {
        Self {
            axis,
            max_rpm,
            acceleration,
            jerk,
            cam_table: CAM_TABLES - 1,
        }
    }
}

fn gcode_err(line: usize, m: impl Into<String>) -> Error {
    Error::Gcode(GcodeError::new(line, m))
}

/// One axis's share of a thread: its part of the line (|Δᵢ|/L) and its path limits (its user
/// units, per second).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AxisShare {
    /// |Δᵢ| / L.
    pub share: f64,
    /// Velocity limit.
    pub velocity: f64,
    /// Acceleration limit.
    pub acceleration: f64,
    /// Jerk limit.
    pub jerk: f64,
}

/// Ramp intervals in the cam table (each ramp).
const RAMP_INTERVALS: usize = 32;
/// The least ramp, revolutions.
const MIN_RAMP: f64 = 0.01;
/// Revolutions added to a tap's linear part beyond what the spindle takes to stop.
const TAP_SLACK: f64 = 1.0;

/// One pass of G33 or G33.1 as a function of the spindle's angle (see the module's doc): `s(u)`
/// in mm along the line, `u` in revolutions from the anchor.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ThreadPlan {
    /// mm per revolution.
    pub pitch: f64,
    /// The line's length, mm.
    pub length: f64,
    /// Revolutions of each ramp (`R`).
    pub ramp: f64,
    /// Whole revolutions from the anchor to where the helix starts (`k`).
    pub k: f64,
    /// G33.1: the line is tapped in and out.
    pub tap: bool,
    /// G33.1: revolutions the thread's linear part runs on past the end.
    pub overrun: f64,
}

impl ThreadPlan {
    /// The pass for `pitch` and `length` at `speed` rev/s, the spindle within `spindle_acc`
    /// and `spindle_jerk`, each moving axis's share and limits: the least ramp that keeps every
    /// axis within its limits, or why there is none.
    pub fn new(
        pitch: f64,
        length: f64,
        speed: f64,
        (spindle_acc, spindle_jerk): (f64, f64),
        axes: &[AxisShare],
        tap: bool,
    ) -> std::result::Result<Self, String> {
        if !(pitch.is_finite() && pitch > 0.0) {
            return Err(format!("the pitch must be above 0, not {pitch}"));
        }
        if !(speed.is_finite() && speed > 0.0) {
            return Err("the spindle is stopped (M3 or M4 with S first)".into());
        }
        let mut ramp = MIN_RAMP;
        for (i, a) in axes.iter().enumerate() {
            if a.share <= 0.0 {
                continue;
            }
            let c = a.share * pitch;
            let v = c * speed;
            if v > a.velocity * (1.0 + 1e-9) {
                return Err(format!(
                    "at {:.0} rpm the thread moves group axis {i} at {v:.4}/s, above its limit \
                     {:.4}/s",
                    speed * 60.0,
                    a.velocity
                ));
            }
            // A tap follows the spindle's reversal as well as the ramp.
            let (acc, jerk) = if tap {
                (a.acceleration - c * spindle_acc, a.jerk - c * spindle_jerk)
            } else {
                (a.acceleration, a.jerk)
            };
            if acc <= 0.0 || jerk <= 0.0 {
                return Err(format!(
                    "the spindle's reversal ({spindle_acc} rev/s², {spindle_jerk} rev/s³) \
                     needs {:.4}/s² and {:.4}/s³ on group axis {i}, beyond its limits",
                    c * spindle_acc,
                    c * spindle_jerk
                ));
            }
            ramp = ramp
                .max(1.5 * c * speed * speed / acc)
                .max((6.0 * c * speed.powi(3) / jerk).sqrt());
        }
        let need = if tap {
            pitch * ramp / 2.0
        } else {
            pitch * ramp
        };
        if length < need {
            return Err(format!(
                "the line ({length:.4} mm) is shorter than the {need:.4} mm the spindle's \
                 speed takes to ramp in{}",
                if tap { "" } else { " and out" }
            ));
        }
        let overrun = if tap {
            // What the spindle turns on while it stops (a jerk-limited stop takes at most
            // ω/α + α/j), and a revolution more.
            speed * (speed / spindle_acc + spindle_acc / spindle_jerk) + TAP_SLACK
        } else {
            0.0
        };
        Ok(ThreadPlan {
            pitch,
            length,
            ramp,
            k: (ramp / 2.0).ceil(),
            tap,
            overrun,
        })
    }

    /// Where the ramp-in starts (`u_s`).
    pub fn ramp_start(&self) -> f64 {
        self.k - self.ramp / 2.0
    }

    /// Where the thread's linear part starts.
    fn linear_start(&self) -> f64 {
        self.ramp_start() + self.ramp
    }

    /// Where the linear part ends (G33: the ramp-out starts; G33.1: the table ends).
    fn linear_end(&self) -> f64 {
        let at_end = self.k + self.length / self.pitch;
        if self.tap {
            at_end + self.overrun
        } else {
            at_end - self.ramp / 2.0
        }
    }

    /// Where the table ends: the axes stand still after it.
    pub fn table_end(&self) -> f64 {
        if self.tap {
            self.linear_end()
        } else {
            self.linear_end() + self.ramp
        }
    }

    /// G33.1: where the tool reaches the end and the spindle is reversed.
    pub fn reverse_at(&self) -> f64 {
        self.k + self.length / self.pitch
    }

    /// `s(u)`, mm along the line.
    pub fn position(&self, u: f64) -> f64 {
        let (p, r, us) = (self.pitch, self.ramp, self.ramp_start());
        if u <= us {
            0.0
        } else if u < us + r {
            let x = (u - us) / r;
            p * r * (x * x * x - x * x * x * x / 2.0)
        } else if u <= self.linear_end() {
            p * (u - self.k)
        } else if !self.tap && u < self.table_end() {
            let x = (u - self.linear_end()) / r;
            p * (self.linear_end() - self.k) + p * r * (x - x * x * x + x * x * x * x / 2.0)
        } else if self.tap {
            p * (self.linear_end() - self.k)
        } else {
            self.length
        }
    }

    /// The cam table's points (u, s): each ramp in `RAMP_INTERVALS` equal steps, the linear
    /// part in steps growing from a ramp's step near the ramps (where the cubic spline settles
    /// onto the line) to at most its length / 800. Fewer than [`CAM_MAX_POINTS`].
    pub fn table(&self) -> Vec<(f64, f64)> {
        let h0 = self.ramp / RAMP_INTERVALS as f64;
        let mut u = Vec::with_capacity(CAM_MAX_POINTS);
        let us = self.ramp_start();
        for i in 0..RAMP_INTERVALS {
            u.push(us + h0 * i as f64);
        }
        let (a, b) = (self.linear_start(), self.linear_end());
        u.push(a);
        u.extend(spread(a, b, h0));
        u.push(b);
        if !self.tap {
            for i in 1..=RAMP_INTERVALS {
                u.push(b + h0 * i as f64);
            }
        }
        u.into_iter().map(|x| (x, self.position(x))).collect()
    }
}

/// Points strictly between `a` and `b`: steps from `h0` growing by half each toward the middle,
/// up to `max((b − a)/800, h0)`, that step in the middle.
fn spread(a: f64, b: f64, h0: f64) -> Vec<f64> {
    let len = b - a;
    let hmax = (len / 800.0).max(h0);
    let (mut left, mut right) = (Vec::new(), Vec::new());
    let (mut xl, mut xr, mut h) = (a, b, h0);
    while h < hmax && xr - xl > 4.0 * h {
        xl += h;
        xr -= h;
        left.push(xl);
        right.push(xr);
        h *= 1.5;
    }
    let n = ((xr - xl) / hmax).ceil().max(1.0) as usize;
    let step = (xr - xl) / n as f64;
    for i in 1..n {
        left.push(xl + step * i as f64);
    }
    left.extend(right.into_iter().rev());
    left
}

/// What the spindle is doing for the run.
#[derive(Debug)]
enum Job {
    /// Nothing to wait for.
    Idle,
    /// Waiting for the spindle to reach its velocity (or rest), for `line`.
    Ramp { line: usize },
    /// A thread.
    Thread(Box<Thread>),
    /// M19: stopping, then turning to `target` (revolutions, once chosen).
    Orient {
        line: usize,
        /// The angle, a fraction of a revolution in [0, 1).
        angle: f64,
        dir: SpindleDir,
        target: Option<f64>,
    },
}

/// Where a thread is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Phase {
    /// The axes follow the table (G33.1: in).
    Following,
    /// G33.1: the spindle reversed, the axes come back out.
    Returning,
    /// The axes halted (G33.1: the spindle back to its direction): waiting for rest, then the
    /// group is enabled again.
    Settling,
}

#[derive(Debug)]
struct Thread {
    line: usize,
    plan: ThreadPlan,
    /// The spindle's direction of turning, ±1.
    sigma: f64,
    /// The anchor, the spindle's whole revolution where `u` = 0.
    anchor: f64,
    /// The cammed card axes, with their halting deceleration and jerk (user units).
    coupled: Vec<(usize, f64, f64)>,
    phase: Phase,
}

/// The spindle and coolant of a run (see the module's doc).
#[derive(Debug)]
pub(super) struct SpindleUnit {
    cfg: Option<SpindleSettings>,
    mist: Option<u32>,
    flood: Option<u32>,
    /// The spindle's velocity as last commanded, rev/s (signed).
    velocity: f64,
    job: Job,
}

impl SpindleUnit {
    /// Checked against `group`: the spindle axis exists and is not the group's, its limits are
    /// above 0, the outputs are the card's.
    pub(super) fn new(
        group: &Group,
        cfg: Option<SpindleSettings>,
        mist: Option<u32>,
        flood: Option<u32>,
    ) -> Result<Self> {
        let bad = |m: String| Err(Error::BadConfig(m));
        for (what, o) in [("mist", mist), ("flood", flood)] {
            if o.is_some_and(|o| o >= OUTPUTS as u32) {
                return bad(format!(
                    "the {what} output {}: the card has outputs 0..{OUTPUTS}",
                    o.unwrap_or(0)
                ));
            }
        }
        if let Some(c) = &cfg {
            let card = group.card_pub();
            let (n, ids) = group.axes_pub()?;
            if c.axis >= card.info().axes {
                return bad(format!("the spindle axis {}: no such axis", c.axis));
            }
            if ids[..n].contains(&c.axis) {
                return bad(format!(
                    "the spindle axis {} is one of the group's axes",
                    c.axis
                ));
            }
            for (what, v) in [
                ("largest speed", c.max_rpm),
                ("acceleration", c.acceleration),
                ("jerk", c.jerk),
            ] {
                if !(v.is_finite() && v > 0.0) {
                    return bad(format!("the spindle's {what} must be above 0, not {v}"));
                }
            }
            if c.cam_table >= CAM_TABLES {
                return bad(format!(
                    "the spindle's cam table {}: the card has 0..{CAM_TABLES}",
                    c.cam_table
                ));
            }
        }
        Ok(SpindleUnit {
            cfg,
            mist,
            flood,
            velocity: 0.0,
            job: Job::Idle,
        })
    }

    /// Is there a spindle on the card?
    pub(super) fn configured(&self) -> bool {
        self.cfg.is_some()
    }

    fn status(&self, group: &Group) -> Result<Status> {
        let c = self.cfg.as_ref().map_or(0, |c| c.axis);
        group.card_pub().axis(c)?.status()
    }

    /// M3/M4/M5, S (at `line`): the spindle to `rpm` in `dir`; a message when the speed is
    /// clamped to the largest. The run waits until it is there ([`SpindleUnit::poll`]).
    pub(super) fn set(
        &mut self,
        group: &Group,
        line: usize,
        rpm: f64,
        dir: SpindleDir,
    ) -> Result<Option<String>> {
        let Some(cfg) = self.cfg.clone() else {
            return Ok(None);
        };
        let mut note = None;
        let mut rpm = rpm.max(0.0);
        if rpm > cfg.max_rpm {
            note = Some(format!(
                "S{rpm} is above the spindle's largest speed: {} rpm",
                cfg.max_rpm
            ));
            rpm = cfg.max_rpm;
        }
        let v = match dir {
            SpindleDir::Cw => rpm / 60.0,
            SpindleDir::Ccw => -rpm / 60.0,
            SpindleDir::Off => 0.0,
        };
        let axis = group.card_pub().axis(cfg.axis)?;
        if v == 0.0 {
            if axis.status()?.state != AxisState::Standstill {
                axis.halt(cfg.acceleration, cfg.jerk)?;
            }
        } else {
            axis.move_velocity(v, &VelocityLimits::new(cfg.acceleration, cfg.jerk))?;
        }
        self.velocity = v;
        self.job = Job::Ramp { line };
        Ok(note)
    }

    /// M19 at `line`: the spindle halts, then turns to `angle` degrees from its index (a
    /// whole revolution), clockwise (forward, as M3), counter-clockwise or the shorter way
    /// (`dir` Off); the run waits until it rests there ([`SpindleUnit::poll`]).
    pub(super) fn orient(
        &mut self,
        group: &Group,
        line: usize,
        angle: f64,
        dir: SpindleDir,
    ) -> Result<()> {
        let Some(cfg) = self.cfg.clone() else {
            return Err(gcode_err(line, "M19: no spindle is configured on the card"));
        };
        if !angle.is_finite() {
            return Err(gcode_err(line, format!("M19 R{angle}")));
        }
        let axis = group.card_pub().axis(cfg.axis)?;
        if axis.status()?.state != AxisState::Standstill {
            axis.halt(cfg.acceleration, cfg.jerk)?;
        }
        self.velocity = 0.0;
        self.job = Job::Orient {
            line,
            angle: (angle / 360.0).rem_euclid(1.0),
            dir,
            target: None,
        };
        Ok(())
    }

    /// M7/M8/M9: the mist and flood outputs that are given.
    pub(super) fn coolant(&self, group: &Group, mist: bool, flood: bool) -> Result<()> {
        let (mut mask, mut value) = (0u32, 0u32);
        for (o, on) in [(self.mist, mist), (self.flood, flood)] {
            if let Some(o) = o {
                mask |= 1 << o;
                if on {
                    value |= 1 << o;
                }
            }
        }
        if mask != 0 {
            group.card_pub().set_outputs(mask, value)?;
        }
        Ok(())
    }

    /// G33 (`tap` false) or G33.1 at `line` from `start` to `end` (group axes, user units),
    /// `pitch` mm per revolution: the group is left, its axes cammed to the spindle; the run
    /// waits until the pass is done and the group enabled again ([`SpindleUnit::poll`]).
    pub(super) fn start_thread(
        &mut self,
        group: &Group,
        line: usize,
        (start, end): (&[f64], &[f64]),
        pitch: f64,
        tap: bool,
    ) -> Result<()> {
        let what = if tap { "G33.1" } else { "G33" };
        let Some(cfg) = self.cfg.clone() else {
            return Err(gcode_err(
                line,
                format!("{what}: no spindle is configured on the card"),
            ));
        };
        let card = group.card_pub();
        let sp = self.status(group)?;
        let turning = self.velocity != 0.0
            && sp.state == AxisState::ContinuousMotion
            && sp.motion.contains(MotionFlags::IN_VELOCITY);
        if !turning {
            return Err(gcode_err(
                line,
                format!("{what}: the spindle is stopped (M3 or M4 with S first)"),
            ));
        }
        let length = start
            .iter()
            .zip(end)
            .map(|(a, b)| (b - a) * (b - a))
            .sum::<f64>()
            .sqrt();
        if length <= super::ZERO_LENGTH {
            return Ok(());
        }
        let (n, ids) = group.axes_pub()?;
        let path = group.path_config()?;
        let mut shares = Vec::with_capacity(n);
        for (g, &a) in ids[..n].iter().enumerate() {
            let s = card.scale(a).abs();
            shares.push(AxisShare {
                share: (end[g] - start[g]).abs() / length,
                velocity: path.vmax[g] / s,
                acceleration: path.amax[g] / s,
                jerk: path.jmax[g] / s,
            });
        }
        let speed = self.velocity.abs();
        let plan = ThreadPlan::new(
            pitch,
            length,
            speed,
            (cfg.acceleration, cfg.jerk),
            &shares,
            tap,
        )
        .map_err(|m| gcode_err(line, format!("{what}: {m}")))?;
        let sigma = self.velocity.signum();
        group.disable()?;
        let coupled = self.couple(group, &cfg, &plan, sigma, (start, end), &shares);
        match coupled {
            Ok((anchor, coupled)) => {
                self.job = Job::Thread(Box::new(Thread {
                    line,
                    plan,
                    sigma,
                    anchor,
                    coupled,
                    phase: Phase::Following,
                }));
                Ok(())
            }
            Err(e) => {
                // Nothing half done: the axes that took the cam halt, and the group takes
                // them back once they rest.
                for (g, &a) in ids[..n].iter().enumerate() {
                    if let Ok(ax) = card.axis(a) {
                        if ax.status().is_ok_and(|s| s.state != AxisState::Standstill) {
                            let _ = ax.halt(shares[g].acceleration, shares[g].jerk);
                        }
                    }
                }
                Err(e)
            }
        }
    }

    /// The table loaded and the axes cammed: the anchor and the coupled axes.
    #[allow(clippy::type_complexity)]
    fn couple(
        &self,
        group: &Group,
        cfg: &SpindleSettings,
        plan: &ThreadPlan,
        sigma: f64,
        (start, end): (&[f64], &[f64]),
        shares: &[AxisShare],
    ) -> Result<(f64, Vec<(usize, f64, f64)>)> {
        let card = group.card_pub();
        card.load_cam_table(cfg.cam_table, &plan.table(), true, false)?;
        let (n, ids) = group.axes_pub()?;
        let sp_scale = card.scale(cfg.axis);
        // The next index far enough ahead for the commands to reach the card before the
        // ramp starts: 20 ms of turning and a hundredth of a revolution.
        let here = sigma * self.status(group)?.actual_position;
        let lead = self.velocity.abs() * 0.02 + 0.01;
        let anchor = sigma * (here + lead).ceil();
        let length = plan.length;
        let mut coupled = Vec::new();
        for (g, &a) in ids[..n].iter().enumerate() {
            let d = end[g] - start[g];
            if d.abs() <= super::ZERO_LENGTH {
                continue;
            }
            let scale = card.scale(a);
            let cam = CamSettings {
                table: cfg.cam_table,
                master_offset: anchor * sp_scale,
                slave_offset: start[g] * scale,
                master_scale: sigma * sp_scale,
                slave_scale: d / length * scale,
                relative: false,
            };
            let sh = &shares[g];
            let lim = SyncLimits::new(sh.velocity, sh.acceleration, sh.jerk);
            card.axis(a)?.cam_in(Master::Actual(cfg.axis), &cam, &lim)?;
            coupled.push((a, sh.acceleration, sh.jerk));
        }
        Ok((anchor, coupled))
    }

    /// The spindle's work, a step: `true` once nothing is left to wait for (the spindle at its
    /// speed, a thread done and the group enabled again).
    pub(super) fn poll(&mut self, group: &Group) -> Result<bool> {
        match &mut self.job {
            Job::Idle => Ok(true),
            Job::Ramp { line } => {
                let line = *line;
                let s = self.status(group)?;
                if at_velocity(&s, self.velocity) {
                    self.job = Job::Idle;
                    return Ok(true);
                }
                if matches!(s.state, AxisState::ErrorStop | AxisState::Disabled) {
                    self.job = Job::Idle;
                    return Err(gcode_err(
                        line,
                        format!("the spindle stopped: its axis is in {:?}", s.state),
                    ));
                }
                Ok(false)
            }
            Job::Thread(_) => self.poll_thread(group),
            Job::Orient { .. } => self.poll_orient(group),
        }
    }

    fn poll_orient(&mut self, group: &Group) -> Result<bool> {
        let (
            Job::Orient {
                line,
                angle,
                dir,
                target,
            },
            Some(cfg),
        ) = (&mut self.job, self.cfg.as_ref())
        else {
            return Ok(true);
        };
        let s = group.card_pub().axis(cfg.axis)?.status()?;
        if matches!(s.state, AxisState::ErrorStop | AxisState::Disabled) {
            let line = *line;
            self.job = Job::Idle;
            return Err(gcode_err(
                line,
                format!("M19: the spindle's axis is in {:?}", s.state),
            ));
        }
        if s.state != AxisState::Standstill {
            return Ok(false);
        }
        match *target {
            None => {
                // At rest: the angle's position ahead (M3's way), behind, or the nearer.
                let p = s.command_position;
                let base = p.floor() + *angle;
                let t = match dir {
                    SpindleDir::Cw if base < p => base + 1.0,
                    SpindleDir::Ccw if base > p => base - 1.0,
                    SpindleDir::Off => [base - 1.0, base, base + 1.0]
                        .into_iter()
                        .min_by(|a, b| (a - p).abs().total_cmp(&(b - p).abs()))
                        .unwrap_or(base),
                    _ => base,
                };
                let limits = MoveLimits::new(cfg.max_rpm / 60.0, cfg.acceleration, cfg.jerk);
                group.card_pub().axis(cfg.axis)?.move_absolute(t, &limits)?;
                *target = Some(t);
                Ok(false)
            }
            Some(t) if (s.command_position - t).abs() < 1e-9 => {
                self.job = Job::Idle;
                Ok(true)
            }
            Some(_) => Ok(false),
        }
    }

    fn poll_thread(&mut self, group: &Group) -> Result<bool> {
        let Job::Thread(t) = &mut self.job else {
            return Ok(true);
        };
        let Some(cfg) = self.cfg.as_ref() else {
            return Ok(true);
        };
        let card = group.card_pub();
        let sp = card.axis(cfg.axis)?.status()?;
        let u = t.sigma * (sp.actual_position - t.anchor);
        let line = t.line;
        let statuses = card.statuses(&t.coupled.iter().map(|c| c.0).collect::<Vec<_>>())?;
        if t.phase != Phase::Settling {
            if let Some((i, s)) = statuses
                .iter()
                .enumerate()
                .find(|(_, s)| s.state != AxisState::SynchronizedMotion)
            {
                let a = t.coupled[i].0;
                let state = s.state;
                self.halt_thread(group);
                return Err(gcode_err(
                    line,
                    format!("the thread was cut short: axis {a} is in {state:?}"),
                ));
            }
            if matches!(sp.state, AxisState::ErrorStop | AxisState::Disabled) {
                self.halt_thread(group);
                return Err(gcode_err(
                    line,
                    format!(
                        "the spindle stopped in the thread: its axis is in {:?}",
                        sp.state
                    ),
                ));
            }
        }
        let lim = VelocityLimits::new(cfg.acceleration, cfg.jerk);
        match t.phase {
            Phase::Following if !t.plan.tap => {
                if u >= t.plan.table_end() {
                    for &(a, d, j) in &t.coupled {
                        card.axis(a)?.halt(d, j)?;
                    }
                    t.phase = Phase::Settling;
                }
            }
            Phase::Following => {
                if u >= t.plan.reverse_at() {
                    card.axis(cfg.axis)?.move_velocity(-self.velocity, &lim)?;
                    t.phase = Phase::Returning;
                }
            }
            Phase::Returning => {
                if u < t.plan.ramp_start() {
                    for &(a, d, j) in &t.coupled {
                        card.axis(a)?.halt(d, j)?;
                    }
                    card.axis(cfg.axis)?.move_velocity(self.velocity, &lim)?;
                    t.phase = Phase::Settling;
                }
            }
            Phase::Settling => {
                let rest = statuses.iter().all(|s| s.state == AxisState::Standstill);
                if rest && at_velocity(&sp, self.velocity) {
                    group.enable()?;
                    self.job = Job::Idle;
                    return Ok(true);
                }
                if statuses
                    .iter()
                    .any(|s| matches!(s.state, AxisState::ErrorStop | AxisState::Disabled))
                {
                    self.job = Job::Idle;
                    return Err(gcode_err(line, "an axis of the thread faulted at its end"));
                }
            }
        }
        Ok(false)
    }

    /// Halts a thread's axes (and a tap's spindle: the tap is in the hole). Errors are not
    /// reported: this is the way out of one.
    fn halt_thread(&mut self, group: &Group) {
        let Job::Thread(t) = &self.job else { return };
        let card = group.card_pub();
        for &(a, d, j) in &t.coupled {
            if let Ok(ax) = card.axis(a) {
                let _ = ax.halt(d, j);
            }
        }
        if let (true, Some(c)) = (t.plan.tap, &self.cfg) {
            if let Ok(ax) = card.axis(c.axis) {
                let _ = ax.halt(c.acceleration, c.jerk);
                self.velocity = 0.0;
            }
        }
        self.job = Job::Idle;
    }

    /// The run is aborted: a thread's axes halt (a tap's spindle too). `true` when a thread
    /// was running: its group is left disabled (enable it again once the axes rest).
    pub(super) fn abort(&mut self, group: &Group) -> bool {
        let thread = matches!(self.job, Job::Thread(_));
        self.halt_thread(group);
        self.job = Job::Idle;
        thread
    }
}

/// The spindle at `v` rev/s: at rest, or in velocity mode there.
fn at_velocity(s: &Status, v: f64) -> bool {
    if v == 0.0 {
        s.state == AxisState::Standstill
    } else {
        s.state == AxisState::ContinuousMotion && s.motion.contains(MotionFlags::IN_VELOCITY)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use card_firmware::host::CamTable;

    fn z(acc: f64, jerk: f64) -> AxisShare {
        AxisShare {
            share: 1.0,
            velocity: 100.0,
            acceleration: acc,
            jerk,
        }
    }

    /// The largest difference between the card's cubic table and `s(u)` over `[a, b]`.
    fn table_error(plan: &ThreadPlan, a: f64, b: f64) -> f64 {
        let t = CamTable::new(&plan.table(), true, false).unwrap();
        let n = 200_000;
        (0..=n)
            .map(|i| a + (b - a) * i as f64 / n as f64)
            .map(|u| (t.eval(u).s - plan.position(u)).abs())
            .fold(0.0, f64::max)
    }

    #[test]
    fn the_ramp_keeps_the_axis_within_its_limits() {
        // 1.5 mm at 600 rpm: 15 mm/s; 1000 mm/s², 1e5 mm/s³.
        let p = ThreadPlan::new(1.5, 20.0, 10.0, (100.0, 1e4), &[z(1000.0, 1e5)], false).unwrap();
        // Acceleration 1.5·p·ω²/R and jerk 6·p·ω³/R², the larger bound wins (jerk here).
        let (acc, jerk) = (
            1.5 * 1.5 * 100.0 / p.ramp,
            6.0 * 1.5 * 1000.0 / p.ramp.powi(2),
        );
        assert!(
            acc <= 1000.0 * (1.0 + 1e-12) && jerk <= 1e5 * (1.0 + 1e-12),
            "{p:?}"
        );
        assert!(
            (jerk - 1e5).abs() < 1e-6 || (acc - 1000.0).abs() < 1e-9,
            "{p:?}"
        );
        // Sampled in time at 600 rpm: the velocity, acceleration and jerk of s(u(t)).
        let dt = 1e-4;
        let s: Vec<f64> = (0..20_000)
            .map(|i| p.position(p.ramp_start() - 0.1 + 10.0 * dt * i as f64))
            .collect();
        let mut amax: f64 = 0.0;
        for w in s.windows(3) {
            amax = amax.max(((w[2] - 2.0 * w[1] + w[0]) / (dt * dt)).abs());
        }
        assert!(amax <= 1000.0 * 1.001, "{amax}");
        // The thread: 15 mm/s, p per revolution.
        let u = p.ramp_start() + p.ramp + 1.0;
        assert!((p.position(u + 1.0) - p.position(u) - 1.5).abs() < 1e-12);
        // A whole number of pitches from the anchor's helix.
        assert_eq!(p.position(u), 1.5 * (u - p.k));
        assert_eq!(p.k, p.k.round());
        assert!(p.ramp_start() >= 0.0);
        // It ends at the end, at rest.
        assert!((p.position(p.table_end()) - 20.0).abs() < 1e-12);
        assert!((p.position(p.table_end() - 1e-6) - 20.0).abs() < 1e-9);
    }

    #[test]
    fn the_cards_table_follows_the_plan() {
        for (pitch, len, w, tap) in [
            (1.5, 20.0, 10.0, false),
            (1.0, 10.0, 10.0, true),
            (0.5, 500.0, 20.0, false),
            (2.0, 3.0, 5.0, false),
        ] {
            let p = ThreadPlan::new(pitch, len, w, (100.0, 1e4), &[z(1000.0, 1e5)], tap).unwrap();
            let pts = p.table();
            assert!(pts.len() <= CAM_MAX_POINTS, "{}", pts.len());
            let lin = (p.ramp_start() + p.ramp, p.linear_end());
            let e_lin = table_error(&p, lin.0, lin.1);
            let e_all = table_error(&p, p.ramp_start() - 1.0, p.table_end() + 1.0);
            println!("p {pitch} L {len} tap {tap}: {} points, R {:.3} rev, thread {e_lin:.1e} mm, ramps {e_all:.1e} mm", pts.len(), p.ramp);
            // Within 0.1 µm everywhere (measured: 1e-8 mm).
            assert!(e_lin < 1e-7, "{pitch} {len}: the thread {e_lin}");
            assert!(e_all < 1e-7, "{pitch} {len}: the ramps {e_all}");
        }
    }

    #[test]
    fn impossible_threads_are_refused() {
        let e = |r: std::result::Result<ThreadPlan, String>| r.unwrap_err();
        // 2 mm at 6000 rpm: 200 mm/s on an axis of 100.
        assert!(e(ThreadPlan::new(
            2.0,
            20.0,
            100.0,
            (100.0, 1e4),
            &[z(1e3, 1e5)],
            false
        ))
        .contains("above its limit"));
        assert!(e(ThreadPlan::new(
            0.0,
            20.0,
            10.0,
            (100.0, 1e4),
            &[z(1e3, 1e5)],
            false
        ))
        .contains("pitch"));
        assert!(e(ThreadPlan::new(
            1.0,
            20.0,
            0.0,
            (100.0, 1e4),
            &[z(1e3, 1e5)],
            false
        ))
        .contains("stopped"));
        // A tap whose spindle reverses harder than the axis may follow: 2 mm × 600 rev/s².
        assert!(e(ThreadPlan::new(
            2.0,
            20.0,
            10.0,
            (600.0, 1e4),
            &[z(1e3, 1e5)],
            true
        ))
        .contains("reversal"));
        // Too short for its ramps.
        assert!(e(ThreadPlan::new(
            1.5,
            0.1,
            10.0,
            (100.0, 1e4),
            &[z(1e3, 1e5)],
            false
        ))
        .contains("shorter"));
    }

    #[test]
    fn spread_grows_and_ends_inside() {
        let pts = spread(0.0, 100.0, 0.01);
        assert!(pts.windows(2).all(|w| w[1] > w[0]));
        assert!(pts[0] > 0.0 && *pts.last().unwrap() < 100.0);
        assert!((pts[0] - 0.01).abs() < 1e-12);
        assert!(pts.len() < 900, "{}", pts.len());
        assert!(spread(0.0, 0.001, 0.01).is_empty());
    }
}
