//! Tick step `stop`: the progress of a halt or stop along the path. `MC_GroupHalt` and
//! `MC_GroupStop` replace the active move's feed by a jerk-limited stop profile from its
//! speed (`scurve::plan_stop`, Thinh eq 1–28 run as a stop): each tick advances the time into
//! it, and the profile gives the arc length and the speed there. A straight or circular move
//! takes that arc length; a NURBS curve runs its interpolator at that speed (see `feed`).

use crate::motion::scurve::Profile;

/// One tick of a stop profile.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct StopSample {
    /// Arc length reached (from where the move started), counts.
    pub(super) s: f64,
    /// Speed along the path, counts/s.
    pub(super) v: f64,
    /// The profile has run out: at rest.
    pub(super) done: bool,
}

/// Advance the stop `(profile, time into it)` by `ts`.
pub(super) fn stop_progress((profile, t): &mut (Profile, f64), ts: f64) -> StopSample {
    *t += ts;
    let st = profile.sample(*t);
    StopSample {
        s: st.pos,
        v: st.vel,
        done: *t >= profile.duration(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::motion::scurve::plan_stop;

    /// From 1e5 counts/s at 1000 counts into the move, decelerating at 1e6 counts/s² with
    /// jerk 1e8: the speed falls monotonically to 0, the stop ends at the planned distance
    /// (more than v²/2D = 5000 counts because of the jerk ramps) and then stays there.
    #[test]
    fn a_stop_slows_monotonically_to_rest_at_its_planned_end() {
        let ts = 1e-4;
        let p = plan_stop(1_000.0, 1e5, 0.0, 1e6, 1e8).unwrap();
        let end = p.end_pos();
        assert!(end > 1_000.0 + 5_000.0 && end < 1_000.0 + 5_000.0 + 1e5 * 1e6 / 1e8);
        let mut stop = (p, 0.0);
        let mut prev = stop_progress(&mut stop, ts);
        assert!(prev.v < 1e5 && prev.v > 1e5 - 1e6 * ts);
        assert!((prev.s - (1_000.0 + 1e5 * ts)).abs() < 1e-3, "{}", prev.s);
        let mut ticks = 1;
        while !prev.done {
            let st = stop_progress(&mut stop, ts);
            assert!(
                st.v <= prev.v + 1e-9 && st.s >= prev.s,
                "{prev:?} -> {st:?}"
            );
            prev = st;
            ticks += 1;
            assert!(ticks < 10_000);
        }
        // 0.1 s at 1e6 counts/s² plus the jerk ramp (1e6/1e8 = 10 ms): about 1100 ticks.
        assert!((1_050..=1_150).contains(&ticks), "{ticks} ticks");
        assert!(prev.v.abs() < 1e-6, "{prev:?}");
        assert!((prev.s - end).abs() < 1e-6, "{} vs {end}", prev.s);
        let after = stop_progress(&mut stop, ts);
        assert!(after.done && (after.s - end).abs() < 1e-6 && after.v.abs() < 1e-6);
    }
}
