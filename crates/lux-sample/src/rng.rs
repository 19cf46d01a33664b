//! A tiny deterministic random number generator for tests, examples and benchmarks.

/// SplitMix64 (Steele, Lea, Flood 2014): a 64-bit counter passed through a bijective mixer.
///
/// Statistically sound for Monte-Carlo tests and fully reproducible from its seed; it is not
/// meant for cryptography. Kept here so that tests, examples and benches share one generator
/// without a `rand` dependency.
#[derive(Clone, Debug)]
pub struct SplitMix64 {
    state: u64,
}

impl SplitMix64 {
    /// A generator seeded with `seed`.
    pub fn new(seed: u64) -> Self {
        Self { state: seed }
    }

    /// Next 64 random bits.
    #[inline]
    pub fn next_u64(&mut self) -> u64 {
        self.state = self.state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform double in \[0, 1) with 53 random bits.
    #[inline]
    pub fn next_f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// Two uniform doubles in \[0, 1).
    #[inline]
    pub fn next_2d(&mut self) -> [f64; 2] {
        [self.next_f64(), self.next_f64()]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mean_and_range() {
        let mut r = SplitMix64::new(7);
        let n = 100_000;
        let mut s = 0.0;
        for _ in 0..n {
            let x = r.next_f64();
            assert!((0.0..1.0).contains(&x));
            s += x;
        }
        // Mean of U(0,1) is 1/2 with σ = 1/sqrt(12 n) ≈ 0.0009.
        assert!((s / n as f64 - 0.5).abs() < 0.004);
    }
}
