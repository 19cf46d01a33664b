//! CylinderLight (UsdLux `CylinderLight`): the lateral surface of a cylinder along local X
//! (`inputs:length`, `inputs:radius`), no caps, emitting outward.

use super::{LiSample, LightBase, LightHit, Seen, box_corners, box_of, quadratic};
use glam::DVec3;
use lux_sample::{LightBounds, Reference, Strategy};

/// A cylinder light: its radius, half length and sampler.
#[derive(Clone, Debug)]
pub struct CylinderLight {
    /// What every light carries.
    pub base: LightBase,
    radius: f64,
    half_length: f64,
    /// lux-sample's sampler of the shape ([`super::Light::seen_from`] reads it).
    pub(super) sampler: lux_sample::CylinderLight,
    /// For a cylinder of uniform radiance (identity shaping) under a similarity transform:
    /// its world centre and unit axis, so that a light sample's radiance is the light's own
    /// wherever the radial part of `q − centre` at its point `q` points along `emit` (the
    /// outward side [`CylinderLight::le`] tests in light space, whose dot products a
    /// similarity keeps the signs of).
    uniform_axis: Option<(DVec3, DVec3)>,
}

impl CylinderLight {
    /// A cylinder of `radius` and `length` sampled by solid angle (lux) or by area (hdEmbree);
    /// `Err` names what lux-sample refused.
    pub(super) fn new(
        base: LightBase,
        radius: f64,
        length: f64,
        cone_clipping: bool,
    ) -> Result<CylinderLight, String> {
        let cut = if cone_clipping {
            base.shaping.emission_half_angle()
        } else {
            std::f64::consts::PI
        };
        let sampler = lux_sample::CylinderLight::new(
            radius,
            length,
            base.xf,
            lux_sample::CylinderTechnique::SolidAngle,
        )
        .map_err(|e| e.to_string())?
        // only the stretch of each line inside the shaping's emission cone
        .with_emission_cone(cut);
        let uniform_axis = (base.shaping.is_identity() && base.xf.is_similarity()).then(|| {
            (
                base.xf.point(DVec3::ZERO),
                base.xf.vector(DVec3::X).normalize(),
            )
        });
        Ok(CylinderLight {
            uniform_axis,
            base,
            radius,
            half_length: 0.5 * length,
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
    pub fn sample_li_from(&self, from: &lux_sample::CylinderFrom, u: [f64; 2]) -> Option<LiSample> {
        let s = from.sample(u)?;
        // (the radial part of q − centre against the direction to the receiver)
        let outward = self.uniform_axis.map(|(c, a)| {
            let q = s.point - c;
            q.dot(s.wi) - q.dot(a) * a.dot(s.wi) < 0.0
        });
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
    /// unless `emit` leaves the outward side (`(0, y, z) · ω_light > 0`).
    #[inline]
    pub fn le(&self, local: DVec3, emit: DVec3, _seen: Seen) -> DVec3 {
        let Some(wl) = self.base.local_direction(emit) else {
            return DVec3::ZERO;
        };
        if local.y * wl.y + local.z * wl.z <= 0.0 {
            return DVec3::ZERO;
        }
        self.base.shaped(wl)
    }

    /// A finite light: nothing arrives from infinity.
    #[inline]
    pub fn le_escape(&self, _wi: DVec3) -> DVec3 {
        DVec3::ZERO
    }

    /// See [`super::Light::uniform_area`]: not one of its kinds.
    #[inline]
    pub fn uniform_area(&self) -> bool {
        false
    }

    /// See [`super::Light::intersect`]: the first root of `y² + z² = r²` within the length.
    #[inline]
    pub fn intersect(&self, o: DVec3, d: DVec3, tmin: f64, tmax: f64) -> Option<LightHit> {
        let ol = self.base.xf.inv_point(o);
        let dl = self.base.xf.inv_vector(d);
        let r = self.radius;
        let a = dl.y * dl.y + dl.z * dl.z;
        let b = ol.y * dl.y + ol.z * dl.z;
        let c = ol.y * ol.y + ol.z * ol.z - r * r;
        let (t0, t1) = quadratic(a, b, c)?;
        for t in [t0, t1] {
            if t > tmin && t < tmax {
                let q = ol + t * dl;
                if q.x.abs() <= self.half_length {
                    return Some(LightHit {
                        t,
                        local: q,
                        front: q.y * dl.y + q.z * dl.z < 0.0,
                    });
                }
            }
        }
        None
    }

    /// World box of the cylinder's local bounding box.
    pub fn surface_box(&self) -> Option<(DVec3, DVec3)> {
        Some(self.world_box())
    }

    fn world_box(&self) -> (DVec3, DVec3) {
        let (r, hl) = (self.radius, self.half_length);
        box_of(&self.base.xf, box_corners(DVec3::new(hl, r, r)))
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
