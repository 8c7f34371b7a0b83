//! Camming (layout 1.7): PLCopen MC_CamTableSelect, MC_CamIn, MC_CamOut, run by the card.
//!
//! A cam table is up to 1024 points (master, slave) in **encoder counts**, loaded into the
//! card's RAM with commands ([`Card::load_cam_table`]), interpolated linearly or by a cubic
//! spline (velocity and acceleration continuous), periodic or not (a periodic table repeats
//! every span of the master, the slave rising by its last minus first point per cycle).
//! [`Axis::cam_in`] couples a slave to a [`Master`](crate::Master) through a table:
//! `slave = slave_offset + slave_scale · table((master − master_offset) / master_scale)`,
//! caught up within [`SyncLimits`](crate::SyncLimits) as gearing does;
//! [`Axis::cam_switch`] takes another table at the end of the current cycle, the slave's position
//! continuous; [`Axis::cam_out`] leaves it in velocity mode. `card_firmware::motion::cam` and the
//! register map's header (`MC_OP_CAM_TABLE`) have the rules.

use crate::card::{finite, Axis, Card, Motion, Outcome};
use crate::error::{Result, Target};
use crate::sync::{Master, SyncLimits};
use firmware_proto::{
    Opcode, SyncEvent, CAM_AT_CYCLE_END, CAM_CUBIC, CAM_DATA_MAX, CAM_PERIODIC, CAM_RELATIVE,
};
use std::time::Duration;

/// Which cam table, and how it maps the master onto the slave (counts).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CamSettings {
    /// Table 0..`CAM_TABLES`.
    pub table: usize,
    /// Subtracted from the master's position before the table, counts.
    pub master_offset: f64,
    /// Added to the table's slave position, counts.
    pub slave_offset: f64,
    /// The master's position is divided by it before the table (nonzero).
    pub master_scale: f64,
    /// The table's slave position is multiplied by it (nonzero).
    pub slave_scale: f64,
    /// PLCopen StartMode relative: the card shifts the slave offset so that the cam starts
    /// where the slave stands (only a velocity difference is caught up). Else absolute: the
    /// slave ramps onto `slave_offset + slave_scale · table(…)` within the limits.
    pub relative: bool,
}

impl CamSettings {
    /// Table `table`, no offset, scale 1.
    pub fn new(table: usize) -> Self {
        Self {
            table,
            master_offset: 0.0,
            slave_offset: 0.0,
            master_scale: 1.0,
            slave_scale: 1.0,
            relative: false,
        }
    }
}

impl Card {
    /// Load cam table `table` with `points` (master, slave; counts; the master strictly
    /// increasing), `cubic` (else linear), `periodic`. Sent five points a command; the card
    /// builds the table when the last arrives (`CamTable` if it refuses it: a count out of
    /// 2..=1024, cubic under 3, a master not strictly increasing; `NotFinite`). A table a slave
    /// follows cannot be reloaded (`CamTable`).
    pub fn load_cam_table(
        &self,
        table: usize,
        points: &[(f64, f64)],
        cubic: bool,
        periodic: bool,
    ) -> Result<()> {
        let axis = self.axis(0)?;
        let mut open = axis
            .op(Opcode::CamTable)
            .with_args(&[table as f64, points.len() as f64]);
        open.flags = if cubic { CAM_CUBIC } else { 0 } | if periodic { CAM_PERIODIC } else { 0 };
        self.execute(open, "load_cam_table", Target::Card)?;
        for (k, chunk) in points.chunks(CAM_DATA_MAX).enumerate() {
            let mut args = vec![table as f64, (k * CAM_DATA_MAX) as f64, chunk.len() as f64];
            for (m, s) in chunk {
                finite("cam master", *m)?;
                finite("cam slave", *s)?;
                args.extend([*m, *s]);
            }
            let cmd = axis.op(Opcode::CamData).with_args(&args);
            self.execute(cmd, "load_cam_table", Target::Card)?;
        }
        Ok(())
    }
}

impl Axis {
    fn cam_command(
        &self,
        master: Master,
        cam: &CamSettings,
        limits: &SyncLimits,
        flags: u32,
        what: &'static str,
    ) -> Result<Motion> {
        for (w, v) in [
            ("master offset", cam.master_offset),
            ("slave offset", cam.slave_offset),
            ("master scale", cam.master_scale),
            ("slave scale", cam.slave_scale),
        ] {
            finite(w, v)?;
        }
        crate::card::positive("velocity", limits.velocity)?;
        crate::card::positive("acceleration", limits.acceleration)?;
        crate::card::positive("jerk", limits.jerk)?;
        let (source, index) = master.source();
        let s = self.scale().abs();
        let mut cmd = self.op(Opcode::CamIn).with_args(&[
            index as f64,
            cam.table as f64,
            cam.master_offset,
            cam.slave_offset,
            cam.master_scale,
            cam.slave_scale,
            limits.velocity * s,
            limits.acceleration * s,
            limits.jerk * s,
        ]);
        cmd.flags = source.to_raw() | flags;
        let seq = self.run(cmd, what)?;
        Ok(Motion::new(self.card().clone(), self.index(), seq))
    }

    /// MC_CamIn (Aborting): this axis follows `master` through cam table `cam.table` (from
    /// where it stands with `cam.relative`), caught up within `limits`; [`Motion::wait_in_sync`] returns once it is on the cam. Refused:
    /// `CamTable` (not loaded), `SyncMaster`, `OutOfRange` (a scale of 0 or beyond 10^±9),
    /// `Infeasible`.
    pub fn cam_in(&self, master: Master, cam: &CamSettings, limits: &SyncLimits) -> Result<Motion> {
        let start = if cam.relative { CAM_RELATIVE } else { 0 };
        let m = self.cam_command(master, cam, limits, start, "cam_in")?;
        Ok(self.started(m.seq()))
    }

    /// MC_CamTableSelect + MC_CamIn at the end of the cycle: on an axis that cams, table
    /// `cam.table` (with `cam`'s scales; the offsets are those that continue the slave's
    /// position from the end of the cycle) takes over when the current cycle ends
    /// ([`Motion::wait_cam_switch`]). `InvalidState` if the axis does not cam.
    pub fn cam_switch(
        &self,
        master: Master,
        cam: &CamSettings,
        limits: &SyncLimits,
    ) -> Result<Motion> {
        self.cam_command(master, cam, limits, CAM_AT_CYCLE_END, "cam_switch")
    }

    /// MC_CamOut: as [`Axis::gear_out`], velocity mode at the slave's velocity.
    pub fn cam_out(&self) -> Result<Motion> {
        let seq = self.run(self.op(Opcode::CamOut), "cam_out")?;
        Ok(self.started(seq))
    }
}

impl Motion {
    /// Wait until the table switch of [`Axis::cam_switch`] took place; the slave's commanded
    /// position then (user units).
    pub fn wait_cam_switch(&self, timeout: Duration) -> Result<f64> {
        self.wait_outcome_of(timeout, |o| match o {
            Outcome::Sync(code, v) if SyncEvent::from_raw(code) == Some(SyncEvent::CamSwitch) => {
                Some(v)
            }
            _ => None,
        })
    }
}
