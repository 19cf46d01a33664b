//! The film: the image's pixels, rendered in 16 × 16 tiles on rayon's pool, each pixel the
//! mean of its camera samples (box filter, stratified jitter), with the render's counters.
//!
//! Determinism: every random number is a function of (seed, pixel, sample, dimension)
//! ([`crate::sampler`]) and pixels are independent, so the image is bit-identical for any
//! thread count and tile order.

use crate::camera::Camera;
use crate::image_io::ImageRgba;
use crate::integrator::{CameraRay, Integrator};
use crate::sampler::{Dim, SampleStream};
use glam::{DVec3, DVec4};
use rayon::prelude::*;
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

/// Samples per pixel from which the penumbra pilot runs (below, its cost would outweigh it).
const PILOT_MIN_SPP: u32 = 8;

/// Counters of a finished render.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RenderStats {
    /// Pixels rendered.
    pub pixels: u64,
    /// Camera samples (pixels × spp).
    pub samples: u64,
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

/// What one worker counts while it renders a tile (summed into [`RenderStats`]).
#[derive(Clone, Copy, Debug, Default)]
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
}

/// The image being rendered: its size, the pixels to render, samples and seed.
#[derive(Clone, Copy, Debug)]
pub struct Film {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// The pixels to render, `[x0, y0, x1, y1)` (crop ∩ data window); the rest stays 0 with
    /// alpha 0.
    pub window: [u32; 4],
    /// Samples per pixel.
    pub spp: u32,
    /// Seed of every random number.
    pub seed: u64,
    /// The camera's linear exposure scale applied to every sample (UsdGeomCamera
    /// `ComputeLinearExposureScale`; ×1 is exact).
    pub exposure_scale: f64,
    /// Light samples per light in penumbrae ([`crate::settings::RenderOptions::penumbra_samples`];
    /// 1: no penumbra pass).
    pub penumbra_samples: u32,
}

impl Film {
    /// Renders every pixel of the window with `integrator` through `camera`. `progress` is
    /// called (from worker threads) with the number of pixels finished by each tile.
    pub fn render(
        &self,
        camera: &Camera,
        integrator: &Integrator,
        progress: &(dyn Fn(u64) + Sync),
    ) -> (ImageRgba, RenderStats) {
        let [w, h] = [self.width, self.height];
        let [x0, y0, x1, y1] = self.window;
        let start = Instant::now();
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
        let rays = AtomicU64::new(0);
        let shadow = AtomicU64::new(0);
        let light_samples = AtomicU64::new(0);
        let non_finite = AtomicU64::new(0);
        let results: Vec<(usize, Vec<[f32; 4]>)> = tiles
            .par_iter()
            .enumerate()
            .map(|(ti, &[tx0, ty0, tx1, ty1])| {
                let mut c = Counters::default();
                let mut px = Vec::with_capacity(((tx1 - tx0) * (ty1 - ty0)) as usize);
                for y in ty0..ty1 {
                    for x in tx0..tx1 {
                        let v = self.pixel(camera, integrator, x, y, &mut c, &mut |_| {});
                        px.push([v.x as f32, v.y as f32, v.z as f32, v.w as f32]);
                    }
                }
                rays.fetch_add(c.rays, Ordering::Relaxed);
                shadow.fetch_add(c.shadow, Ordering::Relaxed);
                light_samples.fetch_add(c.light_samples, Ordering::Relaxed);
                non_finite.fetch_add(c.non_finite, Ordering::Relaxed);
                progress(px.len() as u64);
                (ti, px)
            })
            .collect();
        let mut pixels = vec![[0.0f32; 4]; w as usize * h as usize];
        for (ti, px) in results {
            let [tx0, ty0, tx1, _] = tiles[ti];
            let tw = (tx1 - tx0) as usize;
            for (k, v) in px.into_iter().enumerate() {
                let (x, y) = (tx0 as usize + k % tw, ty0 as usize + k / tw);
                pixels[y * w as usize + x] = v;
            }
        }
        let npx = (x1 - x0) as u64 * (y1 - y0) as u64;
        let stats = RenderStats {
            pixels: npx,
            samples: npx * self.spp as u64,
            rays: rays.load(Ordering::Relaxed),
            shadow_rays: shadow.load(Ordering::Relaxed),
            light_samples: light_samples.load(Ordering::Relaxed),
            non_finite_samples: non_finite.load(Ordering::Relaxed),
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

    /// The mean of pixel `(x, y)`'s samples, RGB radiance and alpha; `each` sees every
    /// sample's (exposed, finite) radiance.
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
        let spp = self.spp;
        let index = y as u64 * self.width as u64 + x as u64;
        // Penumbrae: before the pixel's samples (at least PILOT_MIN_SPP), a pilot camera
        // sample with PILOT_LIGHT_SAMPLES light samples per light, drawn from points of its
        // own and not part of the estimate, looks at the pixel's shadow rays; if some were
        // blocked, every sample of the pixel takes `penumbra_samples` light samples per light,
        // its points drawn from another scramble of the pixel's sets (independent of the
        // pilot's). The choice depends on the pilot's random numbers only, so each sample
        // stays an unbiased estimate, and the pixel's points stay one stratified set per
        // dimension.
        let mut factor = 1;
        if self.penumbra_samples > 1 && spp >= PILOT_MIN_SPP {
            let blocked0 = c.blocked;
            let st =
                SampleStream::new(self.seed, index, 0, 1).pass(PILOT_SALT, PILOT_LIGHT_SAMPLES);
            let j = st.get2(Dim::Camera);
            let (o, d, tmin, tmax) = camera.ray(x as f64 + j[0], y as f64 + j[1]);
            integrator.li(&CameraRay { o, d, tmin, tmax }, &st, c);
            if c.blocked > blocked0 {
                factor = self.penumbra_samples;
            }
        }
        let mut sum = DVec4::ZERO;
        for s in 0..spp {
            let mut st = SampleStream::new(self.seed, index, s, spp);
            if factor > 1 {
                st = st.pass(PENUMBRA_SALT, factor);
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
            sum += rgb.extend(a);
        }
        sum / spp as f64
    }
}
