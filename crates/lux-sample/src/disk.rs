//! DiskLight (UsdLux `DiskLight`: `inputs:radius`, centred in the local XY plane, emitting from
//! its local −Z side only).

use crate::error::{SampleError, positive};
use crate::not_positive;
use crate::transform::{LightTransform, finish_sample, local_direction};
use crate::warp::sample_concentric_disk;
use crate::{AreaSample, LightSample, Reference, Strategy};
use core::f64::consts::{PI, TAU};
use glam::{DVec2, DVec3};

/// How a [`DiskLight`] chooses its points.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum DiskTechnique {
    /// Uniform by area (concentric map); density (πr²)⁻¹·d²/cos θₗ in solid angle.
    Area,
    /// Azimuth–cosine ("polar chord") sampling, a solid-angle technique replacing spherical
    /// ellipse sampling. Around the axis through the reference point perpendicular to the disk,
    /// the azimuth φ is uniform over the disk's angular extent Φ (2π if the foot point is inside
    /// the disk, 2·asin(r/D) otherwise), and along the chord cut by that azimuth cos α is
    /// uniform between its values at the chord ends, α being the angle from the disk normal.
    /// Density: 1/(Φ·(cos α₁ − cos α₂)). Exactly uniform in solid angle on the axis, but off
    /// the axis the azimuthal marginal ignores how much solid angle each azimuth holds: with the
    /// foot point 0.3 off-centre under a 0.5-radius disk at height 0.5 its irradiance variance is
    /// 14× that of uniform solid-angle sampling (tests/variance.rs). Kept for comparison; use
    /// [`Self::EllipticCone`].
    PolarChord,
    /// Solid-angle sampling in the frame of the elliptic cone of directions that the disk
    /// subtends (the spherical ellipse of Guillén et al. 2017, sampled through its gnomonic
    /// projection with closed forms instead of their elliptic-integral inversion).
    ///
    /// With the apex at the reference point, the directions d reaching the disk satisfy the
    /// quadric dᵀMd ≤ 0; in the frame (x′ towards the disk centre's horizontal offset D, y′
    /// lateral, z the disk normal) M = \[\[h², 0, −hD\], \[0, h², 0\], \[−hD, 0, D² − r²\]\].
    /// Its eigenvalues are h² (lateral), λ_b = (tr + √((h² − D² + r²)² + 4h²D²))/2 > 0 and
    /// λ_a = −h²r²/λ_b < 0, whose eigenvector (hD, 0, h² − λ_a) is the cone axis. On the plane
    /// one unit along that axis the cone is the ellipse X²/A² + Y²/B² ≤ 1, A = hr/λ_b,
    /// B = r/√λ_b, and dω = ρ dρ dψ/(1 + ρ²)^{3/2}. Uniform solid angle would need the azimuth
    /// ψ with density ∝ g(R(ψ)) = 1 − 1/√(1 + R²), whose CDF is an incomplete elliptic
    /// integral. This sampler draws ψ ∝ R²/(1 + R²) instead — exactly the squared radius of the
    /// ellipse with semi-axes A/√(1 + A²), B/√(1 + B²), so ψ is the polar angle of that
    /// ellipse's point at parametric angle 2πu₀ — and then ρ ∈ \[0, R(ψ)\] exactly
    /// proportional to solid angle: 1/√(1 + ρ²) = 1 − u₁·g(R). Because
    /// g(R) = R²/(1 + R²) · s/(1 + s), s = √(1 + R²), the density in solid angle is
    /// (1 + 1/s)/(2π·A′·B′): exactly uniform on the axis (A = B), and never more than a factor
    /// 2 from uniform anywhere (tests/variance.rs measures the variance against exact
    /// solid-angle sampling at six placements).
    #[default]
    EllipticCone,
}

/// The elliptic cone of directions from an apex below the disk plane to the disk (see
/// [`DiskTechnique::EllipticCone`]): its axis, the two gnomonic axes and the semi-axes A, B.
#[derive(Clone, Copy, Debug)]
struct EllipticCone {
    axis: DVec3,
    b: DVec3,
    ey: DVec3,
    a_semi: f64,
    b_semi: f64,
    /// The primed semi-axes A′, B′ (see [`EllipticCone::primed`]).
    primed: (f64, f64),
}

impl EllipticCone {
    /// `c` = disk centre minus apex, in the disk's local frame (c.z = h > 0).
    #[inline]
    fn new(c: DVec3, r: f64) -> Option<Self> {
        let h = c.z;
        let d = (c.x * c.x + c.y * c.y).sqrt();
        let ex = if d > 0.0 {
            DVec3::new(c.x / d, c.y / d, 0.0)
        } else {
            DVec3::X
        };
        let ey = DVec3::new(-ex.y, ex.x, 0.0);
        let (h2, r2, d2) = (h * h, r * r, d * d);
        let tr = h2 + d2 - r2;
        let t = h2 - d2 + r2;
        let disc = (t * t + 4.0 * h2 * d2).sqrt();
        let lb = 0.5 * (tr + disc);
        if not_positive(lb) || not_positive(h) {
            return None;
        }
        let la = -h2 * r2 / lb;
        let axis = (h * d * ex + (h2 - la) * DVec3::Z).normalize();
        let b = ((h2 - la) * ex - h * d * DVec3::Z).normalize();
        let a_semi = h * r / lb;
        let b_semi = r / lb.sqrt();
        if !(axis.is_finite() && b.is_finite() && a_semi > 0.0 && b_semi > 0.0) {
            return None;
        }
        Some(Self {
            axis,
            b,
            ey,
            a_semi,
            b_semi,
            primed: Self::primed(a_semi, b_semi),
        })
    }

    /// Semi-axes A′ = A/√(1 + A²), B′ = B/√(1 + B²) of the ellipse whose radius is
    /// R′² = R²/(1 + R²) (the azimuth proposal).
    #[inline]
    fn primed(a: f64, b: f64) -> (f64, f64) {
        (a / (1.0 + a * a).sqrt(), b / (1.0 + b * b).sqrt())
    }

    /// Solid-angle density for a direction whose gnomonic radius direction has R² = `r2`:
    /// (1 + 1/√(1 + R²)) / (2π·A′·B′).
    #[inline]
    fn density(&self, r2: f64) -> f64 {
        let (ap, bp) = self.primed;
        (1.0 + 1.0 / (1.0 + r2).sqrt()) / (TAU * ap * bp)
    }

    /// A unit local direction inside the cone, and its density.
    #[inline]
    fn sample(&self, u: [f64; 2]) -> (DVec3, f64) {
        let (ap, bp) = self.primed;
        let (s, c) = (TAU * u[0]).sin_cos();
        // Direction ψ of the gnomonic ray: parametric angle of the primed ellipse.
        let (px, py) = (ap * c, bp * s);
        let len = (px * px + py * py).sqrt();
        let (cp, sp) = (px / len, py / len);
        // Radius of the true ellipse along ψ.
        let r2 =
            1.0 / (cp * cp / (self.a_semi * self.a_semi) + sp * sp / (self.b_semi * self.b_semi));
        // ρ ∈ [0, R] proportional to solid angle: 1/√(1 + ρ²) = 1 − u₁·g(R),
        // g(R) = 1 − 1/√(1 + R²) = R²/(√(1 + R²)(1 + √(1 + R²))).
        let sr = (1.0 + r2).sqrt();
        let g = r2 / (sr * (1.0 + sr));
        let ug = u[1] * g;
        let q = 1.0 - ug;
        let rho = (ug * (2.0 - ug)).max(0.0).sqrt() / q;
        let d = self.axis + rho * (cp * self.b + sp * self.ey);
        (d.normalize(), self.density(r2))
    }

    /// Density of the unit local direction `w` (assumed inside the cone).
    #[inline]
    fn pdf(&self, w: DVec3) -> f64 {
        let alpha = w.dot(self.axis);
        if not_positive(alpha) {
            return 0.0;
        }
        let x = w.dot(self.b) / alpha;
        let y = w.dot(self.ey) / alpha;
        let rho2 = x * x + y * y;
        let den = x * x / (self.a_semi * self.a_semi) + y * y / (self.b_semi * self.b_semi);
        let r2 = if den > 0.0 {
            rho2 / den
        } else {
            self.a_semi * self.a_semi
        };
        self.density(r2)
    }
}

/// UsdLux `DiskLight` prepared for sampling (spec §2): the disk of `inputs:radius` in local XY,
/// emitting from its −Z side only, placed by its [`LightTransform`] (an ellipse under a
/// non-uniform scale or shear, sampled with exact densities). `sample`/`pdf` give directions
/// and densities per unit solid angle; [`projected_solid_angle`](Self::projected_solid_angle)
/// the one-sided `Π` of a round disk. Build it from the schema's description with
/// [`crate::Light::from_shape`].
#[derive(Clone, Copy, Debug)]
pub struct DiskLight {
    radius: f64,
    xf: LightTransform,
    technique: DiskTechnique,
}

/// A [`DiskLight`] seen from one receiver ([`DiskLight::seen_from`]): the part of sampling
/// that depends on the receiver alone, done once for the light samples of a shading point.
#[derive(Clone, Copy, Debug)]
pub struct DiskFrom<'a> {
    light: &'a DiskLight,
    /// The receiver (world).
    p: DVec3,
    /// The receiver in light space.
    pl: DVec3,
    plan: DiskPlan<'a>,
}

/// How a [`DiskFrom`] draws its points.
#[derive(Clone, Copy, Debug)]
enum DiskPlan<'a> {
    /// No point: the receiver is behind the disk (or its cone is degenerate).
    Nothing,
    /// Uniform over the disk's area.
    Area,
    /// [`DiskTechnique::EllipticCone`] in this cone.
    Cone(&'a EllipticCone),
    /// [`DiskTechnique::PolarChord`] from the foot point `f` over the azimuths
    /// `[phi0, phi0 + width]`.
    Chord { f: DVec2, phi0: f64, width: f64 },
}

impl DiskFrom<'_> {
    /// Samples a point with `u ∈ [0,1)²`: [`DiskLight::sample_with`] from this receiver.
    #[inline(always)]
    pub fn sample(&self, u: [f64; 2]) -> Option<LightSample> {
        let light = self.light;
        let pl = self.pl;
        let h = -pl.z;
        let (q, pdf) = match &self.plan {
            DiskPlan::Nothing => return None,
            DiskPlan::Area => {
                let d = sample_concentric_disk(u) * light.radius;
                let q = DVec3::new(d.x, d.y, 0.0);
                let d2 = (q - pl).length_squared();
                (q, d2 * d2.sqrt() / (h * PI * light.radius * light.radius))
            }
            DiskPlan::Cone(cone) => {
                let (w, pdf) = cone.sample(u);
                if not_positive(w.z) {
                    return None;
                }
                let t = h / w.z;
                let p2 = DVec2::new(pl.x + t * w.x, pl.y + t * w.y);
                // Round-off can put a silhouette sample a hair outside the rim.
                let len = p2.length();
                let p2 = if len > light.radius {
                    p2 * (light.radius / len)
                } else {
                    p2
                };
                (DVec3::new(p2.x, p2.y, 0.0), pdf)
            }
            &DiskPlan::Chord { f, phi0, width } => {
                let (s, c) = (phi0 + u[0] * width).sin_cos();
                let dir = DVec2::new(c, s);
                let (t1, t2) = chord(f, dir, light.radius).unwrap_or((0.0, 0.0));
                let gap = cos_gap(t1, t2, h);
                if not_positive(gap) {
                    return None;
                }
                let cos1 = h / (t1 * t1 + h * h).sqrt();
                let cos_a = (cos1 - u[1] * gap).max(1e-300);
                let rho = (h * (1.0 - cos_a * cos_a).max(0.0).sqrt() / cos_a).clamp(t1, t2);
                let p2 = f + rho * dir;
                (DVec3::new(p2.x, p2.y, 0.0), 1.0 / (width * gap))
            }
        };
        finish_sample(&light.xf, self.p, pl, q, DVec3::NEG_Z, pdf)
    }
}

/// The chord of the disk along azimuth `dir` from foot point `f`: in-plane distances (t1, t2).
#[inline]
fn chord(f: DVec2, dir: DVec2, r: f64) -> Option<(f64, f64)> {
    let b = f.dot(dir);
    let c = f.length_squared() - r * r;
    let disc = b * b - c;
    if disc < 0.0 {
        return None;
    }
    let s = disc.sqrt();
    if c <= 0.0 {
        Some((0.0, -b + s))
    } else {
        // Outside: both roots share a sign; stable form t1 = c/(−b + s).
        let t2 = -b + s;
        if t2 <= 0.0 {
            return None;
        }
        Some((c / t2, t2))
    }
}

/// cos α₁ − cos α₂ for chord distances t1 < t2 at height h, without cancellation:
/// h(b − a)/(ab) with a = √(t1²+h²), b = √(t2²+h²), b − a = (t2−t1)(t2+t1)/(a+b).
#[inline]
fn cos_gap(t1: f64, t2: f64, h: f64) -> f64 {
    let a = (t1 * t1 + h * h).sqrt();
    let b = (t2 * t2 + h * h).sqrt();
    h * (t2 - t1) * (t2 + t1) / (a * b * (a + b))
}

impl DiskLight {
    /// A disk of `radius` (> 0, UsdLux `inputs:radius`) placed by `xf`; `technique` is the one
    /// `sample`/`pdf` use ([`Strategy::Lux`]).
    pub fn new(
        radius: f64,
        xf: LightTransform,
        technique: DiskTechnique,
    ) -> Result<Self, SampleError> {
        Ok(Self {
            radius: positive("radius", radius)?,
            xf,
            technique,
        })
    }

    /// The sampling technique.
    pub fn technique(&self) -> DiskTechnique {
        self.technique
    }

    /// The world disk — centre, unit normal (the local ±Z axis), radius `s · inputs:radius` —
    /// when the transform is a similarity of scale s (rotation, uniform scale, translation);
    /// `None` under a non-uniform scale or shear, where it is an ellipse. What
    /// `lux_irradiance::projected::disk` takes.
    pub fn world_disk(&self) -> Option<(DVec3, DVec3, f64)> {
        if !self.xf.is_similarity() {
            return None;
        }
        let r = self.radius * self.xf.vector(DVec3::X).length();
        self.xf
            .normal(DVec3::Z)
            .try_normalize()
            .filter(|_| r > 0.0 && r.is_finite())
            .map(|axis| (self.xf.point(DVec3::ZERO), axis, r))
    }

    /// The one-sided **projected solid angle** `Π = ∫ max(0, n·ω) dω` of the disk seen from the
    /// receiver `r` (its `(p, n)`), clipped to the receiver's horizon (lux-irradiance's
    /// `projected::disk`, in closed form): the unshadowed irradiance is `E = L·Π` for a uniform
    /// radiance `L`. The disk emits from its −Z side only (spec §2): a receiver on or behind the
    /// other side gets 0. `None` for a reference without a normal (`n = 0`) and for a disk
    /// under a non-uniform scale or shear (an ellipse: [`world_disk`](Self::world_disk) is
    /// `None`).
    pub fn projected_solid_angle(&self, r: &Reference) -> Option<f64> {
        if r.n == DVec3::ZERO {
            return None;
        }
        let (centre, axis, radius) = self.world_disk()?;
        // world_disk's axis is +Z's image; the disk emits towards −Z's
        if crate::not_positive(-axis.dot(r.p - centre)) {
            return Some(0.0);
        }
        lux_irradiance::projected::disk(r.p, r.n, centre, axis, radius)
    }

    /// Angular extent of the disk around the foot point: (start azimuth, width Φ).
    #[inline]
    fn extent(&self, f: DVec2) -> (f64, f64) {
        let d = f.length();
        if d <= self.radius {
            (0.0, TAU)
        } else {
            let beta = (self.radius / d).min(1.0).asin();
            let centre = (-f.y).atan2(-f.x);
            (centre - beta, 2.0 * beta)
        }
    }

    /// Samples a point seen from `r`; `None` behind the disk (local z ≥ 0).
    #[inline]
    pub fn sample(&self, r: &Reference, u: [f64; 2]) -> Option<LightSample> {
        self.sample_by(r, u, self.technique)
    }

    /// [`Self::sample`] with the techniques of `strategy` (`HdEmbree`: [`DiskTechnique::Area`]).
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
    fn technique_of(&self, strategy: Strategy) -> DiskTechnique {
        match strategy {
            Strategy::Lux => self.technique,
            Strategy::HdEmbree => DiskTechnique::Area,
        }
    }

    /// Calls `f` with the light seen from the receiver `r` with the techniques of `strategy`:
    /// what every sample drawn from there shares (the receiver in light space, the elliptic
    /// cone or the angular extent), computed once, so that `k` samples from one receiver cost
    /// one setup. [`DiskFrom::sample`] equals [`Self::sample_with`]`(r, u, strategy)` for every
    /// `u`, bit for bit.
    #[inline(always)]
    pub fn seen_from<R>(
        &self,
        r: &Reference,
        strategy: Strategy,
        f: impl FnOnce(&DiskFrom<'_>) -> R,
    ) -> R {
        self.seen_by(r, self.technique_of(strategy), f)
    }

    #[inline(always)]
    fn seen_by<R>(
        &self,
        r: &Reference,
        technique: DiskTechnique,
        f: impl FnOnce(&DiskFrom<'_>) -> R,
    ) -> R {
        let pl = self.xf.inv_point(r.p);
        // (the cone stays where it is built: `DiskFrom` borrows it)
        let cone;
        let plan = if pl.z.is_nan() || pl.z >= 0.0 {
            DiskPlan::Nothing
        } else {
            match technique {
                DiskTechnique::Area => DiskPlan::Area,
                DiskTechnique::EllipticCone => match EllipticCone::new(-pl, self.radius) {
                    Some(c) => {
                        cone = c;
                        DiskPlan::Cone(&cone)
                    }
                    None => DiskPlan::Nothing,
                },
                DiskTechnique::PolarChord => {
                    let f = DVec2::new(pl.x, pl.y);
                    let (phi0, width) = self.extent(f);
                    DiskPlan::Chord { f, phi0, width }
                }
            }
        };
        f(&DiskFrom {
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
        technique: DiskTechnique,
    ) -> Option<LightSample> {
        self.seen_by(r, technique, |from| from.sample(u))
    }

    /// Solid-angle density of [`Self::sample`] producing `wi` from `r`.
    #[inline]
    pub fn pdf(&self, r: &Reference, wi: DVec3) -> f64 {
        self.pdf_by(r, wi, self.technique)
    }

    #[inline]
    fn pdf_by(&self, r: &Reference, wi: DVec3, technique: DiskTechnique) -> f64 {
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
        let h = -pl.z;
        let t = h / wl.z;
        let q = pl + t * wl;
        if q.x * q.x + q.y * q.y > self.radius * self.radius {
            return 0.0;
        }
        let pdf = match technique {
            DiskTechnique::Area => t * t / (wl.z * PI * self.radius * self.radius),
            DiskTechnique::EllipticCone => match EllipticCone::new(-pl, self.radius) {
                Some(cone) => cone.pdf(wl),
                None => return 0.0,
            },
            DiskTechnique::PolarChord => {
                let f = DVec2::new(pl.x, pl.y);
                let (_, width) = self.extent(f);
                let v = DVec2::new(wl.x, wl.y);
                let dir = if v.length_squared() > 0.0 {
                    v.normalize()
                } else {
                    DVec2::X
                };
                let Some((t1, t2)) = chord(f, dir, self.radius) else {
                    return 0.0;
                };
                let gap = cos_gap(t1, t2, h);
                if not_positive(gap) {
                    return 0.0;
                }
                1.0 / (width * gap)
            }
        };
        pdf * jac
    }
}

impl DiskLight {
    /// A point uniform by area on the disk (concentric mapping of `u`, local `z = 0`),
    /// emitting towards `xf.normal(−Z)`: emission sampling ([`AreaSample`]).
    #[inline]
    pub fn sample_area(&self, u: [f64; 2]) -> Option<AreaSample> {
        let d = sample_concentric_disk(u) * self.radius;
        let area = PI * self.radius * self.radius * self.xf.area_scale(DVec3::X, DVec3::Y);
        (area > 0.0).then(|| AreaSample {
            point: self.xf.point(DVec3::new(d.x, d.y, 0.0)),
            normal: self.xf.normal(DVec3::NEG_Z),
            pdf: 1.0 / area,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DMat4;

    #[test]
    fn world_disk_under_a_similarity_and_none_under_a_stretch() {
        // Scale 2, a quarter turn about +X (local +Z → world −Y), moved to (1, 2, 3).
        let m = DMat4::from_translation(DVec3::new(1.0, 2.0, 3.0))
            * DMat4::from_rotation_x(std::f64::consts::FRAC_PI_2)
            * DMat4::from_scale(DVec3::splat(2.0));
        let xf = LightTransform::new(m).unwrap();
        let disk = DiskLight::new(0.25, xf, DiskTechnique::EllipticCone).unwrap();
        let (c, axis, r) = disk.world_disk().unwrap();
        assert!(c.distance(DVec3::new(1.0, 2.0, 3.0)) < 1e-12);
        assert!(axis.distance(DVec3::new(0.0, -1.0, 0.0)) < 1e-12, "{axis}");
        assert!((r - 0.5).abs() < 1e-12);
        let stretched = LightTransform::new(DMat4::from_scale(DVec3::new(1.0, 3.0, 1.0))).unwrap();
        let ellipse = DiskLight::new(0.25, stretched, DiskTechnique::EllipticCone).unwrap();
        assert_eq!(ellipse.world_disk(), None);
    }
}
