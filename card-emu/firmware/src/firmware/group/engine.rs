//! Layout 1.14: the path a group runs ([`Engine`]): its members' (`Path<8>`, the same engine
//! as before paths across cards existed) or, once the group has path dimensions, a [`Wide`]
//! one: a `Path<16>` over every dimension of a path whose axes live on several cards, of which
//! the group drives its own members; the engine hands the group its members' coordinates
//! (each member is one dimension). `wide.rs` stages and releases its segments.

use super::*;
use crate::motion::path::{Path, PathError, PathEvent, PathLimits, PauseState, Segment};
use firmware_proto::layout::{PATH_MAX_DIMS, PATH_STAGE_LEN};
use firmware_proto::{GroupDims, PATH_LEN};

/// Dimensions of a path across cards.
pub const DIMS: usize = PATH_MAX_DIMS;

/// A group's path dimensions, validated.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Dims {
    /// How many (1..=DIMS).
    pub(super) n: usize,
    /// Per dimension: the group axis it drives here (None: another card's).
    pub(super) member: [Option<usize>; DIMS],
    pub(super) vmax: [f64; DIMS],
    pub(super) amax: [f64; DIMS],
    pub(super) jmax: [f64; DIMS],
    /// Where the remote dimensions start (0 for the members').
    pub(super) start: [f64; DIMS],
}

impl Dims {
    /// The members' positions in `p`, a point of the path.
    #[inline]
    pub(super) fn members(&self, p: &[f64; DIMS]) -> [f64; MAX_AXES] {
        let mut out = [0.0; MAX_AXES];
        for (d, m) in self.member[..self.n].iter().enumerate() {
            if let Some(m) = *m {
                out[m] = p[d];
            }
        }
        out
    }
}

/// Check a `group_dims` block for a group of `cfg` at `rate` Hz: `None` for no dimensions.
pub(super) fn validate_dims(
    b: &GroupDims,
    cfg: &GroupConfig,
    rate: u32,
) -> Result<Option<Dims>, NackCode> {
    let n = b.ndims as usize;
    if n == 0 {
        return Ok(None);
    }
    if n > DIMS {
        return Err(NackCode::PathDims);
    }
    let mut member = [None; DIMS];
    let mut seen = [false; MAX_AXES];
    for (d, &a) in b.axis[..n].iter().enumerate() {
        if a == raw::MC_DIM_REMOTE {
            continue;
        }
        let m = usize::try_from(a).map_err(|_| NackCode::PathDims)?;
        if m >= cfg.naxes || seen[m] {
            return Err(NackCode::PathDims);
        }
        seen[m] = true;
        member[d] = Some(m);
    }
    if !seen[..cfg.naxes].iter().all(|&s| s) {
        return Err(NackCode::PathDims);
    }
    let mut ranges = [(0i32, 0.0f64); 3 * DIMS];
    for d in 0..n {
        for (k, (order, x)) in [(1i32, b.vmax[d]), (2, b.amax[d]), (3, b.jmax[d])]
            .into_iter()
            .enumerate()
        {
            if !x.is_finite() {
                return Err(NackCode::NotFinite);
            }
            ranges[3 * d + k] = (order, x);
        }
        let s = b.start[d];
        if member[d].is_none() && !s.is_finite() {
            return Err(NackCode::NotFinite);
        }
        if member[d].is_none() && s.abs() > crate::MAX_POSITION {
            return Err(NackCode::OutOfRange);
        }
    }
    crate::firmware::nack::check_ranges(rate, &ranges[..3 * n])?;
    let mut dims = Dims {
        n,
        member,
        vmax: [0.0; DIMS],
        amax: [0.0; DIMS],
        jmax: [0.0; DIMS],
        start: [0.0; DIMS],
    };
    dims.vmax[..n].copy_from_slice(&b.vmax[..n]);
    dims.amax[..n].copy_from_slice(&b.amax[..n]);
    dims.jmax[..n].copy_from_slice(&b.jmax[..n]);
    for (d, m) in member[..n].iter().enumerate() {
        if m.is_none() {
            dims.start[d] = b.start[d];
        }
    }
    Ok(Some(dims))
}

/// A segment staged, with its command's seq.
#[derive(Debug, Clone, Copy)]
pub(super) struct Staged {
    pub(super) seq: u32,
    pub(super) seg: Segment<DIMS>,
}

/// A path across cards: the wide path, its dimensions, the segments staged.
#[derive(Clone)]
pub(super) struct Wide {
    pub(super) path: Path<DIMS>,
    pub(super) dims: Dims,
    pub(super) staged: FixedVec<Staged, PATH_STAGE_LEN>,
    /// Where the next segment staged starts, every dimension.
    pub(super) stage_end: [f64; DIMS],
    /// Where the path starts afresh (set when staging begins on an idle path).
    pub(super) origin: [f64; DIMS],
    /// Applied and not reset since: the remote dimensions are at their `start`.
    pub(super) fresh: bool,
}

/// The path a group runs: its members' or, with dimensions, a wide one. (Unboxed: a group
/// holds one or the other, and the card's build allocates nothing.)
#[derive(Clone)]
#[allow(clippy::large_enum_variant)]
pub(super) enum Engine {
    /// The members' path (`Path<8>`).
    Narrow(Path),
    /// A path across cards.
    Wide(Wide),
}

/// `$e` with `$p` the engine's path, of either width.
macro_rules! on_path {
    ($self:expr, $p:ident => $e:expr) => {
        match $self {
            Engine::Narrow($p) => $e,
            Engine::Wide(w) => {
                let $p = &mut w.path;
                $e
            }
        }
    };
}
macro_rules! on_path_ref {
    ($self:expr, $p:ident => $e:expr) => {
        match $self {
            Engine::Narrow($p) => $e,
            Engine::Wide(w) => {
                let $p = &w.path;
                $e
            }
        }
    };
}

impl Engine {
    /// The members' path, storage for `PATH_LEN` segments.
    pub(super) fn narrow() -> Self {
        Self::Narrow(Path::with_capacity(PATH_LEN))
    }

    /// The members' path (None: a wide one).
    pub(super) fn as_narrow(&mut self) -> Option<&mut Path> {
        match self {
            Self::Narrow(p) => Some(p),
            Self::Wide(_) => None,
        }
    }

    /// The wide path (None: the members').
    pub(super) fn as_wide(&self) -> Option<&Wide> {
        match self {
            Self::Narrow(_) => None,
            Self::Wide(w) => Some(w),
        }
    }

    /// Queue a members' segment (a wide path takes none: `BadAxis`).
    pub(super) fn push(&mut self, seg: Segment) -> Result<(), PathError> {
        match self {
            Self::Narrow(p) => p.push(seg),
            Self::Wide(_) => Err(PathError::BadAxis),
        }
    }

    /// Queue a segment of every dimension (a members' path takes none: `BadAxis`).
    pub(super) fn push_wide(&mut self, seg: Segment<DIMS>) -> Result<(), PathError> {
        match self {
            Self::Narrow(_) => Err(PathError::BadAxis),
            Self::Wide(w) => w.path.push(seg),
        }
    }

    #[inline]
    pub(super) fn is_moving(&self) -> bool {
        on_path_ref!(self, p => p.is_moving())
    }
    pub(super) fn speed(&self) -> f64 {
        on_path_ref!(self, p => p.speed())
    }
    pub(super) fn accel(&self) -> f64 {
        on_path_ref!(self, p => p.accel())
    }
    pub(super) fn distance(&self) -> f64 {
        on_path_ref!(self, p => p.distance())
    }
    pub(super) fn current_id(&self) -> Option<u32> {
        on_path_ref!(self, p => p.current_id())
    }
    pub(super) fn free(&self) -> usize {
        on_path_ref!(self, p => p.free())
    }
    pub(super) fn pause_state(&self) -> PauseState {
        on_path_ref!(self, p => p.pause_state())
    }
    pub(super) fn pause(&mut self) -> bool {
        on_path!(self, p => p.pause())
    }
    pub(super) fn resume(&mut self) {
        on_path!(self, p => p.resume())
    }
    pub(super) fn halt(&mut self, decel: f64, jerk: f64) {
        on_path!(self, p => p.halt(decel, jerk))
    }
    /// Where the members are on the path.
    pub(super) fn position(&self) -> [f64; MAX_AXES] {
        match self {
            Self::Narrow(p) => p.position(),
            Self::Wide(w) => w.dims.members(&w.path.position()),
        }
    }
    /// Where the members are at the end of what is queued.
    pub(super) fn end(&self) -> [f64; MAX_AXES] {
        match self {
            Self::Narrow(p) => p.end(),
            Self::Wide(w) => w.dims.members(&w.path.end()),
        }
    }
    /// A servo tick: the members' positions.
    #[inline]
    pub(super) fn tick(&mut self, factor: f64, ev: &mut impl FnMut(PathEvent)) -> [f64; MAX_AXES] {
        match self {
            Self::Narrow(p) => p.tick(factor, ev),
            Self::Wide(w) => {
                let p = w.path.tick(factor, ev);
                w.dims.members(&p)
            }
        }
    }
    /// Segments staged.
    pub(super) fn staged(&self) -> usize {
        self.as_wide().map_or(0, |w| w.staged.len())
    }
    /// Abort every staged segment (`code`: the opcode that did): one event each, oldest first.
    pub(super) fn abort_staged(&mut self, group: u16, code: i32, tick: u64, out: &mut Outbox) {
        if let Self::Wide(w) = self {
            for s in w.staged.iter() {
                out.push(Event {
                    seq: s.seq,
                    kind: EventKind::GroupMotionAborted as u16,
                    axis: group,
                    code,
                    tick,
                    value: 0.0,
                });
            }
            w.staged.clear();
        }
    }
}

impl Wide {
    /// At rest with nothing queued (`path_at_rest`) and nothing staged: the next segment staged
    /// starts afresh, where the members are (`members`) and the remote dimensions were left.
    pub(super) fn begin_staging(&mut self, path_at_rest: bool, members: &[f64; MAX_AXES]) {
        if !(self.staged.is_empty() && path_at_rest) {
            return;
        }
        let mut o = if self.fresh {
            self.dims.start
        } else {
            self.path.position()
        };
        for (o, m) in o.iter_mut().zip(&self.dims.member[..self.dims.n]) {
            if let Some(m) = *m {
                *o = members[m];
            }
        }
        self.origin = o;
        self.stage_end = o;
    }

    /// Reset at the staging's origin (the members must be there: `PathRelease` else).
    pub(super) fn reset_at_origin(
        &mut self,
        members: &[f64; MAX_AXES],
        lim: PathLimits<DIMS>,
        lookahead: usize,
    ) -> Result<(), NackCode> {
        let moved = (0..self.dims.n)
            .any(|d| self.dims.member[d].is_some_and(|m| self.origin[d] != members[m]));
        if moved {
            // the group moved since these segments were staged from where it was
            return Err(NackCode::PathRelease);
        }
        self.path
            .reset(self.origin, lim, lookahead)
            .map_err(|_| NackCode::BadConfig)?;
        self.fresh = false;
        Ok(())
    }

    /// The dimensions.
    pub(super) fn dims(&self) -> &Dims {
        &self.dims
    }
}
