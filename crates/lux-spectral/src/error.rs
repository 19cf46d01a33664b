//! Typed errors of the crate.

use thiserror::Error;

/// Largest number of samples accepted in one spectrum (caps allocations on absurd input).
pub const MAX_SAMPLES: usize = 1 << 20;

/// What is wrong with one sampled spectrum; the index is the 0-based position of the
/// offending (wavelength, value) pair.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum SpectrumError {
    /// Fewer than two pairs: a spectrum needs a non-empty wavelength interval.
    #[error("{count} (wavelength, value) pairs, expected at least 2")]
    TooFewSamples {
        /// Number of pairs given.
        count: usize,
    },
    /// More pairs than [`MAX_SAMPLES`].
    #[error("{count} (wavelength, value) pairs, expected at most {max}")]
    TooManySamples {
        /// Number of pairs given.
        count: usize,
        /// The cap, [`MAX_SAMPLES`].
        max: usize,
    },
    /// Wavelength and value arrays of different length.
    #[error("{wavelengths} wavelengths but {values} values, expected equal counts")]
    LengthMismatch {
        /// Number of wavelengths.
        wavelengths: usize,
        /// Number of values.
        values: usize,
    },
    /// A wavelength is NaN, infinite, zero or negative.
    #[error("pair {index}: wavelength {wavelength} is not a finite positive number")]
    BadWavelength {
        /// Pair index.
        index: usize,
        /// The wavelength as given (before unit conversion).
        wavelength: f64,
    },
    /// A wavelength is not greater than the one before it.
    #[error(
        "pair {index}: wavelength {wavelength} is not greater than the previous {previous}; \
         wavelengths must increase strictly"
    )]
    NotIncreasing {
        /// Pair index.
        index: usize,
        /// This wavelength.
        wavelength: f64,
        /// The previous wavelength.
        previous: f64,
    },
    /// A value is NaN or infinite.
    #[error("pair {index}: value {value} is not finite")]
    NonFiniteValue {
        /// Pair index.
        index: usize,
        /// The value.
        value: f64,
    },
    /// A value is below the attribute's allowed minimum.
    #[error("pair {index}: value {value} is below {min}, expected {expected}")]
    ValueTooSmall {
        /// Pair index.
        index: usize,
        /// The value.
        value: f64,
        /// The allowed minimum.
        min: f64,
        /// Human-readable allowed range.
        expected: &'static str,
    },
    /// A value is above the attribute's allowed maximum.
    #[error("pair {index}: value {value} is above {max}, expected {expected}")]
    ValueTooLarge {
        /// Pair index.
        index: usize,
        /// The value.
        value: f64,
        /// The allowed maximum.
        max: f64,
        /// Human-readable allowed range.
        expected: &'static str,
    },
}

/// Errors of the spectral API and the physical-light-unit conversions. Every variant names the
/// USD attribute (or metadata key) it is about.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum SpectralError {
    /// A sampled spectrum attribute is malformed.
    #[error("{attribute}: {source}")]
    Spectrum {
        /// USD attribute name, e.g. `wavelength:emission`.
        attribute: String,
        /// What is wrong.
        #[source]
        source: SpectrumError,
    },
    /// An empty spectrum attribute without `illuminantPreset` metadata.
    #[error(
        "{attribute}: empty and no illuminantPreset metadata; expected (wavelength, value) pairs \
         or a preset (a, d50, d65, e, f1, f2, f7, f11)"
    )]
    EmptyWithoutPreset {
        /// USD attribute name.
        attribute: String,
    },
    /// A token attribute or metadata value is not one of its allowed tokens.
    #[error("{attribute}: unknown value {value:?}, expected one of {expected}")]
    UnknownToken {
        /// USD attribute or metadata name.
        attribute: String,
        /// The value found.
        value: String,
        /// The allowed tokens.
        expected: &'static str,
    },
    /// A scalar attribute is NaN, infinite or out of range.
    #[error("{attribute}: value {value} is invalid, expected {expected}")]
    InvalidValue {
        /// USD attribute name (or input name for non-USD inputs such as the world area).
        attribute: String,
        /// The value found.
        value: f64,
        /// What was expected.
        expected: &'static str,
    },
    /// Sellmeier coefficients malformed (wrong count, non-finite).
    #[error("{attribute}: {detail}")]
    Sellmeier {
        /// USD attribute name (`wavelength:ior`).
        attribute: String,
        /// What is wrong.
        detail: String,
    },
    /// The Sellmeier equation has no real refractive index at this wavelength (n² ≤ 0 or a pole).
    #[error("Sellmeier IOR undefined at {wavelength_nm} nm (n² = {n_squared}), expected n² > 0")]
    SellmeierDomain {
        /// Wavelength asked for, nm.
        wavelength_nm: f64,
        /// The value n² evaluates to there.
        n_squared: f64,
    },
    /// An illuminant spectrum has no luminance (e.g. it lies entirely outside 360–830 nm), so
    /// "the colour of 1 nit" and the lm ↔ W conversion are undefined.
    #[error(
        "{attribute}: the illuminant spectrum has zero luminance, expected some visible emission"
    )]
    ZeroLuminance {
        /// USD attribute name.
        attribute: String,
    },
    /// The quantity given does not apply to the light's geometry (e.g. lumens on a dome light).
    #[error("{quantity} does not apply to a {geometry}")]
    QuantityMismatch {
        /// The USD attribute of the quantity.
        quantity: &'static str,
        /// The geometry it was paired with.
        geometry: &'static str,
    },
    /// A shaping integral was asked of a light kind without an area-light emitter model
    /// (`DistantLight`, `DomeLight`, `PortalLight`, a `MeshLightAPI` gprim): G is defined for
    /// `RectLight`, `DiskLight`, `SphereLight` and `CylinderLight` only.
    #[error(
        "{light} has no area-light emitter model for the shaping integral, expected a RectLight, \
         DiskLight, SphereLight or CylinderLight"
    )]
    NotAnAreaEmitter {
        /// The USD type name of the light kind (`lux_math::LightKind::usd_type_name`).
        light: &'static str,
    },
}

impl SpectralError {
    /// Wrap a [`SpectrumError`] with the attribute name it belongs to.
    pub fn spectrum(attribute: &str, source: SpectrumError) -> Self {
        SpectralError::Spectrum {
            attribute: attribute.to_owned(),
            source,
        }
    }
}
