//! Auxiliary encoders (layout 1.7): a conveyor or a handwheel wired to the card's auxiliary
//! encoder inputs, which a geared slave can follow (`firmware::gear`).
//!
//! The count is an integer; the encoder moves at `velocity` counts/s with the fraction of a
//! count kept between periods (so a conveyor at 1,000.5 counts per period counts 2,001 in two),
//! and a test can jump it by any number of counts at once.

/// One auxiliary encoder.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct AuxEncoder {
    /// Counts.
    pub count: i64,
    /// Counts per second (the conveyor's speed, the handwheel turned).
    pub velocity: f64,
    frac: f64,
}

impl AuxEncoder {
    /// Move over one period of `ts` s at the velocity.
    pub fn step(&mut self, ts: f64) {
        let d = self.frac + self.velocity * ts;
        let whole = d.floor();
        if whole.is_finite() && whole.abs() < 9.0e15 {
            self.count = self.count.wrapping_add(whole as i64);
            self.frac = d - whole;
        }
    }

    /// Jump by `counts` at once (a handwheel's detents, a test's large steps).
    pub fn jump(&mut self, counts: i64) {
        self.count = self.count.wrapping_add(counts);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fractions_are_kept() {
        let mut e = AuxEncoder {
            velocity: 1_000.5 * 1e4,
            ..Default::default()
        };
        for _ in 0..10 {
            e.step(1e-4);
        }
        assert_eq!(e.count, 10_005);
        e.velocity = -1e4;
        e.step(1e-4);
        assert_eq!(e.count, 10_004);
        e.jump(1_000_000_000);
        assert_eq!(e.count, 1_000_010_004);
    }
}
