//! Layout 1.11: the PID + feed-forward servo law and the biquad filters on an axis's servo
//! output.

use crate::card::Axis;
use crate::error::Result;
use firmware_proto::cmd::{CardCmd, ServoFilterClear, ServoFilterSet};
use firmware_proto::{layout, raw, Mem};

/// A filter's kind (`MC_BIQUAD_*`).
pub use firmware_proto::cmd::BiquadKind;
/// A filter as set: its kind and parameters (Hz, damping ratio, dB).
pub use firmware_proto::cmd::BiquadSpec;
/// Filters per axis.
pub use firmware_proto::cmd::BIQUADS;
/// The PID + feed-forward gains (`mc_axis_pidff`), volts, counts and seconds:
/// `u = kp·e + ki·∫e + kd·ė (filtered at d_filter_hz) + kvff·v_ref + kaff·a_ref +
/// friction·sgn(v_ref)` (0 while |v_ref| ≤ friction_deadband). `PidffSettings::default()` is
/// the card's default tuning; `PidffSettings::for_drive(accel_per_volt, wc)` places gains for
/// a drive.
pub use firmware_proto::AxisPidff as PidffSettings;

/// A filter an axis holds: as set, and the coefficients the card designed from it at the
/// servo rate (b0, b1, b2, a1, a2; a0 = 1).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ServoFilter {
    /// The filter as set.
    pub spec: BiquadSpec,
    /// The card's coefficients.
    pub coeffs: [f64; 5],
}

impl Axis {
    /// Switch the axis to the PID + feed-forward law with these gains (any state: at rest the
    /// switch does not step the output; gains changed while it runs keep its integrator).
    /// A gain negative, a derivative cut-off or deadband not above 0: `PidffGains`; a number
    /// not finite: `NotFinite`. Nothing changes when refused.
    pub fn configure_pidff(&self, s: &PidffSettings) -> Result<()> {
        let w = self.card().window();
        let a = self.index();
        let _guard = self.card().config_lock();
        let saved = layout::AXIS_PIDFF.at(a).read(w);
        let law_at = layout::AXIS_CONFIG
            .at(a)
            .field(core::mem::offset_of!(raw::mc_axis_config, servo_law));
        let law = w.read32(law_at);
        self.card().write_block(layout::AXIS_PIDFF.at(a), s);
        w.write32(law_at, raw::MC_SERVO_PIDFF);
        self.card().inner().traced(law_at..law_at + 4);
        let r = self.card().execute_seq(
            CardCmd::ApplyAxisConfig.command(a as u16),
            "configure PID+FF",
            crate::Target::Axis(a),
        );
        if r.is_err() {
            self.card().write_block(layout::AXIS_PIDFF.at(a), &saved);
            w.write32(law_at, law);
        }
        r.map(|_| ())
    }

    /// The PID+FF gains the axis runs, read back from the card (`None`: another law).
    pub fn pidff_settings(&self) -> Result<Option<PidffSettings>> {
        let (cfg, _, pid) = self.card().read_axis_config(self.index())?;
        Ok((cfg.servo_law == raw::MC_SERVO_PIDFF).then_some(pid))
    }

    /// Set filter `slot` (0..[`BIQUADS`]) on the servo output, e.g.
    /// `BiquadSpec::notch(24.0, 0.2, -20.0)`. Refused, nothing changed: a slot out of range
    /// (`FilterKind`), a frequency not in (0, servo rate / 2) (`FilterFreq`), a damping, depth
    /// or raw coefficient out of range (`FilterParam`), an unstable design
    /// (`FilterUnstable`), a number not finite (`NotFinite`).
    pub fn set_servo_filter(&self, slot: usize, spec: &BiquadSpec) -> Result<()> {
        let set = ServoFilterSet {
            slot: u8::try_from(slot).unwrap_or(u8::MAX),
            spec: *spec,
        };
        self.run(self.cmd(set_cmd(set)), "set_servo_filter")
            .map(|_| ())
    }

    /// Empty filter `slot` (an empty slot stays empty; out of range: `FilterKind`).
    pub fn clear_servo_filter(&self, slot: usize) -> Result<()> {
        let clear = ServoFilterClear {
            slot: u8::try_from(slot).unwrap_or(u8::MAX),
        };
        self.run(self.cmd(clear_cmd(clear)), "clear_servo_filter")
            .map(|_| ())
    }

    /// Empty every filter slot.
    pub fn clear_servo_filters(&self) -> Result<()> {
        (0..BIQUADS).try_for_each(|k| self.clear_servo_filter(k))
    }

    /// The filters the axis holds, slot by slot, as the card wrote them back.
    pub fn servo_filters(&self) -> Result<[Option<ServoFilter>; BIQUADS]> {
        let b = layout::SERVO_FILTERS
            .at(self.index())
            .read(self.card().window());
        Ok(core::array::from_fn(|k| {
            let s = &b.slot[k];
            let kind = BiquadKind::from_code(s.kind).filter(|_| b.active & (1 << k) != 0)?;
            Some(ServoFilter {
                spec: BiquadSpec {
                    kind,
                    freq_hz: s.freq_hz,
                    damping: s.damping,
                    depth_db: s.depth_db,
                    freq2_hz: s.freq2_hz,
                    coeffs: if kind == BiquadKind::Raw {
                        [s.b0, s.b1, s.b2, s.a1, s.a2]
                    } else {
                        [0.0; 5]
                    },
                },
                coeffs: [s.b0, s.b1, s.b2, s.a1, s.a2],
            })
        }))
    }
}

fn set_cmd(s: ServoFilterSet) -> firmware_proto::cmd::AxisCmd {
    firmware_proto::cmd::AxisCmd::ServoFilterSet(s)
}

fn clear_cmd(c: ServoFilterClear) -> firmware_proto::cmd::AxisCmd {
    firmware_proto::cmd::AxisCmd::ServoFilterClear(c)
}
