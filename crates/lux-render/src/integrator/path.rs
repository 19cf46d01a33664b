//! The `path` integrator: global illumination by path tracing, with next-event estimation
//! (`nee.rs`) at every vertex.
//!
//! A path starts as every integrator's camera ray (`camera_vertex.rs`: visible lights, background,
//! a mesh light's glow at the first surface). At each surface vertex `b` it adds, weighted by the
//! path throughput β, next-event estimation with the random numbers of vertex `b`: light sampling
//! (MIS against BSDF sampling) and the emission found along the BSDF sample
//! `Dim::Bsdf { bounce: b }` (MIS against light sampling). The path then continues along that same
//! BSDF sample (from the camera's vertex, `splits` continuations, each drawn from its own
//! sub-sample [`SampleStream::split`] and weighted 1/`splits`: the camera ray, the first hit and
//! its direct light are shared by them), β ← β·f·cos/pdf, to the first surface on either side (what
//! blocks light for the vertex's estimate), through the surface when the sample was transmitted (a
//! dielectric's refraction, a translucent or thin-walled surface); the emission of what it meets
//! was already counted there. The back of a single-sided surface ends the path: it blocks, but
//! reflects nothing (camera rays do not see it either) — except where its material transmits, whose
//! inside a refracted path meets. After [`ROULETTE_DEPTH`] vertices Russian roulette ends the path
//! with probability 1 − q, q = min(1, [`ROULETTE_SCALE`]·max(β)), and divides β by q; at most
//! `max_depth` vertices are lit (`max_depth = 1` is the direct integrator, bit for bit). The
//! reference estimator (`SamplingMode::Reference`) has no BSDF sampling to continue along: a path
//! of it is the direct integrator.

use super::camera_vertex::{CameraVertex, camera_vertex};
use super::nee::{Nee, Traced};
use super::{BsdfPoint, CameraRay, Ctx, Integrator, SamplingMode, Setup, closest};
use crate::material::SurfacePoint;
use crate::sampler::{Dim, SampleStream};
use glam::DVec3;

/// Vertices lit before Russian roulette may end a path. From the 5th (Mitsuba 3's `rr_depth`)
/// rather than the 3rd, time × variance fell by 6–8 % on the Cornell box and two clutter
/// scenes (128², 64 spp, depth 8): the short paths that roulette ended early carried light
/// the box's walls pass on with albedos near 0.75. Once a path's later vertices drew cheaper,
/// independent numbers, the 4th was better again: time × squared error −2.9 % on the Cornell
/// box, −2.3 % on the StandardShaderBall, 0 to −2 % on four clutter scenes, where the 6th
/// lost 3.6 % on the box (BENCHMARKS.md, issue 39).
pub const ROULETTE_DEPTH: u32 = 4;

/// Russian roulette keeps a path with probability `q = min(1, ROULETTE_SCALE · max(β))`: a
/// path whose throughput is at least 1/2 always goes on. With Mitsuba 3's `q = max(β)`, a
/// scale of one, the paths killed at throughputs of 1/2 to 1 added more variance than their
/// rays saved: with 2, time × variance is 6 % lower on the Cornell box and 1–5 % on two
/// clutter scenes and the StandardShaderBall; 3 is no better (BENCHMARKS.md, issue 39).
pub const ROULETTE_SCALE: f64 = 2.0;

/// The BSDF sample a path leaves a vertex along ([`PathIntegrator::scatter`]).
#[derive(Clone, Copy)]
enum Along {
    /// The sample of these numbers.
    Draw(BsdfPoint),
    /// The sample the vertex's estimate traced, and what its ray met.
    Traced(Traced),
}

/// Path tracing with next-event estimation and MIS at every vertex.
#[derive(Clone, Copy)]
pub struct PathIntegrator<'a> {
    nee: Nee<'a>,
    /// Most surface vertices lit along a path (≥ 1).
    max_depth: u32,
    /// Continuations from the camera's vertex (≥ 1, [`Setup::splits`]).
    splits: u32,
}

impl<'a> PathIntegrator<'a> {
    /// Paths of at most `setup.max_depth` (≥ 1) lit vertices; 1 with the reference estimator.
    pub fn new(setup: &Setup<'a>) -> PathIntegrator<'a> {
        let max_depth = match setup.sampling {
            SamplingMode::Lux => setup.max_depth.max(1),
            SamplingMode::Reference => 1,
        };
        PathIntegrator {
            nee: Nee::new(setup),
            max_depth,
            splits: setup.splits.max(1),
        }
    }
}

impl PathIntegrator<'_> {
    /// Continues a path from `sp`, vertex `bounce`, along its BSDF sample (`along`: drawn
    /// from the vertex's numbers, or the one its estimate already traced, whose hit is taken
    /// instead of tracing the same ray again): `beta` takes the sample's weight (and Russian
    /// roulette's), and the surface met is returned (`None`: the path ends).
    #[inline]
    fn scatter(
        &self,
        sp: &SurfacePoint,
        st: &SampleStream,
        bounce: u32,
        beta: &mut DVec3,
        ctx: &mut Ctx,
        along: Along,
    ) -> Option<SurfacePoint> {
        let w = &self.nee.world;
        let (bs, traced) = match along {
            Along::Traced(t) => (t.bs, Some(t)),
            Along::Draw(point) => (point.sample(&sp.bsdf)?, None),
        };
        let side = sp.ng.dot(bs.wi);
        if side == 0.0 || (side < 0.0 && !sp.bsdf.transmits()) {
            return None;
        }
        *beta *= bs.weight;
        if bounce + 1 >= ROULETTE_DEPTH {
            let q = (ROULETTE_SCALE * beta.max_element()).min(1.0);
            if q.is_nan() || q <= 0.0 || st.get1(Dim::Roulette { bounce }) >= q {
                return None;
            }
            *beta /= q;
        }
        let hit = match traced {
            Some(t) => t.hit?,
            None => {
                ctx.counters.rays += 1;
                // Off the surface on the side the path leaves by (through it when
                // transmitted), as the estimate's BSDF ray leaves.
                let origin = sp.p + sp.ng * (sp.offset * side.signum());
                closest(w, origin, bs.wi, 0.0, f64::INFINITY, true)?
            }
        };
        // The back of a single-sided surface blocks light (as for shadow rays) but has no
        // material there: camera rays cull it, and the path ends on it (black) — unless
        // its material transmits, whose inside a refracted path sees (a solid glass
        // object is closed, whatever its `doubleSided`).
        if hit.back
            && !w.scene.meshes[hit.mesh].double_sided
            && !w.materials.transmits(w.scene, &hit)
        {
            return None;
        }
        Some(w.materials.at(w.scene, &hit, bs.wi))
    }

    /// What a path continued from the camera's vertex `sp0` brings back: the light of every
    /// later vertex, weighted by the throughput to it. `first`: the numbers of its first BSDF
    /// sample (vertex 0 of `st`).
    #[inline]
    fn continuation(
        &self,
        sp0: &SurfacePoint,
        st: &SampleStream,
        first: BsdfPoint,
        ctx: &mut Ctx,
    ) -> DVec3 {
        let mut beta = DVec3::ONE;
        let mut out = DVec3::ZERO;
        // (the camera vertex's estimate drew its BSDF sample from the unsplit stream: not
        // this continuation's)
        let Some(mut sp) = self.scatter(sp0, st, 0, &mut beta, ctx, Along::Draw(first)) else {
            return out;
        };
        for bounce in 1..self.max_depth {
            let last = bounce + 1 == self.max_depth;
            // (drawn before the estimate's shadow rays, which hide the hashing)
            let point = BsdfPoint::draw(&sp.bsdf, st, bounce);
            let mut traced = None;
            out += beta * self.nee.estimate_keeping(&sp, st, bounce, ctx, &mut traced);
            if last {
                break;
            }
            let along = match traced {
                Some(t) => Along::Traced(t),
                None => Along::Draw(point),
            };
            match self.scatter(&sp, st, bounce, &mut beta, ctx, along) {
                Some(next) => sp = next,
                None => break,
            }
        }
        out
    }
}

impl Integrator for PathIntegrator<'_> {
    /// Radiance and alpha along a camera ray.
    fn li(&self, ray: &CameraRay, st: &SampleStream, ctx: &mut Ctx) -> (DVec3, f64) {
        let w = &self.nee.world;
        let (sp, glow) = match camera_vertex(w, self.nee.vis, ray, ctx) {
            CameraVertex::Done(rgb, alpha) => return (rgb, alpha),
            CameraVertex::Surface(hit, glow) => (w.materials.at(w.scene, &hit, ray.d), glow),
        };
        let mut rgb = glow + self.nee.estimate(&sp, st, 0, ctx);
        if self.max_depth == 1 {
            return (rgb, 1.0);
        }
        // `k` continuations, each its own sub-sample of the pixel's stratified set (`k = 1`:
        // `split(0, 1)` is `st` itself, and the sum is divided by 1); the sample's own
        // count when adaptive splitting gave it one
        let k = match st.splits() {
            0 => self.splits,
            k => k,
        };
        let rays1 = ctx.counters.rays;
        let mut sum = DVec3::ZERO;
        let (mut y, mut y2) = (0.0, 0.0);
        // Each continuation's first numbers are drawn while the one before is traced.
        let first = |j| BsdfPoint::draw(&sp.bsdf, &st.split(j, k), 0);
        let mut next = first(0);
        for j in 0..k {
            let point = next;
            if j + 1 < k {
                next = first(j + 1);
            }
            let c = self.continuation(&sp, &st.split(j, k), point, ctx);
            let l = lux_math::luminance(c);
            (y, y2) = (y + l, y2 + l * l);
            sum += c;
        }
        let split = &mut ctx.split;
        if k > 1 {
            let kf = k as f64;
            split.spread += ((y2 - y * y / kf) / (kf - 1.0)).max(0.0);
            split.continuation_rays += ctx.counters.rays - rays1;
        }
        rgb += sum / k as f64;
        (rgb, 1.0)
    }

    fn splits(&self) -> u32 {
        if self.max_depth > 1 { self.splits } else { 1 }
    }
}
