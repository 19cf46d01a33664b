//! `unitForWavelength` (LTESpectralAPI stage/layer and attribute metadata).

use crate::error::SpectralError;

/// Unit of the wavelengths of a spectral attribute: the LTESpectralAPI `unitForWavelength`
/// metadata (stage/layer default `"nanometers"`, overridable per attribute).
///
/// Emission values are spectral densities, so a micrometre table also rescales its values:
/// W·m⁻²·µm⁻¹ = 10⁻³ W·m⁻²·nm⁻¹ (see [`WavelengthUnit::density_to_per_nm`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Hash)]
pub enum WavelengthUnit {
    /// `"nanometers"` (the default).
    #[default]
    Nanometers,
    /// `"micrometers"`.
    Micrometers,
}

impl WavelengthUnit {
    /// Parse the metadata token (`"nanometers"` / `"micrometers"`; `"nm"` / `"um"` / `"µm"` are
    /// accepted as aliases).
    pub fn parse(token: &str) -> Result<Self, SpectralError> {
        match token {
            "nanometers" | "nanometres" | "nm" => Ok(WavelengthUnit::Nanometers),
            "micrometers" | "micrometres" | "um" | "µm" => Ok(WavelengthUnit::Micrometers),
            _ => Err(SpectralError::UnknownToken {
                attribute: "unitForWavelength".to_owned(),
                value: token.to_owned(),
                expected: "\"nanometers\", \"micrometers\"",
            }),
        }
    }

    /// Factor converting a wavelength in this unit to nanometres (1 or 1000).
    pub fn to_nm(self) -> f64 {
        match self {
            WavelengthUnit::Nanometers => 1.0,
            WavelengthUnit::Micrometers => 1000.0,
        }
    }

    /// Factor converting a spectral density "per this unit" to "per nanometre" (1 or 10⁻³).
    pub fn density_to_per_nm(self) -> f64 {
        1.0 / self.to_nm()
    }
}
