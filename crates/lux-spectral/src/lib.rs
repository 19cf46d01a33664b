//! # lux-spectral
//!
//! Physical light units (lm, W, lux, W/m²) and the LTESpectralAPI for UsdLux lights:
//! sampled spectra, the CIE 1931 2° observer and standard illuminants, Planck's law,
//! spectrum → XYZ → linear Rec.709 / ACEScg, and the conversions of the
//! PhysicalLightIlluminantAPI and Photometric/Radiometric {Area, Dome, Distant} LightAPIs to the
//! luminance (nits) and RGB a renderer emits.
//!
//! See the crate README for an overview and an example; every item names the schema attribute
//! or formula it implements.

#![doc = include_str!("../README.md")]
#![warn(missing_docs)]

mod any_spectrum;
mod cie;
mod colorspace;
mod dome;
mod emission;
mod error;
mod illuminant;
mod interpolation;
mod ior;
mod photometry;
mod physical;
mod planck;
mod sellmeier;
mod shaping_integral;
mod spectral_api;
mod spectrum;
mod tables;
mod wavelength;
pub mod xyz;

pub use any_spectrum::Spectrum;
pub use cie::{CMF_MAX_NM, CMF_MIN_NM, cmf, cmf_table};
pub use colorspace::ColorSpace;
pub use dome::{MAX_LATLONG_TEXELS, latlong_cosine_weighted_mean};
pub use emission::{
    Emission, LightGeometry, area_light_flux, area_light_luminance, distant_light_luminance,
    distant_projected_solid_angle, dome_light_luminance, emitted,
};
pub use error::{MAX_SAMPLES, SpectralError, SpectrumError};
pub use illuminant::Illuminant;
pub use interpolation::Interpolation;
pub use ior::{Ior, IorInterpolation, SCALAR_IOR_WAVELENGTH_NM};
pub use photometry::{K_M, uv_1960, xy_chromaticity};
pub use physical::{
    IlluminantKind, PhysicalLightInputs, PhysicalQuantity, ResolvedIlluminant, illuminant_spectrum,
    resolve_illuminant,
};
pub use planck::{BOLTZMANN_K, Blackbody, C1L, C2, PLANCK_H, SPEED_OF_LIGHT, planck_radiance};
pub use sellmeier::Sellmeier;
pub use shaping_integral::ShapingIntegral;
pub use spectral_api::{IorAttribute, SpectralAttribute, SpectralInputs};
pub use spectrum::SampledSpectrum;
pub use wavelength::WavelengthUnit;
pub use xyz::spectrum_to_xyz;
