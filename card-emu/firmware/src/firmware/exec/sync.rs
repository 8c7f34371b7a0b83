//! Synchronised motion (layout 1.7): gearing and camming (`gear.rs`, `cam.rs`) and PT/PVT
//! streams (`pvt.rs`); gantries (layout 1.10, `gantry.rs`), whose commands name the gantry.
//! A gantry's slave refuses every other command of the family (`GantrySlave`).
//!
//! The cam tables are the card's, not an axis's: their commands name any axis and are not
//! checked against it. The others are an axis's: the axis one of the card's and not in an
//! enabled group, then the command's own checks (a malformed gear or stream command is refused
//! after those, as it always was).

use super::super::gantry::MAX_GANTRIES;
use super::super::gear::GearCommand;
use super::super::Firmware;
use firmware_proto::cmd::SyncCmd;
use firmware_proto::{AxisState, Command, Mem, NackCode, Opcode};

impl<M: Mem + Clone> Firmware<M> {
    /// A command of [`firmware_proto::cmd::Family::Sync`].
    pub(super) fn execute_sync(&mut self, c: &Command, op: Opcode) -> Result<f64, NackCode> {
        let decoded = SyncCmd::decode(op, c.flags, &c.args);
        // The cam tables are the card's: no axis is looked at.
        match (op, &decoded) {
            (_, Ok(SyncCmd::CamTable(t))) => return self.cam_table_open(t),
            (Opcode::CamTable, Err(e)) => return Err(e.nack),
            (_, Ok(SyncCmd::CamData(d))) => return self.cam_data(Ok(d)),
            (Opcode::CamData, Err(e)) => return self.cam_data(Err(*e)),
            _ => {}
        }
        // Layout 1.10: the gantry commands' target is the gantry.
        if matches!(
            op,
            Opcode::GantryForm | Opcode::GantryDissolve | Opcode::GantryHome
        ) {
            let g = c.axis as usize;
            if g >= MAX_GANTRIES {
                return Err(NackCode::GantryAxes);
            }
            return match decoded.map_err(|e| e.nack)? {
                SyncCmd::GantryForm(f) => self.gantry_form(g, &f),
                SyncCmd::GantryDissolve => self.gantry_dissolve(g),
                _ => self.gantry_home(g, c.seq),
            };
        }
        let ax = self.target_axis(c)?;
        if self.gantry_of_slave(ax).is_some() {
            return Err(NackCode::GantrySlave);
        }
        let pending = self.axes[ax].pending_motion();
        if self.grouped(ax) {
            return Err(NackCode::AxisGrouped);
        }
        let cmd = decoded.map_err(|e| e.nack)?;
        let (rate, n, seq) = (self.servo_rate_hz, self.num_axes, c.seq);
        // PT/PVT streams start from Standstill and abort nothing (the ack's value: the points
        // still free); gearing and camming take the axis over (Aborting).
        let ((changed, value), aborting) = match &cmd {
            SyncCmd::PvtBegin(b) => (self.pvt_begin(ax, b)?, false),
            SyncCmd::PvtPoints(p) => (self.pvt_points(ax, p)?, false),
            SyncCmd::PvtStart(s) => (self.pvt_start(seq, ax, s)?, false),
            // The ack's value: the coupling's offset (`Gear::offset`).
            SyncCmd::GearIn(g) => {
                let g = GearCommand::gear(g, None, ax, n, rate)?;
                let (outcome, over) = gear(self.execute_gear(seq, ax, g, false, false)?);
                let offset = self.gears[ax].offset().unwrap_or(0.0);
                ((outcome.0, offset), over)
            }
            SyncCmd::GearInPos(p) => {
                let at = Some((p.master_position, p.slave_position));
                let g = GearCommand::gear(&p.gear, at, ax, n, rate)?;
                let (outcome, over) = gear(self.execute_gear(seq, ax, g, false, false)?);
                let offset = self.gears[ax].offset().unwrap_or(0.0);
                ((outcome.0, offset), over)
            }
            SyncCmd::CamIn(ci) => {
                let g = GearCommand::cam(ci, ax, n, rate)?;
                gear(self.execute_gear(seq, ax, g, ci.at_cycle_end, ci.relative)?)
            }
            SyncCmd::GearOut | SyncCmd::CamOut => gear(self.execute_gear_out(seq, ax)?),
            // Served above.
            SyncCmd::CamTable(_)
            | SyncCmd::CamData(_)
            | SyncCmd::GantryForm(_)
            | SyncCmd::GantryDissolve
            | SyncCmd::GantryHome => return Err(NackCode::UnknownOpcode),
        };
        self.finish_axis_command(c, op, ax, pending, aborting, changed);
        Ok(value)
    }
}

/// A gear command's outcome (the old state, whether it took the axis over) as a stream's:
/// (old state, the ack's value 0), taking over.
fn gear((changed, takes_over): (Option<AxisState>, bool)) -> ((Option<AxisState>, f64), bool) {
    ((changed, 0.0), takes_over)
}
