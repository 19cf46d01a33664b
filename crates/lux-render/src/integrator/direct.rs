//! The `direct` integrator: the radiance a camera ray sees, lit directly by every light.
//!
//! Per camera sample: the closest surface or camera-visible light; at a surface, the direct
//! illumination of its BSDF:
//! - **light sampling**: every light (or one light chosen by lux-sample's selection when there
//!   are many) sampled with its lux-sample technique, a shadow ray per sample;
//! - **BSDF sampling**: one direction from the BSDF, which collects the emission of every
//!   analytic light it crosses before the first surface (lights are not occluders, as in the
//!   reference renderer), of the mesh light it hits, or of the infinite lights if it escapes;
//! - combined with the power heuristic (β = 2) of multiple importance sampling.
//!
//! [`SamplingMode::Reference`] replaces this with hdEmbree's estimator — every light sampled
//! with lux-sample's [`Strategy::HdEmbree`] (uniformly by area; the dome uniformly over the
//! hemisphere), light sampling only — for A/B comparisons.
//!
//! Light-only estimation of a rect, disk or sphere of uniform radiance takes the light's closed
//! form where nothing can block it (`geometry/cone.rs`, `integrator/patches.rs`), and its exact
//! penumbra where a few triangles can (`integrator/penumbra.rs`).
//!
//! Lights with non-default `ShadowAPI` inputs (coloured, distance-limited or disabled shadows)
//! are estimated by light sampling alone: a BSDF ray stops at the first occluder, which is not
//! what their shadow says.

use super::{CameraRay, World, closest, power_heuristic, shadow_ray};
use crate::film::Counters;
use crate::geometry::{Hit, Region};
use crate::geometry::{shadow_ray_to, shadow_tmax};
use crate::light::{LiSample, Light, LightBase, Seen};
use crate::material::{Bsdf, SurfacePoint};
use crate::sampler::{Dim, SampleStream};
use crate::settings::SamplingMode;
use crate::visibility::{ConeSearch, FewTriangles, penumbra, regions};
use glam::DVec3;
use lux_sample::{Reference, Strategy};

/// What a camera ray meets first ([`DirectIntegrator::camera_vertex`]).
pub(super) enum CameraVertex {
    /// The path ends: radiance and alpha.
    Done(DVec3, f64),
    /// A surface hit, with the glow it shows (a mesh light's, a textured emission). The caller
    /// shades it (`Materials::at`) into its own frame: a `SurfacePoint` is large enough that
    /// moving it out of an enum costs a `memcpy` per camera ray.
    Surface(Hit, DVec3),
}

/// Whether no triangle can block the light's shadow rays inside `region`, from a point of a
/// patch whose search found `patch` (integrator/patches.rs): without shadows nothing can; a
/// triangle of the patch's that `region` does not rule out may; otherwise the point's own
/// search of the BVH (only the meshes its shadow linking keeps, `casts`) decides.
fn clear_from(
    w: &World,
    base: &LightBase,
    region: &impl Region,
    patch: ConeSearch,
    casts: &impl Fn(usize) -> bool,
) -> bool {
    !base.shadow.enable
        || match patch {
            ConeSearch::Blocked(id) if !w.shadows.culls(region, id) => false,
            _ => w.shadows.cone_clear(region, casts),
        }
}

/// Whether a light's `inputs:diffuse` and `inputs:specular` act on `bsdf` as one factor
/// (`diffuse`): a Lambertian BSDF has no specular part, or the two are equal.
#[inline]
fn one_scale(bsdf: &Bsdf, base: &LightBase) -> bool {
    matches!(bsdf, Bsdf::Diffuse(_)) || base.diffuse == base.specular
}

/// Direct lighting with light sampling and (lux sampling) MIS against BSDF sampling.
#[derive(Clone, Copy)]
pub struct DirectIntegrator<'a> {
    pub(super) world: World<'a>,
    /// The light-sampling strategy.
    strategy: Strategy,
    /// BSDF sampling and MIS (off for the reference estimator).
    mis: bool,
    /// One light per shading point by the light set's selector (off: every light).
    select: bool,
    /// Light samples per light (or per light choice) at each shading point.
    light_samples: u32,
    /// Closed forms where nothing can block a light ([`Self::with_closed_forms`]).
    closed_forms: bool,
}

impl<'a> DirectIntegrator<'a> {
    /// The estimator of `mode` over `world`, with `light_samples` (≥ 1) light samples per
    /// light or light choice.
    pub fn new(world: World<'a>, mode: SamplingMode, light_samples: u32) -> DirectIntegrator<'a> {
        let lux = mode == SamplingMode::Lux;
        DirectIntegrator {
            world,
            strategy: if lux {
                Strategy::Lux
            } else {
                Strategy::HdEmbree
            },
            mis: lux,
            select: lux,
            light_samples: light_samples.max(1),
            closed_forms: true,
        }
    }

    /// With `on` (the default), light-only estimation of a rect, disk or sphere light of
    /// uniform radiance takes the light's closed form `L·Π` where nothing can block it
    /// (`RenderOptions::closed_forms`).
    pub fn with_closed_forms(self, on: bool) -> DirectIntegrator<'a> {
        DirectIntegrator {
            closed_forms: on,
            ..self
        }
    }

    /// Radiance and alpha along a camera ray: a visible light's front (its back is black), the
    /// background of camera-visible lights at infinity where the ray escapes (opaque where a
    /// dome is shown), or the lit surface with a mesh light's own glow.
    pub fn li(&self, ray: &CameraRay, st: &SampleStream, c: &mut Counters) -> (DVec3, f64) {
        match self.camera_vertex(ray, c) {
            CameraVertex::Done(rgb, alpha) => (rgb, alpha),
            CameraVertex::Surface(hit, glow) => {
                let w = &self.world;
                let sp = w.materials.at(w.scene, &hit, ray.d);
                (glow + self.direct(&sp, st, 0, c), 1.0)
            }
        }
    }

    /// What a camera ray meets first: a camera-visible light or the background (its
    /// radiance and alpha, the end of the path), or a surface with the glow it shows if it
    /// carries a mesh light.
    #[inline(always)]
    pub(super) fn camera_vertex(&self, ray: &CameraRay, c: &mut Counters) -> CameraVertex {
        let w = &self.world;
        let lights = &w.lights.lights;
        c.rays += 1;
        let hit = match &c.tile.triangles {
            // (only without transparency: Integrator::tile_rays)
            Some(ids) => w
                .shadows
                .intersect_among(w.scene, ids, ray.o, ray.d, ray.tmin, ray.tmax),
            None => closest(w, ray.o, ray.d, ray.tmin, ray.tmax, false),
        };
        let t_best = hit.map_or(ray.tmax, |h| h.t);
        if let Some((i, h)) = w
            .lights
            .closest_light(ray.o, ray.d, ray.tmin, t_best, |l| l.base().camera_visible)
        {
            let rgb = if h.front {
                lights[i].le(h.local, -ray.d, Seen::Camera)
            } else {
                DVec3::ZERO
            };
            return CameraVertex::Done(rgb, 1.0);
        }
        let Some(hit) = hit else {
            let background = &w.lights.background;
            let bg: DVec3 = background.iter().map(|&i| lights[i].le_escape(ray.d)).sum();
            let alpha = if background.is_empty() { 0.0 } else { 1.0 };
            return CameraVertex::Done(bg, alpha);
        };
        let mut glow = DVec3::ZERO;
        if w.textured_emission {
            glow += w.materials.emission(w.scene, &hit);
        }
        // A mesh light's own glow, seen directly.
        if let Some(li) = w.lights.light_of(hit.mesh, hit.instance) {
            let l = &lights[li];
            glow += match l {
                // materialSyncMode: the material's glow, not the light's radiance.
                Light::Mesh(m) if m.glow.is_some() => m.glow.unwrap_or_default(),
                _ => l.le(l.base().to_local(hit.p), -ray.d, Seen::Camera),
            };
        }
        CameraVertex::Surface(hit, glow)
    }

    /// Direct illumination at a surface point, the random numbers of path vertex `bounce`
    /// (0 for the surface a camera ray meets): light sampling, and the emission found along
    /// the BSDF sample `Dim::Bsdf { bounce }` (with MIS), which a path continues along.
    #[inline(always)]
    pub(super) fn direct(
        &self,
        sp: &SurfacePoint,
        st: &SampleStream,
        bounce: u32,
        c: &mut Counters,
    ) -> DVec3 {
        let w = &self.world;
        let lights = &w.lights.lights;
        let n = lights.len();
        if (n == 0 && !w.textured_emission) || sp.bsdf.is_black() {
            return DVec3::ZERO;
        }
        let r = Reference::surface(sp.p, sp.ns);
        let origin = sp.p + sp.ng * sp.offset;
        let selector = if self.select {
            w.lights.selector.as_ref()
        } else {
            None
        };
        let mut out = DVec3::ZERO;
        // Light sampling alone (every light sampled, lux sampling, a Lambertian BSDF) for the
        // rect, disk and sphere lights of uniform radiance: their samplers follow the
        // cosine-weighted solid angle (the sphere's projected cap exactly, the rect's bilinear
        // cosine warp closely), so a BSDF sample would only add noise. Bit i of `light_only`
        // marks light i estimated this way.
        let lambertian = self.mis && selector.is_none() && sp.bsdf.is_lambertian();
        let mut light_only: u64 = 0;
        // k light samples per light (or light choice), each weighted 1/k: the light
        // technique's density is k·pdf in the MIS weights.
        let k = self.light_samples * st.light_factor();
        let kf = k as f64;
        // Light sampling: the contribution of the sample `ls` of the light `l` chosen with
        // probability `pmf` (times k), with MIS against BSDF sampling unless `alone`. (Light
        // linking: an unlinked light adds nothing here, nor by BSDF sampling; the callers skip
        // it.)
        let sample_light = |l: &Light,
                            ls: Option<LiSample>,
                            pmf: f64,
                            alone: bool,
                            among: Option<&FewTriangles>,
                            c: &mut Counters| {
            let Some(ls) = ls else {
                return DVec3::ZERO;
            };
            c.light_samples += 1;
            let cos = sp.ns.dot(ls.wi);
            if cos <= 0.0 || sp.ng.dot(ls.wi) <= 0.0 || ls.pdf.is_nan() || ls.pdf <= 0.0 {
                return DVec3::ZERO;
            }
            if ls.l == DVec3::ZERO {
                return DVec3::ZERO;
            }
            // A mesh light is geometry: its shadow ray aims at the sampled point from `origin`
            // (`shadow_ray_to`); other lights are not occluders.
            let (dir, tmax) = match l {
                Light::Mesh(_) => match shadow_ray_to(origin, ls.point) {
                    Some(ray) => ray,
                    None => return DVec3::ZERO,
                },
                _ if ls.dist.is_finite() => (ls.wi, shadow_tmax(ls.dist, ls.point)),
                _ => (ls.wi, f64::INFINITY),
            };
            if tmax <= 0.0 {
                return DVec3::ZERO;
            }
            let base = l.base();
            // (the patch's few blockers: `visibility` tests them for plain shadows without
            // transparency)
            let Some(vis) = shadow_ray(w, base, (origin, dir, tmax), among, c) else {
                return DVec3::ZERO;
            };
            let pdf = pmf * ls.pdf;
            let weight = if alone || ls.delta || !self.mis || !base.plain_shadows() {
                1.0
            } else {
                power_heuristic(pdf, sp.bsdf.pdf(ls.wi))
            };
            // The light's inputs:diffuse and inputs:specular scale the two parts of f; one
            // scale for a Lambertian surface or equal multipliers.
            let contrib = if one_scale(&sp.bsdf, base) {
                sp.bsdf.f(ls.wi) * ls.l * vis * (base.diffuse * cos * weight / pdf)
            } else {
                sp.bsdf.f_scaled(ls.wi, base.diffuse, base.specular)
                    * ls.l
                    * vis
                    * (cos * weight / pdf)
            };
            if contrib.is_finite() {
                contrib
            } else {
                DVec3::ZERO
            }
        };
        match selector {
            None => {
                for (li, light) in lights.iter().enumerate() {
                    let alone = lambertian && li < 64 && light.uniform_area();
                    if alone {
                        light_only |= 1 << li;
                    }
                    if !light.base().illuminates(sp.mesh, sp.instance) {
                        continue;
                    }
                    let dim = Dim::Light {
                        bounce,
                        index: li as u32,
                    };
                    if k == 1 {
                        let ls = light.sample_li(&r, st.get2(dim), self.strategy);
                        out += sample_light(light, ls, kf, alone, None, c);
                        continue;
                    }
                    // What the light's k samples share, computed once.
                    light.seen_from(&r, self.strategy, |from| {
                        // Light-only estimation of a light whose unshadowed integral L·Π
                        // has a closed form, where nothing can block it (geometry/cone.rs,
                        // geometry/pyramid.rs):
                        // that closed form is the estimate (what its k samples average to),
                        // without drawing them. What can block it is searched once for the
                        // point's patch of surface (integrator/patches.rs), then for the point
                        // unless the patch's blocker blocks its region too (without shadows,
                        // nothing blocks; with shadow linking, only what it keeps).
                        let base = light.base();
                        let casts = |m| base.casts_shadow(m, None);
                        let (patch, few) = match regions::shadow_ball(from) {
                            Some(ball) if alone && self.closed_forms && base.shadow.enable => {
                                let corners = regions::shadow_corners(from);
                                let corners = corners.as_ref();
                                c.patches
                                    .search(w.scene, &w.shadows, sp, li, ball, corners, &casts)
                            }
                            _ => (ConeSearch::Unsearched, None),
                        };
                        // With the patch's few possible blockers (opaque black shadows; those
                        // the light's shadow links keep), the part of a sphere, rect or disk
                        // they leave visible, in closed form (integrator/penumbra.rs).
                        let exact = || {
                            few.as_ref()
                                .filter(|_| !w.transparent && base.black_shadows())
                                .and_then(|few| penumbra::visible(&w.shadows, from, sp, few))
                        };
                        // The direction the closed form's BSDF is evaluated in (the ball's
                        // centre: a Lambertian f is the same in every direction), and the
                        // fraction of the closed form that passes.
                        let unblocked = match patch {
                            _ if !(alone && self.closed_forms) => None,
                            // (the patch's region holds the point's: the light is above its
                            // horizon)
                            ConeSearch::Clear => regions::shadow_ball(from)
                                .map(|(centre, ..)| ((centre - sp.p).normalize(), 1.0)),
                            // Something may block the patch, and the light's samples are its
                            // closed form where unblocked: the exact penumbra, else the samples
                            // (a search of the point's own region would only spare their
                            // shadow rays, at about their cost, and most often, in a penumbra,
                            // find a blocker).
                            ConeSearch::Blocked(_) if from.samples_exactly() => exact(),
                            // The exact penumbra (a blocked patch's few blockers), else a
                            // rect's or disk's pyramid (tighter than its ball's cone), else the
                            // cone.
                            _ => exact().or_else(|| {
                                match regions::shadow_pyramid(from, sp.p, sp.ng, sp.offset) {
                                    Some(pyramid) => clear_from(w, base, &pyramid, patch, &casts)
                                        .then(|| (pyramid.axis(), 1.0)),
                                    None => regions::shadow_cone(from, sp.p, sp.ng, sp.offset)
                                        .filter(|cone| clear_from(w, base, cone, patch, &casts))
                                        .map(|cone| (cone.axis(), 1.0)),
                                }
                            }),
                        };
                        if let Some((wi, pass)) = unblocked
                            && let Some(le_pi) = from.unshadowed(sp.p, sp.ns)
                        {
                            let le_pi = le_pi * pass;
                            out += if one_scale(&sp.bsdf, base) {
                                sp.bsdf.f(wi) * le_pi * base.diffuse
                            } else {
                                sp.bsdf.f_scaled(wi, base.diffuse, base.specular) * le_pi
                            };
                            return;
                        }
                        // (the point's shadow rays lie in its patch's region)
                        for u in st.split_get2(dim, k) {
                            out +=
                                sample_light(light, from.sample_li(u), kf, alone, few.as_ref(), c);
                        }
                    });
                }
            }
            Some(sel) => {
                for j in 0..k {
                    let sj = st.split(j, k);
                    if let Some((li, pmf)) = sel.sample(&r, sj.get1(Dim::LightChoice { bounce }))
                        && pmf > 0.0
                        && lights[li].base().illuminates(sp.mesh, sp.instance)
                    {
                        let l = &lights[li];
                        let u = sj.get2(Dim::Light { bounce, index: 0 });
                        let ls = l.sample_li(&r, u, self.strategy);
                        out += sample_light(l, ls, pmf * kf, false, None, c);
                    }
                }
            }
        }
        // Every light estimated by light sampling alone: no BSDF ray (unless surfaces glow
        // from textures, which only BSDF rays find).
        if n < 64 && light_only == (1u64 << n) - 1 && !w.textured_emission {
            return out;
        }
        if !self.mis {
            return out;
        }
        // BSDF sampling.
        let Some(bs) = sp.bsdf.sample(st.get2(Dim::Bsdf { bounce })) else {
            return out;
        };
        let wi = bs.wi;
        if sp.ng.dot(wi) <= 0.0 {
            return out;
        }
        let pmf = |li: usize| kf * selector.map_or(1.0, |s| s.pmf(&r, li));
        c.rays += 1;
        // Either side blocks, as for shadow rays.
        let hit = closest(w, origin, wi, 0.0, f64::INFINITY, true);
        if w.textured_emission
            && let Some(h) = &hit
        {
            // No light technique samples it: the BSDF sample's full weight.
            let e = bs.weight * w.materials.emission(w.scene, h);
            if e.is_finite() {
                out += e;
            }
        }
        let t_geo = hit.map_or(f64::INFINITY, |h| h.t);
        let mut add = |l: &Light, le: DVec3, pdf_l: f64| {
            let base = l.base();
            if le != DVec3::ZERO && base.plain_shadows() && base.illuminates(sp.mesh, sp.instance) {
                let mis = power_heuristic(bs.pdf, pdf_l);
                let contrib = if one_scale(&sp.bsdf, base) {
                    bs.weight * le * (mis * base.diffuse)
                } else {
                    // The sample's weight f·cos/pdf with each part of f scaled.
                    let f = sp.bsdf.f(wi);
                    let scaled = sp.bsdf.f_scaled(wi, base.diffuse, base.specular);
                    let ratio = DVec3::select(f.cmpgt(DVec3::ZERO), scaled / f, DVec3::ZERO);
                    bs.weight * le * ratio * mis
                };
                if contrib.is_finite() {
                    out += contrib;
                }
            }
        };
        w.lights.lights_crossed(origin, wi, 0.0, t_geo, |li, h| {
            if h.front && (li >= 64 || light_only & (1 << li) == 0) {
                let l = &lights[li];
                add(l, l.le(h.local, -wi, Seen::Lit), pmf(li) * l.pdf_li(&r, wi));
            }
        });
        match hit {
            Some(h) => {
                // The back of a single-sided emitter emits nothing (light samples never reach
                // it: the sampler checks the side).
                if let Some(li) = w.lights.light_of(h.mesh, h.instance)
                    && (!h.back || w.scene.meshes[h.mesh].double_sided)
                {
                    let l = &lights[li];
                    add(
                        l,
                        l.le(l.base().to_local(h.p), -wi, Seen::Lit),
                        // The density of the point it hit, as light samples from `p` reach
                        // it (the ray left from `origin`: along `wi` from `p` it may pass the
                        // triangle's edge).
                        pmf(li) * l.pdf_li_triangle(&r, h.tri, (h.p - sp.p).normalize()),
                    );
                }
            }
            None => {
                for &li in &w.lights.infinite {
                    let l = &lights[li];
                    add(l, l.le_escape(wi), pmf(li) * l.pdf_li(&r, wi));
                }
            }
        }
        out
    }
}
