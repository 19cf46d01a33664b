//! CylinderLight (UsdLux `CylinderLight`: axis along local X, `inputs:length` along X,
//! `inputs:radius`; lateral surface only, no end caps, emitting outward).

use crate::error::{SampleError, positive};
use crate::not_positive;
use crate::transform::{LightTransform, finish_sample, local_direction};
use crate::{AreaSample, LightSample, Reference, Strategy};
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

/// UsdLux `CylinderLight` prepared for sampling (spec §2): the lateral surface of the cylinder
/// of `inputs:radius` and `inputs:length` along local X (no caps), emitting outwards, placed by
/// its [`LightTransform`] with exact densities under any affine map. `sample`/`pdf` give
/// directions and densities per unit solid angle. Build it from the schema's description with
/// [`crate::Light::from_shape`].
#[derive(Clone, Copy, Debug)]
pub struct CylinderLight {
    radius: f64,
    length: f64,
    xf: LightTransform,
    technique: CylinderTechnique,
    /// tan θe of the emission cone ([`Self::with_emission_cone`]); ∞ without one.
    tan_cut: f64,
    /// θe itself (π/2 without a cone).
    cut: f64,
}

/// A [`CylinderLight`] seen from one receiver ([`CylinderLight::seen_from`]): the part of
/// sampling that depends on the receiver alone, done once for the light samples of a shading
/// point.
#[derive(Clone, Copy, Debug)]
pub struct CylinderFrom<'a> {
    light: &'a CylinderLight,
    /// The receiver (world).
    p: DVec3,
    /// The receiver in light space.
    pl: DVec3,
    plan: CylinderPlan,
}

/// How a [`CylinderFrom`] draws its points.
#[derive(Clone, Copy, Debug)]
enum CylinderPlan {
    /// No point: the receiver is inside the tube's radius (or no angle reaches it).
    Nothing,
    /// [`CylinderTechnique::Area`].
    Area,
    /// [`CylinderTechnique::VisibleArea`]: the azimuths `psi0 ± g`.
    VisibleArea { psi0: f64, g: f64 },
    /// [`CylinderTechnique::SolidAngle`] from the cross-section point `p2` at distance `rho`
    /// from the axis, towards it along `toward`, over the angles `[b0, b1]` (`±beta_max`
    /// without an emission cone).
    SolidAngle {
        p2: DVec2,
        rho: f64,
        beta_max: f64,
        toward: DVec2,
        b0: f64,
        b1: f64,
    },
}

impl CylinderFrom<'_> {
    /// Samples a point with `u ∈ [0,1)²`: [`CylinderLight::sample_with`] from this receiver.
    #[inline(always)]
    pub fn sample(&self, u: [f64; 2]) -> Option<LightSample> {
        let light = self.light;
        let pl = self.pl;
        let rad = light.radius;
        let area_point = |psi: f64, x: f64| {
            let (s, c) = psi.sin_cos();
            let n = DVec3::new(0.0, c, s);
            (DVec3::new(x, rad * c, rad * s), n)
        };
        let (q, n, pdf) = match self.plan {
            CylinderPlan::Nothing => return None,
            CylinderPlan::Area | CylinderPlan::VisibleArea { .. } => {
                let (psi, width) = match self.plan {
                    CylinderPlan::VisibleArea { psi0, g } => {
                        (psi0 + (2.0 * u[1] - 1.0) * g, 2.0 * g)
                    }
                    _ => (TAU * u[1], TAU),
                };
                let (q, n) = area_point(psi, (u[0] - 0.5) * light.length);
                let v = pl - q;
                let d2 = v.length_squared();
                let cos = n.dot(v) / d2.sqrt();
                if not_positive(cos) {
                    return None;
                }
                (q, n, d2 / (cos * width * rad * light.length))
            }
            CylinderPlan::SolidAngle {
                p2,
                rho,
                beta_max,
                toward,
                b0,
                b1,
            } => {
                let (sb, cb) = if light.tan_cut == f64::INFINITY {
                    ((2.0 * u[1] - 1.0) * beta_max).sin_cos()
                } else {
                    (b0 + u[1] * (b1 - b0)).sin_cos()
                };
                let e = DVec2::new(toward.x * cb - toward.y * sb, toward.x * sb + toward.y * cb);
                // Near intersection of the 2D ray with the circle: s = ρ cos β − √(r² − ρ² sin² β).
                let s = (rho * cb - (rad * rad - rho * rho * sb * sb).max(0.0).sqrt()).max(0.0);
                let q2 = p2 + s * e;
                let (xa, xb) = light.stretch(pl, q2)?;
                let ta = ((xa - pl.x) / s).atan();
                let tb = ((xb - pl.x) / s).atan();
                let theta = ta + u[0] * (tb - ta);
                let (st, ct) = theta.sin_cos();
                let x = (pl.x + s * st / ct).clamp(xa, xb);
                let q = DVec3::new(x, q2.x, q2.y);
                let n = DVec3::new(0.0, q2.x, q2.y) / rad;
                let width = if light.tan_cut == f64::INFINITY {
                    2.0 * beta_max
                } else {
                    b1 - b0
                };
                (q, n, 1.0 / (width * (tb - ta) * ct))
            }
        };
        finish_sample(&light.xf, self.p, pl, q, n, pdf)
    }
}

impl CylinderLight {
    /// A cylinder of `radius` and `length` (both > 0; UsdLux `inputs:radius`, `inputs:length`,
    /// along local X) placed by `xf`; `technique` is the one `sample`/`pdf` use
    /// ([`Strategy::Lux`]).
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
            tan_cut: f64::INFINITY,
            cut: core::f64::consts::FRAC_PI_2,
        })
    }

    /// The sampling technique.
    pub fn technique(&self) -> CylinderTechnique {
        self.technique
    }

    /// The light emits nothing along local directions more than `half_angle` = θe off its −Z
    /// axis (`inputs:shaping:cone:angle` or the IES reach:
    /// `lux_shaping::Shaping::emission_half_angle`). The solid-angle technique then samples
    /// only the cross-section angles β whose 2D direction lies within θe of local +Z (a line
    /// reaches the receiver inside the cone only if |Δy| ≤ tan θe·Δz), and on the chosen line
    /// only the stretch that can reach the receiver p: a point q at height v = q.z − p.z and
    /// lateral offset δ = q.y − p.y reaches it when (q.x − p.x)² ≤ (v·tan θe)² − δ² (none when
    /// v ≤ 0). Half-angles of π/2 or more (or NaN) change nothing; the area techniques are not
    /// clipped.
    pub fn with_emission_cone(mut self, half_angle: f64) -> Self {
        if (0.0..core::f64::consts::FRAC_PI_2).contains(&half_angle) {
            self.tan_cut = half_angle.tan();
            self.cut = half_angle;
        } else {
            self.tan_cut = f64::INFINITY;
            self.cut = core::f64::consts::FRAC_PI_2;
        }
        self
    }

    /// The range `[β0, β1]` of cross-section angles sampled (β measured from `toward`, the unit
    /// 2D direction from the reference point to the axis): `[−β_max, β_max]`, narrowed with an
    /// emission cone to the 2D directions within θe of local +Z (a line reaches the receiver
    /// inside the cone only if its cross-section offset does: |Δy| ≤ tan θe·Δz).
    #[inline]
    fn beta_range(&self, toward: DVec2, beta_max: f64) -> Option<(f64, f64)> {
        if self.tan_cut == f64::INFINITY {
            return Some((-beta_max, beta_max));
        }
        let bz = toward.x.atan2(toward.y);
        let (b0, b1) = (
            (bz - self.cut).max(-beta_max),
            (bz + self.cut).min(beta_max),
        );
        (b0 < b1).then_some((b0, b1))
    }

    /// The axial extent `[xa, xb]` sampled on the line through the cross-section point
    /// `q2 = (y, z)` from the local point `pl`: the whole length without an emission cone;
    /// `None` when the line cannot reach `pl` inside it.
    #[inline]
    fn stretch(&self, pl: DVec3, q2: DVec2) -> Option<(f64, f64)> {
        let half = 0.5 * self.length;
        if self.tan_cut == f64::INFINITY {
            return Some((-half, half));
        }
        let v = q2.y - pl.z;
        if not_positive(v) {
            return None;
        }
        let (reach, off) = (v * self.tan_cut, q2.x - pl.y);
        let w2 = reach * reach - off * off;
        if not_positive(w2) {
            return None;
        }
        let w = w2.sqrt();
        let (xa, xb) = ((pl.x - w).max(-half), (pl.x + w).min(half));
        (xa < xb).then_some((xa, xb))
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

    /// Calls `f` with the light seen from the receiver `r` with the techniques of `strategy`:
    /// what every sample drawn from there shares (the receiver in light space, its distance to
    /// the axis and the range of angles sampled), computed once, so that `k` samples from one
    /// receiver cost one setup. [`CylinderFrom::sample`] equals
    /// [`Self::sample_with`]`(r, u, strategy)` for every `u`, bit for bit.
    #[inline(always)]
    pub fn seen_from<R>(
        &self,
        r: &Reference,
        strategy: Strategy,
        f: impl FnOnce(&CylinderFrom<'_>) -> R,
    ) -> R {
        self.seen_by(r, self.technique_of(strategy), f)
    }

    #[inline(always)]
    fn seen_by<R>(
        &self,
        r: &Reference,
        technique: CylinderTechnique,
        f: impl FnOnce(&CylinderFrom<'_>) -> R,
    ) -> R {
        let pl = self.xf.inv_point(r.p);
        let p2 = DVec2::new(pl.y, pl.z);
        let rho = p2.length();
        let rad = self.radius;
        let plan = if rho.is_nan() || rho <= rad {
            CylinderPlan::Nothing
        } else {
            match technique {
                CylinderTechnique::Area => CylinderPlan::Area,
                CylinderTechnique::VisibleArea => CylinderPlan::VisibleArea {
                    psi0: p2.y.atan2(p2.x),
                    g: (rad / rho).acos(),
                },
                CylinderTechnique::SolidAngle => {
                    let beta_max = (rad / rho).min(1.0).asin();
                    let toward = -p2 / rho;
                    match self.beta_range(toward, beta_max) {
                        Some((b0, b1)) => CylinderPlan::SolidAngle {
                            p2,
                            rho,
                            beta_max,
                            toward,
                            b0,
                            b1,
                        },
                        None => CylinderPlan::Nothing,
                    }
                }
            }
        };
        f(&CylinderFrom {
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
        technique: CylinderTechnique,
    ) -> Option<LightSample> {
        self.seen_by(r, technique, |from| from.sample(u))
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
                let beta_max = (rad / rho).min(1.0).asin();
                let ct = DVec2::new(wl.y, wl.z).length();
                let s = t * ct;
                let Some((xa, xb)) = self.stretch(pl, DVec2::new(q.y, q.z)) else {
                    return 0.0;
                };
                if q.x < xa || q.x > xb {
                    return 0.0;
                }
                let ta = ((xa - pl.x) / s).atan();
                let tb = ((xb - pl.x) / s).atan();
                let width = if self.tan_cut == f64::INFINITY {
                    2.0 * beta_max
                } else {
                    let toward = -p2 / rho;
                    let Some((b0, b1)) = self.beta_range(toward, beta_max) else {
                        return 0.0;
                    };
                    let e = DVec2::new(wl.y, wl.z) / ct;
                    let beta = (toward.x * e.y - toward.y * e.x).atan2(toward.dot(e));
                    if beta < b0 || beta > b1 {
                        return 0.0;
                    }
                    b1 - b0
                };
                1.0 / (width * (tb - ta) * ct)
            }
        };
        if pdf.is_finite() { pdf * jac } else { 0.0 }
    }
}

impl CylinderLight {
    /// A point uniform by local area on the cylinder's side (no caps; local axis X), emitting
    /// outward: emission sampling ([`AreaSample`]).
    #[inline]
    pub fn sample_area(&self, u: [f64; 2]) -> Option<AreaSample> {
        let (s, c) = (TAU * u[1]).sin_cos();
        let n = DVec3::new(0.0, c, s);
        let local = DVec3::new((u[0] - 0.5) * self.length, 0.0, 0.0) + n * self.radius;
        let side = TAU * self.radius * self.length;
        let area = side * self.xf.area_scale(DVec3::X, DVec3::new(0.0, -s, c));
        (area > 0.0).then(|| AreaSample {
            point: self.xf.point(local),
            normal: self.xf.normal(n),
            pdf: 1.0 / area,
        })
    }
}
