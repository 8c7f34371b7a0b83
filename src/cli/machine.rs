//! `mcctl compare`, `probe`, `gear` and `cam`: a machine's I/O and synchronised motion tried
//! from the command line. Each arms or couples, optionally runs the move that exercises it
//! (an absolute move of the axis watched, or of the master), collects what the card reports
//! meanwhile and prints it. The move is mcctl's own: the card halts what a leaving host
//! started, so everything here ends with the process. Positions are the axes' user units,
//! which mcctl leaves at counts.

use super::{hold_for, interrupt, progress, show_axis, POLL, WAIT};
use crate::{
    Card, CardEvent, CompareChannel, Direction, Error, EventKind, Master, Motion, MoveLimits,
    ProbeTrigger, Result, SyncLimits, COMPARE_FIRED, COMPARE_MISSED,
};
use card_emu::motion::cam::CamTable;
use serde_json::json;
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

impl Travel {
    fn start(&self, card: &Card) -> Result<Motion> {
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
fn run_collecting(
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

/// Where a compare channel fires.
#[derive(Debug, Clone, PartialEq)]
pub enum ComparePositions {
    /// Once, at this position.
    At(f64),
    /// `count` positions from `start`, `pitch` apart in the direction.
    Series { start: f64, pitch: f64, count: u32 },
    /// The positions of this file ([`table_positions`]) in order (strictly monotonic in the
    /// direction), read and streamed into the channel's table as it empties.
    Table(std::path::PathBuf),
}

/// Checks a compare table file a line at a time (one finite position a line, strictly
/// monotonic in `dir` when it is Positive or Negative) and counts its positions, so that a
/// bad file is refused before anything is armed or moved. Err: the line and what is wrong.
pub fn table_positions(path: &std::path::Path, dir: Direction) -> std::result::Result<u64, String> {
    let (mut n, mut last) = (0u64, None::<f64>);
    for row in super::file_rows(path, 1..=1, "position")? {
        let r = row?;
        let p = r.values[0];
        let onward = match (dir, last) {
            (Direction::Positive, Some(q)) => p > q,
            (Direction::Negative, Some(q)) => p < q,
            _ => true,
        };
        if !onward {
            return Err(format!(
                "line {}: position {p} does not come after {} in the {} direction",
                r.line,
                last.unwrap_or_default(),
                if dir == Direction::Positive {
                    "positive"
                } else {
                    "negative"
                }
            ));
        }
        last = Some(p);
        n += 1;
    }
    if n == 0 {
        return Err("no positions".into());
    }
    Ok(n)
}

/// `mcctl compare`.
#[derive(Debug, Clone, PartialEq)]
pub struct CompareJob {
    pub axis: usize,
    pub channel: usize,
    pub output: u32,
    pub pulse_us: u32,
    pub direction: Direction,
    pub positions: ComparePositions,
    pub travel: Option<Travel>,
    /// Without a move: how long to watch.
    pub hold: Duration,
    /// Power the axis for the move if it is disabled (`--enable`; off again at the end).
    pub enable: bool,
}

/// Arm a compare channel, run the move, and report the channel's own counters with the
/// positions of the card's events (a fire each; the misses of one tick share one event, with
/// the last position); the channel is disarmed at the end. With `enable`, the axis is powered
/// only for a move, once the channel is armed, and powered off again however it ends.
pub fn compare(card: &Card, job: &CompareJob, json: bool) -> Result<String> {
    let ch = card.axis(job.axis)?.compare(job.channel);
    let (out, dir) = (job.output, job.direction);
    let mut table = None;
    match &job.positions {
        ComparePositions::At(p) => ch.arm_single(out, job.pulse_us, *p, dir)?,
        ComparePositions::Series {
            start,
            pitch,
            count,
        } => ch.arm_series(out, job.pulse_us, *start, *pitch, *count, dir)?,
        ComparePositions::Table(path) => {
            let rows =
                super::file_rows(path, 1..=1, "position").map_err(|e| table_error(path, e))?;
            ch.arm_table(out, job.pulse_us, 0, dir)?;
            table = Some((path.as_path(), rows));
        }
    }
    let axis = [(job.axis, halt_of(job.travel.as_ref()))];
    let outcome = Powered::on(card, job.enable && job.travel.is_some(), &axis).and_then(|power| {
        let r = watch_compare(card, &ch, job, table, json);
        let released = power.release();
        let r = r?;
        released.map(|()| r)
    });
    let disarmed = ch.disarm();
    let (fired, missed, at) = outcome?;
    disarmed?;
    let st = ch.status()?;
    Ok(if json {
        json!({
            "axis": job.axis,
            "channel": job.channel,
            "output": job.output,
            "fires": st.fires,
            "missed": st.missed,
            "fired_at": fired,
            "missed_at": missed,
            "position": at,
        })
        .to_string()
    } else {
        let span = |v: &[f64]| match (v.first(), v.last()) {
            (Some(a), Some(b)) => format!(" ({a} .. {b})"),
            _ => String::new(),
        };
        format!(
            "compare {} on axis {}: {} fired{}, {} missed{}, output {}\n",
            job.channel,
            job.axis,
            st.fires,
            span(&fired),
            st.missed,
            span(&missed),
            job.output
        )
    })
}

/// The deceleration and jerk a powered axis is halted at when a command ends with it moving.
fn halt_of(travel: Option<&Travel>) -> (f64, f64) {
    travel.map_or((1e6, 5e7), |t| (t.limits.deceleration, t.limits.jerk[3]))
}

/// A table file that could not be read as it was checked (it changed meanwhile).
fn table_error(path: &std::path::Path, e: String) -> Error {
    Error::Io {
        context: path.display().to_string(),
        source: std::io::Error::other(e),
    }
}

/// The positions fired and missed (from the card's events; with `json` every one, else only
/// the first and the last) and where the move ended.
type Fires = (Vec<f64>, Vec<f64>, Option<f64>);

/// A position of an event: every one kept for the JSON, else the first and the last.
fn keep(v: &mut Vec<f64>, p: f64, all: bool) {
    if all || v.len() < 2 {
        v.push(p);
    } else {
        v[1] = p;
    }
}

fn watch_compare<R: std::io::BufRead>(
    card: &Card,
    ch: &CompareChannel,
    job: &CompareJob,
    mut table: Option<(&std::path::Path, super::NumberRows<R>)>,
    json: bool,
) -> Result<Fires> {
    let (mut fired, mut missed) = (Vec::new(), Vec::new());
    // At most a table's room of positions in hand.
    let mut batch = Vec::new();
    let at = run_collecting(card, job.travel.as_ref(), job.hold, |e| {
        match e {
            Some(e) if e.kind == EventKind::Compare && e.axis as usize == job.channel => {
                match e.code {
                    COMPARE_FIRED => keep(&mut fired, e.value, json),
                    COMPARE_MISSED => keep(&mut missed, e.value, json),
                    _ => {}
                }
            }
            Some(_) => {}
            None => {
                if let Some((path, rows)) = &mut table {
                    let room = ch.room()?;
                    batch.clear();
                    for row in rows.by_ref().take(room) {
                        batch.push(row.map_err(|e| table_error(path, e))?.values[0]);
                    }
                    if !batch.is_empty() {
                        ch.push(job.direction, &batch)?;
                    }
                    if batch.len() < room {
                        table = None;
                    }
                }
            }
        }
        Ok(())
    })?;
    Ok((fired, missed, at))
}

/// `mcctl probe`.
#[derive(Debug, Clone, PartialEq)]
pub struct ProbeJob {
    pub axis: usize,
    pub channel: usize,
    pub trigger: ProbeTrigger,
    pub travel: Option<Travel>,
    pub hold: Duration,
    /// Power the axis for the move if it is disabled (`--enable`; off again at the end).
    pub enable: bool,
}

/// Arm a touch probe (MC_TouchProbe), run the move, and report every capture the card posted;
/// the probe is aborted at the end (MC_AbortTrigger). With `enable`, the axis is powered only
/// for a move, once the probe is armed, and powered off again however it ends.
pub fn probe(card: &Card, job: &ProbeJob, json: bool) -> Result<String> {
    let tp = card.axis(job.axis)?.touch_probe(job.channel);
    tp.arm(&job.trigger)?;
    let mut captures = Vec::new();
    let axis = [(job.axis, halt_of(job.travel.as_ref()))];
    let outcome = Powered::on(card, job.enable && job.travel.is_some(), &axis).and_then(|power| {
        let r = run_collecting(card, job.travel.as_ref(), job.hold, |e| {
            if let Some(e) =
                e.filter(|e| e.kind == EventKind::Probe && e.axis as usize == job.channel)
            {
                captures.push(e.value);
            }
            Ok(())
        });
        let released = power.release();
        let r = r?;
        released.map(|()| r)
    });
    let st = tp.status();
    let aborted = tp.abort();
    let at = outcome?;
    let st = st?;
    aborted?;
    Ok(if json {
        json!({
            "axis": job.axis,
            "channel": job.channel,
            "captures": st.captures,
            "outside_window": st.outside,
            "positions": captures,
            "position": at,
        })
        .to_string()
    } else {
        let mut s = format!(
            "probe {} on axis {}: {} captures, {} edges outside the window\n",
            job.channel, job.axis, st.captures, st.outside
        );
        for (k, p) in captures.iter().enumerate() {
            s += &format!("  {:>4} {p}\n", k + 1);
        }
        s
    })
}

/// A master as `mcctl` names it: `N` (axis N's commanded position), `actual:N`, `aux:K`.
pub fn parse_master(s: &str) -> std::result::Result<Master, String> {
    let num = |t: &str| {
        t.parse::<usize>()
            .map_err(|_| format!("`{s}` is not a master: N, actual:N or aux:K"))
    };
    match s.split_once(':') {
        None => num(s).map(Master::Commanded),
        Some(("actual", n)) => num(n).map(Master::Actual),
        Some(("aux", k)) => num(k).map(Master::Aux),
        Some(_) => Err(format!("`{s}` is not a master: N, actual:N or aux:K")),
    }
}

/// A master's position now: the commanded or actual position of an axis, or an auxiliary
/// encoder's count.
fn master_position(card: &Card, m: Master) -> Result<f64> {
    Ok(match m {
        Master::Commanded(a) => card.axis(a)?.status()?.command_position,
        Master::Actual(a) => card.axis(a)?.status()?.actual_position,
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
fn couple(
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

/// `mcctl gear`: MC_GearIn at `numerator / denominator`, the master's move, MC_GearOut. Reports
/// both travels and the slave's error against the ratio (0 on the card's integer arithmetic).
pub fn gear(
    card: &Card,
    c: &Coupling,
    numerator: i64,
    denominator: i64,
    json: bool,
) -> Result<String> {
    let slave = card.axis(c.slave)?;
    let [(m0, s0), (m1, s1)] = couple(card, c, || {
        slave.gear_in(c.master, numerator, denominator, &c.limits)
    })?;
    let (dm, ds) = (m1 - m0, s1 - s0);
    let error = ds - dm * numerator as f64 / denominator as f64;
    Ok(if json {
        json!({
            "slave": c.slave,
            "ratio": [numerator, denominator],
            "master_travel": dm,
            "slave_travel": ds,
            "error": error,
        })
        .to_string()
    } else {
        format!(
            "axis {} geared {numerator}/{denominator}: master moved {dm}, slave {ds} (error \
             {error})\n",
            c.slave
        )
    })
}

/// A cam table's shape and the mapping of `mcctl cam`.
#[derive(Debug, Clone, PartialEq)]
pub struct CamJob {
    pub points: Vec<(f64, f64)>,
    pub cubic: bool,
    pub periodic: bool,
    pub settings: crate::CamSettings,
}

/// `mcctl cam`: load the table, MC_CamIn, the master's move, MC_CamOut. Reports where the
/// slave ended against where the table puts it for the master's end position (relative: the
/// table's difference from where the cam started).
pub fn cam(card: &Card, c: &Coupling, job: &CamJob, json: bool) -> Result<String> {
    let cs = &job.settings;
    // The card's refusal first (`CamTable`, `NotFinite`); then the same table on the host.
    card.load_cam_table(cs.table, &job.points, job.cubic, job.periodic)?;
    let table = CamTable::new(&job.points, job.cubic, job.periodic).map_err(|e| {
        Error::Protocol(format!("the card took a cam table the host refuses: {e:?}"))
    })?;
    let slave = card.axis(c.slave)?;
    let [(m0, s0), (m, s)] = couple(card, c, || slave.cam_in(c.master, cs, &c.limits))?;
    let at = |m: f64| cs.slave_scale * table.eval((m - cs.master_offset) / cs.master_scale).s;
    // Relative: the card moved the offset so that the cam started where the slave stood.
    let want = if cs.relative {
        s0 + at(m) - at(m0)
    } else {
        cs.slave_offset + at(m)
    };
    Ok(if json {
        json!({
            "slave": c.slave,
            "table": cs.table,
            "points": job.points.len(),
            "master": m,
            "slave_position": s,
            "table_position": want,
            "error": s - want,
        })
        .to_string()
    } else {
        format!(
            "axis {} on cam table {} ({} points): master at {m}, slave at {s}, the table says \
             {want} (error {})\n",
            c.slave,
            cs.table,
            job.points.len(),
            s - want
        )
    })
}
