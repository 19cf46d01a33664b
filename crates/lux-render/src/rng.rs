//! Deterministic sample points: every number a render draws is a pure function of
//! `(seed, pixel, sample index, dimension)`, so an image is bit-identical whatever the thread
//! count or tile order.
//!
//! The points are **padded, scrambled (0, 2)-sequences** (the construction of pbrt-v4's
//! `PaddedSobolSampler`): each 2D dimension pair of a pixel takes the first `spp` points of the
//! 2D Sobol sequence — the van der Corput sequence in x and Sobol's second dimension in y,
//! whose first 2ᵏ points form a (0, k, 2)-net — with
//! - the sample index permuted per (pixel, pair) by a hash-based bijection of `[0, spp)`
//!   (cycle-walking, after Kensler 2013, "Correlated Multi-Jittered Sampling"), so that pairs
//!   are decorrelated from one another, and
//! - each coordinate Owen-scrambled per (pixel, pair) with the hash-based nested uniform
//!   scramble of Burley 2020 ("Practical Hash-based Owen Scrambling"), which keeps the net
//!   property and randomises the point set so the estimator stays unbiased.
//!
//! For smooth integrands (a light's solid angle, a pixel's footprint) the error falls faster
//! than with independent uniform numbers (≈ N^-3/4 instead of N^-1/2 in 2D).

/// 64-bit finaliser of SplitMix64 / MurmurHash3 (a bijection with full avalanche).
#[inline(always)]
fn mix64(mut x: u64) -> u64 {
    x ^= x >> 30;
    x = x.wrapping_mul(0xBF58_476D_1CE4_E5B9);
    x ^= x >> 27;
    x = x.wrapping_mul(0x94D0_49BB_1331_11EB);
    x ^ (x >> 31)
}

/// van der Corput radical inverse in base 2 (the first Sobol dimension), 32 bits.
#[inline(always)]
fn sobol0(i: u32) -> u32 {
    i.reverse_bits()
}

/// Direction numbers of the second Sobol dimension: v₀ = 2³¹, vₖ = vₖ₋₁ ⊕ (vₖ₋₁ >> 1).
const SOBOL1_V: [u32; 32] = {
    let mut v = [0u32; 32];
    v[0] = 1 << 31;
    let mut k = 1;
    while k < 32 {
        v[k] = v[k - 1] ^ (v[k - 1] >> 1);
        k += 1;
    }
    v
};

/// The second Sobol dimension: the XOR of the direction numbers of the set bits of `i`.
#[inline(always)]
fn sobol1(mut i: u32) -> u32 {
    let mut r = 0u32;
    while i != 0 {
        r ^= SOBOL1_V[i.trailing_zeros() as usize];
        i &= i - 1;
    }
    r
}

/// A 32-bit integer hash with low bias (Wellons' `lowbias32`).
#[inline(always)]
fn hash32(mut x: u32) -> u32 {
    x ^= x >> 16;
    x = x.wrapping_mul(0x7FEB_352D);
    x ^= x >> 15;
    x = x.wrapping_mul(0x846C_A68B);
    x ^ (x >> 16)
}

/// Owen scrambling of a 32-bit fraction (Burley 2020): each bit is flipped by a hash of the
/// bits above it, applied in the bit-reversed domain as a Laine–Karras style permutation.
#[inline(always)]
fn owen(x: u32, seed: u32) -> u32 {
    let mut v = x.reverse_bits();
    v ^= v.wrapping_mul(0x3D20_ADEA);
    v = v.wrapping_add(seed);
    v = v.wrapping_mul((seed >> 16) | 1);
    v ^= v.wrapping_mul(0x0552_6C56);
    v ^= v.wrapping_mul(0x53A2_2864);
    v.reverse_bits()
}

/// A hash-based bijection of `[0, n)` (Kensler's `permute`, by cycle walking over the next
/// power of two). `n ≥ 1`.
#[inline]
fn permute(mut i: u32, n: u32, p: u32) -> u32 {
    if n <= 1 {
        return 0;
    }
    let w = n - 1;
    let mut mask = w;
    mask |= mask >> 1;
    mask |= mask >> 2;
    mask |= mask >> 4;
    mask |= mask >> 8;
    mask |= mask >> 16;
    loop {
        i ^= p;
        i = i.wrapping_mul(0xE170_893D);
        i ^= p >> 16;
        i ^= (i & mask) >> 4;
        i ^= p >> 8;
        i = i.wrapping_mul(0x0929_EB3F);
        i ^= p >> 23;
        i ^= (i & mask) >> 1;
        i = i.wrapping_mul(1 | (p >> 27));
        i = i.wrapping_mul(0x6935_FA69);
        i ^= (i & mask) >> 11;
        i = i.wrapping_mul(0x74DC_B303);
        i ^= (i & mask) >> 2;
        i = i.wrapping_mul(0x9E50_1CC3);
        i ^= (i & mask) >> 2;
        i = i.wrapping_mul(0xC860_A3DF);
        i &= mask;
        i ^= i >> 5;
        if i <= w {
            break;
        }
    }
    i.wrapping_add(p) % n
}

/// Unit fraction of a 32-bit integer, in \[0, 1).
#[inline(always)]
fn unit(x: u32) -> f64 {
    x as f64 * (1.0 / 4_294_967_296.0)
}

/// The sample points of one camera sample of one pixel.
#[derive(Clone, Copy, Debug)]
pub struct SampleStream {
    key: u64,
    sample: u32,
    spp: u32,
}

impl SampleStream {
    /// Sample `sample` of `spp` of pixel `pixel` (a linear pixel index) under `seed`.
    #[inline]
    pub fn new(seed: u64, pixel: u64, sample: u32, spp: u32) -> SampleStream {
        let key =
            mix64(mix64(seed ^ 0x6A09_E667_F3BC_C909) ^ pixel.wrapping_mul(0x9E37_79B9_7F4A_7C15));
        SampleStream {
            key,
            sample,
            spp: spp.max(1),
        }
    }

    /// The permutation seed and the two scrambling seeds of dimension (pair) `dim`.
    #[inline(always)]
    fn hashes(&self, dim: u32) -> (u32, u32, u32) {
        let h = mix64(self.key ^ (dim as u64 + 1).wrapping_mul(0xD6E8_FEB8_6659_FD93));
        let (lo, hi) = (h as u32, (h >> 32) as u32);
        (lo, hi, hash32(lo ^ hi.rotate_left(16) ^ 0x5BD1_E995))
    }

    /// The 2D point of dimension pair `dim` (any number identifying the pair): both
    /// coordinates uniform in \[0, 1), stratified across the pixel's samples.
    #[inline]
    pub fn u2(&self, dim: u32) -> [f64; 2] {
        let (p, s0, s1) = self.hashes(dim);
        let i = permute(self.sample, self.spp, p);
        [unit(owen(sobol0(i), s0)), unit(owen(sobol1(i), s1))]
    }

    /// A 1D number of dimension `dim`, uniform in \[0, 1), stratified across the samples.
    #[inline]
    pub fn u(&self, dim: u32) -> f64 {
        let (p, s0, _) = self.hashes(dim ^ 0x8000_0000);
        let i = permute(self.sample, self.spp, p);
        unit(owen(sobol0(i), s0))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pure_functions_of_their_counters() {
        let a = SampleStream::new(7, 1234, 5, 16);
        let b = SampleStream::new(7, 1234, 5, 16);
        assert_eq!(a.u2(3), b.u2(3));
        assert_ne!(a.u2(3), SampleStream::new(8, 1234, 5, 16).u2(3));
        assert_ne!(a.u2(3), SampleStream::new(7, 1235, 5, 16).u2(3));
        assert_ne!(a.u2(3), SampleStream::new(7, 1234, 6, 16).u2(3));
        assert_ne!(a.u2(3), a.u2(4));
    }

    #[test]
    fn sobol_second_dimension_known_values() {
        // The first points of Sobol's second dimension: 0, 1/2, 3/4, 1/4, 5/8, 1/8, 3/8, 7/8.
        let want = [0.0, 0.5, 0.75, 0.25, 0.625, 0.125, 0.375, 0.875];
        for (i, w) in want.iter().enumerate() {
            assert_eq!(unit(sobol1(i as u32)), *w, "point {i}");
        }
    }

    #[test]
    fn permutation_is_a_bijection() {
        for n in [1u32, 2, 3, 7, 16, 100, 1000] {
            for p in [0u32, 1, 0xDEAD_BEEF, 12345] {
                let mut seen = vec![false; n as usize];
                for i in 0..n {
                    let j = permute(i, n, p) as usize;
                    assert!(j < n as usize && !seen[j], "n {n} p {p}");
                    seen[j] = true;
                }
            }
        }
    }

    /// The spp = 2ᵏ points of a pixel's pair form a (0, k, 2)-net: every elementary interval
    /// of area 2⁻ᵏ (all 2ʲ × 2ᵏ⁻ʲ shapes) holds exactly one point.
    #[test]
    fn power_of_two_counts_are_nets() {
        for k in [2u32, 4, 6] {
            let n = 1u32 << k;
            for pixel in 0..20u64 {
                let pts: Vec<[f64; 2]> = (0..n)
                    .map(|s| SampleStream::new(3, pixel, s, n).u2(9))
                    .collect();
                for j in 0..=k {
                    let (nx, ny) = (1u32 << j, 1u32 << (k - j));
                    let mut cells = vec![0u32; n as usize];
                    for p in &pts {
                        let c = (p[0] * nx as f64) as u32 + nx * (p[1] * ny as f64) as u32;
                        cells[c as usize] += 1;
                    }
                    assert!(
                        cells.iter().all(|&c| c == 1),
                        "k {k} pixel {pixel} shape {nx}x{ny}"
                    );
                }
            }
        }
    }

    /// Uniform across pixels: chi-square of 64 bins of many pixels' points, and independence of
    /// two pairs of the same sample (their correlation is about 0).
    #[test]
    fn uniform_and_decorrelated_across_pairs() {
        let mut bins = [0usize; 64];
        let (mut sxy, mut n) = (0.0, 0usize);
        for pixel in 0..4096u64 {
            for s in 0..8 {
                let st = SampleStream::new(1, pixel, s, 8);
                let a = st.u2(2);
                let b = st.u2(5);
                let c = st.u(4);
                for x in [a[0], a[1], b[0], b[1], c] {
                    assert!((0.0..1.0).contains(&x));
                }
                bins[(a[0] * 8.0) as usize * 8 + (a[1] * 8.0) as usize] += 1;
                sxy += (a[0] - 0.5) * (b[0] - 0.5);
                n += 1;
            }
        }
        let e = n as f64 / 64.0;
        let chi2: f64 = bins.iter().map(|&o| (o as f64 - e).powi(2) / e).sum();
        // Stratification makes the bins *more* even than independent draws; 63 degrees of
        // freedom, P(chi2 > 110) < 1e-4 even for independent draws.
        assert!(chi2 < 110.0, "chi2 {chi2}");
        let corr = sxy / n as f64 * 12.0;
        assert!(
            corr.abs() < 4.0 / (n as f64).sqrt(),
            "correlation between pairs {corr}"
        );
    }

    /// The scrambled net integrates a smooth function much better than independent points:
    /// over many pixels, the error of a 64-point estimate of ∫∫ x·y is far below 1/√64.
    #[test]
    fn converges_faster_than_independent_sampling() {
        let mut se = 0.0;
        let pixels = 2000;
        for pixel in 0..pixels {
            let m: f64 = (0..64)
                .map(|s| {
                    let p = SampleStream::new(5, pixel, s, 64).u2(1);
                    p[0] * p[1]
                })
                .sum::<f64>()
                / 64.0;
            se += (m - 0.25) * (m - 0.25);
        }
        let rms = (se / pixels as f64).sqrt();
        // Independent sampling: σ(xy)/8 = 0.2205/8 ≈ 0.0276.
        assert!(rms < 0.0276 / 8.0, "rms error {rms}");
        assert!(rms > 0.0, "a scrambled estimate is random");
    }
}
