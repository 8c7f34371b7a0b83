//! Layout 1.14: a path whose axes live on several cards of one sync bus ([`CardSet::path`]).
//!
//! Each card's part is one of its groups; the path's dimensions are those groups' axes, in the
//! order the parts are given (up to 16). Every card gets every segment of every dimension,
//! plans the same speed profile from them (identical firmware, identical inputs on identical
//! ticks) and drives only its own group's axes: the motion of each axis is, to the last bit,
//! what one planner of all the dimensions would give it.
//!
//! Segments are staged on every card as they are pushed ([`SetPath::push`]: checked there,
//! refused on every card or none, since the cards check the same numbers) and go into the
//! cards' paths on [`SetPath::release`], which is timed to one tick on every card with
//! [`CardSet::sync`]: so every card holds the same segments on every tick, and the look-ahead,
//! which plans from what is queued, plans the same on all of them. The first release is the
//! synchronised start; releases while the path runs stream the rest ([`SetPath::run`] streams
//! a whole program, each segment published to every card ahead of their answers, and
//! releases it in batches of up to [`PATH_STAGE_LEN`]: a card stages at most that many, so a
//! path across cards runs at most [`PATH_STAGE_LEN`] segments per release's margin, see
//! [`CardSet::set_margin`]). A hold, resume,
//! pause or halt ([`SetPath::hold`], [`SetPath::halt`]) is timed the same way.
//!
//! Units: each dimension's targets in its axis's user units; feeds, tolerances and the halt's
//! ramp in the first dimension's. The numbers go to every card as the same counts.
//!
//! A fault on one card stops that card's axes; [`SetPath::wait`] then halts the others at once
//! and returns the fault (their axes can no longer keep to the path together).

use crate::card::finite;
use crate::cardset::CardSet;
use crate::error::{Error, Result, Target};
use crate::group::{arc_counts, ArcSpec, Group, Plane};
use crate::path::PathSettings;
use crate::segment::{Geometry, PathBuffer, Segment, Transition};
use firmware_proto::cmd::{
    ArcGeometry, GroupCmd, GroupOverride, PathArc, PathDwell, PathFlags, PathLine, PathMore,
    PathPause, PathRelease, StopRamp,
};
use firmware_proto::layout::{self, PATH_MAX_DIMS, PATH_STAGE_LEN};
use firmware_proto::{raw, Command, GroupDims, GroupState, NackCode, CMD_ARGS};
use std::collections::VecDeque;
use std::time::{Duration, Instant};

/// One card's part of a path across cards: a group of the set's card `card`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PathPart {
    /// The card, its index in the set.
    pub card: usize,
    /// Its group.
    pub group: usize,
}

/// Where a path across cards is ([`SetPath::progress`]): the same on every card, but for
/// the instant each is read at.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SetPathProgress {
    /// Segments staged on the host's side of the release (pushed, not released).
    pub staged: usize,
    /// Segments released and not finished, on the card that has the most.
    pub queued: usize,
    /// Segments finished, on the card that has the fewest.
    pub done: u32,
}

/// A path across the cards of a [`CardSet`] ([`CardSet::path`]). It holds its own handle of
/// the set's cards.
pub struct SetPath {
    set: CardSet,
    /// Per part: its group and the dimensions of its members, in member order.
    parts: Vec<(Group, Vec<usize>)>,
    /// Counts per user unit, per dimension.
    scales: Vec<f64>,
    /// Counts per user unit of feeds and tolerances (the first dimension's).
    path_scale: f64,
    /// Segments pushed and not released yet (the same number on every card).
    staged: usize,
    /// `path_done` of every part's group when the path began (it counts since enable).
    done0: Vec<u32>,
    /// Per part: the segments published to its card and not answered yet, oldest first:
    /// (the first entry's seq, entries). The same segments on every card.
    in_flight: Vec<VecDeque<(u32, u32)>>,
}

/// Segments in flight on a card at most while [`SetPath::run`] streams (a margin under the
/// command ring's 64 entries: a segment of more than 8 dimensions takes two).
const IN_FLIGHT: usize = 24;

impl std::fmt::Debug for SetPath {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SetPath")
            .field("dims", &self.scales.len())
            .field("parts", &self.parts.len())
            .field("staged", &self.staged)
            .finish()
    }
}

impl CardSet {
    /// A path across the cards of this set: its dimensions are the axes of `parts`' groups, in
    /// order (each group configured and enabled, at rest, its path idle), at most 16;
    /// `settings` gives every dimension's limits (in its axis's units) and the path's
    /// look-ahead and tangential limits (the first dimension's units), written to every card
    /// alike. Every card's group starts the path where the axes are now (each card is told
    /// where the others' are). `BadConfig` for a card or group named twice or not in the set.
    pub fn path(&self, parts: &[PathPart], settings: &PathSettings) -> Result<SetPath> {
        let mut groups: Vec<(Group, Vec<usize>)> = Vec::with_capacity(parts.len());
        // per dimension: (part, card axis)
        let mut owners = Vec::new();
        for (k, p) in parts.iter().enumerate() {
            let card = self.cards().get(p.card).ok_or_else(|| {
                Error::BadConfig(format!(
                    "card {} of a set of {}",
                    p.card,
                    self.cards().len()
                ))
            })?;
            if parts[..k].contains(p) {
                return Err(Error::BadConfig(format!(
                    "group {} of card {} is named twice",
                    p.group, p.card
                )));
            }
            let g = card.group(p.group)?;
            let (n, axes) = g.axes()?;
            let dims = (owners.len()..owners.len() + n).collect();
            owners.extend(axes[..n].iter().map(|&a| (k, a)));
            groups.push((g, dims));
        }
        let n = owners.len();
        if n == 0 || n > PATH_MAX_DIMS {
            return Err(Error::BadConfig(format!(
                "a path across cards has 1 to {PATH_MAX_DIMS} axes, not {n}"
            )));
        }
        settings.check_axes(n)?;
        let scales: Vec<f64> = owners
            .iter()
            .map(|&(k, a)| groups[k].0.card_pub().scale(a))
            .collect();
        let path_scale = scales[0].abs();
        // where every dimension starts: its axis's commanded position, in counts exactly
        let mut start = [0.0; PATH_MAX_DIMS];
        for (d, &(k, a)) in owners.iter().enumerate() {
            start[d] = groups[k].0.card_pub().read_axis_status(a)?.cmd_pos;
        }
        let mut path = settings.block(path_scale);
        let mut dims = GroupDims {
            ndims: n as u32,
            ..GroupDims::default()
        };
        for d in 0..n {
            [dims.vmax[d], dims.amax[d], dims.jmax[d]] = settings.axis_limits(d, scales[d])?;
            dims.start[d] = start[d];
        }
        let mut done0 = Vec::with_capacity(groups.len());
        for (g, own) in &groups {
            let mut d = dims;
            d.axis = [raw::MC_DIM_REMOTE; PATH_MAX_DIMS];
            for (m, &dim) in own.iter().enumerate() {
                d.axis[dim] = m as i32;
                // (the members' limits in group_path too: checked there, not used with
                // dimensions)
                path.vmax[m] = dims.vmax[dim];
                path.amax[m] = dims.amax[dim];
                path.jmax[m] = dims.jmax[dim];
            }
            let card = g.card_pub();
            let target = Target::Group(g.index());
            card.apply_block(
                layout::GROUP_PATH.at(g.index()),
                |b| *b = path,
                g.cmd(GroupCmd::ApplyPath),
                "path across cards",
                target,
            )?;
            card.apply_block(
                layout::GROUP_DIMS.at(g.index()),
                |b| *b = d,
                g.cmd(GroupCmd::ApplyDims),
                "path across cards",
                target,
            )?;
            done0.push(g.status()?.1.path_done);
        }
        Ok(SetPath {
            set: self.clone(),
            scales,
            path_scale,
            staged: 0,
            in_flight: vec![VecDeque::new(); groups.len()],
            parts: groups,
            done0,
        })
    }
}

impl SetPath {
    /// Dimensions of the path.
    pub fn dims(&self) -> usize {
        self.scales.len()
    }

    /// Stage `seg` on every card: a line (a target per dimension), an arc in a plane of two
    /// of the first 8 dimensions (its helix the other dimensions, in order) or a dwell; not
    /// `Aborting` (`Unsupported`). Published to every card at once, then their answers read:
    /// refused by the cards (they check alike: the same refusal from each, nothing staged on
    /// any), or `QueueFull` once [`PATH_STAGE_LEN`] are staged: [`SetPath::release`] first.
    pub fn push(&mut self, seg: &Segment) -> Result<()> {
        // (nothing is in flight between calls: `run` leaves every answer read)
        self.publish(seg)?;
        match self.answer_oldest() {
            Ok(None) => Ok(()),
            Err(e) => {
                // (a card that does not answer: the path cannot go on as one)
                self.abandon();
                Err(e)
            }
            Ok(Some((e, partly))) => {
                self.staged -= 1;
                if partly {
                    // (the cards check alike: a refusal on one where another accepted is a
                    // card that is not in the state the others are; what was staged must go)
                    self.abandon();
                }
                Err(e)
            }
        }
    }

    /// Release everything staged into every card's path on one tick (a margin ahead: the
    /// set's), once every card's path has room for it (the path runs meanwhile; `QueueFull`
    /// after 5 s of card time without room). The first release starts the path. The tick. A
    /// release refused (by a card whose group faulted, or a commit too late) halts the path on
    /// every card and drops what was staged.
    pub fn release(&mut self) -> Result<u64> {
        self.settle_segments()?;
        let k = self.staged;
        if k == 0 {
            return self.set.tick();
        }
        let patience = 5 * u64::from(self.set.cards()[0].info().servo_rate_hz);
        let t0 = self.set.tick()?;
        loop {
            let mut room = usize::MAX;
            for (g, _) in &self.parts {
                // (the segment events of a card not waited on would fill its event ring)
                g.card_pub().poll_events()?;
                let st = g.status()?.1;
                room = room.min(
                    (st.path_free as usize).min(firmware_proto::PATH_LEN - st.path_queued as usize),
                );
            }
            if room >= k {
                break;
            }
            if self.set.tick()?.saturating_sub(t0) > patience {
                return Err(Error::Refused {
                    command: "path release",
                    target: Target::Group(self.parts[0].0.index()),
                    code: NackCode::QueueFull,
                    reason: "the cards' paths had no room for the staged segments",
                });
            }
            self.set.cards()[0].wait_next_tick(Duration::from_secs(1))?;
        }
        let cmd = GroupCmd::PathRelease(PathRelease { count: k as f64 });
        let r = self.set.sync(|| {
            for (g, _) in &self.parts {
                g.run(g.cmd(cmd.clone()), "path release")?;
            }
            Ok(())
        });
        self.staged = 0;
        match r {
            Ok((tick, ())) => Ok(tick),
            Err(e) => {
                // A release refused on its tick by one card (its group faulted meanwhile) ran
                // on the others: halt them all (a release that ran nowhere leaves nothing to
                // halt but what is staged, which goes too).
                let _ = self.halt_now();
                Err(e)
            }
        }
    }

    /// Push and release a whole program: the segments streamed to every card (up to 24 in
    /// flight on each, their answers read as the ring needs room), released in batches as the
    /// staging fills, the last batch at the end. The tick of the first release (the start).
    /// A segment refused halts the path on every card and drops what was staged (the
    /// segments before it that were released have run or are halted: see
    /// [`SetPath::progress`]).
    pub fn run<'s>(&mut self, segments: impl IntoIterator<Item = &'s Segment>) -> Result<u64> {
        let mut start = None;
        for s in segments {
            if self.staged == PATH_STAGE_LEN {
                let t = self.release()?;
                start.get_or_insert(t);
            }
            if self.in_flight[0].len() >= IN_FLIGHT {
                self.settle_oldest()?;
            }
            if let Err(e) = self.publish(s) {
                self.abandon();
                return Err(e);
            }
        }
        let t = self.release()?;
        Ok(*start.get_or_insert(t))
    }

    /// Publish `seg`'s entries to every card without waiting for their answers (counted as
    /// staged). A ring without room: the oldest segment in flight is answered first.
    fn publish(&mut self, seg: &Segment) -> Result<()> {
        if self.staged >= PATH_STAGE_LEN {
            return Err(Error::Refused {
                command: "path across cards",
                target: Target::Group(self.parts[0].0.index()),
                code: NackCode::QueueFull,
                reason: "the staging holds 256 segments: release them first",
            });
        }
        let entries = self.entries(seg)?;
        for i in 0..self.parts.len() {
            let g = &self.parts[i].0;
            let mut cmds: Vec<Command> = entries.iter().map(|c| g.cmd(c.clone())).collect();
            let seq = loop {
                match self.parts[i].0.card_pub().inner().push_all(&mut cmds) {
                    Ok(seq) => break seq,
                    Err(Error::RingFull(_)) if !self.in_flight[i].is_empty() => {
                        self.settle_oldest()?
                    }
                    Err(e) => {
                        if i > 0 {
                            // published on some cards only: what was staged must go
                            self.abandon();
                        }
                        return Err(e);
                    }
                }
            };
            self.in_flight[i].push_back((seq, cmds.len() as u32));
        }
        self.staged += 1;
        Ok(())
    }

    /// Read every card's answers to the oldest segment in flight: `None` when every card
    /// accepted it, else the refusal and whether a card accepted it.
    fn answer_oldest(&mut self) -> Result<Option<(Error, bool)>> {
        let (mut refused, mut accepted) = (None, false);
        for i in 0..self.parts.len() {
            let Some((first, n)) = self.in_flight[i].pop_front() else {
                continue;
            };
            let g = &self.parts[i].0;
            let card = g.card_pub();
            let answer = card.wait_ack(first)?;
            for k in 1..n {
                // (the same outcome: taken off the answers so that none is left behind)
                let _ = card.wait_ack(first.wrapping_add(k))?;
            }
            match answer {
                Ok(()) => accepted = true,
                Err(code) => {
                    refused.get_or_insert(Error::Nack {
                        command: "path segment across cards",
                        target: Target::Group(g.index()),
                        code,
                        reason: crate::nack_reason(code),
                    });
                }
            }
        }
        Ok(refused.map(|e| (e, accepted)))
    }

    /// [`SetPath::answer_oldest`] where any refusal ends the stream: halted, staging dropped.
    fn settle_oldest(&mut self) -> Result<()> {
        match self.answer_oldest() {
            Ok(None) => Ok(()),
            Ok(Some((e, _))) | Err(e) => {
                self.abandon();
                Err(e)
            }
        }
    }

    /// Every segment in flight answered.
    fn settle_segments(&mut self) -> Result<()> {
        while !self.in_flight[0].is_empty() {
            self.settle_oldest()?;
        }
        Ok(())
    }

    /// The path can no longer run as one: every card halted now and what is staged dropped
    /// (the answers still owed are left unread).
    fn abandon(&mut self) {
        for q in &mut self.in_flight {
            q.clear();
        }
        self.staged = 0;
        let _ = self.halt_now();
    }

    /// How far the path has come.
    pub fn progress(&self) -> Result<SetPathProgress> {
        let mut queued = 0;
        let mut done = u32::MAX;
        for ((g, _), d0) in self.parts.iter().zip(&self.done0) {
            let st = g.status()?.1;
            queued = queued.max(st.path_queued as usize);
            done = done.min(st.path_done.wrapping_sub(*d0));
        }
        Ok(SetPathProgress {
            staged: self.staged,
            queued,
            done,
        })
    }

    /// Wait until every card's path has run everything released and its group is at rest in
    /// position (`Timeout` after `timeout`, card time on a stepped set). A group that faults
    /// or is stopped on one card: the others are halted at once and that is the error.
    pub fn wait(&self, timeout: Duration) -> Result<()> {
        let rate = f64::from(self.set.cards()[0].info().servo_rate_hz);
        let t0 = self.set.tick()?;
        let deadline = Instant::now() + timeout.max(Duration::from_secs(1)) * 4;
        loop {
            let mut all = true;
            for (g, _) in &self.parts {
                let (state, st) = g.status()?;
                match state {
                    GroupState::ErrorStop | GroupState::Disabled | GroupState::Stopping => {
                        let _ = self.halt_now();
                        return Err(Error::Refused {
                            command: "path across cards",
                            target: Target::Group(g.index()),
                            code: NackCode::InvalidState,
                            reason: "a card's group stopped or faulted: the others were halted",
                        });
                    }
                    GroupState::Standby => {}
                    _ => all = false,
                }
                all &= st.path_queued == 0 && st.path_staged == 0;
            }
            if all {
                return Ok(());
            }
            let waited = (self.set.tick()?.saturating_sub(t0)) as f64 / rate;
            if waited > timeout.as_secs_f64() || Instant::now() > deadline {
                return Err(Error::Timeout(timeout));
            }
            self.set.cards()[0].wait_next_tick(Duration::from_secs(1))?;
        }
    }

    /// Halt the path on every card on one tick, along its geometry within `deceleration` and
    /// `jerk` (the first dimension's units; each card stops within its limits too, the same
    /// on all). What is staged is dropped. The tick.
    pub fn halt(&mut self, deceleration: f64, jerk: f64) -> Result<u64> {
        let r = self.ramp(deceleration, jerk)?;
        let t = self.on_every_card(GroupCmd::Halt(r))?;
        self.staged = 0;
        Ok(t)
    }

    /// Hold the path on every card on one tick (feed override 0: it comes to rest along its
    /// geometry and stays in its motion); [`SetPath::set_override`] with a factor above 0
    /// resumes it on every card together.
    pub fn hold(&self) -> Result<u64> {
        self.set_override(0.0)
    }

    /// The feed override of every card's group, on one tick.
    pub fn set_override(&self, factor: f64) -> Result<u64> {
        finite("override", factor)?;
        let o = GroupOverride {
            feed: factor,
            rapid: factor,
        };
        self.on_every_card(GroupCmd::SetOverride(o))
    }

    /// Pause the path at the end of a segment on every card on one tick (`false`: go on).
    pub fn pause(&self, on: bool) -> Result<u64> {
        let p = PathPause {
            on: if on { 1.0 } else { 0.0 },
        };
        self.on_every_card(GroupCmd::PathPause(p))
    }

    fn on_every_card(&self, cmd: GroupCmd) -> Result<u64> {
        self.set
            .sync(|| {
                for (g, _) in &self.parts {
                    g.run(g.cmd(cmd.clone()), "path across cards")?;
                }
                Ok(())
            })
            .map(|(t, ())| t)
    }

    /// A halt sent to every card now, untimed (the path has already parted), as hard as the
    /// card takes: each path stops within its own limits.
    fn halt_now(&self) -> Result<()> {
        let rate = self.set.cards()[0].info().servo_rate_hz;
        let r = StopRamp {
            dmax: *firmware_proto::limit_range(2, rate).end(),
            jerk: *firmware_proto::limit_range(3, rate).end(),
        };
        let mut first = None;
        for (g, _) in &self.parts {
            let r = g.run(g.cmd(GroupCmd::Halt(r)), "halt");
            if let Err(e) = r {
                first.get_or_insert(e);
            }
        }
        first.map_or(Ok(()), Err)
    }

    fn ramp(&self, deceleration: f64, jerk: f64) -> Result<StopRamp> {
        crate::card::positive("deceleration", deceleration)?;
        crate::card::positive("jerk", jerk)?;
        Ok(StopRamp {
            dmax: deceleration * self.path_scale,
            jerk: jerk * self.path_scale,
        })
    }

    /// The command entries of `seg` (the same counts for every card): the segment's, then its
    /// `MC_OP_PATH_MORE` when it has more dimensions than its entry holds.
    fn entries(&self, seg: &Segment) -> Result<Vec<GroupCmd>> {
        let n = self.dims();
        let ps = self.path_scale;
        if let Geometry::Dwell { seconds } = seg.geometry {
            crate::card::positive("dwell", seconds)?;
            return Ok(vec![GroupCmd::PathDwell(PathDwell {
                id: seg.id as f64,
                seconds,
                last: seg.last,
            })]);
        }
        crate::card::positive("feed", seg.feed)?;
        let (tm, tol) = match seg.transition {
            Transition::None => (raw::MC_TM_NONE, 0.0),
            Transition::MaxDeviation(t) => (raw::MC_TM_MAX_DEVIATION, t),
            Transition::CornerDistance(t) => (raw::MC_TM_CORNER_DISTANCE, t),
            Transition::TimeShift(t) => (raw::MC_TM_TIME_SHIFT, t),
        };
        finite("tolerance", tol)?;
        let buffer = match seg.buffer {
            PathBuffer::Aborting => {
                return Err(Error::Unsupported(
                    "an Aborting segment on a path across cards (halt it, then push)".into(),
                ))
            }
            PathBuffer::Buffered => raw::MC_PATH_BUFFERED,
            PathBuffer::BlendingLow => raw::MC_PATH_BLEND_LOW,
            PathBuffer::BlendingPrevious => raw::MC_PATH_BLEND_PREVIOUS,
            PathBuffer::BlendingNext => raw::MC_PATH_BLEND_NEXT,
            PathBuffer::BlendingHigh => raw::MC_PATH_BLEND_HIGH,
        };
        let flags = PathFlags {
            relative: seg.relative,
            buffer: buffer as u8,
            transition: tm as u8,
            last: seg.last,
        };
        let (id, feed, tolerance) = (seg.id as f64, seg.feed * ps, tol * ps);
        let more = |rest: &[f64]| {
            let mut targets = [0.0; CMD_ARGS];
            targets[..rest.len()].copy_from_slice(rest);
            GroupCmd::PathMore(PathMore { targets })
        };
        let own = n.min(firmware_proto::MAX_AXES);
        match &seg.geometry {
            Geometry::Line { target } => {
                if target.len() != n {
                    return Err(Error::BadAxis {
                        axis: target.len(),
                        count: n,
                    });
                }
                let mut t = Vec::with_capacity(n);
                for (x, s) in target.iter().zip(&self.scales) {
                    finite("target", *x)?;
                    t.push(x * s);
                }
                let mut targets = [0.0; firmware_proto::MAX_AXES];
                targets[..own].copy_from_slice(&t[..own]);
                let mut v = vec![GroupCmd::PathLine(PathLine {
                    id,
                    feed,
                    tolerance,
                    targets,
                    flags,
                })];
                if n > own {
                    v.push(more(&t[own..]));
                }
                Ok(v)
            }
            Geometry::Arc { arc, plane, helix } => {
                let (arc, h) = self.arc(arc, *plane, helix)?;
                let mut v = vec![GroupCmd::PathArc(PathArc {
                    id,
                    feed,
                    tolerance,
                    arc,
                    flags,
                })];
                if n > own {
                    v.push(more(&h[own - 2..]));
                }
                Ok(v)
            }
            _ => Err(Error::Unsupported(
                "a path across cards takes lines, arcs and helices, and dwells".into(),
            )),
        }
    }

    /// An arc over the path's dimensions: its entry's geometry and all its helix targets
    /// (counts), as `Group::arc_geometry` makes a group's.
    fn arc(&self, arc: &ArcSpec, plane: Plane, helix: &[f64]) -> Result<(ArcGeometry, Vec<f64>)> {
        let n = self.dims();
        let (u, v) = plane.axes();
        if u >= n.min(firmware_proto::MAX_AXES) || v >= n.min(firmware_proto::MAX_AXES) {
            return Err(Error::BadAxis {
                axis: u.max(v),
                count: n.min(firmware_proto::MAX_AXES),
            });
        }
        let others: Vec<f64> = (0..n)
            .filter(|i| *i != u && *i != v)
            .map(|i| self.scales[i])
            .collect();
        let (mut g, h) = arc_counts(arc, plane, helix, (self.scales[u], self.scales[v]), &others)?;
        let own = n.min(firmware_proto::MAX_AXES) - 2;
        g.helix[..own].copy_from_slice(&h[..own]);
        Ok((g, h))
    }
}
