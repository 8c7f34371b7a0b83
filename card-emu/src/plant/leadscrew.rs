//! A leadscrew between the motor (where the encoder is) and the load (layout 1.9's
//! compensation is tested against it): a pitch error curve and a dead band (backlash).
//!
//! The screw turns with the motor: at motor position `m` (counts) the nut would be at
//! `u = m + e(m)`, `e` the pitch error (linear between its points, the end values held
//! outside). The load sits in a dead band of width `b` around that: `u − b/2 <= load <= u + b/2`;
//! the screw pushes it only at the band's edges. So moving forward the load is at `u − b/2`,
//! in reverse at `u + b/2`, and on a reversal the motor travels `b` before the load moves.
//! The nut starts in the middle of the band. Kinematic: the load has no dynamics of its own.

/// One axis's leadscrew.
#[derive(Debug, Clone, PartialEq)]
pub struct Leadscrew {
    /// The pitch error: (motor position, error) in counts, positions increasing.
    pub pitch_error: Vec<(f64, f64)>,
    /// The dead band's width, counts (>= 0).
    pub backlash: f64,
    load: Option<f64>,
}

impl Leadscrew {
    /// A screw with this error curve and backlash; the nut in the middle of its band.
    pub fn new(pitch_error: Vec<(f64, f64)>, backlash: f64) -> Self {
        Self {
            pitch_error,
            backlash: backlash.max(0.0),
            load: None,
        }
    }

    /// The pitch error at motor position `m`, counts.
    pub fn error_at(&self, m: f64) -> f64 {
        let e = &self.pitch_error;
        let (Some(first), Some(last)) = (e.first(), e.last()) else {
            return 0.0;
        };
        if m <= first.0 {
            return first.1;
        }
        if m >= last.0 {
            return last.1;
        }
        let i = e.partition_point(|p| p.0 <= m);
        let (a, b) = (e[i - 1], e[i]);
        a.1 + (b.1 - a.1) * (m - a.0) / (b.0 - a.0)
    }

    /// The motor moved to `m` (counts): the nut follows within its band.
    pub fn follow(&mut self, m: f64) {
        let u = m + self.error_at(m);
        let half = 0.5 * self.backlash;
        let load = self.load.unwrap_or(u);
        self.load = Some(load.clamp(u - half, u + half));
    }

    /// Where the load is, counts (before the first [`Leadscrew::follow`]: at the motor's 0).
    pub fn load(&self) -> f64 {
        self.load.unwrap_or_else(|| self.error_at(0.0))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_load_lags_by_half_the_backlash_and_carries_the_pitch_error() {
        let mut s = Leadscrew::new(vec![(0.0, 0.0), (1000.0, 8.0)], 6.0);
        s.follow(0.0);
        assert_eq!(s.load(), 0.0);
        // Forward: the band's back edge pushes it.
        for m in 0..=500 {
            s.follow(m as f64);
        }
        assert_eq!(s.load(), 500.0 + 4.0 - 3.0);
        // A reversal: the motor crosses the band (6 counts) before the load moves.
        s.follow(495.0);
        assert_eq!(s.load(), 501.0);
        s.follow(490.0);
        assert!(
            (s.load() - (490.0 + 3.92 + 3.0)).abs() < 1e-12,
            "{}",
            s.load()
        );
        // Outside the curve its end value holds.
        assert_eq!(s.error_at(-5.0), 0.0);
        assert_eq!(s.error_at(5000.0), 8.0);
    }
}
