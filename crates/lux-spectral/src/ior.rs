//! Spectral index of refraction (`wavelength:ior`, `iorInterpolation`, scalar `ior` fallback).

use crate::error::SpectralError;
use crate::sellmeier::Sellmeier;
use crate::spectrum::SampledSpectrum;

/// The wavelength used for a scalar `ior` when no `wavelength:ior` is authored (550 nm, per the
/// LTESpectralAPI).
pub const SCALAR_IOR_WAVELENGTH_NM: f64 = 550.0;

/// `iorInterpolation` metadata of `wavelength:ior` (default `"linear"`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Hash)]
pub enum IorInterpolation {
    /// `"linear"`.
    #[default]
    Linear,
    /// `"held"`.
    Held,
    /// `"cubic"` (monotone cubic Hermite, see [`crate::Interpolation::Cubic`]).
    Cubic,
    /// `"sellmeier"`: the pairs are Sellmeier (B, C µm²) coefficients.
    Sellmeier,
}

impl IorInterpolation {
    /// Parse `"linear"`, `"held"`, `"cubic"` or `"sellmeier"`.
    pub fn parse(token: &str) -> Result<Self, SpectralError> {
        match token {
            "linear" => Ok(IorInterpolation::Linear),
            "held" => Ok(IorInterpolation::Held),
            "cubic" => Ok(IorInterpolation::Cubic),
            "sellmeier" => Ok(IorInterpolation::Sellmeier),
            _ => Err(SpectralError::UnknownToken {
                attribute: "iorInterpolation".to_owned(),
                value: token.to_owned(),
                expected: "\"linear\", \"held\", \"cubic\", \"sellmeier\"",
            }),
        }
    }
}

/// A resolved spectral IOR.
#[derive(Debug, Clone, PartialEq)]
pub enum Ior {
    /// A scalar `ior` (meaning its value at 550 nm), used at every wavelength; also a
    /// single-pair `wavelength:ior` table.
    Constant(f64),
    /// A (wavelength, n) table; outside its range the end values hold (an IOR of zero would be
    /// meaningless, unlike emission).
    Tabulated(SampledSpectrum),
    /// Sellmeier coefficients.
    Sellmeier(Sellmeier),
}

impl Ior {
    /// n(λ) at `lambda_nm`. Errors only for Sellmeier outside its domain (n² ≤ 0 or a pole).
    pub fn eval(&self, lambda_nm: f64) -> Result<f64, SpectralError> {
        match self {
            Ior::Constant(n) => Ok(*n),
            Ior::Tabulated(s) => {
                let (lo, hi) = s.bounds();
                let l = if lambda_nm.is_nan() {
                    lo
                } else {
                    lambda_nm.clamp(lo, hi)
                };
                Ok(s.eval(l))
            }
            Ior::Sellmeier(s) => s.ior(lambda_nm),
        }
    }
}
