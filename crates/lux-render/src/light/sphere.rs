//! SphereLight (UsdLux `SphereLight`): a sphere of `inputs:radius` (an ellipsoid under a
//! non-uniform scale), every point emitting over its outward hemisphere.

use super::{LiSample, LightBase, LightHit, Seen, box_corners, box_of, quadratic};
use glam::DVec3;
use lux_sample::{LightBounds, Reference, Strategy};

/// A sphere light: its radius and sampler.
#[derive(Clone, Debug)]
pub struct SphereLight {
    /// What every light carries.
    pub base: LightBase,
    radius: f64,
    /// lux-sample's sampler of the shape ([`super::Light::seen_from`] reads it).
    pub(super) sampler: lux_sample::SphereLight,
    /// For a sphere of uniform radiance (identity shaping) under a similarity transform: its
    /// world centre, so that a light sample's radiance is the light's own wherever
    /// `(q − centre) · emit > 0` at its point `q` (the outward side [`SphereLight::le`] tests
    /// in light space, whose dot products a similarity keeps the signs of).
    uniform_centre: Option<DVec3>,
}

impl SphereLight {
    /// A sphere of `radius` sampled by its cosine-weighted projected cap (lux; its cone of
    /// directions where the horizon cuts it) or by area (hdEmbree);
    /// `Err` names what lux-sample refused (a radius of 0 included).
    pub(super) fn new(base: LightBase, radius: f64) -> Result<SphereLight, String> {
        let sampler = lux_sample::SphereLight::new(
            radius,
            base.xf,
            lux_sample::SphereTechnique::ProjectedCap,
        )
        .map_err(|e| e.to_string())?;
        let uniform_centre = (base.shaping.is_identity() && base.xf.is_similarity())
            .then(|| base.xf.point(DVec3::ZERO));
        Ok(SphereLight {
            uniform_centre,
            base,
            radius,
            sampler,
        })
    }

    /// See [`super::Light::sample_li`].
    #[inline]
    pub fn sample_li(&self, r: &Reference, u: [f64; 2], strategy: Strategy) -> Option<LiSample> {
        self.sampler
            .seen_from(r, strategy, |from| self.sample_li_from(from, u))
    }

    /// [`Self::sample_li`] from the receiver `from` was made for.
    #[inline(always)]
    pub fn sample_li_from(&self, from: &lux_sample::SphereFrom, u: [f64; 2]) -> Option<LiSample> {
        let s = from.sample(u)?;
        let outward = self.uniform_centre.map(|c| (s.point - c).dot(s.wi) < 0.0);
        let l = self.base.sample_radiance(outward, || {
            self.le(self.base.to_local(s.point), -s.wi, Seen::Lit)
        });
        Some(LiSample::new(s, l))
    }

    /// See [`super::Light::pdf_li`].
    #[inline]
    pub fn pdf_li(&self, r: &Reference, wi: DVec3) -> f64 {
        self.sampler.pdf(r, wi)
    }

    /// Radiance from the local surface point `local` along the world direction `emit`: zero
    /// unless `emit` leaves the outward side (`local · ω_light > 0`).
    #[inline]
    pub fn le(&self, local: DVec3, emit: DVec3, _seen: Seen) -> DVec3 {
        let Some(wl) = self.base.local_direction(emit) else {
            return DVec3::ZERO;
        };
        if local.dot(wl) <= 0.0 {
            return DVec3::ZERO;
        }
        self.base.shaped(wl)
    }

    /// A finite light: nothing arrives from infinity.
    #[inline]
    pub fn le_escape(&self, _wi: DVec3) -> DVec3 {
        DVec3::ZERO
    }

    /// See [`super::Light::uniform_area`].
    #[inline]
    pub fn uniform_area(&self) -> bool {
        self.base.shaping.is_identity()
    }

    /// See [`super::Light::intersect`]: the nearer root of `|o + t·d|² = r²` in range.
    #[inline]
    pub fn intersect(&self, o: DVec3, d: DVec3, tmin: f64, tmax: f64) -> Option<LightHit> {
        let ol = self.base.xf.inv_point(o);
        let dl = self.base.xf.inv_vector(d);
        let r = self.radius;
        let (t0, t1) = quadratic(dl.length_squared(), ol.dot(dl), ol.length_squared() - r * r)?;
        let in_range = |t: f64| t > tmin && t < tmax;
        let t = if in_range(t0) {
            t0
        } else if in_range(t1) {
            t1
        } else {
            return None;
        };
        let q = ol + t * dl;
        Some(LightHit {
            t,
            local: q,
            front: q.dot(dl) < 0.0,
        })
    }

    /// World box of the sphere's local bounding cube.
    pub fn surface_box(&self) -> Option<(DVec3, DVec3)> {
        Some(self.world_box())
    }

    fn world_box(&self) -> (DVec3, DVec3) {
        box_of(&self.base.xf, box_corners(DVec3::splat(self.radius)))
    }

    /// See [`super::Light::bounds`]: normals in every direction.
    pub fn bounds(&self) -> Option<LightBounds> {
        let half_pi = std::f64::consts::FRAC_PI_2;
        self.base
            .bounds(self.world_box(), std::f64::consts::PI, half_pi, false)
    }

    /// Power estimate: `Y(base) · area · π · max shaping factor`.
    pub(super) fn power(&self, area: f64) -> f64 {
        lux_math::luminance(self.base.radiance).max(0.0)
            * area
            * std::f64::consts::PI
            * self.base.shaping.max_factor()
    }
}
