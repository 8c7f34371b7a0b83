//! Group homing (layout 1.11, PLCopen Part 4 MC_GroupHome): the home order and what the group
//! keeps of a homing in progress. The firmware runs it (`firmware/group_home.rs`): it starts
//! each stage's axes on their own homing and watches them; the group only holds its state
//! (GroupHoming) and stays out of the way (`Group::guard` does nothing else while it runs).

use super::*;
use firmware_proto::cmd::GROUP_HOME_STAGES;

/// A checked home order: `n` stages, stage k's group axes in `masks[k]` (bit i: group axis i).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct HomeOrder {
    /// Stages (0: none).
    pub n: usize,
    /// Each stage's group axes.
    pub masks: [u8; GROUP_HOME_STAGES],
}

impl HomeOrder {
    /// The order's stages.
    pub fn stages(&self) -> &[u8] {
        &self.masks[..self.n]
    }

    /// Check an order of `stages` stages (as sent) with `masks` for a group of `naxes` axes, in
    /// the card's order: the count (a whole number 0..=GROUP_HOME_STAGES, else `BadConfig`),
    /// then stage by stage its mask (a whole number 0..=255 naming only the group's axes, else
    /// `HomeAxis`; not 0, else `HomeStage`) and no axis of an earlier stage (`HomeTwice`). An
    /// order of 0 stages is valid here (none).
    pub fn check(stages: f64, masks: &[f64], naxes: usize) -> Result<HomeOrder, NackCode> {
        if !stages.is_finite() || masks.iter().take(GROUP_HOME_STAGES).any(|m| !m.is_finite()) {
            return Err(NackCode::NotFinite);
        }
        let n = whole(stages)
            .filter(|&n| n <= GROUP_HOME_STAGES)
            .ok_or(NackCode::BadConfig)?;
        let mut order = HomeOrder {
            n,
            ..HomeOrder::default()
        };
        let group_bits = if naxes >= 8 {
            0xFF
        } else {
            (1u32 << naxes) - 1
        };
        let mut seen = 0u32;
        for k in 0..n {
            let m = masks
                .get(k)
                .copied()
                .and_then(whole)
                .filter(|&m| m <= 0xFF)
                .ok_or(NackCode::HomeAxis)? as u32;
            if m & !group_bits != 0 {
                return Err(NackCode::HomeAxis);
            }
            if m == 0 {
                return Err(NackCode::HomeStage);
            }
            if m & seen != 0 {
                return Err(NackCode::HomeTwice);
            }
            seen |= m;
            order.masks[k] = m as u8;
        }
        Ok(order)
    }
}

/// A group homing in progress (`MC_OP_GROUP_HOME`, command `seq`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GroupHoming {
    /// The command.
    pub seq: u32,
    /// The order.
    pub order: HomeOrder,
    /// The stage running.
    pub stage: usize,
    /// The group axes of the running stage homed so far.
    pub done: u8,
    /// It failed (or was halted): the event's (code, value); the group waits for its members to
    /// come to rest before it ends.
    pub failed: Option<(i32, f64)>,
    /// A group halt (false) or stop (true) ended it.
    pub by_stop: Option<bool>,
}

impl Group {
    /// The homing in progress, if any.
    pub fn homing(&self) -> Option<&GroupHoming> {
        self.home.as_ref()
    }

    /// MC_GroupHome accepted: GroupStandby → GroupHoming.
    pub(crate) fn begin_homing(&mut self, h: GroupHoming, tick: u64, out: &mut Outbox) {
        self.home = Some(h);
        self.final_seq = None;
        self.set_state(GroupState::Homing, tick, out);
    }

    /// A group stop during homing: GroupStopping at once (the members halt on their own).
    pub(crate) fn homing_stopping(&mut self, tick: u64, out: &mut Outbox) {
        self.set_state(GroupState::Stopping, tick, out);
    }

    /// The homing ended with the members at rest: the group's positions are where they stand
    /// now; GroupStandby, or GroupStopping held (as after MC_GroupStop) when a stop ended it.
    pub(crate) fn end_homing(
        &mut self,
        axes: &[Axis; MAX_AXES],
        held: bool,
        tick: u64,
        out: &mut Outbox,
    ) {
        self.home = None;
        if let Some(cfg) = self.config {
            self.sync_positions(axes, &cfg);
        }
        if self.state == GroupState::ErrorStop || self.state == GroupState::Disabled {
            return;
        }
        if held {
            self.stop = Some(StopKind::Stop);
            self.set_state(GroupState::Stopping, tick, out);
        } else {
            self.stop = None;
            self.set_state(GroupState::Standby, tick, out);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check(n: f64, m: &[f64], naxes: usize) -> Result<Vec<u8>, NackCode> {
        HomeOrder::check(n, m, naxes).map(|o| o.stages().to_vec())
    }

    /// Each refusal of an order has its own code, in the card's order; a good order is kept as
    /// sent.
    #[test]
    fn an_order_is_checked_stage_by_stage() {
        assert_eq!(check(2.0, &[4.0, 3.0], 3), Ok(vec![4, 3]));
        assert_eq!(check(0.0, &[], 3), Ok(vec![]));
        assert_eq!(check(9.0, &[1.0; 9], 8), Err(NackCode::BadConfig));
        assert_eq!(check(1.5, &[1.0, 2.0], 3), Err(NackCode::BadConfig));
        assert_eq!(check(1.0, &[8.0], 3), Err(NackCode::HomeAxis));
        assert_eq!(check(1.0, &[256.0], 8), Err(NackCode::HomeAxis));
        assert_eq!(check(1.0, &[0.5], 3), Err(NackCode::HomeAxis));
        assert_eq!(check(2.0, &[1.0, 0.0], 3), Err(NackCode::HomeStage));
        assert_eq!(check(2.0, &[3.0, 2.0], 3), Err(NackCode::HomeTwice));
        assert_eq!(check(1.0, &[f64::NAN], 3), Err(NackCode::NotFinite));
        assert_eq!(check(1.0, &[255.0], 8), Ok(vec![255]));
        // the first fault in stage order wins
        assert_eq!(check(3.0, &[1.0, 1.0, 0.0], 3), Err(NackCode::HomeTwice));
    }
}
