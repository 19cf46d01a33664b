//! The `direct` integrator: the radiance a camera ray sees, lit directly by every light
//! (the reference renderer's light transport, with lux's sampling): at the first surface, its
//! glow plus next-event estimation (`nee.rs`).

use super::camera_vertex::{CameraVertex, camera_vertex};
use super::nee::Nee;
use super::{CameraRay, Ctx, Integrator, Setup};
use crate::sampler::SampleStream;
use glam::DVec3;

/// Direct lighting with light sampling and (lux sampling) MIS against BSDF sampling.
#[derive(Clone, Copy)]
pub struct DirectIntegrator<'a> {
    nee: Nee<'a>,
}

impl<'a> DirectIntegrator<'a> {
    /// Direct lighting over `setup`'s scene with its sampling mode and light samples.
    pub fn new(setup: &Setup<'a>) -> DirectIntegrator<'a> {
        DirectIntegrator {
            nee: Nee::new(setup),
        }
    }
}

impl Integrator for DirectIntegrator<'_> {
    /// Radiance and alpha along a camera ray: what it meets first (`camera_vertex.rs`), and at
    /// a surface its glow plus its direct illumination.
    #[inline]
    fn li(&self, ray: &CameraRay, st: &SampleStream, ctx: &mut Ctx) -> (DVec3, f64) {
        let w = &self.nee.world;
        match camera_vertex(w, self.nee.vis, ray, ctx) {
            CameraVertex::Done(rgb, alpha) => (rgb, alpha),
            CameraVertex::Surface(hit, glow) => {
                let sp = w.materials.at(w.scene, &hit, ray.d);
                (glow + self.nee.estimate(&sp, st, 0, ctx), 1.0)
            }
        }
    }
}
