//! Deterministic sample points and their named dimension layout: every number a render draws
//! is a pure function of `(seed, pixel, sample index, dimension)`, so an image is
//! bit-identical whatever the thread count or tile order.
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
//!
//! **Past the camera's vertex the numbers are independent** ([`STRATIFIED_BOUNCES`]): a path's
//! later vertices read many dimensions, and a pair stratified on its own (not jointly with
//! the vertices before it, which decide where it is) buys little there, while each scrambled
//! point costs some forty integer multiplications. Their numbers are a SplitMix64 stream per
//! (pixel, dimension) read at the sample's index — uniform, independent across samples and
//! dimensions, and as pure a function of the counters. Time × squared error against a ground
//! truth (six seeds): Cornell box −7 %, StandardShaderBall −4 %, clutter_mix −4 % and −19 %,
//! clutter_one −1 % and −3 % (BENCHMARKS.md, issue 39).
//!
//! Which decision reads which dimension is fixed in one place, [`Dim`]: the camera's pixel
//! jitter, then per bounce the light choice, each light's 2D sample, the pick of the light
//! samples that get shadow rays, the BSDF's 2D sample and Russian roulette. A dimension is
//! only a name for a stream: any two distinct names are decorrelated, so the layout never has
//! to be dense.

use lux_sample::SplitMix64;

/// Largest sample count per pixel a render accepts (`RenderOptions::spp` and adaptive counts):
/// a pixel's stream stratifies up to this many samples.
pub const MAX_SPP: u32 = 1 << 20;

/// Path vertices whose numbers are stratified (scrambled Sobol points); the numbers of
/// vertex `STRATIFIED_BOUNCES` and later are independent, a hashed stream per dimension
/// ([`SampleStream::u2`]). One: the camera's vertex only (its light samples, BSDF sample and
/// the direct integrator's every number).
pub const STRATIFIED_BOUNCES: u32 = 1;

/// Whether dimension (pair) id `dim` ([`Dim::id`]) belongs to a vertex whose numbers are
/// independent rather than stratified.
#[inline(always)]
fn is_independent(dim: u32) -> bool {
    dim >> 24 >= STRATIFIED_BOUNCES
}

/// 64 independent uniform bits of dimension (pair) `dim` for point `index` of the pixel
/// `key`: element `index` of the SplitMix64 stream ([`SplitMix64::at`]) seeded by the pixel's
/// and the dimension's hash.
#[inline(always)]
fn independent(key: u64, dim: u64, index: u32) -> u64 {
    let h = mix64(key ^ dim.wrapping_add(1).wrapping_mul(0xD6E8_FEB8_6659_FD93));
    SplitMix64::at(h, index as u64)
}

/// The 2D point of [`independent`]: the two 32-bit halves as unit fractions.
#[inline(always)]
fn independent2(key: u64, dim: u32, index: u32) -> [f64; 2] {
    let h = independent(key, dim as u64, index);
    [unit(h as u32), unit((h >> 32) as u32)]
}

/// The 1D number of [`independent`] (a name apart from the 2D pair's of the same id, as
/// [`point1`]'s).
#[inline(always)]
fn independent1(key: u64, dim: u32, index: u32) -> f64 {
    unit(independent(key, dim as u64 | 1 << 32, index) as u32)
}

/// 64-bit finaliser of SplitMix64 / MurmurHash3 (a bijection with full avalanche).
#[inline(always)]
fn mix64(mut x: u64) -> u64 {
    x ^= x >> 30;
    x = x.wrapping_mul(0xBF58_476D_1CE4_E5B9);
    x ^= x >> 27;
    x = x.wrapping_mul(0x94D0_49BB_1331_11EB);
    x ^ (x >> 31)
}

/// Direction numbers of the second Sobol dimension, bit-reversed: vₖ = vₖ₋₁ ⊕ (vₖ₋₁ >> 1)
/// from v₀ = 2³¹ becomes rₖ = rₖ₋₁ ⊕ (rₖ₋₁ << 1) from r₀ = 1.
const SOBOL1_R: [u32; 32] = {
    let mut r = [0u32; 32];
    r[0] = 1;
    let mut k = 1;
    while k < 32 {
        r[k] = r[k - 1] ^ (r[k - 1] << 1);
        k += 1;
    }
    r
};

/// [`SOBOL1_R`] XOR-summed over every byte value, per byte of the index: entry `k·256 + v`
/// is the XOR of `SOBOL1_R[8k + j]` over the set bits `j` of `v`.
static SOBOL1_BYTES: [u32; 1024] = {
    let mut t = [0u32; 1024];
    let mut k = 0;
    while k < 4 {
        let mut v = 0;
        while v < 256 {
            let mut r = 0u32;
            let mut j = 0;
            while j < 8 {
                if v >> j & 1 == 1 {
                    r ^= SOBOL1_R[8 * k + j];
                }
                j += 1;
            }
            t[k * 256 + v] = r;
            v += 1;
        }
        k += 1;
    }
    t
};

/// The second Sobol dimension of point `i`, bit-reversed (the XOR of the reversed direction
/// numbers of the set bits of `i`; reversal distributes over XOR), a byte at a time
/// ([`SOBOL1_BYTES`]: four lookups and no data-dependent branch).
#[inline(always)]
fn sobol1_rev(i: u32) -> u32 {
    let b = |k: usize| SOBOL1_BYTES[k * 256 + (i >> (8 * k) & 0xFF) as usize];
    b(0) ^ b(1) ^ b(2) ^ b(3)
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
/// Takes the fraction bit-reversed (`v = x.reverse_bits()`) and returns the scrambled
/// fraction: the first Sobol dimension (van der Corput, `i.reverse_bits()`) enters as `i`
/// itself, the second as [`sobol1_rev`], so no reversal is done twice.
#[inline(always)]
fn owen_rev(mut v: u32, seed: u32) -> u32 {
    v ^= v.wrapping_mul(0x3D20_ADEA);
    v = v.wrapping_add(seed);
    v = v.wrapping_mul((seed >> 16) | 1);
    v ^= v.wrapping_mul(0x0552_6C56);
    v ^= v.wrapping_mul(0x53A2_2864);
    v.reverse_bits()
}

/// One round of Kensler's hash over the bits of `mask` (a power of two minus one).
#[inline(always)]
fn permute_round(mut i: u32, mask: u32, p: u32) -> u32 {
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
    i ^ (i >> 5)
}

/// A hash-based bijection of `[0, n)` (Kensler's `permute`, by cycle walking over the next
/// power of two). `n ≥ 1`.
#[inline(always)]
fn permute(i: u32, n: u32, p: u32) -> u32 {
    if n <= 1 {
        return 0;
    }
    let w = n - 1;
    if n & w == 0 {
        // A power of two, the usual sample count: the round stays below n (it keeps the top
        // bit of `i & w`), so no cycle walking, and a mask instead of a division.
        return permute_round(i, w, p).wrapping_add(p) & w;
    }
    permute_walk(i, n, p)
}

/// [`permute`] for `n ≥ 3` not a power of two: rounds until the index falls below `n`.
#[inline(never)]
fn permute_walk(mut i: u32, n: u32, p: u32) -> u32 {
    let w = n - 1;
    let mask = u32::MAX >> w.leading_zeros();
    loop {
        i = permute_round(i, mask, p);
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
    /// Points of the pixel's sequence before this set's ([`SampleStream::after`]).
    base: u32,
    sample: u32,
    spp: u32,
    /// Light samples per light this camera sample takes (a factor on the integrator's).
    light_factor: u32,
    /// Path continuations this camera sample splits into (0: the integrator's own).
    splits: u32,
}

impl SampleStream {
    /// Sample `sample` of `spp` of pixel `pixel` (a linear pixel index) under `seed`.
    #[inline]
    pub fn new(seed: u64, pixel: u64, sample: u32, spp: u32) -> SampleStream {
        let key =
            mix64(mix64(seed ^ 0x6A09_E667_F3BC_C909) ^ pixel.wrapping_mul(0x9E37_79B9_7F4A_7C15));
        let spp = spp.max(1);
        SampleStream {
            key,
            base: 0,
            sample,
            spp,
            light_factor: 1,
            splits: 0,
        }
    }

    /// This sample in the set of the pixel's points that follows its first `base`: the
    /// stream's `spp` points are points `base..base + spp` of each dimension's sequence (under
    /// the same scrambles), so that a pixel's first `base` samples and these together take
    /// the first `base + spp` points of every dimension — a (0, 2)-sequence's prefix, as well
    /// spread as one set of that many. Adaptive sampling's extra samples continue a pixel's
    /// first ones so. Each point stays uniform, so a count chosen apart from these points
    /// keeps the pixel unbiased.
    #[inline]
    pub fn after(&self, base: u32) -> SampleStream {
        SampleStream { base, ..*self }
    }

    /// This sample in a second, independently scrambled set of the pixel's points (same
    /// sample index and count), taking `factor` light samples per light. The film's
    /// penumbra pass draws a pixel's pilot and, when the pilot chose `factor > 1`, its samples
    /// from such sets, so that the samples' points are independent of the pilot's.
    #[inline]
    pub fn pass(&self, salt: u64, factor: u32) -> SampleStream {
        SampleStream {
            key: mix64(self.key ^ salt),
            light_factor: factor.max(1),
            ..*self
        }
    }

    /// Light samples per light this camera sample takes, as a factor on the integrator's.
    #[inline]
    pub fn light_factor(&self) -> u32 {
        self.light_factor
    }

    /// This sample split into `k` path continuations at the camera's vertex (0: the
    /// integrator's own count): adaptive splitting draws a pixel's extra samples so
    /// (`AdaptiveSampling::max_splits`).
    #[inline]
    pub fn with_splits(&self, k: u32) -> SampleStream {
        SampleStream { splits: k, ..*self }
    }

    /// Path continuations this camera sample asks for (0: the integrator's own).
    #[inline]
    pub fn splits(&self) -> u32 {
        self.splits
    }

    /// Sub-sample `j` of `k` of this sample: the stream of sample `sample·k + j` among
    /// `spp·k`, so that the `k` sub-samples of every sample of the pixel together take the
    /// first `spp·k` points of each dimension's net (`k` light samples per camera sample stay
    /// stratified over the pixel). `k = 1` is this stream.
    #[inline]
    pub fn split(&self, j: u32, k: u32) -> SampleStream {
        SampleStream {
            base: self.base * k,
            sample: self.sample * k + j,
            spp: self.spp * k,
            ..*self
        }
    }

    /// The 2D points of the named dimension `dim` of the `k` sub-samples of this sample:
    /// [`SampleStream::split`]`(j, k)`[`.get2(dim)`](SampleStream::get2) for `j` in `0..k`,
    /// with the dimension's hashes computed once.
    #[inline(always)]
    pub fn split_get2(&self, dim: Dim, k: u32) -> impl Iterator<Item = [f64; 2]> + use<> {
        let id = dim.id();
        let (p, s0, s1) = Self::hashes(self.key, id);
        let (base, first, spp) = (self.base * k, self.sample * k, self.spp * k);
        let (key, free) = (self.key, is_independent(id));
        (0..k).map(move |j| {
            if free {
                independent2(key, id, base + first + j)
            } else {
                point2_of(base, first + j, spp, p, s0, s1)
            }
        })
    }

    /// The permutation seed and the two scrambling seeds of dimension (pair) `dim` under `key`.
    #[inline(always)]
    fn hashes(key: u64, dim: u32) -> (u32, u32, u32) {
        let h = mix64(key ^ (dim as u64 + 1).wrapping_mul(0xD6E8_FEB8_6659_FD93));
        let (lo, hi) = (h as u32, (h >> 32) as u32);
        (lo, hi, hash32(lo ^ hi.rotate_left(16) ^ 0x5BD1_E995))
    }

    /// The 2D point of dimension pair `dim` (a [`Dim::id`]): both coordinates uniform in
    /// \[0, 1), stratified across the pixel's samples at the camera's vertex, independent past
    /// it ([`STRATIFIED_BOUNCES`]).
    #[inline(always)]
    pub fn u2(&self, dim: u32) -> [f64; 2] {
        if is_independent(dim) {
            return independent2(self.key, dim, self.base + self.sample);
        }
        point2(self.key, self.base, self.sample, self.spp, dim)
    }

    /// The 2D point of the named dimension `dim`.
    #[inline(always)]
    pub fn get2(&self, dim: Dim) -> [f64; 2] {
        self.u2(dim.id())
    }

    /// The 1D number of the named dimension `dim`.
    #[inline(always)]
    pub fn get1(&self, dim: Dim) -> f64 {
        self.u(dim.id())
    }

    /// A 1D number of dimension `dim` (a [`Dim::id`]), uniform in \[0, 1), stratified across
    /// the samples at the camera's vertex, independent past it ([`STRATIFIED_BOUNCES`]).
    #[inline(always)]
    pub fn u(&self, dim: u32) -> f64 {
        if is_independent(dim) {
            return independent1(self.key, dim, self.base + self.sample);
        }
        point1(self.key, self.base, self.sample, self.spp, dim)
    }
}

/// Point `base + π(sample)` (π a permutation of `[0, spp)`) of the 2D dimension `dim` under
/// `key`.
#[inline(always)]
fn point2(key: u64, base: u32, sample: u32, spp: u32, dim: u32) -> [f64; 2] {
    let (p, s0, s1) = SampleStream::hashes(key, dim);
    point2_of(base, sample, spp, p, s0, s1)
}

/// Point `base + π(sample)` of the 2D dimension whose permutation and scrambling seeds are
/// `p`, `s0` and `s1`.
#[inline(always)]
fn point2_of(base: u32, sample: u32, spp: u32, p: u32, s0: u32, s1: u32) -> [f64; 2] {
    let i = base + permute(sample, spp, p);
    [unit(owen_rev(i, s0)), unit(owen_rev(sobol1_rev(i), s1))]
}

/// Point `base + π(sample)` of the 1D dimension `dim` under `key`.
#[inline(always)]
fn point1(key: u64, base: u32, sample: u32, spp: u32, dim: u32) -> f64 {
    let (p, s0, _) = SampleStream::hashes(key, dim ^ 0x8000_0000);
    let i = base + permute(sample, spp, p);
    unit(owen_rev(i, s0))
}

/// The named dimensions of a camera sample (see the module doc). Bounce 0 is the first
/// surface a camera ray meets; a path's later bounces use disjoint names `bounce·2²⁴ + k`.
///
/// Bounce-0 names are the numbers the direct integrator has always used (camera 0, BSDF 2,
/// light choice 4, light `i` at `5 + 2i`), so images stay bit-identical across releases.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dim {
    /// The pixel jitter of the camera ray (2D).
    Camera,
    /// Which light to sample when one light is chosen per shading point (1D).
    LightChoice {
        /// Path vertex (0 = seen by the camera).
        bounce: u32,
    },
    /// The 2D sample on light `index` (when every light is sampled), or on the chosen light
    /// (`index` 0).
    Light {
        /// Path vertex.
        bounce: u32,
        /// Light index in the light set (0 for a chosen light).
        index: u32,
    },
    /// The BSDF's 2D direction sample.
    Bsdf {
        /// Path vertex.
        bounce: u32,
    },
    /// Which closure of a MaterialX BSDF tree the BSDF sample follows (1D).
    Lobe {
        /// Path vertex.
        bounce: u32,
    },
    /// Russian roulette after the vertex (1D).
    Roulette {
        /// Path vertex.
        bounce: u32,
    },
    /// Which of a shading point's light samples get its shadow rays (1D).
    ShadowPick {
        /// Path vertex.
        bounce: u32,
    },
}

impl Dim {
    /// Largest bounce with its own names (7 bits above the 2²⁴ names of a bounce; the top bit
    /// of a name separates 1D from 2D streams).
    pub const MAX_BOUNCE: u32 = 127;

    /// The stream name of the dimension. Light indices wrap modulo 2²² (a scene with more
    /// lights samples one light per point, [`Dim::Light`] index 0).
    #[inline]
    pub const fn id(self) -> u32 {
        let (bounce, k) = match self {
            Dim::Camera => (0, 0),
            Dim::Lobe { bounce } => (bounce, 1),
            Dim::Bsdf { bounce } => (bounce, 2),
            Dim::Roulette { bounce } => (bounce, 3),
            Dim::LightChoice { bounce } => (bounce, 4),
            Dim::ShadowPick { bounce } => (bounce, 6),
            Dim::Light { bounce, index } => (bounce, 5 + 2 * (index & 0x3F_FFFF)),
        };
        ((bounce & Dim::MAX_BOUNCE) << 24).wrapping_add(k)
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
            assert_eq!(unit(sobol1_rev(i as u32).reverse_bits()), *w, "point {i}");
        }
    }

    /// The byte tables give the XOR of the direction numbers of the set bits, for indices
    /// with bits in every byte (and `u32::MAX`).
    #[test]
    fn sobol_byte_tables_sum_the_direction_numbers() {
        let by_bits = |mut i: u32| {
            let mut r = 0u32;
            while i != 0 {
                r ^= SOBOL1_R[i.trailing_zeros() as usize];
                i &= i - 1;
            }
            r
        };
        let mut i = 0u32;
        for _ in 0..20_000 {
            assert_eq!(sobol1_rev(i), by_bits(i), "index {i}");
            i = i.wrapping_mul(0x2C1B_3C6D).wrapping_add(0x297A_2D39);
        }
        for i in (0..4096).chain([u32::MAX, 1 << 31, 0xFF00_FF00]) {
            assert_eq!(sobol1_rev(i), by_bits(i), "index {i}");
        }
    }

    /// The construction as the module doc states it, without the shortcuts of `point2` and
    /// `point1` (bit reversals done once, the power-of-two permutation without cycle walking).
    mod reference {
        use super::super::{SampleStream, unit};

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

        fn sobol0(i: u32) -> u32 {
            i.reverse_bits()
        }

        fn sobol1(mut i: u32) -> u32 {
            let mut r = 0u32;
            while i != 0 {
                r ^= SOBOL1_V[i.trailing_zeros() as usize];
                i &= i - 1;
            }
            r
        }

        fn owen(x: u32, seed: u32) -> u32 {
            let mut v = x.reverse_bits();
            v ^= v.wrapping_mul(0x3D20_ADEA);
            v = v.wrapping_add(seed);
            v = v.wrapping_mul((seed >> 16) | 1);
            v ^= v.wrapping_mul(0x0552_6C56);
            v ^= v.wrapping_mul(0x53A2_2864);
            v.reverse_bits()
        }

        pub fn permute(mut i: u32, n: u32, p: u32) -> u32 {
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
            (i.wrapping_add(p)) % n
        }

        pub fn point2(key: u64, sample: u32, spp: u32, dim: u32) -> [f64; 2] {
            let (p, s0, s1) = SampleStream::hashes(key, dim);
            let i = permute(sample, spp, p);
            [unit(owen(sobol0(i), s0)), unit(owen(sobol1(i), s1))]
        }

        pub fn point1(key: u64, sample: u32, spp: u32, dim: u32) -> f64 {
            let (p, s0, _) = SampleStream::hashes(key, dim ^ 0x8000_0000);
            let i = permute(sample, spp, p);
            unit(owen(sobol0(i), s0))
        }
    }

    /// The points are those of the construction itself, bit for bit: every sample count from
    /// 1 to 70 and some larger ones (powers of two and not), both 2D and 1D streams.
    #[test]
    fn points_equal_the_reference_construction() {
        let mut counts: Vec<u32> = (1..=70).collect();
        counts.extend([96, 128, 255, 256, 1000, 1024, 4096]);
        for (k, &spp) in counts.iter().enumerate() {
            for pixel in [0u64, 1, 77, 65_535, 1 << 40] {
                let key = SampleStream::new(k as u64 ^ 0x5EED, pixel, 0, spp).key;
                for dim in [0u32, 2, 5, 11, 0x0100_0003, 0x7F00_0005] {
                    let samples = spp.min(300);
                    for s in (0..samples).chain([spp - 1]) {
                        assert_eq!(
                            point2(key, 0, s, spp, dim).map(f64::to_bits),
                            reference::point2(key, s, spp, dim).map(f64::to_bits),
                            "spp {spp} pixel {pixel} dim {dim} sample {s}"
                        );
                        assert_eq!(
                            point1(key, 0, s, spp, dim).to_bits(),
                            reference::point1(key, s, spp, dim).to_bits(),
                            "spp {spp} pixel {pixel} dim {dim} sample {s}"
                        );
                    }
                }
            }
        }
        for n in [2u32, 3, 5, 8, 100, 1 << 20, (1 << 20) + 1, u32::MAX] {
            for i in [0u32, 1, n / 2, n - 1] {
                for p in [0u32, 1, 0xDEAD_BEEF, u32::MAX] {
                    assert_eq!(permute(i, n, p), reference::permute(i, n, p), "{n} {i} {p}");
                }
            }
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

    /// A pixel's first `base` points and the `n` of [`SampleStream::after`]`(base)` are,
    /// as sets, the first `base + n` points of every dimension (2D and 1D, split into
    /// sub-samples too): a continuation is as well spread as one set of that many.
    #[test]
    fn continued_sets_are_the_longer_prefix() {
        for (base, n, k) in [
            (4u32, 12u32, 1u32),
            (5, 11, 1),
            (1, 30, 1),
            (3, 5, 2),
            (8, 8, 4),
        ] {
            let sorted = |v: Vec<[u64; 2]>| {
                let (mut a, mut b): (Vec<u64>, Vec<u64>) = v.iter().map(|&[a, b]| (a, b)).unzip();
                a.sort_unstable();
                b.sort_unstable();
                (a, b)
            };
            for dim in [
                Dim::Camera,
                Dim::Bsdf { bounce: 2 },
                Dim::Light {
                    bounce: 0,
                    index: 3,
                },
            ] {
                // (the 2D and the 1D points apart: each dimension is permuted on its own)
                let key = |st: SampleStream| {
                    let [a, b] = st.get2(dim);
                    [
                        a.to_bits() ^ b.to_bits().rotate_left(17),
                        st.get1(dim).to_bits(),
                    ]
                };
                let whole: Vec<[u64; 2]> = (0..base + n)
                    .flat_map(|s| {
                        let st = SampleStream::new(9, 77, s, base + n);
                        (0..k).map(move |j| st.split(j, k))
                    })
                    .map(key)
                    .collect();
                let parts: Vec<[u64; 2]> = (0..base)
                    .map(|s| SampleStream::new(9, 77, s, base))
                    .chain((0..n).map(|e| SampleStream::new(9, 77, e, n).after(base)))
                    .flat_map(|st| (0..k).map(move |j| st.split(j, k)))
                    .map(key)
                    .collect();
                assert_eq!(
                    sorted(parts),
                    sorted(whole),
                    "{base} + {n}, split {k}, {dim:?}"
                );
            }
        }
        // split_get2 agrees with split(..).get2 on a continuation.
        let st = SampleStream::new(3, 5, 2, 7).after(9);
        let d = Dim::Bsdf { bounce: 1 };
        let a: Vec<[f64; 2]> = st.split_get2(d, 3).collect();
        let b: Vec<[f64; 2]> = (0..3).map(|j| st.split(j, 3).get2(d)).collect();
        assert_eq!(a, b);
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
        // freedom, P(chi2 > 110) = 2.3e-4 even for independent draws.
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

    /// Past the camera's vertex the numbers are independent uniform ones: 2D and 1D bins
    /// even by chi-square, no correlation between consecutive samples of a pixel, between a
    /// pair and the 1D number of the same name, or between neighbouring pixels; a 64-sample
    /// mean of x·y has the error of independent sampling (not the net's); the camera's vertex
    /// keeps its scrambled points.
    #[test]
    fn independent_numbers_past_the_camera_vertex() {
        let (bsdf, roulette) = (Dim::Bsdf { bounce: 1 }, Dim::Roulette { bounce: 3 });
        let mut bins2 = [0usize; 64];
        let mut bins1 = [0usize; 64];
        let (mut lag, mut cross, mut near, mut n) = (0.0, 0.0, 0.0, 0usize);
        for pixel in 0..2048u64 {
            let mut last = 0.5;
            for s in 0..16 {
                let st = SampleStream::new(1, pixel, s, 16);
                let a = st.get2(bsdf);
                let c = st.get1(roulette);
                let d = SampleStream::new(1, pixel + 1, s, 16).get2(bsdf);
                for x in [a[0], a[1], c] {
                    assert!((0.0..1.0).contains(&x));
                }
                bins2[(a[0] * 8.0) as usize * 8 + (a[1] * 8.0) as usize] += 1;
                bins1[(c * 64.0) as usize] += 1;
                lag += (a[0] - 0.5) * (last - 0.5);
                cross += (a[1] - 0.5) * (st.get1(bsdf) - 0.5);
                near += (a[0] - 0.5) * (d[0] - 0.5);
                last = a[0];
                n += 1;
            }
        }
        let e = n as f64 / 64.0;
        for bins in [bins2, bins1] {
            let chi2: f64 = bins.iter().map(|&o| (o as f64 - e).powi(2) / e).sum();
            // 63 degrees of freedom: P(chi2 > 110) = 2.3e-4, P(chi2 < 30) = 1.3e-4 (too
            // even for independent draws).
            assert!((30.0..110.0).contains(&chi2), "chi2 {chi2}");
        }
        for corr in [lag, cross, near] {
            let corr = corr / n as f64 * 12.0;
            assert!(corr.abs() < 4.0 / (n as f64).sqrt(), "correlation {corr}");
        }
        // A pixel's 64-sample estimate of ∫∫ x·y = 1/4: independent sampling's error
        // σ(xy)/8 = √(1/9 − 1/16)/8 ≈ 0.02756 (its estimate from 4000 pixels within ±6 %,
        // about four standard errors), where the camera vertex's net does 8× better.
        let rms = |dim: Dim| {
            let pixels = 4000;
            let se: f64 = (0..pixels)
                .map(|pixel| {
                    let m = (0..64)
                        .map(|s| {
                            let p = SampleStream::new(5, pixel, s, 64).get2(dim);
                            p[0] * p[1]
                        })
                        .sum::<f64>()
                        / 64.0;
                    (m - 0.25) * (m - 0.25)
                })
                .sum();
            (se / pixels as f64).sqrt()
        };
        let independent = (1.0f64 / 9.0 - 1.0 / 16.0).sqrt() / 8.0;
        let past = rms(Dim::Bsdf { bounce: 1 });
        assert!((past / independent - 1.0).abs() < 0.06, "rms {past}");
        assert!(rms(Dim::Bsdf { bounce: 0 }) < independent / 8.0);
        // Pure functions of the counters; a later set (`after`) continues the stream.
        let st = SampleStream::new(2, 77, 3, 8);
        assert_eq!(st.get2(bsdf), SampleStream::new(2, 77, 3, 8).get2(bsdf));
        assert_eq!(
            st.after(8).get2(bsdf),
            SampleStream::new(2, 77, 11, 19).get2(bsdf)
        );
        assert_ne!(st.after(8).get2(bsdf), st.get2(bsdf));
        assert_eq!(
            st.get2(Dim::Bsdf { bounce: 0 }),
            point2(st.key, 0, 3, 8, Dim::Bsdf { bounce: 0 }.id())
        );
    }

    /// `split_get2` is `split(j, k).get2(dim)` for every sub-sample.
    #[test]
    fn split_points_are_the_split_streams() {
        for (sample, spp, k) in [(0, 1, 1), (3, 4, 4), (2, 3, 5), (7, 16, 2)] {
            let st = SampleStream::new(9, 4321, sample, spp);
            let dim = Dim::Light {
                bounce: 1,
                index: 2,
            };
            let got: Vec<[f64; 2]> = st.split_get2(dim, k).collect();
            let want: Vec<[f64; 2]> = (0..k).map(|j| st.split(j, k).get2(dim)).collect();
            assert_eq!(got, want, "sample {sample} of {spp}, k {k}");
        }
    }

    /// The bounce-0 names are the numbers images were rendered with before the layout had
    /// names; names of different dimensions never collide.
    #[test]
    fn dimension_layout() {
        assert_eq!(Dim::Camera.id(), 0);
        assert_eq!(Dim::Bsdf { bounce: 0 }.id(), 2);
        assert_eq!(Dim::LightChoice { bounce: 0 }.id(), 4);
        assert_eq!(
            Dim::Light {
                bounce: 0,
                index: 3
            }
            .id(),
            11
        );
        let mut seen = std::collections::HashSet::new();
        for bounce in [0, 1, 2, Dim::MAX_BOUNCE] {
            for d in [
                Dim::Lobe { bounce },
                Dim::Bsdf { bounce },
                Dim::Roulette { bounce },
                Dim::LightChoice { bounce },
                Dim::ShadowPick { bounce },
            ]
            .into_iter()
            .chain((0..50).map(|index| Dim::Light { bounce, index }))
            {
                assert!(seen.insert(d.id()), "{d:?} collides");
                assert!(d.id() < 0x8000_0000, "{d:?} sets the 1D flag");
            }
        }
        assert!(seen.insert(Dim::Camera.id()));
        let st = SampleStream::new(1, 2, 3, 8);
        assert_eq!(
            st.get2(Dim::Light {
                bounce: 0,
                index: 1
            }),
            st.u2(7)
        );
        assert_eq!(st.get1(Dim::LightChoice { bounce: 0 }), st.u(4));
    }
}
