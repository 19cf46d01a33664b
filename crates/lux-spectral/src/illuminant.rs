//! The CIE standard illuminants of the LTESpectralAPI `illuminantPreset` metadata.

use crate::error::SpectralError;
use crate::interpolation::Interpolation;
use crate::spectrum::SampledSpectrum;
use crate::tables::illuminants as t;

/// A CIE standard illuminant, as named by the LTESpectralAPI `illuminantPreset` metadata of
/// `wavelength:emission`. Relative SPDs on 5 nm grids from the CIE tables (F1, F2, F7, F11 are
/// the CIE FL1, FL2, FL7, FL11 tables), linearly interpolated.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Illuminant {
    /// `"a"`: incandescent / tungsten, Planckian at 2856 K.
    A,
    /// `"d50"`: horizon daylight, CCT ≈ 5003 K.
    D50,
    /// `"d65"`: noon daylight, CCT ≈ 6504 K (the white point of Rec.709/sRGB).
    D65,
    /// `"e"`: equal energy.
    E,
    /// `"f1"`: daylight fluorescent (FL1).
    F1,
    /// `"f2"`: cool white fluorescent (FL2).
    F2,
    /// `"f7"`: broadband D65 simulator (FL7).
    F7,
    /// `"f11"`: narrow-band cool white (FL11).
    F11,
}

impl Illuminant {
    /// All eight presets.
    pub const ALL: [Illuminant; 8] = [
        Illuminant::A,
        Illuminant::D50,
        Illuminant::D65,
        Illuminant::E,
        Illuminant::F1,
        Illuminant::F2,
        Illuminant::F7,
        Illuminant::F11,
    ];

    /// Parse an `illuminantPreset` token: `a`, `d50`, `d65`, `e`, `f1`, `f2`, `f7`, `f11`
    /// (ASCII case-insensitive).
    pub fn parse(token: &str) -> Result<Self, SpectralError> {
        Ok(match token.to_ascii_lowercase().as_str() {
            "a" => Illuminant::A,
            "d50" => Illuminant::D50,
            "d65" => Illuminant::D65,
            "e" => Illuminant::E,
            "f1" => Illuminant::F1,
            "f2" => Illuminant::F2,
            "f7" => Illuminant::F7,
            "f11" => Illuminant::F11,
            _ => {
                return Err(SpectralError::UnknownToken {
                    attribute: "illuminantPreset".to_owned(),
                    value: token.to_owned(),
                    expected: "\"a\", \"d50\", \"d65\", \"e\", \"f1\", \"f2\", \"f7\", \"f11\"",
                });
            }
        })
    }

    /// The preset token (lower case).
    pub fn token(self) -> &'static str {
        match self {
            Illuminant::A => "a",
            Illuminant::D50 => "d50",
            Illuminant::D65 => "d65",
            Illuminant::E => "e",
            Illuminant::F1 => "f1",
            Illuminant::F2 => "f2",
            Illuminant::F7 => "f7",
            Illuminant::F11 => "f11",
        }
    }

    /// The embedded table: (first wavelength nm, values at 5 nm steps).
    pub fn table(self) -> (f64, &'static [f64]) {
        match self {
            Illuminant::A => (t::A_START_NM, &t::A_SPD),
            Illuminant::D50 => (t::D50_START_NM, &t::D50_SPD),
            Illuminant::D65 => (t::D65_START_NM, &t::D65_SPD),
            Illuminant::E => (t::E_START_NM, &t::E_SPD),
            Illuminant::F1 => (t::F1_START_NM, &t::F1_SPD),
            Illuminant::F2 => (t::F2_START_NM, &t::F2_SPD),
            Illuminant::F7 => (t::F7_START_NM, &t::F7_SPD),
            Illuminant::F11 => (t::F11_START_NM, &t::F11_SPD),
        }
    }

    /// The relative SPD as a linearly interpolated [`SampledSpectrum`] over the table's range.
    pub fn spectrum(self) -> SampledSpectrum {
        let (start, values) = self.table();
        let wavelengths = (0..values.len()).map(|i| start + 5.0 * i as f64).collect();
        SampledSpectrum::new(wavelengths, values.to_vec(), Interpolation::Linear)
            .expect("embedded CIE tables are valid")
    }
}
