//! LTESpectralAPI inputs: `wavelength:emission`, `wavelength:reflectance`, `wavelength:ior`.

use glam::DVec3;

use crate::any_spectrum::Spectrum;
use crate::colorspace::ColorSpace;
use crate::error::{SpectralError, SpectrumError};
use crate::illuminant::Illuminant;
use crate::interpolation::Interpolation;
use crate::ior::{Ior, IorInterpolation};
use crate::sellmeier::Sellmeier;
use crate::spectrum::SampledSpectrum;
use crate::wavelength::WavelengthUnit;

/// One authored `float2[] wavelength:*` attribute with its metadata.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct SpectralAttribute {
    /// The (wavelength, value) pairs as authored.
    pub values: Vec<[f32; 2]>,
    /// Per-attribute `unitForWavelength` metadata; `None` = the stage's.
    pub unit_for_wavelength: Option<WavelengthUnit>,
    /// `emissionInterpolation` (emission) / interpolation of reflectance (default linear).
    pub interpolation: Interpolation,
    /// `illuminantPreset` metadata (emission only).
    pub illuminant_preset: Option<Illuminant>,
}

/// The `wavelength:ior` attribute with its metadata.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct IorAttribute {
    /// The pairs: (wavelength, n), or (B, C µm²) for Sellmeier.
    pub values: Vec<[f32; 2]>,
    /// Per-attribute `unitForWavelength`; `None` = the stage's (ignored for Sellmeier).
    pub unit_for_wavelength: Option<WavelengthUnit>,
    /// `iorInterpolation` (default linear).
    pub interpolation: IorInterpolation,
}

/// All LTESpectralAPI inputs of one prim, as the USD loader reads them.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct SpectralInputs {
    /// Stage/layer `unitForWavelength` (default nanometres).
    pub unit_for_wavelength: WavelengthUnit,
    /// `wavelength:emission` — spectral radiance W·m⁻²·nm⁻¹ (per µm in micrometre units).
    pub emission: Option<SpectralAttribute>,
    /// `wavelength:reflectance` — values in [0, 1].
    pub reflectance: Option<SpectralAttribute>,
    /// `wavelength:ior`.
    pub ior: Option<IorAttribute>,
    /// The scalar `ior` input, used as the IOR at 550 nm when `wavelength:ior` is absent.
    pub scalar_ior: Option<f64>,
}

impl SpectralInputs {
    /// The emission spectrum in W·m⁻²·nm⁻¹ per nm: explicit values win over `illuminantPreset`;
    /// empty values take the preset's table; empty without a preset is an error. Micrometre
    /// tables are rescaled (λ×1000, values ×10⁻³). Values must be ≥ 0.
    pub fn emission_spectrum(&self) -> Result<Option<SampledSpectrum>, SpectralError> {
        const ATTR: &str = "wavelength:emission";
        let Some(a) = &self.emission else {
            return Ok(None);
        };
        if a.values.is_empty() {
            return match a.illuminant_preset {
                Some(p) => Ok(Some(p.spectrum())),
                None => Err(SpectralError::EmptyWithoutPreset {
                    attribute: ATTR.to_owned(),
                }),
            };
        }
        let unit = a.unit_for_wavelength.unwrap_or(self.unit_for_wavelength);
        let s =
            SampledSpectrum::from_pairs(&a.values, unit, unit.density_to_per_nm(), a.interpolation)
                .map_err(|e| SpectralError::spectrum(ATTR, e))?;
        check_range(&s, 0.0, f64::INFINITY, "spectral radiance ≥ 0")
            .map_err(|e| SpectralError::spectrum(ATTR, e))?;
        Ok(Some(s))
    }

    /// The reflectance spectrum (values in [0, 1]).
    pub fn reflectance_spectrum(&self) -> Result<Option<SampledSpectrum>, SpectralError> {
        const ATTR: &str = "wavelength:reflectance";
        let Some(a) = &self.reflectance else {
            return Ok(None);
        };
        let unit = a.unit_for_wavelength.unwrap_or(self.unit_for_wavelength);
        let s = SampledSpectrum::from_pairs(&a.values, unit, 1.0, a.interpolation)
            .map_err(|e| SpectralError::spectrum(ATTR, e))?;
        check_range(&s, 0.0, 1.0, "a reflectance in [0, 1]")
            .map_err(|e| SpectralError::spectrum(ATTR, e))?;
        Ok(Some(s))
    }

    /// The IOR: `wavelength:ior` (tabulated, one pair → constant, or Sellmeier), else the scalar
    /// `ior` as a constant (its value at 550 nm), else `None`. Tabulated n must be > 0.
    pub fn ior(&self) -> Result<Option<Ior>, SpectralError> {
        const ATTR: &str = "wavelength:ior";
        let Some(a) = &self.ior else {
            return match self.scalar_ior {
                Some(n) if n.is_finite() && n > 0.0 => Ok(Some(Ior::Constant(n))),
                Some(n) => Err(SpectralError::InvalidValue {
                    attribute: "ior".to_owned(),
                    value: n,
                    expected: "a finite IOR > 0",
                }),
                None => Ok(None),
            };
        };
        let interp = match a.interpolation {
            IorInterpolation::Sellmeier => {
                return Ok(Some(Ior::Sellmeier(Sellmeier::from_pairs(&a.values)?)));
            }
            IorInterpolation::Linear => Interpolation::Linear,
            IorInterpolation::Held => Interpolation::Held,
            IorInterpolation::Cubic => Interpolation::Cubic,
        };
        if a.values.len() == 1 {
            let n = f64::from(a.values[0][1]);
            if !(n.is_finite() && n > 0.0) {
                return Err(SpectralError::spectrum(
                    ATTR,
                    SpectrumError::ValueTooSmall {
                        index: 0,
                        value: n,
                        min: 0.0,
                        expected: "a finite IOR > 0",
                    },
                ));
            }
            return Ok(Some(Ior::Constant(n)));
        }
        let unit = a.unit_for_wavelength.unwrap_or(self.unit_for_wavelength);
        let s = SampledSpectrum::from_pairs(&a.values, unit, 1.0, interp)
            .map_err(|e| SpectralError::spectrum(ATTR, e))?;
        if let Some(index) = s.values().iter().position(|&v| v <= 0.0) {
            return Err(SpectralError::spectrum(
                ATTR,
                SpectrumError::ValueTooSmall {
                    index,
                    value: s.values()[index],
                    min: 0.0,
                    expected: "an IOR > 0",
                },
            ));
        }
        Ok(Some(Ior::Tabulated(s)))
    }

    /// Linear RGB of 1 nit of the emission spectrum (rgb / luminance), the colour a renderer
    /// multiplies `intensity` by; `None` without `wavelength:emission`.
    pub fn emission_rgb_per_nit(&self, space: ColorSpace) -> Result<Option<DVec3>, SpectralError> {
        let Some(s) = self.emission_spectrum()? else {
            return Ok(None);
        };
        let xyz = crate::xyz::spectrum_to_xyz(&s);
        if xyz.y.is_nan() || xyz.y <= 0.0 {
            return Err(SpectralError::ZeroLuminance {
                attribute: "wavelength:emission".to_owned(),
            });
        }
        Ok(Some(space.xyz_to_rgb(xyz) / xyz.y))
    }

    /// Linear RGB albedo of the reflectance spectrum lit by the colour space's white (D65 for
    /// both spaces; see [`crate::resolve_illuminant`]): rgb(R·W) / Y(W). A constant reflectance ρ
    /// gives ≈ (ρ, ρ, ρ) in Rec.709.
    pub fn reflectance_rgb(&self, space: ColorSpace) -> Result<Option<DVec3>, SpectralError> {
        let Some(r) = self.reflectance_spectrum()? else {
            return Ok(None);
        };
        let w = Illuminant::D65.spectrum();
        let white_y = Spectrum::Sampled(w.clone()).luminance();
        let xyz = crate::xyz::integrate_smooth_against_cmf(
            |l| r.eval(l) * w.eval(l),
            r.bounds().0,
            r.bounds().1,
        ) * crate::photometry::K_M;
        Ok(Some(space.xyz_to_rgb(xyz) / white_y))
    }
}

fn check_range(
    s: &SampledSpectrum,
    min: f64,
    max: f64,
    expected: &'static str,
) -> Result<(), SpectrumError> {
    for (index, &value) in s.values().iter().enumerate() {
        if value < min {
            return Err(SpectrumError::ValueTooSmall {
                index,
                value,
                min,
                expected,
            });
        }
        if value > max {
            return Err(SpectrumError::ValueTooLarge {
                index,
                value,
                max,
                expected,
            });
        }
    }
    Ok(())
}
