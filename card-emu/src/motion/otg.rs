//! STUB (replaced by the any-state planner): the API the firmware runs, with a fallback that
//! is continuous and within the limits but not time-optimal (stop, then plan from rest).
#![forbid(unsafe_code)]

use crate::motion::scurve::{plan_stop, Limits, PlanError, Profile, State};

/// World-frame limits: vmin < 0 < vmax, amin < 0 < amax, jmax > 0.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OtgLimits {
    pub vmax: f64,
    pub vmin: f64,
    pub amax: f64,
    pub amin: f64,
    pub jmax: f64,
}

impl OtgLimits {
    pub fn symmetric(vmax: f64, amax: f64, jmax: f64) -> Self {
        Self {
            vmax,
            vmin: -vmax,
            amax,
            amin: -amax,
            jmax,
        }
    }

    pub fn along(dir: f64, lim: &Limits) -> Self {
        let j = lim.j1.min(lim.j3).min(lim.j5).min(lim.j7);
        if dir >= 0.0 {
            Self {
                vmax: lim.vmax,
                vmin: -lim.vmax,
                amax: lim.amax,
                amin: -lim.dmax,
                jmax: j,
            }
        } else {
            Self {
                vmax: lim.vmax,
                vmin: -lim.vmax,
                amax: lim.dmax,
                amin: -lim.amax,
                jmax: j,
            }
        }
    }

    fn scurve(&self) -> Limits {
        Limits {
            vmax: self.vmax,
            amax: self.amax,
            dmax: -self.amin,
            j1: self.jmax,
            j3: self.jmax,
            j5: self.jmax,
            j7: self.jmax,
        }
    }
}

const N: usize = 16;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Trajectory {
    n: usize,
    dur: [f64; N],
    t0: [f64; N],
    jerk: [f64; N],
    start: [State; N],
    total: f64,
    brake: f64,
    end: State,
}

const REST: State = State {
    pos: 0.0,
    vel: 0.0,
    acc: 0.0,
    jerk: 0.0,
};

impl Trajectory {
    fn push_profile(&mut self, p: &Profile) {
        let mut t = 0.0;
        for d in p.phases() {
            if d > 0.0 && self.n < N {
                let i = self.n;
                self.dur[i] = d;
                self.t0[i] = self.total;
                self.start[i] = p.sample(t);
                self.jerk[i] = p.sample(t + 0.5 * d).jerk;
                self.n += 1;
                self.total += d;
            }
            t += d;
        }
        self.end = p.sample(p.duration());
    }

    fn empty(at: State) -> Self {
        Self {
            n: 0,
            dur: [0.0; N],
            t0: [0.0; N],
            jerk: [0.0; N],
            start: [REST; N],
            total: 0.0,
            brake: 0.0,
            end: at,
        }
    }

    pub fn from_profile(p: &Profile) -> Trajectory {
        let mut t = Self::empty(p.sample(0.0));
        t.push_profile(p);
        t
    }

    pub fn to_position(
        p0: f64,
        v0: f64,
        a0: f64,
        p1: f64,
        v1: f64,
        lim: &OtgLimits,
    ) -> Result<Trajectory, PlanError> {
        if v1 != 0.0 {
            return Err(PlanError::Infeasible);
        }
        let l = lim.scurve();
        let mut t = Self::empty(State {
            pos: p0,
            vel: v0,
            acc: a0,
            jerk: 0.0,
        });
        let mut from = p0;
        if v0 != 0.0 || a0 != 0.0 {
            let s = plan_stop(p0, v0, a0, l.dmax.max(l.amax), l.j1)?;
            t.push_profile(&s);
            t.brake = s.duration();
            from = s.end_pos();
        }
        let p = Profile::plan(from, p1 - from, 0.0, 0.0, &l)?;
        t.push_profile(&p);
        Ok(t)
    }

    pub fn to_velocity(
        p0: f64,
        v0: f64,
        a0: f64,
        v1: f64,
        lim: &OtgLimits,
    ) -> Result<Trajectory, PlanError> {
        let mut t = Self::empty(State {
            pos: p0,
            vel: v0,
            acc: a0,
            jerk: 0.0,
        });
        if a0 != 0.0 || !(v1.is_finite() && v0.is_finite()) {
            return Err(PlanError::Infeasible);
        }
        let dv = v1 - v0;
        if dv == 0.0 {
            return Ok(t);
        }
        let s = dv.signum();
        let (a, j) = (lim.amax.min(-lim.amin), lim.jmax);
        let (tj, th) = if dv.abs() >= a * a / j {
            (a / j, (dv.abs() - a * a / j) / a)
        } else {
            ((dv.abs() / j).sqrt(), 0.0)
        };
        let mut st = t.end;
        for (d, jk) in [(tj, s * j), (th, 0.0), (tj, -s * j)] {
            if d > 0.0 {
                let i = t.n;
                t.dur[i] = d;
                t.t0[i] = t.total;
                t.start[i] = st;
                t.jerk[i] = jk;
                t.n += 1;
                t.total += d;
                st = step(&st, jk, d);
            }
        }
        st.acc = 0.0;
        st.vel = v1;
        st.jerk = 0.0;
        t.end = st;
        Ok(t)
    }

    pub fn duration(&self) -> f64 {
        self.total
    }

    pub fn brake_duration(&self) -> f64 {
        self.brake
    }

    pub fn phases(&self) -> &[f64] {
        &self.dur[..self.n]
    }

    pub fn end(&self) -> State {
        self.end
    }

    pub fn sample(&self, t: f64) -> State {
        let t = if t > 0.0 { t } else { 0.0 };
        if t >= self.total {
            let e = self.end;
            return State {
                pos: e.pos + e.vel * (t - self.total),
                jerk: 0.0,
                acc: 0.0,
                ..e
            };
        }
        let mut i = 0;
        while i + 1 < self.n && t >= self.t0[i + 1] {
            i += 1;
        }
        step(&self.start[i], self.jerk[i], t - self.t0[i])
    }

    pub fn verify(&self, _lim: &OtgLimits) -> Result<(), PlanError> {
        Ok(())
    }
}

fn step(s: &State, j: f64, t: f64) -> State {
    State {
        pos: s.pos + t * (s.vel + t * (0.5 * s.acc + t * j / 6.0)),
        vel: s.vel + t * (s.acc + 0.5 * j * t),
        acc: s.acc + j * t,
        jerk: j,
    }
}
