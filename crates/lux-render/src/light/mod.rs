//! The scene's lights prepared for rendering: one type per UsdLux light kind, each answering
//! the same questions (pbrt-v4's light interface), dispatched over the closed set [`Light`].
//!
//! | question | method |
//! |---|---|
//! | a sample towards a receiver: radiance, direction, density, distance | [`Light::sample_li`] |
//! | the same, k times from one receiver (its setup done once) | [`Light::seen_from`] |
//! | the density of a direction, for MIS | [`Light::pdf_li`] |
//! | the radiance leaving a point of the light's surface | [`Light::le`] |
//! | the radiance arriving from an infinitely distant light | [`Light::le_escape`] |
//! | where a ray crosses the light's analytic surface | [`Light::intersect`] |
//! | world bounds, emission cone and power, for light selection | [`Light::bounds`] |
//!
//! Every emitted radiance follows the spec pipeline (spec README §3):
//! `L(ω) = base · shapingFactor(ω_light) · texture(uv)`, with `base` the LightAPI emission
//! `intensity · 2^exposure · color · blackbody / sizeFactor` (lux-math, or lux-spectral for
//! physical units — [`crate::physical`]) and `ω_light` the emission direction (from the light
//! towards the receiver) in the light's local space ([`LightBase::shaped`]).
//!
//! Profile-dependent behaviour implemented here (see [`lux_math::Profile`]):
//! - RectLight texture on the lit path: `Spec` uses the schema orientation (image
//!   u runs along local −X, i.e. left-to-right for an observer facing the emitting −Z side;
//!   image top row at local +Y) on both the lit and the visible path; `HdEmbree`
//!   mirrors u on the lit path (u along +X), as the reference renderer does ([`Seen`]).
//! - Camera visibility: both profiles show the DomeLight as the background of camera rays
//!   that miss (hdEmbree evaluates the dome for a ray that hits nothing; measured on the
//!   luxtest dome-only frame, spec README §4); `HdEmbree` shows only a RectLight
//!   whose custom `inputs:visibility:camera` is true, `Spec` honours that attribute
//!   for every area light.
//! - Texture filtering (not a UsdLux behaviour): nearest texel in `HdEmbree` — the reference's
//!   `SampleLightTexture` reads texel `(⌊w·s⌋, ⌊h·t⌋)` for lighting *and* for the background
//!   of camera rays, which is what makes the dome frame's sharp texel edges agree (a bilinear
//!   background matches its mean to 1e-5 but blurs every edge) — bilinear in `Spec`.
//! - The IES emission direction of an area light (both profiles): from the sampled point on
//!   the light towards the receiver, as hdEmbree's `EvalIES(light, wI)` takes it, not from the
//!   light's centre. In the near field of a small SphereLight with a sharp (angle-scaled)
//!   profile the two differ by at most 0.15 % of the image mean on the luxtest
//!   `iesLibPreview` frames; the 1–2 % (locally 3–9 %) by which one 64-spp reference render
//!   sits below lux there is the right skew of the reference's estimator (uniform sampling of
//!   the whole sphere's area): its realizations are typically below its expectation, which
//!   more samples reach (`tests/hdembree_profile.rs`).
//!
//! Lights are not occluders (as in the reference renderer): a shadow ray stops only at
//! geometry, and a BSDF ray collects every light it crosses before its first surface.
//!
//! **Adding a light kind**: its typed description (`lux_math::LightShape`, read by lux-usd),
//! its sampler in lux-sample, a file here with its type answering every question above (and
//! its power estimate), a variant of [`Light`] and a line of the `dispatch!` list below, and
//! its construction in `load.rs`.

mod cylinder;
mod disk;
mod distant;
mod dome;
mod emit;
mod linking;
mod load;
mod mesh;
mod rect;
mod set;
mod shapes;
mod sphere;

pub use cylinder::CylinderLight;
pub use disk::DiskLight;
pub use distant::DistantLight;
pub use dome::DomeLight;
pub use emit::LeSample;
#[cfg(test)]
pub(crate) use linking::tests as linking_tests;
pub use linking::{GeomSet, LightLinks, MAX_PASS_THROUGH};
pub use mesh::MeshLight;
pub use rect::RectLight;
pub use set::{AUTO_ALL_LIGHTS, LightOptions, LightSelection, LightSet};
pub use shapes::{LINEAR_LIGHTS, LightShapes};
pub use sphere::SphereLight;

use crate::image_io::Texture;
use glam::DVec3;
use lux_math::LightKind;
use lux_sample::{EmissionCone, LightBounds, LightSample, LightTransform, Reference, Strategy};
use lux_shaping::Shaping;
use lux_usd::ShadowInputs;
use std::sync::Arc;

/// What every light kind carries: identity, emission, shaping, transform and the LightAPI /
/// ShadowAPI inputs the integrators read.
#[derive(Clone, Debug)]
pub struct LightBase {
    /// Prim path.
    pub path: String,
    /// Base radiance (RGB nits) before shaping and texture.
    pub radiance: DVec3,
    /// ShapingAPI factor (identity without the API).
    pub shaping: Shaping,
    /// Estimated emitted power (Rec.709-luminance-weighted), for light selection.
    pub power: f64,
    /// Whether camera rays see the light's surface (or, for a dome, the background).
    pub camera_visible: bool,
    /// `inputs:diffuse`: multiplier of the light's effect on diffuse surfaces (finite, ≥ 0).
    pub diffuse: f64,
    /// `inputs:specular`: multiplier of the light's effect on specular lobes (the
    /// UsdPreviewSurface GGX and clearcoat; finite, ≥ 0).
    pub specular: f64,
    /// `ShadowAPI` inputs (`enable`, `color`, `distance`, `falloff`, `falloffGamma`).
    pub shadow: ShadowInputs,
    /// Light → world.
    pub xf: LightTransform,
    /// LightAPI `collection:lightLink` / `collection:shadowLink` resolved over the scene
    /// (none for the default, everything).
    pub links: LightLinks,
}

impl LightBase {
    /// A light at `xf` emitting nothing yet (radiance and power are set once the kind is
    /// built).
    pub(crate) fn new(
        path: &str,
        xf: LightTransform,
        shaping: Shaping,
        shadow: ShadowInputs,
    ) -> LightBase {
        LightBase {
            path: path.to_owned(),
            radiance: DVec3::ZERO,
            shaping,
            power: 0.0,
            camera_visible: false,
            diffuse: 1.0,
            specular: 1.0,
            shadow,
            links: LightLinks::default(),
            xf,
        }
    }

    /// Whether the light's shadows are the physical default (enabled, black, no distance
    /// limit, cast by every piece of geometry: no `collection:shadowLink` restriction).
    /// Lights with other `ShadowAPI` settings or shadow links are estimated by light sampling
    /// alone, since a BSDF ray stops at the first occluder.
    #[inline]
    pub fn plain_shadows(&self) -> bool {
        self.black_shadows() && self.links.shadow.is_none()
    }

    /// Whether each shadow ray either passes or is blocked outright: shadows enabled, black,
    /// without a distance limit (`inputs:shadow:enable`, `:color`, `:distance`); a
    /// `collection:shadowLink` only chooses what casts them.
    #[inline]
    pub fn black_shadows(&self) -> bool {
        self.shadow.enable
            && self.shadow.color == DVec3::ZERO
            && (self.shadow.distance.is_nan() || self.shadow.distance < 0.0)
    }

    /// The light-space point of a world point.
    #[inline]
    pub fn to_local(&self, p: DVec3) -> DVec3 {
        self.xf.inv_point(p)
    }

    /// The unit light-space direction of the world emission direction `emit` (from the light
    /// towards the receiver): `normalize(L⁻¹·emit)` ([`LightTransform::local_direction`], the
    /// one mapping lux-shaping's `Shaping::factor_world` uses); `None` when it has no length.
    #[inline]
    pub fn local_direction(&self, emit: DVec3) -> Option<DVec3> {
        self.xf.local_direction(emit)
    }

    /// The radiance a light sample carries: for a light of uniform radiance (identity
    /// shaping, no texture) whose side test a world dot product answers (`outward`: the
    /// sample's emission direction leaves the emitting side), `base` or 0 — what `le` gives
    /// there, without the light-space point and direction; else `le()`.
    #[inline(always)]
    pub fn sample_radiance(&self, outward: Option<bool>, le: impl FnOnce() -> DVec3) -> DVec3 {
        match outward {
            Some(true) => self.radiance,
            Some(false) => DVec3::ZERO,
            None => le(),
        }
    }

    /// `base · shapingFactor(wl)` for the unit light-space emission direction `wl` (one
    /// returned by [`LightBase::local_direction`], for the kinds that test its side first).
    #[inline]
    pub fn shaped(&self, wl: DVec3) -> DVec3 {
        self.radiance * self.shaping.factor(wl)
    }

    /// `base · shapingFactor` towards the world emission direction `emit`:
    /// `Shaping::factor_world(xf, emit)` (zero for a direction without length).
    #[inline]
    pub fn emitted(&self, emit: DVec3) -> DVec3 {
        self.radiance * self.shaping.factor_world(&self.xf, emit)
    }

    /// Selection bounds of a finite light whose surface lies in the world box `(min, max)`:
    /// its power and emission cone (normals within `theta_o` of the light's −Z axis, emission
    /// within `theta_e` of each normal; `two_sided` doubles it).
    fn bounds(
        &self,
        (min, max): (DVec3, DVec3),
        theta_o: f64,
        theta_e: f64,
        two_sided: bool,
    ) -> Option<LightBounds> {
        let axis = self.xf.normal(DVec3::NEG_Z);
        let cone = EmissionCone::new(axis, theta_o, theta_e).unwrap_or(EmissionCone::SPHERE);
        LightBounds::new(min, max, self.power.max(0.0), cone, two_sided).ok()
    }
}

/// Which path sees an emitted radiance: the `HdEmbree` profile mirrors a RectLight's texture on
/// the lit path only.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Seen {
    /// Directly, by a camera ray.
    Camera,
    /// Lighting a surface (light samples and BSDF rays).
    Lit,
}

/// A light sample from a receiver, with the radiance it carries (pbrt-v4's `LightLiSample`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LiSample {
    /// Radiance arriving along `-wi` (RGB nits), shaping and texture included.
    pub l: DVec3,
    /// Unit direction from the receiver towards the light.
    pub wi: DVec3,
    /// Density of `wi` per unit solid angle (a probability for a delta light).
    pub pdf: f64,
    /// Distance to the sampled point; infinite for lights at infinity.
    pub dist: f64,
    /// The sampled point (for lights at infinity: `wi`).
    pub point: DVec3,
    /// A delta light (DistantLight of angle 0): light sampling only.
    pub delta: bool,
}

impl LiSample {
    #[inline]
    fn new(s: LightSample, l: DVec3) -> LiSample {
        LiSample {
            l,
            wi: s.wi,
            pdf: s.pdf,
            dist: s.distance,
            point: s.point,
            delta: s.delta,
        }
    }
}

/// A light seen from one receiver ([`Light::seen_from`]).
#[derive(Clone, Copy, Debug)]
pub enum LightFrom<'a> {
    /// A rect light and its sampler's view from the receiver.
    Rect(&'a RectLight, &'a lux_sample::RectFrom<'a>),
    /// A disk light and its sampler's view from the receiver.
    Disk(&'a DiskLight, &'a lux_sample::DiskFrom<'a>),
    /// A sphere light and its sampler's view from the receiver.
    Sphere(&'a SphereLight, &'a lux_sample::SphereFrom<'a>),
    /// A cylinder light and its sampler's view from the receiver.
    Cylinder(&'a CylinderLight, &'a lux_sample::CylinderFrom<'a>),
    /// Any other kind, sampled from the receiver each time.
    Other(&'a Light, Reference, Strategy),
}

impl LightFrom<'_> {
    /// Whether each light sample from this receiver returns its closed form
    /// ([`LightFrom::unshadowed`]) exactly where it is unblocked: a uniform sphere drawn from
    /// its projected cap (`L·cos θ / pdf = L·Π` for every sample). Its closed form then saves
    /// the shadow rays but removes no noise.
    #[inline]
    pub fn samples_exactly(&self) -> bool {
        self.sphere_cap().is_some()
    }

    /// For a uniform sphere drawn from its projected cap ([`LightFrom::samples_exactly`]): its
    /// world centre and radius and the cap's projected solid angle Π from the receiver.
    #[inline]
    pub fn sphere_cap(&self) -> Option<(DVec3, f64, f64)> {
        match self {
            LightFrom::Sphere(l, from) if l.uniform_area() => from.projected_cap(),
            _ => None,
        }
    }

    /// For a rect of uniform radiance: its world corners (a parallelogram), what its closed form
    /// [`LightFrom::unshadowed`] integrates over.
    #[inline]
    pub fn rect_corners(&self) -> Option<[DVec3; 4]> {
        match self {
            LightFrom::Rect(l, _) if l.uniform_area() => Some(l.world_corners()),
            _ => None,
        }
    }

    /// For a disk of uniform radiance under a similarity: its world centre, unit normal and
    /// radius, what its closed form [`LightFrom::unshadowed`] integrates over.
    #[inline]
    pub fn world_disk(&self) -> Option<(DVec3, DVec3, f64)> {
        match self {
            LightFrom::Disk(l, _) if l.uniform_area() => l.world_disk(),
            _ => None,
        }
    }

    /// The light's unshadowed cosine-weighted integral at the receiver `(p, n)`,
    /// `∫ L cos θ dω = L·Π` (radiance times the projected solid angle,
    /// [`lux_irradiance::projected`]): what its light-only estimator averages to where nothing
    /// blocks it. For the sphere, Π of the projected cap its samples are drawn from (each
    /// sample returns exactly `L·Π`). `None` for other lights.
    #[inline]
    pub fn unshadowed(&self, p: DVec3, n: DVec3) -> Option<DVec3> {
        // The radiance leaving a point of a uniform light towards p (the same everywhere on
        // its lit side; zero behind a one-sided light).
        let toward = |c: DVec3| (p - c).normalize_or_zero();
        match self {
            LightFrom::Sphere(l, from) if l.uniform_area() => {
                let (centre, radius, pi) = from.projected_cap()?;
                let out = toward(centre);
                let le = l.le(l.base.to_local(centre + out * radius), out, Seen::Lit);
                Some(le * pi)
            }
            LightFrom::Rect(l, _) if l.uniform_area() => {
                let corners = l.world_corners();
                let (centre, _) = l.bounding_sphere();
                let le = l.le(DVec3::ZERO, toward(centre), Seen::Lit);
                Some(le * lux_irradiance::projected::polygon(p, n, &corners))
            }
            LightFrom::Disk(l, _) if l.uniform_area() => {
                let (centre, axis, radius) = l.world_disk()?;
                let le = l.le(DVec3::ZERO, toward(centre), Seen::Lit);
                Some(le * lux_irradiance::projected::disk(p, n, centre, axis, radius)?)
            }
            _ => None,
        }
    }

    /// A light sample with `u ∈ [0,1)²`: [`Light::sample_li`] from the receiver.
    #[inline]
    pub fn sample_li(&self, u: [f64; 2]) -> Option<LiSample> {
        match self {
            LightFrom::Rect(l, from) => l.sample_li_from(from, u),
            LightFrom::Disk(l, from) => l.sample_li_from(from, u),
            LightFrom::Sphere(l, from) => l.sample_li_from(from, u),
            LightFrom::Cylinder(l, from) => l.sample_li_from(from, u),
            LightFrom::Other(l, r, strategy) => l.sample_li(r, u, *strategy),
        }
    }
}

/// What a ray crossing a light's surface found.
#[derive(Clone, Copy, Debug)]
pub struct LightHit {
    /// Distance along the ray.
    pub t: f64,
    /// The point in light space.
    pub local: DVec3,
    /// True when the ray arrives on the emitting side.
    pub front: bool,
}

/// A texture bound to a light (RectLight, DomeLight `inputs:texture:file`), with how it is
/// looked up.
#[derive(Clone, Debug)]
pub struct LightTexture {
    tex: Arc<Texture>,
    nearest: bool,
}

impl LightTexture {
    /// Linear RGB at `(u, v)`, v = 0 at the top row.
    #[inline]
    fn rgb(&self, u: f64, v: f64) -> DVec3 {
        let t = if self.nearest {
            self.tex.nearest(u, v)
        } else {
            self.tex.bilinear(u, v)
        };
        DVec3::new(t[0] as f64, t[1] as f64, t[2] as f64)
    }
}

/// Any light ready to render (the closed set of UsdLux light kinds lux renders).
#[derive(Clone, Debug)]
pub enum Light {
    /// `RectLight`.
    Rect(RectLight),
    /// `DiskLight`.
    Disk(DiskLight),
    /// `SphereLight`.
    Sphere(SphereLight),
    /// `CylinderLight`.
    Cylinder(CylinderLight),
    /// `DistantLight`.
    Distant(DistantLight),
    /// `DomeLight` / `DomeLight_1`.
    Dome(DomeLight),
    /// A mesh with `MeshLightAPI`.
    Mesh(MeshLight),
}

/// `match` over every kind with the same expression (the one list to extend with a new kind).
macro_rules! dispatch {
    ($light:expr, $l:ident => $e:expr) => {
        match $light {
            Light::Rect($l) => $e,
            Light::Disk($l) => $e,
            Light::Sphere($l) => $e,
            Light::Cylinder($l) => $e,
            Light::Distant($l) => $e,
            Light::Dome($l) => $e,
            Light::Mesh($l) => $e,
        }
    };
}

impl Light {
    /// What every kind carries.
    #[inline]
    pub fn base(&self) -> &LightBase {
        dispatch!(self, l => &l.base)
    }

    #[inline]
    fn base_mut(&mut self) -> &mut LightBase {
        dispatch!(self, l => &mut l.base)
    }

    /// The UsdLux family.
    pub fn kind(&self) -> LightKind {
        match self {
            Light::Rect(_) => LightKind::Rect,
            Light::Disk(_) => LightKind::Disk,
            Light::Sphere(_) => LightKind::Sphere,
            Light::Cylinder(_) => LightKind::Cylinder,
            Light::Distant(_) => LightKind::Distant,
            Light::Dome(_) => LightKind::Dome,
            Light::Mesh(_) => LightKind::Mesh,
        }
    }

    /// Samples the light from the receiver `r` with `u ∈ [0,1)²` and the techniques of
    /// `strategy`: the direction, its density, and the radiance arriving along it.
    #[inline]
    pub fn sample_li(&self, r: &Reference, u: [f64; 2], strategy: Strategy) -> Option<LiSample> {
        dispatch!(self, l => l.sample_li(r, u, strategy))
    }

    /// Calls `f` with the light seen from the receiver `r` with the techniques of `strategy`:
    /// what its sampler computes from the receiver alone (a rect's spherical rectangle, a
    /// disk's cone, a sphere's projected cap, a cylinder's angles), done once for the light
    /// samples of a shading point. [`LightFrom::sample_li`] equals [`Light::sample_li`]`(r, u, strategy)`, bit for
    /// bit.
    #[inline(always)]
    pub fn seen_from<R>(
        &self,
        r: &Reference,
        strategy: Strategy,
        f: impl FnOnce(&LightFrom<'_>) -> R,
    ) -> R {
        match self {
            Light::Rect(l) => l
                .sampler
                .seen_from(r, strategy, |from| f(&LightFrom::Rect(l, from))),
            Light::Disk(l) => l
                .sampler
                .seen_from(r, strategy, |from| f(&LightFrom::Disk(l, from))),
            Light::Sphere(l) => l
                .sampler
                .seen_from(r, strategy, |from| f(&LightFrom::Sphere(l, from))),
            Light::Cylinder(l) => l
                .sampler
                .seen_from(r, strategy, |from| f(&LightFrom::Cylinder(l, from))),
            l => f(&LightFrom::Other(l, *r, strategy)),
        }
    }

    /// Solid-angle density with which [`Light::sample_li`] (lux strategy) produces the
    /// direction `wi` from `r` (for MIS). A mesh light's density depends on the triangle a ray
    /// hit: [`MeshLight::pdf_li_triangle`].
    #[inline]
    pub fn pdf_li(&self, r: &Reference, wi: DVec3) -> f64 {
        dispatch!(self, l => l.pdf_li(r, wi))
    }

    /// [`Light::pdf_li`] for a ray that hit triangle `tri` of a mesh light (the density of
    /// sampling that direction through that triangle); [`Light::pdf_li`] for other kinds.
    #[inline]
    pub fn pdf_li_triangle(&self, r: &Reference, tri: usize, wi: DVec3) -> f64 {
        match self {
            Light::Mesh(l) => l.pdf_li_triangle(r, tri, wi),
            l => l.pdf_li(r, wi),
        }
    }

    /// Radiance leaving the light-space surface point `local` along the world direction `emit`
    /// (from the light towards the receiver), seen on the `seen` path; zero for lights at
    /// infinity and on the non-emitting side.
    #[inline]
    pub fn le(&self, local: DVec3, emit: DVec3, seen: Seen) -> DVec3 {
        dispatch!(self, l => l.le(local, emit, seen))
    }

    /// A rect, disk or sphere light of uniform radiance (no ShapingAPI, no texture): one whose
    /// lux-sample technique follows the cosine-weighted solid angle it subtends, so that the
    /// direct integrator estimates it by light sampling alone (its unshadowed irradiance, the
    /// projected solid angle of [`lux_irradiance::projected`] times its radiance, is what those
    /// samples average to).
    #[inline]
    pub fn uniform_area(&self) -> bool {
        dispatch!(self, l => l.uniform_area())
    }

    /// Radiance arriving along the world direction `wi` (receiver → light) from a light at
    /// infinity (the dome's texture, a distant light's cone); zero for finite lights.
    #[inline]
    pub fn le_escape(&self, wi: DVec3) -> DVec3 {
        dispatch!(self, l => l.le_escape(wi))
    }

    /// First crossing of the ray `o + t·d`, `t ∈ (tmin, tmax)`, with the light's analytic
    /// surface (rect, disk, sphere, cylinder; `None` for the others). Transforms are affine, so
    /// `t` is the same in light space.
    #[inline]
    pub fn intersect(&self, o: DVec3, d: DVec3, tmin: f64, tmax: f64) -> Option<LightHit> {
        dispatch!(self, l => l.intersect(o, d, tmin, tmax))
    }

    /// World box of the light's analytic surface (rect, disk, sphere, cylinder), `None` for
    /// the others: where [`Light::intersect`] can succeed.
    pub fn surface_box(&self) -> Option<(DVec3, DVec3)> {
        dispatch!(self, l => l.surface_box())
    }

    /// World bounds, power and emission cone for the light BVH; `None` for lights at infinity.
    pub fn bounds(&self) -> Option<LightBounds> {
        dispatch!(self, l => l.bounds())
    }

    /// Estimated power for light selection (Rec.709 luminance of the base radiance, times the
    /// world `area` (sizeFactor, unused at infinity) and the shaping's angular integral).
    fn power(&self, area: f64) -> f64 {
        dispatch!(self, l => l.power(area))
    }

    /// Whether the light lies at infinity (dome, distant).
    #[inline]
    pub fn is_infinite(&self) -> bool {
        matches!(self, Light::Dome(_) | Light::Distant(_))
    }

    /// A delta light (DistantLight of angle 0): reachable by light sampling only.
    #[inline]
    pub fn is_delta(&self) -> bool {
        matches!(self, Light::Distant(l) if l.is_delta())
    }

    /// The scene mesh a mesh light emits from (for an instance's light, its prototype's mesh:
    /// [`MeshLight::instance`] names the instance).
    pub fn mesh(&self) -> Option<usize> {
        match self {
            Light::Mesh(l) => Some(l.mesh),
            _ => None,
        }
    }
}

/// Roots t0 ≤ t1 of a·t² + 2b·t + c = 0 (numerically stable form), `None` without real roots.
#[inline]
fn quadratic(a: f64, b: f64, c: f64) -> Option<(f64, f64)> {
    if a.is_nan() || a <= 0.0 {
        return None;
    }
    let disc = b * b - a * c;
    if disc.is_nan() || disc < 0.0 {
        return None;
    }
    let s = disc.sqrt();
    let q = -(b + s.copysign(b));
    let (x, y) = if q != 0.0 { (q / a, c / q) } else { (0.0, 0.0) };
    Some((x.min(y), x.max(y)))
}

/// The world box of the light-space points `corners` mapped by `xf`.
fn box_of(xf: &LightTransform, corners: impl IntoIterator<Item = DVec3>) -> (DVec3, DVec3) {
    corners.into_iter().fold(
        (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
        |(lo, hi), c| {
            let p = xf.point(c);
            (lo.min(p), hi.max(p))
        },
    )
}

/// The 8 corners of the light-space box `[−h, h]`.
fn box_corners(h: DVec3) -> [DVec3; 8] {
    let mut out = [DVec3::ZERO; 8];
    for (i, o) in out.iter_mut().enumerate() {
        *o = DVec3::new(
            if i & 1 == 0 { -h.x } else { h.x },
            if i & 2 == 0 { -h.y } else { h.y },
            if i & 4 == 0 { -h.z } else { h.z },
        );
    }
    out
}

/// The ShapingAPI (cone, IES profile and its angleScale) narrows a planar light's emission
/// around its axis to lux-shaping's conservative half-angle, under a similarity transform (a
/// non-uniform scale or shear changes angles between light and world space); π/2 otherwise.
fn planar_emission_half_angle(base: &LightBase) -> f64 {
    if base.xf.is_similarity() {
        base.shaping
            .emission_half_angle()
            .min(std::f64::consts::FRAC_PI_2)
    } else {
        std::f64::consts::FRAC_PI_2
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every light of `scene`, prepared under the `spec` profile.
    fn every_light(scene: &lux_usd::Scene) -> LightSet {
        let options = LightOptions {
            profile: lux_math::Profile::Spec,
            selection: LightSelection::All,
            strict: false,
            cone_clipping: true,
        };
        LightSet::new(scene, options).unwrap()
    }

    /// Only a sphere seen as its projected cap samples its closed form exactly (what lets the
    /// direct integrator skip a point's own search for it): every sample's `L·cos θ / pdf`
    /// is `L·Π` there; not so for a disk or a rect, nor for a sphere cut by the horizon.
    #[test]
    fn only_a_sphere_seen_as_its_cap_samples_exactly() {
        use lux_math::LightShape;
        let down = |c: DVec3| {
            let q = glam::DQuat::from_rotation_arc(DVec3::NEG_Z, DVec3::NEG_Y);
            glam::DMat4::from_rotation_translation(q, c)
        };
        let mut scene = lux_usd::Scene::empty("lights.usda");
        for (path, shape, c) in [
            (
                "/Cap",
                LightShape::Sphere { radius: 0.3 },
                DVec3::new(0.4, 1.5, -0.2),
            ),
            (
                "/Cut",
                LightShape::Sphere { radius: 0.5 },
                DVec3::new(1.0, 0.3, 0.0),
            ),
            (
                "/Disk",
                LightShape::Disk { radius: 0.3 },
                DVec3::new(0.4, 1.5, -0.2),
            ),
            (
                "/Rect",
                LightShape::Rect {
                    width: 0.6,
                    height: 0.4,
                },
                DVec3::new(0.4, 1.5, -0.2),
            ),
        ] {
            scene
                .lights
                .push(lux_usd::Light::with_defaults(path, shape, down(c)));
        }
        let set = every_light(&scene);
        let r = Reference::surface(DVec3::ZERO, DVec3::Y);
        let exact: Vec<bool> = set
            .lights
            .iter()
            .map(|l| {
                l.seen_from(&r, Strategy::Lux, |from| {
                    let closed = from.unshadowed(DVec3::ZERO, DVec3::Y);
                    let mut same = closed.is_some();
                    for i in 0..64 {
                        let u = [(i % 8) as f64 / 8.0 + 0.03, (i / 8) as f64 / 8.0 + 0.05];
                        if let (Some(s), Some(c)) = (from.sample_li(u), closed) {
                            let v = s.l * (s.wi.y / s.pdf);
                            same &= (v - c).abs().max_element() <= 1e-9 * c.max_element();
                        }
                    }
                    assert_eq!(from.samples_exactly(), same, "{:?}", l.base().path);
                    same
                })
            })
            .collect();
        assert_eq!(exact, [true, false, false, false]);
    }

    /// The renderer shapes a light's emission with lux-shaping's world-space entry point: under a
    /// sheared, non-uniformly scaled transform the radiance a light sample carries is
    /// `base · Shaping::factor_world(xf, point → receiver)`, and a 40° cone stretched by 3 along
    /// the light's X lights a receiver 60° off the world axis in that plane (the affine image of
    /// the cone) while one at 45° in the other plane is dark.
    #[test]
    fn shaping_under_shear_is_factor_world() {
        use lux_math::LightShape;
        let shear = glam::DMat4::from_cols_array(&[
            3.0, 0.0, 0.0, 0.0, //
            0.4, 1.0, 0.0, 0.0, //
            0.2, -0.3, 1.5, 0.0, //
            0.0, 0.0, 2.0, 1.0,
        ]);
        let mut scene = lux_usd::Scene::empty("lights.usda");
        for (path, shape) in [
            ("/Disk", LightShape::Disk { radius: 0.3 }),
            ("/Sphere", LightShape::Sphere { radius: 0.2 }),
        ] {
            let mut l = lux_usd::Light::with_defaults(path, shape, shear);
            l.shaping = Some(lux_usd::ShapingInputs {
                cone_angle_deg: 40.0,
                cone_softness: 0.3,
                focus: 2.0,
                focus_tint: DVec3::new(0.1, 0.5, 0.9),
                ..Default::default()
            });
            scene.lights.push(l);
        }
        let set = every_light(&scene);
        let mut lit = 0;
        for light in &set.lights {
            let b = light.base();
            for i in 0..64 {
                let p = DVec3::new(-3.0 + 0.1 * i as f64, 0.05 * i as f64 - 1.0, -1.0);
                let r = Reference::surface(p, DVec3::Z);
                let u = [(i % 8) as f64 / 8.0 + 0.06, (i / 8) as f64 / 8.0 + 0.02];
                let Some(s) = light.sample_li(&r, u, Strategy::Lux) else {
                    continue;
                };
                let want = b.radiance * b.shaping.factor_world(&b.xf, -s.wi);
                assert!(
                    (s.l - want).abs().max_element() <= 1e-12 * want.max_element(),
                    "{}: {} vs {want}",
                    b.path,
                    s.l
                );
                lit += usize::from(s.l != DVec3::ZERO);
            }
        }
        assert!(lit > 20, "{lit}");
        // the cone's edges in world space, from the disk's centre (its −Z axis is the world
        // direction L·(−Z))
        let disk = set.lights[0].base();
        let stretch =
            LightTransform::new(glam::DMat4::from_scale(DVec3::new(3.0, 1.0, 1.0))).unwrap();
        let mut base = disk.clone();
        base.xf = stretch;
        let at = |deg: f64, in_x: bool| {
            let (sn, c) = deg.to_radians().sin_cos();
            let w = if in_x {
                DVec3::new(sn, 0.0, -c)
            } else {
                DVec3::new(0.0, sn, -c)
            };
            base.emitted(w).max_element()
        };
        // atan(3·tan 40°) = 68.2° in XZ; 40° in YZ
        assert!(at(60.0, true) > 0.0 && at(69.0, true) == 0.0);
        assert!(at(30.0, false) > 0.0 && at(45.0, false) == 0.0);
    }

    #[test]
    fn quadratic_roots() {
        // (t − 1)(t − 3) = t² − 4t + 3: a = 1, b = −2, c = 3.
        assert_eq!(quadratic(1.0, -2.0, 3.0), Some((1.0, 3.0)));
        assert_eq!(quadratic(1.0, 0.0, 1.0), None);
        assert_eq!(quadratic(0.0, 1.0, 1.0), None);
        assert_eq!(quadratic(f64::NAN, 1.0, 1.0), None);
        // Tiny root without cancellation: t² − 2·1e8 t + 1 → 5e-9.
        let (t0, _) = quadratic(1.0, -1e8, 1.0).unwrap();
        assert!((t0 - 5e-9).abs() < 1e-22);
    }
}
