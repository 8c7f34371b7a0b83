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
use firmware_proto::{
    Command, MasterSource, Mem, NackCode, Opcode, AUX_ENCODERS, CAM_AT_CYCLE_END, CAM_CUBIC,
    CAM_DATA_MAX, CAM_MAX_POINTS, CAM_PERIODIC, CAM_RELATIVE, CAM_TABLES,
};
use heapless::Vec;

// The pairs of a data entry fit in a command.
const _: () = assert!(3 + 2 * CAM_DATA_MAX <= firmware_proto::CMD_ARGS);

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
    /// Decode and check `MC_OP_CAM_IN` for slave `slave` (the table is checked when it runs).
    pub fn decode_cam(
        args: &[f64],
        flags: u32,
        slave: usize,
        num_axes: usize,
        rate_hz: u32,
    ) -> Result<Self, NackCode> {
        let a = &args[..9];
        if a.iter().any(|x| !x.is_finite()) {
            return Err(NackCode::NotFinite);
        }
        let source = MasterSource::from_raw(flags & !(CAM_AT_CYCLE_END | CAM_RELATIVE))
            .ok_or(NackCode::SyncMaster)?;
        let count = match source {
            MasterSource::Aux => AUX_ENCODERS,
            _ => num_axes,
        };
        let master = index(a[0], count).ok_or(NackCode::SyncMaster)?;
        if source != MasterSource::Aux && master == slave {
            return Err(NackCode::SyncMaster);
        }
        let table = index(a[1], CAM_TABLES).ok_or(NackCode::CamTable)?;
        let big = firmware_proto::MAX_POSITION;
        if a[2].abs() > big || a[3].abs() > big {
            return Err(NackCode::OutOfRange);
        }
        let scale_ok = |x: f64| x.is_normal() && x.abs() <= 1e9 && x.abs() >= 1e-9;
        if !scale_ok(a[4]) || !scale_ok(a[5]) {
            return Err(NackCode::OutOfRange);
        }
        let lim = SyncLimits {
            vmax: a[6],
            amax: a[7],
            jerk: a[8],
        };
        check_ranges(rate_hz, &[(1, lim.vmax), (2, lim.amax), (3, lim.jerk)])?;
        Ok(Self {
            master: Master {
                source,
                index: master,
            },
            law: Law::Cam(CamLaw {
                table,
                m_off: a[2],
                s_off: a[3],
                m_scale: a[4],
                s_scale: a[5],
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

    /// `MC_OP_CAM_TABLE` and `MC_OP_CAM_DATA`.
    pub(super) fn execute_cam_table(&mut self, c: &Command, op: Opcode) -> Result<f64, NackCode> {
        let a = &c.args;
        if op == Opcode::CamTable {
            if a[..2].iter().any(|x| !x.is_finite()) {
                return Err(NackCode::NotFinite);
            }
            let table = index(a[0], CAM_TABLES).ok_or(NackCode::CamTable)?;
            let cubic = c.flags & CAM_CUBIC != 0;
            let min = if cubic { 3 } else { 2 };
            let n = index(a[1], CAM_MAX_POINTS + 1)
                .filter(|&n| n >= min)
                .ok_or(NackCode::CamTable)?;
            if c.flags & !(CAM_CUBIC | CAM_PERIODIC) != 0 {
                return Err(NackCode::CamTable);
            }
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
            (l.table, l.n, l.cubic, l.periodic) = (table, n, cubic, c.flags & CAM_PERIODIC != 0);
            store.loading = Some(l);
            return Ok(0.0);
        }
        // MC_OP_CAM_DATA: table, first index, count, then pairs.
        if a.iter().any(|x| !x.is_finite()) {
            return Err(NackCode::NotFinite);
        }
        let store = self.cams.as_mut().ok_or(NackCode::CamSequence)?;
        let l = store.loading.as_mut().ok_or(NackCode::CamSequence)?;
        let table = index(a[0], CAM_TABLES).ok_or(NackCode::CamTable)?;
        let count = index(a[2], CAM_DATA_MAX + 1)
            .filter(|&k| k >= 1)
            .ok_or(NackCode::CamSequence)?;
        if table != l.table || index(a[1], CAM_MAX_POINTS) != Some(l.points.len()) {
            return Err(NackCode::CamSequence);
        }
        if l.points.len() + count > l.n {
            return Err(NackCode::CamSequence);
        }
        for k in 0..count {
            let _ = l.points.push((a[3 + 2 * k], a[4 + 2 * k])); // n <= capacity
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
