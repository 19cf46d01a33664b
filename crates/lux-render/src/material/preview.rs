//! TEMPORARY STUB (replaced by the bsdf branch): Lambertian behind the PreviewBsdf API.
use super::BsdfSample;
use glam::DVec3;
use lux_math::Frame;
use lux_sample::warp::sample_cosine_hemisphere;
use std::f64::consts::FRAC_1_PI;

/// Stub.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PreviewParams {
    /// Stub.
    pub diffuse_color: DVec3,
    /// Stub.
    pub use_specular_workflow: bool,
    /// Stub.
    pub specular_color: DVec3,
    /// Stub.
    pub metallic: f64,
    /// Stub.
    pub roughness: f64,
    /// Stub.
    pub clearcoat: f64,
    /// Stub.
    pub clearcoat_roughness: f64,
    /// Stub.
    pub ior: f64,
}
impl Default for PreviewParams {
    fn default() -> Self {
        PreviewParams {
            diffuse_color: DVec3::splat(0.18),
            use_specular_workflow: false,
            specular_color: DVec3::ZERO,
            metallic: 0.0,
            roughness: 0.5,
            clearcoat: 0.0,
            clearcoat_roughness: 0.01,
            ior: 1.5,
        }
    }
}
/// Stub.
#[derive(Clone, Copy, Debug)]
pub struct PreviewBsdf {
    albedo: DVec3,
    ns: DVec3,
}
impl PreviewBsdf {
    /// Stub.
    pub fn new(p: &PreviewParams, ns: DVec3, _wo: DVec3) -> PreviewBsdf {
        PreviewBsdf {
            albedo: p.diffuse_color,
            ns,
        }
    }
    /// Stub.
    pub fn f(&self, wi: DVec3) -> DVec3 {
        if self.ns.dot(wi) > 0.0 {
            self.albedo * FRAC_1_PI
        } else {
            DVec3::ZERO
        }
    }
    /// Stub.
    pub fn pdf(&self, wi: DVec3) -> f64 {
        self.ns.dot(wi).max(0.0) * FRAC_1_PI
    }
    /// Stub.
    pub fn sample(&self, u: [f64; 2]) -> Option<BsdfSample> {
        let wi = Frame::from_normal(self.ns).to_world(sample_cosine_hemisphere(u));
        let cos = self.ns.dot(wi);
        (cos > 0.0).then_some(BsdfSample {
            wi,
            pdf: cos * FRAC_1_PI,
            weight: self.albedo,
        })
    }
    /// Stub.
    pub fn is_black(&self) -> bool {
        self.albedo == DVec3::ZERO
    }
    /// Stub.
    pub fn is_delta(&self) -> bool {
        false
    }
}
