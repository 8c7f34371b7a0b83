//! Axes groups, their moves and filters, PD+ and NURBS.

use crate::codes::{
    MC_ARC_BY_BORDER, MC_ARC_BY_CENTRE, MC_ARC_BY_RADIUS, MC_ARC_PLANE_AXES, MC_ARC_PLANE_XY,
    MC_ARC_PLANE_YZ, MC_ARC_PLANE_ZX, MC_FILTER_KIND_BELL, MC_FILTER_KIND_EXPONENTIAL,
    MC_FILTER_KIND_LINEAR, MC_FILTER_KIND_NONE, MC_GROUP_ACCDEC_POST, MC_GROUP_ACCDEC_PRE,
    MC_GROUP_INTERP_EXACT, MC_GROUP_INTERP_REFERENCE_WORD, MC_GROUP_MAX_AXES,
};
use crate::result::{unknown, Failure};
use motioncard_sdk::ErrorKind;
use motioncard_sdk::{
    AccDec, ArcSpec, FeedType, FilterKind, FilterSettings, GroupSettings, GroupState, GroupStatus,
    Interpolator, MoveOptions, NormalArc, NurbsFeed, PathLimits, Plane,
};

/// Most axes in a group, as a length.
const MAX_AXES: usize = MC_GROUP_MAX_AXES as usize;

/// Acc/dec mode (`mc_group_settings.accdec`), besides `MC_GROUP_ACCDEC_PRE` and
/// `MC_GROUP_ACCDEC_POST`: both, the S-curve, then the filters.
pub const MC_GROUP_ACCDEC_BOTH: u32 = MC_GROUP_ACCDEC_PRE | MC_GROUP_ACCDEC_POST;

/// Feed type (`mc_move_options.feed_type`), which selects each axis's acc/dec filter: cutting
/// feed (G01/G02/G03). 0, so a zeroed `mc_move_options` is the default.
pub const MC_FEED_TYPE_CUTTING: u32 = 0;
/// Rapid traverse (G00).
pub const MC_FEED_TYPE_RAPID: u32 = 1;
/// Jog.
pub const MC_FEED_TYPE_JOG: u32 = 2;

/// A group's configuration (`mc_group_configure`). Start from `mc_group_settings_new`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[allow(non_camel_case_types)]
pub struct mc_group_settings {
    /// Card axes of the group's X, Y, Z, … axes; the first `naxes` are used.
    pub axes: [u32; 8],
    /// Axes in the group, 1..8.
    pub naxes: u32,
    /// `MC_GROUP_ACCDEC_` value.
    pub accdec: u32,
    /// `MC_GROUP_INTERP_` value.
    pub interpolator: u32,
    /// Geometry tolerance (centre equidistance, radius against chord), in user units of the
    /// group's first axis.
    pub tolerance: f64,
    /// Layout 1.11: stages in the group's home order (0: none configured), 0..8; what
    /// `mc_group_home` with no stages runs.
    pub home_stages: u32,
    /// Stage k's group axes (the first `home_stages` are used), a mask: bit i is group axis i
    /// (0: the group's X). `{1 << 2, 1 << 0 | 1 << 1}`: Z first, then X and Y together.
    pub home_order: [u32; 8],
}

impl mc_group_settings {
    pub(crate) fn to_sdk(self) -> Result<GroupSettings, Failure> {
        let n = self.naxes as usize;
        if n == 0 || n > MAX_AXES {
            return Err(Failure::new(
                ErrorKind::BadAxis.code(),
                format!("naxes = {n}: a group has 1 to {MAX_AXES} axes"),
            ));
        }
        let axes: Vec<usize> = self.axes[..n].iter().map(|&a| a as usize).collect();
        let accdec = match self.accdec {
            MC_GROUP_ACCDEC_PRE => AccDec::Pre,
            MC_GROUP_ACCDEC_POST => AccDec::Post,
            MC_GROUP_ACCDEC_BOTH => AccDec::Both,
            v => return Err(unknown("acc/dec mode", v)),
        };
        let interpolator = match self.interpolator {
            MC_GROUP_INTERP_EXACT => Interpolator::Exact,
            MC_GROUP_INTERP_REFERENCE_WORD => Interpolator::ReferenceWord,
            v => return Err(unknown("interpolator", v)),
        };
        let stages = self.home_stages as usize;
        if stages > self.home_order.len() {
            return Err(Failure::new(
                ErrorKind::BadConfig.code(),
                format!("home_stages = {stages}: a home order has at most 8 stages"),
            ));
        }
        // Every set bit is an index, those beyond 7 too: the SDK refuses them (HomeAxis).
        let home_order = self.home_order[..stages]
            .iter()
            .map(|&m| (0..32).filter(|&i| m >> i & 1 == 1).collect())
            .collect();
        Ok(GroupSettings {
            axes,
            accdec,
            interpolator,
            tolerance: self.tolerance,
            home_order,
        })
    }
}

impl From<&GroupSettings> for mc_group_settings {
    /// The SDK's settings of at most 8 axes.
    fn from(s: &GroupSettings) -> Self {
        let mut axes = [0u32; 8];
        for (d, a) in axes.iter_mut().zip(&s.axes) {
            *d = *a as u32;
        }
        Self {
            axes,
            naxes: s.axes.len().min(MAX_AXES) as u32,
            accdec: match s.accdec {
                AccDec::Pre => MC_GROUP_ACCDEC_PRE,
                AccDec::Post => MC_GROUP_ACCDEC_POST,
                AccDec::Both => MC_GROUP_ACCDEC_BOTH,
            },
            interpolator: match s.interpolator {
                Interpolator::Exact => MC_GROUP_INTERP_EXACT,
                Interpolator::ReferenceWord => MC_GROUP_INTERP_REFERENCE_WORD,
            },
            tolerance: s.tolerance,
            home_stages: s.home_order.len().min(8) as u32,
            home_order: {
                let mut m = [0u32; 8];
                for (d, stage) in m.iter_mut().zip(&s.home_order) {
                    *d = stage
                        .iter()
                        .filter(|&&i| i < 32)
                        .fold(0, |m, &i| m | 1 << i);
                }
                m
            },
        }
    }
}

/// Limits of the tangential feed of a group move, in user units of the group's first axis.
/// Every value must be finite and greater than zero.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[allow(non_camel_case_types)]
pub struct mc_path_limits {
    /// Feed (path velocity).
    pub velocity: f64,
    /// Tangential acceleration.
    pub acceleration: f64,
    /// Tangential deceleration.
    pub deceleration: f64,
    /// Tangential jerk.
    pub jerk: f64,
}

impl From<mc_path_limits> for PathLimits {
    fn from(l: mc_path_limits) -> Self {
        PathLimits {
            velocity: l.velocity,
            acceleration: l.acceleration,
            deceleration: l.deceleration,
            jerk: l.jerk,
        }
    }
}

impl From<PathLimits> for mc_path_limits {
    fn from(l: PathLimits) -> Self {
        Self {
            velocity: l.velocity,
            acceleration: l.acceleration,
            deceleration: l.deceleration,
            jerk: l.jerk,
        }
    }
}

/// How a group move is queued. All zero (`{0}`) is the default: absolute targets, the group
/// must be at rest, cutting feed.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[allow(non_camel_case_types)]
pub struct mc_move_options {
    /// Non-zero: targets relative to where the previous move ends.
    pub relative: u32,
    /// Non-zero: queue behind the moves already queued (PLCopen Buffered); else the group
    /// must be at rest.
    pub buffered: u32,
    /// `MC_FEED_TYPE_` value.
    pub feed_type: u32,
}

impl mc_move_options {
    pub(crate) fn to_sdk(self) -> Result<MoveOptions, Failure> {
        Ok(MoveOptions {
            relative: self.relative != 0,
            buffered: self.buffered != 0,
            feed_type: match self.feed_type {
                MC_FEED_TYPE_CUTTING => FeedType::Cutting,
                MC_FEED_TYPE_RAPID => FeedType::Rapid,
                MC_FEED_TYPE_JOG => FeedType::Jog,
                v => return Err(unknown("feed type", v)),
            },
        })
    }
}

/// An arc in the coordinates of its plane (user units): the end point, and per `mode`
/// (`MC_ARC_BY_`) the centre, the radius (`aux[0]`) or a point on the arc.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[allow(non_camel_case_types)]
pub struct mc_arc {
    /// `MC_ARC_BY_` value.
    pub mode: u32,
    /// Non-zero: counter-clockwise; zero: clockwise (ignored by `MC_ARC_BY_BORDER`).
    pub ccw: u32,
    /// End point.
    pub end: [f64; 2],
    /// The centre (`MC_ARC_BY_CENTRE`), the radius in `aux[0]` (`MC_ARC_BY_RADIUS`), or a
    /// point on the arc (`MC_ARC_BY_BORDER`).
    pub aux: [f64; 2],
}

impl mc_arc {
    pub(crate) fn to_sdk(self) -> Result<ArcSpec, Failure> {
        let ccw = self.ccw != 0;
        Ok(match self.mode {
            MC_ARC_BY_CENTRE => ArcSpec::Centre {
                end: self.end,
                centre: self.aux,
                ccw,
            },
            MC_ARC_BY_RADIUS => ArcSpec::Radius {
                end: self.end,
                radius: self.aux[0],
                ccw,
            },
            MC_ARC_BY_BORDER => ArcSpec::Border {
                end: self.end,
                via: self.aux,
            },
            v => return Err(unknown("arc mode", v)),
        })
    }
}

/// Layout 1.13: an arc in the plane of three group axes given by a normal vector, for
/// `mc_group_move_circular_normal`: counter-clockwise about `normal` (any length but 0; the
/// right-hand rule) in the plane through the start, around `centre` to `end` (on `axes`, in
/// their user units; an end at the start: a full turn), then `turns` more full turns. `rise`
/// non-zero: the end may lie off the plane along the normal (a helix along it).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[allow(non_camel_case_types)]
pub struct mc_normal_arc {
    /// The plane's group axes a, b, c.
    pub axes: [u32; 3],
    /// The normal on them.
    pub normal: [f64; 3],
    /// The centre on a, b, c.
    pub centre: [f64; 3],
    /// The end on a, b, c.
    pub end: [f64; 3],
    /// Non-zero: the end may rise off the plane along the normal.
    pub rise: u32,
    /// Full turns added to the arc.
    pub turns: u32,
}

impl mc_normal_arc {
    pub(crate) fn to_sdk(self) -> NormalArc {
        NormalArc {
            axes: self.axes.map(|a| a as usize),
            normal: self.normal,
            centre: self.centre,
            end: self.end,
            rise: self.rise != 0,
            turns: self.turns,
        }
    }
}

/// `MC_ARC_PLANE_AXES`: a plane value names its two group axes u and v (counter-clockwise
/// from u towards v) as `MC_ARC_PLANE_AXES | u << MC_ARC_PLANE_U_SHIFT | v <<
/// MC_ARC_PLANE_V_SHIFT` (u, v 0..7; one axis twice is `MC_ERR_PLANE_AXES`).
pub const MC_ARC_PLANE_U_SHIFT: u32 = 8;
/// See `MC_ARC_PLANE_U_SHIFT`.
pub const MC_ARC_PLANE_V_SHIFT: u32 = 12;

/// The plane of an `MC_ARC_PLANE_` value.
pub(crate) fn plane_of(v: u32) -> Result<Plane, Failure> {
    let axis = |shift: u32| (v >> shift & 0xf) as usize;
    match v {
        MC_ARC_PLANE_XY => Ok(Plane::XY),
        MC_ARC_PLANE_YZ => Ok(Plane::YZ),
        MC_ARC_PLANE_ZX => Ok(Plane::ZX),
        v if v & 0xff == MC_ARC_PLANE_AXES && v >> 16 == 0 => Ok(Plane::Axes(
            axis(MC_ARC_PLANE_U_SHIFT),
            axis(MC_ARC_PLANE_V_SHIFT),
        )),
        v => Err(unknown("plane", v)),
    }
}

/// A group move started by `mc_group_move_linear`, `_ptp`, `_circular`, `_nurbs`,
/// `mc_group_halt` or `mc_group_stop`; wait for it with `mc_group_motion_wait`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[allow(non_camel_case_types)]
pub struct mc_group_motion {
    /// The group.
    pub group: u32,
    /// The seq of the command that started it (`MC_EVENT_GROUP_` events carry the same seq).
    pub seq: u32,
}

/// A consistent snapshot of a group's status. Path quantities are in counts of the group's
/// first axis (no scale applied), as the card publishes them.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[allow(non_camel_case_types)]
pub struct mc_group_status {
    /// `MC_GROUP_STATE_` value.
    pub state: u32,
    /// Moves waiting in the queue.
    pub queued: u32,
    /// Seq of the move being interpolated (0: none).
    pub active_seq: u32,
    /// Group moves started since boot.
    pub move_count: u32,
    /// Distance along the active move, counts.
    pub path_pos: f64,
    /// Length of the active move, counts.
    pub path_len: f64,
    /// Tangential velocity before the filters, counts/s.
    pub feed: f64,
    /// Tangential acceleration before the filters, counts/s².
    pub feed_acc: f64,
    /// Servo tick of this snapshot.
    pub tick: u64,
    /// At the group's last coming to rest, the largest |programmed end − commanded position|
    /// over its axes: the correction its snap to the end made, counts (what the interpolation
    /// and the filters lost, plus the rounding of the sums).
    pub snap_last: f64,
    /// The largest `snap_last` since the group was enabled, counts.
    pub snap_max: f64,
    /// Segments in the group's path buffer not finished yet (`mc_group_path_push`).
    pub path_queued: u32,
    /// Free segments in the path buffer (`MC_PATH_SEGMENTS` - `path_queued`).
    pub path_free: u32,
    /// Id of the segment running (valid while `path_flags` has `MC_PATH_STATUS_RUNNING`).
    pub path_id: u32,
    /// `MC_PATH_STATUS_` bits.
    pub path_flags: u32,
    /// Path segments ended since the group's last `mc_group_enable` (wrapping): 0 after each
    /// enable, whatever ran before it (a disable keeps the count until the next enable; a
    /// program that opens the card finds the count of the enable before it).
    pub path_done: u32,
}

impl From<(GroupState, GroupStatus)> for mc_group_status {
    fn from((state, s): (GroupState, GroupStatus)) -> Self {
        Self {
            state: state as u32,
            queued: s.queued,
            active_seq: s.active_seq,
            move_count: s.move_count,
            path_pos: s.path_pos,
            path_len: s.path_len,
            feed: s.feed,
            feed_acc: s.feed_acc,
            tick: s.tick,
            snap_last: s.snap_last,
            snap_max: s.snap_max,
            path_queued: s.path_queued,
            path_free: s.path_free,
            path_id: s.path_id,
            path_flags: s.path_flags,
            path_done: s.path_done,
        }
    }
}

/// One acc/dec filter: kind and time constant.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[allow(non_camel_case_types)]
pub struct mc_filter {
    /// `MC_FILTER_KIND_` value.
    pub kind: u32,
    /// Time constant, s.
    pub tau: f64,
}

/// An axis's post-interpolation acc/dec filters, one per feed type.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[allow(non_camel_case_types)]
pub struct mc_filter_settings {
    /// Rapid traverse (`MC_FEED_TYPE_RAPID`).
    pub rapid: mc_filter,
    /// Cutting feed (`MC_FEED_TYPE_CUTTING`).
    pub cutting: mc_filter,
    /// Jog (`MC_FEED_TYPE_JOG`).
    pub jog: mc_filter,
}

pub(crate) fn filter_kind(v: u32) -> Result<FilterKind, Failure> {
    match v {
        MC_FILTER_KIND_NONE => Ok(FilterKind::None),
        MC_FILTER_KIND_LINEAR => Ok(FilterKind::Linear),
        MC_FILTER_KIND_EXPONENTIAL => Ok(FilterKind::Exponential),
        MC_FILTER_KIND_BELL => Ok(FilterKind::Bell),
        v => Err(unknown("filter kind", v)),
    }
}

fn filter_code(k: FilterKind) -> u32 {
    match k {
        FilterKind::None => MC_FILTER_KIND_NONE,
        FilterKind::Linear => MC_FILTER_KIND_LINEAR,
        FilterKind::Exponential => MC_FILTER_KIND_EXPONENTIAL,
        FilterKind::Bell => MC_FILTER_KIND_BELL,
    }
}

impl mc_filter_settings {
    pub(crate) fn to_sdk(self) -> Result<FilterSettings, Failure> {
        let f = |c: mc_filter| Ok::<_, Failure>((filter_kind(c.kind)?, c.tau));
        Ok(FilterSettings {
            rapid: f(self.rapid)?,
            cutting: f(self.cutting)?,
            jog: f(self.jog)?,
        })
    }
}

impl From<FilterSettings> for mc_filter_settings {
    fn from(s: FilterSettings) -> Self {
        let f = |(kind, tau): (FilterKind, f64)| mc_filter {
            kind: filter_code(kind),
            tau,
        };
        Self {
            rapid: f(s.rapid),
            cutting: f(s.cutting),
            jog: f(s.jog),
        }
    }
}

/// The PD+ servo law of an axis (Yeh eq 2.12) and its drive model (Yeh eq 2.2), in counts,
/// seconds and volts: the card's `mc_axis_pdplus` register block, the same struct as in the
/// register map (`gains`: `u = kp·e + kd·ė + kv·v_ref + ka·a_ref`; `drive`: `dw/dt = −w/tau +
/// (kc/tau)·u`, `dθ/dt = ke·w`; `umax`, at most the axis's `dac_limit_v`).
#[allow(non_camel_case_types)]
pub type mc_pdplus_settings = firmware_proto::raw::mc_axis_pdplus;

/// How a NURBS curve is followed, in user units of the group's first axis.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[allow(non_camel_case_types)]
pub struct mc_nurbs_feed {
    /// Feed along the curve.
    pub feed: f64,
    /// Tangential acceleration limit.
    pub accel: f64,
    /// Tangential jerk limit.
    pub jerk: f64,
    /// Chord error tolerance (the feed is lowered where the curvature needs it), in the user
    /// units of the group's first axis; 0: the default, one encoder count (1 µm on a 1 µm/count
    /// scale).
    pub chord_tolerance: f64,
    /// Saturation-aware feed (Yeh §3.4): the fraction of each axis's PD+ `umax` the look-ahead
    /// may plan with, in (0, 1]; needs PD+ on every group axis (`MC_ERR_INCOMPATIBLE_MODE`
    /// otherwise). 0: not saturation-aware.
    pub saturation_budget: f64,
}

/// One NURBS curve of a path (`mc_group_move_nurbs_path`), described as the arguments of
/// `mc_group_move_nurbs`: `n_ctrl` control points of `dim` values in `ctrl`, `n_ctrl` weights,
/// `n_knots` knots. The arrays are read during the call only.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
#[allow(non_camel_case_types)]
pub struct mc_nurbs_curve {
    /// Degree, 1..5.
    pub degree: u32,
    /// Dimension: the group's axis count.
    pub dim: u32,
    /// `n_ctrl * dim` doubles, point after point, in group axis order and user units.
    pub ctrl: *const f64,
    /// Control points.
    pub n_ctrl: usize,
    /// `n_ctrl` weights, finite and positive.
    pub weights: *const f64,
    /// `n_knots` knots, clamped and non-decreasing.
    pub knots: *const f64,
    /// `n_ctrl + degree + 1`.
    pub n_knots: usize,
}

impl Default for mc_nurbs_curve {
    /// No curve: NULL arrays, zero counts.
    fn default() -> Self {
        Self {
            degree: 0,
            dim: 0,
            ctrl: std::ptr::null(),
            n_ctrl: 0,
            weights: std::ptr::null(),
            knots: std::ptr::null(),
            n_knots: 0,
        }
    }
}

impl From<NurbsFeed> for mc_nurbs_feed {
    fn from(f: NurbsFeed) -> Self {
        Self {
            feed: f.feed,
            accel: f.accel,
            jerk: f.jerk,
            chord_tolerance: f.chord_tolerance.unwrap_or(0.0),
            saturation_budget: f.saturation.unwrap_or(0.0),
        }
    }
}

impl From<mc_nurbs_feed> for NurbsFeed {
    fn from(f: mc_nurbs_feed) -> Self {
        NurbsFeed {
            feed: f.feed,
            accel: f.accel,
            jerk: f.jerk,
            chord_tolerance: (f.chord_tolerance != 0.0).then_some(f.chord_tolerance),
            saturation: (f.saturation_budget != 0.0).then_some(f.saturation_budget),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use motioncard_sdk::proto::raw;

    #[test]
    fn both_is_pre_and_post() {
        assert_eq!(
            MC_GROUP_ACCDEC_BOTH,
            raw::MC_ACCDEC_PRE | raw::MC_ACCDEC_POST
        );
    }

    #[test]
    fn group_types_round_trip_and_unknown_values_are_refused() {
        let s = GroupSettings {
            accdec: AccDec::Both,
            interpolator: Interpolator::ReferenceWord,
            home_order: vec![vec![2], vec![0, 1]],
            ..GroupSettings::new(&[3, 1, 2])
        };
        let c = mc_group_settings::from(&s);
        assert_eq!(c.naxes, 3);
        assert_eq!((c.home_stages, &c.home_order[..3]), (2, &[4, 3, 0][..]));
        assert_eq!(c.to_sdk().unwrap(), s);
        let bad = mc_group_settings {
            home_stages: 9,
            ..c
        };
        assert_eq!(bad.to_sdk().unwrap_err().code, ErrorKind::BadConfig.code());
        for (field, v) in [(0, 0), (0, 4), (1, 2)] {
            let mut bad = c;
            match field {
                0 => bad.accdec = v,
                _ => bad.interpolator = v,
            }
            assert_eq!(
                bad.to_sdk().unwrap_err().code,
                ErrorKind::BadConfig.code(),
                "{bad:?}"
            );
        }
        for n in [0, 9, u32::MAX] {
            let bad = mc_group_settings { naxes: n, ..c };
            assert_eq!(
                bad.to_sdk().unwrap_err().code,
                ErrorKind::BadAxis.code(),
                "naxes {n}"
            );
        }

        for f in [
            FilterSettings::shin_table1(),
            FilterSettings::shin_table1_z(),
        ] {
            assert_eq!(mc_filter_settings::from(f).to_sdk().unwrap(), f);
        }
        let mut f = mc_filter_settings::from(FilterSettings::shin_table1());
        f.jog.kind = 4;
        assert_eq!(f.to_sdk().unwrap_err().code, ErrorKind::BadConfig.code());

        // A zeroed mc_move_options is the SDK's default.
        assert_eq!(
            mc_move_options::default().to_sdk().unwrap(),
            MoveOptions::default()
        );
        let o = mc_move_options {
            relative: 7,
            buffered: 1,
            feed_type: MC_FEED_TYPE_JOG,
        };
        assert_eq!(
            o.to_sdk().unwrap(),
            MoveOptions {
                relative: true,
                buffered: true,
                feed_type: FeedType::Jog
            }
        );
        let bad = mc_move_options { feed_type: 3, ..o };
        assert_eq!(bad.to_sdk().unwrap_err().code, ErrorKind::BadConfig.code());

        let arc = |mode| mc_arc {
            mode,
            ccw: 1,
            end: [1.0, 2.0],
            aux: [3.0, 4.0],
        };
        assert_eq!(
            arc(MC_ARC_BY_CENTRE).to_sdk().unwrap(),
            ArcSpec::Centre {
                end: [1.0, 2.0],
                centre: [3.0, 4.0],
                ccw: true
            }
        );
        assert_eq!(
            arc(MC_ARC_BY_RADIUS).to_sdk().unwrap(),
            ArcSpec::Radius {
                end: [1.0, 2.0],
                radius: 3.0,
                ccw: true
            }
        );
        assert_eq!(
            arc(MC_ARC_BY_BORDER).to_sdk().unwrap(),
            ArcSpec::Border {
                end: [1.0, 2.0],
                via: [3.0, 4.0]
            }
        );
        assert_eq!(
            arc(3).to_sdk().unwrap_err().code,
            ErrorKind::BadConfig.code()
        );
        assert_eq!(plane_of(MC_ARC_PLANE_ZX).unwrap(), Plane::ZX);
        assert_eq!(plane_of(4).unwrap_err().code, ErrorKind::BadConfig.code());
        assert_eq!(
            plane_of(MC_ARC_PLANE_AXES | 3 << MC_ARC_PLANE_U_SHIFT | 1 << MC_ARC_PLANE_V_SHIFT)
                .unwrap(),
            Plane::Axes(3, 1)
        );
        assert_eq!(
            plane_of(MC_ARC_PLANE_AXES | 1 << 16).unwrap_err().code,
            ErrorKind::BadConfig.code()
        );

        let feed = mc_nurbs_feed {
            feed: 1.0,
            accel: 2.0,
            jerk: 3.0,
            chord_tolerance: 4.0,
            saturation_budget: 0.0,
        };
        assert_eq!(NurbsFeed::from(feed).saturation, None);
        assert_eq!(NurbsFeed::from(feed).chord_tolerance, Some(4.0));
        let default_chord = mc_nurbs_feed {
            chord_tolerance: 0.0,
            ..feed
        };
        assert_eq!(NurbsFeed::from(default_chord).chord_tolerance, None);
        let aware = mc_nurbs_feed {
            saturation_budget: 0.8,
            ..feed
        };
        assert_eq!(NurbsFeed::from(aware).saturation, Some(0.8));
        for f in [
            NurbsFeed::new(1.0, 2.0, 3.0),
            NurbsFeed {
                saturation: Some(0.5),
                ..NurbsFeed::new(1.0, 2.0, 3.0)
            },
        ] {
            assert_eq!(NurbsFeed::from(mc_nurbs_feed::from(f)), f);
        }
    }
}
