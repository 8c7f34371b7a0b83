//! The scope's commands (layout 1.8, `scope.rs`); nothing moves.

use super::super::{scope, Firmware};
use firmware_proto::cmd::ScopeCmd;
use firmware_proto::{layout, Command, Mem, NackCode, Opcode};

impl<M: Mem + Clone> Firmware<M> {
    /// A command of [`firmware_proto::cmd::Family::Scope`].
    pub(super) fn execute_scope(&mut self, c: &Command, op: Opcode) -> Result<(), NackCode> {
        let cmd = ScopeCmd::decode(op, c.flags, &c.args).map_err(|e| e.nack)?;
        let tick = self.tick;
        if cmd == ScopeCmd::Configure && !self.scope.is_some() {
            // Checked before the scope (and its history) is made: a refusal changes nothing.
            let block = layout::SCOPE_CONFIG.read(&self.mem);
            firmware_proto::check_config(&block, self.num_axes)?;
            self.scope.get_or_insert_with(scope::Scope::new);
        }
        let Some(sc) = self.scope.as_mut() else {
            return Err(NackCode::ScopeState);
        };
        match cmd {
            ScopeCmd::Configure => {
                let block = layout::SCOPE_CONFIG.read(&self.mem);
                sc.configure(&block, self.num_axes)?
            }
            ScopeCmd::Arm => sc.arm(c.seq, tick)?,
            ScopeCmd::Trigger => sc.force_trigger()?,
            ScopeCmd::Stop => sc.stop()?,
        }
        layout::SCOPE_STATUS.write(&self.mem, &sc.status());
        Ok(())
    }
}
