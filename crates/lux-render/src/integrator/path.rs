//! The `path` integrator: global illumination by path tracing, built on the direct
//! integrator's estimate at every vertex.
//!
//! A path starts as the direct integrator's camera ray (visible lights, background, a mesh
//! light's glow at the first surface). At each surface vertex `b` it adds, weighted by the
//! path throughput β, the direct integrator's estimate with the random numbers of vertex `b`:
//! next-event estimation through the light interface (MIS against BSDF sampling) and the
//! emission found along the BSDF sample `Dim::Bsdf { bounce: b }` (MIS against light
//! sampling). The path then continues along that same BSDF sample, β ← β·f·cos/pdf, to the
//! first surface on either side (what blocks light for the vertex's estimate); the emission
//! of what it meets was already counted there. The back of a single-sided surface ends the
//! path: it blocks, but reflects nothing (camera rays do not see it either). After [`ROULETTE_DEPTH`] vertices Russian
//! roulette ends the path with probability 1 − q, q = min(1, max(β)), and divides β by q; at
//! most `max_depth` vertices are lit (`max_depth = 1` is the direct integrator, bit for bit).

use super::direct::{CameraVertex, DirectIntegrator};
use super::{CameraRay, World, closest};
use crate::film::Counters;
use crate::sampler::{Dim, SampleStream};
use glam::DVec3;

/// Vertices lit before Russian roulette may end a path.
pub const ROULETTE_DEPTH: u32 = 3;

/// Path tracing with next-event estimation and MIS at every vertex.
#[derive(Clone, Copy)]
pub struct PathIntegrator<'a> {
    direct: DirectIntegrator<'a>,
    /// Most surface vertices lit along a path (≥ 1).
    max_depth: u32,
}

impl<'a> PathIntegrator<'a> {
    /// The scene it renders.
    pub(super) fn world(&self) -> &World<'a> {
        &self.direct.world
    }

    /// Paths of at most `max_depth` (≥ 1) lit vertices over the direct integrator's estimate.
    pub fn new(direct: DirectIntegrator<'a>, max_depth: u32) -> PathIntegrator<'a> {
        PathIntegrator {
            direct,
            max_depth: max_depth.max(1),
        }
    }

    /// Radiance and alpha along a camera ray.
    pub fn li(&self, ray: &CameraRay, st: &SampleStream, c: &mut Counters) -> (DVec3, f64) {
        let (mut sp, glow) = match self.direct.camera_vertex(ray, c) {
            CameraVertex::Done(rgb, alpha) => return (rgb, alpha),
            CameraVertex::Surface(hit, glow) => {
                let w = &self.direct.world;
                (w.materials.at(w.scene, &hit, ray.d), glow)
            }
        };
        let w = &self.direct.world;
        let mut rgb = glow;
        let mut beta = DVec3::ONE;
        for bounce in 0..self.max_depth {
            rgb += beta * self.direct.direct(&sp, st, bounce, c);
            if bounce + 1 == self.max_depth {
                break;
            }
            let Some(bs) = sp.bsdf.sample(st.get2(Dim::Bsdf { bounce })) else {
                break;
            };
            if sp.ng.dot(bs.wi) <= 0.0 {
                break;
            }
            beta *= bs.weight;
            if bounce + 1 >= ROULETTE_DEPTH {
                let q = beta.max_element().min(1.0);
                if q.is_nan() || q <= 0.0 || st.get1(Dim::Roulette { bounce }) >= q {
                    break;
                }
                beta /= q;
            }
            c.rays += 1;
            let origin = sp.p + sp.ng * sp.offset;
            let Some(hit) = closest(w, origin, bs.wi, 0.0, f64::INFINITY, true) else {
                break;
            };
            // The back of a single-sided surface blocks light (as for shadow rays) but has no
            // material there: camera rays cull it, and the path ends on it (black).
            if hit.back && !w.scene.meshes[hit.mesh].double_sided {
                break;
            }
            sp = w.materials.at(w.scene, &hit, bs.wi);
        }
        (rgb, 1.0)
    }
}
