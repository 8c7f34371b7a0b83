//! NURBS moves: the curve type, PD+ configuration, and streaming a curve to the card.

use crate::card::{finite, positive, Axis};
use crate::error::{Error, Result, Target};
use crate::group::{Group, GroupMotion, MoveOptions};
use firmware_proto::cmd::{self, CardCmd, CurveSize, GroupCmd};
use firmware_proto::layout;
use firmware_proto::{raw, Mem, NackCode, NURBS_DATA_MAX};
use std::time::Duration;

/// Split a curve with more control points than the card takes ([`NURBS_MAX_CTRL`]) into
/// pieces for [`Group::move_nurbs_path`]: exact (knot insertion at the cut knots), in order,
/// each piece starting where the one before ends.
pub use card_firmware::host::split_curve as split_nurbs;
pub use card_firmware::host::{clamped_uniform_knots, Nurbs, NurbsError};
/// Limits of a [`Nurbs`] curve: degree, dimension (axes), control points, knots.
pub use card_firmware::host::{
    MAX_CTRL as NURBS_MAX_CTRL, MAX_DEGREE as NURBS_MAX_DEGREE, MAX_DIM as NURBS_MAX_DIM,
    MAX_KNOTS as NURBS_MAX_KNOTS,
};

/// PD+ servo law of an axis (Yeh eq 2.12) and its drive model (Yeh eq 2.2) in counts,
/// seconds and volts: `u = kp·e + kd·ė + kv·v_ref + ka·a_ref` (`gains`); `dw/dt = −w/τ +
/// (kc/τ)·u`, `dθ/dt = ke·w` (`drive`); the drive limit `umax`. The card's `mc_axis_pdplus`
/// block, whose fields the register map's header lists.
pub use firmware_proto::AxisPdPlus as PdPlusSettings;

/// Yeh Table 1, axis 0 (X) or 1 (Y), in volts (1 DU = 10 V).
pub fn die_bonder_pdplus(axis: usize) -> PdPlusSettings {
    let m = card_firmware::host::die_bonder_volts().axes[axis.min(1)];
    PdPlusSettings {
        gains: m.gains,
        drive: m.plant,
        umax: m.umax,
        ..Default::default()
    }
}

/// The plant of Yeh's die bonder, axis 0 (X) or 1 (Y), for an emulated card.
#[cfg(feature = "emulator")]
pub fn die_bonder_plant(axis: usize) -> card_emu::MotorParams {
    let m = card_firmware::host::die_bonder_volts().axes[axis.min(1)];
    card_emu::MotorParams::die_bonder(m.plant.kc, m.plant.tau)
}

impl Axis {
    /// Switch the axis to the PD+ servo law with these gains and drive model.
    pub fn configure_pdplus(&self, s: &PdPlusSettings) -> Result<()> {
        let w = self.card().window();
        let a = self.index();
        let _guard = self.card().config_lock();
        self.card().write_block(layout::AXIS_PDPLUS.at(a), s);
        let law = layout::AXIS_CONFIG
            .at(a)
            .field(core::mem::offset_of!(raw::mc_axis_config, servo_law));
        w.write32(law, raw::MC_SERVO_PDPLUS);
        self.card().inner().traced(law..law + 4);
        self.card()
            .execute_seq(
                CardCmd::ApplyAxisConfig.command(a as u16),
                "configure PD+",
                Target::Axis(a),
            )
            .map(|_| ())
    }

    /// Layout 1.8: the PD+ law the axis runs, read back from the card (`None`: it runs FFPIV).
    pub fn pdplus_settings(&self) -> Result<Option<PdPlusSettings>> {
        let (cfg, pd, _) = self.card().read_axis_config(self.index())?;
        Ok((cfg.servo_law == raw::MC_SERVO_PDPLUS).then_some(pd))
    }
}

/// How a NURBS curve is followed (path units of the group's first axis).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NurbsFeed {
    /// Feed along the curve.
    pub feed: f64,
    /// Tangential acceleration limit.
    pub accel: f64,
    /// Tangential jerk limit.
    pub jerk: f64,
    /// Chord error tolerance (the feed is lowered where the curvature needs it), in the first
    /// axis's user units; `None` is one encoder count, converted to user units when the move
    /// is sent (1 µm on the usual 1 µm/count linear scale, whatever the user units are).
    pub chord_tolerance: Option<f64>,
    /// Saturation-aware feed (Yeh §3.4): the fraction of Umax the look-ahead may plan with
    /// (e.g. 0.8); `None` for no saturation awareness. Needs PD+ on every group axis.
    pub saturation: Option<f64>,
}

impl NurbsFeed {
    /// Feed `v`, acceleration `a`, jerk `j`, the default chord tolerance (one encoder count),
    /// no saturation awareness.
    pub fn new(v: f64, a: f64, j: f64) -> Self {
        Self {
            feed: v,
            accel: a,
            jerk: j,
            chord_tolerance: None,
            saturation: None,
        }
    }
}

impl Group {
    /// Move along a NURBS curve (control points in the group's axis order and user units,
    /// absolute; the curve must start where the group's path is). The curve reaches the card in
    /// continuation entries: a begin, data entries of up to 12 values, an end; each is answered
    /// by its own ack or nack.
    pub fn move_nurbs(
        &self,
        curve: &Nurbs,
        f: &NurbsFeed,
        opts: MoveOptions,
    ) -> Result<GroupMotion> {
        let (n, axes) = self.axes_pub()?;
        if curve.dim() != n {
            return Err(Error::Refused {
                command: "move nurbs",
                target: Target::Group(self.index()),
                code: NackCode::NurbsDimension,
                reason: "the curve's dimension differs from the group's axis count",
            });
        }
        let s = self.path_scale_pub()?;
        for (what, v) in [
            ("feed", f.feed),
            ("acceleration", f.accel),
            ("jerk", f.jerk),
            ("chord tolerance", f.chord_tolerance.unwrap_or(1.0)),
        ] {
            positive(what, v)?;
        }
        // in counts: the default is one count
        let chord = f.chord_tolerance.map_or(1.0, |c| c * s);
        let budget = f.saturation.unwrap_or(0.0);
        finite("saturation budget", budget)?;
        let stream = self.nurbs_stream(curve, &axes[..n]);
        let o = Self::opts_pub(&opts);
        let begin = cmd::NurbsBegin {
            size: CurveSize {
                degree: curve.degree() as f64,
                n_ctrl: curve.n_ctrl() as f64,
                n_knots: curve.knots().len() as f64,
            },
            feed: f.feed * s,
            accel: f.accel * s,
            jerk: f.jerk * s,
            chord_tolerance: chord,
            budget,
            buffered: o.buffered,
            saturation: f.saturation.is_some(),
            feed_type: o.feed_type,
        };
        // (A NURBS move's control points are absolute: `opts.relative` is not sent.)
        self.card_pub().execute_seq(
            self.cmd(GroupCmd::NurbsBegin(begin)),
            "nurbs begin",
            Target::Group(self.index()),
        )?;
        self.send_data(&stream)?;
        let seq = self.card_pub().execute_seq(
            self.cmd(GroupCmd::NurbsEnd),
            "nurbs end",
            Target::Group(self.index()),
        )?;
        Ok(self.motion_pub(seq))
    }

    /// A curve's data stream: control points (scaled per axis to counts), weights, knots.
    pub(crate) fn nurbs_stream(&self, curve: &Nurbs, axes: &[usize]) -> Vec<f64> {
        let mut stream =
            Vec::with_capacity(curve.n_ctrl() * (axes.len() + 1) + curve.knots().len());
        for i in 0..curve.n_ctrl() {
            let p = curve.control_point(i).unwrap_or_default();
            for (j, &a) in axes.iter().enumerate() {
                stream.push(p[j] * self.card_pub().scale(a));
            }
        }
        stream.extend((0..curve.n_ctrl()).map(|i| curve.weight(i).unwrap_or(0.0)));
        stream.extend_from_slice(curve.knots());
        stream
    }

    /// Stream `values` as data entries, keeping at most 32 unanswered.
    pub(crate) fn send_data(&self, values: &[f64]) -> Result<()> {
        let card = self.card_pub();
        let mut pending = std::collections::VecDeque::new();
        let check = |seq: u32| -> Result<()> {
            match card.wait_ack(seq)? {
                Ok(()) => Ok(()),
                Err(code) => Err(Error::Nack {
                    command: "nurbs data",
                    target: Target::Group(self.index()),
                    code,
                    reason: crate::nack_reason(code),
                }),
            }
        };
        for (k, chunk) in values.chunks(NURBS_DATA_MAX).enumerate() {
            let data = cmd::NurbsData {
                offset: (k * NURBS_DATA_MAX) as u32,
                // At most NURBS_DATA_MAX values (the chunk).
                values: chunk.iter().copied().collect(),
            };
            let cmd = self.cmd(GroupCmd::NurbsData(data));
            loop {
                match card.send_raw(cmd) {
                    Ok(seq) => {
                        pending.push_back(seq);
                        break;
                    }
                    Err(e) if e.kind() == crate::ErrorKind::RingFull => match pending.pop_front() {
                        Some(seq) => check(seq)?,
                        None => return Err(e),
                    },
                    Err(e) => return Err(e),
                }
            }
            if pending.len() >= 32 {
                if let Some(seq) = pending.pop_front() {
                    check(seq)?;
                }
            }
        }
        while let Some(seq) = pending.pop_front() {
            check(seq)?;
        }
        Ok(())
    }

    /// A path longer than the card holds: queue the pieces one after another, waiting for
    /// earlier pieces to finish whenever the group's queue is full (a curve of more than
    /// [`NURBS_MAX_CTRL`] points: [`split_nurbs`] it first). Where a piece ends and the next
    /// starts with the same tangent and limits (as the pieces of a split curve do), the card
    /// runs on through the joint without stopping, as long as the next piece is queued before
    /// the motion has to start slowing down for the end of the one before; if it is not (the
    /// host fell behind), the motion stops at the end of what was queued, within its limits,
    /// and goes on when more arrives. Returns the motion of the last piece.
    pub fn move_nurbs_path(
        &self,
        pieces: &[Nurbs],
        f: &NurbsFeed,
        timeout: Duration,
    ) -> Result<GroupMotion> {
        let mut queued: std::collections::VecDeque<GroupMotion> = std::collections::VecDeque::new();
        let mut last = None;
        for piece in pieces {
            loop {
                match self.move_nurbs(piece, f, MoveOptions::buffered()) {
                    Ok(m) => {
                        queued.push_back(m.clone());
                        last = Some(m);
                        break;
                    }
                    Err(e) if e.kind() == crate::ErrorKind::QueueFull => match queued.pop_front() {
                        Some(m) => m.wait(timeout)?,
                        None => return Err(e),
                    },
                    Err(e) => return Err(e),
                }
            }
        }
        last.ok_or_else(|| Error::Unsupported("an empty NURBS path".into()))
    }
}
