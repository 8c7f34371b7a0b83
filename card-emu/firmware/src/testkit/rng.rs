//! One seeded generator for the tests' random inputs (xorshift64): the same numbers on every
//! machine, no crate needed.

/// A seeded xorshift64 generator.
#[derive(Debug, Clone)]
pub struct Rng(u64);

impl Rng {
    /// Seeded. The seed is mixed first (the SplitMix64 finaliser), so that small seeds do not
    /// start xorshift on a run of small numbers; a state of 0 (which xorshift never leaves)
    /// becomes 1.
    pub fn new(seed: u64) -> Self {
        let mut z = seed.wrapping_add(0x9E37_79B9_7F4A_7C15);
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        Self((z ^ (z >> 31)).max(1))
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }

    /// Uniform in [0, 1).
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in [lo, hi).
    pub fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }

    /// Log-uniform in [lo, hi) (both > 0).
    pub fn log_uniform(&mut self, lo: f64, hi: f64) -> f64 {
        self.uniform(lo.ln(), hi.ln()).exp()
    }

    /// Uniform integer in [lo, hi] (both included; lo <= hi).
    pub fn int(&mut self, lo: usize, hi: usize) -> usize {
        lo + (self.next_u64() % (hi - lo + 1) as u64) as usize
    }

    /// True with probability `p`.
    pub fn chance(&mut self, p: f64) -> bool {
        self.unit() < p
    }

    /// +1 or -1, even odds.
    pub fn sign(&mut self) -> f64 {
        if self.chance(0.5) {
            1.0
        } else {
            -1.0
        }
    }

    /// A closure of [`Rng::unit`], for code that wants `FnMut() -> f64`.
    pub fn units(mut self) -> impl FnMut() -> f64 {
        move || self.unit()
    }
}

#[cfg(test)]
mod tests {
    use super::Rng;

    #[test]
    fn same_seed_same_numbers_small_seeds_start_mixed() {
        let a: Vec<u64> = (0..4)
            .scan(Rng::new(7), |r, _| Some(r.next_u64()))
            .collect();
        let b: Vec<u64> = (0..4)
            .scan(Rng::new(7), |r, _| Some(r.next_u64()))
            .collect();
        assert_eq!(a, b);
        for seed in 0..64 {
            let mut r = Rng::new(seed);
            let u = r.unit();
            assert!((0.0..1.0).contains(&u));
            // xorshift from a raw small state gives numbers below 2^40 for several steps
            assert!(r.next_u64() > 1 << 40, "seed {seed}");
        }
        let mut r = Rng::new(1);
        let n = 10_000;
        let heads = (0..n).filter(|_| r.chance(0.5)).count();
        assert!((4_700..5_300).contains(&heads), "{heads}");
        assert!((0..1000).all(|_| (3..=9).contains(&r.int(3, 9))));
    }
}
