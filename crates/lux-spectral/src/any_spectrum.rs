//! `Spectrum`: the closed set of spectra a light can have (sampled table or black body).

use glam::DVec3;

use crate::colorspace::ColorSpace;
use crate::planck::Blackbody;
use crate::spectrum::SampledSpectrum;
use crate::xyz;

/// Any spectrum lux evaluates: a sampled table (custom illuminants, `wavelength:*` attributes,
/// CIE presets) or a band-limited black body. Values are spectral radiance in
/// W·sr⁻¹·m⁻²·nm⁻¹ for emitters (relative units are fine for colours).
#[derive(Debug, Clone, PartialEq)]
pub enum Spectrum {
    /// A sampled table.
    Sampled(SampledSpectrum),
    /// Planck's law on a band.
    Blackbody(Blackbody),
}

impl Spectrum {
    /// Value at `lambda_nm`, zero outside the spectrum's bounds.
    pub fn eval(&self, lambda_nm: f64) -> f64 {
        match self {
            Spectrum::Sampled(s) => s.eval(lambda_nm),
            Spectrum::Blackbody(b) => b.eval(lambda_nm),
        }
    }

    /// (first, last) wavelength, nm.
    pub fn bounds(&self) -> (f64, f64) {
        match self {
            Spectrum::Sampled(s) => s.bounds(),
            Spectrum::Blackbody(b) => b.bounds(),
        }
    }

    /// ∫ S(λ) dλ over its bounds (W·sr⁻¹·m⁻² for spectral radiance) — the "integrated over the
    /// domain of the light's illuminant spectrum" of `radiometric:power`.
    pub fn integral(&self) -> f64 {
        match self {
            Spectrum::Sampled(s) => s.integral(),
            Spectrum::Blackbody(b) => xyz::integrate_smooth(|l| b.eval(l), b.bounds()),
        }
    }

    /// Photometric tristimulus values 683·∫ S (x̄, ȳ, z̄) dλ; see [`xyz::spectrum_to_xyz`].
    pub fn to_xyz(&self) -> DVec3 {
        match self {
            Spectrum::Sampled(s) => xyz::spectrum_to_xyz(s),
            Spectrum::Blackbody(b) => xyz::blackbody_to_xyz(b),
        }
    }

    /// Luminance 683·∫ S ȳ dλ (nits for spectral radiance).
    pub fn luminance(&self) -> f64 {
        self.to_xyz().y
    }

    /// Linear RGB in `space` (same photometric scale: luminance of the RGB = [`Self::luminance`]).
    pub fn to_rgb(&self, space: ColorSpace) -> DVec3 {
        space.xyz_to_rgb(self.to_xyz())
    }

    /// Luminous efficacy of the spectrum, lm/W: 683·∫S ȳ dλ / ∫S dλ over its bounds.
    /// 0 when ∫S dλ is not positive.
    pub fn luminous_efficacy(&self) -> f64 {
        let e = self.integral();
        if e > 0.0 { self.luminance() / e } else { 0.0 }
    }
}
