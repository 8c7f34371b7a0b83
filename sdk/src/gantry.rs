//! Layout 1.10: gantry axes. A [`Gantry`] is one logical axis driven by a master and its
//! slaves, each with its own servo loop and drive: the card drives every slave to the master's
//! commanded position of the same servo tick plus the slave's offset, and a yaw (skew) loop
//! corrects each slave's reference acceleration (a force on the slave, through its servo's
//! acceleration feed-forward) by a PI law on its skew
//! (`skew = slave actual − master actual − offset in force`, counts):
//!
//! ```text
//! moving:  I += ki · (skew − clamp(skew, ±1)) · Ts,   correction = −(kp · skew + I)
//! at rest: I = 0,                                      correction = −kp · (skew − clamp(skew, ±1))
//! ```
//!
//! (counts/s², both bounded by the slave's stop deceleration; kp in 1/s², ki in 1/s³: the law
//! and why it acts on the acceleration are in the header, `MC_OP_GANTRY_FORM`'s block).
//! A skew beyond the limit stops every axis of the gantry together (category 1, stop reason
//! [`StopReason::GantrySkew`](crate::StopReason)), and so does a safety stop of any one of
//! them (reason `Gantry` on the others); both post [`EventKind::GantryFault`](crate::EventKind)
//! naming the gantry. The master is commanded like any axis (moves, velocity, jog, halt, stop,
//! power and reset act on every member; a group or path that contains the master drives the
//! slaves); a slave refuses every command of its own ([`ErrorKind::GantrySlave`]).
//! [`Gantry::home`] homes each side with its own homing settings and squares the bridge to the
//! configured offsets. The header (`MC_OP_GANTRY_FORM`) and `card_firmware::firmware::gantry`
//! have the rules.
//!
//! Units: the skew limit, the offsets and every figure of [`GantryStatus`] are in the
//! master's user units; every member must have the master's scale.
//!
//! [`ErrorKind::GantrySlave`]: crate::ErrorKind::GantrySlave

use crate::card::{finite, Axis, Card};
use crate::error::{nack_reason, Error, Result, Target};
use firmware_proto::cmd::{
    GantryForm, GantrySlave, SyncCmd, GANTRY_KI_MAX, GANTRY_KP_MAX, GANTRY_MAX_SLAVES, MAX_GANTRIES,
};
use firmware_proto::{layout, raw, NackCode, MAX_POSITION};
use std::time::Duration;

pub use firmware_proto::cmd::MAX_GANTRIES as GANTRIES_MAX;

/// A gantry's yaw loop and limits (the skew limit and offsets in user units of the master).
#[derive(Debug, Clone, PartialEq)]
pub struct GantryConfig {
    /// Proportional gain of the yaw loop, 1/s² (counts/s² of correction per count of skew,
    /// `0 ≤ kp ≤ 10⁹`).
    pub kp: f64,
    /// Integral gain of the yaw loop, 1/s³ (`0 ≤ ki ≤ 10¹²`).
    pub ki: f64,
    /// The skew beyond which every axis of the gantry stops (> 0).
    pub skew_limit: f64,
    /// Each slave's square offset (slave − master when the bridge is square), in the order of
    /// the slaves; empty: 0 for every slave. Used by [`Gantry::home`].
    pub offsets: Vec<f64>,
}

impl Default for GantryConfig {
    /// kp 10⁶ /s², ki 0 (on the plant's default motors: `tests/gantry.rs`), a skew limit of 0
    /// (it must be set), no offsets.
    fn default() -> Self {
        Self {
            kp: 1e6,
            ki: 0.0,
            skew_limit: 0.0,
            offsets: Vec::new(),
        }
    }
}

/// What a gantry is doing.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GantryPhase {
    /// The slaves follow the master.
    Coupled,
    /// [`Gantry::home`]: each side homes on its own.
    Homing,
    /// [`Gantry::home`]: the slaves move to their square offsets.
    Squaring,
}

/// One slave of a gantry, user units of the master.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GantrySide {
    /// The slave axis.
    pub axis: usize,
    /// Its square offset (configured).
    pub offset: f64,
    /// The offset in force: the skew it was coupled with, the square offset once homed.
    pub hold: f64,
    /// The skew of the last tick: slave actual − master actual − `hold`.
    pub skew: f64,
    /// The yaw loop's correction of the last tick (user units/s²).
    pub correction: f64,
    /// The largest |skew| while coupled since the gantry was formed.
    pub max_skew: f64,
}

/// A gantry as the card reports it.
#[derive(Debug, Clone, PartialEq)]
pub struct GantryStatus {
    /// The gantry's number.
    pub index: usize,
    /// What it is doing.
    pub phase: GantryPhase,
    /// The master axis.
    pub master: usize,
    /// The slaves.
    pub slaves: Vec<GantrySide>,
    /// The yaw loop's gains and the skew limit.
    pub kp: f64,
    /// See [`GantryConfig::ki`].
    pub ki: f64,
    /// See [`GantryConfig::skew_limit`] (user units).
    pub skew_limit: f64,
    /// [`Gantry::home`] squared it (and no power cycle or reset moved a slave's offset in
    /// force by more than a count since).
    pub squared: bool,
}

impl GantryStatus {
    /// The configuration it was formed with (user units).
    pub fn config(&self) -> GantryConfig {
        GantryConfig {
            kp: self.kp,
            ki: self.ki,
            skew_limit: self.skew_limit,
            offsets: self.slaves.iter().map(|s| s.offset).collect(),
        }
    }
}

/// A formed gantry.
#[derive(Clone)]
pub struct Gantry {
    card: Card,
    index: usize,
}

/// A gantry's homing in progress; wait for it with [`GantryHoming::wait`].
#[derive(Clone)]
pub struct GantryHoming {
    card: Card,
    index: usize,
    seq: u32,
}

impl GantryHoming {
    /// The command's seq (the members' own motion events carry it too).
    pub fn seq(&self) -> u32 {
        self.seq
    }

    /// Wait until the bridge is squared: slave 0's skew then (master's user units). A side
    /// that fails is [`Error::GantryHomingFailed`] naming the gantry and the axis.
    pub fn wait(&self, timeout: Duration) -> Result<f64> {
        self.card.wait_gantry_homed(self.index, self.seq, timeout)
    }
}

fn refused(target: Target, code: NackCode) -> Error {
    Error::Refused {
        command: "gantry",
        target,
        code,
        reason: nack_reason(code),
    }
}

impl Card {
    /// Form a gantry of `master` and `slaves` in the first free gantry slot of the card
    /// (see [`Card::gantry_at`]).
    pub fn gantry(&self, master: usize, slaves: &[usize], cfg: &GantryConfig) -> Result<Gantry> {
        let free = (0..MAX_GANTRIES).find(|&g| {
            layout::GANTRY_STATUS.at(g).read(self.window()).phase == raw::MC_GANTRY_NONE
        });
        let Some(g) = free else {
            return Err(refused(Target::Card, NackCode::GantryState));
        };
        self.gantry_at(g, master, slaves, cfg)
    }

    /// Form gantry `index` (below [`GANTRIES_MAX`]) of `master` and `slaves` (1 to 4, each
    /// with the master's scale). Every member at rest, all powered (Standstill) or all
    /// disabled; each slave is coupled where it stands (nothing moves), SynchronizedMotion
    /// while powered. Checked here as the card checks it (nothing is sent): `GantryAxes`
    /// (a slave count, the master among the slaves, a slave twice), `BadAxis`, `NotFinite`,
    /// `GantryGains` (kp, ki, skew limit, an offset, or offsets not one per slave), `BadConfig`
    /// (members of different scales). The card then refuses `GantryInUse` (a member in another
    /// gantry, geared, streaming; a slave in a group) and `GantryState`.
    pub fn gantry_at(
        &self,
        index: usize,
        master: usize,
        slaves: &[usize],
        cfg: &GantryConfig,
    ) -> Result<Gantry> {
        let target = Target::Gantry(index);
        let count = self.info().axes;
        if index >= MAX_GANTRIES || slaves.is_empty() || slaves.len() > GANTRY_MAX_SLAVES {
            return Err(refused(target, NackCode::GantryAxes));
        }
        for (k, &a) in slaves.iter().enumerate() {
            if a == master || slaves[..k].contains(&a) {
                return Err(refused(target, NackCode::GantryAxes));
            }
        }
        if let Some(&axis) = std::iter::once(&master)
            .chain(slaves)
            .find(|&&a| a >= count)
        {
            return Err(Error::BadAxis { axis, count });
        }
        finite("kp", cfg.kp)?;
        finite("ki", cfg.ki)?;
        finite("skew_limit", cfg.skew_limit)?;
        for &o in &cfg.offsets {
            finite("offset", o)?;
        }
        if !cfg.offsets.is_empty() && cfg.offsets.len() != slaves.len() {
            return Err(refused(target, NackCode::GantryGains));
        }
        let scale = self.scale(master);
        if let Some(&a) = slaves.iter().find(|&&a| self.scale(a) != scale) {
            return Err(Error::BadConfig(format!(
                "gantry {index}: axis {a} has {} counts per unit, the master (axis {master}) {scale}",
                self.scale(a)
            )));
        }
        let offset = |k: usize| cfg.offsets.get(k).copied().unwrap_or(0.0) * scale;
        let form = GantryForm {
            master: master as u8,
            kp: cfg.kp,
            ki: cfg.ki,
            skew_limit: cfg.skew_limit * scale.abs(),
            slaves: slaves
                .iter()
                .enumerate()
                .map(|(k, &a)| GantrySlave {
                    axis: a as u8,
                    offset: offset(k),
                })
                .collect(),
        };
        let gains_ok = (0.0..=GANTRY_KP_MAX).contains(&form.kp)
            && (0.0..=GANTRY_KI_MAX).contains(&form.ki)
            && form.skew_limit > 0.0
            && form.skew_limit <= MAX_POSITION
            && form.slaves.iter().all(|s| s.offset.abs() <= MAX_POSITION);
        if !gains_ok {
            return Err(refused(target, NackCode::GantryGains));
        }
        let cmd = SyncCmd::GantryForm(form).command(index as u16);
        self.execute(cmd, "gantry form", target)?;
        Ok(Gantry {
            card: self.clone(),
            index,
        })
    }

    /// A handle to gantry `index` as it is on the card (formed by this host, another one, or
    /// a configuration file); `GantryState` if it is not formed.
    pub fn gantry_handle(&self, index: usize) -> Result<Gantry> {
        let g = Gantry {
            card: self.clone(),
            index,
        };
        g.status()?;
        Ok(g)
    }

    /// Every formed gantry's status, in gantry order.
    pub fn gantries(&self) -> Vec<GantryStatus> {
        (0..MAX_GANTRIES)
            .filter_map(|g| gantry_status(self, g))
            .collect()
    }
}

/// Gantry `g`'s status block in user units, `None` when it is not formed.
fn gantry_status(card: &Card, g: usize) -> Option<GantryStatus> {
    let b = layout::GANTRY_STATUS.at(g).read(card.window());
    let phase = match b.phase {
        raw::MC_GANTRY_COUPLED => GantryPhase::Coupled,
        raw::MC_GANTRY_HOMING => GantryPhase::Homing,
        raw::MC_GANTRY_SQUARING => GantryPhase::Squaring,
        _ => return None,
    };
    let master = b.master as usize;
    let s = card.scale(master);
    let n = (b.nslaves as usize).min(GANTRY_MAX_SLAVES);
    let slaves = (0..n)
        .map(|k| GantrySide {
            axis: b.slave[k] as usize,
            offset: b.offset[k] / s,
            hold: b.hold[k] / s,
            skew: b.skew[k] / s,
            correction: b.correction[k] / s,
            max_skew: b.max_skew[k] / s.abs(),
        })
        .collect();
    Some(GantryStatus {
        index: g,
        phase,
        master,
        slaves,
        kp: b.kp,
        ki: b.ki,
        skew_limit: b.skew_limit / s.abs(),
        squared: b.squared != 0,
    })
}

impl Gantry {
    /// The gantry's number.
    pub fn index(&self) -> usize {
        self.index
    }

    /// Its status (`GantryState` if it is no longer formed).
    pub fn status(&self) -> Result<GantryStatus> {
        gantry_status(&self.card, self.index)
            .ok_or_else(|| refused(Target::Gantry(self.index), NackCode::GantryState))
    }

    /// The master axis: the handle the gantry is commanded through.
    pub fn master(&self) -> Result<Axis> {
        self.card.axis(self.status()?.master)
    }

    /// Home the gantry: every side runs its own homing method (its [`HomingSettings`], home
    /// position 0), then each slave moves until slave − master is its square offset, which
    /// becomes its offset in force. Every member in Standstill (`GantryState`); each side's
    /// homing settings checked as `MC_Home` checks them.
    ///
    /// [`HomingSettings`]: crate::HomingSettings
    pub fn home(&self) -> Result<GantryHoming> {
        let cmd = SyncCmd::GantryHome.command(self.index as u16);
        let seq = self
            .card
            .execute_seq(cmd, "gantry home", Target::Gantry(self.index))?;
        Ok(GantryHoming {
            card: self.card.clone(),
            index: self.index,
            seq,
        })
    }

    /// Dissolve the gantry: the master at rest (`GantryState`); the slaves hold where they
    /// are, in Standstill, each its own axis again.
    pub fn dissolve(self) -> Result<()> {
        let cmd = SyncCmd::GantryDissolve.command(self.index as u16);
        self.card
            .execute(cmd, "gantry dissolve", Target::Gantry(self.index))
    }
}
