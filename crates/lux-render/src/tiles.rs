//! The tile loop (pbrt-v4's image-tile integrator): the window's pixels in 16 × 16 tiles on
//! rayon's pool, each pixel the mean of its camera samples (box filter, stratified jitter)
//! through an [`Integrator`], into the [`Film`] with the integrator's splats, and the render's
//! counters ([`RenderStats`]).
//!
//! Before a tile's samples the visibility is asked what its camera rays can meet
//! ([`Visibility::tile`]); each worker's visibility scratch (its patch answers) goes from tile
//! to tile. With adaptive sampling ([`AdaptiveSampling`]) a render is two passes: every pixel's
//! `spp` samples (and, for a band of rows, those of the rows its neighbours reach beyond each
//! side), then each pixel's extra samples, counted from its neighbours' first-pass luminances
//! (and, by the linear noise measure, the frame's mean luminance from a sparse pilot over the
//! whole frame, [`FramePilot`]); the penumbra pilot ([`PenumbraPilot`]) sets a pixel's light
//! samples before its first. With adaptive splitting the first pass also keeps each pixel's
//! [`SplitStats`] (its path continuations' spread and rays, `Ctx::split`), from which a pixel's
//! extra samples take their continuation count and their weight in its mean
//! ([`AdaptiveSampling::extra_at`]).
//!
//! Determinism: every random number is a function of (seed, pixel, sample, dimension)
//! ([`crate::sampler`]), pixels are independent and splats sum in fixed point, so the image is
//! bit-identical for any thread count and tile order.

use crate::adaptive::{
    AdaptiveSampling, FramePilot, Luma, NoiseMeasure, PenumbraPilot, SplitStats,
};
use crate::camera::Camera;
use crate::film::{Film, Splat, Splats};
use crate::image_io::ImageRgba;
use crate::integrator::{CameraRay, Ctx, Integrator, SplitSums};
use crate::sampler::{Dim, SampleStream};
use crate::stats::{Counters, RenderStats};
use crate::visibility::{Scratch, Visibility};
use crate::world::World;
use glam::{DVec3, DVec4};
use rayon::prelude::*;
use std::sync::Mutex;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

/// Tile side in pixels.
pub const TILE: u32 = 16;

/// What a render samples: the image's size, the pixels to render, samples and seed.
#[derive(Clone, Copy, Debug)]
pub struct Frame {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// The pixels to render, `[x0, y0, x1, y1)` (crop ∩ data window, maybe restricted to a band
    /// of rows); the rest stays 0 with alpha 0.
    pub window: [u32; 4],
    /// The rows `[y0, y1)` of the whole frame's window (crop ∩ data window): a band's adaptive
    /// pass reads its neighbours' first samples up to `reach` rows beyond it
    /// ([`AdaptiveSampling::reach`]), and the linear measure's frame pilot all of them.
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
    /// The penumbra pilot ([`PenumbraPilot`]; `samples` 1: none).
    pub pilot: PenumbraPilot,
}

/// What a render reads: the camera, the scene, how it sees, and the integrator.
#[derive(Clone, Copy)]
pub struct Scene<'a, I: Integrator> {
    /// The camera rays come from.
    pub camera: &'a Camera,
    /// The prepared scene.
    pub world: World<'a>,
    /// The visibility the integrator uses (asked for each tile's hint).
    pub vis: &'a Visibility,
    /// The light transport.
    pub integrator: &'a I,
}

/// A pixel after its first `spp` samples: the mean RGBA, the mean luminance and mean squared
/// luminance of the samples (what neighbours' adaptive counts read), and the penumbra factor
/// its extra samples keep. Only a tile's worth exists at a time: the RGBA goes to the film,
/// the luminances to a [`Luma`] grid, the factor to its own grid when the pilot can run.
#[derive(Clone, Copy, Debug, Default)]
struct FirstPass {
    rgba: [f32; 4],
    y: f32,
    y2: f32,
    factor: u32,
    split: SplitStats,
}

/// Sums over a run of a pixel's camera samples: RGB radiance and alpha, luminance and its
/// square; the rays they traced, and the spread and rays of their path continuations
/// (`Ctx::split`, the spread exposed as the luminances).
#[derive(Clone, Copy, Debug, Default)]
struct Sums {
    rgba: DVec4,
    y: f64,
    y2: f64,
    rays: u64,
    spread: f64,
    continuation_rays: u64,
}

/// A run of a pixel's camera samples: `n` of them, taking `factor` × the integrator's light
/// samples per light, drawn from the pixel's stratified set of `n` points — rescrambled under
/// `salt` when there is one (penumbra samples, the frame pilot's), the `n` points after the
/// pixel's first `base` ([`SampleStream::after`]: adaptive extra samples), split into `splits`
/// path continuations each (0: the integrator's own; adaptive splitting).
#[derive(Clone, Copy, Debug)]
struct Run {
    n: u32,
    factor: u32,
    salt: Option<u64>,
    base: u32,
    splits: u32,
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

/// A pixel's RGBA as stored in the film.
#[inline]
fn to_f32(v: DVec4) -> [f32; 4] {
    [v.x as f32, v.y as f32, v.z as f32, v.w as f32]
}

/// Puts a finished tile's results (row-major) into the pass's buffers: [`Tiles::run`].
type StoreTile<'a, D, T> = dyn Fn(&mut D, [u32; 4], &[T]) + Sync + 'a;

/// One pass over a rectangle of pixels in tiles: what every tile of a pass shares.
struct Tiles<'r, 'a, I: Integrator> {
    scene: &'r Scene<'a, I>,
    shared: &'r Shared,
    /// Each worker's visibility scratch (`memo[rayon::current_thread_index()]`), handed from
    /// tile to tile — each patch answer is a function of its key alone (`visibility/patches.rs`)
    /// — so that neighbouring tiles share the cells on their edges, and the passes theirs.
    memo: &'r [Mutex<Scratch>],
    /// Where splats go, and the exposure they take ([`Frame::exposure_scale`]).
    splats: Option<&'r Splats>,
    exposure: f64,
    /// Splats dropped (outside the image or not finite).
    dropped: &'r AtomicU64,
}

impl<I: Integrator> Tiles<'_, '_, I> {
    /// Runs `f` over every pixel of `rect` (`[x0, y0, x1, y1)`) in 16 × 16 tiles on rayon's
    /// pool and hands each finished tile's results (row-major) with its rectangle to `store`,
    /// which puts them into `dest` (one tile at a time). `done` is called with each finished
    /// tile's rectangle, after its counters (and the extra samples `f` reports) are added up
    /// and its splats added to the film. A finished tile is stored at once, so no frame-sized
    /// buffer is made besides `dest`.
    fn run<T: Copy + Send, D: Send, F: Fn(u32, u32, &mut Ctx, &mut u64) -> T + Sync>(
        &self,
        rect: [u32; 4],
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
        tiles.par_iter().with_max_len(1).for_each(|&tile| {
            let px = self.tile(tile, f);
            {
                // (a poisoned lock only means another tile's job panicked; its panic goes on)
                let mut d = dest.lock().unwrap_or_else(|e| e.into_inner());
                store(&mut d, tile, &px);
            }
            done(tile);
        });
    }

    /// `f` over the pixels of one tile with the worker's scratch and the tile's visibility
    /// hint; each pixel's splats go to the film, the tile's counters and extra samples to the
    /// render's, and the scratch back to the worker.
    fn tile<T, F: Fn(u32, u32, &mut Ctx, &mut u64) -> T>(
        &self,
        [tx0, ty0, tx1, ty1]: [u32; 4],
        f: &F,
    ) -> Vec<T> {
        let kept = rayon::current_thread_index().and_then(|i| self.memo.get(i));
        let mut vis = kept.map_or_else(Scratch::default, |m| {
            std::mem::take(&mut *m.lock().unwrap_or_else(|e| e.into_inner()))
        });
        let s = self.scene;
        vis.tile = s.vis.tile(&s.world, s.camera, [tx0, ty0, tx1, ty1]);
        let mut ctx = Ctx {
            vis,
            ..Ctx::default()
        };
        let mut extra = 0;
        let mut px = Vec::with_capacity(((tx1 - tx0) * (ty1 - ty0)) as usize);
        for y in ty0..ty1 {
            for x in tx0..tx1 {
                px.push(f(x, y, &mut ctx, &mut extra));
                if !ctx.splats.is_empty() {
                    self.flush(&mut ctx.splats);
                }
            }
        }
        self.shared.add(&ctx.counters, extra);
        if let Some(m) = kept {
            *m.lock().unwrap_or_else(|e| e.into_inner()) = std::mem::take(&mut ctx.vis);
        }
        px
    }
}

impl<I: Integrator> Tiles<'_, '_, I> {
    /// Adds `splats` (exposed) to the film's and empties it; those it drops are counted.
    fn flush(&self, splats: &mut Vec<Splat>) {
        if let Some(s) = self.splats {
            let mut dropped = 0;
            for mut sp in splats.drain(..) {
                sp.rgb *= self.exposure;
                dropped += !s.add(&sp) as u64;
            }
            self.dropped.fetch_add(dropped, Ordering::Relaxed);
        }
        splats.clear();
    }
}

/// Copies the row-major results `px` of tile `[tx0, ty0, tx1, ty1]` into the film, the rows
/// in `[y0, y1)` only.
fn copy_rows(film: &mut Film, [tx0, ty0, tx1, _]: [u32; 4], px: &[[f32; 4]], [y0, y1]: [u32; 2]) {
    let tw = (tx1 - tx0) as usize;
    for (row, chunk) in px.chunks(tw).enumerate() {
        let y = ty0 + row as u32;
        if (y0..y1).contains(&y) {
            film.row_mut([tx0, y], tw).copy_from_slice(chunk);
        }
    }
}

impl Frame {
    /// Renders every pixel of the window of `scene`. `progress` is called (from worker
    /// threads) with the number of pixels finished by each tile of each pass
    /// ([`Frame::passes`] passes in all). A splatting integrator
    /// ([`Integrator::splats`]) takes `spp` samples a pixel, no adaptive or penumbra ones.
    pub fn render<I: Integrator>(
        &self,
        scene: &Scene<'_, I>,
        progress: &(dyn Fn(u64) + Sync),
    ) -> (ImageRgba, RenderStats) {
        let [x0, y0, x1, y1] = self.window;
        let start = Instant::now();
        let shared = Shared::default();
        let splats = scene
            .integrator
            .splats()
            .then(|| Splats::new(self.width, self.height));
        let mut film = Film::new(self.width, self.height);
        let memo: Vec<Mutex<Scratch>> = (0..rayon::current_num_threads())
            .map(|_| Mutex::default())
            .collect();
        let dropped = AtomicU64::new(0);
        let tiles = Tiles {
            scene,
            shared: &shared,
            memo: &memo,
            splats: splats.as_ref(),
            exposure: self.exposure_scale,
            dropped: &dropped,
        };
        let frame = self.for_integrator(scene.integrator);
        // A splatting integrator's band traces the particles of the whole frame's rows (a
        // particle may land anywhere), keeping its own rows: the same bits as the frame's.
        let traced = match splats {
            Some(_) if y0 < y1 => [
                x0,
                self.frame_rows[0].min(y0),
                x1,
                self.frame_rows[1].max(y1),
            ],
            _ => self.window,
        };
        match Some(frame.adaptive).filter(|a| a.is_on() && x0 < x1 && y0 < y1) {
            None => {
                tiles.run(
                    traced,
                    &|x, y, c, _| to_f32(frame.pixel(scene, x, y, c, &mut |_| {})),
                    &|[a, b, c, d]| {
                        let rows = d.min(y1).saturating_sub(b.max(y0));
                        progress((c - a) as u64 * rows as u64)
                    },
                    &mut film,
                    &|film: &mut Film, rect, px| copy_rows(film, rect, px, [y0, y1]),
                );
            }
            Some(adaptive) => frame.adaptive_passes(&tiles, adaptive, &mut film, progress),
        }
        let npx = (x1 - x0) as u64 * (y1 - y0) as u64;
        let extra = shared.extra.load(Ordering::Relaxed);
        let traced_px = (traced[2] - traced[0]) as u64 * (traced[3] - traced[1]) as u64;
        let samples = traced_px * self.spp as u64 + extra;
        let stats = RenderStats {
            pixels: npx,
            samples,
            adaptive_samples: extra,
            rays: shared.rays.load(Ordering::Relaxed),
            shadow_rays: shared.shadow.load(Ordering::Relaxed),
            light_samples: shared.light_samples.load(Ordering::Relaxed),
            non_finite_samples: shared.non_finite.load(Ordering::Relaxed)
                + dropped.load(Ordering::Relaxed),
            seconds: start.elapsed().as_secs_f64(),
        };
        (film.finish(self.window, splats.as_ref(), samples), stats)
    }

    /// The frame as `integrator` renders it: a splatting one takes neither adaptive nor
    /// penumbra samples (every camera sample one particle of the same estimator).
    fn for_integrator(&self, integrator: &impl Integrator) -> Frame {
        if integrator.splats() {
            Frame {
                adaptive: AdaptiveSampling::OFF,
                pilot: PenumbraPilot { samples: 1 },
                ..*self
            }
        } else {
            *self
        }
    }

    /// Adaptive sampling's two passes into `film` ([`AdaptiveSampling`]).
    fn adaptive_passes<I: Integrator>(
        &self,
        tiles: &Tiles<'_, '_, I>,
        adaptive: AdaptiveSampling,
        film: &mut Film,
        progress: &(dyn Fn(u64) + Sync),
    ) {
        let scene = tiles.scene;
        let [x0, y0, x1, y1] = self.window;
        let rw = (x1 - x0) as usize;
        // First pass: the window's rows and `reach` rows beyond each side (within the frame's
        // window), so a band reads the neighbours the whole frame reads. The window's pixels
        // take their first-pass means, which the second pass updates where it adds samples;
        // every row's luminances go to `luma`, the penumbra factors (when the pilot can run)
        // to `factors`.
        let reach = adaptive.reach() as u32;
        let hy0 = y0.saturating_sub(reach).max(self.frame_rows[0]).min(y0);
        let hy1 = (y1 + reach).min(self.frame_rows[1]).max(y1);
        let rows = (hy1 - hy0) as usize;
        let mut luma: Vec<Luma> = vec![[0.0; 2]; rw * rows];
        let mut factors: Vec<u32> = if self.pilot.runs(self.spp) {
            vec![1; rw * rows]
        } else {
            Vec::new()
        };
        // Adaptive splitting: the continuations' statistics of every first-pass row.
        let first_splits = scene.integrator.splits();
        let mut split: Vec<SplitStats> = if adaptive.measure == NoiseMeasure::Linear
            && adaptive.max_splits > 1
            && first_splits > 1
        {
            vec![[0.0; 3]; rw * rows]
        } else {
            Vec::new()
        };
        tiles.run(
            [x0, hy0, x1, hy1],
            &|x, y, c, _| self.first_pass(scene, x, y, c),
            &|[a, b, c, d]| {
                let rows = d.min(y1).saturating_sub(b.max(y0));
                progress((c - a) as u64 * rows as u64)
            },
            &mut (&mut *film, &mut luma, &mut factors, &mut split),
            &|(film, luma, factors, split), [tx0, ty0, tx1, _], px: &[FirstPass]| {
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
                    if !split.is_empty() {
                        for (f, p) in split[at..at + tw].iter_mut().zip(first) {
                            *f = p.split;
                        }
                    }
                    if (y0..y1).contains(&y) {
                        for (q, p) in film.row_mut([tx0, y], tw).iter_mut().zip(first) {
                            *q = p.rgba;
                        }
                    }
                }
            },
        );
        let frame_mean = match adaptive.measure {
            NoiseMeasure::Linear => self.frame_mean(tiles),
            NoiseMeasure::Perceived => 0.0,
        };
        // Second pass: each pixel's extra samples, counted from its neighbours' pooled
        // luminance statistics; a pixel that takes some becomes the mean of all its samples.
        tiles.run(
            self.window,
            &|x, y, c, extra| {
                let (i, j) = ((x - x0) as usize, (y - hy0) as usize);
                let extra_at = adaptive.extra_at(
                    self.spp,
                    &luma,
                    &split,
                    first_splits,
                    [rw, rows],
                    [i, j],
                    frame_mean,
                );
                let n = extra_at.n;
                if n <= self.spp {
                    return None;
                }
                let ne = n - self.spp;
                *extra += ne as u64;
                let factor = factors.get(j * rw + i).copied().unwrap_or(1);
                // (they continue the pixel's first points, under the first samples' scramble)
                let run = Run {
                    n: ne,
                    factor,
                    salt: (factor > 1).then_some(PenumbraPilot::SALT),
                    base: self.spp,
                    splits: extra_at.splits,
                };
                let sums = self.samples(scene, [x, y], run, c, &mut |_| {});
                Some((ne, extra_at.weight, sums.rgba))
            },
            &|[a, b, c, d]| progress((c - a) as u64 * (d - b) as u64),
            film,
            &|film, [tx0, ty0, tx1, _], px: &[Option<(u32, f64, DVec4)>]| {
                let tw = (tx1 - tx0) as usize;
                for (row, second) in px.chunks(tw).enumerate() {
                    let y = ty0 + row as u32;
                    for (q, s) in film.row_mut([tx0, y], tw).iter_mut().zip(second) {
                        // the mean of all its samples, the extra ones weighted `w` against
                        // the first ones (1 but with adaptive splitting)
                        if let Some((ne, w, sums)) = *s {
                            let base = DVec4::from_array(q.map(f64::from)) * self.spp as f64;
                            *q = to_f32((base + sums * w) / (self.spp as f64 + ne as f64 * w));
                        }
                    }
                }
            },
        );
    }

    /// The frame's mean luminance `μ̄` by the frame pilot ([`FramePilot`]): one sample in every
    /// pilot pixel of the whole frame's window (`[x0, x1)` × [`Frame::frame_rows`]), summed in
    /// row-major order whatever the tiles. Its rays count in the render's; its samples are not
    /// the image's.
    fn frame_mean<I: Integrator>(&self, tiles: &Tiles<'_, '_, I>) -> f64 {
        let [x0, _, x1, _] = self.window;
        let [fy0, fy1] = self.frame_rows;
        if x0 >= x1 || fy0 >= fy1 {
            return 0.0;
        }
        // The pilot's pixels' luminances, in a grid of their own (row-major).
        let (fx, fy) = (FramePilot::first([x0, x1]), FramePilot::first([fy0, fy1]));
        let nx = FramePilot::along([x0, x1]).count();
        let ny = FramePilot::along([fy0, fy1]).count();
        let mut at: Vec<f64> = vec![0.0; nx * ny];
        let on = |x, y| FramePilot::on([x0, x1], x) && FramePilot::on([fy0, fy1], y);
        let salt = Some(FramePilot::SALT);
        tiles.run(
            [x0, fy0, x1, fy1],
            &|x, y, c, _| {
                if !on(x, y) {
                    return 0.0;
                }
                let run = Run {
                    n: 1,
                    factor: 1,
                    salt,
                    base: 0,
                    splits: 0,
                };
                self.samples(tiles.scene, [x, y], run, c, &mut |_| {}).y
            },
            &|_| {},
            &mut at,
            &|at, [tx0, ty0, tx1, _], px: &[f64]| {
                let tw = (tx1 - tx0) as usize;
                for (row, chunk) in px.chunks(tw).enumerate() {
                    let y = ty0 + row as u32;
                    for (x, &v) in (tx0..tx1).zip(chunk) {
                        if on(x, y) {
                            let (i, j) =
                                ((x - fx) / FramePilot::STRIDE, (y - fy) / FramePilot::STRIDE);
                            at[j as usize * nx + i as usize] = v;
                        }
                    }
                }
            },
        );
        at.iter().sum::<f64>() / at.len().max(1) as f64
    }

    /// Passes over the window a render makes: 2 with adaptive sampling that can add samples
    /// (`max_factor` > 1), else 1. Progress reports every pixel once per pass.
    pub fn passes(&self) -> u32 {
        if self.adaptive.is_on() { 2 } else { 1 }
    }

    /// A pixel's first `spp` samples (adaptive sampling's first pass).
    fn first_pass<I: Integrator>(
        &self,
        scene: &Scene<'_, I>,
        x: u32,
        y: u32,
        c: &mut Ctx,
    ) -> FirstPass {
        let (factor, s) = self.first_samples(scene, [x, y], c, &mut |_| {});
        let k = 1.0 / self.spp as f64;
        // (per sample: a sample that does not split has no spread and traces no continuation)
        let continuations = self.spp as f64 * scene.integrator.splits() as f64;
        FirstPass {
            rgba: to_f32(s.rgba / self.spp as f64),
            y: (s.y * k) as f32,
            y2: (s.y2 * k) as f32,
            factor,
            split: [
                (s.spread * k) as f32,
                ((s.rays - s.continuation_rays) as f64 * k) as f32,
                (s.continuation_rays as f64 / continuations) as f32,
            ],
        }
    }

    /// The mean of pixel `(x, y)`'s `spp` samples, RGB radiance and alpha; `each` sees every
    /// sample's (exposed, finite) radiance. (Without the adaptive extra samples, and without
    /// splats from other pixels' samples.)
    #[inline]
    pub fn pixel<I: Integrator>(
        &self,
        scene: &Scene<'_, I>,
        x: u32,
        y: u32,
        c: &mut Ctx,
        each: &mut dyn FnMut(DVec3),
    ) -> DVec4 {
        let (_, s) = self.first_samples(scene, [x, y], c, &mut |v| each(v));
        s.rgba / self.spp as f64
    }

    /// The penumbra factor of pixel `[x, y]` and the sums over its `spp` samples.
    #[inline]
    fn first_samples<I: Integrator>(
        &self,
        scene: &Scene<'_, I>,
        [x, y]: [u32; 2],
        c: &mut Ctx,
        each: &mut impl FnMut(DVec3),
    ) -> (u32, Sums) {
        let factor = self.penumbra_factor(scene, x, y, c);
        let salt = (factor > 1).then_some(PenumbraPilot::SALT);
        let run = Run {
            n: self.spp,
            factor,
            salt,
            base: 0,
            splits: 0,
        };
        let s = self.samples(scene, [x, y], run, c, each);
        (factor, s)
    }

    /// Light samples per light for pixel `(x, y)`'s samples, as a factor: the penumbra pilot's
    /// answer ([`PenumbraPilot`]), 1 when it does not run.
    fn penumbra_factor<I: Integrator>(
        &self,
        scene: &Scene<'_, I>,
        x: u32,
        y: u32,
        c: &mut Ctx,
    ) -> u32 {
        if !self.pilot.runs(self.spp) {
            return 1;
        }
        if c.vis.tile.is_empty() {
            // (its ray meets nothing: no shadow ray)
            c.counters.rays += 1;
            return 1;
        }
        let index = y as u64 * self.width as u64 + x as u64;
        let blocked0 = c.counters.blocked;
        let st = SampleStream::new(self.seed, index, 0, 1)
            .pass(PenumbraPilot::PILOT_SALT, PenumbraPilot::LIGHT_SAMPLES);
        let j = st.get2(Dim::Camera);
        let (o, d, tmin, tmax) = scene.camera.ray(x as f64 + j[0], y as f64 + j[1]);
        scene.integrator.li(&CameraRay { o, d, tmin, tmax }, &st, c);
        self.pilot.factor(c.counters.blocked - blocked0)
    }

    /// Sums over the camera samples `run` of pixel `[x, y]`.
    #[inline]
    fn samples<I: Integrator>(
        &self,
        scene: &Scene<'_, I>,
        [x, y]: [u32; 2],
        Run {
            n,
            factor,
            salt,
            base,
            splits,
        }: Run,
        c: &mut Ctx,
        each: &mut impl FnMut(DVec3),
    ) -> Sums {
        let mut sums = Sums::default();
        if c.vis.tile.is_empty() && !scene.integrator.splats() {
            // Every camera ray of the tile meets nothing (`Tile::is_empty`): what every
            // integrator's camera vertex answers for such a ray, black with alpha 0, taken
            // without drawing or tracing it (the sums stay 0, as adding those samples leaves
            // them). A splatting integrator is asked: its particles go elsewhere.
            // (the rays count as drawn: one each, also in the sums adaptive splitting reads, so
            // that they do not depend on where a tile's edges fall)
            c.counters.rays += n as u64;
            sums.rays = n as u64;
            let rgb = DVec3::ZERO * self.exposure_scale;
            (0..n).for_each(|_| each(rgb));
            return sums;
        }
        let index = y as u64 * self.width as u64 + x as u64;
        // (the continuations' sums start from zero for each run, not as differences of the
        // worker's running totals, whose rounding would depend on the tiles it rendered before)
        let rays0 = c.counters.rays;
        c.split = SplitSums::default();
        for s in 0..n {
            let mut st = SampleStream::new(self.seed, index, s, n);
            if let Some(salt) = salt {
                st = st.pass(salt, factor);
            }
            if base > 0 {
                st = st.after(base);
            }
            if splits > 0 {
                st = st.with_splits(splits);
            }
            let j = st.get2(Dim::Camera);
            let (o, d, tmin, tmax) = scene.camera.ray(x as f64 + j[0], y as f64 + j[1]);
            let (rgb, a) = scene.integrator.li(&CameraRay { o, d, tmin, tmax }, &st, c);
            let rgb = if rgb.is_finite() {
                rgb * self.exposure_scale
            } else {
                c.counters.non_finite += 1;
                DVec3::ZERO
            };
            each(rgb);
            let l = lux_math::luminance(rgb);
            sums.rgba += rgb.extend(a);
            sums.y += l;
            sums.y2 += l * l;
        }
        sums.rays = c.counters.rays - rays0;
        sums.spread = c.split.spread * self.exposure_scale * self.exposure_scale;
        sums.continuation_rays = c.split.continuation_rays;
        sums
    }
}
