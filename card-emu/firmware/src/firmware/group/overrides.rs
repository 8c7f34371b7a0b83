//! MC_SetOverride of a group: a feed factor for lines and arcs and a rapid factor for
//! point-to-point moves. An S-curve feed is replanned along the path from its current speed
//! and acceleration (the geometry stays); a constant feed is scaled (the post-interpolation
//! filters smooth the change). 0 holds the group on its path in Moving; a factor above 0
//! resumes from there.

use super::*;
use crate::firmware::nack::plan_nack;
use crate::motion::otg::OtgLimits;
use firmware_proto::OVERRIDE_MAX;

impl Group {
    /// The override that applies to `mv`: rapid for point-to-point moves, else feed.
    pub(super) fn factor_of(&self, mv: &Move) -> f64 {
        if mv.ptp {
            self.overrides.1
        } else {
            self.overrides.0
        }
    }

    /// Set the (feed, rapid) factors and replan the active move's S-curve for its factor. A
    /// factor outside 0..=OVERRIDE_MAX is `OverrideRange`; a replan that fails is its nack,
    /// and then nothing changes.
    pub fn set_override(&mut self, feed: f64, rapid: f64, rate_hz: u32) -> Result<(), NackCode> {
        if !(feed.is_finite() && rapid.is_finite()) {
            return Err(NackCode::NotFinite);
        }
        let range = 0.0..=OVERRIDE_MAX;
        if !(range.contains(&feed) && range.contains(&rapid)) {
            return Err(NackCode::OverrideRange);
        }
        let old = self.overrides;
        self.overrides = (feed, rapid);
        if let Err(e) = self.replan_active(rate_hz) {
            self.overrides = old;
            return Err(e);
        }
        Ok(())
    }

    /// Replan the active move's S-curve (if it runs on its own feed) for the factor in force,
    /// from its arc length, speed and acceleration to the end of its path.
    pub(super) fn replan_active(&mut self, rate_hz: u32) -> Result<(), NackCode> {
        let Some(act) = &self.active else {
            return Ok(());
        };
        let k = self.factor_of(&act.mv);
        let len = act.mv.geom.len();
        let (s, v, a) = (act.s, act.v, act.a);
        let Some(act) = self.active.as_mut().filter(|a| a.stopping.is_none()) else {
            return Ok(());
        };
        let Feed::Profile { lim, .. } = &act.mv.feed else {
            return Ok(());
        };
        act.retimed = Some((plan_path(s, v, a, len, lim, k, rate_hz)?, 0.0));
        Ok(())
    }
}

impl Group {
    /// Hold the active move where it is (as a 0 % override would).
    pub(super) fn hold_active(&mut self, rate_hz: u32) {
        if let Some(act) = &mut self.active {
            let (s, v, a, len) = (act.s, act.v, act.a, act.mv.geom.len());
            if let Feed::Profile { lim, .. } = &act.mv.feed {
                act.retimed = plan_path(s, v, a, len, lim, 0.0, rate_hz)
                    .ok()
                    .map(|hold| (hold, 0.0));
            }
        }
    }
}

/// The path's S-curve from (arc length `s`, speed `v`, acceleration `a`) to rest at `len`
/// within `lim` with its velocity scaled by `k` (0: to rest where it is).
pub(super) fn plan_path(
    s: f64,
    v: f64,
    a: f64,
    len: f64,
    lim: &Limits,
    k: f64,
    rate_hz: u32,
) -> Result<Trajectory, NackCode> {
    let eff = Limits {
        vmax: lim.vmax * k,
        ..*lim
    };
    let along = OtgLimits::along(1.0, if k > 0.0 { &eff } else { lim });
    let traj = if k == 0.0 {
        Trajectory::to_velocity(s, v, a, 0.0, &along)
    } else {
        eff.check_range(rate_hz).map_err(plan_nack)?;
        if v == 0.0 && a == 0.0 {
            Profile::plan_checked(s, len - s, 0.0, 0.0, &eff, rate_hz)
                .map(|p| Trajectory::from_profile(&p))
        } else if let Some(ramp) = Trajectory::slow_to_limit(s, v, a, len, &along) {
            // Down to the lowered feed first (replanned from there when the ramp ends).
            Ok(ramp)
        } else {
            Trajectory::to_position(s, v, a, len, 0.0, &along)
        }
    }
    .and_then(|t| t.verify(&along).map(|()| t))
    .map_err(plan_nack)?;
    if !traj.duration().is_finite() || traj.duration() > crate::MAX_MOVE_TIME {
        return Err(NackCode::Infeasible);
    }
    Ok(traj)
}
