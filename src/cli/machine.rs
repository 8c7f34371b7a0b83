//! What `mcctl compare`, `probe`, `gear` and `cam` share: a machine's I/O and synchronised
//! motion tried from the command line. Each arms or couples, optionally runs the move that
//! exercises it (an absolute move of the axis watched, or of the master), collects what the
//! card reports meanwhile and prints it. The move is mcctl's own: the card halts what a leaving
//! host started, so everything here ends with the process. Positions are the axes' user units,
//! which mcctl leaves at counts.

use super::args::{SyncArgs, TravelArgs};
use super::{hold_for, interrupt, progress, show_axis, POLL, WAIT};
use crate::{Card, CardEvent, Error, Master, Motion, MoveLimits, Result, SyncLimits};
use std::time::Duration;

/// An absolute move that exercises what was armed or coupled.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Travel {
    /// The axis moved (the watched axis, or the master).
    pub axis: usize,
    /// Its target.
    pub target: f64,
    pub limits: MoveLimits,
}

impl TravelArgs {
    /// The move of `axis` to --move, when given.
    pub fn travel(&self, axis: usize) -> Option<Travel> {
        self.target.map(|target| Travel {
            axis,
            target,
            limits: self.limits.limits(),
        })
    }
}

impl Travel {
    pub(crate) fn start(&self, card: &Card) -> Result<Motion> {
        card.axis(self.axis)?
            .move_absolute(self.target, &self.limits)
    }
}

/// The axes a command powered for itself (`--enable`): powered off again when it ends, on
/// every path ([`Powered::release`], or when dropped after an error). An axis still moving
/// then is halted first at its (deceleration, jerk) and waited for: MC_Power off cuts a
/// moving axis's power at once.
pub struct Powered<'a> {
    card: &'a Card,
    axes: Vec<(usize, (f64, f64))>,
}

impl<'a> Powered<'a> {
    /// Power on those of `axes` (each with the deceleration and jerk it is halted at) that are
    /// disabled; `enable` false: none.
    pub fn on(card: &'a Card, enable: bool, axes: &[(usize, (f64, f64))]) -> Result<Self> {
        let mut p = Powered {
            card,
            axes: Vec::new(),
        };
        if enable {
            for &(a, halt) in axes {
                let ax = card.axis(a)?;
                if ax.status()?.state == crate::AxisState::Disabled {
                    ax.enable()?;
                    p.axes.push((a, halt));
                }
            }
        }
        Ok(p)
    }

    /// Power the axes off again (the first error, after trying every axis).
    pub fn release(mut self) -> Result<()> {
        self.power_off()
    }

    fn power_off(&mut self) -> Result<()> {
        let mut first = Ok(());
        for (a, (dec, jerk)) in std::mem::take(&mut self.axes).into_iter().rev() {
            let r = (|| {
                let ax = self.card.axis(a)?;
                let st = ax.status()?;
                if st.command_velocity != 0.0 || st.state != crate::AxisState::Standstill {
                    if let Ok(m) = ax.halt(dec, jerk) {
                        let _ = m.wait(WAIT);
                    }
                }
                ax.disable()
            })();
            if first.is_ok() {
                first = r;
            }
        }
        first
    }
}

impl Drop for Powered<'_> {
    fn drop(&mut self) {
        let _ = self.power_off();
    }
}

/// Run `travel` (or let `hold` pass), calling `each` between looks at the card with the
/// events taken meanwhile. Returns where the moved axis ended (`None` without a move).
pub(crate) fn run_collecting(
    card: &Card,
    travel: Option<&Travel>,
    hold: Duration,
    mut each: impl FnMut(Option<CardEvent>) -> Result<()>,
) -> Result<Option<f64>> {
    let motion = travel.map(|t| t.start(card)).transpose()?;
    let bar = progress(
        None,
        if motion.is_some() {
            "moving"
        } else {
            "watching"
        },
    );
    // Card time held, so a stepped card holds as long as a real one.
    let mut held = Duration::ZERO;
    let at = loop {
        interrupt::check()?;
        while let Some(e) = card.next_event(Duration::ZERO)? {
            each(Some(e))?;
        }
        each(None)?;
        if let Some(t) = travel {
            show_axis(card, t.axis, &bar)?;
        }
        match &motion {
            Some(m) => match m.wait(POLL) {
                Ok(at) => break Some(at),
                Err(Error::Timeout(_)) => {}
                Err(e) => return Err(e),
            },
            None if held >= hold => break None,
            None => {
                hold_for(card, POLL);
                held += POLL;
            }
        }
    };
    bar.finish_and_clear();
    // What the card posted in the move's last tick.
    hold_for(card, POLL);
    while let Some(e) = card.next_event(Duration::ZERO)? {
        each(Some(e))?;
    }
    Ok(at)
}

/// The deceleration and jerk a powered axis is halted at when a command ends with it moving.
pub(crate) fn halt_of(travel: Option<&Travel>) -> (f64, f64) {
    travel.map_or((1e6, 5e7), |t| (t.limits.deceleration, t.limits.jerk[3]))
}

/// A master as `mcctl` names it: `N` (axis N's commanded position), `actual:N`, `lead:N`
/// (actual, led by a servo period), `aux:K`.
pub fn parse_master(s: &str) -> std::result::Result<Master, String> {
    let num = |t: &str| {
        t.parse::<usize>()
            .map_err(|_| format!("`{s}` is not a master: N, actual:N, lead:N or aux:K"))
    };
    match s.split_once(':') {
        None => num(s).map(Master::Commanded),
        Some(("actual", n)) => num(n).map(Master::Actual),
        Some(("lead", n)) => num(n).map(Master::ActualLead),
        Some(("aux", k)) => num(k).map(Master::Aux),
        Some(_) => Err(format!(
            "`{s}` is not a master: N, actual:N, lead:N or aux:K"
        )),
    }
}

/// A master's position now: the commanded or actual position of an axis, or an auxiliary
/// encoder's count.
pub(crate) fn master_position(card: &Card, m: Master) -> Result<f64> {
    Ok(match m {
        Master::Commanded(a) => card.axis(a)?.status()?.command_position,
        Master::Actual(a) | Master::ActualLead(a) => card.axis(a)?.status()?.actual_position,
        Master::Aux(k) => card.aux_encoder(k)? as f64,
    })
}

/// What `mcctl gear` and `mcctl cam` share: the slave, its master, its limits while it
/// engages, and the master's move (or how long to follow an auxiliary encoder).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Coupling {
    pub slave: usize,
    pub master: Master,
    pub limits: SyncLimits,
    pub travel: Option<Travel>,
    pub hold: Duration,
    /// Power the axes it moves if they are disabled (`--enable`): once the card took what it
    /// was given (a cam table), and off again at the end, however it ends.
    pub enable: bool,
}

impl Coupling {
    /// The axes it moves: the slave, and the master axis when it runs a move.
    pub fn axes(&self) -> Vec<usize> {
        [Some(self.slave), self.travel.map(|t| t.axis)]
            .into_iter()
            .flatten()
            .collect()
    }

    /// [`Coupling::axes`] with the deceleration and jerk each is halted at.
    fn halts(&self) -> Vec<(usize, (f64, f64))> {
        let slave = (self.slave, (self.limits.acceleration, self.limits.jerk));
        std::iter::once(slave)
            .chain(self.travel.map(|t| (t.axis, halt_of(Some(&t)))))
            .collect()
    }
}

/// The slave engaged (waited until in sync), the master moved, then the slave uncoupled and
/// halted. Returns the master's and the slave's commanded positions once in sync and at the
/// end.
pub(crate) fn couple(
    card: &Card,
    c: &Coupling,
    engage: impl FnOnce() -> Result<Motion>,
) -> Result<[(f64, f64); 2]> {
    let power = Powered::on(card, c.enable, &c.halts())?;
    let r = run_coupled(card, c, engage);
    let released = power.release();
    let r = r?;
    released.map(|()| r)
}

fn run_coupled(
    card: &Card,
    c: &Coupling,
    engage: impl FnOnce() -> Result<Motion>,
) -> Result<[(f64, f64); 2]> {
    let slave = card.axis(c.slave)?;
    let synced = engage()?;
    synced.wait_in_sync(WAIT)?;
    let read = || -> Result<(f64, f64)> {
        Ok((
            master_position(card, c.master)?,
            slave.status()?.command_position,
        ))
    };
    let start = read()?;
    run_collecting(card, c.travel.as_ref(), c.hold, |_| Ok(()))?;
    // A slave of a commanded position follows it a servo tick late.
    hold_for(card, POLL);
    let end = read()?;
    slave.gear_out()?;
    slave
        .halt(c.limits.acceleration, c.limits.jerk)?
        .wait(WAIT)?;
    Ok([start, end])
}

/// The coupling of `mcctl gear` and `mcctl cam`: the master's move needs a master axis.
pub fn coupling(
    slave: usize,
    master: Master,
    sync: &SyncArgs,
    t: &TravelArgs,
) -> Result<Coupling, String> {
    let axis = match master {
        Master::Commanded(a) | Master::Actual(a) | Master::ActualLead(a) => Some(a),
        Master::Aux(_) => None,
    };
    let travel = match (axis, t.target) {
        (Some(a), _) => t.travel(a),
        (None, None) => None,
        (None, Some(_)) => {
            return Err("--move needs a master axis, not an auxiliary encoder".into())
        }
    };
    Ok(Coupling {
        slave,
        master,
        limits: SyncLimits::new(sync.slave_vmax, sync.slave_amax, sync.slave_jmax),
        travel,
        hold: t.hold,
        enable: t.enable,
    })
}
