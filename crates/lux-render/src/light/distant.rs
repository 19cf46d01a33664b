//! DistantLight (UsdLux `DistantLight`): light from infinitely far away along local −Z, over a
//! cone of angular diameter `inputs:angle` (a delta direction at 0°).

use super::{LiSample, LightBase, LightHit, Seen};
use glam::DVec3;
use lux_sample::{LightBounds, Reference, Strategy};

/// A distant light: its cone sampler.
#[derive(Clone, Debug)]
pub struct DistantLight {
    /// What every light carries.
    pub base: LightBase,
    sampler: lux_sample::DistantLight,
}

impl DistantLight {
    /// From `inputs:angle` in degrees; `Err` names what lux-sample refused.
    pub(super) fn new(base: LightBase, angle_deg: f64) -> Result<DistantLight, String> {
        let sampler =
            lux_sample::DistantLight::new(angle_deg, &base.xf).map_err(|e| e.to_string())?;
        Ok(DistantLight { base, sampler })
    }

    /// `inputs:angle` = 0: a single direction, reached by light sampling only.
    #[inline]
    pub fn is_delta(&self) -> bool {
        self.sampler.is_delta()
    }

    /// See [`super::Light::sample_li`] (both strategies sample the cone uniformly).
    #[inline]
    pub fn sample_li(&self, r: &Reference, u: [f64; 2], strategy: Strategy) -> Option<LiSample> {
        let s = self.sampler.sample_with(r, u, strategy)?;
        Some(LiSample::new(s, self.emitted(-s.wi)))
    }

    /// See [`super::Light::pdf_li`]: uniform inside the cone, 0 for a delta light.
    #[inline]
    pub fn pdf_li(&self, r: &Reference, wi: DVec3) -> f64 {
        self.sampler.pdf(r, wi)
    }

    /// `base · shapingFactor` along the world emission direction `emit`.
    #[inline]
    fn emitted(&self, emit: DVec3) -> DVec3 {
        self.base.emitted(emit)
    }

    /// Radiance arriving along `wi` (receiver → light): inside the cone, the emission along
    /// `−wi`; zero outside it and for a delta light (no direction reaches it by chance).
    #[inline]
    pub fn le_escape(&self, wi: DVec3) -> DVec3 {
        if self.is_delta() || self.sampler.pdf(&Reference::point(DVec3::ZERO), wi) <= 0.0 {
            return DVec3::ZERO;
        }
        self.emitted(-wi)
    }

    /// See [`super::Light::uniform_area`]: not one of its kinds.
    #[inline]
    pub fn uniform_area(&self) -> bool {
        false
    }

    /// At infinity: no surface point emits.
    #[inline]
    pub fn le(&self, _local: DVec3, _emit: DVec3, _seen: Seen) -> DVec3 {
        DVec3::ZERO
    }

    /// No analytic surface: found by rays only through `le_escape` when they escape.
    #[inline]
    pub fn intersect(&self, _o: DVec3, _d: DVec3, _tmin: f64, _tmax: f64) -> Option<LightHit> {
        None
    }

    /// No analytic surface.
    pub fn surface_box(&self) -> Option<(DVec3, DVec3)> {
        None
    }

    /// At infinity: no bounds.
    pub fn bounds(&self) -> Option<LightBounds> {
        None
    }

    /// Power estimate for selection: `Y(base) · π`.
    pub(super) fn power(&self, _area: f64) -> f64 {
        lux_math::luminance(self.base.radiance).max(0.0) * std::f64::consts::PI
    }
}
