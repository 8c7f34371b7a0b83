//! The NURBS curve transfer of a group: `MC_OP_NURBS_BEGIN` (a move) or `MC_OP_PATH_NURBS` (a
//! path segment) opens it, `MC_OP_NURBS_DATA` stages its control points, weights and knots in
//! order, `MC_OP_NURBS_END` checks the curve and queues the move (or, for the path, hands it to
//! `path.rs`).

use super::*;
use firmware_proto::cmd::{NurbsBegin, NurbsData, PathFlags};

/// A NURBS transfer in progress: header and the staged data stream.
#[derive(Debug, Clone, Default)]
pub(super) struct NurbsRx {
    pub(super) open: bool,
    pub(super) degree: usize,
    /// The group's axes when the transfer began (the stream's layout depends on it).
    pub(super) naxes: usize,
    pub(super) n_ctrl: usize,
    pub(super) total: usize,
    pub(super) received: usize,
    /// feed, accel, jerk, chord tolerance, saturation budget.
    pub(super) params: [f64; 5],
    pub(super) saturation: bool,
    /// A move's: buffered, feed type.
    pub(super) opts: MoveOpts,
    /// The curve is a path segment (MC_OP_PATH_NURBS) with these flags: `params` are feed,
    /// tolerance, fit tolerance, id.
    pub(super) path: Option<PathFlags>,
    /// Control points, weights, knots: allocated once at boot.
    pub(super) stage: FixedVec<f64, STAGE_LEN>,
}

/// Values one transfer can hold: control points of up to 8 axes, weights, knots.
pub(super) const STAGE_LEN: usize =
    crate::motion::nurbs::MAX_CTRL * (MAX_AXES + 1) + crate::motion::nurbs::MAX_KNOTS;

/// A curve transfer's degree, control point count and knot count (for a group of `naxes`):
/// (degree, n_ctrl).
pub(super) fn curve_header(
    degree: f64,
    n_ctrl: f64,
    n_knots: f64,
    naxes: usize,
) -> Result<(usize, usize), NackCode> {
    let int = |x: f64| whole(x).filter(|n| *n <= 1_000_000);
    let degree = int(degree)
        .filter(|d| (1..=crate::motion::nurbs::MAX_DEGREE).contains(d))
        .ok_or(NackCode::NurbsDegree)?;
    if naxes < 2 {
        return Err(NackCode::NurbsDimension);
    }
    let n_ctrl = int(n_ctrl)
        .filter(|n| (degree + 1..=crate::motion::nurbs::MAX_CTRL).contains(n))
        .ok_or(NackCode::NurbsCtrlCount)?;
    if int(n_knots) != Some(n_ctrl + degree + 1) {
        return Err(NackCode::NurbsKnotCount);
    }
    Ok((degree, n_ctrl))
}

/// The nack for a curve the NURBS module refuses: one code per fault. Public so that the host
/// SDK reports a curve it refuses before sending it with the code the card would give.
pub fn nurbs_nack(e: NurbsError) -> NackCode {
    match e {
        NurbsError::BadDegree { .. } => NackCode::NurbsDegree,
        NurbsError::BadDimension { .. } => NackCode::NurbsDimension,
        NurbsError::ControlDataLength { .. }
        | NurbsError::TooFewControlPoints { .. }
        | NurbsError::TooManyControlPoints { .. }
        | NurbsError::WeightCountMismatch { .. } => NackCode::NurbsCtrlCount,
        NurbsError::KnotCountMismatch { .. } => NackCode::NurbsKnotCount,
        NurbsError::KnotsDecreasing { .. } => NackCode::NurbsKnotsDecreasing,
        NurbsError::KnotMultiplicity { .. } => NackCode::NurbsKnotMultiplicity,
        NurbsError::NotClamped | NurbsError::EmptyDomain => NackCode::NurbsNotClamped,
        NurbsError::BadWeight { .. } => NackCode::NurbsWeight,
        NurbsError::NonFiniteKnot { .. } => NackCode::NurbsKnot,
        NurbsError::NonFiniteControlPoint { .. } => NackCode::NurbsPoint,
        NurbsError::NonFiniteParameter
        | NurbsError::ParameterOutOfRange
        | NurbsError::BadCircle => NackCode::BadConfig,
    }
}

impl Group {
    /// MC_OP_NURBS_BEGIN: check the header and open the transfer (a new begin replaces an
    /// unfinished one).
    pub fn nurbs_begin(
        &mut self,
        b: &NurbsBegin,
        axes: &[Axis; MAX_AXES],
        ts: f64,
    ) -> Result<(), NackCode> {
        self.rx.open = false;
        let cfg = self.can_queue(b.buffered)?;
        let [degree, n_ctrl, n_knots] = b.size.to_array();
        let a = [
            degree,
            n_ctrl,
            n_knots,
            b.feed,
            b.accel,
            b.jerk,
            b.chord_tolerance,
            b.budget,
        ];
        if a.iter().any(|x| !x.is_finite()) {
            return Err(NackCode::NotFinite);
        }
        let (degree, n_ctrl) = curve_header(a[0], a[1], a[2], cfg.naxes)?;
        if a[6] <= 0.0 {
            return Err(NackCode::NonPositiveLimit); // the chord tolerance
        }
        let rate = crate::firmware::rate_hz(ts);
        crate::firmware::nack::check_ranges(rate, &[(1, a[3]), (2, a[4]), (3, a[5])])?;
        let saturation = b.saturation;
        if !(0.0..=1.0).contains(&a[7]) || (saturation && a[7] == 0.0) {
            return Err(NackCode::BadConfig);
        }
        if saturation
            && cfg.axes[..cfg.naxes]
                .iter()
                .any(|&ax| axes[ax].config.pdplus.is_none())
        {
            // The saturation-aware feed predicts each axis's PD+ drive output (Yeh eq 3.5).
            return Err(NackCode::IncompatibleMode);
        }
        if saturation && cfg.post {
            // ... from the reference the interpolator gives it: post-interpolation filters
            // change what reaches the servo, and the prediction would no longer hold.
            return Err(NackCode::IncompatibleMode);
        }
        let params = [a[3], a[4], a[5], a[6], a[7]];
        let opts = MoveOpts {
            relative: false,
            buffered: b.buffered,
            feed_type: b.feed_type,
        };
        self.open_rx((degree, cfg.naxes, n_ctrl), params, saturation, opts, None);
        Ok(())
    }

    /// Opens a curve transfer of (degree, axes, control points) into the staging buffer: a
    /// move's (with `opts`) or a path segment's (with its flags, `path`).
    pub(super) fn open_rx(
        &mut self,
        (degree, n, n_ctrl): (usize, usize, usize),
        params: [f64; 5],
        saturation: bool,
        opts: MoveOpts,
        path: Option<PathFlags>,
    ) {
        self.rx = NurbsRx {
            open: true,
            degree,
            naxes: n,
            n_ctrl,
            total: n_ctrl * (n + 1) + n_ctrl + degree + 1,
            received: 0,
            params,
            saturation,
            opts,
            path,
            stage: core::mem::take(&mut self.rx.stage),
        };
    }

    /// MC_OP_NURBS_DATA: the next values of the stream, in order.
    pub fn nurbs_data(&mut self, d: &NurbsData) -> Result<(), NackCode> {
        let rx = &mut self.rx;
        let (offset, count) = (d.offset as usize, d.values.len());
        if !rx.open
            || offset != rx.received
            || count == 0
            || count > firmware_proto::NURBS_DATA_MAX
            || offset + count > rx.total
            || self.config.map(|c| c.naxes) != Some(rx.naxes)
        {
            return Err(NackCode::NurbsSequence);
        }
        let n = rx.naxes;
        let weights = rx.n_ctrl * n..rx.n_ctrl * (n + 1);
        for (i, v) in d.values.iter().enumerate() {
            let k = offset + i;
            if !v.is_finite() {
                return Err(if weights.contains(&k) {
                    NackCode::NurbsWeight
                } else if k >= weights.end {
                    NackCode::NurbsKnot
                } else {
                    NackCode::NurbsPoint
                });
            }
            // The curve stays inside the convex hull of its control points: bounding them
            // bounds the whole path, like the target of any other move.
            if k < weights.start && v.abs() > crate::MAX_POSITION {
                return Err(NackCode::OutOfRange);
            }
        }
        let Some(dst) = rx.stage.get_mut(offset..offset + count) else {
            return Err(NackCode::NurbsSequence);
        };
        dst.copy_from_slice(&d.values);
        rx.received += count;
        Ok(())
    }

    /// MC_OP_NURBS_END: validate the curve (every fault its own code) and queue the move. The
    /// curve and its look-ahead profile are planned into a free slot of the group's pool
    /// (`QueueFull` when none is free); only the planning's scratch tables allocate.
    pub fn nurbs_end(
        &mut self,
        seq: u32,
        axes: &[Axis; MAX_AXES],
        ts: f64,
        tick: u64,
        out: &mut Outbox,
    ) -> Result<(), NackCode> {
        if !self.rx.open || self.rx.received != self.rx.total {
            self.rx.open = false;
            return Err(NackCode::NurbsSequence);
        }
        self.rx.open = false;
        if self.rx.path.is_some() {
            return self.path_curve(seq, ts, tick, out);
        }
        let cfg = self.can_queue(self.rx.opts.buffered)?;
        let n = cfg.naxes;
        let rx = &self.rx;
        // (A reconfigured group closes the transfer; the layout is checked all the same.)
        let split = (n == rx.naxes)
            .then(|| rx.stage.get(..rx.total))
            .flatten()
            .and_then(|s| s.split_at_checked(rx.n_ctrl * n))
            .and_then(|(pts, rest)| Some((pts, rest.split_at_checked(rx.n_ctrl)?)));
        let Some((pts, (weights, knots))) = split else {
            return Err(NackCode::NurbsSequence);
        };
        let (active, queue) = (&self.active, &self.queue);
        let slot = self
            .nurbs
            .free(|k| slot_taken(active, queue, k))
            .ok_or(NackCode::QueueFull)?;
        let Some(nf) = self.nurbs.get_mut(slot) else {
            return Err(NackCode::QueueFull);
        };
        nf.sat = None;
        nf.interp
            .set_curve(rx.degree, n, pts, weights, knots)
            .map_err(nurbs_nack)?;
        let curve = nf.interp.curve();
        let start = curve.eval_clamped(curve.domain().0).0;
        if (0..n).any(|i| (start[i] - self.queue_end[i]).abs() > cfg.tolerance) {
            return Err(NackCode::NurbsStart);
        }
        let [feed, accel, jerk, chord_tol, budget] = rx.params;
        let icfg = InterpConfig {
            ts,
            feed,
            accel,
            jerk,
            chord_tol,
            max_corrections: 3,
        };
        let yeh_nack = |e: InterpError| match e {
            InterpError::ZeroLengthCurve => NackCode::NurbsZeroLength,
            InterpError::Curve(e) => nurbs_nack(e),
            InterpError::BadFeed
            | InterpError::BadAccel
            | InterpError::BadJerk
            | InterpError::BadChordTolerance => NackCode::NonPositiveLimit,
            _ => NackCode::BadConfig,
        };
        let end = curve.eval_clamped(curve.domain().1).0;
        if rx.saturation {
            let mut models = [AxisModel {
                gains: PdPlusGains {
                    kp: 0.0,
                    kd: 0.0,
                    kv: 0.0,
                    ka: 0.0,
                },
                plant: DriveModel {
                    kc: 1.0,
                    tau: 1.0,
                    ke: 1.0,
                },
                umax: 1.0,
            }; MAX_AXES];
            for (m, &a) in models.iter_mut().zip(&cfg.axes[..n]) {
                *m = axes[a].config.pdplus.ok_or(NackCode::IncompatibleMode)?;
            }
            let sat = SaturationAwareFeed::new(&models[..n], ts).map_err(yeh_nack)?;
            nf.interp
                .plan_curve(icfg, Some((&sat, budget)))
                .map_err(yeh_nack)?;
            nf.sat = Some(sat);
        } else {
            nf.interp.plan_curve(icfg, None).map_err(yeh_nack)?;
        }
        let mut s = [0.0; MAX_AXES];
        let mut e = [0.0; MAX_AXES];
        for i in 0..n {
            s[i] = self.queue_end[i];
            e[i] = end[i];
        }
        let len = nf.interp.length();
        // As for every other move: one that would run for longer than MAX_MOVE_TIME (at its
        // top feed already) comes from limits that are almost certainly wrong.
        let shortest = len / feed;
        if !shortest.is_finite() || shortest > crate::MAX_MOVE_TIME {
            return Err(NackCode::Infeasible);
        }
        let geom = Geometry::Curve {
            start: s,
            end: e,
            len,
        };
        let feed_type = rx.opts.feed_type.min(2) as usize;
        self.push(
            Move {
                seq,
                geom,
                feed: Feed::Nurbs(slot),
                feed_type,
                ptp: false,
                runout: false,
            },
            n,
            tick,
            out,
        );
        Ok(())
    }
}
