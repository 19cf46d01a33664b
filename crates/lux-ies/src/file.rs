//! The parsed file, field for field (lossless: writing it back and parsing gives the same value).

use crate::edition::Edition;
use crate::error::{IesError, Position};
use crate::header::{self, HeaderLine};
use crate::opening::LuminousOpening;
use crate::tilt::Tilt;

/// Photometric type (LM-63 "photometric type" field): which goniometer coordinate system the
/// angles are in.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum PhotometricType {
    /// 1 = type C: vertical angle γ from nadir (0..180), horizontal angle = C-plane (0..360).
    C,
    /// 2 = type B: vertical angle −90..90 (elevation), horizontal −90..90 about a lateral polar axis.
    B,
    /// 3 = type A: like B with the polar axis along the luminaire's length.
    A,
}

impl PhotometricType {
    /// The code written in the file: C = 1, B = 2, A = 3.
    pub const fn code(self) -> i64 {
        match self {
            PhotometricType::C => 1,
            PhotometricType::B => 2,
            PhotometricType::A => 3,
        }
    }

    /// From the file code; `None` for anything but 1, 2, 3.
    pub const fn from_code(c: i64) -> Option<PhotometricType> {
        match c {
            1 => Some(PhotometricType::C),
            2 => Some(PhotometricType::B),
            3 => Some(PhotometricType::A),
            _ => None,
        }
    }

    /// 'A', 'B' or 'C'.
    pub const fn letter(self) -> char {
        match self {
            PhotometricType::C => 'C',
            PhotometricType::B => 'B',
            PhotometricType::A => 'A',
        }
    }
}

/// Units of the luminous opening dimensions (LM-63 "units type" field).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Units {
    /// 1 = feet.
    Feet,
    /// 2 = metres.
    Meters,
}

impl Units {
    /// The code written in the file: feet = 1, metres = 2.
    pub const fn code(self) -> i64 {
        match self {
            Units::Feet => 1,
            Units::Meters => 2,
        }
    }

    /// From the file code; `None` for anything but 1, 2.
    pub const fn from_code(c: i64) -> Option<Units> {
        match c {
            1 => Some(Units::Feet),
            2 => Some(Units::Meters),
            _ => None,
        }
    }
}

/// An LM-63 file as written: every header field, the keyword block in order, the TILT block, the
/// angle sets and the candela table.
///
/// Candela values are stored raw (before the candela multiplier), row by row: the values of
/// horizontal angle `h` occupy `candela[h * n_v .. (h + 1) * n_v]` (the file's order).
#[derive(Clone, Debug, PartialEq)]
pub struct IesFile {
    /// Edition, from the version line (LM-63-1986 when there is none).
    pub edition: Edition,
    /// Keyword and free-text lines before `TILT=`, in file order.
    pub header: Vec<HeaderLine>,
    /// The `TILT=` specification.
    pub tilt: Tilt,
    /// "Number of lamps".
    pub lamp_count: i64,
    /// "Lumens per lamp"; −1 means absolute photometry (LM-63-2002 §5.9).
    pub lumens_per_lamp: f64,
    /// "Candela multiplier": every candela value is multiplied by it.
    pub candela_multiplier: f64,
    /// "Photometric type".
    pub photometric_type: PhotometricType,
    /// "Units type" of the opening dimensions.
    pub units: Units,
    /// Luminous opening width (sign encodes the shape, see [`LuminousOpening`]).
    pub width: f64,
    /// Luminous opening length.
    pub length: f64,
    /// Luminous opening height.
    pub height: f64,
    /// "Ballast factor": a multiplier on every candela value.
    pub ballast_factor: f64,
    /// Third number of the second header line: the "ballast-lamp photometric factor" (a
    /// multiplier) up to LM-63-2002, the "file generation type" (a code such as 1.00001) in
    /// LM-63-2019.
    pub third_factor: f64,
    /// "Input watts".
    pub input_watts: f64,
    /// Vertical angles in degrees, strictly increasing.
    pub vertical_angles_deg: Vec<f64>,
    /// Horizontal angles in degrees, strictly increasing.
    pub horizontal_angles_deg: Vec<f64>,
    /// Raw candela values, `n_h` rows of `n_v` values.
    pub candela: Vec<f64>,
}

impl IesFile {
    /// Number of vertical angles.
    pub fn num_vertical(&self) -> usize {
        self.vertical_angles_deg.len()
    }

    /// Number of horizontal angles.
    pub fn num_horizontal(&self) -> usize {
        self.horizontal_angles_deg.len()
    }

    /// Raw candela value at horizontal index `h`, vertical index `v` (`None` out of range).
    pub fn candela_at(&self, h: usize, v: usize) -> Option<f64> {
        let nv = self.num_vertical();
        if v >= nv || h >= self.num_horizontal() {
            return None;
        }
        self.candela.get(h * nv + v).copied()
    }

    /// First value of keyword `name` (ASCII case-insensitive), e.g. `keyword("TEST")`.
    pub fn keyword(&self, name: &str) -> Option<&str> {
        header::find(&self.header, name)
    }

    /// `true` for absolute photometry (lumens per lamp = −1).
    pub fn is_absolute(&self) -> bool {
        self.lumens_per_lamp == -1.0
    }

    /// Shape of the luminous opening from width, length, height.
    pub fn luminous_opening(&self) -> LuminousOpening {
        LuminousOpening::from_dimensions(self.width, self.length, self.height)
    }

    /// LM-63-2019 "file generation type" code (the third factor), `None` in earlier editions.
    pub fn file_generation_type(&self) -> Option<f64> {
        (self.edition == Edition::Lm63_2019).then_some(self.third_factor)
    }

    /// The factor turning a raw candela value into candela under `profile`:
    /// `candela multiplier × ballast factor × third`, where `third` is the ballast-lamp photometric
    /// factor before LM-63-2019. In LM-63-2019 the third number is the file generation type, a
    /// code: [`lux_math::Profile::Spec`] ignores it, [`lux_math::Profile::HdEmbree`] multiplies by
    /// it as the reference does.
    pub fn candela_scale(&self, profile: lux_math::Profile) -> f64 {
        let third = match (self.edition, profile) {
            (Edition::Lm63_2019, lux_math::Profile::Spec) => 1.0,
            _ => self.third_factor,
        };
        self.candela_multiplier * self.ballast_factor * third
    }

    /// Checks what the parser checks, for a value built in code: array sizes agree, numbers are
    /// finite, candela values non-negative, angles strictly increasing and in the ranges LM-63
    /// allows for the photometric type. Errors carry position `0:0`.
    pub fn validate(&self) -> Result<(), IesError> {
        let at = Position::default();
        let nv = self.num_vertical();
        let nh = self.num_horizontal();
        if nv.checked_mul(nh) != Some(self.candela.len()) {
            return Err(IesError::Inconsistent {
                at,
                what: format!(
                    "{} candela values for {nh} horizontal x {nv} vertical angles",
                    self.candela.len()
                ),
            });
        }
        for (field, v) in [
            ("lumens per lamp", self.lumens_per_lamp),
            ("candela multiplier", self.candela_multiplier),
            ("width", self.width),
            ("length", self.length),
            ("height", self.height),
            ("ballast factor", self.ballast_factor),
            (
                "ballast-lamp factor / file generation type",
                self.third_factor,
            ),
            ("input watts", self.input_watts),
        ] {
            if !v.is_finite() {
                return Err(IesError::InvalidValue {
                    at,
                    field,
                    value: v.to_string(),
                    expected: "a finite number".into(),
                });
            }
        }
        for (field, v) in [
            ("candela multiplier", self.candela_multiplier),
            ("ballast factor", self.ballast_factor),
        ] {
            if v < 0.0 {
                return Err(IesError::InvalidValue {
                    at,
                    field,
                    value: v.to_string(),
                    expected: "a non-negative number".into(),
                });
            }
        }
        if let Some(&c) = self.candela.iter().find(|c| !(c.is_finite() && **c >= 0.0)) {
            return Err(IesError::InvalidValue {
                at,
                field: "candela value",
                value: c.to_string(),
                expected: "a finite, non-negative candela value".into(),
            });
        }
        let none = |_| at;
        crate::parse::check_angles(
            self.photometric_type,
            &self.vertical_angles_deg,
            &none,
            &self.horizontal_angles_deg,
            &none,
        )
    }
}
