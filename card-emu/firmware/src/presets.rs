//! The papers' parameter sets, as named presets.
//!
//! The two-axis die bonder of Yeh & Sun 2008 (Table 1), with its drive models and PD+ gains,
//! and a path like its Fig 5.

use crate::motion::nurbs::{clamped_uniform_knots, Nurbs};
use crate::servo::pdplus::{AxisModel, DriveModel, PdPlusGains, PdPlusGainsExt};
use alloc::vec::Vec;

/// Two-axis die bonder of Yeh Table 1 (X, Y) at Ts = 1 ms.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DieBonderPreset {
    /// Sample time, s (the paper's 1 ms).
    pub ts: f64,
    /// X then Y.
    pub axes: [AxisModel; 2],
}

/// Yeh Table 1 in one consistent unit set:
///
/// * position θ: encoder counts (10 000 counts/rev); time: s; axis speed: counts/s;
///   acceleration: counts/s²; 1 count/ms = 1 pulse/ms of Fig 6 = 1000 counts/s.
/// * plant (eq 2.2 corrected): `dw/dt = -w/τ + (K_c/τ)u`, `dθ/dt = K_e·w` with w in rad/s,
///   τ in s (X 0.31, Y 0.135), K_e = 1591.5494 counts/rad = 10000/2π, K_c in (rad/s)/DU
///   (X 2506.17, Y 3156.23). The drive unit DU is defined by the plant: 1 DU held gives a
///   steady motor speed of K_c rad/s = K_c·K_e counts/s (X 3.989e6, Y 5.023e6 counts/s).
/// * PD+ (eq 2.12): `u = K_p(θ_d-θ) + K_d(w_d-w) + (τ/K_c)ẇ_d + w_d/K_c` with K_p in DU/count
///   (X 0.0136, Y 0.00577) and K_d in DU/(rad/s) (X 0.03, Y 0.028), i.e. in counts:
///   kp = K_p, kd = K_d/K_e, kv = 1/(K_c K_e), ka = τ/(K_c K_e). With this reading the
///   continuous loop `s² + (1/τ + K_c K_d/τ)s + K_c K_p K_e/τ` has ωn = 418 rad/s, ζ = 0.29
///   (X) and ωn = 463 rad/s, ζ = 0.71 (Y) — the Y value is the textbook pole-placement
///   choice, which supports this unit reading.
/// * Umax = 1 DU on both axes: the paper gives no number; 1 DU is a choice (with it X can
///   hold about 1.2e7 counts/s² of feed-forward acceleration, Y about 3.6e7).
pub fn die_bonder_preset() -> DieBonderPreset {
    die_bonder_in_du()
}

/// The die bonder in the card's units: volts instead of drive units, 1 DU = 10 V (the DAC's
/// full scale), so gains ×10, K_c ÷10 and Umax = 10 V; positions in counts, time in s.
pub fn die_bonder_volts() -> DieBonderPreset {
    let mut p = die_bonder_in_du();
    for a in p.axes.iter_mut() {
        a.gains.kp *= 10.0;
        a.gains.kd *= 10.0;
        a.gains.kv *= 10.0;
        a.gains.ka *= 10.0;
        a.plant.kc /= 10.0;
        a.umax *= 10.0;
    }
    p
}

fn die_bonder_in_du() -> DieBonderPreset {
    let x_plant = DriveModel {
        kc: 2506.17,
        tau: 0.31,
        ke: 1591.5494,
    };
    let y_plant = DriveModel {
        kc: 3156.23,
        tau: 0.135,
        ke: 1591.5494,
    };
    DieBonderPreset {
        ts: 1e-3,
        axes: [
            AxisModel {
                gains: PdPlusGains::from_paper(0.0136, 0.03, &x_plant),
                plant: x_plant,
                umax: 1.0,
            },
            AxisModel {
                gains: PdPlusGains::from_paper(0.00577, 0.028, &y_plant),
                plant: y_plant,
                umax: 1.0,
            },
        ],
    }
}

/// A die-bonder path with two sharp corners like Yeh Fig 5: up 20,000 counts, across 60,000,
/// down 20,000, as a cubic B-spline whose corners have a 600-count control-point radius.
pub fn die_bonder_path() -> Nurbs {
    let (h, w, r) = (20_000.0, 60_000.0, 600.0);
    let pts: [[f64; 2]; 15] = [
        [0.0, 0.0],
        [0.0, 6_000.0],
        [0.0, 13_000.0],
        [0.0, h - r],
        [0.0, h],
        [r, h],
        [15_000.0, h],
        [30_000.0, h],
        [45_000.0, h],
        [w - r, h],
        [w, h],
        [w, h - r],
        [w, 13_000.0],
        [w, 6_000.0],
        [w, 0.0],
    ];
    let ctrl: Vec<f64> = pts.iter().flatten().copied().collect();
    let knots = clamped_uniform_knots(15, 3).expect("15 > 3");
    Nurbs::new(3, 2, &ctrl, &[1.0; 15], &knots).expect("a valid curve")
}
