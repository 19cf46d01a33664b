//! Planck's law: the spectral radiance of a black body.

use crate::error::SpectralError;

/// Planck constant h, J·s (exact, SI 2019).
pub const PLANCK_H: f64 = 6.626_070_15e-34;
/// Speed of light in vacuum c, m/s (exact).
pub const SPEED_OF_LIGHT: f64 = 299_792_458.0;
/// Boltzmann constant k_B, J/K (exact, SI 2019).
pub const BOLTZMANN_K: f64 = 1.380_649e-23;
/// Second radiation constant c₂ = h·c/k_B ≈ 1.438777 × 10⁻² m·K.
pub const C2: f64 = PLANCK_H * SPEED_OF_LIGHT / BOLTZMANN_K;
/// First radiation constant for spectral radiance c₁L = 2·h·c² ≈ 1.191043 × 10⁻¹⁶ W·m²·sr⁻¹.
pub const C1L: f64 = 2.0 * PLANCK_H * SPEED_OF_LIGHT * SPEED_OF_LIGHT;

/// Planck's law for spectral radiance per nanometre:
/// `L(λ, T) = c₁L / λ⁵ / (exp(c₂ / (λ T)) − 1)`, λ in metres, result converted to
/// W·sr⁻¹·m⁻²·nm⁻¹ (×10⁻⁹).
///
/// Documented finite result for bad input: 0 when λ or T is not a finite positive number
/// (and when exp overflows, where the true value underflows to 0 anyway).
pub fn planck_radiance(lambda_nm: f64, temperature_k: f64) -> f64 {
    if !(lambda_nm.is_finite()
        && lambda_nm > 0.0
        && temperature_k.is_finite()
        && temperature_k > 0.0)
    {
        return 0.0;
    }
    let lambda_m = lambda_nm * 1e-9;
    let x = C2 / (lambda_m * temperature_k);
    let denom = x.exp_m1();
    if !denom.is_finite() {
        return 0.0;
    }
    let l5 = lambda_m * lambda_m * lambda_m * lambda_m * lambda_m;
    C1L / (l5 * denom) * 1e-9
}

/// A black-body emitter restricted to a wavelength band: the `physical:illuminant = "blackbody"`
/// spectrum (temperature from `inputs:colorTemperature`, band [380, 780] nm per the
/// PhysicalLightIlluminantAPI) or Planck's law on any band.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Blackbody {
    temperature_k: f64,
    min_nm: f64,
    max_nm: f64,
}

impl Blackbody {
    /// The band of the "white" and "blackbody" illuminants of PhysicalLightIlluminantAPI, nm.
    pub const VISIBLE_NM: (f64, f64) = (380.0, 780.0);

    /// A black body at `temperature_k` kelvin emitting over [min_nm, max_nm]; errors name
    /// `inputs:colorTemperature` for a non-finite or non-positive temperature.
    pub fn new(temperature_k: f64, min_nm: f64, max_nm: f64) -> Result<Self, SpectralError> {
        if !(temperature_k.is_finite() && temperature_k > 0.0) {
            return Err(SpectralError::InvalidValue {
                attribute: "inputs:colorTemperature".to_owned(),
                value: temperature_k,
                expected: "a finite temperature > 0 K",
            });
        }
        if !(min_nm.is_finite() && max_nm.is_finite() && min_nm > 0.0 && max_nm > min_nm) {
            return Err(SpectralError::InvalidValue {
                attribute: "blackbody band".to_owned(),
                value: if min_nm.is_finite() && min_nm > 0.0 {
                    max_nm
                } else {
                    min_nm
                },
                expected: "0 < min_nm < max_nm, finite",
            });
        }
        Ok(Blackbody {
            temperature_k,
            min_nm,
            max_nm,
        })
    }

    /// A black body over [380, 780] nm, the PhysicalLightIlluminantAPI domain.
    pub fn visible(temperature_k: f64) -> Result<Self, SpectralError> {
        Self::new(temperature_k, Self::VISIBLE_NM.0, Self::VISIBLE_NM.1)
    }

    /// Temperature, K.
    pub fn temperature(&self) -> f64 {
        self.temperature_k
    }

    /// (min, max) wavelength of the band, nm.
    pub fn bounds(&self) -> (f64, f64) {
        (self.min_nm, self.max_nm)
    }

    /// Spectral radiance W·sr⁻¹·m⁻²·nm⁻¹ at `lambda_nm` inside the band, 0 outside.
    pub fn eval(&self, lambda_nm: f64) -> f64 {
        if lambda_nm >= self.min_nm && lambda_nm <= self.max_nm {
            planck_radiance(lambda_nm, self.temperature_k)
        } else {
            0.0
        }
    }
}
