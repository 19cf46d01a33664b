//! Next-event estimation: the direct illumination of a surface point, written once for every
//! integrator that lights its vertices (direct, path).
//!
//! - **Light sampling**: every light (or one light chosen by lux-sample's selection when there
//!   are many) sampled with its lux-sample technique, a shadow ray per sample (`shadow.rs`);
//!   `k` samples per light, each weighted `1/k`. Past the camera's vertex, the one-sample
//!   light samples of several lights with opaque plain shadows share `Setup::shadow_rays`
//!   shadow rays instead (`Nee::resolve`): picked in proportion to their unshadowed
//!   contributions `wᵢ` by systematic resampling and weighted `W/(k·wᵢ)`, the same
//!   expectation (resampled importance sampling's estimate of their sum, Talbot et al. 2005).
//! - **BSDF sampling**: one direction from the BSDF, which collects the emission of every
//!   analytic light it crosses before the first surface (lights are not occluders, as in the
//!   reference renderer), of the mesh light it hits, or of the infinite lights if it escapes.
//! - Combined with the power heuristic (β = 2) of multiple importance sampling; the light
//!   technique's density is `k·pmf·pdf`.
//!
//! Light sampling alone (no BSDF ray) for the rect, disk and sphere lights of uniform radiance
//! at a Lambertian point: their samplers follow the cosine-weighted solid angle (the sphere's
//! projected cap exactly, the rect's bilinear cosine warp closely), so a BSDF sample would only
//! add noise. That holds with a selector too: its probabilities are conservative (a light BVH
//! gives 0 only to lights that cannot reach the point), so every light that lights the point
//! is chosen with some probability. When every light is sampled, [`Visibility::estimate`]
//! may answer exactly (the light's closed form where nothing blocks it, its exact penumbra
//! behind a few triangles) instead of the samples.
//!
//! [`SamplingMode::Reference`] is hdEmbree's estimator instead: every light sampled with
//! lux-sample's [`Strategy::HdEmbree`] (uniformly by area; the dome uniformly over the
//! hemisphere), light sampling only. Lights with non-default `ShadowAPI` inputs (coloured,
//! distance-limited or disabled shadows, shadow links) are estimated by light sampling alone:
//! a BSDF ray stops at the first occluder, which is not what their shadow says.

use super::{Ctx, SamplingMode, Setup, power_heuristic, shadow_ray};
use crate::geometry::{Hit, shadow_ray_to, shadow_tmax};
use crate::light::{LiSample, Light, LightBase, Seen};
use crate::material::{Bsdf, BsdfSample, SurfacePoint};
use crate::sampler::{Dim, SampleStream};
use crate::visibility::{ShadowHint, Visibility};
use crate::world::World;
use glam::DVec3;
use lux_sample::{LightSelector, Reference, Strategy};

/// Next-event estimation over a scene.
#[derive(Clone, Copy)]
pub(super) struct Nee<'a> {
    pub(super) world: World<'a>,
    pub(super) vis: &'a Visibility,
    /// The light-sampling strategy.
    strategy: Strategy,
    /// BSDF sampling and MIS (off for the reference estimator).
    mis: bool,
    /// One light per shading point by the light set's selector (off: every light).
    select: bool,
    /// Light samples per light (or per light choice) at each shading point.
    light_samples: u32,
    /// Whether every light is a rect, disk or sphere of uniform radiance
    /// ([`Light::uniform_area`]): at a Lambertian point, all are then estimated by light
    /// sampling alone and no BSDF ray is needed.
    all_uniform: bool,
    /// Shadow rays the pooled light samples of a vertex past the camera's share (0: one
    /// each, no pool).
    shadow_rays: u32,
}

/// What the light samples of one shading point share.
struct At {
    /// The receiver lux-sample samples from.
    r: Reference,
    /// Where its rays start (`p` off the surface by its offset, on the viewer's side).
    origin: DVec3,
    /// Where rays through a transmitting surface start (`p` off its other side).
    origin_back: DVec3,
    /// Whether the BSDF transmits: lights behind the surface count too.
    transmits: bool,
    /// Light samples per light (or light choice).
    k: u32,
    /// The BSDF is Lambertian (and MIS is on): uniform lights go alone.
    lambertian: bool,
}

impl At {
    /// Whether `light` is estimated by light sampling alone here.
    #[inline]
    fn alone(&self, light: &Light) -> bool {
        self.lambertian && light.uniform_area()
    }
}

/// Whether a light's `inputs:diffuse` and `inputs:specular` act on `bsdf` as one factor
/// (`diffuse`): a Lambertian BSDF has no specular part, or the two are equal.
#[inline]
fn one_scale(bsdf: &Bsdf, base: &LightBase) -> bool {
    matches!(bsdf, Bsdf::Diffuse(_)) || base.diffuse == base.specular
}

/// The BSDF sample an estimate traced (for its emission) and what its ray met, which a path
/// continues along without tracing it again.
#[derive(Clone, Copy, Debug)]
pub(super) struct Traced {
    /// The sample (`Dim::Bsdf { bounce }`).
    pub bs: BsdfSample,
    /// The first surface on either side along it (`None`: it escaped).
    pub hit: Option<Hit>,
}

/// One light sample before its shadow ray: what it adds were nothing in the way, and the ray.
#[derive(Clone, Copy, Debug)]
pub(super) struct Candidate {
    /// Shadow ray: origin, direction, distance.
    ray: (DVec3, DVec3, f64),
    /// BSDF times the light's radiance.
    fl: DVec3,
    /// The scalar factor: cos θ · MIS weight · diffuse multiplier / (pmf · pdf).
    s: f64,
}

/// The light samples of a shading point whose shadow rays are resampled together
/// (`Nee::resolve`): those of lights with opaque plain shadows, each with its light's index
/// and its unshadowed contribution `wᵢ = |c|₁` (> 0, finite). A worker's one buffer
/// ([`Ctx::pool`]), refilled at each vertex.
#[derive(Clone, Debug, Default)]
pub struct ShadowPool(Vec<(u32, Candidate, f64)>);

impl<'a> Nee<'a> {
    /// The estimator of `setup`: its scene, visibility, sampling mode, light samples per
    /// light or light choice (≥ 1) and shadow rays past the camera's vertex.
    pub(super) fn new(setup: &Setup<'a>) -> Nee<'a> {
        let lux = setup.sampling == SamplingMode::Lux;
        let world = setup.world;
        Nee {
            world,
            vis: setup.vis,
            strategy: if lux {
                Strategy::Lux
            } else {
                Strategy::HdEmbree
            },
            mis: lux,
            select: lux,
            light_samples: setup.light_samples.max(1),
            all_uniform: world.lights.lights.iter().all(Light::uniform_area),
            shadow_rays: setup.shadow_rays,
        }
    }

    /// How one light sample of `light` is drawn at path vertex `bounce`: the sampling mode's
    /// technique, except for a rect light that goes `alone` (no MIS, so no other density to
    /// agree with) after the camera's vertex, drawn uniformly by area (`Strategy::HdEmbree`,
    /// density `d²/(A·cos θₗ)`): the solid-angle rectangle with its cosine warp costs several
    /// times as much, and past the first vertex a path's noise is its directions, not its
    /// light samples (time × variance −12 % on the Cornell box, −23 % on the StandardShaderBall's
    /// five RectLights, −1 to −3 % on clutter_mix; BENCHMARKS.md, issue 39). Sphere lights keep
    /// their cone (area sampling them lost 3×).
    #[inline(always)]
    fn strategy_for(&self, light: &Light, alone: bool, bounce: u32) -> Strategy {
        if alone && bounce >= 1 && matches!(light, Light::Rect(_)) {
            Strategy::HdEmbree
        } else {
            self.strategy
        }
    }

    /// The selector of one light per shading point, when used.
    #[inline]
    fn selector(&self) -> Option<&'a LightSelector> {
        if self.select {
            self.world.lights.selector.as_ref()
        } else {
            None
        }
    }

    /// Direct illumination at a surface point with the random numbers of path vertex `bounce`
    /// (0 for the surface a camera ray meets): light sampling, and the emission found along
    /// the BSDF sample `Dim::Bsdf { bounce }` (with MIS), which a path continues along.
    #[inline(always)]
    pub(super) fn estimate(
        &self,
        sp: &SurfacePoint,
        st: &SampleStream,
        bounce: u32,
        ctx: &mut Ctx,
    ) -> DVec3 {
        self.estimate_keeping(sp, st, bounce, ctx, &mut None)
    }

    /// [`Nee::estimate`], keeping in `traced` the BSDF sample it traced, if it traced one.
    #[inline(always)]
    pub(super) fn estimate_keeping(
        &self,
        sp: &SurfacePoint,
        st: &SampleStream,
        bounce: u32,
        ctx: &mut Ctx,
        traced: &mut Option<Traced>,
    ) -> DVec3 {
        let w = &self.world;
        if (w.lights.lights.is_empty() && !w.textured_emission) || sp.bsdf.is_black() {
            return DVec3::ZERO;
        }
        let selector = self.selector();
        let transmits = sp.bsdf.transmits();
        let at = At {
            // A transmitting surface is lit from both sides: no hemisphere to sample within.
            r: if transmits {
                Reference::point(sp.p)
            } else {
                Reference::surface(sp.p, sp.ns)
            },
            origin: sp.p + sp.ng * sp.offset,
            origin_back: sp.p - sp.ng * sp.offset,
            transmits,
            k: self.light_samples * st.light_factor(),
            lambertian: self.mis && sp.bsdf.is_lambertian(),
        };
        let mut out = match selector {
            None => self.every_light(sp, st, bounce, &at, ctx),
            Some(sel) => self.chosen_lights(sel, sp, st, bounce, &at, ctx),
        };
        // Every light estimated by light sampling alone: no BSDF ray (unless surfaces glow
        // from textures, which only BSDF rays find).
        if (at.lambertian && self.all_uniform && !w.textured_emission) || !self.mis {
            return out;
        }
        if let Some(bs) = super::sample_bsdf(&sp.bsdf, st, bounce)
            && (sp.ng.dot(bs.wi) > 0.0 || at.transmits)
        {
            // (added to `out` term by term, in the order of the terms)
            let hit = self.bsdf_sample(sp, &bs, &at, selector, ctx, &mut out);
            *traced = Some(Traced { bs, hit });
        }
        out
    }

    /// Light sampling of every light: `k` samples each, or its exact answer
    /// ([`Visibility::estimate`]) where it goes alone.
    #[inline(always)]
    fn every_light(
        &self,
        sp: &SurfacePoint,
        st: &SampleStream,
        bounce: u32,
        at: &At,
        ctx: &mut Ctx,
    ) -> DVec3 {
        let kf = at.k as f64;
        let mut out = DVec3::ZERO;
        // Past the camera's vertex, the light samples of several lights share the pool's
        // shadow rays (at the camera's vertex, every one keeps its own: resampling them lost
        // there, BENCHMARKS.md).
        let rays = if bounce > 0 && self.world.lights.lights.len() > 1 {
            self.shadow_rays
        } else {
            0
        };
        let mut pool = if rays > 0 {
            std::mem::take(&mut ctx.pool)
        } else {
            ShadowPool::default()
        };
        pool.0.clear();
        for (li, light) in self.world.lights.lights.iter().enumerate() {
            // (light linking: an unlinked light adds nothing here, nor by BSDF sampling)
            if !light.base().illuminates(sp.mesh, sp.instance) {
                continue;
            }
            let alone = at.alone(light);
            let dim = Dim::Light {
                bounce,
                index: li as u32,
            };
            if at.k == 1 {
                let strategy = self.strategy_for(light, alone, bounce);
                let ls = light.sample_li(&at.r, st.get2(dim), strategy);
                if let Some(c) = self.unshadowed(sp, at, light, ls, kf, alone, ctx) {
                    out += self.pool_or_trace(&mut pool, rays, li, c, ctx);
                }
                continue;
            }
            // What the light's k samples share, computed once.
            light.seen_from(&at.r, self.strategy, |from| {
                let base = light.base();
                let e = self
                    .vis
                    .estimate(&self.world, &mut ctx.vis, sp, li, light, from, alone);
                if let Some((wi, pass)) = e.exact
                    && let Some(le_pi) = from.unshadowed(sp.p, sp.ns)
                {
                    // The light's closed form `L·Π` (times what passes): what its k samples
                    // average to, without drawing them.
                    let le_pi = le_pi * pass;
                    out += if one_scale(&sp.bsdf, base) {
                        sp.bsdf.f(wi) * le_pi * base.diffuse
                    } else {
                        sp.bsdf.f_scaled(wi, base.diffuse, base.specular) * le_pi
                    };
                    return;
                }
                for u in st.split_get2(dim, at.k) {
                    let ls = from.sample_li(u);
                    out += self.sample_light(sp, at, light, ls, kf, alone, &e.hint, ctx);
                }
            });
        }
        if rays > 0 {
            out += self.resolve(&pool.0, rays as usize, st, bounce, ctx);
            ctx.pool = pool;
        }
        out
    }

    /// Puts the candidate `c` of light `li` in `pool` if its shadow ray may be resampled
    /// (`rays` > 0, opaque plain shadows), else traces it: what it adds now.
    #[inline(always)]
    fn pool_or_trace(
        &self,
        pool: &mut ShadowPool,
        rays: u32,
        li: usize,
        c: Candidate,
        ctx: &mut Ctx,
    ) -> DVec3 {
        let l = &self.world.lights.lights[li];
        if rays == 0
            || self.world.transparent
            || !l.base().shadow.enable
            || !l.base().plain_shadows()
        {
            return self.shadowed(&c, l, &ShadowHint::NONE, ctx);
        }
        let w = c.fl.abs().element_sum() * c.s.abs();
        // (adding nothing, or nothing finite, which is dropped, whatever its shadow ray finds)
        if w > 0.0 && w.is_finite() {
            pool.0.push((li as u32, c, w));
        }
        DVec3::ZERO
    }

    /// The pooled light samples' contribution through `k` shadow rays: every candidate traced
    /// when there are no more than `k`, else `k` picks by systematic resampling in proportion
    /// to the unshadowed contributions `wᵢ` (`|c|₁`), one number `u` (`Dim::ShadowPick`) for
    /// the `k` evenly spaced points `(j + u)/k` of their cumulative sum `W`, each pick
    /// weighted `W/(k·wᵢ)` (picks of one candidate share its ray): unbiased for the sum of
    /// the candidates' shadowed contributions, and exactly it where every pick is unblocked
    /// and the candidates' colours agree.
    fn resolve(
        &self,
        pool: &[(u32, Candidate, f64)],
        k: usize,
        st: &SampleStream,
        bounce: u32,
        ctx: &mut Ctx,
    ) -> DVec3 {
        let lights = &self.world.lights.lights;
        let mut out = DVec3::ZERO;
        if pool.len() <= k {
            for (li, c, _) in pool {
                out += self.shadowed(c, &lights[*li as usize], &ShadowHint::NONE, ctx);
            }
            return out;
        }
        let total: f64 = pool.iter().map(|p| p.2).sum();
        let u = st.get1(Dim::ShadowPick { bounce });
        let kf = k as f64;
        let (mut i, mut cum) = (0, pool[0].2);
        let mut j = 0;
        while j < k {
            let t = (j as f64 + u) / kf * total;
            while t >= cum && i + 1 < pool.len() {
                i += 1;
                cum += pool[i].2;
            }
            let mut m = 1;
            while j + m < k && ((j + m) as f64 + u) / kf * total < cum {
                m += 1;
            }
            let (li, c, w) = &pool[i];
            let scale = m as f64 * total / (kf * w);
            out += self.shadowed(c, &lights[*li as usize], &ShadowHint::NONE, ctx) * scale;
            j += m;
        }
        out
    }

    /// Light sampling of `k` lights chosen by the selector `sel`.
    fn chosen_lights(
        &self,
        sel: &LightSelector,
        sp: &SurfacePoint,
        st: &SampleStream,
        bounce: u32,
        at: &At,
        ctx: &mut Ctx,
    ) -> DVec3 {
        let lights = &self.world.lights.lights;
        let mut out = DVec3::ZERO;
        // The k choices of the point, made in one descent of the selector per 16 (they share
        // the top of a light BVH), each then sampled as its own sub-sample.
        const CHUNK: u32 = 16;
        let (mut us, mut chosen) = ([0.0; CHUNK as usize], [None; CHUNK as usize]);
        for j0 in (0..at.k).step_by(CHUNK as usize) {
            let n = (at.k - j0).min(CHUNK) as usize;
            for (i, u) in us[..n].iter_mut().enumerate() {
                *u = st
                    .split(j0 + i as u32, at.k)
                    .get1(Dim::LightChoice { bounce });
            }
            sel.sample_each(&at.r, &us[..n], &mut chosen[..n]);
            for (i, c) in chosen[..n].iter().enumerate() {
                if let Some((li, pmf)) = *c
                    && pmf > 0.0
                    && lights[li].base().illuminates(sp.mesh, sp.instance)
                {
                    let l = &lights[li];
                    let sj = st.split(j0 + i as u32, at.k);
                    let u = sj.get2(Dim::Light { bounce, index: 0 });
                    let alone = at.alone(l);
                    let ls = l.sample_li(&at.r, u, self.strategy_for(l, alone, bounce));
                    let pmf = pmf * at.k as f64;
                    out += self.sample_light(sp, at, l, ls, pmf, alone, &ShadowHint::NONE, ctx);
                }
            }
        }
        out
    }

    /// The contribution of the light sample `ls` of light `l`, chosen with probability `pmf`
    /// (times k), with MIS against BSDF sampling unless `alone`; `hint`: what the visibility
    /// knows of its shadow ray.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn sample_light(
        &self,
        sp: &SurfacePoint,
        at: &At,
        l: &Light,
        ls: Option<LiSample>,
        pmf: f64,
        alone: bool,
        hint: &ShadowHint,
        ctx: &mut Ctx,
    ) -> DVec3 {
        match self.unshadowed(sp, at, l, ls, pmf, alone, ctx) {
            Some(c) => self.shadowed(&c, l, hint, ctx),
            None => DVec3::ZERO,
        }
    }

    /// The light sample `ls` of light `l` as a [`Candidate`]: its contribution were nothing
    /// in the way (MIS-weighted, divided by `pmf · pdf`) and its shadow ray; `None` when it
    /// adds nothing whatever the shadow ray finds.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn unshadowed(
        &self,
        sp: &SurfacePoint,
        at: &At,
        l: &Light,
        ls: Option<LiSample>,
        pmf: f64,
        alone: bool,
        ctx: &mut Ctx,
    ) -> Option<Candidate> {
        let ls = ls?;
        ctx.counters.light_samples += 1;
        let mut cos = sp.ns.dot(ls.wi);
        let side = sp.ng.dot(ls.wi);
        let mut origin = at.origin;
        if at.transmits && side < 0.0 {
            // Behind a transmitting surface: the shading normal must agree on the side.
            if cos >= 0.0 {
                return None;
            }
            cos = -cos;
            origin = at.origin_back;
        }
        if cos <= 0.0 || side == 0.0 || ls.pdf.is_nan() || ls.pdf <= 0.0 {
            return None;
        }
        if side < 0.0 && !at.transmits {
            return None;
        }
        if ls.l == DVec3::ZERO {
            return None;
        }
        // A mesh light is geometry: its shadow ray aims at the sampled point from `origin`
        // (`shadow_ray_to`); other lights are not occluders.
        let (dir, tmax) = match l {
            Light::Mesh(_) => shadow_ray_to(origin, ls.point)?,
            _ if ls.dist.is_finite() => (ls.wi, shadow_tmax(ls.dist, ls.point)),
            _ => (ls.wi, f64::INFINITY),
        };
        if tmax <= 0.0 {
            return None;
        }
        let base = l.base();
        let pdf = pmf * ls.pdf;
        let weight = if alone || ls.delta || !self.mis || !base.plain_shadows() {
            1.0
        } else {
            power_heuristic(pdf, sp.bsdf.pdf(ls.wi))
        };
        // The light's inputs:diffuse and inputs:specular scale the two parts of f; one scale
        // for a Lambertian surface or equal multipliers.
        let (fl, s) = if one_scale(&sp.bsdf, base) {
            (sp.bsdf.f(ls.wi) * ls.l, base.diffuse * cos * weight / pdf)
        } else {
            (
                sp.bsdf.f_scaled(ls.wi, base.diffuse, base.specular) * ls.l,
                cos * weight / pdf,
            )
        };
        Some(Candidate {
            ray: (origin, dir, tmax),
            fl,
            s,
        })
    }

    /// A candidate's contribution through its shadow ray.
    #[inline(always)]
    fn shadowed(&self, c: &Candidate, l: &Light, hint: &ShadowHint, ctx: &mut Ctx) -> DVec3 {
        let Some(vis) = shadow_ray(&self.world, self.vis, l.base(), c.ray, hint, ctx) else {
            return DVec3::ZERO;
        };
        let contrib = c.fl * vis * c.s;
        if contrib.is_finite() {
            contrib
        } else {
            DVec3::ZERO
        }
    }

    /// The emission found along the BSDF sample `bs` (MIS against light sampling): analytic
    /// lights it crosses before the first surface, the mesh light or textured emission it
    /// hits, the lights at infinity if it escapes, added to `out`. Returns the surface hit.
    fn bsdf_sample(
        &self,
        sp: &SurfacePoint,
        bs: &BsdfSample,
        at: &At,
        selector: Option<&LightSelector>,
        ctx: &mut Ctx,
        out: &mut DVec3,
    ) -> Option<Hit> {
        let w = &self.world;
        let lights = &w.lights.lights;
        let wi = bs.wi;
        let kf = at.k as f64;
        let pmf = |li: usize| kf * selector.map_or(1.0, |s| s.pmf(&at.r, li));
        // MIS against light sampling, which cannot reach the direction of a delta lobe.
        let mis_weight = |pdf_l: f64| {
            if bs.delta {
                1.0
            } else {
                power_heuristic(bs.pdf, pdf_l)
            }
        };
        let origin = if sp.ng.dot(wi) < 0.0 {
            at.origin_back
        } else {
            at.origin
        };
        ctx.counters.rays += 1;
        // Either side blocks, as for shadow rays.
        let hit = super::closest(w, origin, wi, 0.0, f64::INFINITY, true);
        if w.textured_emission
            && let Some(h) = &hit
        {
            // No light technique samples it: the BSDF sample's full weight.
            let e = bs.weight * w.materials.emission(w.scene, h);
            if e.is_finite() {
                *out += e;
            }
        }
        let t_geo = hit.map_or(f64::INFINITY, |h| h.t);
        let mut add = |l: &Light, le: DVec3, pdf_l: f64| {
            let base = l.base();
            if le != DVec3::ZERO && base.plain_shadows() && base.illuminates(sp.mesh, sp.instance) {
                let mis = mis_weight(pdf_l);
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
                    *out += contrib;
                }
            }
        };
        w.lights.lights_crossed(origin, wi, 0.0, t_geo, |li, h| {
            let l = &lights[li];
            if h.front && !at.alone(l) {
                add(
                    l,
                    l.le(h.local, -wi, Seen::Lit),
                    pmf(li) * l.pdf_li(&at.r, wi),
                );
            }
        });
        match &hit {
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
                        pmf(li) * l.pdf_li_triangle(&at.r, h.tri, (h.p - sp.p).normalize()),
                    );
                }
            }
            None => {
                for &li in &w.lights.infinite {
                    let l = &lights[li];
                    add(l, l.le_escape(wi), pmf(li) * l.pdf_li(&at.r, wi));
                }
            }
        }
        hit
    }
}
