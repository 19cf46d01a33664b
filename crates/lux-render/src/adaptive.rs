//! Where a pixel's samples go: the two policies that give some pixels more than `spp`
//! samples, each a pure function of the scene, settings and seed (images stay bit-identical
//! for any thread count) that keeps every pixel an unbiased estimate.
//!
//! - [`AdaptiveSampling`]: after its first `spp` samples, a pixel whose neighbourhood is noisy
//!   or crosses an edge takes more (a second pass).
//! - [`PenumbraPilot`]: before its samples, a pilot camera sample per pixel decides whether it
//!   lies in a penumbra; such a pixel takes more light samples per light in all its samples.
//!
//! The tile loop (`tiles.rs`) runs both; this module holds their rules and constants.

use crate::sampler::MAX_SPP;

/// Adaptive sampling: where a pixel's samples go after its first `spp`.
///
/// Every pixel first takes `spp` samples. From the luminances `Y` of the samples of its (up to
/// 8) neighbours, `m` of them, pooled — mean `μ`, unbiased variance `σ²` (pixel noise and edges
/// across the neighbourhood alike) — the pixel then takes
///
/// `n = min(⌈spp · σ / (t · √max(μ, μ_min))⌉, max_factor · spp)`
///
/// samples in all (more than `spp` only), `t` = [`AdaptiveSampling::threshold`] and
/// `μ_min` = [`AdaptiveSampling::MIN_MEAN`]. `σ / √μ` is the noise of one sample in a
/// square-root (gamma 2) encoding of the image, where noise is seen about as the eye sees it
/// (the measure of Blender Cycles' adaptive sampling); samples go in proportion to it, the
/// allocation that minimises the summed squared error for a given number of samples
/// (`n ∝ σ`), wherever it exceeds `t`. So a render costs a multiple of `spp` set by the image,
/// not by `spp`: 1.4–2.5 × on the luxtest frames at the default.
///
/// The count depends on the neighbours' samples only, never on the pixel's own, and the
/// extra samples draw from an independent scramble of the pixel's points
/// ([`AdaptiveSampling::SALT`]): each pixel stays an unbiased estimate. A band of rows renders
/// its neighbours' first samples one row beyond it to match the whole frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AdaptiveSampling {
    /// Noise threshold `t` (> 0): the noise of one sample's luminance, relative to the square
    /// root of the neighbourhood's mean luminance (after exposure), above which a pixel takes
    /// proportionally more samples.
    pub threshold: f64,
    /// Most samples a pixel takes, as a multiple of `spp` (≥ 1).
    pub max_factor: u32,
}

/// Largest [`AdaptiveSampling::max_factor`].
pub const MAX_ADAPTIVE_FACTOR: u32 = 1024;

/// A pixel's mean luminance and mean squared luminance over its first `spp` samples (what its
/// neighbours' counts read).
pub type Luma = [f32; 2];

impl AdaptiveSampling {
    /// The default: `t` = 0.01, at most 16 × `spp` samples a pixel.
    pub const DEFAULT: AdaptiveSampling = AdaptiveSampling {
        threshold: 0.01,
        max_factor: 16,
    };

    /// No extra samples: every pixel takes `spp` (`max_factor` 1).
    pub const OFF: AdaptiveSampling = AdaptiveSampling {
        threshold: 0.01,
        max_factor: 1,
    };

    /// Key of a pixel's extra samples (`SampleStream::pass`): a scramble independent of its
    /// first samples' and of the penumbra pilot's.
    pub const SALT: u64 = 0xA409_3822_299F_31D0;

    /// Whether a pixel can take more than `spp` samples (`max_factor` > 1).
    pub fn is_on(&self) -> bool {
        self.max_factor > 1
    }

    /// Mean luminance below which the threshold stops shrinking (`μ_min`): black regions are
    /// held to the noise allowed at this level, not to 0.
    pub const MIN_MEAN: f64 = 1e-3;

    /// Samples a pixel takes in all given its neighbours' pooled luminance statistics
    /// (`count` samples, `mean`, unbiased `variance`) and its base `spp`: the formula of the
    /// type's doc, at least `spp`; `spp` when fewer than 2 samples were pooled.
    pub fn samples(&self, spp: u32, count: u32, mean: f64, variance: f64) -> u32 {
        let cap = spp
            .saturating_mul(self.max_factor.max(1))
            .min(MAX_SPP)
            .max(spp);
        let sigma = variance.max(0.0).sqrt();
        let n = spp as f64 * sigma / (self.threshold * mean.max(Self::MIN_MEAN).sqrt());
        if count < 2 || n.is_nan() || n <= spp as f64 {
            spp
        } else if n >= cap as f64 {
            cap
        } else {
            n.ceil() as u32
        }
    }

    /// Samples cell `[i, j]` of the `[w, h]` grid `first` (its pixels' first-pass [`Luma`])
    /// takes in all, each of them having taken `spp`: [`AdaptiveSampling::samples`] of the
    /// pooled statistics of its neighbours ([`neighbours`]).
    pub fn samples_at(
        &self,
        spp: u32,
        first: &[Luma],
        [w, h]: [usize; 2],
        [i, j]: [usize; 2],
    ) -> u32 {
        let (k, sy, sy2) = neighbours(first, [w, h], [i, j]);
        let m = k * spp;
        let (mean, var) = if k == 0 {
            (0.0, 0.0)
        } else {
            let mean = sy / k as f64;
            let e2 = sy2 / k as f64;
            let n = m as f64;
            (mean, ((e2 - mean * mean) * n / (n - 1.0).max(1.0)).max(0.0))
        };
        self.samples(spp, m, mean, var)
    }
}

/// The count of the (up to 8) neighbours of cell `[i, j]` of the `[w, h]` grid `first` and the
/// sums of their luminances and squared luminances, row by row from the top, left to right
/// (one order for every pixel, so the sums do not depend on the tile).
#[inline]
pub fn neighbours(first: &[Luma], [w, h]: [usize; 2], [i, j]: [usize; 2]) -> (u32, f64, f64) {
    let (mut sy, mut sy2) = (0.0f64, 0.0f64);
    if i > 0 && j > 0 && i + 1 < w && j + 1 < h {
        // Inside: the 8 cells at fixed offsets.
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
            let [y, y2] = first[at];
            sy += y as f64;
            sy2 += y2 as f64;
        }
        return (8, sy, sy2);
    }
    let mut k = 0;
    for nj in j.saturating_sub(1)..(j + 2).min(h) {
        for ni in i.saturating_sub(1)..(i + 2).min(w) {
            if (ni, nj) != (i, j) {
                let [y, y2] = first[nj * w + ni];
                k += 1;
                sy += y as f64;
                sy2 += y2 as f64;
            }
        }
    }
    (k, sy, sy2)
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
        };
        let first = vec![[0.25f32, 0.125f32]; 9];
        let var = (0.125 - 0.0625) * 32.0 / 31.0;
        assert_eq!(
            a.samples_at(4, &first, [3, 3], [1, 1]),
            a.samples(4, 32, 0.25, var)
        );
        // A lone pixel has no neighbours: spp.
        assert_eq!(a.samples_at(4, &first[..1], [1, 1], [0, 0]), 4);
    }

    #[test]
    fn pilot_rules() {
        let p = PenumbraPilot { samples: 4 };
        assert!(p.runs(8) && !p.runs(7));
        assert!(!PenumbraPilot { samples: 1 }.runs(64));
        assert_eq!((p.factor(0), p.factor(3)), (1, 4));
    }

    /// The neighbourhood sums equal a direct count over the 3 × 3 block clipped to the grid,
    /// inside (the fast path), along edges and at corners, in grids down to one cell.
    #[test]
    fn neighbour_sums_match_the_clipped_block() {
        for [w, h] in [[1, 1], [1, 4], [3, 1], [2, 2], [5, 4], [7, 6]] {
            let first: Vec<Luma> = (0..w * h)
                .map(|n| [(n * n % 11) as f32 + 0.25, (n % 7) as f32 * 1.5])
                .collect();
            for j in 0..h {
                for i in 0..w {
                    let (mut k, mut sy, mut sy2) = (0, 0.0, 0.0);
                    for nj in j as i64 - 1..=j as i64 + 1 {
                        for ni in i as i64 - 1..=i as i64 + 1 {
                            let inside = (0..w as i64).contains(&ni) && (0..h as i64).contains(&nj);
                            if inside && (ni, nj) != (i as i64, j as i64) {
                                let [y, y2] = first[nj as usize * w + ni as usize];
                                k += 1;
                                sy += y as f64;
                                sy2 += y2 as f64;
                            }
                        }
                    }
                    let expected_k = (i.min(1) + 1 + (w - 1 - i).min(1))
                        * (j.min(1) + 1 + (h - 1 - j).min(1))
                        - 1;
                    assert_eq!(k as usize, expected_k);
                    assert_eq!(
                        neighbours(&first, [w, h], [i, j]),
                        (k, sy, sy2),
                        "{w}×{h} at {i},{j}"
                    );
                }
            }
        }
    }
}
