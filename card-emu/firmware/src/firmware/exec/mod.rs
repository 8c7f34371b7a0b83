//! The command manager's `execute`: one command, decoded once into its typed arguments
//! (`firmware_proto::cmd`) and handed to its family's handler, a file each:
//!
//! - `axis.rs`: single-axis motion (MC_Power, the moves, velocity mode and jog, the override,
//!   MC_Halt, MC_Stop, MC_Reset, MC_Home, MC_SetPosition);
//! - `group.rs`: axes groups, their move queue, NURBS curves and the continuous path;
//! - `sync.rs`: gearing, camming and PT/PVT streams;
//! - `io.rs`: the outputs, position compare and touch probes;
//! - `card.rs`: configuration, sessions and safety (the applies, the read-back, the scale,
//!   attach and detach, the e-stop and the safety reset);
//! - `scope.rs`: the scope.
//!
//! Every command first meets the opcode check and the session gate (`safety.rs`); each
//! handler then checks its target (axis or group), the values and the card's state in the
//! order the card always has, so each fault keeps its nack (`firmware_proto::cmd` says what
//! decoding refuses and what it leaves to the card).

mod axis;
mod card;
mod group;
mod io;
mod scope;
mod sync;

use super::axis::Axis;
use super::{safety, state_event, Firmware};
use firmware_proto::cmd::{family, Family};
use firmware_proto::{AxisState, Command, Event, EventKind, Mem, NackCode, Opcode};

impl<M: Mem + Clone> Firmware<M> {
    /// Execute one command: the value of its ack, or its nack.
    pub(crate) fn execute(&mut self, c: &Command) -> Result<f64, NackCode> {
        let op = Opcode::from_raw(c.opcode).ok_or(NackCode::UnknownOpcode)?;
        // [safety] the session gate: with nobody in command, only what stops, reads, observes
        // or stages data (safety.rs)
        if !self.safety.in_command() && !safety::allowed_without_session(op) {
            return Err(NackCode::NoSession);
        }
        match family(op) {
            Family::Io => self.execute_io(c, op),
            Family::Group => self.execute_group(c, op).map(|()| 0.0),
            Family::Scope => self.execute_scope(c, op).map(|()| 0.0),
            Family::Axis => self.execute_axis(c, op),
            Family::Sync => self.execute_sync(c, op),
            Family::Card => self.execute_card(c, op),
        }
    }

    /// The axis a command names, if it is one of the card's.
    fn target_axis(&self, c: &Command) -> Result<usize, NackCode> {
        let ax = c.axis as usize;
        if ax >= self.num_axes {
            return Err(NackCode::BadAxis);
        }
        Ok(ax)
    }

    /// Is axis `ax` a member of an enabled group (single-axis motion is refused)?
    fn grouped(&self, ax: usize) -> bool {
        self.groups.iter().any(|g| g.owns_enabled(ax))
    }

    /// The end of a command accepted on axis `ax` (command `c`, opcode `op`): the axis
    /// records it; if it took the axis over (PLCopen Aborting) the motion still waiting for
    /// its done (`pending`, but this command) and every buffered move are aborted; and a state
    /// change it made (from `changed`) is posted.
    fn finish_axis_command(
        &mut self,
        c: &Command,
        op: Opcode,
        ax: usize,
        pending: Option<u32>,
        aborting: bool,
        changed: Option<AxisState>,
    ) {
        let tick = self.tick;
        let axis = &mut self.axes[ax];
        axis.accepted(c.seq);
        if aborting {
            // The motion still waiting for its done, and every buffered move, end here.
            let dropped = axis.drain_queue();
            // (the pending motion tested on its own, not filtered out of a chain: valgrind
            // saw the optimised chain branch on the payload of a `None`)
            let first = match pending {
                Some(s) if s != c.seq => Some(s),
                _ => None,
            };
            for seq in first.into_iter().chain(dropped) {
                self.outbox.push(Event {
                    seq,
                    kind: EventKind::MotionAborted as u16,
                    axis: c.axis,
                    code: op as i32,
                    tick,
                    value: 0.0,
                });
            }
        }
        if let Some(old) = changed {
            self.outbox
                .push(state_event(c.axis, old, self.axes[ax].state, tick));
        }
    }
}

/// The hardest stop ramp every member of a group allows along its path: the smallest of their
/// stop decelerations and jerks (an axis's share of the path's acceleration is at most the
/// path's own).
pub(super) fn hard_stop_ramp(axes: &[Axis], members: &[usize]) -> (f64, f64) {
    members
        .iter()
        .filter_map(|&a| axes.get(a))
        .fold((f64::MAX, f64::MAX), |(d, j), ax| {
            let c = &ax.safety.config;
            (d.min(c.stop_decel), j.min(c.stop_jerk))
        })
}
