//! DomeLight (UsdLux `DomeLight`, `DomeLight_1`): light from infinitely far away in every
//! direction, optionally a latlong texture (`inputs:texture:file`, spec §2 orientation,
//! `poleAxis`).

use super::{LiSample, LightBase, LightHit, LightTexture, Seen};
use glam::{DMat4, DVec3};
use lux_sample::{DomeTechnique, LatLongMap, LightBounds, Reference, Strategy};
use lux_usd::{Light as UsdLight, PoleAxis, Scene, UpAxis};

/// A dome light: its texture and sampler (the texture's luminance × sin θ, or uniform).
#[derive(Clone, Debug)]
pub struct DomeLight {
    /// What every light carries.
    pub base: LightBase,
    texture: Option<LightTexture>,
    sampler: lux_sample::DomeLight,
}

/// The dome's latlong frame: its light-to-world transform, turned +90° about X when the pole
/// axis is Z (`poleAxis = "Z"`, or `"scene"` on a Z-up stage), spec §2.
pub(super) fn dome_transform(scene: &Scene, l: &UsdLight) -> DMat4 {
    let z_up = match l.pole_axis {
        PoleAxis::Z => true,
        PoleAxis::Y => false,
        PoleAxis::Scene => scene.up_axis == UpAxis::Z,
    };
    if z_up {
        l.light_to_world * DMat4::from_rotation_x(std::f64::consts::FRAC_PI_2)
    } else {
        l.light_to_world
    }
}

impl DomeLight {
    /// A dome sampled in proportion to its texture's luminance (lux) or uniformly over the
    /// receiver's hemisphere (hdEmbree); uniform over the sphere without a texture. `Err` when
    /// the texture cannot be sampled (negative or non-finite texels, too large).
    pub(super) fn new(base: LightBase, texture: Option<LightTexture>) -> Result<DomeLight, String> {
        let sampler = match &texture {
            Some(t) => {
                let (w, h) = (t.tex.width(), t.tex.height());
                let lum: Vec<f32> = t
                    .tex
                    .texels_iter()
                    .map(|p| {
                        lux_math::luminance(DVec3::new(p[0] as f64, p[1] as f64, p[2] as f64))
                            .max(0.0) as f32
                    })
                    .collect();
                LatLongMap::new(w, h, lum)
                    .and_then(|map| {
                        lux_sample::DomeLight::new(&map, base.xf, DomeTechnique::Texture)
                    })
                    .map_err(|e| format!("dome texture unusable ({e})"))?
            }
            None => lux_sample::DomeLight::uniform(base.xf),
        };
        Ok(DomeLight {
            base,
            texture,
            sampler,
        })
    }

    /// See [`super::Light::sample_li`].
    #[inline]
    pub fn sample_li(&self, r: &Reference, u: [f64; 2], strategy: Strategy) -> Option<LiSample> {
        let s = self.sampler.sample_with(r, u, strategy)?;
        Some(LiSample::new(s, self.le_escape(s.wi)))
    }

    /// See [`super::Light::pdf_li`].
    #[inline]
    pub fn pdf_li(&self, r: &Reference, wi: DVec3) -> f64 {
        self.sampler.pdf(r, wi)
    }

    /// Radiance arriving along the world direction `wi`: `base · texture(latlong(L⁻¹·wi))`.
    #[inline]
    pub fn le_escape(&self, wi: DVec3) -> DVec3 {
        let Some(t) = &self.texture else {
            return self.base.radiance;
        };
        let d = self.base.xf.inv_vector(wi).normalize_or_zero();
        if d == DVec3::ZERO {
            return DVec3::ZERO;
        }
        let uv = lux_sample::latlong_uv(d);
        self.base.radiance * t.rgb(uv[0], uv[1])
    }

    /// See [`super::Light::uniform_area`]: not one of its kinds.
    #[inline]
    pub fn uniform_area(&self) -> bool {
        false
    }

    /// At infinity: no surface point emits.
    #[inline]
    pub fn le(&self, _local: DVec3, _emit: DVec3, _seen: Seen) -> DVec3 {
        DVec3::ZERO
    }

    /// No analytic surface: found by rays only through `le_escape` when they escape.
    #[inline]
    pub fn intersect(&self, _o: DVec3, _d: DVec3, _tmin: f64, _tmax: f64) -> Option<LightHit> {
        None
    }

    /// No analytic surface.
    pub fn surface_box(&self) -> Option<(DVec3, DVec3)> {
        None
    }

    /// At infinity: no bounds.
    pub fn bounds(&self) -> Option<LightBounds> {
        None
    }

    /// Power estimate for selection: `Y(base) · mean texture luminance · π`.
    pub(super) fn power(&self, _area: f64) -> f64 {
        let mean_tex = self.texture.as_ref().map_or(1.0, |t| {
            let a = t.tex.average();
            lux_math::luminance(DVec3::new(a[0], a[1], a[2]))
        });
        lux_math::luminance(self.base.radiance).max(0.0) * mean_tex * std::f64::consts::PI
    }
}
