//! Deterministic pseudo-random numbers for the unit tests of the formulations: the same cases
//! on every run, and no dependency.

/// A 64-bit linear congruential generator (Knuth's MMIX constants), uniform in [0, 1).
pub(crate) struct Lcg(pub(crate) u64);

impl Lcg {
    /// The next number in [0, 1), from the top 53 bits of the state.
    pub(crate) fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }

    /// A number uniform in [lo, hi).
    pub(crate) fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next()
    }

    /// An index uniform in 0..n (n ≥ 1).
    pub(crate) fn below(&mut self, n: usize) -> usize {
        ((self.next() * n as f64) as usize).min(n - 1)
    }
}
