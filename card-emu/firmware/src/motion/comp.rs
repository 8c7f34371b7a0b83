//! Leadscrew pitch-error and backlash compensation (layout 1.9): the table, its checks, its
//! interpolation, and the ramp that takes up every jump of the correction.
//!
//! ## The frames
//! The user commands where the *load* (the nut, the table) goes: the commanded position `x`.
//! The encoder is on the motor, and the leadscrew between them has a pitch error and a dead
//! band (backlash), so the load is not where the motor's count says. The correction `c` is
//! what the motor must be moved by so that the load is at `x`: the servo follows
//! `x + c(x, direction)`, the *compensated* position, and the load's position is estimated as
//! the motor's less the correction in force.
//!
//! ## The table
//! Points `(position, forward, reverse)`, positions strictly increasing, at most
//! [`MAX_POINTS`]. Between two points the correction is linear in the position; before the
//! first and after the last the end point's correction holds. `forward` applies while the
//! commanded velocity is positive (and at rest after a positive motion), `reverse` while it is
//! negative. A scalar backlash `b` adds `+b/2` forward and `-b/2` in reverse (LinuxCNC's
//! convention), so a table of one column plus a backlash and a table of two columns describe
//! the same axis. Every `|correction ± b/2|` is within the table's `bound`.
//!
//! ## Never a step
//! The correction in force is `base(x, dir) + q`: `base` is the table's (continuous in `x`
//! for one direction), `q` the part of a jump still to be taken up. Whenever `base` would jump
//! (a reversal changes the column; a table is loaded or cleared; the axis gains or loses its
//! reference frame), the jump goes into `q` and the correction in force does not move; `q`
//! then runs to 0 along a time-optimal jerk-limited trajectory from its current state
//! (`otg`), within the table's ramp velocity and acceleration (jerk: [`RAMP_JERK_PER_ACC`]
//! times the acceleration). So the correction's own motion is bounded by the ramp's limits
//! plus the table's slope times the commanded velocity, and it is continuous in position and
//! velocity.

use crate::motion::otg::{OtgLimits, Trajectory};

/// Most points a table holds (`MC_COMP_MAX_POINTS`).
pub const MAX_POINTS: usize = firmware_proto::raw::MC_COMP_MAX_POINTS as usize;

/// The ramp's jerk, per unit of its acceleration (1/s): the acceleration is reached in 1 ms.
pub const RAMP_JERK_PER_ACC: f64 = 1000.0;

/// One point of a table, counts.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct CompPoint {
    /// Position, in the axis's homed frame.
    pub position: f64,
    /// Correction moving forward.
    pub forward: f64,
    /// Correction moving in reverse (equal to `forward` for a table of one column).
    pub reverse: f64,
}

/// A table's settings, counts and seconds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CompParams {
    /// The largest `|correction ± backlash/2|` allowed (> 0).
    pub bound: f64,
    /// The dead band taken up on a reversal (>= 0).
    pub backlash: f64,
    /// The ramp's velocity limit (> 0).
    pub ramp_vel: f64,
    /// The ramp's acceleration limit (> 0).
    pub ramp_acc: f64,
    /// The table gives a correction per direction (else `reverse == forward`).
    pub bidir: bool,
}

impl Default for CompParams {
    /// No compensation: bound 1, no backlash, ramps of 1000 counts/s and 10⁶ counts/s².
    fn default() -> Self {
        Self {
            bound: 1.0,
            backlash: 0.0,
            ramp_vel: 1000.0,
            ramp_acc: 1e6,
            bidir: false,
        }
    }
}

/// Why a table is refused (each is one nack: `MC_NACK_COMP_*`, `MC_NACK_NOT_FINITE`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CompError {
    /// A point count, bound, backlash or ramp limit out of range.
    Table,
    /// Data without an open table, or out of order.
    Sequence,
    /// Positions not strictly increasing.
    Order,
    /// A correction beyond the bound, or a reverse correction in a table of one column that
    /// differs from the forward one.
    Bound,
    /// A value that is NaN or infinite.
    NotFinite,
}

impl CompParams {
    /// The settings alone: finite, bound > 0, backlash in `0..=2·bound`, ramp limits in the
    /// card's kinematic range at `servo_rate_hz`.
    pub fn validate(&self, servo_rate_hz: u32) -> Result<(), CompError> {
        let v = [self.bound, self.backlash, self.ramp_vel, self.ramp_acc];
        if v.iter().any(|x| !x.is_finite()) {
            return Err(CompError::NotFinite);
        }
        if self.bound <= 0.0
            || self.bound > crate::MAX_POSITION
            || self.backlash < 0.0
            || self.backlash > 2.0 * self.bound
        {
            return Err(CompError::Table);
        }
        self.ramp_limits()
            .check_range(servo_rate_hz)
            .map_err(|_| CompError::Table)
    }

    /// The ramp's limits.
    pub fn ramp_limits(&self) -> OtgLimits {
        OtgLimits::symmetric(
            self.ramp_vel,
            self.ramp_acc,
            self.ramp_acc * RAMP_JERK_PER_ACC,
        )
    }

    /// Point `p`, the one before it (if any): finite, after `prev`, within the bound.
    pub fn check_point(&self, prev: Option<&CompPoint>, p: &CompPoint) -> Result<(), CompError> {
        if ![p.position, p.forward, p.reverse]
            .iter()
            .all(|x| x.is_finite())
        {
            return Err(CompError::NotFinite);
        }
        if p.position.abs() > crate::MAX_POSITION {
            return Err(CompError::Order);
        }
        if let Some(q) = prev {
            if p.position <= q.position {
                return Err(CompError::Order);
            }
        }
        if !self.bidir && p.reverse != p.forward {
            return Err(CompError::Bound);
        }
        let half = 0.5 * self.backlash;
        if (p.forward + half).abs() > self.bound || (p.reverse - half).abs() > self.bound {
            return Err(CompError::Bound);
        }
        Ok(())
    }

    /// A whole table: [`CompParams::validate`], at most [`MAX_POINTS`] points, each checked.
    pub fn check_table(&self, points: &[CompPoint], servo_rate_hz: u32) -> Result<(), CompError> {
        self.validate(servo_rate_hz)?;
        if points.len() > MAX_POINTS {
            return Err(CompError::Table);
        }
        let mut prev = None;
        for p in points {
            self.check_point(prev, p)?;
            prev = Some(p);
        }
        Ok(())
    }
}

/// The table's correction at `x` moving forward (`true`) or in reverse, and its slope
/// d(correction)/dx there (0 outside the table). No backlash.
#[inline]
pub fn interpolate(points: &[CompPoint], x: f64, forward: bool) -> (f64, f64) {
    let col = |p: &CompPoint| if forward { p.forward } else { p.reverse };
    let (Some(first), Some(last)) = (points.first(), points.last()) else {
        return (0.0, 0.0);
    };
    if x.is_nan() {
        return (col(first), 0.0);
    }
    if x <= first.position {
        return (col(first), 0.0);
    }
    if x >= last.position {
        return (col(last), 0.0);
    }
    // first.position < x < last.position: 1 <= i <= len - 1.
    let i = points.partition_point(|p| p.position <= x);
    let (Some(a), Some(b)) = (points.get(i.wrapping_sub(1)), points.get(i)) else {
        return (col(last), 0.0);
    };
    let slope = (col(b) - col(a)) / (b.position - a.position);
    (col(a) + slope * (x - a.position), slope)
}

/// What the compensation of one axis holds from tick to tick (plain data, no table).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CompState {
    /// The direction of the last motion (forward: positive commanded velocity).
    forward: bool,
    /// Was the table in use last tick?
    active: bool,
    /// Bumped by whoever changes the table or the frame (`changed`).
    generation: u32,
    seen_generation: u32,
    /// `base` of the last tick.
    base: f64,
    /// The part of a jump not taken up yet: position, velocity, acceleration.
    q: (f64, f64, f64),
    /// The ramp running `q` to 0, its time and segment.
    ramp: Option<(Trajectory, f64, usize)>,
    /// The ramp limits (of the last table loaded, or cleared).
    limits: OtgLimits,
    /// The correction in force, its velocity and acceleration.
    applied: (f64, f64, f64),
}

impl Default for CompState {
    fn default() -> Self {
        Self::new()
    }
}

impl CompState {
    /// No compensation.
    pub fn new() -> Self {
        Self {
            forward: true,
            active: false,
            generation: 0,
            seen_generation: 0,
            base: 0.0,
            q: (0.0, 0.0, 0.0),
            ramp: None,
            limits: CompParams::default().ramp_limits(),
            applied: (0.0, 0.0, 0.0),
        }
    }

    /// The table or the frame changed: the next [`CompState::step`] takes up any jump of the
    /// base correction with a ramp of these limits.
    pub fn changed(&mut self, limits: Option<OtgLimits>) {
        self.generation = self.generation.wrapping_add(1);
        if let Some(l) = limits {
            self.limits = l;
        }
    }

    /// The correction in force (counts), its velocity and acceleration.
    #[inline]
    pub fn applied(&self) -> (f64, f64, f64) {
        self.applied
    }

    /// Moving forward (the direction the correction's column is taken for)?
    pub fn forward(&self) -> bool {
        self.forward
    }

    /// No jump is being taken up.
    #[inline]
    pub fn settled(&self) -> bool {
        self.q == (0.0, 0.0, 0.0) && self.ramp.is_none()
    }

    /// Idle: no table in use and nothing to take up (the tick's fast path).
    #[inline]
    pub fn idle(&self) -> bool {
        !self.active && self.settled() && self.applied.0 == 0.0
    }

    /// One tick: the commanded position `x`, velocity `v` and acceleration `a`, the table
    /// and settings if the compensation is to be in use (`None`: it is not). Returns the
    /// correction in force, its velocity and acceleration.
    pub fn step(
        &mut self,
        table: Option<(&[CompPoint], &CompParams)>,
        x: f64,
        v: f64,
        a: f64,
        ts: f64,
    ) -> (f64, f64, f64) {
        if table.is_none() && self.idle() && self.generation == self.seen_generation {
            return (0.0, 0.0, 0.0);
        }
        let forward = if v > 0.0 {
            true
        } else if v < 0.0 {
            false
        } else {
            self.forward
        };
        let (base, slope) = match table {
            Some((points, p)) => {
                let (c, s) = interpolate(points, x, forward);
                let half = 0.5 * p.backlash;
                (c + if forward { half } else { -half }, s)
            }
            None => (0.0, 0.0),
        };
        let jumped = forward != self.forward
            || table.is_some() != self.active
            || self.generation != self.seen_generation;
        self.forward = forward;
        self.active = table.is_some();
        self.seen_generation = self.generation;
        if jumped {
            // The correction in force stays; what the base jumped by is left to take up.
            self.q.0 += self.base - base;
            self.ramp = None;
        }
        self.base = base;
        if let Some((traj, t, seg)) = &mut self.ramp {
            *t += ts;
            let s = traj.sample_from(*t, seg);
            if *t >= traj.duration() {
                self.q = (0.0, 0.0, 0.0);
                self.ramp = None;
            } else {
                self.q = (s.pos, s.vel, s.acc);
            }
        } else if self.q != (0.0, 0.0, 0.0) {
            // Plan from the state the jump left: to rest at 0. A plan that fails (it cannot
            // with valid limits) is tried again next tick, the jump held meanwhile.
            match Trajectory::to_position(self.q.0, self.q.1, self.q.2, 0.0, 0.0, &self.limits) {
                Ok(traj) => self.ramp = Some((traj, 0.0, 0)),
                Err(_) => self.q = (self.q.0, 0.0, 0.0),
            }
        }
        let applied = (base + self.q.0, slope * v + self.q.1, slope * a + self.q.2);
        self.applied = applied;
        applied
    }
}

#[cfg(test)]
mod tests;
