//! The PD+ servo law of Yeh & Sun 2008 (eq 2.12) and the first-order drive model it is tuned
//! for (eq 2.1–2.2 as corrected in the papers' README): `dw/dt = −w/τ + (K_c/τ)·u`,
//! `dθ/dt = K_e·w`. The saturation-aware feed (`motion::saturation`) predicts the law's
//! output with the same model.
//!
//! Units: positions in encoder counts, time in seconds; the drive output `u` in drive units
//! (volts on the card). [`PdPlus::update`] and [`DriveModel::step`] allocate nothing and never
//! panic.

use crate::math;
use core::fmt;

/// Why a PD+ law or its drive model is refused.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ModelError {
    /// Sample time not finite or not in (0, 1] s.
    BadSampleTime,
    /// A PD+ gain is negative / not finite, or all of them vanish (axis index).
    BadGain { axis: usize },
    /// A drive-model constant (K_c, τ, K_e) is not finite and > 0 (axis index).
    BadPlant { axis: usize },
    /// Umax not finite and > 0 (axis index).
    BadUmax { axis: usize },
}

impl fmt::Display for ModelError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Self::BadSampleTime => write!(f, "sample time must be finite and in (0, 1] s"),
            Self::BadGain { axis } => write!(f, "axis {axis}: bad PD+ gains"),
            Self::BadPlant { axis } => write!(f, "axis {axis}: bad drive-model constants"),
            Self::BadUmax { axis } => write!(f, "axis {axis}: Umax must be finite and > 0"),
        }
    }
}

impl core::error::Error for ModelError {}

fn pos_finite(x: f64) -> bool {
    x.is_finite() && x > 0.0
}

/// First-order motor model of Yeh eq 2.1–2.2 as corrected in the README:
/// `dw/dt = -w/τ + (K_c/τ)·u`, `dθ/dt = K_e·w` (w in rad/s, θ in counts, u in DU): the register
/// map's `mc_drive_model` (`kc` (rad/s)/DU, `tau` s, `ke` counts/rad; 1591.5494 = 10000/2π
/// for a 10000-count encoder). Its methods are in [`DriveModelExt`].
pub use firmware_proto::DriveModel;
/// PD+ gains in counts/seconds form (Yeh eq 2.12),
/// `u = kp·(θ_d-θ) + kd·(θ̇_d-θ̇) + kv·θ̇_d + ka·θ̈_d`: the register map's `mc_pdplus_gains`
/// (`kp` = Table 1 K_p, DU per count; `kd` = Table 1 K_d / K_e, since eq 2.12 applies K_d to w
/// in rad/s; `kv` = 1/(K_c K_e), eq 2.12's term w_d/K_c; `ka` = τ/(K_c K_e), its term
/// τ ẇ_d/K_c). Its methods are in [`PdPlusGainsExt`].
pub use firmware_proto::PdPlusGains;

/// What the drive model computes.
pub trait DriveModelExt {
    /// Checks that all constants are finite and > 0 (`axis` only labels the error).
    fn validate(&self, axis: usize) -> Result<(), ModelError>;
    /// Steady-state axis speed per drive unit, (counts/s)/DU = K_c·K_e.
    fn counts_gain(&self) -> f64;
    /// One sample of the plant with `u` held (zero-order hold), exact solution of eq 2.2
    /// written in counts: with `v = K_e·w` (counts/s), `dv/dt = -v/τ + (K_c K_e/τ)·u`,
    /// `dθ/dt = v`. Returns `(θ, v)` one sample `ts` later.
    fn step(&self, ts: f64, theta: f64, vel: f64, u: f64) -> (f64, f64);
}

impl DriveModelExt for DriveModel {
    fn validate(&self, axis: usize) -> Result<(), ModelError> {
        if pos_finite(self.kc) && pos_finite(self.tau) && pos_finite(self.ke) {
            Ok(())
        } else {
            Err(ModelError::BadPlant { axis })
        }
    }

    fn counts_gain(&self) -> f64 {
        self.kc * self.ke
    }

    fn step(&self, ts: f64, theta: f64, vel: f64, u: f64) -> (f64, f64) {
        let g = self.counts_gain();
        let a = math::exp(-ts / self.tau);
        let one_m_a = -math::exp_m1(-ts / self.tau); // 1 - a, accurate for small ts/τ
        let vel_next = a * vel + one_m_a * g * u;
        let theta_next = theta + self.tau * one_m_a * vel + g * u * (ts - self.tau * one_m_a);
        (theta_next, vel_next)
    }
}

/// What the PD+ gains compute.
pub trait PdPlusGainsExt: Sized {
    /// Gains from the paper's form: eq 2.12 `u = K_d(w_d-w) + K_p(θ_d-θ) + (τ/K_c)ẇ_d + w_d/K_c`
    /// with w = θ̇/K_e in rad/s, converted to counts.
    fn from_paper(k_p: f64, k_d: f64, plant: &DriveModel) -> Self;
    /// Checks finiteness and non-negativity; `axis` labels the error.
    fn validate(&self, axis: usize) -> Result<(), ModelError>;
    /// `k_p' + k_d + k_v + k_a` of Yeh eq 3.5 (the README's corrected denominator of eq 3.6),
    /// with `k_p' = kp·Ts` and the discrete `k_a = ka/Ts` (eq 3.4's `τ/(K_c T_s)`).
    fn drive_coefficient(&self, ts: f64) -> f64;
}

impl PdPlusGainsExt for PdPlusGains {
    fn from_paper(k_p: f64, k_d: f64, plant: &DriveModel) -> Self {
        let g = plant.counts_gain();
        Self {
            kp: k_p,
            kd: k_d / plant.ke,
            kv: 1.0 / g,
            ka: plant.tau / g,
        }
    }

    fn validate(&self, axis: usize) -> Result<(), ModelError> {
        let all = [self.kp, self.kd, self.kv, self.ka];
        if all.iter().all(|g| g.is_finite() && *g >= 0.0) && all.iter().any(|g| *g > 0.0) {
            Ok(())
        } else {
            Err(ModelError::BadGain { axis })
        }
    }

    fn drive_coefficient(&self, ts: f64) -> f64 {
        self.kp * ts + self.kd + self.kv + self.ka / ts
    }
}

/// The PD+ servo law of Yeh eq 2.12 at sample time `ts`; the measured speed is the backward
/// difference of the measured position (§3.2, `w_a[k] ≈ (θ_a[k]-θ_a[k-1])/T_s`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PdPlus {
    gains: PdPlusGains,
    ts: f64,
    prev_meas: f64,
    primed: bool,
    fault: bool,
    terms: super::ffpiv::ServoTerms,
}

impl PdPlus {
    /// New controller; the first `update` takes its measured speed as zero.
    pub fn new(gains: PdPlusGains, ts: f64) -> Result<Self, ModelError> {
        gains.validate(0)?;
        if !(pos_finite(ts) && ts <= 1.0) {
            return Err(ModelError::BadSampleTime);
        }
        Ok(Self {
            gains,
            ts,
            prev_meas: 0.0,
            primed: false,
            fault: false,
            terms: Default::default(),
        })
    }

    /// The measured position's frame moved by `delta` (MC_SetPosition, homing): the previous
    /// measurement moves with it, so the measured speed does not see the shift.
    pub fn shift(&mut self, delta: f64) {
        self.prev_meas += delta;
    }

    /// Sets the previous measurement (measured speed zero at the next update).
    pub fn reset(&mut self, meas_pos: f64) {
        self.prev_meas = meas_pos;
        self.primed = meas_pos.is_finite();
        self.fault = false;
    }

    /// Gains in use.
    pub fn gains(&self) -> PdPlusGains {
        self.gains
    }

    /// The terms of the last output (Yeh eq 2.12's, in DU).
    pub fn terms(&self) -> super::ffpiv::ServoTerms {
        self.terms
    }

    /// True after an update saw a non-finite input or produced a non-finite output
    /// (that update returned 0). Cleared by `reset`.
    pub fn fault(&self) -> bool {
        self.fault
    }

    /// Yeh eq 2.12 / 3.3: `u = kp(θ_d-θ_a) + kd(w_d-w_a) + kv·w_d + ka·α_d`, with
    /// `w_a = (θ_a[k]-θ_a[k-1])/Ts`. Counts, counts/s, counts/s² in; DU out.
    pub fn update(&mut self, ref_pos: f64, ref_vel: f64, ref_acc: f64, meas_pos: f64) -> f64 {
        if !meas_pos.is_finite() {
            self.fault = true;
            return 0.0;
        }
        let w_a = if self.primed {
            (meas_pos - self.prev_meas) / self.ts
        } else {
            0.0
        };
        self.prev_meas = meas_pos;
        self.primed = true;
        let g = &self.gains;
        let u =
            g.kp * (ref_pos - meas_pos) + g.kd * (ref_vel - w_a) + g.kv * ref_vel + g.ka * ref_acc;
        self.terms = super::ffpiv::ServoTerms {
            p: g.kp * (ref_pos - meas_pos),
            i: 0.0,
            d: g.kd * (ref_vel - w_a),
            ff: g.kv * ref_vel + g.ka * ref_acc,
        };
        if u.is_finite() {
            u
        } else {
            self.fault = true;
            0.0
        }
    }
}

/// One axis for the saturation predictor: PD+ gains, plant, and the drive limit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AxisModel {
    pub gains: PdPlusGains,
    pub plant: DriveModel,
    /// Drive limit Umax, DU (|u_a| ≤ Umax).
    pub umax: f64,
}

impl AxisModel {
    pub fn validate(&self, axis: usize) -> Result<(), ModelError> {
        self.gains.validate(axis)?;
        self.plant.validate(axis)?;
        if !pos_finite(self.umax) {
            return Err(ModelError::BadUmax { axis });
        }
        Ok(())
    }
}
