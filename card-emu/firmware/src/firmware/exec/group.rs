//! Axes groups: configuration, enable and disable, halt, stop and reset, the move queue
//! (lines, arcs, point-to-point, NURBS curves) and the continuous path (`group/`). The
//! command's target is the group.

use super::super::group::{GroupMove, SegmentCmd};
use super::super::{config, nack, Firmware};
use super::hard_stop_ramp;
use firmware_proto::cmd::GroupCmd;
use firmware_proto::{layout, Command, Mem, NackCode, Opcode, StopReason, MAX_GROUPS};

impl<M: Mem + Clone> Firmware<M> {
    /// A command of [`firmware_proto::cmd::Family::Group`].
    pub(super) fn execute_group(&mut self, c: &Command, op: Opcode) -> Result<(), NackCode> {
        let g = c.axis as usize;
        if g >= MAX_GROUPS {
            return Err(NackCode::BadGroup);
        }
        let cmd = match GroupCmd::decode(op, c.flags, &c.args) {
            Ok(cmd) => cmd,
            // The limits' first axis and count are checked after the group's state.
            Err(e) if op == Opcode::GroupPtpLimits => {
                return self.groups[g].stage_ptp_limits(Err(e.nack), self.ts())
            }
            Err(e) => return Err(e.nack),
        };
        let (tick, ts, seq) = (self.tick, self.ts(), c.seq);
        if let GroupCmd::Stop(r) | GroupCmd::Halt(r) = &cmd {
            nack::check_ranges(self.servo_rate_hz, &[(2, r.dmax), (3, r.jerk)])?;
        }
        let max_time = self.safety.config().max_stop_time();
        let hard = self.groups[g].config.map_or((f64::MAX, f64::MAX), |cfg| {
            hard_stop_ramp(&self.axes, &cfg.axes[..cfg.naxes])
        });
        // Layout 1.11: MC_GroupHome, and what ends a group homing (group_home.rs).
        let homing = self.groups[g].homing().is_some();
        match &cmd {
            GroupCmd::Home(h) => return self.group_home(g, seq, h),
            GroupCmd::Stop(r) | GroupCmd::Halt(r) if homing => {
                let stop = matches!(cmd, GroupCmd::Stop(_));
                if !stop && self.groups[g].state == firmware_proto::GroupState::Stopping {
                    return Err(NackCode::InvalidState);
                }
                self.group_home_halt(g, seq, stop, (r.dmax, r.jerk));
                return Ok(());
            }
            GroupCmd::Disable if homing => self.group_home_disable(g),
            _ => {}
        }
        // Layout 1.13: a normal-vector arc move's second entry, taken with it (mod.rs).
        let piece = match (&cmd, self.second) {
            (GroupCmd::MoveCircularNormal(_), Some(n)) => {
                match GroupCmd::decode(Opcode::GroupCircularPlane, n.flags, &n.args) {
                    Ok(GroupCmd::CircularPlane(p)) => Some(p),
                    Ok(_) => return Err(NackCode::ArcPiece),
                    Err(e) => return Err(e.nack),
                }
            }
            _ => None,
        };
        // Layout 1.14: a path segment's MC_OP_PATH_MORE, taken with it (group/wide.rs).
        let more = match (&cmd, self.second) {
            (GroupCmd::PathLine(_) | GroupCmd::PathArc(_), Some(n)) => {
                match GroupCmd::decode(Opcode::PathMore, n.flags, &n.args) {
                    Ok(GroupCmd::PathMore(m)) => Some(m),
                    Ok(_) => return Err(NackCode::PathMore),
                    Err(e) => return Err(e.nack),
                }
            }
            _ => None,
        };
        let group = &mut self.groups[g];
        let out = &mut self.outbox;
        match &cmd {
            GroupCmd::Home(_) => unreachable!("served above"),
            GroupCmd::Configure => {
                let block = layout::GROUP_CONFIG.at(g).read(&self.mem);
                let cfg = config::validate_group_config(&block, self.num_axes)?;
                let taken =
                    self.groups.iter().enumerate().any(|(i, o)| {
                        i != g && cfg.axes[..cfg.naxes].iter().any(|&a| o.contains(a))
                    });
                if taken {
                    return Err(NackCode::AxisInOtherGroup);
                }
                // Layout 1.10: a gantry's slave is driven by its master, never as a member.
                if cfg.axes[..cfg.naxes]
                    .iter()
                    .any(|&a| self.gantry_of_slave(a).is_some())
                {
                    return Err(NackCode::GantrySlave);
                }
                self.groups[g].configure(cfg)
            }
            GroupCmd::Enable => group.enable(&mut self.axes, tick, out),
            GroupCmd::Disable => {
                group.disable(&mut self.axes, &mut self.filters, tick, out);
                Ok(())
            }
            GroupCmd::Reset => group.reset(&mut self.axes, tick, out),
            GroupCmd::Stop(r) | GroupCmd::Halt(r) => {
                let stop = matches!(cmd, GroupCmd::Stop(_));
                group.start_stop(seq, stop, (r.dmax, r.jerk), hard, max_time, tick, out)?;
                // The members' motion ends by this halt or stop (their stop reason).
                let reason = if stop {
                    StopReason::Stop
                } else {
                    StopReason::Halt
                };
                for &a in group
                    .config
                    .as_ref()
                    .map_or(&[][..], |c| &c.axes[..c.naxes])
                {
                    self.axes[a].group_stopping(reason);
                }
                Ok(())
            }
            GroupCmd::StopRelease => group.release_stop(),
            GroupCmd::MoveLinear(m) => group.queue_move(seq, GroupMove::Linear(m), ts, tick, out),
            GroupCmd::MovePtp(m) => group.queue_move(seq, GroupMove::Ptp(m), ts, tick, out),
            GroupCmd::MoveCircular(m) => {
                group.queue_move(seq, GroupMove::Circular(m), ts, tick, out)
            }
            GroupCmd::NurbsBegin(b) => group.nurbs_begin(b, &self.axes, ts),
            GroupCmd::NurbsData(d) => group.nurbs_data(d),
            GroupCmd::NurbsEnd => group.nurbs_end(seq, &self.axes, ts, tick, out),
            GroupCmd::PtpLimits(l) => group.stage_ptp_limits(Ok(l), ts),
            GroupCmd::SetOverride(o) => group.set_override(o.feed, o.rapid, self.servo_rate_hz),
            GroupCmd::PathLine(s) => {
                group.path_segment(seq, &SegmentCmd::Line(*s), more.as_ref(), ts, tick, out)
            }
            GroupCmd::PathArc(s) => {
                group.path_segment(seq, &SegmentCmd::Arc(*s), more.as_ref(), ts, tick, out)
            }
            GroupCmd::PathDwell(s) => {
                group.path_segment(seq, &SegmentCmd::Dwell(*s), None, ts, tick, out)
            }
            GroupCmd::PathArcPlane(p) => group.set_arc_plane(p),
            GroupCmd::PathArcNormal(s) => group.path_arc_normal(seq, s, ts, tick, out),
            GroupCmd::MoveCircularNormal(m) => match &piece {
                Some(p) => group.queue_move(seq, GroupMove::CircularNormal(m, p), ts, tick, out),
                None => Err(NackCode::ArcPiece),
            },
            // (taken alone: the pair is served together)
            GroupCmd::CircularPlane(_) => Err(NackCode::ArcPiece),
            GroupCmd::PathOutput(o) => group.path_output(o, ts),
            GroupCmd::PathPause(p) => group.path_pause(p.on, ts, tick, out),
            GroupCmd::PathNurbs(p) => group.path_nurbs_begin(p, ts),
            GroupCmd::ApplyPath => {
                let block = layout::GROUP_PATH.at(g).read(&self.mem);
                group.apply_path(block, self.servo_rate_hz)
            }
            GroupCmd::ApplyDims => {
                let block = layout::GROUP_DIMS.at(g).read(&self.mem);
                group.apply_dims(&block, self.servo_rate_hz)
            }
            // (taken alone: a segment takes its own)
            GroupCmd::PathMore(_) => Err(NackCode::PathMore),
            GroupCmd::PathRelease(r) => group.path_release(r.count, ts, tick, out),
        }
    }
}
