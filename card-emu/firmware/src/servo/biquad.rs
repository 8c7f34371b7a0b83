//! Biquad filters on the servo output (layout 1.11): up to [`BIQUADS`] second-order sections in
//! series after the servo law, before the DAC clamp (the notch and lead/lag of a servo drive,
//! Kim et al. 1991's "tunable notch filter which is used to damp a critical machine vibration
//! frequency").
//!
//! Each filter is designed from a continuous prototype `H(s) = N(s)/D(s)` by the bilinear
//! transform with pre-warping (Oppenheim & Schafer, *Discrete-Time Signal Processing*, "the
//! bilinear transformation"):
//!
//! ```text
//! s = K·(1 − z⁻¹)/(1 + z⁻¹),   K = ω₀ / tan(ω₀·T/2)
//! ```
//!
//! so that the digital filter at the prototype's characteristic frequency ω₀ has exactly the
//! prototype's response there (`K = 2/T` would map ω₀ to `(2/T)·atan(ω₀T/2)`). For
//! `N = n₂s² + n₁s + n₀` (and D alike) the coefficients are `n₂K² + n₁K + n₀`,
//! `2(n₀ − n₂K²)`, `n₂K² − n₁K + n₀`, normalised by D's first. The prototypes:
//!
//! - notch: `(s² + 2ζ_z·ω·s + ω²)/(s² + 2ζ·ω·s + ω²)`, `ζ_z = ζ·10^(depth/20)`: the gain at ω
//!   is `ζ_z/ζ` (the depth), 1 at DC and at high frequency; ζ sets the width (the −3 dB band
//!   is about 2ζ·f wide for a deep notch);
//! - low-pass: `ω²/(s² + 2ζ·ω·s + ω²)`;
//! - lead/lag: `(1 + s/ω₁)/(1 + s/ω₂)`, first order: each corner pre-warped on its own
//!   (`ω_a = (2/T)·tan(ωT/2)`), then `K = 2/T` with `(1 + z⁻¹)` (not its square: that would
//!   put a pole on the unit circle at z = −1);
//! - raw: the coefficients as given.
//!
//! A filter is checked when it is set: every number finite, frequencies in (0, Nyquist), the
//! damping in (0, 10], the depth in [−120, 0] dB, and the designed poles (roots of
//! `z² + a₁z + a₂`) inside the unit circle by [`POLE_MARGIN`]; else it is refused and nothing
//! changes. Each runs in transposed direct form II; a filter set or cleared starts from the
//! steady state of its input at the time (no step at rest when its DC gain is 1).

use crate::math;
use firmware_proto::cmd::{BiquadKind, BiquadSpec, BIQUADS};
use firmware_proto::raw::{mc_biquad, mc_servo_filters, MC_BIQUAD_POLE_MARGIN};
use firmware_proto::NackCode;

/// How far inside the unit circle a filter's poles must lie.
pub const POLE_MARGIN: f64 = MC_BIQUAD_POLE_MARGIN;

/// The largest |b| a raw filter may have (`MC_BIQUAD_RAW_B_MAX`).
pub const RAW_GAIN_MAX: f64 = firmware_proto::raw::MC_BIQUAD_RAW_B_MAX;

/// A designed filter: normalised coefficients (a₀ = 1) and the state of its transposed direct
/// form II.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Biquad {
    /// b₀, b₁, b₂, a₁, a₂.
    pub c: [f64; 5],
    s1: f64,
    s2: f64,
}

fn bilinear2(n: [f64; 3], d: [f64; 3], k: f64) -> [f64; 5] {
    // n = [n2, n1, n0], d likewise.
    let k2 = k * k;
    let z = |p: [f64; 3]| {
        [
            p[0] * k2 + p[1] * k + p[2],
            2.0 * (p[2] - p[0] * k2),
            p[0] * k2 - p[1] * k + p[2],
        ]
    };
    let (nb, da) = (z(n), z(d));
    [
        nb[0] / da[0],
        nb[1] / da[0],
        nb[2] / da[0],
        da[1] / da[0],
        da[2] / da[0],
    ]
}

/// The largest modulus of the roots of `z² + a1·z + a2` (NaN when a coefficient is).
pub fn pole_radius(a1: f64, a2: f64) -> f64 {
    let disc = a1 * a1 - 4.0 * a2;
    if disc < 0.0 {
        math::sqrt(a2)
    } else {
        0.5 * (a1.abs() + math::sqrt(disc))
    }
}

/// Check `spec` and design it at `rate_hz`: the coefficients, or the nack that refuses it.
pub fn design(spec: &BiquadSpec, rate_hz: f64) -> Result<[f64; 5], NackCode> {
    let s = spec;
    let nums = [s.freq_hz, s.damping, s.depth_db, s.freq2_hz];
    if nums.iter().chain(s.coeffs.iter()).any(|x| !x.is_finite()) {
        return Err(NackCode::NotFinite);
    }
    let ts = 1.0 / rate_hz;
    let nyquist = 0.5 * rate_hz;
    let freq_ok = |f: f64| f > 0.0 && f < nyquist;
    let damping_ok = s.damping > 0.0 && s.damping <= 10.0;
    let w = 2.0 * core::f64::consts::PI * s.freq_hz;
    let c = match s.kind {
        BiquadKind::Notch | BiquadKind::LowPass => {
            if !freq_ok(s.freq_hz) {
                return Err(NackCode::FilterFreq);
            }
            if !damping_ok || (s.kind == BiquadKind::Notch && !(-120.0..=0.0).contains(&s.depth_db))
            {
                return Err(NackCode::FilterParam);
            }
            let k = w / math::tan(0.5 * w * ts);
            let d = [1.0, 2.0 * s.damping * w, w * w];
            let n = if s.kind == BiquadKind::Notch {
                let zeta_z = s.damping * math::exp(s.depth_db / 20.0 * core::f64::consts::LN_10);
                [1.0, 2.0 * zeta_z * w, w * w]
            } else {
                [0.0, 0.0, w * w]
            };
            bilinear2(n, d, k)
        }
        BiquadKind::LeadLag => {
            if !freq_ok(s.freq_hz) || !freq_ok(s.freq2_hz) {
                return Err(NackCode::FilterFreq);
            }
            let warp = |f: f64| 2.0 / ts * math::tan(core::f64::consts::PI * f * ts);
            let (w1, w2) = (warp(s.freq_hz), warp(s.freq2_hz));
            let k = 2.0 / ts;
            // (1 + s/w1)/(1 + s/w2) with s = K(1 − z⁻¹)/(1 + z⁻¹), times (1 + z⁻¹).
            let (n0, n1) = (1.0 + k / w1, 1.0 - k / w1);
            let (d0, d1) = (1.0 + k / w2, 1.0 - k / w2);
            [n0 / d0, n1 / d0, 0.0, d1 / d0, 0.0]
        }
        BiquadKind::Raw => {
            if s.coeffs[..3].iter().any(|b| b.abs() > RAW_GAIN_MAX) {
                return Err(NackCode::FilterParam);
            }
            s.coeffs
        }
    };
    if c.iter().any(|x| !x.is_finite()) {
        return Err(NackCode::FilterUnstable);
    }
    // A NaN radius is no radius within the margin: refused.
    let within = pole_radius(c[3], c[4]) <= 1.0 - POLE_MARGIN;
    if !within {
        return Err(NackCode::FilterUnstable);
    }
    Ok(c)
}

impl Biquad {
    /// A filter with coefficients `c` ([`design`]'s), at rest.
    pub fn new(c: [f64; 5]) -> Self {
        Self {
            c,
            s1: 0.0,
            s2: 0.0,
        }
    }

    /// The DC gain, `H(1)`.
    pub fn dc_gain(&self) -> f64 {
        let c = &self.c;
        (c[0] + c[1] + c[2]) / (1.0 + c[3] + c[4])
    }

    /// Put the state where a constant input `x` has held it for ever.
    pub fn settle(&mut self, x: f64) {
        let c = &self.c;
        let y = self.dc_gain() * x;
        self.s2 = c[2] * x - c[4] * y;
        self.s1 = c[1] * x - c[3] * y + self.s2;
    }

    /// One sample.
    #[inline]
    pub fn run(&mut self, x: f64) -> f64 {
        let c = &self.c;
        let y = c[0] * x + self.s1;
        self.s1 = c[1] * x - c[3] * y + self.s2;
        self.s2 = c[2] * x - c[4] * y;
        y
    }

    /// The gain (dB) and phase (rad) of the discrete transfer function at `hz`, at `rate_hz`.
    pub fn response(&self, hz: f64, rate_hz: f64) -> (f64, f64) {
        let th = 2.0 * core::f64::consts::PI * hz / rate_hz;
        let (c1, s1, c2, s2) = (
            math::cos(th),
            -math::sin(th),
            math::cos(2.0 * th),
            -math::sin(2.0 * th),
        );
        let c = &self.c;
        let (nr, ni) = (c[0] + c[1] * c1 + c[2] * c2, c[1] * s1 + c[2] * s2);
        let (dr, di) = (1.0 + c[3] * c1 + c[4] * c2, c[3] * s1 + c[4] * s2);
        let mag2 = (nr * nr + ni * ni) / (dr * dr + di * di);
        (
            10.0 * math::log10(mag2),
            math::atan2(ni, nr) - math::atan2(di, dr),
        )
    }
}

/// An axis's filter chain: the slots in order, the bit mask of those in use.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ServoFilters {
    active: u8,
    slot: [Biquad; BIQUADS],
    spec: [Option<BiquadSpec>; BIQUADS],
}

impl ServoFilters {
    /// Is any filter set? (The tick runs the chain only then.)
    #[inline]
    pub fn any(&self) -> bool {
        self.active != 0
    }

    /// The chain's output for input `x`.
    #[inline]
    pub fn run(&mut self, mut x: f64) -> f64 {
        for k in 0..BIQUADS {
            if self.active & (1 << k) != 0 {
                x = self.slot[k].run(x);
            }
        }
        x
    }

    /// Every filter's state where a constant chain input `x` has held it.
    pub fn settle(&mut self, x: f64) {
        let mut x = x;
        for k in 0..BIQUADS {
            if self.active & (1 << k) != 0 {
                self.slot[k].settle(x);
                x *= self.slot[k].dc_gain();
            }
        }
    }

    /// The input slot `k` sees at rest when the chain's input is `x`.
    fn input_of(&self, k: usize, x: f64) -> f64 {
        (0..k)
            .filter(|j| self.active & (1 << j) != 0)
            .fold(x, |x, j| x * self.slot[j].dc_gain())
    }

    /// Set slot `k` (checked: [`design`]) at `rate_hz`, its state settled for the chain input
    /// `x` (the servo law's output of the tick). Refused: nothing changes.
    pub fn set(
        &mut self,
        k: usize,
        spec: &BiquadSpec,
        rate_hz: f64,
        x: f64,
    ) -> Result<(), NackCode> {
        let c = design(spec, rate_hz)?;
        let mut f = Biquad::new(c);
        f.settle(self.input_of(k, x));
        self.slot[k] = f;
        self.spec[k] = Some(*spec);
        self.active |= 1 << k;
        Ok(())
    }

    /// Empty slot `k` (an empty one stays empty).
    pub fn clear(&mut self, k: usize) {
        self.slot[k] = Biquad::default();
        self.spec[k] = None;
        self.active &= !(1 << k);
    }

    /// The same filters designed at `rate_hz` (a servo rate change), at rest; refused when one
    /// does not pass at that rate.
    pub fn redesigned(&self, rate_hz: f64) -> Result<Self, NackCode> {
        let mut out = Self::default();
        for k in 0..BIQUADS {
            if let Some(spec) = &self.spec[k] {
                out.set(k, spec, rate_hz, 0.0)?;
            }
        }
        Ok(out)
    }

    /// Slot `k`'s filter, if set.
    pub fn filter(&self, k: usize) -> Option<(&BiquadSpec, &Biquad)> {
        self.spec[k].as_ref().map(|s| (s, &self.slot[k]))
    }

    /// The register map's read-back block (`mc_servo_filters`).
    pub fn block(&self) -> mc_servo_filters {
        let mut b = mc_servo_filters {
            active: self.active as u32,
            ..Default::default()
        };
        for k in 0..BIQUADS {
            if let Some((s, f)) = self.filter(k) {
                let c = f.c;
                b.slot[k] = mc_biquad {
                    kind: s.kind.code(),
                    freq_hz: s.freq_hz,
                    damping: s.damping,
                    depth_db: s.depth_db,
                    freq2_hz: s.freq2_hz,
                    b0: c[0],
                    b1: c[1],
                    b2: c[2],
                    a1: c[3],
                    a2: c[4],
                    ..Default::default()
                };
            }
        }
        b
    }
}

#[cfg(test)]
mod tests;
