//! RectLight (UsdLux `RectLight`: `inputs:width` along local X, `inputs:height` along local Y,
//! centred, emitting from its local −Z side only).

use crate::error::{SampleError, positive};
use crate::spherical::SphericalRectangle;
use crate::transform::{LightTransform, finish_sample_with_normal, local_direction};
use crate::warp::{bilinear_pdf, sample_bilinear};
use crate::{LightSample, MIN_SOLID_ANGLE, Reference, Strategy};
use glam::DVec3;

/// How a [`RectLight`] chooses its points.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum RectTechnique {
    /// Uniform by area (what hdEmbree does); density A⁻¹·d²/cos θₗ in solid angle.
    Area,
    /// Uniform in solid angle over the spherical rectangle (Ureña et al. 2013); falls back to
    /// area sampling when the solid angle is below [`MIN_SOLID_ANGLE`].
    #[default]
    SphericalRectangle,
    /// Spherical rectangle warped by the bilinear fit of the receiver cosine at the four corner
    /// directions (Hart et al. 2020, §4.2); needs the receiver normal, otherwise equals
    /// `SphericalRectangle`.
    SphericalRectangleCosine,
}

/// A rectangle light prepared for sampling. Geometry in `f64`, local space per spec §2.
#[derive(Clone, Copy, Debug)]
pub struct RectLight {
    width: f64,
    height: f64,
    xf: LightTransform,
    technique: RectTechnique,
    /// The world normal, `xf.normal(−Z)` (fixed for a planar light).
    normal: DVec3,
}

impl RectLight {
    /// A `width × height` rectangle (UsdLux `inputs:width`, `inputs:height`, both > 0) placed
    /// by `xf`.
    pub fn new(
        width: f64,
        height: f64,
        xf: LightTransform,
        technique: RectTechnique,
    ) -> Result<Self, SampleError> {
        Ok(Self {
            width: positive("width", width)?,
            height: positive("height", height)?,
            xf,
            technique,
            normal: xf.normal(DVec3::NEG_Z),
        })
    }

    /// The sampling technique.
    pub fn technique(&self) -> RectTechnique {
        self.technique
    }

    /// The world-space corners, in local order (−w/2, −h/2), (+, −), (+, +), (−, +).
    pub fn corners(&self) -> [DVec3; 4] {
        let (a, b) = (0.5 * self.width, 0.5 * self.height);
        [
            self.xf.point(DVec3::new(-a, -b, 0.0)),
            self.xf.point(DVec3::new(a, -b, 0.0)),
            self.xf.point(DVec3::new(a, b, 0.0)),
            self.xf.point(DVec3::new(-a, b, 0.0)),
        ]
    }

    #[inline]
    fn spherical(&self, pl: DVec3) -> SphericalRectangle {
        SphericalRectangle::centred(pl, 0.5 * self.width, 0.5 * self.height)
    }

    /// Corner weights of the cosine warp, or `None` if the warp does not apply.
    #[inline]
    fn cosine_weights(
        &self,
        sr: &SphericalRectangle,
        nl: DVec3,
        technique: RectTechnique,
    ) -> Option<[f64; 4]> {
        if technique != RectTechnique::SphericalRectangleCosine || nl == DVec3::ZERO {
            return None;
        }
        let d = sr.corner_directions();
        let w = [
            d[0].dot(nl).max(0.0),
            d[1].dot(nl).max(0.0),
            d[2].dot(nl).max(0.0),
            d[3].dot(nl).max(0.0),
        ];
        if w[0] + w[1] + w[2] + w[3] > 0.0 {
            Some(w)
        } else {
            None
        }
    }

    /// Samples a point seen from `r` with `u ∈ [0,1)²`. `None` when `r` is not on the emitting
    /// side (local z ≥ 0) or the sample is degenerate.
    #[inline]
    pub fn sample(&self, r: &Reference, u: [f64; 2]) -> Option<LightSample> {
        self.sample_by(r, u, self.technique)
    }

    /// [`Self::sample`] with the techniques of `strategy` (`HdEmbree`: [`RectTechnique::Area`]).
    #[inline]
    pub fn sample_with(
        &self,
        r: &Reference,
        u: [f64; 2],
        strategy: Strategy,
    ) -> Option<LightSample> {
        self.sample_by(r, u, self.technique_of(strategy))
    }

    /// The technique `strategy` stands for.
    #[inline]
    fn technique_of(&self, strategy: Strategy) -> RectTechnique {
        match strategy {
            Strategy::Lux => self.technique,
            Strategy::HdEmbree => RectTechnique::Area,
        }
    }

    #[inline]
    fn sample_by(
        &self,
        r: &Reference,
        u: [f64; 2],
        technique: RectTechnique,
    ) -> Option<LightSample> {
        let pl = self.xf.inv_point(r.p);
        if pl.z.is_nan() || pl.z >= 0.0 {
            return None;
        }
        let area = self.width * self.height;
        let area_sample = |u: [f64; 2]| {
            let q = DVec3::new((u[0] - 0.5) * self.width, (u[1] - 0.5) * self.height, 0.0);
            let d2 = (q - pl).length_squared();
            let cos = -pl.z / d2.sqrt();
            (q, d2 / (cos * area))
        };
        let (q, pdf) = match technique {
            RectTechnique::Area => area_sample(u),
            _ => {
                let sr = self.spherical(pl);
                let s = sr.solid_angle();
                if s.is_nan() || s < MIN_SOLID_ANGLE {
                    area_sample(u)
                } else if let Some(w) = self.cosine_weights(&sr, self.xf.inv_normal(r.n), technique)
                {
                    let uv = sample_bilinear(u, w);
                    (sr.sample(uv), bilinear_pdf(uv, w) / s)
                } else {
                    (sr.sample(u), 1.0 / s)
                }
            }
        };
        finish_sample_with_normal(&self.xf, r.p, pl, q, self.normal, pdf)
    }

    /// Solid-angle density with which [`Self::sample`] produces direction `wi` (unit, world)
    /// from `r`; 0 if the ray misses the light or `r` is behind it.
    #[inline]
    pub fn pdf(&self, r: &Reference, wi: DVec3) -> f64 {
        self.pdf_by(r, wi, self.technique)
    }

    /// [`Self::pdf`] of the techniques of `strategy`.
    #[inline]
    pub fn pdf_with(&self, r: &Reference, wi: DVec3, strategy: Strategy) -> f64 {
        self.pdf_by(r, wi, self.technique_of(strategy))
    }

    #[inline]
    fn pdf_by(&self, r: &Reference, wi: DVec3, technique: RectTechnique) -> f64 {
        let pl = self.xf.inv_point(r.p);
        let Some((wl, jac)) = local_direction(&self.xf, wi) else {
            return 0.0;
        };
        if !pl.is_finite() {
            return 0.0;
        }
        if !(pl.z < 0.0 && wl.z > 0.0) {
            return 0.0;
        }
        let t = -pl.z / wl.z;
        let q = pl + t * wl;
        if q.x.abs() > 0.5 * self.width || q.y.abs() > 0.5 * self.height {
            return 0.0;
        }
        let area_pdf = t * t / (wl.z * self.width * self.height);
        let pdf = match technique {
            RectTechnique::Area => area_pdf,
            _ => {
                let sr = self.spherical(pl);
                let s = sr.solid_angle();
                if s.is_nan() || s < MIN_SOLID_ANGLE {
                    area_pdf
                } else if let Some(w) = self.cosine_weights(&sr, self.xf.inv_normal(r.n), technique)
                {
                    bilinear_pdf(sr.invert(q), w) / s
                } else {
                    1.0 / s
                }
            }
        };
        pdf * jac
    }
}
