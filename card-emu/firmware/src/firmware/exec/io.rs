//! The outputs (layout 1.6), position compare and touch probes (layout 1.7): the compare and
//! probe channels are the I/O unit's (`io.rs`); nothing moves.

use super::super::io::arm_axis;
use super::super::Firmware;
use firmware_proto::cmd::{Field, IoCmd, SetOutputs};
use firmware_proto::{Command, Mem, NackCode, Opcode};

impl<M: Mem + Clone> Firmware<M> {
    /// A command of [`firmware_proto::cmd::Family::Io`].
    pub(super) fn execute_io(&mut self, c: &Command, op: Opcode) -> Result<f64, NackCode> {
        let cmd = match IoCmd::decode(op, c.flags, &c.args) {
            Ok(cmd) => cmd,
            Err(e) => {
                // An arm's channel is checked before its axis, the rest of it after.
                if matches!(op, Opcode::CompareArm | Opcode::ProbeArm) && e.field != Field::Arg(0) {
                    arm_axis(c.axis, self.num_axes)?;
                }
                return Err(e.nack);
            }
        };
        match cmd {
            IoCmd::SetOutputs(o) => {
                self.set_outputs(o);
                Ok(0.0)
            }
            _ => {
                let (mem, n, rate) = (&self.mem, self.num_axes, self.servo_rate_hz);
                self.io.command(mem, c.seq, c.axis, &cmd, n, rate)
            }
        }
    }

    /// `MC_OP_SET_OUTPUTS`: the outputs in `mask` become `value` (decoding checked both are
    /// output words).
    fn set_outputs(&mut self, o: SetOutputs) {
        self.outputs = (self.outputs & !o.mask) | (o.value & o.mask);
    }
}
