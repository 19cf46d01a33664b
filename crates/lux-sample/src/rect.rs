//! RectLight (UsdLux `RectLight`: `inputs:width` along local X, `inputs:height` along local Y,
//! centred, emitting from its local −Z side only).

use crate::error::{SampleError, positive};
use crate::spherical::SphericalRectangle;
use crate::transform::{LightTransform, finish_sample_with_normal, local_direction};
use crate::warp::{bilinear_pdf, sample_bilinear};
use crate::{AreaSample, LightSample, MIN_SOLID_ANGLE, Reference, Strategy};
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

/// UsdLux `RectLight` prepared for sampling (spec §2): the `inputs:width × inputs:height`
/// rectangle centred in local XY, emitting from its −Z side only, placed by its
/// [`LightTransform`] (any affine map: a non-uniformly scaled or sheared rect is a
/// parallelogram, sampled with exact densities). `sample`/`pdf` give directions and densities
/// per unit solid angle; [`projected_solid_angle`](Self::projected_solid_angle) the one-sided
/// `Π = ∫ max(0, n·ω) dω` (`E = L·Π` for a uniform radiance L). Build it from the schema's
/// description with [`crate::Light::from_shape`].
#[derive(Clone, Copy, Debug)]
pub struct RectLight {
    width: f64,
    height: f64,
    xf: LightTransform,
    technique: RectTechnique,
    /// The world normal, `xf.normal(−Z)` (fixed for a planar light).
    normal: DVec3,
    /// tan θe of the emission cone ([`Self::with_emission_cone`]); ∞ without one.
    tan_cut: f64,
}

/// A [`RectLight`] seen from one receiver ([`RectLight::seen_from`]): the part of sampling
/// that depends on the receiver alone, done once for the light samples of a shading point.
#[derive(Clone, Copy, Debug)]
pub struct RectFrom<'a> {
    light: &'a RectLight,
    /// The receiver (world).
    p: DVec3,
    /// The receiver in light space.
    pl: DVec3,
    plan: RectPlan<'a>,
}

/// How a [`RectFrom`] draws its points.
#[derive(Clone, Copy, Debug)]
enum RectPlan<'a> {
    /// No point: the receiver is behind the light, or the emission cone misses the rect.
    Nothing,
    /// Uniform over the rect's area.
    Area,
    /// Uniform over the area of the window `[x0, y0, x1, y1]` (its solid angle is too small).
    WindowArea([f64; 4]),
    /// The spherical rectangle `sr` of solid angle `s`, warped by the cosine weights `cw`.
    Spherical {
        sr: &'a SphericalRectangle,
        s: f64,
        cw: Option<[f64; 4]>,
    },
}

impl RectFrom<'_> {
    /// Samples a point with `u ∈ [0,1)²`: [`RectLight::sample_with`] from this receiver.
    #[inline(always)]
    pub fn sample(&self, u: [f64; 2]) -> Option<LightSample> {
        let light = self.light;
        let pl = self.pl;
        let (q, pdf) = match &self.plan {
            RectPlan::Nothing => return None,
            RectPlan::Area => {
                let area = light.width * light.height;
                let q = DVec3::new((u[0] - 0.5) * light.width, (u[1] - 0.5) * light.height, 0.0);
                let d2 = (q - pl).length_squared();
                // d²/(A·cos θ) with cos θ = −p.z/d: one division, not two
                (q, d2 * d2.sqrt() / (-pl.z * area))
            }
            RectPlan::WindowArea(w) => {
                let q = DVec3::new(
                    w[0] + u[0] * (w[2] - w[0]),
                    w[1] + u[1] * (w[3] - w[1]),
                    0.0,
                );
                let d2 = (q - pl).length_squared();
                (q, d2 * d2.sqrt() / (-pl.z * (w[2] - w[0]) * (w[3] - w[1])))
            }
            RectPlan::Spherical {
                sr,
                s,
                cw: Some(cw),
            } => {
                let uv = sample_bilinear(u, *cw);
                (sr.sample(uv), bilinear_pdf(uv, *cw) / s)
            }
            RectPlan::Spherical { sr, s, cw: None } => (sr.sample(u), 1.0 / s),
        };
        finish_sample_with_normal(&light.xf, self.p, pl, q, light.normal, pdf)
    }
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
            tan_cut: f64::INFINITY,
        })
    }

    /// The light emits nothing along local directions more than `half_angle` off its −Z axis
    /// (ShapingAPI `inputs:shaping:cone:angle`, or the reach of `inputs:shaping:ies:file` after
    /// `ies:angleScale`: `lux_shaping::Shaping::emission_half_angle`).
    /// The solid-angle techniques then sample only the part of the rect that can reach the
    /// receiver: the points seen from a receiver at height h below the light's plane within
    /// θe of the axis form a disk of radius h·tan θe around its foot, whose bounding square
    /// clipped to the rect is sampled instead of the rect (what Blender Cycles does for an area
    /// light's spread). Half-angles of π/2 or more (or NaN) change nothing; the area technique
    /// (hdEmbree's) is not clipped.
    pub fn with_emission_cone(mut self, half_angle: f64) -> Self {
        self.tan_cut = if (0.0..core::f64::consts::FRAC_PI_2).contains(&half_angle) {
            half_angle.tan()
        } else {
            f64::INFINITY
        };
        self
    }

    /// The sampled window `[x0, y0, x1, y1]` of the rect seen from the local point `pl`
    /// (`pl.z < 0`): the whole rect without an emission cone; `None` when the cone's disk
    /// misses the rect.
    #[inline]
    fn window(&self, pl: DVec3) -> Option<[f64; 4]> {
        let (a, b) = (0.5 * self.width, 0.5 * self.height);
        if self.tan_cut == f64::INFINITY {
            return Some([-a, -b, a, b]);
        }
        let r = -pl.z * self.tan_cut;
        let w = [
            (pl.x - r).max(-a),
            (pl.y - r).max(-b),
            (pl.x + r).min(a),
            (pl.y + r).min(b),
        ];
        (w[0] < w[2] && w[1] < w[3]).then_some(w)
    }

    /// The sampling technique chosen at construction (see [`Strategy`] for the one rule).
    pub fn technique(&self) -> RectTechnique {
        self.technique
    }

    /// The one-sided **projected solid angle** `Π = ∫ max(0, n·ω) dω` of the rect seen from the
    /// receiver `r` (its `(p, n)`), clipped to the receiver's horizon: the unshadowed irradiance
    /// of the light is `E = L·Π` for a uniform radiance `L` (lux-irradiance's
    /// `projected::polygon` over [`corners`](Self::corners), Lambert's formula). The rect emits
    /// from its −Z side only (spec §2), so a receiver on or behind its plane's other side gets 0.
    /// `None` for a reference without a normal (`n = 0`).
    pub fn projected_solid_angle(&self, r: &Reference) -> Option<f64> {
        if r.n == DVec3::ZERO {
            return None;
        }
        if crate::not_positive(self.normal.dot(r.p - self.xf.translation())) {
            return Some(0.0);
        }
        Some(lux_irradiance::projected::polygon(
            r.p,
            r.n,
            &self.corners(),
        ))
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

    /// Calls `f` with the light seen from the receiver `r` with the techniques of `strategy`:
    /// what every sample drawn from there shares (the receiver in light space, the spherical
    /// rectangle and its cosine weights), computed once, so that `k` samples from one receiver
    /// cost one setup. [`RectFrom::sample`] equals [`Self::sample_with`]`(r, u, strategy)` for
    /// every `u`, bit for bit.
    #[inline(always)]
    pub fn seen_from<R>(
        &self,
        r: &Reference,
        strategy: Strategy,
        f: impl FnOnce(&RectFrom<'_>) -> R,
    ) -> R {
        self.seen_by(r, self.technique_of(strategy), f)
    }

    #[inline(always)]
    fn seen_by<R>(
        &self,
        r: &Reference,
        technique: RectTechnique,
        f: impl FnOnce(&RectFrom<'_>) -> R,
    ) -> R {
        let pl = self.xf.inv_point(r.p);
        // (the spherical rectangle stays where it is built: `RectFrom` borrows it)
        let sr;
        let plan = if pl.z.is_nan() || pl.z >= 0.0 {
            RectPlan::Nothing
        } else {
            match technique {
                RectTechnique::Area => RectPlan::Area,
                _ if self.tan_cut < f64::INFINITY => match self.window(pl) {
                    None => RectPlan::Nothing,
                    Some(w) => {
                        sr = SphericalRectangle::window(pl, w);
                        let s = sr.solid_angle();
                        if s.is_nan() || s < MIN_SOLID_ANGLE {
                            RectPlan::WindowArea(w)
                        } else {
                            let cw = self.cosine_weights(&sr, self.xf.inv_normal(r.n), technique);
                            RectPlan::Spherical { sr: &sr, s, cw }
                        }
                    }
                },
                _ => {
                    sr = self.spherical(pl);
                    let s = sr.solid_angle();
                    if s.is_nan() || s < MIN_SOLID_ANGLE {
                        RectPlan::Area
                    } else {
                        let cw = self.cosine_weights(&sr, self.xf.inv_normal(r.n), technique);
                        RectPlan::Spherical { sr: &sr, s, cw }
                    }
                }
            }
        };
        f(&RectFrom {
            light: self,
            p: r.p,
            pl,
            plan,
        })
    }

    #[inline]
    fn sample_by(
        &self,
        r: &Reference,
        u: [f64; 2],
        technique: RectTechnique,
    ) -> Option<LightSample> {
        self.seen_by(r, technique, |from| from.sample(u))
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
            _ if self.tan_cut < f64::INFINITY => {
                let Some(w) = self.window(pl) else {
                    return 0.0;
                };
                if q.x < w[0] || q.x > w[2] || q.y < w[1] || q.y > w[3] {
                    return 0.0;
                }
                let sr = SphericalRectangle::window(pl, w);
                let s = sr.solid_angle();
                if s.is_nan() || s < MIN_SOLID_ANGLE {
                    t * t / (wl.z * (w[2] - w[0]) * (w[3] - w[1]))
                } else if let Some(cw) =
                    self.cosine_weights(&sr, self.xf.inv_normal(r.n), technique)
                {
                    bilinear_pdf(sr.invert(q), cw) / s
                } else {
                    1.0 / s
                }
            }
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

impl RectLight {
    /// A point uniform by area on the rect (local `(±w/2, ±h/2, 0)` placed by the transform),
    /// emitting towards `xf.normal(−Z)`: emission sampling ([`AreaSample`]).
    #[inline]
    pub fn sample_area(&self, u: [f64; 2]) -> Option<AreaSample> {
        let local = DVec3::new((u[0] - 0.5) * self.width, (u[1] - 0.5) * self.height, 0.0);
        let area = self.width * self.height * self.xf.area_scale(DVec3::X, DVec3::Y);
        (area > 0.0).then(|| AreaSample {
            point: self.xf.point(local),
            normal: self.normal,
            pdf: 1.0 / area,
        })
    }
}
