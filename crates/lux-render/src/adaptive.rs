//! Where a pixel's samples go: the two policies that give some pixels more than `spp`
//! samples, each a pure function of the scene, settings and seed (images stay bit-identical
//! for any thread count) that keeps every pixel an unbiased estimate.
//!
//! - [`AdaptiveSampling`]: after its first `spp` samples, a pixel whose neighbourhood is noisy
//!   (or, by the perceived measure, crosses an edge) takes more (a second pass).
//! - [`PenumbraPilot`]: before its samples, a pilot camera sample per pixel decides whether it
//!   lies in a penumbra; such a pixel takes more light samples per light in all its samples.
//!
//! The tile loop (`tiles.rs`) runs both; this module holds their rules and constants.

use crate::sampler::MAX_SPP;

/// The noise by which adaptive sampling counts a pixel's samples ([`AdaptiveSampling::measure`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NoiseMeasure {
    /// `σ / √max(μ, μ_min)`: the spread `σ` of the luminances of the samples of the 8
    /// neighbours, pooled (pixel noise and edges across the neighbourhood alike), relative to
    /// the square root of their mean `μ` — noise in a square-root (gamma 2) encoding, about as
    /// the eye sees it (the measure of Blender Cycles' adaptive sampling); it antialiases
    /// edges. The direct integrator's default.
    Perceived,
    /// `σ_w / μ̄`: the spread of luminance within a pixel, pooled over the 48 neighbours of its
    /// 7 × 7 block (`σ_w² = mean_j (E_j[Y²] − E_j[Y]²) · s/(s − 1)` over neighbours `j` of `s`
    /// samples; the pooled spread `σ` when `s` = 1), relative to the frame's mean luminance
    /// `μ̄` ([`FramePilot`]). Samples in proportion to it are the allocation that minimises
    /// the image's summed squared error in linear values (its RMSE, the races' measure) for
    /// their number; quiet pixels keep `spp`. The wide block steadies the estimate of a path's
    /// heavy-tailed noise (on the clutter scenes 3 × 3 gave 7–11 % less). The path tracer's
    /// default.
    Linear,
}

/// Adaptive sampling: where a pixel's samples go after its first `spp`.
///
/// Every pixel first takes `spp` samples. From the luminances `Y` of the samples of its
/// neighbours (those within [`AdaptiveSampling::reach`]), the pixel then takes
///
/// `n = min(⌈spp · s / t⌉, max_factor · spp)`
///
/// samples in all (more than `spp` only), `t` = [`AdaptiveSampling::threshold`] and `s` the
/// noise of one sample by [`AdaptiveSampling::measure`]:
/// `σ / √max(μ, μ_min)` ([`NoiseMeasure::Perceived`], `μ_min` = [`AdaptiveSampling::MIN_MEAN`])
/// or `σ_w / μ̄` ([`NoiseMeasure::Linear`]). Samples go in proportion to `s` wherever it
/// exceeds `t`, the allocation that minimises the summed squared error of the measure for a
/// given number of samples (`n ∝ σ`). So a render costs a multiple of `spp` set by the image,
/// not by `spp`: 1.4–2.5 × on the luxtest frames at the default.
///
/// The count depends on the neighbours' samples (and the frame pilot's, drawn apart) only,
/// never on the pixel's own, and the extra samples are the points that follow the pixel's
/// first `spp` in its sequences (`SampleStream::after`; the pixel's samples together stay as
/// well spread as one set of `n`): each pixel stays an unbiased estimate. A band of rows
/// renders its neighbours' first samples `reach` rows beyond it, and the frame pilot of the
/// whole frame, to match the whole frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AdaptiveSampling {
    /// Noise threshold `t` (> 0): the noise of one sample's luminance by `measure` above which
    /// a pixel takes proportionally more samples.
    pub threshold: f64,
    /// Most samples a pixel takes, as a multiple of `spp` (≥ 1).
    pub max_factor: u32,
    /// The noise `t` is a threshold of.
    pub measure: NoiseMeasure,
    /// Adaptive splitting: the most path continuations a pixel's extra samples split into at
    /// their camera vertex (1, or no more than the first samples': off). By the linear measure,
    /// for an integrator whose camera samples split into `k₀ ≥ 2` (`Integrator::splits`), each
    /// pixel's extra samples split into the `k` of `k₀`, 2·`k₀` … `max_splits` that its
    /// neighbours' first samples find the most efficient ([`best_splits`],
    /// [`AdaptiveSampling::extra_at`]).
    pub max_splits: u32,
}

/// Largest [`AdaptiveSampling::max_factor`].
pub const MAX_ADAPTIVE_FACTOR: u32 = 1024;

/// A pixel's mean luminance and mean squared luminance over its first `spp` samples (what its
/// neighbours' counts read).
pub type Luma = [f32; 2];

impl AdaptiveSampling {
    /// The default of the direct integrator: `t` = 0.01 by the perceived measure, at most
    /// 16 × `spp` samples a pixel.
    pub const DEFAULT: AdaptiveSampling = AdaptiveSampling {
        threshold: 0.01,
        max_factor: 16,
        measure: NoiseMeasure::Perceived,
        max_splits: 1,
    };

    /// The default of the path tracer: `t` = 0.1 by the linear measure (a pixel whose one
    /// sample's noise exceeds a tenth of the frame's mean level takes more), at most 16 ×
    /// `spp`. A path-traced render takes 2.5–6 × `spp` samples on average at the default (the
    /// shader ball, the clutter scenes, the Cornell box).
    pub const PATH: AdaptiveSampling = AdaptiveSampling {
        threshold: 0.1,
        max_factor: 16,
        measure: NoiseMeasure::Linear,
        max_splits: 8,
    };

    /// The default by `measure`: [`AdaptiveSampling::DEFAULT`] (perceived) or
    /// [`AdaptiveSampling::PATH`] (linear).
    pub fn default_for(measure: NoiseMeasure) -> AdaptiveSampling {
        match measure {
            NoiseMeasure::Perceived => AdaptiveSampling::DEFAULT,
            NoiseMeasure::Linear => AdaptiveSampling::PATH,
        }
    }

    /// No extra samples: every pixel takes `spp` (`max_factor` 1).
    pub const OFF: AdaptiveSampling = AdaptiveSampling {
        threshold: 0.01,
        max_factor: 1,
        measure: NoiseMeasure::Perceived,
        max_splits: 1,
    };

    /// Whether a pixel can take more than `spp` samples (`max_factor` > 1).
    pub fn is_on(&self) -> bool {
        self.max_factor > 1
    }

    /// How far a pixel's neighbours reach, in pixels across and down: 1 (the 3 × 3 block) by
    /// the perceived measure, 3 (7 × 7) by the linear one.
    pub fn reach(&self) -> usize {
        match self.measure {
            NoiseMeasure::Perceived => 1,
            NoiseMeasure::Linear => 3,
        }
    }

    /// Mean luminance below which the threshold stops shrinking (`μ_min`): black regions are
    /// held to the noise allowed at this level, not to 0.
    pub const MIN_MEAN: f64 = 1e-3;

    /// Samples a pixel takes in all given its neighbours' pooled luminance statistics
    /// (`count` samples, `mean`, unbiased `variance`) and its base `spp`, by the perceived
    /// measure: [`AdaptiveSampling::for_noise`] of `σ / √max(μ, μ_min)`; `spp` when fewer than
    /// 2 samples were pooled.
    pub fn samples(&self, spp: u32, count: u32, mean: f64, variance: f64) -> u32 {
        if count < 2 {
            return spp;
        }
        let sigma = variance.max(0.0).sqrt();
        self.for_noise(spp, sigma / mean.max(Self::MIN_MEAN).sqrt())
    }

    /// Samples a pixel takes in all whose one sample's noise by the measure is `noise`:
    /// `min(⌈spp · noise / t⌉, max_factor · spp)` (and at most [`MAX_SPP`]), `spp` when that is
    /// no more than `spp` or `noise` is NaN.
    pub fn for_noise(&self, spp: u32, noise: f64) -> u32 {
        let cap = spp
            .saturating_mul(self.max_factor.max(1))
            .min(MAX_SPP)
            .max(spp);
        let n = spp as f64 * noise / self.threshold;
        if n.is_nan() || n <= spp as f64 {
            spp
        } else if n >= cap as f64 {
            cap
        } else {
            n.ceil() as u32
        }
    }

    /// Samples cell `[i, j]` of the `[w, h]` grid `first` (its pixels' first-pass [`Luma`])
    /// takes in all, each of them having taken `spp`, from the pooled statistics of its
    /// neighbours within [`AdaptiveSampling::reach`] ([`neighbours`]) by
    /// [`AdaptiveSampling::measure`]; `frame_mean` is the frame's mean luminance `μ̄` of the
    /// linear measure ([`FramePilot`]; unused by the perceived one). By the linear measure a
    /// frame of mean ≤ 0 takes no extra samples.
    pub fn samples_at(
        &self,
        spp: u32,
        first: &[Luma],
        [w, h]: [usize; 2],
        [i, j]: [usize; 2],
        frame_mean: f64,
    ) -> u32 {
        let nb = neighbours(first, [w, h], [i, j], self.reach());
        let m = nb.count * spp;
        if m < 2 {
            return spp;
        }
        match self.measure {
            NoiseMeasure::Perceived => {
                let k = nb.count as f64;
                self.samples(spp, m, nb.y / k, pooled_variance(&nb, spp))
            }
            NoiseMeasure::Linear => {
                if frame_mean.is_nan() || frame_mean <= 0.0 {
                    return spp;
                }
                self.for_noise(spp, linear_variance(&nb, spp).sqrt() / frame_mean)
            }
        }
    }

    /// A pixel's extra samples with adaptive splitting ([`AdaptiveSampling::max_splits`]):
    /// cell `[i, j]` of the grid of `first` and `splits` (the cells' first-pass [`Luma`] and
    /// [`SplitStats`]), whose first samples split into `first_splits` continuations. Without
    /// splitting (the perceived measure, `max_splits` 1, `first_splits` 1, no statistics), or
    /// when the first samples' split count is the best, the count of
    /// [`AdaptiveSampling::samples_at`].
    ///
    /// From the neighbours' first samples (the block of [`neighbours`], the cell itself left
    /// out): `V` the variance of one sample's luminance as [`NoiseMeasure::Linear`] pools it
    /// (with one sample a pixel, the spread across pixels: `V_a` then errs high, towards fewer
    /// splits), `V_c` the mean spread of one continuation's luminance (`SplitStats[0]`), so
    /// `V = V_a + V_c/k₀` (`V_a` what the camera ray and its vertex add, `k₀ = first_splits`,
    /// `V_a` ≥ 0), and the rays a sample traces before its continuations `C_a` and a
    /// continuation `C_c`. A sample split into `k` has variance `V_k = V·(V_a + V_c/k)/(V_a +
    /// V_c/k₀)` and costs `C_k = C_a + k·C_c` rays; [`best_splits`] takes the `k` of least
    /// `V_k·C_k`. The pixel would take `n₀` samples in all with `k₀` (the count without
    /// splitting); its `m` extra ones with `k` instead carry weight `w = V/V_k` each against a
    /// first one (inverse-variance weights, from the neighbours only, so the pixel stays
    /// unbiased), and `m = (V_k/V)·(n₀·√(V·C_k₀/(V_k·C_k)) − spp)`: the precision `n₀/V` the
    /// pixel would reach, scaled by the square root of the efficiency gained — what minimises
    /// squared error plus rays at the rate the threshold sets.
    #[allow(clippy::too_many_arguments)]
    pub fn extra_at(
        &self,
        spp: u32,
        first: &[Luma],
        splits: &[SplitStats],
        first_splits: u32,
        [w, h]: [usize; 2],
        [i, j]: [usize; 2],
        frame_mean: f64,
    ) -> Extra {
        let n0 = self.samples_at(spp, first, [w, h], [i, j], frame_mean);
        let plain = Extra {
            n: n0,
            splits: 0,
            weight: 1.0,
        };
        if n0 <= spp
            || self.measure != NoiseMeasure::Linear
            || self.max_splits < 2
            || first_splits < 2
            || splits.len() != first.len()
        {
            return plain;
        }
        let nb = neighbours(first, [w, h], [i, j], self.reach());
        let count = nb.count as f64;
        let s = spp as f64;
        let v = linear_variance(&nb, spp);
        let mut sum = [0.0f64; 3];
        for c in block([w, h], [i, j], self.reach()) {
            for (a, b) in sum.iter_mut().zip(splits[c]) {
                *a += b as f64;
            }
        }
        let [v_c, c_a, c_c] = sum.map(|x| x / count);
        let k0 = first_splits as f64;
        let v_a = (v - v_c / k0).max(0.0);
        let k = best_splits([v_a, v_c], [c_a, c_c], first_splits, self.max_splits);
        let kf = k as f64;
        let model0 = v_a + v_c / k0;
        let (cost0, cost) = (c_a + k0 * c_c, c_a + kf * c_c);
        if k == first_splits || model0 <= 0.0 || cost0 <= 0.0 || cost <= 0.0 {
            return plain;
        }
        // V_k / V, and the efficiency V·C_k₀ / (V_k·C_k) gained
        let ratio = (v_a + v_c / kf) / model0;
        let gain = cost0 / (ratio * cost);
        let m = ratio * (n0 as f64 * gain.sqrt() - s);
        let cap = self.for_noise(spp, f64::INFINITY) - spp;
        let m = if m.is_nan() || m < 1.0 {
            1
        } else {
            (m.ceil() as u32).min(cap)
        };
        Extra {
            n: spp + m,
            splits: k,
            weight: 1.0 / ratio,
        }
    }
}

/// A pixel's extra samples ([`AdaptiveSampling::extra_at`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Extra {
    /// Samples in all, its first `spp` included (no more than `spp`: none).
    pub n: u32,
    /// Path continuations each extra sample splits into (0: as the first ones).
    pub splits: u32,
    /// Weight of an extra sample against a first one in the pixel's mean (1 without splitting).
    pub weight: f64,
}

/// The unbiased variance of all the samples pooled in `nb` (`spp` each), within and across
/// pixels: `(E[Y²] − E[Y]²)·n/(n − 1)` over their `n` samples.
fn pooled_variance(nb: &Neighbours, spp: u32) -> f64 {
    let k = nb.count as f64;
    let (mean, e2) = (nb.y / k, nb.y2 / k);
    let n = k * spp as f64;
    ((e2 - mean * mean) * n / (n - 1.0)).max(0.0)
}

/// The variance of one sample's luminance by [`NoiseMeasure::Linear`]: the spread within the
/// pixels of `nb`, pooled (`mean_j (E_j[Y²] − E_j[Y]²)·s/(s − 1)`, `s = spp`), or with one
/// sample a pixel, where no spread within is known, [`pooled_variance`].
fn linear_variance(nb: &Neighbours, spp: u32) -> f64 {
    if spp < 2 {
        return pooled_variance(nb, spp);
    }
    let (k, s) = (nb.count as f64, spp as f64);
    ((nb.y2 - nb.yy) / k * s / (s - 1.0)).max(0.0)
}

/// The continuations `k` among `k₀`, 2·`k₀`, 4·`k₀` … ≤ `max` of least `(v_a + v_c/k) · (c_a +
/// k·c_c)`: a camera sample's variance (`v_a` from its camera ray and vertex, `v_c` that of one
/// continuation) times its rays (`c_a` before the continuations, `c_c` a continuation) — the
/// squared error for a given number of rays, whose continuous minimum is at
/// `k = √((v_c·c_a)/(v_a·c_c))`. The smaller `k` on a tie; `k₀` when nothing is finite. Counts
/// double from `k₀`, so that a camera sample's continuations stay a net of the pixel's points;
/// fewer than `k₀` are not tried (on the clutter scenes, where the estimate chose one for about a
/// fifth of the pixels, time × variance rose by 4 %; BENCHMARKS.md).
pub fn best_splits([v_a, v_c]: [f64; 2], [c_a, c_c]: [f64; 2], k0: u32, max: u32) -> u32 {
    let k0 = k0.max(1);
    let mut best = (f64::INFINITY, k0);
    let mut k = k0;
    while k <= max {
        let kf = k as f64;
        let e = (v_a + v_c / kf) * (c_a + kf * c_c);
        if e < best.0 {
            best = (e, k);
        }
        k *= 2;
    }
    best.1
}

/// A pixel's first-pass statistics of the path tracer's continuations (adaptive splitting,
/// [`AdaptiveSampling::max_splits`]), means over its samples: the variance of one
/// continuation's luminance (each sample's unbiased estimate from its `k₀` continuations,
/// `Ctx::split`), the rays a sample traced before its continuations, and the rays one
/// continuation traced.
pub type SplitStats = [f32; 3];

/// The sums over the neighbours of a cell ([`neighbours`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Neighbours {
    /// How many there are.
    pub count: u32,
    /// Sum of their mean luminances `E_j[Y]`.
    pub y: f64,
    /// Sum of their mean squared luminances `E_j[Y²]`.
    pub y2: f64,
    /// Sum of the squares of their mean luminances `E_j[Y]²`.
    pub yy: f64,
}

impl Neighbours {
    #[inline(always)]
    fn add(&mut self, [y, y2]: Luma) {
        let y = y as f64;
        self.count += 1;
        self.y += y;
        self.y2 += y2 as f64;
        self.yy += y * y;
    }
}

/// The frame pilot of the linear noise measure ([`NoiseMeasure::Linear`]): the frame's mean
/// luminance `μ̄`, from one camera sample in every pixel at `(STRIDE·a + STRIDE/2,
/// STRIDE·b + STRIDE/2)` of the whole frame's window (`≈ 1/STRIDE²` of a sample a pixel), drawn
/// from points of its own ([`FramePilot::SALT`]) and not part of the image. Every band of a
/// frame draws the same pilot, so its counts are the whole frame's.
pub struct FramePilot;

impl FramePilot {
    /// Pixels between the pilot's samples, across and down.
    pub const STRIDE: u32 = 4;

    /// Key of the pilot's points (`SampleStream::pass`).
    pub const SALT: u64 = 0xB7E1_5162_8AED_2A6A;

    /// The pilot's first pixel coordinate along `[a, b)`: `a + STRIDE/2`, or the middle one
    /// when the range is shorter.
    pub fn first([a, b]: [u32; 2]) -> u32 {
        if b - a > Self::STRIDE / 2 {
            a + Self::STRIDE / 2
        } else {
            a + (b - a) / 2
        }
    }

    /// The pilot's pixel coordinates along `[a, b)`: every [`FramePilot::STRIDE`]-th from
    /// [`FramePilot::first`].
    pub fn along([a, b]: [u32; 2]) -> impl Iterator<Item = u32> + Clone {
        (Self::first([a, b])..b).step_by(Self::STRIDE as usize)
    }

    /// Whether coordinate `x` is one of [`FramePilot::along`]`([a, b])`.
    pub fn on([a, b]: [u32; 2], x: u32) -> bool {
        let f = Self::first([a, b]);
        (f..b).contains(&x) && (x - f).is_multiple_of(Self::STRIDE)
    }
}

/// The sums over the neighbours of cell `[i, j]` of the `[w, h]` grid `first` — the cells of
/// the `(2·reach + 1)²` block around it, clipped to the grid, but itself — row by row from the
/// top, left to right (one order for every pixel, so the sums do not depend on the tile).
#[inline]
pub fn neighbours(
    first: &[Luma],
    [w, h]: [usize; 2],
    [i, j]: [usize; 2],
    reach: usize,
) -> Neighbours {
    let mut nb = Neighbours::default();
    if reach == 1 && i > 0 && j > 0 && i + 1 < w && j + 1 < h {
        // Inside, 3 × 3: the 8 cells at fixed offsets.
        let c = j * w + i;
        for at in [
            c - w - 1,
            c - w,
            c - w + 1,
            c - 1,
            c + 1,
            c + w - 1,
            c + w,
            c + w + 1,
        ] {
            nb.add(first[at]);
        }
        return nb;
    }
    for c in block([w, h], [i, j], reach) {
        nb.add(first[c]);
    }
    nb
}

/// The cells of the `(2·reach + 1)²` block around cell `[i, j]` of a `[w, h]` grid (row-major
/// indices), clipped to the grid, but itself — row by row from the top, left to right.
#[inline]
fn block([w, h]: [usize; 2], [i, j]: [usize; 2], reach: usize) -> impl Iterator<Item = usize> {
    let cols = i.saturating_sub(reach)..(i + reach + 1).min(w);
    (j.saturating_sub(reach)..(j + reach + 1).min(h))
        .flat_map(move |nj| cols.clone().map(move |ni| (ni, nj)))
        .filter(move |&c| c != (i, j))
        .map(move |(ni, nj)| nj * w + ni)
}

/// The penumbra pilot (`RenderOptions::penumbra_samples`): light samples per light for a
/// pixel's samples, as a factor — `samples` where its pilot met a blocked shadow ray, else 1.
///
/// Before the pixel's samples (at least [`PenumbraPilot::MIN_SPP`]), a pilot camera sample
/// with [`PenumbraPilot::LIGHT_SAMPLES`] light samples per light, drawn from points of its own
/// ([`PenumbraPilot::PILOT_SALT`]) and not part of the estimate, looks at the pixel's shadow
/// rays; if some were blocked, every sample of the pixel takes `samples` light samples per
/// light, its points drawn from another scramble of the pixel's sets
/// ([`PenumbraPilot::SALT`], independent of the pilot's). The choice depends on the pilot's
/// random numbers only, so each sample stays an unbiased estimate, and the pixel's points stay
/// one stratified set per dimension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PenumbraPilot {
    /// Light samples per light in penumbrae, as a factor (1: no pilot).
    pub samples: u32,
}

impl PenumbraPilot {
    /// Light samples per light of the pilot's one camera sample.
    pub const LIGHT_SAMPLES: u32 = 4;

    /// Samples per pixel from which the pilot runs (below, its cost would outweigh it).
    pub const MIN_SPP: u32 = 8;

    /// Key of the pilot's points (`SampleStream::pass`).
    pub const PILOT_SALT: u64 = 0x1319_8A2E_0370_7344;

    /// Key of the samples of a pixel the pilot sent to the penumbra pass.
    pub const SALT: u64 = 0x243F_6A88_85A3_08D3;

    /// Whether the pilot runs for pixels of `spp` samples.
    pub fn runs(&self, spp: u32) -> bool {
        self.samples > 1 && spp >= Self::MIN_SPP
    }

    /// The factor of a pixel whose pilot found `blocked` shadow rays blocked.
    pub fn factor(&self, blocked: u64) -> u32 {
        if blocked > 0 { self.samples } else { 1 }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn adaptive_sample_counts() {
        let a = AdaptiveSampling {
            threshold: 0.1,
            max_factor: 16,
            measure: NoiseMeasure::Perceived,
            max_splits: 1,
        };
        // n = spp · σ / (t √μ): 4 · 0.5 / (0.1 · √0.25) = 40.
        assert_eq!(a.samples(4, 8, 0.25, 0.25), 40);
        // 4 · 0.02 / (0.1 · √0.04) = 4 → no more than spp.
        assert_eq!(a.samples(4, 8, 0.04, 0.0004), 4);
        // 4 · 0.021 / (0.1 · 0.2) = 4.2 → rounded up to 5.
        assert_eq!(a.samples(4, 8, 0.04, 0.021 * 0.021), 5);
        // Capped at 16 × spp.
        assert_eq!(a.samples(4, 8, 0.25, 100.0), 64);
        // Black neighbourhoods are held to μ_min = 1e-3: 1 · 0.01 / (0.1 · √1e-3) = 3.16 → 4.
        assert_eq!(a.samples(1, 8, 0.0, 1e-4), 4);
        // Fewer than 2 pooled samples, no variance, or NaN: spp.
        assert_eq!(a.samples(4, 1, 0.25, 0.25), 4);
        assert_eq!(a.samples(4, 8, 0.25, 0.0), 4);
        assert_eq!(a.samples(4, 8, 0.25, f64::NAN), 4);
        assert_eq!(a.samples(4, 8, 0.25, f64::INFINITY), 64);
        // The count scales with spp: twice the spp, twice the samples.
        assert_eq!(a.samples(8, 8, 0.25, 0.25), 80);
        // The cap never exceeds MAX_SPP, and never falls below spp.
        assert_eq!(a.samples(MAX_SPP, 8, 0.25, 1e9), MAX_SPP);
        let one = AdaptiveSampling { max_factor: 1, ..a };
        assert_eq!(one.samples(4, 8, 0.25, 0.25), 4);
    }

    /// A cell's count pools its neighbours' samples: 8 neighbours of 4 samples, luminance 0.25
    /// each with E[Y²] = 0.125, give μ = 0.25 and σ² = (0.125 − 0.0625)·32/31.
    #[test]
    fn counts_pool_the_neighbours() {
        let a = AdaptiveSampling {
            threshold: 0.1,
            max_factor: 16,
            measure: NoiseMeasure::Perceived,
            max_splits: 1,
        };
        let first = vec![[0.25f32, 0.125f32]; 9];
        let var = (0.125 - 0.0625) * 32.0 / 31.0;
        assert_eq!(
            a.samples_at(4, &first, [3, 3], [1, 1], 0.0),
            a.samples(4, 32, 0.25, var)
        );
        // A lone pixel has no neighbours: spp.
        assert_eq!(a.samples_at(4, &first[..1], [1, 1], [0, 0], 0.0), 4);
    }

    /// `best_splits` against the products written out: `(v_a + v_c/k)·(c_a + k·c_c)` with
    /// `v_a` = 1, `v_c` = 16, `c_a` = `c_c` = 1 is 27, 25, 27 at k = 2, 4, 8 (the continuous
    /// optimum √16 = 4).
    #[test]
    fn best_splits_minimise_variance_times_rays() {
        assert_eq!(best_splits([1.0, 16.0], [1.0, 1.0], 2, 8), 4);
        // Up to `max` only, and counts double from k₀ (v_c = 64 from 3: 89.3, 81.7, 82.3 at
        // 3, 6, 12 → 6).
        assert_eq!(best_splits([1.0, 16.0], [1.0, 1.0], 2, 2), 2);
        assert_eq!(best_splits([1.0, 64.0], [1.0, 1.0], 3, 16), 6);
        // No spread among the continuations: more cost no less variance, k₀; all of the
        // variance theirs: as many as allowed.
        assert_eq!(best_splits([1.0, 0.0], [1.0, 1.0], 2, 8), 2);
        assert_eq!(best_splits([0.0, 1.0], [1.0, 1.0], 2, 8), 8);
        // Cheap continuations take more: c_c = 1/16 moves the optimum to 16.
        assert_eq!(best_splits([1.0, 16.0], [1.0, 1.0 / 16.0], 2, 64), 16);
        // Nothing finite: k₀.
        assert_eq!(best_splits([f64::NAN, 1.0], [1.0, 1.0], 2, 8), 2);
    }

    /// Adaptive splitting's count, continuations and weight against the formulas of
    /// `extra_at` worked by hand, on a 7 × 7 grid of equal cells (centre (3, 3), 48 neighbours
    /// of 4 samples): within-pixel variance V = 0.03 (E[Y] = 0.5, E[Y²] = 0.25 + 0.0225), one
    /// continuation's spread V_c = 0.056, 2 rays before the continuations and 5 in each, k₀ = 2.
    /// V_a = 0.03 − 0.028 = 0.002; V_k·C_k = 0.360, 0.352, 0.378 at k = 2, 4, 8 → k = 4. The
    /// count without splitting n₀ = ⌈4·√0.03/(0.1·0.5)⌉ = 14; V_4/V = 0.016/0.03 = 8/15, the
    /// efficiency gained 0.360/0.352; m = (8/15)·(14·√(0.360/0.352) − 4) = 5.42 → 6 extra
    /// samples of weight 15/8.
    #[test]
    fn extra_samples_split_where_their_continuations_are_noisy() {
        let a = AdaptiveSampling::PATH;
        assert_eq!(a.max_splits, 8);
        let (w, h) = (7usize, 7usize);
        let first: Vec<Luma> = vec![[0.5, 0.25 + 0.0225]; w * h];
        let stats: Vec<SplitStats> = vec![[0.056, 2.0, 5.0]; w * h];
        let e = a.extra_at(4, &first, &stats, 2, [w, h], [3, 3], 0.5);
        assert_eq!(a.samples_at(4, &first, [w, h], [3, 3], 0.5), 14);
        let m = 8.0 / 15.0 * (14.0 * f64::sqrt(0.360 / 0.352) - 4.0);
        assert!((m - 5.42).abs() < 0.01, "{m}");
        assert_eq!((e.n, e.splits), (4 + 6, 4));
        assert!((e.weight - 15.0 / 8.0).abs() < 1e-4, "{}", e.weight);
        // (the pixel's own statistics are not read: any value there gives the same)
        let mut own = stats.clone();
        own[3 * w + 3] = [1e9, 0.0, 0.0];
        assert_eq!(a.extra_at(4, &first, &own, 2, [w, h], [3, 3], 0.5), e);
        // Without splitting — off, first samples that do not split, no statistics, the
        // perceived measure, or continuations with no spread — the plain count, weight 1.
        let plain = Extra {
            n: 14,
            splits: 0,
            weight: 1.0,
        };
        let off = AdaptiveSampling { max_splits: 1, ..a };
        assert_eq!(
            off.extra_at(4, &first, &stats, 2, [w, h], [3, 3], 0.5),
            plain
        );
        assert_eq!(a.extra_at(4, &first, &stats, 1, [w, h], [3, 3], 0.5), plain);
        assert_eq!(a.extra_at(4, &first, &[], 2, [w, h], [3, 3], 0.5), plain);
        let quiet = vec![[0.0, 2.0, 5.0]; w * h];
        assert_eq!(a.extra_at(4, &first, &quiet, 2, [w, h], [3, 3], 0.5), plain);
        let perceived = AdaptiveSampling {
            measure: NoiseMeasure::Perceived,
            ..a
        };
        assert_eq!(
            perceived.extra_at(4, &first, &stats, 2, [w, h], [3, 3], 0.5),
            Extra {
                n: perceived.samples_at(4, &first, [w, h], [3, 3], 0.5),
                ..plain
            }
        );
        // One sample a pixel: the pooled spread stands in for the one within pixels, V =
        // 0.0225·48/47 = 0.02298 < V_c/2, so V_a = 0 and k = 8; n₀ = ⌈√0.02298/0.05⌉ = 4,
        // V_8/V = 1/4, gain 12/(42/4); m = (4·√(8/7) − 1)/4 = 0.82 → 1 sample of weight 4.
        let one = a.extra_at(1, &first, &stats, 2, [w, h], [3, 3], 0.5);
        assert_eq!(a.samples_at(1, &first, [w, h], [3, 3], 0.5), 4);
        assert_eq!((one.n, one.splits), (2, 8));
        assert!((one.weight - 4.0).abs() < 1e-9, "{}", one.weight);
        // A pixel that takes no extra sample splits no further.
        let calm: Vec<Luma> = vec![[0.5, 0.25]; w * h];
        let none = a.extra_at(4, &calm, &stats, 2, [w, h], [3, 3], 0.5);
        assert_eq!((none.n, none.splits, none.weight), (4, 0, 1.0));
    }

    /// The linear measure: `n = ⌈spp · σ_w / (t · μ̄)⌉` with `σ_w²` the neighbours' mean
    /// within-pixel variance, whatever their means (an edge between them adds nothing).
    #[test]
    fn linear_counts_read_the_spread_within_pixels() {
        let a = AdaptiveSampling {
            threshold: 0.1,
            max_factor: 16,
            measure: NoiseMeasure::Linear,
            max_splits: 1,
        };
        assert_eq!(a.reach(), 3);
        // 7 × 7 cells; the left half dark (E[Y] = 0.1, E[Y²] = 0.02: variance 0.01), the right
        // bright (E[Y] = 2, E[Y²] = 4.09: variance 0.09), 4 samples each.
        let (w, h) = (7usize, 7usize);
        let first: Vec<Luma> = (0..w * h)
            .map(|c| if c % w < 3 { [0.1, 0.02] } else { [2.0, 4.09] })
            .collect();
        // The centre (3, 3) pools 48 cells: 21 dark, 27 bright (itself left out).
        let within = (21.0 * 0.01 + 27.0 * 0.09) / 48.0 * 4.0 / 3.0;
        let frame_mean = 0.5;
        let expected = (4.0 * f64::sqrt(within) / (0.1 * frame_mean)).ceil() as u32;
        assert_eq!(
            a.samples_at(4, &first, [w, h], [3, 3], frame_mean),
            expected
        );
        assert_eq!(expected, 22);
        // A twice brighter frame: half the noise, half the samples (⌈10.8⌉).
        assert_eq!(a.samples_at(4, &first, [w, h], [3, 3], 1.0), 11);
        // No light in the frame, or no pilot: spp.
        for m in [0.0, -1.0, f64::NAN] {
            assert_eq!(a.samples_at(4, &first, [w, h], [3, 3], m), 4);
        }
        // Pixels of equal means and no spread within: spp, where the perceived measure's
        // pooled spread would see the edge between them.
        let edge: Vec<Luma> = (0..w * h)
            .map(|c| if c % w < 3 { [0.1, 0.01] } else { [2.0, 4.0] })
            .collect();
        assert_eq!(a.samples_at(4, &edge, [w, h], [3, 3], frame_mean), 4);
        let perceived = AdaptiveSampling {
            measure: NoiseMeasure::Perceived,
            ..a
        };
        assert!(perceived.samples_at(4, &edge, [w, h], [3, 3], 0.0) > 4);
        // One sample a pixel: no spread within is known, the pooled one stands in.
        let one: Vec<Luma> = (0..w * h)
            .map(|c| [(c % 2) as f32, (c % 2) as f32])
            .collect();
        let nb = neighbours(&one, [w, h], [3, 3], 3);
        let (k, m) = (nb.count as f64, nb.y / nb.count as f64);
        let pooled = (nb.y2 / k - m * m) * k / (k - 1.0);
        assert_eq!(
            a.samples_at(1, &one, [w, h], [3, 3], 1.0),
            a.for_noise(1, pooled.sqrt())
        );
    }

    #[test]
    fn frame_pilot_pixels() {
        assert_eq!(FramePilot::along([0, 10]).collect::<Vec<_>>(), [2, 6]);
        assert_eq!(FramePilot::along([5, 6]).collect::<Vec<_>>(), [5]);
        assert_eq!(FramePilot::along([3, 5]).collect::<Vec<_>>(), [4]);
        assert_eq!(FramePilot::along([3, 3]).count(), 0);
        for r in [[0, 10], [5, 6], [3, 5], [7, 40]] {
            for x in r[0]..r[1] {
                assert_eq!(FramePilot::on(r, x), FramePilot::along(r).any(|p| p == x));
            }
        }
    }

    #[test]
    fn pilot_rules() {
        let p = PenumbraPilot { samples: 4 };
        assert!(p.runs(8) && !p.runs(7));
        assert!(!PenumbraPilot { samples: 1 }.runs(64));
        assert_eq!((p.factor(0), p.factor(3)), (1, 4));
    }

    /// The neighbourhood sums equal a direct count over the block clipped to the grid, inside
    /// (the 3 × 3 fast path), along edges and at corners, in grids down to one cell, for
    /// reaches 1 to 3.
    #[test]
    fn neighbour_sums_match_the_clipped_block() {
        for [w, h] in [[1, 1], [1, 4], [3, 1], [2, 2], [5, 4], [7, 6], [9, 8]] {
            let first: Vec<Luma> = (0..w * h)
                .map(|n| [(n * n % 11) as f32 + 0.25, (n % 7) as f32 * 1.5])
                .collect();
            for r in 1..=3usize {
                for j in 0..h {
                    for i in 0..w {
                        let mut want = Neighbours::default();
                        let (r, i, j) = (r as i64, i as i64, j as i64);
                        for nj in j - r..=j + r {
                            for ni in i - r..=i + r {
                                let inside =
                                    (0..w as i64).contains(&ni) && (0..h as i64).contains(&nj);
                                if inside && (ni, nj) != (i, j) {
                                    want.add(first[nj as usize * w + ni as usize]);
                                }
                            }
                        }
                        let (r, i, j) = (r as usize, i as usize, j as usize);
                        let expected_k = (i.min(r) + 1 + (w - 1 - i).min(r))
                            * (j.min(r) + 1 + (h - 1 - j).min(r))
                            - 1;
                        assert_eq!(want.count as usize, expected_k);
                        assert_eq!(
                            neighbours(&first, [w, h], [i, j], r),
                            want,
                            "{w}×{h} at {i},{j}, reach {r}"
                        );
                    }
                }
            }
        }
    }
}
