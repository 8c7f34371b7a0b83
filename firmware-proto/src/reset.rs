//! The blocks the host configures, under the names the firmware and the SDK use, and their
//! reset values: what the card loads into them at boot.
//!
//! The fields themselves are listed once, in the header (and so in the bindings); a new field
//! is one edit there plus its reset value here (the compiler asks for it) plus its use.

use crate::raw;

/// An axis's servo configuration (`mc_axis_config`): the servo law, the FFPIV gains, the DAC
/// clamp and the in-position windows.
pub type AxisConfig = raw::mc_axis_config;
/// The FFPIV gains and the velocity estimator's cut-off (`mc_ffpiv_gains`, Thinh Fig 5).
pub type FfpivGains = raw::mc_ffpiv_gains;
/// An axis's PD+ law and drive model (`mc_axis_pdplus`): read with its `mc_axis_config` when
/// the servo law is PD+.
pub type AxisPdPlus = raw::mc_axis_pdplus;
/// The PD+ gains (`mc_pdplus_gains`, Yeh eq 2.12), counts and seconds.
pub type PdPlusGains = raw::mc_pdplus_gains;
/// An axis's PID + feed-forward gains (`mc_axis_pidff`, layout 1.11): read with its
/// `mc_axis_config` when the servo law is PID+FF.
pub type AxisPidff = raw::mc_axis_pidff;
/// The first-order drive model (`mc_drive_model`, Yeh eq 2.1–2.2 as corrected).
pub type DriveModel = raw::mc_drive_model;
/// An axis's homing configuration (`mc_axis_homing`, layout 1.5): the CiA 402 method, its
/// velocities and limits, the home offset and the bounds that make a homing fail.
pub type AxisHoming = raw::mc_axis_homing;
/// A group's continuous-path configuration (`mc_group_path`): look-ahead, low-water mark,
/// tangential limits and every group axis's limits.
pub type GroupPath = raw::mc_group_path;
/// A group's path dimensions (`mc_group_dims`, layout 1.14): a path across cards, its axes
/// each this group's or another card's, with their limits and the others' starts.
pub type GroupDims = raw::mc_group_dims;

/// The acceleration per volt of the card's default drive and motor (the emulator's
/// `MotorParams::default_servo`: 3 Nm/10 V on 5e-4 kg·m², 10,000 counts/rev), counts/s² per V.
pub const DEFAULT_ACCEL_PER_VOLT: f64 = 0.3 * 10_000.0 / (5e-4 * core::f64::consts::TAU);

/// The velocity-loop bandwidth of the default tuning, rad/s (60 Hz).
pub const DEFAULT_BANDWIDTH: f64 = 2.0 * core::f64::consts::PI * 60.0;

impl FfpivGains {
    /// Gains placed from the plant: velocity-loop crossover `wc` (rad/s), K_P = wc/4,
    /// K_I = wc/6, full velocity feed-forward, ideal acceleration feed-forward.
    pub fn for_drive(accel_per_volt: f64, wc: f64) -> Self {
        Self {
            kp: wc / 4.0,
            ki: wc / 6.0,
            kv: wc / accel_per_volt,
            kvff: 1.0,
            kaff: 1.0 / accel_per_volt,
            vel_filter_hz: 1500.0,
        }
    }
}

impl AxisPidff {
    /// Gains placed from the plant, a pure inertia of `accel_per_volt` (counts/s² per V), at
    /// crossover `wc` (rad/s), the same placement as [`FfpivGains::for_drive`]: the derivative
    /// alone crosses at `wc` (kd = wc/A), the proportional's zero at wc/4 (kp = wc²/(4A)), the
    /// integral's at wc/10 below it (ki = kp·wc/10); the ideal acceleration feed-forward
    /// (kaff = 1/A), no velocity or friction feed-forward (an inertia has neither); the
    /// derivative filtered at 1,500 Hz, the friction deadband 100 counts/s.
    pub fn for_drive(accel_per_volt: f64, wc: f64) -> Self {
        let kp = wc * wc / (4.0 * accel_per_volt);
        Self {
            kp,
            ki: kp * wc / 10.0,
            kd: wc / accel_per_volt,
            kvff: 0.0,
            kaff: 1.0 / accel_per_volt,
            friction: 0.0,
            friction_deadband: 100.0,
            d_filter_hz: 1500.0,
            _reserved: [0.0; 8],
        }
    }
}

/// The default PID+FF tuning: for the default drive and motor at [`DEFAULT_BANDWIDTH`].
impl Default for AxisPidff {
    fn default() -> Self {
        Self::for_drive(DEFAULT_ACCEL_PER_VOLT, DEFAULT_BANDWIDTH)
    }
}

/// The default tuning: for the default drive and motor ([`DEFAULT_ACCEL_PER_VOLT`]) at
/// [`DEFAULT_BANDWIDTH`].
impl Default for FfpivGains {
    fn default() -> Self {
        Self::for_drive(DEFAULT_ACCEL_PER_VOLT, DEFAULT_BANDWIDTH)
    }
}

/// For the default motor (10,000 counts/rev, an index pulse per revolution): method 37 (the
/// current position: homing with no switch), search at 20,000 counts/s (2 rev/s), creep at
/// 1,000 counts/s (0.1 count per tick at 10 kHz), 200,000 counts/s² and 2·10⁷ counts/s³, no
/// home offset; fail after 60 s, beyond 10⁶ counts (100 revolutions) from the start, or without
/// an index within 12,000 counts (1.2 revolutions); a hard stop is a following error of 200
/// counts held 20 ms; the encoder has an index, and the axis ends at the home point.
impl Default for AxisHoming {
    fn default() -> Self {
        Self {
            method: 37,
            flags: raw::MC_HOMING_INDEX | raw::MC_HOMING_MOVE_TO_HOME,
            search_vel: 20_000.0,
            creep_vel: 1_000.0,
            accel: 200_000.0,
            jerk: 2e7,
            home_offset: 0.0,
            timeout: 60.0,
            max_distance: 1e6,
            index_distance: 12_000.0,
            hard_stop_ferror: 200.0,
            hard_stop_dwell: 0.02,
            _reserved: [0.0; 5],
        }
    }
}

/// Look ahead over 256 segments, no low-water event, tangential limits from the axes, the
/// planner's default period (1 ms), and for every axis of the default motor 100,000 counts/s
/// (10 rev/s), 10⁶ counts/s² and 10⁸ counts/s³.
impl Default for GroupPath {
    fn default() -> Self {
        Self {
            lookahead: 256,
            low_water: 0,
            accel: 0.0,
            jerk: 0.0,
            vmax: [1e5; 8],
            amax: [1e6; 8],
            jmax: [1e8; 8],
            plan_period: 0.0,
            _reserved: [0.0; 5],
        }
    }
}

/// FFPIV with the default tuning, the full ±10 V, one count and 2000 counts/s in-position
/// windows held 2 ms; jog at up to 50,000 counts/s (5 rev/s of the default motor) at
/// 500,000 counts/s² and 5e7 counts/s³.
impl Default for AxisConfig {
    fn default() -> Self {
        Self {
            servo_law: raw::MC_SERVO_FFPIV,
            _reserved0: 0,
            ffpiv: FfpivGains::default(),
            dac_limit_v: 10.0,
            in_pos_window: 1.0,
            in_vel_window: 2000.0,
            settle_time: 0.002,
            jog_max_vel: 50_000.0,
            jog_accel: 500_000.0,
            jog_jerk: 5e7,
            scale: 1.0,
            modulo: 0.0,
        }
    }
}
