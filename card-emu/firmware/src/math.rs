//! The floating-point functions of the firmware and its algorithms, from `libm`: the same code
//! on the card and in the emulator, so the emulator computes bit for bit what the card does.
//! (Rust's `f64` methods need `std`, and on a host call its C library, whose `sin`, `exp` or
//! `pow` may differ from the card's in the last bit.) `sqrt`, `floor`, `ceil`, `round`,
//! `trunc`, `fract`, `rem_euclid` and `powi` are exact or exactly specified, so they agree
//! with the methods of the same name wherever those exist.
//!
//! On a host (`host`, or the tests) `sqrt`, `floor`, `ceil` and `trunc` are `std`'s (the same
//! results to the bit: they are exactly rounded): the CPU's instructions inline, where
//! `libm`'s are calls into another crate (the path engine's push spent 12 % more
//! instructions with them). `round` is written out here (inline, on the card too), tested
//! against libm's to the bit: the servo loop and the DAC round on every axis every tick.
//!
//! Called as `math::sqrt(x)`, never as methods: with `std` linked anywhere in the build, a
//! method call on an `f64` would silently take `std`'s.

/// √x, correctly rounded.
#[inline]
pub fn sqrt(x: f64) -> f64 {
    #[cfg(any(test, feature = "host"))]
    return f64::sqrt(x);
    #[cfg(not(any(test, feature = "host")))]
    libm::sqrt(x)
}

/// ∛x.
#[inline]
pub fn cbrt(x: f64) -> f64 {
    libm::cbrt(x)
}

/// sin x.
#[inline]
pub fn sin(x: f64) -> f64 {
    libm::sin(x)
}

/// cos x.
#[inline]
pub fn cos(x: f64) -> f64 {
    libm::cos(x)
}

/// tan x.
#[inline]
pub fn tan(x: f64) -> f64 {
    libm::tan(x)
}

/// log₁₀ x.
#[inline]
pub fn log10(x: f64) -> f64 {
    libm::log10(x)
}

/// (sin x, cos x), as two calls.
#[inline]
pub fn sin_cos(x: f64) -> (f64, f64) {
    (libm::sin(x), libm::cos(x))
}

/// The angle of (x, y) in (−π, π], as `y.atan2(x)`.
#[inline]
pub fn atan2(y: f64, x: f64) -> f64 {
    libm::atan2(y, x)
}

/// asin x.
#[inline]
pub fn asin(x: f64) -> f64 {
    libm::asin(x)
}

/// acos x.
#[inline]
pub fn acos(x: f64) -> f64 {
    libm::acos(x)
}

/// eˣ.
#[inline]
pub fn exp(x: f64) -> f64 {
    libm::exp(x)
}

/// eˣ − 1, accurate near 0.
#[inline]
pub fn exp_m1(x: f64) -> f64 {
    libm::expm1(x)
}

/// ln x.
#[inline]
pub fn ln(x: f64) -> f64 {
    libm::log(x)
}

/// ln(1 + x), accurate near 0.
#[inline]
pub fn ln_1p(x: f64) -> f64 {
    libm::log1p(x)
}

/// xʸ.
#[inline]
pub fn powf(x: f64, y: f64) -> f64 {
    libm::pow(x, y)
}

/// √(x² + y²) without overflow or underflow.
#[inline]
pub fn hypot(x: f64, y: f64) -> f64 {
    libm::hypot(x, y)
}

/// xⁿ by repeated squaring: the multiplications `f64::powi` makes (compiler-rt's
/// `__powidf2`), so the result is the same bit for bit (firmware-proto's, which the limits of
/// the register map use).
#[inline]
pub fn powi(x: f64, n: i32) -> f64 {
    firmware_proto::powi(x, n)
}

/// The largest integer ≤ x.
#[inline]
pub fn floor(x: f64) -> f64 {
    #[cfg(any(test, feature = "host"))]
    return f64::floor(x);
    #[cfg(not(any(test, feature = "host")))]
    libm::floor(x)
}

/// The smallest integer ≥ x.
#[inline]
pub fn ceil(x: f64) -> f64 {
    #[cfg(any(test, feature = "host"))]
    return f64::ceil(x);
    #[cfg(not(any(test, feature = "host")))]
    libm::ceil(x)
}

/// The nearest integer, halves away from zero (libm's `round` to the bit, inline: the servo
/// loop and the DAC call it every tick on every axis). Below 2⁵², the integer part `t` of `x`
/// and the fraction `x − t` are exact, so comparing the fraction with ½ decides; the sign of
/// `x` is the result's (−0.3 rounds to −0). From 2⁵² up every `f64` is an integer, and
/// infinities and NaN come back as they are, as from libm.
#[inline]
pub fn round(x: f64) -> f64 {
    const TWO_52: f64 = 4_503_599_627_370_496.0;
    if x.abs() < TWO_52 {
        let t = x as i64 as f64;
        let r = if (x - t).abs() >= 0.5 {
            t + 1f64.copysign(x)
        } else {
            t
        };
        r.copysign(x)
    } else {
        x
    }
}

/// The integer part, towards zero.
#[inline]
pub fn trunc(x: f64) -> f64 {
    #[cfg(any(test, feature = "host"))]
    return f64::trunc(x);
    #[cfg(not(any(test, feature = "host")))]
    libm::trunc(x)
}

/// x − trunc(x).
#[inline]
pub fn fract(x: f64) -> f64 {
    x - libm::trunc(x)
}

/// The least non-negative remainder of x / y, as `f64::rem_euclid`.
#[inline]
pub fn rem_euclid(x: f64, y: f64) -> f64 {
    let r = x % y;
    if r < 0.0 {
        r + y.abs()
    } else {
        r
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The exact ones agree with std's methods, and powi with std's to the bit.
    #[test]
    fn the_exact_functions_agree_with_std() {
        let mut rng = crate::testkit::rng::Rng::new(0x5eed);
        for _ in 0..100_000 {
            let x = rng.uniform(-1e6, 1e6) * 10f64.powi(rng.uniform(-8.0, 8.0) as i32);
            assert_eq!(sqrt(x.abs()).to_bits(), x.abs().sqrt().to_bits());
            assert_eq!(floor(x).to_bits(), x.floor().to_bits());
            assert_eq!(ceil(x).to_bits(), x.ceil().to_bits());
            assert_eq!(round(x).to_bits(), x.round().to_bits());
            assert_eq!(trunc(x).to_bits(), x.trunc().to_bits());
            assert_eq!(fract(x).to_bits(), x.fract().to_bits());
            assert_eq!(rem_euclid(x, 6.5).to_bits(), x.rem_euclid(6.5).to_bits());
            for n in -4..=7 {
                assert_eq!(powi(x, n).to_bits(), x.powi(n).to_bits(), "{x}^{n}");
            }
        }
    }

    /// `round` is libm's (the card's) to the bit: halves, the numbers next to them, signed
    /// zeros, the edges of 2⁵² and 2⁵³, infinities, NaN, and random numbers of every size.
    #[test]
    fn round_is_libms() {
        let same = |x: f64| {
            let (a, b) = (round(x), libm::round(x));
            assert!(
                a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan()),
                "round({x:e}) = {a:e}, libm {b:e}"
            );
        };
        let edges = [
            0.0,
            0.5,
            1.5,
            2.5,
            0.49999999999999994,
            4_503_599_627_370_495.5,
            4_503_599_627_370_496.0,
            9_007_199_254_740_991.0,
            9_007_199_254_740_992.0,
            f64::MIN_POSITIVE,
            5e-324,
            f64::MAX,
            f64::INFINITY,
            f64::NAN,
        ];
        for x in edges {
            for y in [
                x,
                -x,
                f64::from_bits(x.to_bits() + 1),
                f64::from_bits(x.to_bits().saturating_sub(1)),
            ] {
                same(y);
                same(-y);
            }
        }
        for k in -2000..2000 {
            let h = k as f64 + 0.5;
            for y in [
                h,
                f64::from_bits(h.to_bits() + 1),
                f64::from_bits(h.to_bits() - 1),
            ] {
                same(y);
            }
        }
        let mut rng = crate::testkit::rng::Rng::new(0x0d0d);
        for _ in 0..200_000 {
            let x = rng.uniform(-1.0, 1.0) * 2f64.powi(rng.uniform(-60.0, 70.0) as i32);
            same(x);
        }
    }
}
