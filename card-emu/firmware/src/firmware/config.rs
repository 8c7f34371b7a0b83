//! Layout 1.8: the configuration read back, and the checks of the configuration blocks.
//!
//! `MC_OP_READ_CONFIG` (args: a [`ConfigKind`], an index) makes the card encode the settings it
//! holds, its validated and applied copy, into the configuration block of that kind and index
//! before its ack; the host reads the block after the ack. So the card writes a host's
//! configuration blocks only at boot (the reset values) and while it serves a read-back of
//! that block. Reading back changes nothing the card runs with.
//!
//! `MC_OP_SET_SCALE` keeps an axis's scale (counts per user unit) for hosts: the card does not
//! use it, it only gives it back (`mc_axis_config.scale`), so that a host opening the card, or
//! a configuration file saved from it, finds the units the machine was set up in.
//!
//! The checks of the blocks are plain functions of a block ([`validate_axis_config`],
//! [`validate_group_config`], [`decode_axis_filter`], and beside their own types
//! `FilterConfig::validate`, `HomingConfig::validate`, `IoConfig::validate`,
//! `AxisSafetyConfig::validate_on_card`, `SafetyConfig::validate`,
//! `group::path::validate_path_config`): the card runs them on apply, and a host checks a
//! configuration file with the same functions before it applies anything.

use super::axis::AxisConfig;
use super::group::{FilterConfig, GroupConfig, HomeOrder};
use super::Firmware;
use crate::servo::pdplus::{AxisModel, DriveModelExt, PdPlusGainsExt};
use crate::servo::pidff::{self, PidffGains};
use firmware_proto::cmd::ReadConfig;
use firmware_proto::{layout, raw, AxisPdPlus, AxisPidff, ConfigKind, Mem, NackCode, MAX_AXES};
use firmware_proto::{MAX_GROUPS, SCALE_RANGE};

impl<M: Mem + Clone> Firmware<M> {
    /// `MC_OP_READ_CONFIG`: write the settings the card holds into the block asked for
    /// (decoding checked the kind and the index are integers, the kind one of the card's).
    pub(super) fn read_config(&mut self, r: &ReadConfig) -> Result<(), NackCode> {
        let (kind, i) = (r.kind, r.index as usize);
        if kind.per_axis() && i >= self.num_axes {
            return Err(NackCode::BadAxis);
        }
        if kind.per_group() && i >= MAX_GROUPS {
            return Err(NackCode::BadGroup);
        }
        let m = &self.mem;
        match kind {
            ConfigKind::Card => layout::CARD_CONFIG.write(
                m,
                &raw::mc_card_config {
                    servo_rate_hz: self.servo_rate_hz,
                    ..Default::default()
                },
            ),
            ConfigKind::Axis => {
                let cfg = &self.axes[i].config;
                let block = firmware_proto::AxisConfig {
                    scale: self.scales[i],
                    modulo: self.axes[i].modulo(),
                    _reserved0: 0,
                    ..cfg.block
                };
                layout::AXIS_CONFIG.at(i).write(m, &block);
                layout::AXIS_PDPLUS
                    .at(i)
                    .write(m, &pdplus_block(cfg.pdplus.as_ref()));
                layout::AXIS_PIDFF
                    .at(i)
                    .write(m, &pidff_block(cfg.pidff.as_ref()));
            }
            ConfigKind::AxisFilter => layout::AXIS_FILTER
                .at(i)
                .write(m, &self.filters[i].config.to_block()),
            ConfigKind::Group => layout::GROUP_CONFIG
                .at(i)
                .write(m, &group_config_block(self.groups[i].config.as_ref())),
            ConfigKind::Safety => layout::SAFETY_CONFIG.write(m, &self.safety.config().to_block()),
            ConfigKind::AxisSafety => layout::AXIS_SAFETY
                .at(i)
                .write(m, &self.axes[i].safety.config.to_block()),
            ConfigKind::AxisHoming => {
                let block = raw::mc_axis_homing {
                    _reserved: [0.0; 5],
                    ..self.homing[i].config().block
                };
                layout::AXIS_HOMING.at(i).write(m, &block);
            }
            ConfigKind::GroupPath => {
                let block = raw::mc_group_path {
                    _reserved: [0.0; 5],
                    ..*self.groups[i].path_config()
                };
                layout::GROUP_PATH.at(i).write(m, &block);
            }
            ConfigKind::Io => layout::IO_CONFIG.write(m, &self.io.config().to_block()),
        }
        Ok(())
    }

    /// `MC_OP_SET_SCALE` on axis `axis`: keep its scale `s` for hosts (any state; nothing
    /// else changes).
    pub(super) fn set_scale(&mut self, axis: u16, s: f64) -> Result<(), NackCode> {
        let a = axis as usize;
        if a >= self.num_axes {
            return Err(NackCode::BadAxis);
        }
        if !s.is_finite() {
            return Err(NackCode::NotFinite);
        }
        if !SCALE_RANGE.contains(&s.abs()) {
            return Err(NackCode::OutOfRange);
        }
        self.scales[a] = s;
        Ok(())
    }
}

/// The PD+ block of an axis's PD+ law (all zero without one: the axis runs FFPIV).
pub fn pdplus_block(m: Option<&AxisModel>) -> AxisPdPlus {
    match m {
        Some(m) => AxisPdPlus {
            gains: m.gains,
            drive: m.plant,
            umax: m.umax,
            _reserved: [0.0; 8],
        },
        None => AxisPdPlus {
            gains: Default::default(),
            drive: Default::default(),
            umax: 0.0,
            _reserved: [0.0; 8],
        },
    }
}

/// The PID+FF block of an axis's PID+FF law (all zero without one).
pub fn pidff_block(g: Option<&PidffGains>) -> AxisPidff {
    match g {
        Some(g) => AxisPidff {
            _reserved: [0.0; 8],
            ..*g
        },
        None => AxisPidff {
            kp: 0.0,
            ki: 0.0,
            kd: 0.0,
            kvff: 0.0,
            kaff: 0.0,
            friction: 0.0,
            friction_deadband: 0.0,
            d_filter_hz: 0.0,
            _reserved: [0.0; 8],
        },
    }
}

/// The `group_config` block of a group's configuration (`naxes` 0: not configured).
pub fn group_config_block(cfg: Option<&GroupConfig>) -> raw::mc_group_config {
    let Some(c) = cfg else {
        return raw::mc_group_config::default();
    };
    let mut axes = [0u8; 8];
    for (b, &a) in axes.iter_mut().zip(&c.axes[..c.naxes]) {
        *b = a as u8;
    }
    let mut accdec = 0;
    if c.pre {
        accdec |= raw::MC_ACCDEC_PRE;
    }
    if c.post {
        accdec |= raw::MC_ACCDEC_POST;
    }
    raw::mc_group_config {
        naxes: c.naxes as u32,
        axes,
        accdec,
        interpolator: if c.reference_word {
            raw::MC_INTERP_REFERENCE_WORD
        } else {
            raw::MC_INTERP_EXACT
        },
        tolerance: c.tolerance,
        home_stages: c.home.n as u32,
        home_order: c.home.masks,
        ..Default::default()
    }
}

/// Check an axis configuration block, with the PD+ block of its axis when its servo law is
/// PD+ (`NotFinite`, `BadConfig`) or its PID+FF block when it is PID+FF (`NotFinite`,
/// `PidffGains`). The scale is not the card's business
/// (`MC_OP_SET_SCALE`).
pub fn validate_axis_config(
    block: &firmware_proto::AxisConfig,
    pdplus: &AxisPdPlus,
    pidff: &AxisPidff,
) -> Result<AxisConfig, NackCode> {
    let (pdplus, pidff) = match block.servo_law {
        raw::MC_SERVO_FFPIV => (None, None),
        raw::MC_SERVO_PDPLUS => (Some(validate_pdplus(pdplus)?), None),
        raw::MC_SERVO_PIDFF => {
            if !pidff::all_finite(pidff) {
                return Err(NackCode::NotFinite);
            }
            if !pidff::gains_valid(pidff) {
                return Err(NackCode::PidffGains);
            }
            (None, Some(*pidff))
        }
        _ => return Err(NackCode::BadConfig),
    };
    let cfg = AxisConfig {
        block: *block,
        pdplus,
        pidff,
    };
    cfg.validate()?;
    if cfg.pdplus.is_some_and(|p| p.umax > cfg.dac_limit_v) {
        return Err(NackCode::BadConfig);
    }
    Ok(cfg)
}

/// Check the PD+ gains and drive model of an axis (Yeh eq 2.12, 2.2).
fn validate_pdplus(b: &AxisPdPlus) -> Result<AxisModel, NackCode> {
    let (g, d) = (&b.gains, &b.drive);
    let v = [g.kp, g.kd, g.kv, g.ka, d.kc, d.tau, d.ke, b.umax];
    if v.iter().any(|x| !x.is_finite()) {
        return Err(NackCode::NotFinite);
    }
    let model = AxisModel {
        gains: b.gains,
        plant: b.drive,
        umax: b.umax,
    };
    model.gains.validate(0).map_err(|_| NackCode::BadConfig)?;
    model.plant.validate(0).map_err(|_| NackCode::BadConfig)?;
    if model.umax <= 0.0 {
        return Err(NackCode::BadConfig);
    }
    Ok(model)
}

/// Check a group configuration block on a card of `num_axes` axes.
pub fn validate_group_config(
    block: &raw::mc_group_config,
    num_axes: usize,
) -> Result<GroupConfig, NackCode> {
    let naxes = block.naxes as usize;
    if naxes == 0 || naxes > MAX_AXES {
        return Err(NackCode::BadConfig);
    }
    let mut axes = [0usize; MAX_AXES];
    for (i, b) in block.axes.iter().take(naxes).enumerate() {
        let a = *b as usize;
        if a >= num_axes {
            return Err(NackCode::BadAxis);
        }
        if axes[..i].contains(&a) {
            return Err(NackCode::BadConfig);
        }
        axes[i] = a;
    }
    let (accdec, interp, tolerance) = (block.accdec, block.interpolator, block.tolerance);
    if accdec == 0
        || accdec & !(raw::MC_ACCDEC_PRE | raw::MC_ACCDEC_POST) != 0
        || interp > raw::MC_INTERP_REFERENCE_WORD
        || !(tolerance.is_finite() && tolerance > 0.0)
    {
        return Err(NackCode::BadConfig);
    }
    let reference_word = interp == raw::MC_INTERP_REFERENCE_WORD;
    let (pre, post) = (
        accdec & raw::MC_ACCDEC_PRE != 0,
        accdec & raw::MC_ACCDEC_POST != 0,
    );
    if reference_word && pre {
        // Kim's interpolator steps a constant angle: its acc/dec must come after it.
        return Err(NackCode::IncompatibleMode);
    }
    // Layout 1.11: the home order, checked as MC_OP_GROUP_HOME's.
    let masks = block.home_order.map(f64::from);
    let home = HomeOrder::check(f64::from(block.home_stages), &masks, naxes)?;
    Ok(GroupConfig {
        naxes,
        axes,
        pre,
        post,
        reference_word,
        tolerance,
        home,
    })
}

/// Decode an axis filter block (its time constants are checked by `FilterConfig::validate`
/// at the servo rate).
pub fn decode_axis_filter(block: &raw::mc_axis_filter) -> Result<FilterConfig, NackCode> {
    let mut cfg = FilterConfig::default();
    for f in 0..3 {
        cfg.kind[f] = FilterConfig::kind_from_raw(block.kind[f]).ok_or(NackCode::BadConfig)?;
        cfg.tau[f] = block.tau[f];
        if !cfg.tau[f].is_finite() {
            return Err(NackCode::NotFinite);
        }
    }
    Ok(cfg)
}

#[cfg(test)]
mod tests {
    use super::*;
    use firmware_proto::mem::HeapWindow;
    use firmware_proto::{Command, Opcode};
    use std::sync::Arc;

    type Fw = Firmware<Arc<HeapWindow>>;

    /// A card with a host in command (its session attached: the applies need one).
    fn boot() -> (Arc<HeapWindow>, Fw) {
        let w = Arc::new(HeapWindow::new());
        let mut fw = Firmware::boot(w.clone(), 2, 10_000);
        let mut attach = Command::new(Opcode::HostAttach, 0);
        attach.flags = 1;
        assert_eq!(fw.execute(&attach), Ok(0.0));
        (w, fw)
    }

    fn run(fw: &mut Fw, op: Opcode, target: u16, args: &[f64]) -> Result<f64, NackCode> {
        fw.execute(&Command::new(op, target).with_args(args))
    }

    fn read(fw: &mut Fw, kind: ConfigKind, i: usize) -> Result<f64, NackCode> {
        run(fw, Opcode::ReadConfig, 0, &[kind as u32 as f64, i as f64])
    }

    /// The read-back is the card's applied copy: what a host wrote afterwards, or wrote and
    /// the card refused, does not come back.
    #[test]
    fn read_back_gives_what_the_card_holds_not_what_the_host_wrote() {
        let (w, mut fw) = boot();
        let at = layout::AXIS_CONFIG.at(1);
        let mut b = at.read(&w);
        assert_eq!(b.scale, 1.0, "boot");
        b.ffpiv.kp = 321.0;
        b.scale = 7.0; // ignored by the apply
        at.write(&w, &b);
        run(&mut fw, Opcode::ApplyAxisConfig, 1, &[]).unwrap();
        run(&mut fw, Opcode::SetScale, 1, &[-2.5]).unwrap();
        // The host overwrites the block, and has a bad one refused.
        b.ffpiv.kp = 999.0;
        b.dac_limit_v = 11.0;
        at.write(&w, &b);
        assert_eq!(
            run(&mut fw, Opcode::ApplyAxisConfig, 1, &[]),
            Err(NackCode::BadConfig)
        );
        read(&mut fw, ConfigKind::Axis, 1).unwrap();
        let back = at.read(&w);
        assert_eq!(back.ffpiv.kp, 321.0);
        assert_eq!(back.dac_limit_v, 10.0);
        assert_eq!(back.scale, -2.5);
        let pd = layout::AXIS_PDPLUS.at(1).read(&w);
        assert_eq!((pd.gains.kp, pd.umax), (0.0, 0.0), "FFPIV: no PD+ block");
        // Axis 0 is untouched.
        read(&mut fw, ConfigKind::Axis, 0).unwrap();
        let a0 = layout::AXIS_CONFIG.at(0).read(&w);
        assert_eq!(a0, firmware_proto::AxisConfig::default());

        // Card-wide: the safety block and the servo rate.
        let mut s = layout::SAFETY_CONFIG.read(&w);
        s.max_stop_time_us = 3_000_000;
        layout::SAFETY_CONFIG.write(&w, &s);
        run(&mut fw, Opcode::ApplySafetyConfig, 0, &[]).unwrap();
        s.max_stop_time_us = 1; // refused on apply, never held
        s.watchdog_timeout_us = 5;
        layout::SAFETY_CONFIG.write(&w, &s);
        read(&mut fw, ConfigKind::Safety, 0).unwrap();
        let back = layout::SAFETY_CONFIG.read(&w);
        assert_eq!(back.max_stop_time_us, 3_000_000);
        assert_eq!(back.watchdog_timeout_us, 100_000);
        layout::CARD_CONFIG.write(&w, &raw::mc_card_config::default());
        read(&mut fw, ConfigKind::Card, 0).unwrap();
        assert_eq!(layout::CARD_CONFIG.read(&w).servo_rate_hz, 10_000);
    }

    #[test]
    fn a_group_reads_back_configured_or_not() {
        let (w, mut fw) = boot();
        read(&mut fw, ConfigKind::Group, 3).unwrap();
        assert_eq!(
            layout::GROUP_CONFIG.at(3).read(&w).naxes,
            0,
            "not configured"
        );
        let block = raw::mc_group_config {
            naxes: 2,
            axes: [1, 0, 0, 0, 0, 0, 0, 0],
            accdec: raw::MC_ACCDEC_POST,
            interpolator: raw::MC_INTERP_REFERENCE_WORD,
            tolerance: 0.5,
            ..Default::default()
        };
        layout::GROUP_CONFIG.at(2).write(&w, &block);
        run(&mut fw, Opcode::GroupConfigure, 2, &[]).unwrap();
        layout::GROUP_CONFIG
            .at(2)
            .write(&w, &raw::mc_group_config::default());
        read(&mut fw, ConfigKind::Group, 2).unwrap();
        assert_eq!(layout::GROUP_CONFIG.at(2).read(&w), block);
        assert_eq!(
            validate_group_config(&block, 2).map(|c| group_config_block(Some(&c))),
            Ok(block),
            "the block and the check are each other's inverse"
        );
    }

    #[test]
    fn unknown_kinds_indices_and_scales_are_refused() {
        let (_w, mut fw) = boot();
        for args in [
            [0.0, 0.0],
            [10.0, 0.0],
            [2.5, 0.0],
            [f64::NAN, 0.0],
            [2.0, 0.5],
        ] {
            assert_eq!(
                run(&mut fw, Opcode::ReadConfig, 0, &args),
                Err(NackCode::ConfigKind),
                "{args:?}"
            );
        }
        assert_eq!(read(&mut fw, ConfigKind::Axis, 2), Err(NackCode::BadAxis));
        assert_eq!(
            read(&mut fw, ConfigKind::AxisHoming, 9),
            Err(NackCode::BadAxis)
        );
        assert_eq!(
            read(&mut fw, ConfigKind::GroupPath, 4),
            Err(NackCode::BadGroup)
        );
        assert_eq!(read(&mut fw, ConfigKind::Io, 0), Ok(0.0));
        for (s, e) in [
            (0.0, NackCode::OutOfRange),
            (1e-10, NackCode::OutOfRange),
            (-2e12, NackCode::OutOfRange),
            (f64::NAN, NackCode::NotFinite),
            (f64::INFINITY, NackCode::NotFinite),
        ] {
            assert_eq!(run(&mut fw, Opcode::SetScale, 0, &[s]), Err(e), "{s}");
        }
        assert_eq!(
            run(&mut fw, Opcode::SetScale, 2, &[1.0]),
            Err(NackCode::BadAxis)
        );
        assert_eq!(run(&mut fw, Opcode::SetScale, 0, &[1e12]), Ok(0.0));
    }

    /// Layout 1.10: `MC_OP_SET_MODULO` sets the period (rounded to 1/65536 count), read back in
    /// `axis_config.modulo`; 0 makes the axis linear; every refusal has its nack and changes
    /// nothing; a moving axis refuses it.
    #[test]
    fn modulo_is_checked_set_and_read_back() {
        let (w, mut fw) = boot();
        let at = layout::AXIS_CONFIG.at(1);
        assert_eq!(
            run(&mut fw, Opcode::SetModulo, 1, &[360_000.0]),
            Ok(360_000.0)
        );
        // 1/3 of a count is held to 1/65536.
        let third: f64 = 1000.0 + 1.0 / 3.0;
        let held = (third * 65536.0).round() / 65536.0;
        assert_eq!(run(&mut fw, Opcode::SetModulo, 0, &[third]), Ok(held));
        for (m, e) in [
            (-360.0, NackCode::ModuloRange),
            (0.5, NackCode::ModuloRange),
            (2e11, NackCode::ModuloRange),
            (f64::NAN, NackCode::NotFinite),
            (f64::INFINITY, NackCode::NotFinite),
        ] {
            assert_eq!(run(&mut fw, Opcode::SetModulo, 1, &[m]), Err(e), "{m}");
        }
        assert_eq!(
            run(&mut fw, Opcode::SetModulo, 2, &[360.0]),
            Err(NackCode::BadAxis)
        );
        read(&mut fw, ConfigKind::Axis, 1).unwrap();
        assert_eq!(
            at.read(&w).modulo,
            360_000.0,
            "the refusals changed nothing"
        );
        read(&mut fw, ConfigKind::Axis, 0).unwrap();
        assert_eq!(layout::AXIS_CONFIG.at(0).read(&w).modulo, held);
        // Moving: refused, unchanged.
        run(&mut fw, Opcode::PowerOn, 1, &[]).unwrap();
        run(&mut fw, Opcode::MoveVelocity, 1, &[1000.0, 1e5, 1e5, 1e7]).unwrap();
        assert_eq!(
            run(&mut fw, Opcode::SetModulo, 1, &[720.0]),
            Err(NackCode::ModuloBusy)
        );
        assert_eq!(
            run(&mut fw, Opcode::SetModulo, 1, &[0.0]),
            Err(NackCode::ModuloBusy)
        );
        read(&mut fw, ConfigKind::Axis, 1).unwrap();
        assert_eq!(at.read(&w).modulo, 360_000.0);
        // A linear axis takes no direction; a modulo one no target outside its turn.
        let mut mv = Command::new(Opcode::MoveAbsolute, 0)
            .with_args(&[10.0, 1e4, 1e5, 1e5, 1e7, 1e7, 1e7, 1e7]);
        mv.flags = raw::MC_MOVE_DIR_POSITIVE << raw::MC_MOVE_DIR_SHIFT;
        run(&mut fw, Opcode::SetModulo, 0, &[0.0]).unwrap();
        run(&mut fw, Opcode::PowerOn, 0, &[]).unwrap();
        assert_eq!(fw.execute(&mv), Err(NackCode::ModuloMove));
        run(&mut fw, Opcode::SetModulo, 0, &[5.0]).unwrap();
        mv.args[0] = 5.0;
        assert_eq!(fw.execute(&mv), Err(NackCode::ModuloMove));
        mv.args[0] = 4.5;
        assert_eq!(fw.execute(&mv), Ok(0.0));
    }
}
