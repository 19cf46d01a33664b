//! PhysicalLightIlluminantAPI and the Photometric/Radiometric {Area, Dome, Distant} LightAPI
//! inputs, and the illuminant's "colour of 1 nit".

use glam::DVec3;

use crate::any_spectrum::Spectrum;
use crate::colorspace::ColorSpace;
use crate::error::{SpectralError, SpectrumError};
use crate::illuminant::Illuminant;
use crate::interpolation::Interpolation;
use crate::planck::Blackbody;
use crate::spectrum::SampledSpectrum;
use crate::wavelength::WavelengthUnit;

/// `physical:illuminant` (PhysicalLightIlluminantAPI), default `"white"`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Hash)]
pub enum IlluminantKind {
    /// `"white"`: the white point of the rendering colour space, over [380, 780] nm.
    #[default]
    White,
    /// `"blackbody"`: Planck's law at `inputs:colorTemperature`, over [380, 780] nm.
    Blackbody,
    /// `"custom"`: the `physical:customIlluminant` table.
    Custom,
}

impl IlluminantKind {
    /// Parse the token `"white"`, `"blackbody"` or `"custom"`.
    pub fn parse(token: &str) -> Result<Self, SpectralError> {
        match token {
            "white" => Ok(IlluminantKind::White),
            "blackbody" => Ok(IlluminantKind::Blackbody),
            "custom" => Ok(IlluminantKind::Custom),
            _ => Err(SpectralError::UnknownToken {
                attribute: "physical:illuminant".to_owned(),
                value: token.to_owned(),
                expected: "\"white\", \"blackbody\", \"custom\"",
            }),
        }
    }
}

/// The physical quantity a light is specified in: which Photometric/Radiometric API is
/// applied, with its value.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PhysicalQuantity {
    /// PhotometricAreaLightAPI `photometric:power`, lm (schema default 1600).
    PhotometricPower(f64),
    /// RadiometricAreaLightAPI `radiometric:power`, W over the illuminant's band (default 2.34).
    RadiometricPower(f64),
    /// Photometric{Dome,Distant}LightAPI `photometric:illuminance`, lux (default 10000).
    PhotometricIlluminance(f64),
    /// Radiometric{Dome,Distant}LightAPI `radiometric:irradiance`, W/m² over the illuminant's
    /// band (default 14.64).
    RadiometricIrradiance(f64),
}

impl PhysicalQuantity {
    /// Schema default of `photometric:power`, lm.
    pub const DEFAULT_PHOTOMETRIC_POWER: f64 = 1600.0;
    /// Schema default of `radiometric:power`, W.
    pub const DEFAULT_RADIOMETRIC_POWER: f64 = 2.34;
    /// Schema default of `photometric:illuminance`, lux.
    pub const DEFAULT_PHOTOMETRIC_ILLUMINANCE: f64 = 10000.0;
    /// Schema default of `radiometric:irradiance`, W/m².
    pub const DEFAULT_RADIOMETRIC_IRRADIANCE: f64 = 14.64;

    /// The USD attribute name of this quantity.
    pub fn attribute(self) -> &'static str {
        match self {
            PhysicalQuantity::PhotometricPower(_) => "photometric:power",
            PhysicalQuantity::RadiometricPower(_) => "radiometric:power",
            PhysicalQuantity::PhotometricIlluminance(_) => "photometric:illuminance",
            PhysicalQuantity::RadiometricIrradiance(_) => "radiometric:irradiance",
        }
    }

    /// The value as authored.
    pub fn value(self) -> f64 {
        match self {
            PhysicalQuantity::PhotometricPower(v)
            | PhysicalQuantity::RadiometricPower(v)
            | PhysicalQuantity::PhotometricIlluminance(v)
            | PhysicalQuantity::RadiometricIrradiance(v) => v,
        }
    }
}

/// Everything the physical-light-unit APIs author on one light, with the schema defaults. The
/// USD loader fills it and calls [`crate::emitted`].
#[derive(Debug, Clone, PartialEq)]
pub struct PhysicalLightInputs {
    /// `physical:illuminant` (default white).
    pub illuminant: IlluminantKind,
    /// `physical:customIlluminant` (nm, spectral radiance) pairs (default empty).
    pub custom_illuminant: Vec<[f64; 2]>,
    /// `inputs:colorTemperature`, K (UsdLux default 6500), used by the blackbody illuminant.
    pub color_temperature: f64,
    /// The applied Photometric/Radiometric API and its value.
    pub quantity: PhysicalQuantity,
}

impl PhysicalLightInputs {
    /// Defaults of the schema for the given quantity.
    pub fn new(quantity: PhysicalQuantity) -> Self {
        PhysicalLightInputs {
            illuminant: IlluminantKind::White,
            custom_illuminant: Vec::new(),
            color_temperature: 6500.0,
            quantity,
        }
    }
}

/// An illuminant reduced to what the unit conversions need.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ResolvedIlluminant {
    /// Linear RGB of 1 nit of this spectrum: rgb(S) / luminance(S); its luminance is 1.
    pub rgb_per_nit: DVec3,
    /// Luminous efficacy K = 683·∫S ȳ dλ / ∫S dλ over the spectrum's band, lm/W: converts
    /// `radiometric:*` quantities to photometric ones.
    pub efficacy: f64,
}

/// The spectrum of the illuminant: white → CIE D65 on [380, 780] nm (for ACEScg as well, see
/// [`resolve_illuminant`]), blackbody → Planck on [380, 780] nm, custom → the table (nm, linear,
/// zero outside; values must be ≥ 0).
pub fn illuminant_spectrum(inputs: &PhysicalLightInputs) -> Result<Spectrum, SpectralError> {
    match inputs.illuminant {
        IlluminantKind::White => Ok(Spectrum::Sampled(
            Illuminant::D65
                .spectrum()
                .restricted(Blackbody::VISIBLE_NM.0, Blackbody::VISIBLE_NM.1)
                .expect("D65 covers [380, 780] nm"),
        )),
        IlluminantKind::Blackbody => Ok(Spectrum::Blackbody(Blackbody::visible(
            inputs.color_temperature,
        )?)),
        IlluminantKind::Custom => {
            let attr = "physical:customIlluminant";
            let s = SampledSpectrum::from_pairs(
                &inputs.custom_illuminant,
                WavelengthUnit::Nanometers,
                1.0,
                Interpolation::Linear,
            )
            .map_err(|e| SpectralError::spectrum(attr, e))?;
            if let Some(index) = s.values().iter().position(|&v| v < 0.0) {
                return Err(SpectralError::spectrum(
                    attr,
                    SpectrumError::ValueTooSmall {
                        index,
                        value: s.values()[index],
                        min: 0.0,
                        expected: "spectral radiance ≥ 0",
                    },
                ));
            }
            Ok(Spectrum::Sampled(s))
        }
    }
}

/// Reduce the light's illuminant to its colour of 1 nit and its luminous efficacy.
///
/// "white" is exactly RGB (1, 1, 1) in `space` (its white point); its efficacy is that of D65
/// on [380, 780] nm. For ACEScg, whose white is the ACES white (≈ D60), D65's efficacy is used
/// too: lux embeds no D60 table, and the two differ by well under 1 %.
pub fn resolve_illuminant(
    inputs: &PhysicalLightInputs,
    space: ColorSpace,
) -> Result<ResolvedIlluminant, SpectralError> {
    let spectrum = illuminant_spectrum(inputs)?;
    let xyz = spectrum.to_xyz();
    let attr = match inputs.illuminant {
        IlluminantKind::Custom => "physical:customIlluminant",
        _ => "physical:illuminant",
    };
    if !(xyz.y > 0.0 && xyz.y.is_finite()) {
        return Err(SpectralError::ZeroLuminance {
            attribute: attr.to_owned(),
        });
    }
    let efficacy = spectrum.luminous_efficacy();
    let rgb_per_nit = match inputs.illuminant {
        IlluminantKind::White => DVec3::ONE,
        _ => space.xyz_to_rgb(xyz) / xyz.y,
    };
    Ok(ResolvedIlluminant {
        rgb_per_nit,
        efficacy,
    })
}
