//! The `direct` integrator and the tiled, deterministic render loop.
//!
//! Per camera sample (box filter, stratified jitter): the closest surface or camera-visible
//! light; at a surface, the direct illumination of a diffuse BRDF `albedo/π`:
//! - **light sampling**: every light (or one light chosen by lux-sample's selection when there
//!   are many) sampled with its lux-sample technique, a shadow ray per sample;
//! - **BSDF sampling**: one cosine-weighted direction, which collects the emission of every
//!   analytic light it crosses before the first surface (lights are not occluders, as in the
//!   reference renderer), of the mesh light it hits, or of the infinite lights if it escapes;
//! - combined with the power heuristic (β = 2) of multiple importance sampling.
//!
//! `SamplingMode::Reference` replaces this with hdEmbree's estimator — every light sampled
//! uniformly by area (dome: uniform hemisphere), light sampling only — for A/B comparisons.
//!
//! Determinism: every random number is a function of (seed, pixel, sample, dimension)
//! ([`crate::rng`]) and pixels are independent, so the image is bit-identical for any thread
//! count and tile order.

use crate::RenderError;
use crate::conformance::ResolvedProfile;
use crate::geometry::{Geometry, offset_scale};
use crate::image_io::ImageRgba;
use crate::lights::{LightOptions, LightSelection, LightSet, RenderLight, SamplingMode};
use crate::rng::SampleStream;
use crate::surface::{SurfacePoint, Surfaces};
use crate::view::View;
use glam::{DVec3, DVec4};
use lux_math::{Frame, Profile};
use lux_sample::Reference;
use lux_sample::warp::sample_cosine_hemisphere;
use lux_usd::Scene;
use rayon::prelude::*;
use std::f64::consts::FRAC_1_PI;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

/// Largest image side accepted (pixels).
pub const MAX_RESOLUTION: u32 = 65_536;
/// Largest sample count per pixel accepted.
pub const MAX_SPP: u32 = 1 << 20;
/// Tile side in pixels.
pub const TILE: u32 = 16;

/// Everything a render depends on besides the scene.
#[derive(Clone, Debug)]
pub struct RenderOptions {
    /// Samples per pixel (≥ 1).
    pub spp: u32,
    /// Output resolution; `None` = the RenderSettings' (or its product's) resolution.
    pub resolution: Option<[u32; 2]>,
    /// Only render pixels `[x0, y0, x1, y1)` (y from the top); others stay 0 with alpha 0.
    pub crop: Option<[u32; 4]>,
    /// Camera prim path; `None` = the RenderSettings' camera, else the first camera.
    pub camera: Option<String>,
    /// The conformance profile (resolved by [`crate::conformance::resolve_profile`]).
    pub profile: ResolvedProfile,
    /// Sampling techniques.
    pub sampling: SamplingMode,
    /// Light selection strategy.
    pub selection: LightSelection,
    /// Seed of every random number.
    pub seed: u64,
    /// An IES profile or texture that does not resolve or cannot be read is an error instead
    /// of a warning with a fallback (the light without it, the texture's `inputs:fallback`).
    pub strict: bool,
}

impl RenderOptions {
    /// 16 spp, the scene's resolution and camera, the `spec` profile, lux sampling, seed 0.
    pub fn new(profile: ResolvedProfile) -> RenderOptions {
        RenderOptions {
            spp: 16,
            resolution: None,
            crop: None,
            camera: None,
            profile,
            sampling: SamplingMode::Lux,
            selection: LightSelection::Auto,
            seed: 0,
            strict: false,
        }
    }
}

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

#[derive(Clone, Copy, Default)]
struct Counters {
    rays: u64,
    shadow: u64,
    light_samples: u64,
    non_finite: u64,
}

/// A scene prepared for rendering: BVH, lights, materials and camera.
pub struct Renderer<'s> {
    scene: &'s Scene,
    geometry: Geometry,
    lights: LightSet,
    surfaces: Surfaces,
    view: View,
    /// The camera's UsdGeomCamera linear exposure scale (1 with the schema defaults).
    exposure_scale: f64,
    options: RenderOptions,
    /// The pixels to render: crop ∩ data window.
    window: [u32; 4],
    /// Finite lights seen by camera rays, and infinite lights shown as background.
    visible_finite: Vec<usize>,
    visible_infinite: Vec<usize>,
    /// Lights that a BSDF ray can hit analytically, and infinite lights it can escape to.
    analytic: Vec<usize>,
    infinite: Vec<usize>,
}

/// Power heuristic, β = 2.
#[inline]
fn power_heuristic(a: f64, b: f64) -> f64 {
    let (a2, b2) = (a * a, b * b);
    if a2.is_infinite() {
        return 1.0;
    }
    if a2 + b2 > 0.0 { a2 / (a2 + b2) } else { 0.0 }
}

impl<'s> Renderer<'s> {
    /// Prepares `scene` for rendering with `options`.
    pub fn new(scene: &'s Scene, options: RenderOptions) -> Result<Renderer<'s>, RenderError> {
        if options.spp == 0 || options.spp > MAX_SPP {
            return Err(RenderError::Settings(format!(
                "samples per pixel {}: expected 1 to {MAX_SPP}",
                options.spp
            )));
        }
        let camera = match &options.camera {
            Some(p) => scene.cameras.iter().find(|c| &c.path == p).ok_or_else(|| {
                RenderError::NoCamera(format!("no camera at <{p}> in {}", scene.source.display()))
            })?,
            None => scene.render_camera().ok_or_else(|| {
                RenderError::NoCamera(format!("{} has no Camera prim", scene.source.display()))
            })?,
        };
        let settings = scene.render_settings.first();
        let product = settings.and_then(|s| s.products.first());
        let resolution = options
            .resolution
            .unwrap_or_else(|| scene.default_resolution(camera));
        if resolution[0] == 0
            || resolution[1] == 0
            || resolution[0] > MAX_RESOLUTION
            || resolution[1] > MAX_RESOLUTION
        {
            return Err(RenderError::Settings(format!(
                "resolution {}×{}: expected 1 to {MAX_RESOLUTION} pixels per side",
                resolution[0], resolution[1]
            )));
        }
        let par = product
            .and_then(|p| p.base.pixel_aspect_ratio)
            .or_else(|| settings.map(|s| s.pixel_aspect_ratio()))
            .unwrap_or(1.0);
        let ndc = product
            .and_then(|p| p.base.data_window_ndc)
            .or_else(|| settings.map(|s| s.data_window_ndc()))
            .unwrap_or(DVec4::new(0.0, 0.0, 1.0, 1.0));
        let view = View::new(camera, resolution, par, ndc)?;
        let mut window = view.pixel_window;
        if let Some([x0, y0, x1, y1]) = options.crop {
            if x0 >= x1 || y0 >= y1 || x1 > resolution[0] || y1 > resolution[1] {
                return Err(RenderError::Settings(format!(
                    "crop {x0},{y0},{x1},{y1}: expected x0 < x1 ≤ {}, y0 < y1 ≤ {}",
                    resolution[0], resolution[1]
                )));
            }
            window = [
                window[0].max(x0),
                window[1].max(y0),
                window[2].min(x1),
                window[3].min(y1),
            ];
            window[2] = window[2].max(window[0]);
            window[3] = window[3].max(window[1]);
        }
        let profile = options.profile.profile;
        let lights = LightSet::new(
            scene,
            LightOptions {
                profile,
                selection: options.selection,
                strict: options.strict,
            },
        )?;
        let surfaces = Surfaces::with_policy(scene, options.strict)?;
        let geometry = Geometry::new(scene);
        let mut visible_finite = Vec::new();
        let mut visible_infinite = Vec::new();
        let mut analytic = Vec::new();
        let mut infinite = Vec::new();
        for (i, l) in lights.lights.iter().enumerate() {
            if l.is_infinite() {
                if !l.delta {
                    infinite.push(i);
                }
                if l.camera_visible {
                    visible_infinite.push(i);
                }
            } else if l.mesh().is_none() {
                analytic.push(i);
                if l.camera_visible {
                    visible_finite.push(i);
                }
            }
        }
        let exposure_scale = camera.linear_exposure_scale();
        Ok(Renderer {
            scene,
            geometry,
            lights,
            surfaces,
            view,
            exposure_scale,
            options,
            window,
            visible_finite,
            visible_infinite,
            analytic,
            infinite,
        })
    }

    /// The prepared lights (with the warnings met while preparing them).
    pub fn lights(&self) -> &LightSet {
        &self.lights
    }

    /// Everything the render set-up replaced or left out: lights that cannot emit, IES profiles
    /// and textures that could not be read (each named with the light or material using it).
    pub fn warnings(&self) -> impl Iterator<Item = &String> {
        self.lights.warnings.iter().chain(&self.surfaces.warnings)
    }

    /// Output image size.
    pub fn resolution(&self) -> [u32; 2] {
        [self.view.width, self.view.height]
    }

    /// The pixels that are rendered, `[x0, y0, x1, y1)`.
    pub fn window(&self) -> [u32; 4] {
        self.window
    }

    /// Number of BVH triangles (each instanced prototype's once).
    pub fn triangle_count(&self) -> usize {
        self.geometry.triangle_count()
    }

    /// The scene's prepared geometry (BVHs, instances, world bounds).
    pub fn geometry(&self) -> &Geometry {
        &self.geometry
    }

    /// Renders the image. `progress` is called (from worker threads) with the number of
    /// pixels finished by each completed tile.
    pub fn render(&self, progress: &(dyn Fn(u64) + Sync)) -> (ImageRgba, RenderStats) {
        let [w, h] = self.resolution();
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
                        let v = self.pixel(x, y, &mut c);
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
            samples: npx * self.options.spp as u64,
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

    /// The mean of the pixel's samples: RGB radiance and alpha (coverage by geometry or a
    /// visible light).
    pub fn pixel_value(&self, x: u32, y: u32) -> DVec4 {
        self.pixel(x, y, &mut Counters::default())
    }

    /// The pixel's sample moments: the mean (RGB, alpha) and the mean of the squared Rec.709
    /// luminance of the samples, from which a caller estimates the variance of the pixel
    /// estimate (`(E[Y²] − E[Y]²) / (spp − 1)`), as the conformance tests do.
    pub fn pixel_moments(&self, x: u32, y: u32) -> (DVec4, f64) {
        let mut y2 = 0.0;
        let mean = self.pixel_with(x, y, &mut Counters::default(), &mut |rgb| {
            let l = crate::lights::luminance(rgb);
            y2 += l * l;
        });
        (mean, y2 / self.options.spp as f64)
    }

    fn pixel(&self, x: u32, y: u32, c: &mut Counters) -> DVec4 {
        self.pixel_with(x, y, c, &mut |_| {})
    }

    #[inline]
    fn pixel_with(&self, x: u32, y: u32, c: &mut Counters, each: &mut dyn FnMut(DVec3)) -> DVec4 {
        let spp = self.options.spp;
        let index = y as u64 * self.view.width as u64 + x as u64;
        let mut sum = DVec4::ZERO;
        for s in 0..spp {
            let st = SampleStream::new(self.options.seed, index, s, spp);
            let j = st.u2(0);
            let (o, d, tmin, tmax) = self.view.ray(x as f64 + j[0], y as f64 + j[1]);
            let (rgb, a) = self.trace_camera(o, d, tmin, tmax, &st, c);
            let rgb = if rgb.is_finite() {
                // the camera's exposure (UsdGeomCamera ComputeLinearExposureScale; ×1 is exact)
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

    fn trace_camera(
        &self,
        o: DVec3,
        d: DVec3,
        tmin: f64,
        tmax: f64,
        st: &SampleStream,
        c: &mut Counters,
    ) -> (DVec3, f64) {
        c.rays += 1;
        let hit = self.geometry.intersect(self.scene, o, d, tmin, tmax);
        let mut t_best = hit.map_or(tmax, |h| h.t);
        let mut light_hit = None;
        for &i in &self.visible_finite {
            if let Some(h) = self.lights.lights[i].intersect(o, d, tmin, t_best) {
                t_best = h.t;
                light_hit = Some((i, h));
            }
        }
        if let Some((i, h)) = light_hit {
            // A visible light is opaque: its front shows its emission, its back is black.
            let l = &self.lights.lights[i];
            let rgb = if h.front {
                l.emitted(h.local, -d, false)
            } else {
                DVec3::ZERO
            };
            return (rgb, 1.0);
        }
        let Some(hit) = hit else {
            let bg: DVec3 = self
                .visible_infinite
                .iter()
                .map(|&i| self.lights.lights[i].infinite_radiance(d))
                .sum();
            // The background is opaque where a dome is shown.
            let alpha = if self.visible_infinite.is_empty() {
                0.0
            } else {
                1.0
            };
            return (bg, alpha);
        };
        let sp = self.surfaces.at(self.scene, &hit, d);
        let mut rgb = DVec3::ZERO;
        // A mesh light's own glow, seen directly.
        if let Some(li) = self.lights.mesh_light.get(hit.mesh).copied().flatten() {
            let l = &self.lights.lights[li];
            rgb += l.emitted(l.to_local(sp.p), -d, false);
        }
        rgb += self.direct(&sp, st, c);
        (rgb, 1.0)
    }

    /// Emission arriving along a light sample's direction.
    #[inline]
    fn sample_radiance(&self, li: usize, ls: &lux_sample::LightSample) -> DVec3 {
        let l = &self.lights.lights[li];
        if ls.distance.is_finite() {
            l.emitted(l.to_local(ls.point), -ls.wi, true)
        } else if l.kind == lux_math::LightKind::Distant {
            l.emitted(DVec3::ZERO, -ls.wi, true)
        } else {
            l.infinite_radiance(ls.wi)
        }
    }

    /// Direct illumination at a surface point (diffuse BRDF albedo/π).
    fn direct(&self, sp: &SurfacePoint, st: &SampleStream, c: &mut Counters) -> DVec3 {
        let n = self.lights.lights.len();
        if n == 0 || sp.albedo == DVec3::ZERO {
            return DVec3::ZERO;
        }
        let r = Reference::surface(sp.p, sp.ns);
        let origin = sp.p + sp.ng * sp.offset;
        let f = sp.albedo * FRAC_1_PI;
        let mode = self.options.sampling;
        let mis = mode == SamplingMode::Lux;
        let selector = if mode == SamplingMode::Reference {
            None
        } else {
            self.lights.selector.as_ref()
        };
        let mut out = DVec3::ZERO;
        // Light sampling.
        let mut sample_light = |li: usize, pmf: f64, u: [f64; 2], c: &mut Counters| {
            let l = &self.lights.lights[li];
            let Some(ls) = l.sample(&r, u, mode) else {
                return;
            };
            c.light_samples += 1;
            let cos = sp.ns.dot(ls.wi);
            if cos <= 0.0 || sp.ng.dot(ls.wi) <= 0.0 || ls.pdf.is_nan() || ls.pdf <= 0.0 {
                return;
            }
            let le = self.sample_radiance(li, &ls);
            if le == DVec3::ZERO {
                return;
            }
            let tmax = if ls.distance.is_finite() {
                ls.distance - offset_scale(ls.point)
            } else {
                f64::INFINITY
            };
            if tmax <= 0.0 {
                return;
            }
            let Some(vis) = self.visibility(l, origin, ls.wi, tmax, c) else {
                return;
            };
            let pdf = pmf * ls.pdf;
            let w = if ls.delta || !mis || !l.plain_shadows() {
                1.0
            } else {
                power_heuristic(pdf, cos * FRAC_1_PI)
            };
            let contrib = f * le * vis * (l.diffuse * cos * w / pdf);
            if contrib.is_finite() {
                out += contrib;
            }
        };
        match selector {
            None => {
                for li in 0..n {
                    sample_light(li, 1.0, st.u2(5 + 2 * li as u32), c);
                }
            }
            Some(sel) => {
                if let Some((li, pmf)) = sel.sample(&r, st.u(4))
                    && pmf > 0.0
                {
                    sample_light(li, pmf, st.u2(5), c);
                }
            }
        }
        if !mis {
            return out;
        }
        // BSDF sampling: cosine-weighted hemisphere around the shading normal.
        let frame = Frame::from_normal(sp.ns);
        let wi = frame.to_world(sample_cosine_hemisphere(st.u2(2)));
        let cos = sp.ns.dot(wi);
        if cos <= 0.0 || sp.ng.dot(wi) <= 0.0 {
            return out;
        }
        let pdf_b = cos * FRAC_1_PI;
        let pmf = |li: usize| selector.map_or(1.0, |s| s.pmf(&r, li));
        c.rays += 1;
        let hit = self
            .geometry
            .intersect(self.scene, origin, wi, 0.0, f64::INFINITY);
        let t_geo = hit.map_or(f64::INFINITY, |h| h.t);
        let mut add = |l: &RenderLight, le: DVec3, pdf_l: f64| {
            if le != DVec3::ZERO && l.plain_shadows() {
                let w = power_heuristic(pdf_b, pdf_l);
                let contrib = sp.albedo * le * (w * l.diffuse);
                if contrib.is_finite() {
                    out += contrib;
                }
            }
        };
        for &li in &self.analytic {
            let l = &self.lights.lights[li];
            if let Some(h) = l.intersect(origin, wi, 0.0, t_geo)
                && h.front
            {
                add(l, l.emitted(h.local, -wi, true), pmf(li) * l.pdf(&r, wi));
            }
        }
        match hit {
            Some(h) => {
                if let Some(li) = self.lights.mesh_light.get(h.mesh).copied().flatten() {
                    let l = &self.lights.lights[li];
                    add(
                        l,
                        l.emitted(l.to_local(h.p), -wi, true),
                        pmf(li) * l.pdf_triangle(&r, h.tri, wi),
                    );
                }
            }
            None => {
                for &li in &self.infinite {
                    let l = &self.lights.lights[li];
                    add(l, l.infinite_radiance(wi), pmf(li) * l.pdf(&r, wi));
                }
            }
        }
        out
    }

    /// Transmission of a shadow ray towards light `l` (`ShadowAPI`): `None` when fully
    /// blocked, else the RGB multiplier (1 unoccluded; `lux_math::shadowed` of the occluder's
    /// `shadow_strength` otherwise). Shadows disabled: no ray is traced.
    #[inline]
    fn visibility(
        &self,
        l: &RenderLight,
        origin: DVec3,
        dir: DVec3,
        tmax: f64,
        c: &mut Counters,
    ) -> Option<DVec3> {
        if !l.shadow.enable {
            return Some(DVec3::ONE);
        }
        c.rays += 1;
        c.shadow += 1;
        if l.plain_shadows() {
            return (!self.geometry.occluded(origin, dir, 0.0, tmax)).then_some(DVec3::ONE);
        }
        let Some(t) = self.geometry.first_occluder(origin, dir, 0.0, tmax) else {
            return Some(DVec3::ONE);
        };
        let sh = &l.shadow;
        let s = lux_math::shadow_strength(t, sh.distance, sh.falloff, sh.falloff_gamma);
        let m = lux_math::shadowed(s, sh.color);
        (m != DVec3::ZERO).then_some(m)
    }

    /// The conformance profile in use.
    pub fn profile(&self) -> Profile {
        self.options.profile.profile
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn power_heuristic_values() {
        assert_eq!(power_heuristic(1.0, 1.0), 0.5);
        assert_eq!(power_heuristic(3.0, 1.0), 0.9);
        assert_eq!(power_heuristic(0.0, 0.0), 0.0);
        assert_eq!(power_heuristic(f64::INFINITY, 1.0), 1.0);
        assert!((power_heuristic(1.0, 3.0) + power_heuristic(3.0, 1.0) - 1.0).abs() < 1e-15);
    }
}
