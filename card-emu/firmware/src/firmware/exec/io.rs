//! The outputs (layout 1.6), position compare and touch probes (layout 1.7): the compare and
//! probe channels are the I/O unit's (`io.rs`); analog I/O and the PSO (layout 1.11) the analog
//! unit's (`analog.rs`); nothing moves.

use super::super::io::arm_axis;
use super::super::Firmware;
use firmware_proto::cmd::{Field, IoCmd, PsoOutput, SetOutputs};
use firmware_proto::{Command, Mem, NackCode, Opcode, COMPARE_CHANNELS, MAX_GROUPS};

impl<M: Mem + Clone> Firmware<M> {
    /// A command of [`firmware_proto::cmd::Family::Io`].
    pub(super) fn execute_io(&mut self, c: &Command, op: Opcode) -> Result<f64, NackCode> {
        // Layout 1.11: a PSO's group is checked before its arguments.
        if op == Opcode::Pso {
            let g = c.axis as usize;
            if g >= MAX_GROUPS || self.groups[g].config.is_none() {
                return Err(NackCode::PsoGroup);
            }
        }
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
            IoCmd::AnalogInput(a) => {
                self.analog.configure_input(&a, self.servo_rate_hz)?;
                Ok(0.0)
            }
            IoCmd::AnalogOutput(o) => self.analog.set_output(&o),
            IoCmd::Pso(p) => {
                if let PsoOutput::Pwm { output, .. } = p.output {
                    let pulsed = (0..COMPARE_CHANNELS)
                        .filter_map(|ch| self.io.compare(ch))
                        .fold(0, |m, k| m | k.output_mask());
                    if pulsed & (1 << output) != 0 {
                        return Err(NackCode::PsoConfig);
                    }
                }
                self.analog
                    .start_pso(c.axis as usize, p, self.servo_rate_hz)?;
                Ok(0.0)
            }
            IoCmd::PsoOff => {
                self.analog.stop_pso();
                Ok(0.0)
            }
            // Layout 1.12: no compare channel on the output the PSO's PWM holds (an output
            // that is not one is the I/O unit's to refuse).
            IoCmd::CompareArm(a)
                if self
                    .analog
                    .pwm()
                    .is_some_and(|(o, ..)| a.output == o as f64) =>
            {
                Err(NackCode::PsoOutput)
            }
            _ => {
                let (mem, n, rate) = (&self.mem, self.num_axes, self.servo_rate_hz);
                let axes = &self.axes;
                let modulo = |a: usize| axes.get(a).map_or(0.0, |x| x.modulo());
                self.io.command(mem, c.seq, c.axis, &cmd, n, rate, modulo)
            }
        }
    }

    /// `MC_OP_SET_OUTPUTS`: the outputs in `mask` become `value` (decoding checked both are
    /// output words).
    fn set_outputs(&mut self, o: SetOutputs) {
        self.outputs = (self.outputs & !o.mask) | (o.value & o.mask);
    }
}
