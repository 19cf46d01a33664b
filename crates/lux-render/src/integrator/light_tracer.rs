//! The `light` integrator: light tracing (particle tracing), pbrt-v4's `LightPathIntegrator`.
//!
//! Each camera sample traces one particle from the lights: a light chosen in proportion to its
//! estimated power, a point and direction leaving it ([`Light::sample_le`]) carrying
//! `β = Le·|cos θ| / (p_light · p_A · p_ω)`. At every surface it reaches — up to `max_depth`
//! of them, as a path of the path integrator lights at most `max_depth` vertices — the
//! particle is connected to the camera: if the camera ray through the point's projection
//! ([`Camera::project`]) reaches it unblocked, it adds the splat
//!
//! `β · f(ωᵢ, ω_c) · |nₛ·ωᵢ| / |n_g·ωᵢ| · |n_g·ω_c| · W`
//!
//! to that pixel, `W` the camera's importance ([`CameraPoint::importance`]) and the ratio of
//! cosines the adjoint correction for shading normals (Veach 1997, §5.3). It then continues
//! along a BSDF sample, `β ← β·f·|nₛ·ωᵢ|·|n_g·ωₒ| / (p·|n_g·ωᵢ|)`, with Russian roulette on
//! its throughput after [`PARTICLE_ROULETTE_DEPTH`] vertices. The film divides the splats' sums by the
//! number of camera samples of the render (one particle each).
//!
//! What the camera sees directly — visible lights, the background, a surface's glow — comes
//! from the camera ray (`camera_vertex.rs`), so the two estimators split the paths between
//! them without overlap: the light tracer's picture equals the path tracer's in expectation
//! (`tests/render_light_tracer.rs` checks it on the Cornell box).
//!
//! As the particles see the scene: light linking holds at the first surface a particle meets
//! (where next-event estimation would sample the light), as do a light's `inputs:diffuse` and
//! `inputs:specular`. Shadow linking and non-default `ShadowAPI` inputs (coloured,
//! distance-limited or disabled shadows) are not followed — particles stop at the first
//! surface as plain shadows do — and surfaces glowing through a texture or primvar emission
//! send no particles: both are warnings ([`Integrator::warnings`]).
//!
//! [`Light::sample_le`]: crate::light::Light::sample_le
//! [`CameraPoint::importance`]: crate::camera::CameraPoint::importance

use super::camera_vertex::{CameraVertex, camera_vertex};
use super::{CameraRay, Ctx, Integrator, Setup, closest};
use crate::camera::Camera;
use crate::film::Splat;
use crate::geometry::Hit;
use crate::light::{Light, LightBase};
use crate::material::{Bsdf, SurfacePoint};
use crate::sampler::{Dim, SampleStream};
use crate::visibility::Visibility;
use crate::world::World;
use glam::DVec3;
use lux_sample::AliasTable;
use std::f64::consts::PI;

/// Vertices a particle passes before Russian roulette may end it. It stays at the 3rd where
/// the path tracer's moved later ([`super::ROULETTE_DEPTH`]): for particles the 5th as a
/// start cost 4–9 % more time × variance (Cornell box and a clutter scene, 128², 16 spp;
/// BENCHMARKS.md, issue 39).
pub const PARTICLE_ROULETTE_DEPTH: u32 = 3;

/// Light tracing: particles from the lights, splatted to the camera at every vertex.
pub struct LightTracer<'a> {
    world: World<'a>,
    vis: &'a Visibility,
    camera: &'a Camera,
    /// Most surface vertices a particle reaches (≥ 1).
    max_depth: u32,
    /// The lights' choice by estimated power; `None` when none emits.
    choice: Option<AliasTable>,
    /// A sphere holding the scene (centre, radius), which particles from lights at infinity
    /// enter through.
    bounds: (DVec3, f64),
}

/// The light's estimated power for the choice of a particle's light: `LightBase::power` for a
/// finite light, `Y(L)·π·πR²` (a uniform sky's flux through the scene's disk) for one at
/// infinity.
fn choice_weight(l: &Light, radius: f64) -> f64 {
    let base = l.base();
    let w = if l.is_infinite() {
        lux_math::luminance(base.radiance) * PI * PI * radius * radius
    } else {
        base.power
    };
    if w.is_finite() && w > 0.0 { w } else { 0.0 }
}

impl<'a> LightTracer<'a> {
    /// A light tracer over `setup`'s scene, paths of at most `setup.max_depth` vertices.
    pub fn new(setup: &Setup<'a>) -> LightTracer<'a> {
        let w = setup.world;
        let bounds = w
            .geometry
            .world_bounds()
            .map_or((DVec3::ZERO, 1.0), |(lo, hi)| {
                let r = 0.5 * (hi - lo).length();
                (0.5 * (lo + hi), (r * 1.001).max(1e-6))
            });
        let weights: Vec<f64> = w
            .lights
            .lights
            .iter()
            .map(|l| choice_weight(l, bounds.1))
            .collect();
        LightTracer {
            world: w,
            vis: setup.vis,
            camera: setup.camera,
            max_depth: setup.max_depth.max(1),
            choice: AliasTable::new(&weights).ok(),
            bounds,
        }
    }

    /// Traces the particle of camera sample `st`, adding its splats to `ctx`.
    fn trace_particle(&self, st: &SampleStream, ctx: &mut Ctx) {
        let w = &self.world;
        let Some(choice) = &self.choice else {
            return;
        };
        let (li, pmf) = choice.sample(st.get1(Dim::LightChoice { bounce: 0 }));
        let light = &w.lights.lights[li];
        ctx.counters.light_samples += 1;
        let u_pos = st.get2(Dim::Light {
            bounce: 0,
            index: 0,
        });
        let u_dir = st.get2(Dim::Light {
            bounce: 0,
            index: 1,
        });
        let Some(le) = light.sample_le(u_pos, u_dir, self.bounds) else {
            return;
        };
        let mut beta = le.weight / pmf;
        // (the throughput since the light, for Russian roulette)
        let mut throughput = DVec3::ONE;
        let (mut o, mut d) = (le.origin, le.dir);
        for depth in 0..self.max_depth {
            ctx.counters.rays += 1;
            let Some(hit) = closest(w, o, d, 0.0, f64::INFINITY, true) else {
                return;
            };
            // The back of a single-sided surface absorbs (it has no material there).
            if hit.back && !w.scene.meshes[hit.mesh].double_sided {
                return;
            }
            // Light linking, and the light's diffuse and specular multipliers, at the first
            // surface: where next-event estimation samples the light.
            let first = (depth == 0).then_some(light.base());
            if first.is_some_and(|b| !b.illuminates(hit.mesh, hit.instance)) {
                return;
            }
            let sp = w.materials.at(w.scene, &hit, d);
            if sp.bsdf.is_black() {
                return;
            }
            self.splat(&sp, &hit, beta, -d, first, ctx);
            if depth + 1 == self.max_depth {
                return;
            }
            let Some(bs) = super::sample_bsdf(&sp.bsdf, st, depth) else {
                return;
            };
            let wi = -d;
            let cos_ng_o = sp.ng.dot(bs.wi);
            let cos_ns_o = sp.ns.dot(bs.wi).abs();
            if cos_ng_o <= 0.0 || cos_ns_o == 0.0 {
                return;
            }
            // A MaterialX tree need not be reciprocal (`layer` scales its base by the top's
            // albedo towards the viewer): the particle carries f(ωₒ, ωᵢ), the BSDF seen from
            // the direction it leaves by, evaluated towards the light it came from.
            let weight = if !sp.bsdf.reciprocal() && !bs.delta {
                let seen = w.materials.at(w.scene, &hit, -bs.wi);
                seen.bsdf.f(wi) * (cos_ns_o / bs.pdf)
            } else {
                bs.weight
            };
            // f·|nₛ·ωᵢ|·|n_g·ωₒ| / (p·|n_g·ωᵢ|) from the sample's f·|nₛ·ωₒ|/p
            let adjoint = sp.ns.dot(wi).abs() * cos_ng_o / (sp.ng.dot(wi).abs() * cos_ns_o);
            let step = weight * adjoint * first.map_or(DVec3::ONE, |b| scale(&sp.bsdf, b, bs.wi));
            beta *= step;
            throughput *= step;
            if depth + 1 >= PARTICLE_ROULETTE_DEPTH {
                let q = throughput.max_element().min(1.0);
                if q.is_nan() || q <= 0.0 || st.get1(Dim::Roulette { bounce: depth }) >= q {
                    return;
                }
                beta /= q;
                throughput /= q;
            }
            if !beta.is_finite() {
                return;
            }
            o = sp.p + sp.ng * sp.offset;
            d = bs.wi;
        }
    }

    /// Connects the particle at `sp` (arrived from direction `wi`, weight `beta`; `first`: the
    /// light, at the first surface) to the camera, adding its splat when the camera sees it.
    fn splat(
        &self,
        sp: &SurfacePoint,
        hit: &Hit,
        beta: DVec3,
        wi: DVec3,
        first: Option<&LightBase>,
        ctx: &mut Ctx,
    ) {
        let w = &self.world;
        let Some(cp) = self.camera.project(sp.p) else {
            return;
        };
        let (o, dir) = cp.ray;
        let wc = -dir;
        let cos_c = sp.ng.dot(wc);
        // (reflection only: the camera on the side the particle came from; camera rays do not
        // see the back of a single-sided surface)
        if cos_c <= 0.0 || (hit.ng.dot(dir) > 0.0 && !w.scene.meshes[hit.mesh].double_sided) {
            return;
        }
        // A MaterialX tree seen from the camera (it need not be reciprocal), towards the light.
        let seen;
        let (bsdf, towards) = if !sp.bsdf.reciprocal() {
            seen = w.materials.at(w.scene, hit, dir);
            (&seen.bsdf, wi)
        } else {
            (&sp.bsdf, wc)
        };
        let f = match first {
            Some(b) => scaled_f(bsdf, b, towards),
            None => bsdf.f(towards),
        };
        let cos_ng_i = sp.ng.dot(wi).abs();
        if f == DVec3::ZERO || cos_ng_i == 0.0 {
            return;
        }
        let value = beta * f * (sp.ns.dot(wi).abs() / cos_ng_i * cos_c * cp.importance);
        if value == DVec3::ZERO {
            return;
        }
        // The camera ray through the point reaches it unblocked (its surface's f32 clearance,
        // along the ray, kept before it).
        ctx.counters.rays += 1;
        let clear = 2.0 * sp.offset / cos_c.max(0.05);
        let near = cp.near_t.min(cp.t);
        if cp.t - clear > near && closest(w, o, dir, near, cp.t - clear, false).is_some() {
            return;
        }
        let pixel = cp.raster.map(|v| v.floor() as u32);
        ctx.splats.push(Splat { pixel, rgb: value });
    }
}

/// `f(ω)` with the light `b`'s `inputs:diffuse` and `inputs:specular` on its two parts.
fn scaled_f(bsdf: &Bsdf, b: &LightBase, wi: DVec3) -> DVec3 {
    if matches!(bsdf, Bsdf::Diffuse(_)) || b.diffuse == b.specular {
        bsdf.f(wi) * b.diffuse
    } else {
        bsdf.f_scaled(wi, b.diffuse, b.specular)
    }
}

/// The factor the light `b`'s multipliers put on a BSDF sample's weight towards `wi`: per
/// channel, the scaled `f` over `f`.
fn scale(bsdf: &Bsdf, b: &LightBase, wi: DVec3) -> DVec3 {
    let f = bsdf.f(wi);
    let scaled = scaled_f(bsdf, b, wi);
    DVec3::select(f.cmpgt(DVec3::ZERO), scaled / f, DVec3::ZERO)
}

impl Integrator for LightTracer<'_> {
    /// What the camera ray sees directly (lights, background, glow), and the particle of this
    /// camera sample, splatted.
    fn li(&self, ray: &CameraRay, st: &SampleStream, ctx: &mut Ctx) -> (DVec3, f64) {
        let seen = match camera_vertex(&self.world, self.vis, ray, ctx) {
            CameraVertex::Done(rgb, alpha) => (rgb, alpha),
            CameraVertex::Surface(_, glow) => (glow, 1.0),
        };
        self.trace_particle(st, ctx);
        seen
    }

    fn splats(&self) -> bool {
        true
    }

    fn warnings(&self) -> Vec<String> {
        let w = &self.world;
        let mut out: Vec<String> = w
            .lights
            .lights
            .iter()
            .filter(|l| !l.base().plain_shadows())
            .map(|l| {
                format!(
                    "light {}: the light tracer does not follow its ShadowAPI inputs or shadow \
                     links; its particles stop at the first surface (plain shadows)",
                    l.base().path
                )
            })
            .collect();
        if w.textured_emission {
            out.push(
                "the light tracer sends no particles from surfaces glowing through a texture or \
                 primvar emission: they are seen, but light nothing"
                    .to_owned(),
            );
        }
        out
    }
}
