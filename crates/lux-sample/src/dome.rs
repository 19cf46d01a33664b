//! DomeLight (UsdLux `DomeLight` with `inputs:texture:file` in latlong layout): importance
//! sampling of the texture, its MIS-compensated variant, or a uniform sphere without texture.

use crate::distribution::Distribution2D;
use crate::error::{MAX_ENTRIES, SampleError};
use crate::transform::LightTransform;
use crate::warp::{sample_uniform_hemisphere, sample_uniform_sphere};
use crate::{LightSample, Reference, Strategy};
use core::f64::consts::{FRAC_1_PI, PI};
use glam::DVec3;
use lux_math::{Frame, latlong_direction, latlong_uv};

/// A latlong luminance map, row-major, row 0 at the top (+Y), per spec §2 / OpenEXR latlong:
/// the centre column looks along +Z, u = 0.25 along +X, longitude runs from +π at u = 0 to −π at
/// u = 1 (the convention of [`lux_math::latlong_direction`], defined there). The renderer
/// passes a scalar importance per texel (e.g. Rec.709 luminance of RGB).
#[derive(Clone, Debug)]
pub struct LatLongMap {
    width: usize,
    height: usize,
    texels: Vec<f32>,
}

impl LatLongMap {
    /// Validates `texels.len() = width·height`, both ≥ 1, at most [`MAX_ENTRIES`] texels, every
    /// value finite and ≥ 0.
    pub fn new(width: usize, height: usize, texels: Vec<f32>) -> Result<Self, SampleError> {
        let n = width
            .checked_mul(height)
            .filter(|&n| n > 0 && n <= MAX_ENTRIES);
        if n != Some(texels.len()) {
            return Err(SampleError::BadSize {
                field: "texels",
                expected: format!("width·height = {width}·{height} (≥ 1, ≤ {MAX_ENTRIES})"),
                got: texels.len(),
            });
        }
        for (index, &v) in texels.iter().enumerate() {
            if !(v.is_finite() && v >= 0.0) {
                return Err(SampleError::BadWeight {
                    field: "texels",
                    index,
                    value: v as f64,
                });
            }
        }
        Ok(Self {
            width,
            height,
            texels,
        })
    }

    /// Width in texels.
    pub fn width(&self) -> usize {
        self.width
    }

    /// Height in texels.
    pub fn height(&self) -> usize {
        self.height
    }

    /// Nearest texel at (u, v) ∈ \[0,1\]² (hdEmbree looks textures up nearest-texel), widened
    /// from the stored `f32`.
    #[inline]
    pub fn texel(&self, uv: [f64; 2]) -> f64 {
        let x = ((uv[0] * self.width as f64) as usize).min(self.width - 1);
        let y = ((uv[1] * self.height as f64) as usize).min(self.height - 1);
        f64::from(self.texels[y * self.width + x])
    }
}

/// How the dome's directions are chosen.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum DomeTechnique {
    /// Proportional to texel value × sin θ (the latlong Jacobian): piecewise-constant 2D.
    #[default]
    Texture,
    /// MIS-compensated (Karlík, Šik, Vévoda, Skřivan, Křivánek 2019): proportional to
    /// max(0, f − mean f) so that BSDF sampling takes over the flat part; falls back to
    /// `Texture` for a constant map.
    MisCompensated,
}

/// UsdLux `DomeLight` prepared for sampling (spec §2): light from infinitely far away in every
/// direction, its `inputs:texture:file` a latlong map (+Y up, +Z at the centre column,
/// [`crate::latlong_direction`]) oriented by its [`LightTransform`]. Without a texture,
/// uniform over the sphere (density `1/(4π)`); with one, proportional to texel × sin θ (density
/// `p(u, v) / (2π² sin θ)` per unit solid angle).
#[derive(Clone, Debug)]
pub struct DomeLight {
    xf: LightTransform,
    dist: Option<Distribution2D>,
}

impl DomeLight {
    /// A dome without texture (uniform sphere sampling, density `1/(4π)`) oriented by `xf`.
    pub fn uniform(xf: LightTransform) -> Self {
        Self { xf, dist: None }
    }

    /// A textured dome. The table is the texel values times sin θ at the row centre, so that
    /// the 2D density converts to solid angle as p(ω) = p(u,v)/(2π² sin θ).
    pub fn new(
        map: &LatLongMap,
        xf: LightTransform,
        technique: DomeTechnique,
    ) -> Result<Self, SampleError> {
        let (w, h) = (map.width, map.height);
        let mut f: Vec<f64> = map.texels.iter().map(|&t| t as f64).collect();
        if technique == DomeTechnique::MisCompensated {
            // Mean over the sphere (texel solid angle ∝ sin θ).
            let mut num = 0.0;
            let mut den = 0.0;
            for (y, row) in f.chunks_exact(w).enumerate() {
                let s = (PI * (y as f64 + 0.5) / h as f64).sin();
                num += s * row.iter().sum::<f64>();
                den += s * w as f64;
            }
            let mean = num / den;
            if f.iter().any(|&v| v > mean * (1.0 + 1e-12)) {
                for v in f.iter_mut() {
                    *v = (*v - mean).max(0.0);
                }
            }
        }
        for (y, row) in f.chunks_exact_mut(w).enumerate() {
            let s = (PI * (y as f64 + 0.5) / h as f64).sin();
            for v in row {
                *v *= s;
            }
        }
        let dist = Distribution2D::new(&f, w, h)?;
        if dist.integral() == 0.0 {
            return Ok(Self::uniform(xf));
        }
        Ok(Self {
            xf,
            dist: Some(dist),
        })
    }

    /// Samples a direction (world); the reference position does not matter.
    #[inline]
    pub fn sample(&self, _r: &Reference, u: [f64; 2]) -> Option<LightSample> {
        let (dl, pdf_local) = match &self.dist {
            None => (sample_uniform_sphere(u), 0.25 * FRAC_1_PI),
            Some(d) => {
                let (uv, p) = d.sample_alias(u);
                let st = (PI * uv[1]).sin();
                if !(p > 0.0 && st > 0.0) {
                    return None;
                }
                (latlong_direction(uv), p / (2.0 * PI * PI * st))
            }
        };
        let wi = self.xf.vector(dl).normalize();
        let pdf = pdf_local * self.xf.pdf_to_world(dl);
        Some(LightSample {
            point: wi,
            normal: -wi,
            wi,
            distance: f64::INFINITY,
            pdf,
            delta: false,
        })
    }

    /// [`Self::sample`] with the techniques of `strategy`. `HdEmbree`: uniform over the
    /// hemisphere around the receiver normal `r.n`, density 1/(2π), whatever the texture (the
    /// reference renderer's dome sampling); uniform over the sphere (through the dome's
    /// transform, as [`Self::uniform`]) when `r` has no normal.
    #[inline]
    pub fn sample_with(
        &self,
        r: &Reference,
        u: [f64; 2],
        strategy: Strategy,
    ) -> Option<LightSample> {
        match strategy {
            Strategy::Lux => self.sample(r, u),
            Strategy::HdEmbree if r.n == DVec3::ZERO => self.sample_uniform(u),
            Strategy::HdEmbree => {
                let w = Frame::from_normal(r.n).to_world(sample_uniform_hemisphere(u));
                Some(LightSample {
                    point: w,
                    normal: -w,
                    wi: w,
                    distance: f64::INFINITY,
                    pdf: 0.5 * FRAC_1_PI,
                    delta: false,
                })
            }
        }
    }

    /// Uniform sphere sampling through the dome's transform.
    #[inline]
    fn sample_uniform(&self, u: [f64; 2]) -> Option<LightSample> {
        let dl = sample_uniform_sphere(u);
        let wi = self.xf.vector(dl).normalize();
        Some(LightSample {
            point: wi,
            normal: -wi,
            wi,
            distance: f64::INFINITY,
            pdf: 0.25 * FRAC_1_PI * self.xf.pdf_to_world(dl),
            delta: false,
        })
    }

    /// [`Self::pdf`] of the techniques of `strategy` (`HdEmbree`: 1/(2π) above the receiver's
    /// tangent plane, 0 below; the uniform sphere's density without a normal).
    #[inline]
    pub fn pdf_with(&self, r: &Reference, wi: DVec3, strategy: Strategy) -> f64 {
        match strategy {
            Strategy::Lux => self.pdf(r, wi),
            Strategy::HdEmbree if r.n == DVec3::ZERO => {
                match crate::transform::local_direction(&self.xf, wi) {
                    Some((_, jac)) => 0.25 * FRAC_1_PI * jac,
                    None => 0.0,
                }
            }
            Strategy::HdEmbree => {
                if r.n.dot(wi) > 0.0 {
                    0.5 * FRAC_1_PI
                } else {
                    0.0
                }
            }
        }
    }

    /// Solid-angle density of direction `wi` (world).
    #[inline]
    pub fn pdf(&self, _r: &Reference, wi: DVec3) -> f64 {
        let Some((dl, jac)) = crate::transform::local_direction(&self.xf, wi) else {
            return 0.0;
        };
        let p = match &self.dist {
            None => 0.25 * FRAC_1_PI,
            Some(d) => {
                let uv = latlong_uv(dl);
                let st = (PI * uv[1]).sin();
                if st <= 0.0 {
                    return 0.0;
                }
                d.pdf(uv) / (2.0 * PI * PI * st)
            }
        };
        p * jac
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rejects_bad_maps() {
        assert!(LatLongMap::new(2, 2, vec![1.0; 3]).is_err());
        assert!(LatLongMap::new(0, 2, vec![]).is_err());
        assert!(LatLongMap::new(usize::MAX, 2, vec![]).is_err());
        assert!(matches!(
            LatLongMap::new(2, 1, vec![1.0, -2.0]),
            Err(SampleError::BadWeight { index: 1, .. })
        ));
    }
}
