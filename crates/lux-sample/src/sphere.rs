//! SphereLight (UsdLux `SphereLight`: `inputs:radius`, emitting outward from its whole surface).
//! Under a non-uniform scale the light is an ellipsoid; it is sampled exactly through its local
//! sphere (see [`crate::transform`]).

use crate::error::{SampleError, positive};
use crate::transform::{LightTransform, finish_sample, finish_sample_dir, local_direction};
use crate::warp::{sample_concentric_disk, sample_uniform_sphere};
use crate::{AreaSample, LightSample, Reference, Strategy};
use core::f64::consts::{PI, TAU};
use glam::DVec3;
use lux_math::Frame;

/// How a [`SphereLight`] chooses its points from outside (inside, both use area sampling).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SphereTechnique {
    /// Uniform by area over the whole sphere; back-facing points return `None`.
    Area,
    /// Uniform in the cone of directions subtended by the sphere (pbrt-v4 §6.2.4): density
    /// 1/(2π(1 − cos α)), sin α = r/d, with 1 − cos α = sin²α/(1 + cos α) so that small,
    /// distant spheres keep full precision.
    #[default]
    Cone,
    /// Cosine-weighted over the cap (Peters & Dachsbacher 2019, "Sampling projected spherical
    /// caps in real time"): seen from a receiver with normal n, a cap wholly above its
    /// horizon projects orthographically onto the tangent plane as an ellipse — centre
    /// (cos α sin β, 0), semi-axes sin α cos β and sin α, β the angle between n and the
    /// cap's axis — of area π sin²α cos β, the projected solid angle. A point uniform in it,
    /// lifted to the hemisphere, has density cos θ/(π sin²α cos β): the cosine-weighted
    /// irradiance estimator of a uniform sphere is then exact where it is unoccluded. Caps
    /// cut by the horizon, receivers without a normal and non-uniformly scaled spheres use
    /// `Cone`.
    ProjectedCap,
}

/// UsdLux `SphereLight` prepared for sampling (spec §2): the sphere of `inputs:radius` about the
/// local origin, every point emitting over its outward hemisphere, placed by its
/// [`LightTransform`] (an ellipsoid under a non-uniform scale or shear, sampled with exact
/// densities). `sample`/`pdf` give directions and densities per unit solid angle (the cone
/// technique: `1/(2π(1 − cos α))`, `sin α = r/d`); [`projected_solid_angle`](Self::projected_solid_angle)
/// the `Π` of a round sphere (`π sin²α cos ω` above the horizon). Build it from the schema's
/// description with [`crate::Light::from_shape`].
#[derive(Clone, Copy, Debug)]
pub struct SphereLight {
    radius: f64,
    /// 1/radius and 1/(2π·radius²), so that sampling needs no divisions by them.
    inv_radius: f64,
    inv_tau_r2: f64,
    xf: LightTransform,
    technique: SphereTechnique,
    /// The world sphere when `xf` is a rotation and uniform scale s (to a few ulp) plus a
    /// translation c: the light is the sphere |x − c| = s·r, and the cone is sampled in world
    /// space without transforming the reference point or the sample.
    world: Option<WorldSphere>,
}

/// A sphere in world space (see [`SphereLight`]'s `world`).
#[derive(Clone, Copy, Debug)]
struct WorldSphere {
    centre: DVec3,
    radius: f64,
    inv_radius: f64,
    inv_tau_r2: f64,
}

/// A point of the cone sampled from a reference point, relative to the sphere's centre.
struct ConeSample {
    /// Point on the sphere minus its centre.
    q: DVec3,
    /// Unit direction from the reference point.
    w: DVec3,
    /// Distance along `w`.
    t: f64,
    /// Solid-angle density.
    pdf: f64,
}

/// Uniform sampling of the cone of directions towards the sphere |x| = `rad` from the point `p`
/// (relative to the centre, |p| > rad): pbrt-v4 §6.2.4 with the algebra below. `inv_tau_r2` is
/// 1/(2π·rad²).
#[inline(always)]
fn sample_cone(p: DVec3, d2: f64, rad: f64, inv_tau_r2: f64, u: [f64; 2]) -> ConeSample {
    Cone::new(p, d2, rad, inv_tau_r2).sample(u)
}

/// The cone of directions towards the sphere |x| = `rad` from a point outside it: what
/// [`sample_cone`] computes from the point alone.
#[derive(Clone, Copy, Debug)]
struct Cone {
    rad: f64,
    d: f64,
    dpe: f64,
    dde: f64,
    inv_dde: f64,
    pdf: f64,
    frame: Frame,
}

impl Cone {
    /// The cone from `p` (relative to the centre, |p|² = `d2` > rad²); `inv_tau_r2` is
    /// 1/(2π·rad²).
    #[inline(always)]
    fn new(p: DVec3, d2: f64, rad: f64, inv_tau_r2: f64) -> Cone {
        // With e = √(d² − r²) (so cos α = e/d): 1 − cos α = r²/(d·(d + e)), whose reciprocal
        // also gives the density 1/(2π(1 − cos α)) = d·(d + e)/(2π r²). Square root and
        // division share one unit on current CPUs and their latency dominates this sampler, so
        // every square root below is taken of an expression free of that division (see the
        // direction), and the division only scales the results.
        let d = d2.sqrt();
        let e = (d2 - rad * rad).max(0.0).sqrt();
        let dpe = d + e;
        let dde = d * dpe;
        let inv_dde = 1.0 / dde;
        let pdf = dde * inv_tau_r2;
        // The cone's frame around the unit axis n = v/d, v = −p, as `Frame::from_normal(n)`
        // (Duff et al. 2017) but from v and d: with σ = sign(v.z) and k = −1/(d·(σd + v.z)),
        // its a/d² is k and 1/d = −k·(σd + v.z). That division needs only d, so it runs beside
        // the one above instead of after it. (σd + v.z has no cancellation: both terms share a
        // sign.)
        let v = -p;
        let sgn = 1.0f64.copysign(v.z);
        let sdz = sgn * d + v.z;
        let k = -1.0 / (d * sdz);
        let n = v * (-k * sdz);
        let bxy = v.x * v.y * k;
        let frame = Frame {
            t: DVec3::new(1.0 + sgn * v.x * v.x * k, sgn * bxy, -sgn * n.x),
            b: DVec3::new(bxy, sgn + v.y * v.y * k, -n.y),
            n,
        };
        Cone {
            rad,
            d,
            dpe,
            dde,
            inv_dde,
            pdf,
            frame,
        }
    }

    /// The point and direction of `u ∈ [0,1)²`.
    #[inline(always)]
    fn sample(&self, u: [f64; 2]) -> ConeSample {
        let Cone {
            rad,
            d,
            dpe,
            dde,
            inv_dde,
            pdf,
            frame,
        } = *self;
        // The direction of `warp::sample_uniform_cone(u, 1 − cos α)`: cos θ = 1 − u₀·(1 − cos α)
        // = 1 − u₀r²/dde (dde = d(d + e)), and sin²θ = (1 − cos θ)(1 + cos θ)
        // = u₀r²·(2·dde − u₀r²)/dde², so sin θ = √(u₀r²·(2·dde − u₀r²))·(1/dde): the root needs
        // dde only (2·dde − u₀r² ≥ dde since dde > r²: no cancellation).
        let ur2 = u[0] * (rad * rad);
        let cos_t = 1.0 - ur2 * inv_dde;
        let sin_t = (ur2 * (2.0 * dde - ur2)).max(0.0).sqrt() * inv_dde;
        let sin2_t = sin_t * sin_t;
        let (sp, cp) = (TAU * u[1]).sin_cos();
        let wc = DVec3::new(sin_t * cp, sin_t * sp, cos_t);
        // Nearest hit along wc from the reference point, which sits at (0, 0, −d) in the cone
        // frame: t = d·(cos θ − g) with g² = sin²α − sin²θ = cos²θ − cos²α
        // = (1 − u₀)(1 − cos α)·(cos θ + cos α) = (1 − u₀)r²·((d + e)² − u₀r²)/dde², a product
        // without cancellation (g = 0 on the silhouette) whose root again needs dde only. The
        // hit point relative to the centre, (t·wc.x, t·wc.y, −d + t·cos θ), has
        // −d + t·cos θ = −d·(sin²θ + cos θ·g): no cancellation, unlike p + t·w.
        let g = (((rad * rad) - ur2) * (dpe * dpe - ur2)).max(0.0).sqrt() * inv_dde;
        let t = d * (cos_t - g);
        let qc = DVec3::new(t * wc.x, t * wc.y, -d * (sin2_t + cos_t * g));
        ConeSample {
            q: frame.to_world(qc),
            w: frame.to_world(wc),
            t,
            pdf,
        }
    }
}

/// The projected cap's frame (t, b, n), centre abscissa, semi-axes and area.
type CapEllipse = (Frame, f64, f64, f64, f64);

/// The ellipse of [`SphereTechnique::ProjectedCap`] seen from the receiver normal `n` for the
/// sphere of radius `rad` whose centre is at `v` from the receiver: its frame (t, b, n), centre
/// abscissa, semi-axes and area; `None` unless the cap lies wholly above the horizon.
#[inline]
fn projected_cap(v: DVec3, d2: f64, rad: f64, n: DVec3) -> Option<CapEllipse> {
    let d = d2.sqrt();
    let a = v / d;
    let sin2 = rad * rad / d2;
    let sin_a = sin2.sqrt();
    let cos_a = (1.0 - sin2).max(0.0).sqrt();
    let cos_b = n.dot(a);
    if !(cos_b > sin_a && sin2 < 1.0) {
        return None;
    }
    let tv = a - cos_b * n;
    let sin_b = tv.length();
    let frame = if sin_b > 1e-12 {
        let t = tv / sin_b;
        Frame {
            t,
            b: n.cross(t),
            n,
        }
    } else {
        Frame::from_normal(n)
    };
    let sin_b = sin_b.min(1.0);
    Some((
        frame,
        cos_a * sin_b,
        sin_a * cos_b,
        sin_a,
        PI * sin2 * cos_b,
    ))
}

/// Nearest intersection parameter t ≥ 0 of the ray p + t·w (unit w) with the sphere |x| = r, as
/// (t_near, t_far); `None` if missed.
#[inline]
fn hit(p: DVec3, w: DVec3, r: f64) -> Option<(f64, f64)> {
    let b = p.dot(w);
    // Discriminant from the perpendicular distance: r² − |p − (p·w)w|² (accurate far away).
    let perp = p - b * w;
    let disc = r * r - perp.length_squared();
    if disc < 0.0 {
        return None;
    }
    let s = disc.sqrt();
    Some((-b - s, -b + s))
}

/// A [`SphereLight`] seen from one receiver ([`SphereLight::seen_from`]): the part of sampling
/// that depends on the receiver alone, done once for the light samples of a shading point.
#[derive(Clone, Copy, Debug)]
pub struct SphereFrom<'a> {
    light: &'a SphereLight,
    r: Reference,
    plan: SpherePlan<'a>,
}

/// How a [`SphereFrom`] draws its points.
#[derive(Clone, Copy, Debug)]
enum SpherePlan<'a> {
    /// [`SphereTechnique::ProjectedCap`]: the world sphere, the receiver relative to its centre
    /// and the cap's ellipse.
    Cap {
        ws: &'a WorldSphere,
        p: DVec3,
        cap: &'a CapEllipse,
    },
    /// [`SphereTechnique::Cone`] around the world sphere.
    WorldCone { ws: &'a WorldSphere, cone: &'a Cone },
    /// Light-space sampling by this technique, from the receiver each time.
    Local(SphereTechnique),
}

impl SphereFrom<'_> {
    /// With [`SphereTechnique::ProjectedCap`] drawing (the whole cap above the receiver's
    /// horizon): the world sphere's centre and radius and the cap's projected solid angle
    /// Π = π sin²α cos β = ∫ cos θ dω over the cap. For a uniform radiance L, `L·Π` is the
    /// unoccluded cosine-weighted integral, the value every sample of the technique returns.
    pub fn projected_cap(&self) -> Option<(DVec3, f64, f64)> {
        match self.plan {
            SpherePlan::Cap {
                ws,
                cap: &(.., area),
                ..
            } => Some((ws.centre, ws.radius, area)),
            _ => None,
        }
    }

    /// Samples a point with `u ∈ [0,1)²`: [`SphereLight::sample_with`] from this receiver.
    #[inline(always)]
    pub fn sample(&self, u: [f64; 2]) -> Option<LightSample> {
        match self.plan {
            SpherePlan::Cap {
                ws,
                p,
                cap: &(f, cx, ax, ay, area),
            } => {
                let e = sample_concentric_disk(u);
                let (x, y) = (cx + ax * e.x, ay * e.y);
                let z = (1.0 - x * x - y * y).max(0.0).sqrt();
                let w = f.to_world(DVec3::new(x, y, z)).normalize();
                // The nearest hit; on the silhouette (numerically just outside) the tangent
                // point.
                let t = hit(p, w, ws.radius).map_or(-p.dot(w), |(t0, _)| t0);
                let q = p + t * w;
                let pdf = z / area;
                if !(t > 0.0 && pdf > 0.0 && pdf.is_finite()) {
                    return None;
                }
                Some(LightSample {
                    point: ws.centre + q,
                    normal: q * ws.inv_radius,
                    wi: w,
                    distance: t,
                    pdf,
                    delta: false,
                })
            }
            SpherePlan::WorldCone { ws, cone } => {
                let c = cone.sample(u);
                if !(c.t > 0.0 && c.pdf.is_finite()) {
                    return None;
                }
                Some(LightSample {
                    point: ws.centre + c.q,
                    normal: c.q * ws.inv_radius,
                    wi: c.w,
                    distance: c.t,
                    pdf: c.pdf,
                    delta: false,
                })
            }
            SpherePlan::Local(technique) => self.light.sample_local(&self.r, u, technique),
        }
    }
}

impl SphereLight {
    /// A sphere of `radius` (> 0, UsdLux `inputs:radius`) placed by `xf`; `technique` is the one
    /// `sample`/`pdf` use ([`Strategy::Lux`]).
    pub fn new(
        radius: f64,
        xf: LightTransform,
        technique: SphereTechnique,
    ) -> Result<Self, SampleError> {
        let radius = positive("radius", radius)?;
        let world = xf.inverse_uniform_scale().and_then(|k| {
            let (s, centre) = (1.0 / k, xf.translation());
            let radius = radius * s;
            let inv_tau_r2 = 1.0 / (TAU * radius * radius);
            (radius.is_finite() && inv_tau_r2.is_finite()).then_some(WorldSphere {
                centre,
                radius,
                inv_radius: 1.0 / radius,
                inv_tau_r2,
            })
        });
        Ok(Self {
            radius,
            inv_radius: 1.0 / radius,
            inv_tau_r2: 1.0 / (TAU * radius * radius),
            xf,
            technique,
            world,
        })
    }

    /// The **projected solid angle** `Π = ∫ max(0, n·ω) dω` of the sphere seen from the receiver
    /// `r` (its `(p, n)`), clipped to the receiver's horizon (lux-irradiance's
    /// `projected::sphere`, in closed form; `π sin²α cos ω` unclipped): the unshadowed irradiance
    /// is `E = L·Π` for a uniform radiance `L`. The sphere emits outwards (spec §2), so a
    /// receiver inside it gets 0. `None` for a reference without a normal (`n = 0`) and for a
    /// sphere under a non-uniform scale or shear (an ellipsoid).
    pub fn projected_solid_angle(&self, r: &Reference) -> Option<f64> {
        if r.n == DVec3::ZERO || !self.xf.is_similarity() {
            return None;
        }
        let centre = self.xf.translation();
        let radius = self.radius * self.xf.vector(DVec3::X).length();
        if crate::not_positive(r.p.distance(centre) - radius) {
            return Some(0.0);
        }
        lux_irradiance::projected::sphere(r.p, r.n, centre, radius)
    }

    /// The sampling technique.
    pub fn technique(&self) -> SphereTechnique {
        self.technique
    }

    /// Samples a point seen from `r` with the built technique: the direction `wi`, its density
    /// per unit solid angle, the point and its outward normal.
    #[inline]
    pub fn sample(&self, r: &Reference, u: [f64; 2]) -> Option<LightSample> {
        self.sample_by(r, u, self.technique)
    }

    /// [`Self::sample`] with the techniques of `strategy` (`HdEmbree`: [`SphereTechnique::Area`]).
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
    fn technique_of(&self, strategy: Strategy) -> SphereTechnique {
        match strategy {
            Strategy::Lux => self.technique,
            Strategy::HdEmbree => SphereTechnique::Area,
        }
    }

    /// The world sphere, the receiver relative to its centre and the projected-cap ellipse
    /// ([`SphereTechnique::ProjectedCap`]) when that technique applies from `r`.
    #[inline]
    fn projected_cap_from(&self, r: &Reference) -> Option<(&WorldSphere, DVec3, CapEllipse)> {
        let ws = self.world.as_ref()?;
        if r.n == DVec3::ZERO {
            return None;
        }
        let p = r.p - ws.centre;
        let d2 = p.length_squared();
        if d2.is_nan() || d2 <= ws.radius * ws.radius {
            return None;
        }
        Some((ws, p, projected_cap(-p, d2, ws.radius, r.n)?))
    }

    /// Calls `f` with the light seen from the receiver `r` with the techniques of `strategy`:
    /// what every sample drawn from there shares (the projected cap's ellipse, or the cone's
    /// frame), computed once, so that `k` samples from one receiver cost one setup.
    /// [`SphereFrom::sample`] equals [`Self::sample_with`]`(r, u, strategy)` for every `u`, bit
    /// for bit.
    #[inline(always)]
    pub fn seen_from<R>(
        &self,
        r: &Reference,
        strategy: Strategy,
        f: impl FnOnce(&SphereFrom<'_>) -> R,
    ) -> R {
        self.seen_by(r, self.technique_of(strategy), f)
    }

    #[inline(always)]
    fn seen_by<R>(
        &self,
        r: &Reference,
        technique: SphereTechnique,
        f: impl FnOnce(&SphereFrom<'_>) -> R,
    ) -> R {
        // (the cap's ellipse and the cone stay where they are built: `SphereFrom` borrows them)
        let (cap, cone);
        let plan = 'plan: {
            if technique == SphereTechnique::ProjectedCap
                && let Some((ws, p, c)) = self.projected_cap_from(r)
            {
                cap = c;
                break 'plan SpherePlan::Cap { ws, p, cap: &cap };
            }
            let technique = if technique == SphereTechnique::ProjectedCap {
                SphereTechnique::Cone
            } else {
                technique
            };
            if technique == SphereTechnique::Cone
                && let Some(ws) = &self.world
            {
                let p = r.p - ws.centre;
                let d2 = p.length_squared();
                if d2 > ws.radius * ws.radius {
                    cone = Cone::new(p, d2, ws.radius, ws.inv_tau_r2);
                    break 'plan SpherePlan::WorldCone { ws, cone: &cone };
                }
            }
            SpherePlan::Local(technique)
        };
        f(&SphereFrom {
            light: self,
            r: *r,
            plan,
        })
    }

    #[inline]
    fn sample_by(
        &self,
        r: &Reference,
        u: [f64; 2],
        technique: SphereTechnique,
    ) -> Option<LightSample> {
        self.seen_by(r, technique, |from| from.sample(u))
    }

    /// [`SphereTechnique::Area`] or [`SphereTechnique::Cone`] in light space (receivers inside
    /// the sphere are sampled by area).
    #[inline]
    fn sample_local(
        &self,
        r: &Reference,
        u: [f64; 2],
        technique: SphereTechnique,
    ) -> Option<LightSample> {
        let pl = self.xf.inv_point(r.p);
        let rad = self.radius;
        let d2 = pl.length_squared();
        let inside = d2 <= rad * rad;
        if inside || technique == SphereTechnique::Area {
            let n = sample_uniform_sphere(u);
            let q = n * rad;
            let v = q - pl;
            let dist2 = v.length_squared();
            let cos = n.dot(v) / dist2.sqrt();
            if !inside && cos >= 0.0 {
                return None; // back-facing: hidden by the sphere itself
            }
            let pdf = dist2 / (cos.abs() * 4.0 * PI * rad * rad);
            return finish_sample(&self.xf, r.p, pl, q, n, pdf);
        }
        let c = sample_cone(pl, d2, rad, self.inv_tau_r2, u);
        finish_sample_dir(&self.xf, c.q, c.q * self.inv_radius, c.w, c.t, c.pdf)
    }

    /// Solid-angle density of [`Self::sample`] producing `wi` from `r`.
    #[inline]
    pub fn pdf(&self, r: &Reference, wi: DVec3) -> f64 {
        self.pdf_by(r, wi, self.technique)
    }

    #[inline]
    fn pdf_by(&self, r: &Reference, wi: DVec3, technique: SphereTechnique) -> f64 {
        if technique == SphereTechnique::ProjectedCap
            && let Some((ws, p, (_, _, _, _, area))) = self.projected_cap_from(r)
        {
            return match hit(p, wi, ws.radius) {
                Some((t0, _)) if t0 >= 0.0 => r.n.dot(wi).max(0.0) / area,
                _ => 0.0,
            };
        }
        let pl = self.xf.inv_point(r.p);
        let Some((wl, jac)) = local_direction(&self.xf, wi) else {
            return 0.0;
        };
        if !pl.is_finite() {
            return 0.0;
        }
        let rad = self.radius;
        let d2 = pl.length_squared();
        let Some((t0, t1)) = hit(pl, wl, rad) else {
            return 0.0;
        };
        let pdf = if d2 <= rad * rad {
            let q = pl + t1 * wl;
            let cos = (q / rad).dot(wl).abs();
            t1 * t1 / (cos * 4.0 * PI * rad * rad)
        } else if t0 < 0.0 {
            0.0
        } else if technique == SphereTechnique::Area {
            let q = pl + t0 * wl;
            let cos = (q / rad).dot(wl).abs();
            t0 * t0 / (cos * 4.0 * PI * rad * rad)
        } else {
            let sin2 = rad * rad / d2;
            let omc = sin2 / (1.0 + (1.0 - sin2).max(0.0).sqrt());
            1.0 / (TAU * omc)
        };
        pdf * jac
    }
}

impl SphereLight {
    /// A point uniform by local area on the sphere (by world area under a similarity; an
    /// ellipsoid's density carries the transform's area scale at the point), emitting outward:
    /// emission sampling ([`AreaSample`]).
    #[inline]
    pub fn sample_area(&self, u: [f64; 2]) -> Option<AreaSample> {
        let n = sample_uniform_sphere(u);
        let f = Frame::from_normal(n);
        let r = self.radius;
        let area = 4.0 * PI * r * r * self.xf.area_scale(f.t, f.b);
        (area > 0.0).then(|| AreaSample {
            point: self.xf.point(n * r),
            normal: self.xf.normal(n),
            pdf: 1.0 / area,
        })
    }
}
