//! A tiny deterministic random number generator for tests, examples and benchmarks, and a
//! counter-based read of its stream for renderers that need numbers by index.

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

    /// The counter's increment γ = ⌊2⁶⁴/φ⌋ (odd, so the counter visits every state).
    const GAMMA: u64 = 0x9E37_79B9_7F4A_7C15;

    /// Next 64 random bits: `mix(state += γ)`.
    #[inline]
    pub fn next_u64(&mut self) -> u64 {
        self.state = self.state.wrapping_add(Self::GAMMA);
        Self::mix(self.state)
    }

    /// Element `index` (from 0) of the stream seeded with `seed`, without stepping through the
    /// ones before it: `mix(seed + (index + 1)·γ)`, what the `index + 1`-th [`next_u64`] of
    /// `SplitMix64::new(seed)` returns. A pure function of its counters, for numbers drawn by
    /// (stream, index) in any order.
    ///
    /// [`next_u64`]: SplitMix64::next_u64
    #[inline(always)]
    pub fn at(seed: u64, index: u64) -> u64 {
        Self::mix(seed.wrapping_add(index.wrapping_add(1).wrapping_mul(Self::GAMMA)))
    }

    /// The output mixer (Stafford's variant 13 of MurmurHash3's finaliser), a bijection.
    #[inline(always)]
    fn mix(mut z: u64) -> u64 {
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

    /// `at(seed, i)` is the stream's element `i`, for seeds that wrap the counter too.
    #[test]
    fn at_reads_the_stream() {
        for seed in [0u64, 7, u64::MAX - 3, 0x1234_5678_9ABC_DEF0] {
            let mut r = SplitMix64::new(seed);
            for i in 0..100 {
                assert_eq!(
                    SplitMix64::at(seed, i),
                    r.next_u64(),
                    "seed {seed} element {i}"
                );
            }
        }
        // Known first output of seed 0 (the reference implementation's).
        assert_eq!(SplitMix64::at(0, 0), 0xE220_A839_7B1D_CDAF);
    }
}
