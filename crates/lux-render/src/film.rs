//! The film: the image's pixels, rendered in 16 × 16 tiles on rayon's pool, each pixel the
//! mean of its camera samples (box filter, stratified jitter), with the render's counters.
//!
//! With adaptive sampling ([`AdaptiveSampling`]) a render is two passes: every pixel's `spp`
//! samples (and, for a band of rows, those of the row beyond each side), then each pixel's
//! extra samples, counted from its neighbours' first-pass luminances.
//!
//! Determinism: every random number is a function of (seed, pixel, sample, dimension)
//! ([`crate::sampler`]) and pixels are independent, so the image is bit-identical for any
//! thread count and tile order.

use crate::camera::Camera;
use crate::image_io::ImageRgba;
use crate::integrator::{CameraRay, Integrator, TileRays};
use crate::sampler::{Dim, SampleStream};
use crate::settings::AdaptiveSampling;
use crate::visibility::ClearPatches;
use glam::{DVec3, DVec4};
use rayon::prelude::*;
use std::sync::Mutex;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

/// Tile side in pixels.
pub const TILE: u32 = 16;

/// Light samples per light of a pixel's penumbra pilot, one camera sample
/// ([`Film::penumbra_samples`]).
const PILOT_LIGHT_SAMPLES: u32 = 4;

/// Keys of the penumbra pilot's points and of the samples of a pixel it sent to the penumbra
/// pass ([`SampleStream::pass`]).
const PILOT_SALT: u64 = 0x1319_8A2E_0370_7344;
const PENUMBRA_SALT: u64 = 0x243F_6A88_85A3_08D3;

/// Key of a pixel's adaptive extra samples ([`SampleStream::pass`]): a scramble independent of
/// its first samples' and of the penumbra pilot's.
const ADAPTIVE_SALT: u64 = 0xA409_3822_299F_31D0;

/// Samples per pixel from which the penumbra pilot runs (below, its cost would outweigh it).
const PILOT_MIN_SPP: u32 = 8;

/// Counters of a finished render.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RenderStats {
    /// Pixels rendered.
    pub pixels: u64,
    /// Camera samples (pixels × spp, plus the adaptive extra samples).
    pub samples: u64,
    /// Adaptive extra samples among them ([`AdaptiveSampling`]).
    pub adaptive_samples: u64,
    /// Rays traced through the BVH: camera, shadow and BSDF rays.
    pub rays: u64,
    /// Shadow rays among them.
    pub shadow_rays: u64,
    /// Light samples drawn.
    pub light_samples: u64,
    /// Camera samples whose radiance came out NaN or infinite and were counted as black. Any
    /// non-zero count is a renderer or input defect: the luxtest and robustness tests require 0.
    pub non_finite_samples: u64,
    /// Wall-clock seconds of the render loop (scene preparation excluded).
    pub seconds: f64,
}

/// What one worker counts while it renders a tile (summed into [`RenderStats`]), and what it
/// remembers between the tile's samples.
#[derive(Clone, Debug, Default)]
pub struct Counters {
    /// Rays traced.
    pub rays: u64,
    /// Shadow rays among them.
    pub shadow: u64,
    /// Light samples drawn.
    pub light_samples: u64,
    /// Non-finite camera samples.
    pub non_finite: u64,
    /// Shadow rays that found an occluder (what the penumbra pass looks at).
    pub blocked: u64,
    /// The worker's patches of surface known to see a light unblocked, or not (`par_tiles`
    /// hands them from tile to tile).
    pub patches: ClearPatches,
    /// What the tile's camera rays can meet ([`Integrator::tile_rays`]).
    pub tile: TileRays,
}

/// The image being rendered: its size, the pixels to render, samples and seed.
#[derive(Clone, Copy, Debug)]
pub struct Film {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// The pixels to render, `[x0, y0, x1, y1)` (crop ∩ data window, maybe restricted to a band
    /// of rows); the rest stays 0 with alpha 0.
    pub window: [u32; 4],
    /// The rows `[y0, y1)` of the whole frame's window (crop ∩ data window): a band's adaptive
    /// pass reads its neighbours' first samples up to one row beyond it, within these.
    pub frame_rows: [u32; 2],
    /// Samples per pixel (with adaptive sampling, the least a pixel takes).
    pub spp: u32,
    /// Adaptive sampling ([`AdaptiveSampling::OFF`]: none).
    pub adaptive: AdaptiveSampling,
    /// Seed of every random number.
    pub seed: u64,
    /// The camera's linear exposure scale applied to every sample (UsdGeomCamera
    /// `ComputeLinearExposureScale`; ×1 is exact).
    pub exposure_scale: f64,
    /// Light samples per light in penumbrae ([`crate::settings::RenderOptions::penumbra_samples`];
    /// 1: no penumbra pass).
    pub penumbra_samples: u32,
}

/// A pixel after its first `spp` samples: the mean RGBA, the mean luminance and mean squared
/// luminance of the samples (what neighbours' adaptive counts read), and the penumbra factor
/// its extra samples keep. Only a tile's worth exists at a time: the RGBA goes to the image,
/// the luminances to a [`Luma`] grid, the factor to its own grid when the pilot can run.
#[derive(Clone, Copy, Debug, Default)]
struct FirstPass {
    rgba: [f32; 4],
    y: f32,
    y2: f32,
    factor: u32,
}

/// A pixel's mean luminance and mean squared luminance over its first `spp` samples.
type Luma = [f32; 2];

/// The count of the (up to 8) neighbours of cell `[i, j]` of the `[w, h]` grid `first` and the
/// sums of their luminances and squared luminances, row by row from the top, left to right
/// (one order for every pixel, so the sums do not depend on the tile).
#[inline]
fn neighbours(first: &[Luma], [w, h]: [usize; 2], [i, j]: [usize; 2]) -> (u32, f64, f64) {
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

/// Sums over a run of a pixel's camera samples: RGB radiance and alpha, luminance and its
/// square.
#[derive(Clone, Copy, Debug, Default)]
struct Sums {
    rgba: DVec4,
    y: f64,
    y2: f64,
}

/// The render's counters, summed over the workers.
#[derive(Default)]
struct Shared {
    rays: AtomicU64,
    shadow: AtomicU64,
    light_samples: AtomicU64,
    non_finite: AtomicU64,
    extra: AtomicU64,
}

impl Shared {
    fn add(&self, c: &Counters, extra: u64) {
        self.rays.fetch_add(c.rays, Ordering::Relaxed);
        self.shadow.fetch_add(c.shadow, Ordering::Relaxed);
        self.light_samples
            .fetch_add(c.light_samples, Ordering::Relaxed);
        self.non_finite.fetch_add(c.non_finite, Ordering::Relaxed);
        self.extra.fetch_add(extra, Ordering::Relaxed);
    }
}

/// A pixel's RGBA as stored in the image.
#[inline]
fn to_f32(v: DVec4) -> [f32; 4] {
    [v.x as f32, v.y as f32, v.z as f32, v.w as f32]
}

/// Puts a finished tile's results (row-major) into the pass's buffers: [`par_tiles`].
type StoreTile<'a, D, T> = dyn Fn(&mut D, [u32; 4], &[T]) + Sync + 'a;

/// Runs `f` over every pixel of `rect` (`[x0, y0, x1, y1)`) in 16 × 16 tiles on rayon's pool
/// and hands each finished tile's results (row-major) with its rectangle to `store`, which
/// puts them into `dest` (one tile at a time). `done` is called with each finished tile's
/// rectangle, after its counters (and the extra samples `f` reports) are added to `shared`.
/// Each tile's samples see what its camera rays can meet (`tile_rays`, in their [`Counters`]).
/// A finished tile is stored at once, so no frame-sized buffer is made besides `dest`. Each
/// worker's remembered patch answers (`memo[rayon::current_thread_index()]`) go from tile to
/// tile — each is a function of its key alone (integrator/patches.rs) — so that neighbouring
/// tiles share the cells on their edges, and the passes share theirs.
#[allow(clippy::too_many_arguments)]
fn par_tiles<T: Copy + Send, D: Send, F: Fn(u32, u32, &mut Counters, &mut u64) -> T + Sync>(
    rect: [u32; 4],
    shared: &Shared,
    memo: &[Mutex<ClearPatches>],
    tile_rays: &(dyn Fn([u32; 4]) -> TileRays + Sync),
    f: &F,
    done: &(dyn Fn([u32; 4]) + Sync),
    dest: &mut D,
    store: &StoreTile<'_, D, T>,
) {
    let [x0, y0, x1, y1] = rect;
    let mut tiles = Vec::new();
    let mut ty = y0;
    while ty < y1 {
        let mut tx = x0;
        while tx < x1 {
            tiles.push([tx, ty, (tx + TILE).min(x1), (ty + TILE).min(y1)]);
            tx += TILE;
        }
        ty += TILE;
    }
    let dest = Mutex::new(dest);
    // One tile per job: the adaptive pass's work sits in a few tiles (edges, penumbrae), and
    // rayon's default splitting leaves whole runs of them to one thread.
    tiles
        .par_iter()
        .with_max_len(1)
        .for_each(|&[tx0, ty0, tx1, ty1]| {
            // (the worker's remembered patch answers)
            let kept = rayon::current_thread_index().and_then(|i| memo.get(i));
            let patches = kept.map_or_else(ClearPatches::default, |m| {
                std::mem::take(&mut *m.lock().unwrap_or_else(|e| e.into_inner()))
            });
            let mut c = Counters {
                tile: tile_rays([tx0, ty0, tx1, ty1]),
                patches,
                ..Counters::default()
            };
            let mut extra = 0;
            let mut px = Vec::with_capacity(((tx1 - tx0) * (ty1 - ty0)) as usize);
            for y in ty0..ty1 {
                for x in tx0..tx1 {
                    px.push(f(x, y, &mut c, &mut extra));
                }
            }
            {
                // (a poisoned lock only means another tile's job panicked; its panic goes on)
                let mut d = dest.lock().unwrap_or_else(|e| e.into_inner());
                store(&mut d, [tx0, ty0, tx1, ty1], &px);
            }
            shared.add(&c, extra);
            if let Some(m) = kept {
                *m.lock().unwrap_or_else(|e| e.into_inner()) = std::mem::take(&mut c.patches);
            }
            done([tx0, ty0, tx1, ty1]);
        });
}

/// Copies the row-major results `px` of tile `[tx0, ty0, tx1, ty1]` into `dest`, a row-major
/// buffer `stride` wide whose first element is pixel `origin`.
fn copy_tile<T: Copy>(
    dest: &mut [T],
    stride: usize,
    origin: [u32; 2],
    [tx0, ty0, tx1, _]: [u32; 4],
    px: &[T],
) {
    let tw = (tx1 - tx0) as usize;
    for (row, chunk) in px.chunks(tw).enumerate() {
        let at = (ty0 - origin[1]) as usize + row;
        let from = at * stride + (tx0 - origin[0]) as usize;
        dest[from..from + tw].copy_from_slice(chunk);
    }
}

impl Film {
    /// Renders every pixel of the window with `integrator` through `camera`. `progress` is
    /// called (from worker threads) with the number of pixels finished by each tile of each
    /// pass ([`Film::passes`] passes in all).
    pub fn render(
        &self,
        camera: &Camera,
        integrator: &Integrator,
        progress: &(dyn Fn(u64) + Sync),
    ) -> (ImageRgba, RenderStats) {
        let [w, h] = [self.width, self.height];
        let [x0, y0, x1, y1] = self.window;
        let start = Instant::now();
        let shared = Shared::default();
        let mut pixels = vec![[0.0f32; 4]; w as usize * h as usize];
        let rw = (x1 - x0) as usize;
        let tile_rays = |rect| integrator.tile_rays(camera, rect);
        let memo: Vec<Mutex<ClearPatches>> = (0..rayon::current_num_threads())
            .map(|_| Mutex::default())
            .collect();
        match Some(self.adaptive).filter(|a| a.is_on() && x0 < x1 && y0 < y1) {
            None => {
                par_tiles(
                    self.window,
                    &shared,
                    &memo,
                    &tile_rays,
                    &|x, y, c, _| to_f32(self.pixel(camera, integrator, x, y, c, &mut |_| {})),
                    &|[a, b, c, d]| progress((c - a) as u64 * (d - b) as u64),
                    &mut pixels,
                    &|d: &mut Vec<[f32; 4]>, rect, px| copy_tile(d, w as usize, [0, 0], rect, px),
                );
            }
            Some(adaptive) => {
                // First pass: the window's rows and one row beyond each side (within the
                // frame's window), so a band reads the neighbours the whole frame reads. The
                // window's pixels take their first-pass means, which the second pass updates
                // where it adds samples; every row's luminances go to `luma`, the penumbra
                // factors (when the pilot can run) to `factors`.
                let hy0 = y0.saturating_sub(1).max(self.frame_rows[0]).min(y0);
                let hy1 = (y1 + 1).min(self.frame_rows[1]).max(y1);
                let rows = (hy1 - hy0) as usize;
                let mut luma: Vec<Luma> = vec![[0.0; 2]; rw * rows];
                let mut factors: Vec<u32> = if self.pilot_runs() {
                    vec![1; rw * rows]
                } else {
                    Vec::new()
                };
                par_tiles(
                    [x0, hy0, x1, hy1],
                    &shared,
                    &memo,
                    &tile_rays,
                    &|x, y, c, _| self.first_pass(camera, integrator, x, y, c),
                    &|[a, b, c, d]| {
                        let rows = d.min(y1).saturating_sub(b.max(y0));
                        progress((c - a) as u64 * rows as u64)
                    },
                    &mut (&mut pixels, &mut luma, &mut factors),
                    &|(pixels, luma, factors), [tx0, ty0, tx1, _], px: &[FirstPass]| {
                        let tw = (tx1 - tx0) as usize;
                        for (row, first) in px.chunks(tw).enumerate() {
                            let y = ty0 + row as u32;
                            let at = (y - hy0) as usize * rw + (tx0 - x0) as usize;
                            for (l, p) in luma[at..at + tw].iter_mut().zip(first) {
                                *l = [p.y, p.y2];
                            }
                            if !factors.is_empty() {
                                for (f, p) in factors[at..at + tw].iter_mut().zip(first) {
                                    *f = p.factor;
                                }
                            }
                            if (y0..y1).contains(&y) {
                                let from = y as usize * w as usize + tx0 as usize;
                                for (q, p) in pixels[from..from + tw].iter_mut().zip(first) {
                                    *q = p.rgba;
                                }
                            }
                        }
                    },
                );
                // Second pass: each pixel's extra samples, counted from its neighbours' pooled
                // luminance statistics; a pixel that takes some becomes the mean of all its
                // samples.
                par_tiles(
                    self.window,
                    &shared,
                    &memo,
                    &tile_rays,
                    &|x, y, c, extra| {
                        let (i, j) = ((x - x0) as usize, (y - hy0) as usize);
                        let (k, sy, sy2) = neighbours(&luma, [rw, rows], [i, j]);
                        let m = k * self.spp;
                        let (mean, var) = if k == 0 {
                            (0.0, 0.0)
                        } else {
                            let mean = sy / k as f64;
                            let e2 = sy2 / k as f64;
                            let n = m as f64;
                            (mean, ((e2 - mean * mean) * n / (n - 1.0).max(1.0)).max(0.0))
                        };
                        let n = adaptive.samples(self.spp, m, mean, var);
                        if n <= self.spp {
                            return None;
                        }
                        let ne = n - self.spp;
                        *extra += ne as u64;
                        let factor = factors.get(j * rw + i).copied().unwrap_or(1);
                        let sums = self.samples(
                            camera,
                            integrator,
                            [x, y],
                            [ne, factor],
                            ADAPTIVE_SALT,
                            c,
                            &mut |_| {},
                        );
                        Some((n, sums.rgba))
                    },
                    &|[a, b, c, d]| progress((c - a) as u64 * (d - b) as u64),
                    &mut pixels,
                    &|pixels, [tx0, ty0, tx1, _], px: &[Option<(u32, DVec4)>]| {
                        let tw = (tx1 - tx0) as usize;
                        for (row, second) in px.chunks(tw).enumerate() {
                            let from = (ty0 as usize + row) * w as usize + tx0 as usize;
                            for (q, s) in pixels[from..from + tw].iter_mut().zip(second) {
                                if let Some((n, sums)) = *s {
                                    let base =
                                        DVec4::from_array(q.map(f64::from)) * self.spp as f64;
                                    *q = to_f32((base + sums) / n as f64);
                                }
                            }
                        }
                    },
                );
            }
        }
        let npx = (x1 - x0) as u64 * (y1 - y0) as u64;
        let extra = shared.extra.load(Ordering::Relaxed);
        let stats = RenderStats {
            pixels: npx,
            samples: npx * self.spp as u64 + extra,
            adaptive_samples: extra,
            rays: shared.rays.load(Ordering::Relaxed),
            shadow_rays: shared.shadow.load(Ordering::Relaxed),
            light_samples: shared.light_samples.load(Ordering::Relaxed),
            non_finite_samples: shared.non_finite.load(Ordering::Relaxed),
            seconds: start.elapsed().as_secs_f64(),
        };
        (
            ImageRgba {
                width: w as usize,
                height: h as usize,
                pixels,
            },
            stats,
        )
    }

    /// Passes over the window a render makes: 2 with adaptive sampling that can add samples
    /// (`max_factor` > 1), else 1. Progress reports every pixel once per pass.
    pub fn passes(&self) -> u32 {
        if self.adaptive.is_on() { 2 } else { 1 }
    }

    /// Whether a pixel's penumbra pilot runs ([`Film::penumbra_factor`]): penumbra samples
    /// asked for, and at least PILOT_MIN_SPP samples a pixel.
    fn pilot_runs(&self) -> bool {
        self.penumbra_samples > 1 && self.spp >= PILOT_MIN_SPP
    }

    /// A pixel's first `spp` samples (adaptive sampling's first pass).
    fn first_pass(
        &self,
        camera: &Camera,
        integrator: &Integrator,
        x: u32,
        y: u32,
        c: &mut Counters,
    ) -> FirstPass {
        let (factor, s) = self.first_samples(camera, integrator, [x, y], c, &mut |_| {});
        let k = 1.0 / self.spp as f64;
        FirstPass {
            rgba: to_f32(s.rgba / self.spp as f64),
            y: (s.y * k) as f32,
            y2: (s.y2 * k) as f32,
            factor,
        }
    }

    /// The mean of pixel `(x, y)`'s `spp` samples, RGB radiance and alpha; `each` sees every
    /// sample's (exposed, finite) radiance. (Without the adaptive extra samples.)
    #[inline]
    pub fn pixel(
        &self,
        camera: &Camera,
        integrator: &Integrator,
        x: u32,
        y: u32,
        c: &mut Counters,
        each: &mut dyn FnMut(DVec3),
    ) -> DVec4 {
        let (_, s) = self.first_samples(camera, integrator, [x, y], c, &mut |v| each(v));
        s.rgba / self.spp as f64
    }

    /// The penumbra factor of pixel `[x, y]` and the sums over its `spp` samples.
    #[inline]
    fn first_samples(
        &self,
        camera: &Camera,
        integrator: &Integrator,
        [x, y]: [u32; 2],
        c: &mut Counters,
        each: &mut impl FnMut(DVec3),
    ) -> (u32, Sums) {
        let factor = self.penumbra_factor(camera, integrator, x, y, c);
        let s = self.samples(
            camera,
            integrator,
            [x, y],
            [self.spp, factor],
            PENUMBRA_SALT,
            c,
            each,
        );
        (factor, s)
    }

    /// Light samples per light for pixel `(x, y)`'s samples, as a factor: `penumbra_samples`
    /// where its penumbra pilot met a blocked shadow ray, else 1.
    ///
    /// Penumbrae: before the pixel's samples (at least PILOT_MIN_SPP), a pilot camera sample
    /// with PILOT_LIGHT_SAMPLES light samples per light, drawn from points of its own and not
    /// part of the estimate, looks at the pixel's shadow rays; if some were blocked, every
    /// sample of the pixel takes `penumbra_samples` light samples per light, its points drawn
    /// from another scramble of the pixel's sets (independent of the pilot's). The choice
    /// depends on the pilot's random numbers only, so each sample stays an unbiased estimate,
    /// and the pixel's points stay one stratified set per dimension.
    fn penumbra_factor(
        &self,
        camera: &Camera,
        integrator: &Integrator,
        x: u32,
        y: u32,
        c: &mut Counters,
    ) -> u32 {
        if !self.pilot_runs() {
            return 1;
        }
        if c.tile.empty {
            // (its ray meets nothing: no shadow ray)
            c.rays += 1;
            return 1;
        }
        let index = y as u64 * self.width as u64 + x as u64;
        let blocked0 = c.blocked;
        let st = SampleStream::new(self.seed, index, 0, 1).pass(PILOT_SALT, PILOT_LIGHT_SAMPLES);
        let j = st.get2(Dim::Camera);
        let (o, d, tmin, tmax) = camera.ray(x as f64 + j[0], y as f64 + j[1]);
        integrator.li(&CameraRay { o, d, tmin, tmax }, &st, c);
        if c.blocked > blocked0 {
            self.penumbra_samples
        } else {
            1
        }
    }

    /// Sums over `n` camera samples of pixel `[x, y]` taking `factor` × the integrator's light
    /// samples per light: the pixel's stratified set of `n` points, rescrambled under `salt`
    /// when `factor > 1` or for adaptive extra samples (`salt` = ADAPTIVE_SALT).
    #[allow(clippy::too_many_arguments)]
    #[inline]
    fn samples(
        &self,
        camera: &Camera,
        integrator: &Integrator,
        [x, y]: [u32; 2],
        [n, factor]: [u32; 2],
        salt: u64,
        c: &mut Counters,
        each: &mut impl FnMut(DVec3),
    ) -> Sums {
        let mut sums = Sums::default();
        if c.tile.empty {
            // Every camera ray of the tile meets nothing (`TileRays::empty`): what `li` returns
            // for such a ray, black with alpha 0, without drawing or tracing it (the sums stay
            // 0, as adding those samples leaves them).
            c.rays += n as u64;
            let rgb = DVec3::ZERO * self.exposure_scale;
            (0..n).for_each(|_| each(rgb));
            return sums;
        }
        let index = y as u64 * self.width as u64 + x as u64;
        for s in 0..n {
            let mut st = SampleStream::new(self.seed, index, s, n);
            if factor > 1 || salt == ADAPTIVE_SALT {
                st = st.pass(salt, factor);
            }
            let j = st.get2(Dim::Camera);
            let (o, d, tmin, tmax) = camera.ray(x as f64 + j[0], y as f64 + j[1]);
            let (rgb, a) = integrator.li(&CameraRay { o, d, tmin, tmax }, &st, c);
            let rgb = if rgb.is_finite() {
                rgb * self.exposure_scale
            } else {
                c.non_finite += 1;
                DVec3::ZERO
            };
            each(rgb);
            let l = lux_math::luminance(rgb);
            sums.rgba += rgb.extend(a);
            sums.y += l;
            sums.y2 += l * l;
        }
        sums
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
