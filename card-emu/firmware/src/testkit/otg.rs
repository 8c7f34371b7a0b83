//! The random single-axis problems of the online planner's tests and bench
//! (`motion::otg`): limits at scales over several decades, start states of eight kinds.
use super::rng::Rng;
use crate::motion::otg::OtgLimits;

/// A random single-axis problem: limits and start/target state.
#[derive(Clone, Copy, Debug)]
pub struct Case {
    pub lim: OtgLimits,
    pub p0: f64,
    pub v0: f64,
    pub a0: f64,
    pub p1: f64,
    pub v1: f64,
}

/// The kinds of start state of the comparison, in fixed proportions (one each in turn).
pub const KINDS: [&str; 8] = [
    "toward the target",
    "away from the target",
    "|v0| beyond vmax/vmin",
    "|a0| beyond amax/amin",
    "v1 != 0",
    "strongly asymmetric limits",
    "rest or near rest",
    "anything within the limits",
];

/// Limits at a random scale: lengths `L` over 5 decades, times `T` over 3, each limit a
/// factor of 0.3..3 off `L/T^k`; asymmetric (vmin, amin up to 3x off) half of the time,
/// strongly (10x) when `strong`.
fn limits(rng: &mut Rng, strong: bool) -> (OtgLimits, f64, f64) {
    let len = 10f64.powf(rng.uniform(-2.0, 3.0));
    let time = 10f64.powf(rng.uniform(-1.5, 1.5));
    let f = |rng: &mut Rng| rng.log_uniform(0.3, 3.0);
    let vmax = len / time * f(rng);
    let amax = len / (time * time) * f(rng);
    let jmax = len / (time * time * time) * f(rng);
    let (rv, ra) = if strong {
        (rng.log_uniform(0.1, 10.0), rng.log_uniform(0.1, 10.0))
    } else if rng.chance(0.5) {
        (
            rng.log_uniform(1.0 / 3.0, 3.0),
            rng.log_uniform(1.0 / 3.0, 3.0),
        )
    } else {
        (1.0, 1.0)
    };
    let lim = OtgLimits {
        vmax,
        vmin: -vmax * rv,
        amax,
        amin: -amax * ra,
        jmax,
    };
    (lim, len, time)
}

pub fn case(rng: &mut Rng, kind: usize) -> Case {
    let (lim, len, _) = limits(rng, kind == 5);
    let vin = |rng: &mut Rng| rng.uniform(lim.vmin, lim.vmax);
    let ain = |rng: &mut Rng| rng.uniform(lim.amin, lim.amax);
    let p0 = len * rng.uniform(-10.0, 10.0);
    // Distances over several decades, either sign.
    let d = len * 10f64.powf(rng.uniform(-3.0, 1.5)) * rng.sign();
    let mut c = Case {
        lim,
        p0,
        v0: vin(rng),
        a0: ain(rng),
        p1: p0 + d,
        v1: 0.0,
    };
    match kind {
        0 => {
            c.v0 = c.v0.abs().min(if d > 0.0 { lim.vmax } else { -lim.vmin }) * d.signum();
        }
        1 => {
            c.v0 = -c.v0.abs().min(if d > 0.0 { -lim.vmin } else { lim.vmax }) * d.signum();
        }
        2 => {
            c.v0 = if rng.chance(0.5) {
                lim.vmax * rng.uniform(1.0, 3.0)
            } else {
                lim.vmin * rng.uniform(1.0, 3.0)
            };
        }
        3 => {
            c.a0 = if rng.chance(0.5) {
                lim.amax * rng.uniform(1.0, 3.0)
            } else {
                lim.amin * rng.uniform(1.0, 3.0)
            };
        }
        4 => c.v1 = vin(rng),
        5 => {
            if rng.chance(0.5) {
                c.v1 = vin(rng);
            }
        }
        6 => {
            c.v0 = if rng.chance(0.5) {
                0.0
            } else {
                vin(rng) * 1e-3
            };
            c.a0 = if rng.chance(0.5) {
                0.0
            } else {
                ain(rng) * 1e-3
            };
        }
        _ => {
            if rng.chance(0.5) {
                c.v1 = vin(rng);
            }
        }
    }
    c
}
