//! CylinderLight (UsdLux `CylinderLight`: axis along local X, `inputs:length` along X,
//! `inputs:radius`; lateral surface only, no end caps, emitting outward).

use crate::error::{SampleError, positive};
use crate::not_positive;
use crate::transform::{LightTransform, finish_sample, local_direction};
use crate::{LightSample, Reference, Strategy};
use core::f64::consts::TAU;
use glam::{DVec2, DVec3};

/// How a [`CylinderLight`] chooses its points.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum CylinderTechnique {
    /// Uniform by area over the whole lateral surface (hdEmbree); back-facing points → `None`.
    Area,
    /// Uniform by area over the visible strip only: the azimuths ψ whose outward normal faces
    /// the reference point, |ψ − ψ₀| < acos(r/ρ), ρ the reference point's distance to the axis.
    VisibleArea,
    /// Solid-angle technique: in the cross-section the 2D angle β subtended by the circle is
    /// uniform in \[−asin(r/ρ), asin(r/ρ)\]; along the axis the elevation θ is uniform between
    /// the elevations of the two ends of the chosen line. Density 1/(2β_max·Θ·cos θ).
    #[default]
    SolidAngle,
}

/// A cylinder light prepared for sampling (geometry in `f64`).
#[derive(Clone, Copy, Debug)]
pub struct CylinderLight {
    radius: f64,
    length: f64,
    xf: LightTransform,
    technique: CylinderTechnique,
}

impl CylinderLight {
    /// A cylinder of `radius` and `length` (both > 0) placed by `xf`.
    pub fn new(
        radius: f64,
        length: f64,
        xf: LightTransform,
        technique: CylinderTechnique,
    ) -> Result<Self, SampleError> {
        Ok(Self {
            radius: positive("radius", radius)?,
            length: positive("length", length)?,
            xf,
            technique,
        })
    }

    /// The sampling technique.
    pub fn technique(&self) -> CylinderTechnique {
        self.technique
    }

    /// Distance from the reference point (local) to the first hit of the lateral surface along
    /// the unit direction w, if that hit is on the outside of the finite tube.
    #[inline]
    fn front_hit(&self, pl: DVec3, w: DVec3) -> Option<f64> {
        let p2 = DVec2::new(pl.y, pl.z);
        let w2 = DVec2::new(w.y, w.z);
        let a = w2.length_squared();
        if a == 0.0 {
            return None;
        }
        let b = p2.dot(w2);
        let c = p2.length_squared() - self.radius * self.radius;
        if c <= 0.0 {
            return None;
        }
        let disc = b * b - a * c;
        if disc < 0.0 || b >= 0.0 {
            return None;
        }
        let t = c / (-b + disc.sqrt());
        let x = pl.x + t * w.x;
        (x.abs() <= 0.5 * self.length).then_some(t)
    }

    /// Samples a point seen from `r`; `None` when `r` is inside the tube's radius (it then sees
    /// only the non-emitting inside) or the sample is back-facing (area technique).
    #[inline]
    pub fn sample(&self, r: &Reference, u: [f64; 2]) -> Option<LightSample> {
        self.sample_by(r, u, self.technique)
    }

    /// [`Self::sample`] with the techniques of `strategy` (`HdEmbree`: [`CylinderTechnique::Area`]).
    #[inline]
    pub fn sample_with(
        &self,
        r: &Reference,
        u: [f64; 2],
        strategy: Strategy,
    ) -> Option<LightSample> {
        self.sample_by(r, u, self.technique_of(strategy))
    }

    /// [`Self::pdf`] of the techniques of `strategy`.
    #[inline]
    pub fn pdf_with(&self, r: &Reference, wi: DVec3, strategy: Strategy) -> f64 {
        self.pdf_by(r, wi, self.technique_of(strategy))
    }

    /// The technique `strategy` stands for.
    #[inline]
    fn technique_of(&self, strategy: Strategy) -> CylinderTechnique {
        match strategy {
            Strategy::Lux => self.technique,
            Strategy::HdEmbree => CylinderTechnique::Area,
        }
    }

    #[inline]
    fn sample_by(
        &self,
        r: &Reference,
        u: [f64; 2],
        technique: CylinderTechnique,
    ) -> Option<LightSample> {
        let pl = self.xf.inv_point(r.p);
        let p2 = DVec2::new(pl.y, pl.z);
        let rho = p2.length();
        let rad = self.radius;
        if rho.is_nan() || rho <= rad {
            return None;
        }
        let half = 0.5 * self.length;
        let psi0 = p2.y.atan2(p2.x);
        let area_point = |psi: f64, x: f64| {
            let (s, c) = psi.sin_cos();
            let n = DVec3::new(0.0, c, s);
            (DVec3::new(x, rad * c, rad * s), n)
        };
        let (q, n, pdf) = match technique {
            CylinderTechnique::Area | CylinderTechnique::VisibleArea => {
                let (psi, width) = if technique == CylinderTechnique::Area {
                    (TAU * u[1], TAU)
                } else {
                    let g = (rad / rho).acos();
                    (psi0 + (2.0 * u[1] - 1.0) * g, 2.0 * g)
                };
                let (q, n) = area_point(psi, (u[0] - 0.5) * self.length);
                let v = pl - q;
                let d2 = v.length_squared();
                let cos = n.dot(v) / d2.sqrt();
                if not_positive(cos) {
                    return None;
                }
                (q, n, d2 / (cos * width * rad * self.length))
            }
            CylinderTechnique::SolidAngle => {
                let beta_max = (rad / rho).min(1.0).asin();
                let (sb, cb) = ((2.0 * u[1] - 1.0) * beta_max).sin_cos();
                let toward = -p2 / rho;
                let e = DVec2::new(toward.x * cb - toward.y * sb, toward.x * sb + toward.y * cb);
                // Near intersection of the 2D ray with the circle: s = ρ cos β − √(r² − ρ² sin² β).
                let s = (rho * cb - (rad * rad - rho * rho * sb * sb).max(0.0).sqrt()).max(0.0);
                let ta = ((-half - pl.x) / s).atan();
                let tb = ((half - pl.x) / s).atan();
                let theta = ta + u[0] * (tb - ta);
                let (st, ct) = theta.sin_cos();
                let x = (pl.x + s * st / ct).clamp(-half, half);
                let q2 = p2 + s * e;
                let q = DVec3::new(x, q2.x, q2.y);
                let n = DVec3::new(0.0, q2.x, q2.y) / rad;
                (q, n, 1.0 / (2.0 * beta_max * (tb - ta) * ct))
            }
        };
        finish_sample(&self.xf, r.p, pl, q, n, pdf)
    }

    /// Solid-angle density of [`Self::sample`] producing `wi` from `r`.
    #[inline]
    pub fn pdf(&self, r: &Reference, wi: DVec3) -> f64 {
        self.pdf_by(r, wi, self.technique)
    }

    #[inline]
    fn pdf_by(&self, r: &Reference, wi: DVec3, technique: CylinderTechnique) -> f64 {
        let pl = self.xf.inv_point(r.p);
        let Some((wl, jac)) = local_direction(&self.xf, wi) else {
            return 0.0;
        };
        if !pl.is_finite() {
            return 0.0;
        }
        let Some(t) = self.front_hit(pl, wl) else {
            return 0.0;
        };
        let rad = self.radius;
        let p2 = DVec2::new(pl.y, pl.z);
        let rho = p2.length();
        let q = pl + t * wl;
        let n = DVec3::new(0.0, q.y, q.z) / rad;
        let cos = -n.dot(wl);
        let pdf = match technique {
            CylinderTechnique::Area => t * t / (cos * TAU * rad * self.length),
            CylinderTechnique::VisibleArea => {
                let g = (rad / rho).acos();
                t * t / (cos * 2.0 * g * rad * self.length)
            }
            CylinderTechnique::SolidAngle => {
                let half = 0.5 * self.length;
                let beta_max = (rad / rho).min(1.0).asin();
                let ct = DVec2::new(wl.y, wl.z).length();
                let s = t * ct;
                let ta = ((-half - pl.x) / s).atan();
                let tb = ((half - pl.x) / s).atan();
                1.0 / (2.0 * beta_max * (tb - ta) * ct)
            }
        };
        if pdf.is_finite() { pdf * jac } else { 0.0 }
    }
}
