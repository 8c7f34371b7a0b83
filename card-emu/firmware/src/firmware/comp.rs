//! Leadscrew compensation on the card (layout 1.9): each axis's table in the card's RAM, the
//! transfer that loads it (`MC_OP_COMP_TABLE`, `MC_OP_COMP_DATA`) and the read-back
//! (`MC_OP_COMP_READ`). The table's arithmetic and the ramp are `motion::comp`; the axis
//! applies them between its trajectory and its servo law (`Axis::control_into`).
//!
//! A table is loaded into a staging table and becomes the axis's only when its last point has
//! arrived and passed: any refusal leaves the table in force as it was and closes the
//! transfer. Made the first time a `MC_OP_COMP_TABLE` arrives (`Lazy`): one table of
//! [`MAX_POINTS`] points per axis plus the staging one (6 KiB each).

use crate::motion::comp::{CompError, CompParams, CompPoint, MAX_POINTS};
use crate::ram::FixedVec;
use firmware_proto::cmd::{CompData, CompHeader};
use firmware_proto::raw::{mc_comp_point, mc_comp_readback};
use firmware_proto::{NackCode, MAX_AXES};

/// The nack of a table fault.
pub fn comp_nack(e: CompError) -> NackCode {
    match e {
        CompError::Table => NackCode::CompTable,
        CompError::Sequence => NackCode::CompSequence,
        CompError::Order => NackCode::CompOrder,
        CompError::Bound => NackCode::CompBound,
        CompError::NotFinite => NackCode::NotFinite,
    }
}

/// One axis's table.
pub struct CompTable {
    /// Its settings; `None`: no compensation.
    pub params: Option<CompParams>,
    /// Its points.
    pub points: FixedVec<CompPoint, MAX_POINTS>,
}

impl CompTable {
    fn new() -> Self {
        Self {
            params: None,
            points: FixedVec::with_capacity(MAX_POINTS),
        }
    }
}

/// A table being loaded.
struct Open {
    axis: usize,
    expected: usize,
}

/// Every axis's table and the one being loaded.
pub struct CompStore {
    tables: [CompTable; MAX_AXES],
    staging: CompTable,
    open: Option<Open>,
}

impl Default for CompStore {
    fn default() -> Self {
        Self::new()
    }
}

impl CompStore {
    /// No compensation on any axis (each table's room reserved).
    pub fn new() -> Self {
        Self {
            tables: core::array::from_fn(|_| CompTable::new()),
            staging: CompTable::new(),
            open: None,
        }
    }

    /// Axis `axis`'s table and settings, if it has compensation.
    #[inline]
    pub fn table(&self, axis: usize) -> Option<(&[CompPoint], &CompParams)> {
        let t = self.tables.get(axis)?;
        t.params.as_ref().map(|p| (&t.points[..], p))
    }

    /// `MC_OP_COMP_TABLE` for `axis`: checked, then either in force at once (no points) or
    /// open for its points. Returns its settings when it took effect at once.
    pub fn begin(
        &mut self,
        axis: usize,
        h: &CompHeader,
        rate_hz: u32,
    ) -> Result<Option<CompParams>, NackCode> {
        self.open = None;
        let params = CompParams {
            bound: h.bound,
            backlash: h.backlash,
            ramp_vel: h.ramp_vel,
            ramp_acc: h.ramp_acc,
            bidir: h.bidir,
        };
        params.validate(rate_hz).map_err(comp_nack)?;
        self.staging.params = Some(params);
        self.staging.points.clear();
        if h.points == 0 {
            // No table: only the backlash, or (no backlash) compensation off.
            let t = &mut self.tables[axis];
            t.points.clear();
            t.params = (params.backlash > 0.0).then_some(params);
            return Ok(Some(params));
        }
        self.open = Some(Open {
            axis,
            expected: usize::from(h.points),
        });
        Ok(None)
    }

    /// `MC_OP_COMP_DATA` for `axis`: the points, in order. Returns the settings in force when
    /// the last point made the table the axis's.
    pub fn data(&mut self, axis: usize, d: &CompData) -> Result<Option<CompParams>, NackCode> {
        let r = self.take(axis, d);
        if r.is_err() {
            self.open = None;
        }
        r
    }

    fn take(&mut self, axis: usize, d: &CompData) -> Result<Option<CompParams>, NackCode> {
        let seq = NackCode::CompSequence;
        let open = self.open.as_ref().ok_or(seq)?;
        let (Some(params), true) = (self.staging.params, open.axis == axis) else {
            return Err(seq);
        };
        let have = self.staging.points.len();
        if usize::from(d.first) != have || have + d.points().len() > open.expected {
            return Err(seq);
        }
        for p in d.points() {
            let p = CompPoint {
                position: p.position,
                forward: p.forward,
                reverse: p.reverse,
            };
            params
                .check_point(self.staging.points.last(), &p)
                .map_err(comp_nack)?;
            self.staging.points.push(p).map_err(|_| seq)?;
        }
        if self.staging.points.len() < open.expected {
            return Ok(None);
        }
        self.open = None;
        let t = &mut self.tables[axis];
        core::mem::swap(&mut t.points, &mut self.staging.points);
        t.params = Some(params);
        Ok(Some(params))
    }

    /// Close any transfer (a refusal leaves nothing half-loaded).
    pub fn close(&mut self) {
        self.open = None;
    }

    /// Is a transfer open for `axis`?
    pub fn open_for(&self, axis: usize) -> bool {
        self.open.as_ref().is_some_and(|o| o.axis == axis)
    }

    /// `axis`'s table from point `first` on, as the read-back block.
    pub fn readback(&self, axis: usize, first: usize) -> mc_comp_readback {
        readback(self.tables.get(axis), axis, first)
    }
}

/// The read-back block of `table` (none: no compensation) from point `first` on.
pub fn readback(table: Option<&CompTable>, axis: usize, first: usize) -> mc_comp_readback {
    let mut b = mc_comp_readback {
        axis: axis as u32,
        first: first as u32,
        ..Default::default()
    };
    let Some(t) = table else {
        return b;
    };
    let Some(p) = t.params else {
        return b;
    };
    b.points = t.points.len() as u32;
    b.flags = if p.bidir {
        firmware_proto::raw::MC_COMP_BIDIR
    } else {
        0
    };
    b.bound = p.bound;
    b.backlash = p.backlash;
    b.ramp_vel = p.ramp_vel;
    b.ramp_acc = p.ramp_acc;
    let from = first.min(t.points.len());
    let mut n = 0;
    for (dst, src) in b.point.iter_mut().zip(&t.points[from..]) {
        *dst = mc_comp_point {
            position: src.position,
            forward: src.forward,
            reverse: src.reverse,
        };
        n += 1;
    }
    b.count = n;
    b
}
