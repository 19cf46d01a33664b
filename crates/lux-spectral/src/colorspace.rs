//! Rendering colour spaces: linear Rec.709/sRGB (D65) and ACEScg (AP1), XYZ ↔ RGB.

use glam::{DMat3, DVec2, DVec3};

use crate::error::SpectralError;

type Rows = [[f64; 3]; 3];

/// A linear RGB rendering colour space. "white" (`physical:illuminant = "white"`) is its white
/// point, which maps to RGB (1, 1, 1) with luminance 1.
///
/// XYZ → RGB is the space's own matrix, derived from its primaries and white point with the
/// white normalised to Y = 1; there is **no chromatic adaptation** (a D65 spectrum is white in
/// Rec.709 and slightly blue in ACEScg, whose white is the ACES white point).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Hash)]
pub enum ColorSpace {
    /// Linear Rec.709 / sRGB primaries, D65 white (x, y) = (0.3127, 0.3290) (ITU-R BT.709).
    #[default]
    Rec709,
    /// ACEScg: ACES AP1 primaries, ACES white (0.32168, 0.33767) (SMPTE ST 2065-1, S-2014-004).
    AcesCg,
}

/// (red, green, blue, white) xy chromaticities of Rec.709.
const REC709_XY: [[f64; 2]; 4] = [[0.64, 0.33], [0.30, 0.60], [0.15, 0.06], [0.3127, 0.3290]];
/// (red, green, blue, white) xy chromaticities of ACES AP1 with the ACES white point.
const AP1_XY: [[f64; 2]; 4] = [
    [0.713, 0.293],
    [0.165, 0.830],
    [0.128, 0.044],
    [0.32168, 0.33767],
];

const fn xyz_of_xy(xy: [f64; 2]) -> [f64; 3] {
    [xy[0] / xy[1], 1.0, (1.0 - xy[0] - xy[1]) / xy[1]]
}

const fn det(m: &Rows) -> f64 {
    m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
        - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
        + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
}

const fn inverse(m: &Rows) -> Rows {
    let d = det(m);
    [
        [
            (m[1][1] * m[2][2] - m[1][2] * m[2][1]) / d,
            (m[0][2] * m[2][1] - m[0][1] * m[2][2]) / d,
            (m[0][1] * m[1][2] - m[0][2] * m[1][1]) / d,
        ],
        [
            (m[1][2] * m[2][0] - m[1][0] * m[2][2]) / d,
            (m[0][0] * m[2][2] - m[0][2] * m[2][0]) / d,
            (m[0][2] * m[1][0] - m[0][0] * m[1][2]) / d,
        ],
        [
            (m[1][0] * m[2][1] - m[1][1] * m[2][0]) / d,
            (m[0][1] * m[2][0] - m[0][0] * m[2][1]) / d,
            (m[0][0] * m[1][1] - m[0][1] * m[1][0]) / d,
        ],
    ]
}

/// RGB → XYZ rows: columns are the primaries' XYZ scaled so that RGB (1,1,1) gives the white
/// point with Y = 1.
const fn rgb_to_xyz_rows(p: [[f64; 2]; 4]) -> Rows {
    let r = xyz_of_xy(p[0]);
    let g = xyz_of_xy(p[1]);
    let b = xyz_of_xy(p[2]);
    let w = xyz_of_xy(p[3]);
    let prim: Rows = [[r[0], g[0], b[0]], [r[1], g[1], b[1]], [r[2], g[2], b[2]]];
    let inv = inverse(&prim);
    let s = [
        inv[0][0] * w[0] + inv[0][1] * w[1] + inv[0][2] * w[2],
        inv[1][0] * w[0] + inv[1][1] * w[1] + inv[1][2] * w[2],
        inv[2][0] * w[0] + inv[2][1] * w[1] + inv[2][2] * w[2],
    ];
    [
        [prim[0][0] * s[0], prim[0][1] * s[1], prim[0][2] * s[2]],
        [prim[1][0] * s[0], prim[1][1] * s[1], prim[1][2] * s[2]],
        [prim[2][0] * s[0], prim[2][1] * s[1], prim[2][2] * s[2]],
    ]
}

const REC709_TO_XYZ: Rows = rgb_to_xyz_rows(REC709_XY);
const XYZ_TO_REC709: Rows = inverse(&REC709_TO_XYZ);
const AP1_TO_XYZ: Rows = rgb_to_xyz_rows(AP1_XY);
const XYZ_TO_AP1: Rows = inverse(&AP1_TO_XYZ);

#[inline]
fn apply(m: &Rows, v: DVec3) -> DVec3 {
    DVec3::new(
        m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z,
        m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z,
        m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z,
    )
}

fn to_mat(m: &Rows) -> DMat3 {
    DMat3::from_cols(
        DVec3::new(m[0][0], m[1][0], m[2][0]),
        DVec3::new(m[0][1], m[1][1], m[2][1]),
        DVec3::new(m[0][2], m[1][2], m[2][2]),
    )
}

impl ColorSpace {
    /// Parse a colour-space name: `"lin_rec709"`, `"rec709"`, `"srgb"`, `"lin_srgb"` →
    /// [`ColorSpace::Rec709`]; `"acescg"`, `"lin_ap1"`, `"ap1"` → [`ColorSpace::AcesCg`]
    /// (ASCII case-insensitive).
    pub fn parse(name: &str) -> Result<Self, SpectralError> {
        match name.to_ascii_lowercase().as_str() {
            "lin_rec709" | "rec709" | "srgb" | "lin_srgb" | "linear_srgb" => Ok(ColorSpace::Rec709),
            "acescg" | "lin_ap1" | "ap1" => Ok(ColorSpace::AcesCg),
            _ => Err(SpectralError::UnknownToken {
                attribute: "colour space".to_owned(),
                value: name.to_owned(),
                expected: "\"lin_rec709\", \"srgb\", \"acescg\", \"lin_ap1\"",
            }),
        }
    }

    fn rows(self) -> (&'static Rows, &'static Rows) {
        match self {
            ColorSpace::Rec709 => (&REC709_TO_XYZ, &XYZ_TO_REC709),
            ColorSpace::AcesCg => (&AP1_TO_XYZ, &XYZ_TO_AP1),
        }
    }

    /// xy of the white point.
    pub fn white_xy(self) -> DVec2 {
        let w = match self {
            ColorSpace::Rec709 => REC709_XY[3],
            ColorSpace::AcesCg => AP1_XY[3],
        };
        DVec2::new(w[0], w[1])
    }

    /// xy of the red, green and blue primaries.
    pub fn primaries_xy(self) -> [DVec2; 3] {
        let p = match self {
            ColorSpace::Rec709 => REC709_XY,
            ColorSpace::AcesCg => AP1_XY,
        };
        [
            DVec2::from_array(p[0]),
            DVec2::from_array(p[1]),
            DVec2::from_array(p[2]),
        ]
    }

    /// The RGB → XYZ matrix (column-vector convention).
    pub fn rgb_to_xyz_matrix(self) -> DMat3 {
        to_mat(self.rows().0)
    }

    /// The XYZ → RGB matrix (column-vector convention).
    pub fn xyz_to_rgb_matrix(self) -> DMat3 {
        to_mat(self.rows().1)
    }

    /// Linear RGB of XYZ tristimulus values.
    #[inline]
    pub fn xyz_to_rgb(self, xyz: DVec3) -> DVec3 {
        apply(self.rows().1, xyz)
    }

    /// XYZ of linear RGB.
    #[inline]
    pub fn rgb_to_xyz(self, rgb: DVec3) -> DVec3 {
        apply(self.rows().0, rgb)
    }

    /// Luminance Y of linear RGB in this space: the middle row of its RGB → XYZ matrix
    /// (Rec.709: 0.2126, 0.7152, 0.0722). For Rec.709 this is `lux_math::luminance` (the same
    /// weights, derived here from the primaries; the tests hold them equal to 1e-15).
    #[inline]
    pub fn luminance(self, rgb: DVec3) -> f64 {
        let r = &self.rows().0[1];
        r[0] * rgb.x + r[1] * rgb.y + r[2] * rgb.z
    }
}
