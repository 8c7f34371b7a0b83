//! Axes groups: coordinated linear, circular and helical moves, synchronised point-to-point
//! moves, and the per-axis acc/dec filters.

use crate::card::{finite, lock, positive, Axis, Card};
use crate::error::{Error, Result, Target};
use firmware_proto::cmd::{
    ArcFlags, ArcGeometry, CardCmd, CircularMove, CircularNormalMove, CircularPlane, Cmd,
    FeedLimits, GroupCmd, GroupHome, GroupOverride, LinearMove, MoveOpts, PathArcPlane, PtpLimits,
    PtpMove, StopRamp, GROUP_HOME_STAGES,
};
use firmware_proto::layout;
use firmware_proto::seqlock;
use firmware_proto::{raw, Command, GroupState, GroupStatus, MAX_AXES, MAX_GROUPS};
use std::time::Duration;

pub use card_firmware::host::FilterKind;

/// Where the tangential acceleration comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AccDec {
    /// An S-curve of the feed along the path (before interpolation).
    Pre,
    /// Constant feed along the path, each axis's acc/dec filter after interpolation (Kim, Shin).
    Post,
    /// Both: the S-curve, then the filters.
    Both,
}

/// Which arc interpolator the group uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Interpolator {
    /// Points exactly on the circle at each tick's arc length.
    Exact,
    /// Kim's reference-word interpolator (eq 15–23): constant angle steps; needs [`AccDec::Post`].
    ReferenceWord,
}

/// A group's configuration.
#[derive(Debug, Clone, PartialEq)]
pub struct GroupSettings {
    /// Card axes of the group's X, Y, Z, … axes (1 to 8).
    pub axes: Vec<usize>,
    /// Acc/dec mode.
    pub accdec: AccDec,
    /// Arc interpolator.
    pub interpolator: Interpolator,
    /// Geometry tolerance (centre equidistance, radius vs chord), in the first axis's units.
    pub tolerance: f64,
    /// Layout 1.11: the group's home order, stages of group axis indices (0: the group's X),
    /// `[[2], [0, 1]]`: Z first, then X and Y together; what [`Group::home`] with an empty
    /// order runs (the configuration file's `home_order`). Empty: none configured.
    pub home_order: Vec<Vec<usize>>,
}

impl GroupSettings {
    /// A group of `axes`, S-curve feed, exact arcs, tolerance 2 counts (in user units of the
    /// first axis: set it after [`Axis::set_scale`]).
    pub fn new(axes: &[usize]) -> Self {
        Self {
            axes: axes.to_vec(),
            accdec: AccDec::Pre,
            interpolator: Interpolator::Exact,
            tolerance: 2.0,
            home_order: Vec::new(),
        }
    }
}

/// Feed type: selects each axis's acc/dec filter (Shin Table 1).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum FeedType {
    /// Rapid traverse (G00).
    Rapid,
    /// Cutting feed (G01/G02/G03).
    #[default]
    Cutting,
    /// Jog.
    Jog,
}

/// Limits of the tangential feed (user units of the group's first axis).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathLimits {
    /// Feed (path velocity).
    pub velocity: f64,
    /// Tangential acceleration (pre-interpolation S-curve).
    pub acceleration: f64,
    /// Tangential deceleration.
    pub deceleration: f64,
    /// Tangential jerk.
    pub jerk: f64,
}

impl PathLimits {
    /// Feed `v`, acceleration and deceleration `a`, jerk `j`.
    pub fn new(v: f64, a: f64, j: f64) -> Self {
        Self {
            velocity: v,
            acceleration: a,
            deceleration: a,
            jerk: j,
        }
    }
}

/// How a move is queued.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct MoveOptions {
    /// Targets relative to where the previous move ends.
    pub relative: bool,
    /// Queue behind the moves already queued (PLCopen Buffered); else the group must be at rest.
    pub buffered: bool,
    /// Feed type.
    pub feed_type: FeedType,
}

impl MoveOptions {
    /// Buffered behind the queued moves.
    pub fn buffered() -> Self {
        Self {
            buffered: true,
            ..Self::default()
        }
    }
}

/// The plane of an arc, in group axes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Plane {
    /// Group axes 0 and 1.
    #[default]
    XY,
    /// Group axes 1 and 2.
    YZ,
    /// Group axes 2 and 0.
    ZX,
    /// Any two group axes (u, v), counter-clockwise from u towards v (layout 1.10): a
    /// rotary table's plane, a second XY pair. Two different axes.
    Axes(usize, usize),
}

impl Plane {
    /// The plane's group axes (u, v).
    pub fn axes(self) -> (usize, usize) {
        match self {
            Plane::XY => (0, 1),
            Plane::YZ => (1, 2),
            Plane::ZX => (2, 0),
            Plane::Axes(u, v) => (u, v),
        }
    }
}

/// An arc, in the coordinates of its plane (`end`, `centre`, `via`: plane coordinates of the
/// end point, the centre and a point on the arc; `ccw`: counter-clockwise, else clockwise).
#[derive(Debug, Clone, Copy, PartialEq)]
#[allow(missing_docs)]
pub enum ArcSpec {
    /// By centre; `ccw` else clockwise. `end == start` is a full circle.
    Centre {
        end: [f64; 2],
        centre: [f64; 2],
        ccw: bool,
    },
    /// By radius; a negative radius takes the arc longer than half a turn.
    Radius {
        end: [f64; 2],
        radius: f64,
        ccw: bool,
    },
    /// Through a point on the arc (three-point circle); the direction follows the points.
    Border { end: [f64; 2], via: [f64; 2] },
}

/// Layout 1.13: an arc in the plane of three group axes given by a normal vector, for the
/// move queue ([`Group::move_circular_normal`]); the same geometry as a path's
/// [`Geometry::ArcNormal`](crate::Geometry::ArcNormal): counter-clockwise about `normal` (the
/// right-hand rule; reversed, the arc runs the other way) in the plane through the start,
/// around `centre`, to `end` (an end at the start: a full turn), then `turns` more full turns.
/// `centre` and `end` are on the three axes, in order, in their user units (the three need one
/// scale). The card refuses a centre off the plane or an end off the circle by more than the
/// group's tolerance, and an end off the plane unless `rise` (then its offset along the
/// normal is a helix's rise, spread over the whole length).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NormalArc {
    /// The plane's group axes a, b, c.
    pub axes: [usize; 3],
    /// The normal on them (any length but 0).
    pub normal: [f64; 3],
    /// The centre on a, b, c.
    pub centre: [f64; 3],
    /// The end on a, b, c.
    pub end: [f64; 3],
    /// The end may lie off the plane along the normal (a helix along it).
    pub rise: bool,
    /// Full turns added to the arc.
    pub turns: u32,
}

impl NormalArc {
    /// The arc in the plane of `axes` with `normal` around `centre` to `end` (no rise, no turn
    /// added).
    pub fn new(axes: [usize; 3], normal: [f64; 3], centre: [f64; 3], end: [f64; 3]) -> Self {
        Self {
            axes,
            normal,
            centre,
            end,
            rise: false,
            turns: 0,
        }
    }
}

/// An axes group on a card.
#[derive(Clone)]
pub struct Group {
    card: Card,
    index: usize,
}

/// Layout 1.11: a group homing in progress ([`Group::home`]).
#[derive(Clone)]
pub struct GroupHoming {
    card: Card,
    group: usize,
    seq: u32,
}

impl GroupHoming {
    /// The command's seq (the members' own motion events carry it too).
    pub fn seq(&self) -> u32 {
        self.seq
    }

    /// Wait until every member is homed and the group stands by: the stages run. A member
    /// that fails (or a halt, stop, disable or safety stop) is
    /// [`Error::GroupHomingFailed`], naming the axis and its homing error, once the group is
    /// at rest.
    pub fn wait(&self, timeout: Duration) -> Result<usize> {
        self.card.wait_group_homed(self.group, self.seq, timeout)
    }
}

/// A group move in progress.
#[derive(Clone)]
pub struct GroupMotion {
    card: Card,
    group: usize,
    seq: u32,
}

impl std::fmt::Debug for GroupMotion {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("GroupMotion")
            .field("group", &self.group)
            .field("seq", &self.seq)
            .finish()
    }
}

impl GroupMotion {
    /// The seq of the command.
    pub fn seq(&self) -> u32 {
        self.seq
    }

    /// Wait for the move's motion done: the last move of a queue is done when the group is at
    /// rest and in position; an earlier one when the next move takes over.
    pub fn wait(&self, timeout: Duration) -> Result<()> {
        self.card
            .wait_outcome(Target::Group(self.group), self.seq, timeout)
            .map(|_| ())
    }
}

impl Card {
    /// An axes group handle (`0..MAX_GROUPS`).
    pub fn group(&self, index: usize) -> Result<Group> {
        if index >= MAX_GROUPS {
            return Err(Error::BadGroup {
                group: index,
                count: MAX_GROUPS,
            });
        }
        Ok(Group {
            card: self.clone(),
            index,
        })
    }
}

impl Group {
    /// Group number.
    pub fn index(&self) -> usize {
        self.index
    }

    /// The entry of a command to this group.
    pub(crate) fn cmd(&self, c: impl Into<Cmd>) -> Command {
        c.into().command(self.index as u16)
    }

    pub(crate) fn run(&self, cmd: Command, what: &'static str) -> Result<u32> {
        self.card.execute_seq(cmd, what, Target::Group(self.index))
    }

    /// The group's axes as the card accepted them: remembered from [`Group::configure`], or,
    /// for a group configured by an earlier host, read back from the configuration block once
    /// the card shows the group enabled.
    pub(crate) fn axes(&self) -> Result<(usize, [usize; MAX_AXES])> {
        if let Some(c) = lock(&self.card.inner().group_axes)[self.index] {
            return Ok(c);
        }
        let not_configured = || Error::Refused {
            command: "group move",
            target: Target::Group(self.index),
            code: firmware_proto::NackCode::GroupDisabled,
            reason: "the group is not configured",
        };
        if self.status()?.0 == GroupState::Disabled {
            return Err(not_configured());
        }
        let block = layout::GROUP_CONFIG.at(self.index).read(self.card.window());
        let n = block.naxes as usize;
        if n == 0 || n > MAX_AXES {
            return Err(not_configured());
        }
        let mut axes = [0usize; MAX_AXES];
        for (d, b) in axes.iter_mut().zip(block.axes) {
            *d = b as usize;
        }
        Ok((n, axes))
    }

    pub(crate) fn axes_pub(&self) -> Result<(usize, [usize; MAX_AXES])> {
        self.axes()
    }

    pub(crate) fn path_scale_pub(&self) -> Result<f64> {
        self.path_scale()
    }

    pub(crate) fn card_pub(&self) -> &Card {
        &self.card
    }

    pub(crate) fn opts_pub(opts: &MoveOptions) -> MoveOpts {
        Self::opts(opts)
    }

    pub(crate) fn motion_pub(&self, seq: u32) -> GroupMotion {
        self.motion(seq)
    }

    /// A home order's stages as the card's masks (bit i: group axis i), or what the host can
    /// refuse before the card sees it: `BadConfig` (more than [`GROUP_HOME_STAGES`] stages),
    /// `HomeAxis` (an index beyond 7), `HomeTwice` (an index twice in a stage). The card checks
    /// the rest (an index the group does not have, an axis in two stages, an empty stage).
    fn home_masks(&self, order: &[&[usize]], command: &'static str) -> Result<Vec<u8>> {
        let refuse = |code: firmware_proto::NackCode, reason: &'static str| Error::Refused {
            command,
            target: Target::Group(self.index),
            code,
            reason,
        };
        if order.len() > GROUP_HOME_STAGES {
            return Err(refuse(
                firmware_proto::NackCode::BadConfig,
                "a home order has at most 8 stages",
            ));
        }
        let mut masks = Vec::with_capacity(order.len());
        for stage in order {
            let mut m = 0u8;
            for &i in *stage {
                if i >= MAX_AXES {
                    return Err(refuse(
                        firmware_proto::NackCode::HomeAxis,
                        "a home order names group axes 0 to 7 (the group's X, Y, Z, ...), not card axes beyond them",
                    ));
                }
                if m >> i & 1 == 1 {
                    return Err(refuse(
                        firmware_proto::NackCode::HomeTwice,
                        "a home order names an axis twice in one stage",
                    ));
                }
                m |= 1 << i;
            }
            masks.push(m);
        }
        Ok(masks)
    }

    /// Write the configuration and have the card check and apply it (group disabled). A bad
    /// home order is refused as [`Group::home`] refuses one (`HomeAxis`, `HomeTwice`,
    /// `HomeStage`, `BadConfig` for more than [`GROUP_HOME_STAGES`] stages), the card's
    /// configuration unchanged.
    pub fn configure(&self, s: &GroupSettings) -> Result<()> {
        let n = s.axes.len();
        if n == 0 || n > MAX_AXES {
            return Err(Error::BadAxis {
                axis: n,
                count: MAX_AXES,
            });
        }
        finite("tolerance", s.tolerance)?;
        let order: Vec<&[usize]> = s.home_order.iter().map(Vec::as_slice).collect();
        let masks = self.home_masks(&order, "group configure")?;
        let count = self.card.info().axes;
        let mut bytes = [0u8; 8];
        for (b, &a) in bytes.iter_mut().zip(&s.axes) {
            if a >= count {
                return Err(Error::BadAxis { axis: a, count });
            }
            *b = a as u8;
        }
        let mut block = raw::mc_group_config {
            naxes: n as u32,
            axes: bytes,
            accdec: match s.accdec {
                AccDec::Pre => raw::MC_ACCDEC_PRE,
                AccDec::Post => raw::MC_ACCDEC_POST,
                AccDec::Both => raw::MC_ACCDEC_PRE | raw::MC_ACCDEC_POST,
            },
            interpolator: if s.interpolator == Interpolator::ReferenceWord {
                raw::MC_INTERP_REFERENCE_WORD
            } else {
                raw::MC_INTERP_EXACT
            },
            tolerance: s.tolerance * self.card.scale(s.axes[0]).abs(),
            home_stages: masks.len() as u32,
            ..Default::default()
        };
        block.home_order[..masks.len()].copy_from_slice(&masks);
        let guard = self.card.config_lock();
        self.card
            .write_block(layout::GROUP_CONFIG.at(self.index), &block);
        self.run(self.cmd(GroupCmd::Configure), "group configure")?;
        drop(guard);
        let mut axes = [0usize; MAX_AXES];
        axes[..n].copy_from_slice(&s.axes);
        lock(&self.card.inner().group_axes)[self.index] = Some((n, axes));
        Ok(())
    }

    /// The group's configuration as the card holds it (layout 1.8: read back; `None`: not
    /// configured), the tolerance in the first axis's user units.
    pub fn settings(&self) -> Result<Option<GroupSettings>> {
        let g = self.index;
        let b = self.card.read_block(
            layout::GROUP_CONFIG.at(g),
            firmware_proto::ConfigKind::Group,
            g,
        )?;
        let n = b.naxes as usize;
        if n == 0 || n > MAX_AXES {
            return Ok(None);
        }
        let axes: Vec<usize> = b.axes[..n].iter().map(|&a| a as usize).collect();
        let pre = b.accdec & raw::MC_ACCDEC_PRE != 0;
        let post = b.accdec & raw::MC_ACCDEC_POST != 0;
        Ok(Some(GroupSettings {
            accdec: match (pre, post) {
                (true, true) => AccDec::Both,
                (false, true) => AccDec::Post,
                _ => AccDec::Pre,
            },
            interpolator: if b.interpolator == raw::MC_INTERP_REFERENCE_WORD {
                Interpolator::ReferenceWord
            } else {
                Interpolator::Exact
            },
            tolerance: b.tolerance / self.card.scale(axes[0]).abs(),
            home_order: b.home_order[..(b.home_stages as usize).min(GROUP_HOME_STAGES)]
                .iter()
                .map(|&m| (0..MAX_AXES).filter(|&i| m >> i & 1 == 1).collect())
                .collect(),
            axes,
        }))
    }

    /// MC_GroupEnable: every axis must be enabled and at rest.
    pub fn enable(&self) -> Result<()> {
        self.run(self.cmd(GroupCmd::Enable), "group enable")
            .map(|_| ())
    }

    /// MC_GroupDisable: aborts queued moves, leaves the axes enabled where they are.
    pub fn disable(&self) -> Result<()> {
        self.run(self.cmd(GroupCmd::Disable), "group disable")
            .map(|_| ())
    }

    /// Layout 1.11: MC_GroupHome. The group homes its axes in `order`: stages of group axis
    /// indices (0: the group's X, its first axis; not card axes), each stage's axes together,
    /// each with its own homing ([`crate::Axis::configure_homing`]; the home point reads the axis's home
    /// offset), a stage once the one before it is homed and at rest. A member that is a
    /// gantry's master homes its gantry (squaring it). An empty `order` homes in the group's
    /// configured order ([`GroupSettings::home_order`], the configuration file's `home_order`). `[[2], [0, 1]]`: Z first,
    /// then X and Y together. The group is in [`GroupState::Homing`] until it ends, then
    /// Standby. From Standby with every member at rest; refused: `GroupDisabled`,
    /// `InvalidState` (not at rest), `AxisBusy`, `HomeAxis` (an index the group does not have),
    /// `HomeTwice` (an axis twice), `HomeStage` (an empty stage; or an empty order and none
    /// configured), `BadConfig` (more than [`GROUP_HOME_STAGES`] stages), and each axis's
    /// homing refusals (`HomingMethod`, `OutOfRange`, `BadConfig`), `GantryState`.
    pub fn home(&self, order: &[&[usize]]) -> Result<GroupHoming> {
        let masks = self.home_masks(order, "group home")?;
        let cmd = self.cmd(GroupCmd::Home(GroupHome::from_masks(&masks)));
        let seq = self.run(cmd, "group home")?;
        Ok(GroupHoming {
            card: self.card.clone(),
            group: self.index,
            seq,
        })
    }

    /// MC_GroupReset: GroupErrorStop → GroupStandby.
    pub fn reset(&self) -> Result<()> {
        self.run(self.cmd(GroupCmd::Reset), "group reset")
            .map(|_| ())
    }

    fn stopping(
        &self,
        stop: bool,
        deceleration: f64,
        jerk: f64,
        what: &'static str,
    ) -> Result<GroupMotion> {
        positive("deceleration", deceleration)?;
        positive("jerk", jerk)?;
        let s = self.path_scale()?;
        let ramp = StopRamp {
            dmax: deceleration * s,
            jerk: jerk * s,
        };
        let c = if stop {
            GroupCmd::Stop(ramp)
        } else {
            GroupCmd::Halt(ramp)
        };
        let seq = self.run(self.cmd(c), what)?;
        Ok(self.motion(seq))
    }

    /// MC_GroupHalt: decelerate along the path, then GroupStandby. Queued moves are aborted.
    pub fn halt(&self, deceleration: f64, jerk: f64) -> Result<GroupMotion> {
        self.stopping(false, deceleration, jerk, "group halt")
    }

    /// MC_GroupStop: decelerate along the path and stay in GroupStopping until released.
    pub fn stop(&self, deceleration: f64, jerk: f64) -> Result<GroupMotion> {
        self.stopping(true, deceleration, jerk, "group stop")
    }

    /// MC_SetOverride of the group: `feed` scales the path speed of lines and arcs, `rapid`
    /// that of point-to-point moves; each 0.0 to 2.0 (0 % to 200 %), else `OverrideRange`. The
    /// active move's S-curve is replanned along the path from its current speed within the
    /// path limits (the geometry unchanged); 0 holds the group on its path, a factor above 0
    /// resumes. A constant feed (post-interpolation acc/dec only) is scaled, and the filters
    /// smooth the change; reference-word arcs and NURBS curves keep their programmed feed.
    pub fn set_override(&self, feed: f64, rapid: f64) -> Result<()> {
        finite("feed override", feed)?;
        finite("rapid override", rapid)?;
        self.run(
            self.cmd(GroupCmd::SetOverride(GroupOverride { feed, rapid })),
            "group override",
        )
        .map(|_| ())
    }

    /// Leave GroupStopping.
    pub fn release_stop(&self) -> Result<()> {
        self.run(self.cmd(GroupCmd::StopRelease), "group stop release")
            .map(|_| ())
    }

    pub(crate) fn motion(&self, seq: u32) -> GroupMotion {
        lock(&self.card.inner().last_group_motion)[self.index] = Some(seq);
        self.motion_untracked(seq)
    }

    /// A handle on command `seq` that [`Group::wait_done`] does not wait for.
    pub(crate) fn motion_untracked(&self, seq: u32) -> GroupMotion {
        GroupMotion {
            card: self.card.clone(),
            group: self.index,
            seq,
        }
    }

    /// Counts per user unit for path quantities: the first group axis's scale.
    pub(crate) fn path_scale(&self) -> Result<f64> {
        let (_, axes) = self.axes()?;
        Ok(self.card.scale(axes[0]).abs())
    }

    fn path_limits(&self, lim: &PathLimits) -> Result<FeedLimits> {
        let named = [
            ("feed", lim.velocity),
            ("acceleration", lim.acceleration),
            ("deceleration", lim.deceleration),
            ("jerk", lim.jerk),
        ];
        let s = self.path_scale()?;
        let mut out = [0.0; 4];
        for (o, (what, v)) in out.iter_mut().zip(named) {
            positive(what, v)?;
            *o = v * s;
        }
        Ok(FeedLimits::from_array(out))
    }

    /// The options of a move as the command carries them.
    fn opts(opts: &MoveOptions) -> MoveOpts {
        let feed = match opts.feed_type {
            FeedType::Rapid => raw::MC_FEED_RAPID,
            FeedType::Cutting => raw::MC_FEED_CUTTING,
            FeedType::Jog => raw::MC_FEED_JOG,
        };
        MoveOpts {
            relative: opts.relative,
            buffered: opts.buffered,
            feed_type: feed as u8,
        }
    }

    /// One target per group axis, in counts, as a move carries them (the rest 0).
    pub(crate) fn target_array(&self, target: &[f64]) -> Result<[f64; MAX_AXES]> {
        let t = self.targets(target)?;
        let mut out = [0.0; MAX_AXES];
        out[..t.len()].copy_from_slice(&t);
        Ok(out)
    }

    pub(crate) fn targets(&self, target: &[f64]) -> Result<Vec<f64>> {
        let (n, axes) = self.axes()?;
        if target.len() != n {
            return Err(Error::BadAxis {
                axis: target.len(),
                count: n,
            });
        }
        target
            .iter()
            .zip(&axes[..n])
            .map(|(t, a)| {
                finite("target", *t)?;
                Ok(t * self.card.scale(*a))
            })
            .collect()
    }

    /// A line (`ptp`: synchronised point-to-point) to `target`.
    fn line(
        &self,
        ptp: bool,
        target: &[f64],
        lim: &PathLimits,
        opts: &MoveOptions,
        what: &'static str,
    ) -> Result<GroupMotion> {
        let line = LinearMove {
            limits: self.path_limits(lim)?,
            targets: self.target_array(target)?,
            opts: Self::opts(opts),
        };
        let c = if ptp {
            GroupCmd::MovePtp(PtpMove {
                line,
                axis_limits: false,
            })
        } else {
            GroupCmd::MoveLinear(line)
        };
        let seq = self.run(self.cmd(c), what)?;
        Ok(self.motion(seq))
    }

    /// MC_MoveLinearAbsolute / Relative: a straight line to `target` (one value per group
    /// axis) at the feed of `lim`.
    pub fn move_linear(
        &self,
        target: &[f64],
        lim: &PathLimits,
        opts: MoveOptions,
    ) -> Result<GroupMotion> {
        self.line(false, target, lim, &opts, "move linear")
    }

    /// A point-to-point move's options: the cutting feed type becomes rapid (G00).
    fn ptp_options(opts: MoveOptions) -> MoveOptions {
        MoveOptions {
            feed_type: if opts.feed_type == FeedType::Cutting {
                FeedType::Rapid
            } else {
                opts.feed_type
            },
            ..opts
        }
    }

    /// Synchronised point-to-point (Kim eq 10–14): every axis starts and ends together, each
    /// within `lim` (in the first axis's units, like a path): the axis with the longest
    /// distance moves at `lim` and the others scale. The cutting feed type becomes rapid.
    /// [`move_ptp_axes`](Self::move_ptp_axes) gives each axis its own limits.
    pub fn move_ptp(
        &self,
        target: &[f64],
        lim: &PathLimits,
        opts: MoveOptions,
    ) -> Result<GroupMotion> {
        let opts = Self::ptp_options(opts);
        self.line(true, target, lim, &opts, "move ptp")
    }

    /// Synchronised point-to-point with each axis's own limits (Kim eq 10–14): `limits[i]`
    /// bounds group axis `i` (velocity, acceleration, deceleration and jerk in that axis's
    /// user units). The axis that needs the most time within its limits sets the time (when
    /// one axis is the tightest in every limit, the move takes exactly its own time), the
    /// others scale, every axis within its own limits, and all start and end on the same
    /// tick. The limits reach the card staged in `MC_OP_GROUP_PTP_LIMITS` entries.
    pub fn move_ptp_axes(
        &self,
        target: &[f64],
        limits: &[PathLimits],
        opts: MoveOptions,
    ) -> Result<GroupMotion> {
        let (n, axes) = self.axes()?;
        if limits.len() != n {
            return Err(Error::BadAxis {
                axis: limits.len(),
                count: n,
            });
        }
        let targets = self.target_array(target)?;
        let mut per = Vec::with_capacity(n);
        let mut widest = [0.0f64; 4];
        for (l, &a) in limits.iter().zip(&axes[..n]) {
            let s = self.card.scale(a).abs();
            let named = [
                ("velocity", l.velocity),
                ("acceleration", l.acceleration),
                ("deceleration", l.deceleration),
                ("jerk", l.jerk),
            ];
            let mut counts = [0.0; 4];
            for ((c, w), (what, v)) in counts.iter_mut().zip(widest.iter_mut()).zip(named) {
                positive(what, v)?;
                *c = v * s;
                *w = w.max(*c);
            }
            per.push(counts);
        }
        for (k, chunk) in per.chunks(firmware_proto::PTP_LIMITS_MAX).enumerate() {
            let staged = PtpLimits {
                first: (k * firmware_proto::PTP_LIMITS_MAX) as u32,
                // At most PTP_LIMITS_MAX (the chunk).
                limits: chunk.iter().map(|l| FeedLimits::from_array(*l)).collect(),
            };
            self.run(self.cmd(GroupCmd::PtpLimits(staged)), "ptp axis limits")?;
        }
        // The command's limits apply to every axis too (the smaller wins): the widest of the
        // axes' own leaves each axis at its own.
        let ptp = PtpMove {
            line: LinearMove {
                limits: FeedLimits::from_array(widest),
                targets,
                opts: Self::opts(&Self::ptp_options(opts)),
            },
            axis_limits: true,
        };
        let seq = self.run(self.cmd(GroupCmd::MovePtp(ptp)), "move ptp")?;
        Ok(self.motion(seq))
    }

    /// MC_MoveCircular: an arc in `plane`; `helix` holds the targets of the group's other axes
    /// (in group order), which move linearly with the arc (a helix). Empty for a plain arc.
    pub fn move_circular(
        &self,
        arc: &ArcSpec,
        plane: Plane,
        helix: &[f64],
        lim: &PathLimits,
        opts: MoveOptions,
    ) -> Result<GroupMotion> {
        let m = CircularMove {
            arc: self.arc_geometry(arc, plane, helix)?,
            limits: self.path_limits(lim)?,
            opts: Self::opts(&opts),
        };
        let seq = self.run(self.cmd(GroupCmd::MoveCircular(m)), "move circular")?;
        Ok(self.motion(seq))
    }

    /// Layout 1.13: MC_MoveCircular in a plane given by a normal vector (see [`NormalArc`]):
    /// a rest-to-rest S-curve along the arc within `lim` (the limits along the path, as
    /// [`move_circular`](Self::move_circular)'s); `helix` holds the targets of the group's
    /// other axes (in group order), which move linearly with the arc, or is empty (they stay).
    /// With `opts.relative` the centre, the end and the targets are from the end of what is
    /// queued. The move takes two command entries, sent together; it cannot be timed.
    pub fn move_circular_normal(
        &self,
        arc: &NormalArc,
        helix: &[f64],
        lim: &PathLimits,
        opts: MoveOptions,
    ) -> Result<GroupMotion> {
        let layout = self.card.info().layout;
        if layout.1 < 13 {
            return Err(Error::Unsupported(format!(
                "moves in a plane given by a normal vector need layout 1.13 (the card has 1.{})",
                layout.1
            )));
        }
        let (s3, others) = self.arc_normal_scales(&arc.axes)?;
        for x in arc
            .normal
            .iter()
            .chain(&arc.centre)
            .chain(&arc.end)
            .chain(helix)
        {
            finite("arc coordinate", *x)?;
        }
        if !helix.is_empty() && helix.len() != others.len() {
            return Err(Error::BadAxis {
                axis: helix.len(),
                count: others.len(),
            });
        }
        let mut h = [0.0; MAX_AXES - 3];
        for ((d, x), s) in h.iter_mut().zip(helix).zip(&others) {
            *d = x * s;
        }
        let m = CircularNormalMove {
            limits: self.path_limits(lim)?,
            centre: arc.centre.map(|x| x * s3),
            end: arc.end.map(|x| x * s3),
            turns: f64::from(arc.turns),
            rise: arc.rise,
            helix_relative: helix.is_empty(),
            opts: Self::opts(&opts),
        };
        let plane = CircularPlane {
            plane: PathArcPlane {
                axes: arc.axes.map(|a| a as f64),
                normal: arc.normal,
            },
            helix: h,
        };
        let mut cmds = [
            self.cmd(GroupCmd::MoveCircularNormal(m)),
            self.cmd(GroupCmd::CircularPlane(plane)),
        ];
        let seq = self.card.execute_together(
            &mut cmds,
            "move circular normal",
            Target::Group(self.index),
        )?;
        Ok(self.motion(seq))
    }

    /// An arc in counts (end, aux, the other axes' targets) with its flags (mode, direction,
    /// plane, helix relative), as MC_OP_GROUP_MOVE_CIRCULAR and MC_OP_PATH_ARC take it.
    pub(crate) fn arc_geometry(
        &self,
        arc: &ArcSpec,
        plane: Plane,
        helix: &[f64],
    ) -> Result<ArcGeometry> {
        let (n, axes) = self.axes()?;
        let (u, v) = plane.axes();
        if let Plane::Axes(..) = plane {
            // (one axis twice is the card's to refuse: MC_NACK_PLANE_AXES, ErrorKind::PlaneAxes)
            for a in [u, v] {
                if a >= n {
                    return Err(Error::BadAxis { axis: a, count: n });
                }
            }
            let layout = self.card.info().layout;
            if layout.1 < 10 {
                return Err(Error::Unsupported(format!(
                    "arcs in the plane of group axes {u}, {v} need layout 1.10 (the card has \
                     1.{})",
                    layout.1
                )));
            }
        }
        let su = self.card.scale(axes[u.min(n.saturating_sub(1))]);
        let sv = self.card.scale(axes[v.min(n.saturating_sub(1))]);
        let others: Vec<usize> = (0..n).filter(|i| *i != u && *i != v).collect();
        let scales: Vec<f64> = others.iter().map(|&i| self.card.scale(axes[i])).collect();
        let (g, h) = arc_counts(arc, plane, helix, (su, sv), &scales)?;
        let mut first = [0.0; MAX_AXES - 2];
        first[..h.len()].copy_from_slice(&h);
        Ok(ArcGeometry { helix: first, ..g })
    }

    /// Wait for the last move queued through this library on this group. `NoMotion` when none
    /// was queued since the card was opened (nothing to wait for).
    pub fn wait_done(&self, timeout: Duration) -> Result<()> {
        let seq = lock(&self.card.inner().last_group_motion)[self.index]
            .ok_or(Error::NoMotion(Target::Group(self.index)))?;
        self.card
            .wait_outcome(Target::Group(self.index), seq, timeout)
            .map(|_| ())
    }

    /// A consistent snapshot of the group's status (path quantities in counts).
    pub fn status(&self) -> Result<(GroupState, GroupStatus)> {
        let st = self
            .card
            .read_snapshot(&format!("group {}", self.index), |w| {
                seqlock::read_group_status(w, self.index)
            })?;
        let state = st.state().ok_or_else(|| {
            Error::Protocol(format!(
                "group {} reports unknown state {}",
                self.index, st.state
            ))
        })?;
        Ok((state, st))
    }
}

/// An axis's acc/dec filters: kind and time constant (s) per feed type.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FilterSettings {
    /// Rapid traverse.
    pub rapid: (FilterKind, f64),
    /// Cutting feed.
    pub cutting: (FilterKind, f64),
    /// Jog.
    pub jog: (FilterKind, f64),
}

impl FilterSettings {
    /// Shin Table 1 for the x and y axes: rapid bell 35 ms, cutting linear 30 ms, jog
    /// exponential 50 ms (the card's default).
    pub fn shin_table1() -> Self {
        Self::from_preset(card_firmware::host::FilterPreset::shin_table1())
    }

    /// Shin Table 1 for the z axis: rapid bell 85 ms, cutting linear 30 ms, jog exponential 40 ms.
    pub fn shin_table1_z() -> Self {
        Self::from_preset(card_firmware::host::FilterPreset::shin_table1_z())
    }

    /// One filter for every feed type.
    pub fn all(kind: FilterKind, tau: f64) -> Self {
        Self {
            rapid: (kind, tau),
            cutting: (kind, tau),
            jog: (kind, tau),
        }
    }

    fn from_preset(p: card_firmware::host::FilterPreset) -> Self {
        Self {
            rapid: (p.rapid.kind, p.rapid.time_constant_s),
            cutting: (p.cutting.kind, p.cutting.time_constant_s),
            jog: (p.jog.kind, p.jog.time_constant_s),
        }
    }
}

impl Axis {
    /// The axis's acc/dec filters as the card holds them (layout 1.8: read back).
    pub fn filter_settings(&self) -> Result<FilterSettings> {
        let a = self.index();
        let b = self.card().read_block(
            layout::AXIS_FILTER.at(a),
            firmware_proto::ConfigKind::AxisFilter,
            a,
        )?;
        let f = card_firmware::host::decode_axis_filter(&b)
            .map_err(|_| Error::Protocol(format!("axis {a}: the card holds an unknown filter")))?;
        Ok(FilterSettings {
            rapid: (f.kind[0], f.tau[0]),
            cutting: (f.kind[1], f.tau[1]),
            jog: (f.kind[2], f.tau[2]),
        })
    }

    /// Set the axis's post-interpolation acc/dec filters (applied when it holds no distance).
    pub fn set_filters(&self, f: &FilterSettings) -> Result<()> {
        let a = self.index();
        let mut block = raw::mc_axis_filter::default();
        for (i, (kind, tau)) in [f.rapid, f.cutting, f.jog].into_iter().enumerate() {
            finite("filter time constant", tau)?;
            block.kind[i] = card_firmware::host::FilterConfig::kind_to_raw(kind);
            block.tau[i] = tau;
        }
        let _guard = self.card().config_lock();
        self.card().write_block(layout::AXIS_FILTER.at(a), &block);
        self.card()
            .execute_seq(
                CardCmd::ApplyAxisFilter.command(a as u16),
                "set filters",
                Target::Axis(a),
            )
            .map(|_| ())
    }
}

/// An arc in counts, as MC_OP_GROUP_MOVE_CIRCULAR and MC_OP_PATH_ARC take it: its end, aux
/// point and flags (mode, direction, plane, helix relative) with the plane's axes at scales
/// `(su, sv)`, and the other axes' targets (a helix) at `others`' scales, in order, all of
/// them (the entry's `helix` is left 0: the caller places them).
pub(crate) fn arc_counts(
    arc: &ArcSpec,
    plane: Plane,
    helix: &[f64],
    (su, sv): (f64, f64),
    others: &[f64],
) -> Result<(ArcGeometry, Vec<f64>)> {
    let (mode, end, aux, ccw) = match *arc {
        ArcSpec::Centre { end, centre, ccw } => (
            raw::MC_CIRC_BY_CENTRE,
            end,
            [centre[0] * su, centre[1] * sv],
            ccw,
        ),
        ArcSpec::Radius { end, radius, ccw } => {
            (raw::MC_CIRC_BY_RADIUS, end, [radius * su.abs(), 0.0], ccw)
        }
        ArcSpec::Border { end, via } => (
            raw::MC_CIRC_BY_BORDER,
            end,
            [via[0] * su, via[1] * sv],
            false,
        ),
    };
    for x in end.iter().chain(aux.iter()).chain(helix) {
        finite("arc coordinate", *x)?;
    }
    // No helical targets: the other axes stay where they are (distance 0).
    if !helix.is_empty() && helix.len() != others.len() {
        return Err(Error::BadAxis {
            axis: helix.len(),
            count: others.len(),
        });
    }
    let mut h = vec![0.0; others.len()];
    for ((d, x), s) in h.iter_mut().zip(helix).zip(others) {
        *d = x * s;
    }
    let (plane_bits, plane_axes) = match plane {
        Plane::XY => (raw::MC_PLANE_XY, (0, 0)),
        Plane::YZ => (raw::MC_PLANE_YZ, (0, 0)),
        Plane::ZX => (raw::MC_PLANE_ZX, (0, 0)),
        Plane::Axes(u, v) => (raw::MC_PLANE_AXES, (u as u8, v as u8)),
    };
    let g = ArcGeometry {
        end: [end[0] * su, end[1] * sv],
        aux,
        helix: [0.0; MAX_AXES - 2],
        flags: ArcFlags {
            mode: mode as u8,
            plane: plane_bits as u8,
            axes: plane_axes,
            ccw,
            helix_relative: helix.is_empty(),
        },
    };
    Ok((g, h))
}
