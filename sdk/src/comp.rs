//! Layout 1.9: leadscrew pitch-error and backlash compensation, per axis, run by the card.
//!
//! A [`Compensation`] is a table of points (position, forward correction, reverse correction)
//! in the axis's **user units**, positions strictly increasing, plus a backlash, a bound on the
//! corrections, and the limits of the ramp that takes up every jump of the correction (a
//! reversal, a table loaded or cleared). The card interpolates it linearly (outside the table
//! the end point's correction holds), adds `±backlash/2` by direction, and drives the motor to
//! `commanded + correction` so that the load is at the commanded position; the axis's actual
//! position is the load's (the encoder's less the correction), and [`Status`](crate::Status)
//! has the motor's reference as `compensated_position`. The table is used while the axis is
//! homed ([`MotionFlags::HOMED`](crate::MotionFlags), also set by a set position) and not
//! homing. `card_firmware::motion::comp` and the header (`MC_OP_COMP_TABLE`) have the rules.
//!
//! The SDK checks a table as the card does before it sends any of it (the same error kinds);
//! the card refuses a change on an axis that is not at rest (`CompBusy`). A refused table
//! changes nothing on the card.

use crate::card::Axis;
use crate::error::{nack_reason, Error, Result, Target};
use card_firmware::host::{comp_nack, CompError, CompParams, CompPoint as CardPoint};
use firmware_proto::cmd::{AxisCmd, CompData, CompHeader, CompPointArgs, CompRead};
use firmware_proto::cmd::{COMP_DATA_MAX, COMP_MAX_POINTS, COMP_READ_MAX};
use firmware_proto::layout;

/// One point of a compensation table, user units.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct CompPoint {
    /// Position.
    pub position: f64,
    /// Correction added moving forward (and at rest after a forward motion).
    pub forward: f64,
    /// Correction added moving in reverse (equal to `forward` unless the table is
    /// bidirectional).
    pub reverse: f64,
}

impl CompPoint {
    /// A point whose correction is the same both ways.
    pub fn new(position: f64, correction: f64) -> Self {
        Self {
            position,
            forward: correction,
            reverse: correction,
        }
    }
}

/// An axis's pitch-error and backlash compensation, user units and seconds.
#[derive(Debug, Clone, PartialEq)]
pub struct Compensation {
    /// The points, positions strictly increasing (at most [`COMP_MAX_POINTS`]; none: only
    /// the backlash).
    pub points: Vec<CompPoint>,
    /// The points give a correction per direction (else `reverse` must equal `forward`).
    pub bidirectional: bool,
    /// Backlash (>= 0): `+backlash/2` moving forward, `-backlash/2` in reverse.
    pub backlash: f64,
    /// The largest |correction ± backlash/2| allowed (> 0).
    pub bound: f64,
    /// The ramp's velocity (> 0).
    pub ramp_velocity: f64,
    /// The ramp's acceleration (> 0).
    pub ramp_acceleration: f64,
}

/// Most points of a table.
pub const COMP_POINTS_MAX: usize = COMP_MAX_POINTS;

fn refused(code: firmware_proto::NackCode, target: Target) -> Error {
    Error::Refused {
        command: "set_compensation",
        target,
        code,
        reason: nack_reason(code),
    }
}

impl Compensation {
    /// The table in counts for an axis of `scale` counts per unit (a negative scale reverses
    /// the points and swaps the columns: the axis's forward is the encoder's reverse).
    fn to_counts(&self, scale: f64) -> (CompParams, Vec<CardPoint>) {
        let k = scale.abs();
        let params = CompParams {
            bound: self.bound * k,
            backlash: self.backlash * k,
            ramp_vel: self.ramp_velocity * k,
            ramp_acc: self.ramp_acceleration * k,
            bidir: self.bidirectional,
        };
        let mut pts: Vec<CardPoint> = self
            .points
            .iter()
            .map(|p| {
                let (f, r) = if scale < 0.0 {
                    (p.reverse, p.forward)
                } else {
                    (p.forward, p.reverse)
                };
                CardPoint {
                    position: p.position * scale,
                    forward: f * scale,
                    reverse: r * scale,
                }
            })
            .collect();
        if scale < 0.0 {
            pts.reverse();
        }
        (params, pts)
    }

    /// The card's checks of this table on an axis of `scale` counts per unit at `rate` Hz:
    /// the refusal it would give.
    pub(crate) fn nack(
        &self,
        scale: f64,
        rate: u32,
    ) -> std::result::Result<(), firmware_proto::NackCode> {
        let (params, pts) = self.to_counts(scale);
        params.check_table(&pts, rate).map_err(comp_nack)
    }

    fn from_counts(params: &CompParams, pts: &[CardPoint], scale: f64) -> Self {
        let k = scale.abs();
        let mut points: Vec<CompPoint> = pts
            .iter()
            .map(|p| {
                let (f, r) = if scale < 0.0 {
                    (p.reverse, p.forward)
                } else {
                    (p.forward, p.reverse)
                };
                CompPoint {
                    position: p.position / scale,
                    forward: f / scale,
                    reverse: r / scale,
                }
            })
            .collect();
        if scale < 0.0 {
            points.reverse();
        }
        Self {
            points,
            bidirectional: params.bidir,
            backlash: params.backlash / k,
            bound: params.bound / k,
            ramp_velocity: params.ramp_vel / k,
            ramp_acceleration: params.ramp_acc / k,
        }
    }
}

impl Axis {
    /// Load `comp` as this axis's compensation (layout 1.9). Checked first as the card checks
    /// it: `CompTable` (more than [`COMP_POINTS_MAX`] points, a bound, backlash or ramp limit
    /// out of range), `CompOrder` (positions not strictly increasing), `CompBound` (a
    /// correction beyond the bound), `NotFinite`; then sent, four points a command; the card
    /// refuses it on an axis that is not at rest (`CompBusy`). The table in force changes
    /// only once the last point is in, and the jump is ramped.
    pub fn set_compensation(&self, comp: &Compensation) -> Result<()> {
        let target = Target::Axis(self.index());
        let rate = self.card().info().servo_rate_hz;
        let (params, pts) = comp.to_counts(self.scale());
        params.check_table(&pts, rate).map_err(|e| match e {
            CompError::NotFinite => Error::NotFinite {
                what: "compensation",
                value: f64::NAN,
            },
            e => refused(comp_nack(e), target),
        })?;
        if pts.is_empty() && params.backlash == 0.0 {
            // Nothing to compensate: the same as clearing it (with these ramp limits).
            return self.send_comp_header(&params, 0);
        }
        self.send_comp(&params, &pts)
    }

    /// Switch this axis's compensation off (its correction ramps out at the default ramp:
    /// 1000 counts/s, 10⁶ counts/s²). `CompBusy` if the axis is not at rest.
    pub fn clear_compensation(&self) -> Result<()> {
        self.send_comp_header(&CompParams::default(), 0)
    }

    fn send_comp_header(&self, params: &CompParams, points: usize) -> Result<()> {
        let h = CompHeader {
            points: points as u16,
            bound: params.bound,
            backlash: params.backlash,
            ramp_vel: params.ramp_vel,
            ramp_acc: params.ramp_acc,
            bidir: params.bidir,
        };
        self.run(self.cmd(AxisCmd::CompTable(h)), "set_compensation")
            .map(|_| ())
    }

    fn send_comp(&self, params: &CompParams, pts: &[CardPoint]) -> Result<()> {
        let _g = self.card().config_lock();
        self.send_comp_header(params, pts.len())?;
        for (k, chunk) in pts.chunks(COMP_DATA_MAX).enumerate() {
            let args: Vec<CompPointArgs> = chunk
                .iter()
                .map(|p| CompPointArgs {
                    position: p.position,
                    forward: p.forward,
                    reverse: p.reverse,
                })
                .collect();
            let d = CompData::new((k * COMP_DATA_MAX) as u16, &args);
            self.run(self.cmd(AxisCmd::CompData(d)), "set_compensation")?;
        }
        Ok(())
    }

    /// The compensation the card holds for this axis, read back (user units); `None`: none.
    pub fn compensation(&self) -> Result<Option<Compensation>> {
        let _g = self.card().config_lock();
        let mut pts = Vec::new();
        let mut first = 0usize;
        loop {
            let r = CompRead {
                first: first as u16,
            };
            self.run(self.cmd(AxisCmd::CompRead(r)), "compensation")?;
            let b = layout::COMP_READBACK.read(self.card().window());
            let params = CompParams {
                bound: b.bound,
                backlash: b.backlash,
                ramp_vel: b.ramp_vel,
                ramp_acc: b.ramp_acc,
                bidir: b.flags & firmware_proto::raw::MC_COMP_BIDIR != 0,
            };
            if b.bound == 0.0 {
                return Ok(None);
            }
            let total = (b.points as usize).min(COMP_MAX_POINTS);
            let n = (b.count as usize).min(COMP_READ_MAX);
            pts.extend(b.point[..n].iter().map(|p| CardPoint {
                position: p.position,
                forward: p.forward,
                reverse: p.reverse,
            }));
            first += n;
            if first >= total || n == 0 {
                return Ok(Some(Compensation::from_counts(&params, &pts, self.scale())));
            }
        }
    }
}
