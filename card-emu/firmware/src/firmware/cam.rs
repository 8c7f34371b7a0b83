//! Camming (layout 1.7): the cam tables in the card's RAM and the commands that load them
//! (`MC_OP_CAM_TABLE`, `MC_OP_CAM_DATA`), and MC_CamIn's arguments. A cammed slave runs as a
//! coupling of `gear.rs` whose law is the table (`Law::Cam`): the same catch-up, the same
//! MC_GearOut/MC_CamOut, the same halt, stop and lost-master rules; `motion::cam` evaluates the
//! tables.
//!
//! The store (`MC_CAM_TABLES` tables of up to `MC_CAM_MAX_POINTS` points, and the points of the
//! table being loaded) is made the first time a table is opened and kept for the card's life;
//! a table is built (its spline solved) in the command manager when its last point arrives,
//! and a table a slave follows cannot be reloaded.
#![forbid(unsafe_code)]

use crate::firmware::gear::{CamLaw, GearCommand, Law, Master, SyncLimits};
use crate::firmware::nack::check_ranges;
use crate::firmware::Firmware;
use crate::math;
use crate::motion::cam::{CamError, CamTable};
use firmware_proto::cmd;
use firmware_proto::{MasterSource, Mem, NackCode, CAM_MAX_POINTS, CAM_TABLES};
use heapless::Vec;

/// A table being loaded.
#[derive(Debug)]
struct Loading {
    table: usize,
    n: usize,
    cubic: bool,
    periodic: bool,
    points: Vec<(f64, f64), CAM_MAX_POINTS>,
}

/// The card's cam tables.
#[derive(Debug)]
pub struct CamStore {
    tables: [Option<CamTable>; CAM_TABLES],
    loading: Option<Loading>,
}

impl CamStore {
    fn new() -> Self {
        Self {
            tables: core::array::from_fn(|_| None),
            loading: None,
        }
    }

    /// The tables.
    pub fn tables(&self) -> &[Option<CamTable>] {
        &self.tables
    }
}

/// An integer argument in `0..n`.
fn index(x: f64, n: usize) -> Option<usize> {
    (x.is_finite() && math::fract(x) == 0.0 && x >= 0.0 && x < n as f64).then_some(x as usize)
}

impl GearCommand {
    /// Check `MC_OP_CAM_IN` for slave `slave` after decoding (which found every argument
    /// finite, the master source known and its number an integer of its range; the table is
    /// checked when it runs).
    pub fn cam(
        ci: &cmd::CamIn,
        slave: usize,
        num_axes: usize,
        rate_hz: u32,
    ) -> Result<Self, NackCode> {
        let source = ci.master.source;
        let master = ci.master.index as usize;
        if source != MasterSource::Aux && master >= num_axes {
            return Err(NackCode::SyncMaster);
        }
        if source != MasterSource::Aux && master == slave {
            return Err(NackCode::SyncMaster);
        }
        let table = index(ci.table, CAM_TABLES).ok_or(NackCode::CamTable)?;
        let big = firmware_proto::MAX_POSITION;
        if ci.master_offset.abs() > big || ci.slave_offset.abs() > big {
            return Err(NackCode::OutOfRange);
        }
        let scale_ok = |x: f64| x.is_normal() && x.abs() <= 1e9 && x.abs() >= 1e-9;
        if !scale_ok(ci.master_scale) || !scale_ok(ci.slave_scale) {
            return Err(NackCode::OutOfRange);
        }
        let lim = SyncLimits {
            vmax: ci.limits.vmax,
            amax: ci.limits.amax,
            jerk: ci.limits.jerk,
        };
        check_ranges(rate_hz, &[(1, lim.vmax), (2, lim.amax), (3, lim.jerk)])?;
        Ok(Self {
            master: Master {
                source,
                index: master,
            },
            law: Law::Cam(CamLaw {
                table,
                m_off: ci.master_offset,
                s_off: ci.slave_offset,
                m_scale: ci.master_scale,
                s_scale: ci.slave_scale,
            }),
            lim,
            sync_at: None,
        })
    }
}

impl<M: Mem + Clone> Firmware<M> {
    /// The cam tables (empty until the first is opened).
    pub(super) fn cam_tables(&self) -> &[Option<CamTable>] {
        self.cams.as_ref().map_or(&[], |c| c.tables())
    }

    /// A loaded cam table (for inspection by tests).
    pub fn cam_table(&self, t: usize) -> Option<&CamTable> {
        self.cam_tables().get(t)?.as_ref()
    }

    /// `MC_OP_CAM_TABLE`: open table `t.table` for its points (its other faults were found by
    /// decoding); a table a slave follows cannot be reloaded.
    pub(super) fn cam_table_open(&mut self, t: &cmd::CamTable) -> Result<f64, NackCode> {
        let (table, n, cubic) = (t.table as usize, t.points as usize, t.cubic);
        if self.gears.iter().any(|g| g.cam_table() == Some(table)) {
            return Err(NackCode::CamTable);
        }
        let store = self.cams.get_or_insert_with(CamStore::new);
        store.tables[table] = None;
        let mut l = store.loading.take().unwrap_or(Loading {
            table,
            n,
            cubic,
            periodic: false,
            points: Vec::new(),
        });
        l.points.clear();
        (l.table, l.n, l.cubic, l.periodic) = (table, n, cubic, t.periodic);
        store.loading = Some(l);
        Ok(0.0)
    }

    /// `MC_OP_CAM_DATA`: the next points of the table being loaded, in order; the last builds
    /// it. A fault decoding found (every argument finite, then the table, the count, the first
    /// index) is the card's answer where it always was: a NaN before anything, the others
    /// after the table being loaded is looked for.
    pub(super) fn cam_data(
        &mut self,
        d: Result<&cmd::CamData, cmd::DecodeError>,
    ) -> Result<f64, NackCode> {
        if let Err(e) = d {
            if e.fault == cmd::Fault::NotFinite {
                return Err(e.nack);
            }
        }
        let store = self.cams.as_mut().ok_or(NackCode::CamSequence)?;
        let l = store.loading.as_mut().ok_or(NackCode::CamSequence)?;
        let d = d.map_err(|e| e.nack)?;
        if d.table as usize != l.table || d.first as usize != l.points.len() {
            return Err(NackCode::CamSequence);
        }
        if l.points.len() + d.points.len() > l.n {
            return Err(NackCode::CamSequence);
        }
        for p in &d.points {
            let _ = l.points.push(*p); // n <= capacity
        }
        if l.points.len() < l.n {
            return Ok((l.n - l.points.len()) as f64);
        }
        let built = CamTable::new(&l.points, l.cubic, l.periodic);
        let table = l.table;
        store.loading = None;
        match built {
            Ok(t) => {
                store.tables[table] = Some(t);
                Ok(0.0)
            }
            Err(CamError::NotFinite) => Err(NackCode::NotFinite),
            Err(_) => Err(NackCode::CamTable),
        }
    }
}
