//! Camming (layout 1.7): PLCopen MC_CamTableSelect, MC_CamIn, MC_CamOut, run by the card.
//!
//! A cam table is up to 1024 points (master, slave) in **encoder counts**, loaded into the
//! card's RAM with commands ([`Card::load_cam_table`]), interpolated linearly or by a cubic
//! spline (velocity and acceleration continuous), periodic or not (a periodic table repeats
//! every span of the master, the slave rising by its last minus first point per cycle).
//! [`Axis::cam_in`] couples a slave to a [`Master`] through a table:
//! `slave = slave_offset + slave_scale · table((master − master_offset) / master_scale)`,
//! caught up within [`SyncLimits`] as gearing does;
//! [`Axis::cam_switch`] takes another table at the end of the current cycle, the slave's position
//! continuous; [`Axis::cam_out`] leaves it in velocity mode. `card_firmware::motion::cam` and the
//! register map's header (`MC_OP_CAM_TABLE`) have the rules.

use crate::card::{finite, Axis, Card, Motion, Outcome};
use crate::error::{Result, Target};
use crate::sync::{Master, SyncLimits};
use firmware_proto::cmd::{self, SyncCmd};
use firmware_proto::{SyncEvent, CAM_DATA_MAX};
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
        // A table or a count the card does not take is its to refuse (`CamTable`).
        let table = table.min(u8::MAX as usize) as u8;
        let open = cmd::CamTable {
            table,
            points: points.len().min(u16::MAX as usize) as u16,
            cubic,
            periodic,
        };
        self.execute(
            axis.cmd(SyncCmd::CamTable(open)),
            "load_cam_table",
            Target::Card,
        )?;
        for (k, chunk) in points.chunks(CAM_DATA_MAX).enumerate() {
            for (m, s) in chunk {
                finite("cam master", *m)?;
                finite("cam slave", *s)?;
            }
            let data = cmd::CamData {
                table,
                // The card took the table: at most MC_CAM_MAX_POINTS points.
                first: (k * CAM_DATA_MAX) as u16,
                points: chunk.iter().copied().collect(),
            };
            self.execute(
                axis.cmd(SyncCmd::CamData(data)),
                "load_cam_table",
                Target::Card,
            )?;
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
        (at_cycle_end, relative): (bool, bool),
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
        let cam_in = cmd::CamIn {
            // A master the card does not have is its to refuse (`SyncMaster`).
            master: cmd::Master {
                source,
                index: index.min(u8::MAX as usize) as u8,
            },
            table: cam.table as f64,
            master_offset: cam.master_offset,
            slave_offset: cam.slave_offset,
            master_scale: cam.master_scale,
            slave_scale: cam.slave_scale,
            limits: limits.counts(s),
            at_cycle_end,
            relative,
        };
        let seq = self.run(self.cmd(SyncCmd::CamIn(cam_in)), what)?;
        Ok(Motion::new(self.card().clone(), self.index(), seq))
    }

    /// MC_CamIn (Aborting): this axis follows `master` through cam table `cam.table` (from
    /// where it stands with `cam.relative`), caught up within `limits`; [`Motion::wait_in_sync`] returns once it is on the cam. Refused:
    /// `CamTable` (not loaded), `SyncMaster`, `OutOfRange` (a scale of 0 or beyond 10^±9),
    /// `Infeasible`.
    pub fn cam_in(&self, master: Master, cam: &CamSettings, limits: &SyncLimits) -> Result<Motion> {
        let m = self.cam_command(master, cam, limits, (false, cam.relative), "cam_in")?;
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
        self.cam_command(master, cam, limits, (true, false), "cam_switch")
    }

    /// MC_CamOut: as [`Axis::gear_out`], velocity mode at the slave's velocity.
    pub fn cam_out(&self) -> Result<Motion> {
        let seq = self.run(self.cmd(SyncCmd::CamOut), "cam_out")?;
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
