//! The card's 12-bit ±10 V DAC: what the servo law's output becomes on the wire to the drive.

use crate::math;

/// The 12-bit bipolar DAC: code 2048 is 0 V, one LSB is 20/4096 V, codes saturate at 0 and 4095.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Dac;

impl Dac {
    /// Volts per LSB.
    pub const LSB: f64 = 20.0 / 4096.0;

    /// The code for a requested voltage (NaN gives mid-scale).
    pub fn code(volts: f64) -> u16 {
        if volts.is_nan() {
            return 2048;
        }
        let c = math::round(volts / Self::LSB) + 2048.0;
        c.clamp(0.0, 4095.0) as u16
    }

    /// The voltage a code produces.
    pub fn volts(code: u16) -> f64 {
        (code.min(4095) as f64 - 2048.0) * Self::LSB
    }

    /// Quantise and saturate: the voltage actually produced, and whether it saturated.
    pub fn output(volts: f64) -> (f64, bool) {
        let code = Self::code(volts);
        (Self::volts(code), code == 0 || code == 4095)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dac_is_12_bit_and_saturates() {
        assert_eq!(Dac::code(0.0), 2048);
        assert_eq!(Dac::code(100.0), 4095);
        assert_eq!(Dac::code(-100.0), 0);
        assert_eq!(Dac::output(-10.0), (-10.0, true));
        let (v, sat) = Dac::output(1.0);
        assert!(!sat && (v - 1.0).abs() <= Dac::LSB / 2.0);
        assert_eq!(Dac::output(f64::NAN), (0.0, false));
    }
}
