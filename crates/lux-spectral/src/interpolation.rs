//! Interpolation of sampled spectra (`emissionInterpolation`, `iorInterpolation`).

use crate::error::SpectralError;

/// How a sampled spectrum is evaluated between its samples: the LTESpectralAPI
/// `emissionInterpolation` / `iorInterpolation` metadata (default `"linear"`). The
/// `"sellmeier"` IOR mode is not an interpolation and lives in [`crate::Ior`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Hash)]
pub enum Interpolation {
    /// `"linear"`: piecewise linear between samples.
    #[default]
    Linear,
    /// `"held"`: USD held interpolation, a step function; the value of sample i holds on
    /// [λᵢ, λᵢ₊₁) and the last sample's value at its own wavelength only.
    Held,
    /// `"cubic"`: piecewise cubic Hermite with Fritsch–Carlson monotone tangents (PCHIP). It is
    /// C¹, passes through every sample and never overshoots, so non-negative data stays
    /// non-negative.
    Cubic,
}

impl Interpolation {
    /// Parse the metadata token `"linear"`, `"held"` or `"cubic"`; `attribute` names the metadata
    /// key for the error.
    pub fn parse(token: &str, attribute: &str) -> Result<Self, SpectralError> {
        match token {
            "linear" => Ok(Interpolation::Linear),
            "held" => Ok(Interpolation::Held),
            "cubic" => Ok(Interpolation::Cubic),
            _ => Err(SpectralError::UnknownToken {
                attribute: attribute.to_owned(),
                value: token.to_owned(),
                expected: "\"linear\", \"held\", \"cubic\"",
            }),
        }
    }
}
