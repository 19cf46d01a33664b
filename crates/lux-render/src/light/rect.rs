//! RectLight (UsdLux `RectLight`): a `inputs:width × inputs:height` rectangle in local XY,
//! centred, emitting from its −Z side, optionally textured (`inputs:texture:file`).

use super::{
    LiSample, LightBase, LightHit, LightTexture, Seen, box_of, planar_emission_half_angle,
};
use glam::DVec3;
use lux_sample::{LightBounds, Reference, Strategy};

/// A rect light: its half extents, texture and sampler.
#[derive(Clone, Debug)]
pub struct RectLight {
    /// What every light carries.
    pub base: LightBase,
    /// Half width (local X) and half height (local Y).
    half: [f64; 2],
    texture: Option<LightTexture>,
    /// The `HdEmbree` profile's mirrored texture u on the lit path.
    mirror_u: bool,
    /// lux-sample's sampler of the shape ([`super::Light::seen_from`] reads it).
    pub(super) sampler: lux_sample::RectLight,
    /// World corners and a sphere holding them ([`RectLight::world_corners`],
    /// [`RectLight::bounding_sphere`]).
    corners: [DVec3; 4],
    bound: (DVec3, f64),
    /// For a rect of uniform radiance (no texture, identity shaping): its world normal on the
    /// local +Z side, `L⁻ᵀ ẑ`, so that a light sample's radiance is the light's own wherever
    /// `emit · n < 0` (the −Z side [`RectLight::le`] tests as `(L⁻¹ emit).z < 0`), without the
    /// light-space point and direction.
    uniform_side: Option<DVec3>,
}

impl RectLight {
    /// A `width × height` rect (both > 0) sampled by spherical rectangle with the bilinear cosine
    /// warp (lux; only inside the shaping's emission cone) or by area
    /// (hdEmbree); `Err` names what lux-sample refused.
    pub(super) fn new(
        base: LightBase,
        width: f64,
        height: f64,
        texture: Option<LightTexture>,
        mirror_u: bool,
        cone_clipping: bool,
    ) -> Result<RectLight, String> {
        let cut = if cone_clipping {
            base.shaping.emission_half_angle()
        } else {
            std::f64::consts::PI
        };
        let sampler = lux_sample::RectLight::new(
            width,
            height,
            base.xf,
            lux_sample::RectTechnique::SphericalRectangleCosine,
        )
        .map_err(|e| e.to_string())?
        // only the part of the rect inside the shaping's emission cone
        .with_emission_cone(cut);
        let corners = sampler.corners();
        let centre = base.xf.point(DVec3::ZERO);
        let radius = corners
            .iter()
            .map(|q| q.distance(centre))
            .fold(0.0, f64::max);
        let uniform_side =
            (texture.is_none() && base.shaping.is_identity()).then(|| base.xf.normal(DVec3::Z));
        Ok(RectLight {
            uniform_side,
            base,
            half: [0.5 * width, 0.5 * height],
            texture,
            mirror_u,
            sampler,
            corners,
            bound: (centre, radius),
        })
    }

    /// The world corners, in order around the rect: local (±w/2, ±h/2, 0) for UsdLux
    /// `inputs:width` w and `inputs:height` h, placed by the light's transform (a parallelogram
    /// under any affine one; [`lux_sample::RectLight::corners`], kept per light).
    #[inline]
    pub fn world_corners(&self) -> [DVec3; 4] {
        self.corners
    }

    /// A ball holding the rect: its centre (the light's origin) and the farthest world corner's
    /// distance from it.
    #[inline]
    pub fn bounding_sphere(&self) -> (DVec3, f64) {
        self.bound
    }

    /// See [`super::Light::sample_li`].
    #[inline]
    pub fn sample_li(&self, r: &Reference, u: [f64; 2], strategy: Strategy) -> Option<LiSample> {
        self.sampler
            .seen_from(r, strategy, |from| self.sample_li_from(from, u))
    }

    /// [`Self::sample_li`] from the receiver `from` was made for.
    #[inline(always)]
    pub fn sample_li_from(&self, from: &lux_sample::RectFrom, u: [f64; 2]) -> Option<LiSample> {
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

    /// Radiance from the local point `local` along the world direction `emit`: zero unless
    /// `emit` leaves the −Z side; the texture at `u = ½ − x/w` (schema orientation; `½ + x/w`
    /// on the lit path of the `HdEmbree` profile), `v = ½ − y/h` (top row at +Y).
    #[inline]
    pub fn le(&self, local: DVec3, emit: DVec3, seen: Seen) -> DVec3 {
        let Some(wl) = self.base.local_direction(emit) else {
            return DVec3::ZERO;
        };
        if wl.z >= 0.0 {
            return DVec3::ZERO;
        }
        let mut l = self.base.shaped(wl);
        if let Some(t) = &self.texture {
            let [hw, hh] = self.half;
            let x = 0.5 * local.x / hw;
            let u = if seen == Seen::Lit && self.mirror_u {
                0.5 + x
            } else {
                0.5 - x
            };
            let v = 0.5 - 0.5 * local.y / hh;
            l *= t.rgb(u, v);
        }
        l
    }

    /// A finite light: nothing arrives from infinity.
    #[inline]
    pub fn le_escape(&self, _wi: DVec3) -> DVec3 {
        DVec3::ZERO
    }

    /// See [`super::Light::uniform_area`].
    #[inline]
    pub fn uniform_area(&self) -> bool {
        self.texture.is_none() && self.base.shaping.is_identity()
    }

    /// See [`super::Light::intersect`]: the plane z = 0 within the half extents.
    #[inline]
    pub fn intersect(&self, o: DVec3, d: DVec3, tmin: f64, tmax: f64) -> Option<LightHit> {
        let ol = self.base.xf.inv_point(o);
        let dl = self.base.xf.inv_vector(d);
        let t = -ol.z / dl.z;
        if !(t > tmin && t < tmax) {
            return None;
        }
        let q = ol + t * dl;
        let [hw, hh] = self.half;
        (q.x.abs() <= hw && q.y.abs() <= hh).then_some(LightHit {
            t,
            local: DVec3::new(q.x, q.y, 0.0),
            front: dl.z > 0.0,
        })
    }

    /// World box of the four corners.
    pub fn surface_box(&self) -> Option<(DVec3, DVec3)> {
        Some(self.world_box())
    }

    fn world_box(&self) -> (DVec3, DVec3) {
        let [hw, hh] = self.half;
        box_of(
            &self.base.xf,
            [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
                .map(|(a, b)| DVec3::new(a * hw, b * hh, 0.0)),
        )
    }

    /// See [`super::Light::bounds`]: one-sided, normal −Z, emission narrowed by the shaping.
    pub fn bounds(&self) -> Option<LightBounds> {
        let theta_e = planar_emission_half_angle(&self.base);
        self.base.bounds(self.world_box(), 0.0, theta_e, false)
    }

    /// Power estimate: `Y(base) · mean texture · area · G`, G = ∫ shaping · cos over the
    /// hemisphere (π unshaped).
    pub(super) fn power(&self, area: f64) -> f64 {
        let mean_tex = self.texture.as_ref().map_or(1.0, |t| {
            let a = t.tex.average();
            lux_math::luminance(DVec3::new(a[0], a[1], a[2]))
        });
        let g = lux_math::luminance(self.base.shaping.integral_cos_hemisphere()).max(0.0);
        lux_math::luminance(self.base.radiance).max(0.0) * mean_tex * area * g
    }
}
