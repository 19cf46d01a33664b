//! DiskLight (UsdLux `DiskLight`): a disk of `inputs:radius` in local XY, centred, emitting
//! from its −Z side.

use super::{LiSample, LightBase, LightHit, Seen, box_corners, box_of, planar_emission_half_angle};
use glam::DVec3;
use lux_sample::{LightBounds, Reference, Strategy};

/// A disk light: its radius and sampler.
#[derive(Clone, Debug)]
pub struct DiskLight {
    /// What every light carries.
    pub base: LightBase,
    radius: f64,
    /// lux-sample's sampler of the shape ([`super::Light::seen_from`] reads it).
    pub(super) sampler: lux_sample::DiskLight,
    /// [`DiskLight::world_disk`].
    world: Option<(DVec3, DVec3, f64)>,
    /// For a disk of uniform radiance (identity shaping): its world normal on the local +Z
    /// side, `L⁻ᵀ ẑ`, so that a light sample's radiance is the light's own wherever
    /// `emit · n < 0` (the −Z side [`DiskLight::le`] tests as `(L⁻¹ emit).z < 0`).
    uniform_side: Option<DVec3>,
}

impl DiskLight {
    /// A disk of `radius` (> 0) sampled by its elliptic cone of directions (lux) or by area
    /// (hdEmbree); `Err` names what lux-sample refused.
    pub(super) fn new(base: LightBase, radius: f64) -> Result<DiskLight, String> {
        let sampler =
            lux_sample::DiskLight::new(radius, base.xf, lux_sample::DiskTechnique::EllipticCone)
                .map_err(|e| e.to_string())?;
        let world = sampler.world_disk();
        let uniform_side = base.shaping.is_identity().then(|| base.xf.normal(DVec3::Z));
        Ok(DiskLight {
            uniform_side,
            base,
            radius,
            sampler,
            world,
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
    pub fn sample_li_from(&self, from: &lux_sample::DiskFrom, u: [f64; 2]) -> Option<LiSample> {
        let s = from.sample(u)?;
        let outward = self.uniform_side.map(|n| s.wi.dot(n) > 0.0);
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

    /// Radiance along the world direction `emit`: zero unless it leaves the −Z side.
    #[inline]
    pub fn le(&self, _local: DVec3, emit: DVec3, _seen: Seen) -> DVec3 {
        let Some(wl) = self.base.local_direction(emit) else {
            return DVec3::ZERO;
        };
        if wl.z >= 0.0 {
            return DVec3::ZERO;
        }
        self.base.shaped(wl)
    }

    /// A finite light: nothing arrives from infinity.
    #[inline]
    pub fn le_escape(&self, _wi: DVec3) -> DVec3 {
        DVec3::ZERO
    }

    /// The world disk — centre, unit normal, radius `s · inputs:radius` — under a similarity
    /// transform of scale s ([`lux_sample::DiskLight::world_disk`], kept per light).
    #[inline]
    pub fn world_disk(&self) -> Option<(DVec3, DVec3, f64)> {
        self.world
    }

    /// See [`super::Light::uniform_area`].
    #[inline]
    pub fn uniform_area(&self) -> bool {
        self.base.shaping.is_identity()
    }

    /// See [`super::Light::intersect`]: the plane z = 0 within the radius.
    #[inline]
    pub fn intersect(&self, o: DVec3, d: DVec3, tmin: f64, tmax: f64) -> Option<LightHit> {
        let ol = self.base.xf.inv_point(o);
        let dl = self.base.xf.inv_vector(d);
        let t = -ol.z / dl.z;
        if !(t > tmin && t < tmax) {
            return None;
        }
        let q = ol + t * dl;
        let r = self.radius;
        (q.x * q.x + q.y * q.y <= r * r).then_some(LightHit {
            t,
            local: DVec3::new(q.x, q.y, 0.0),
            front: dl.z > 0.0,
        })
    }

    /// World box of the disk's local bounding square.
    pub fn surface_box(&self) -> Option<(DVec3, DVec3)> {
        Some(self.world_box())
    }

    fn world_box(&self) -> (DVec3, DVec3) {
        let r = self.radius;
        box_of(&self.base.xf, box_corners(DVec3::new(r, r, 0.0)))
    }

    /// See [`super::Light::bounds`]: one-sided, normal −Z, emission narrowed by the shaping.
    pub fn bounds(&self) -> Option<LightBounds> {
        let theta_e = planar_emission_half_angle(&self.base);
        self.base.bounds(self.world_box(), 0.0, theta_e, false)
    }

    /// Power estimate: `Y(base) · area · G` (G = ∫ shaping · cos over the hemisphere).
    pub(super) fn power(&self, area: f64) -> f64 {
        let g = lux_math::luminance(self.base.shaping.integral_cos_hemisphere()).max(0.0);
        lux_math::luminance(self.base.radiance).max(0.0) * area * g
    }
}
