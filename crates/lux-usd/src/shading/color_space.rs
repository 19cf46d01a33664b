//! The colour spaces MaterialX names (`MaterialX.Specification.md`, "Color Spaces and Color
//! Management"), and their transforms into `lin_rec709`, lux's working space, as MaterialX's
//! cmlib defines them (`NG_srgb_texture_to_lin_rec709`, `NG_g22_rec709_to_lin_rec709`,
//! `NG_acescg_to_lin_rec709`, …).
//!
//! A colour value (`color3`/`color4`) is in its element's active colour space (its own
//! `colorspace`, else the nearest enclosing element's, else the document's); USD states one
//! with an attribute's `colorSpace` metadata. lux converts such values to `lin_rec709` when
//! it reads them; texture texels are converted when the texture loads.

use std::path::Path;

/// A colour space lux converts from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ColorSpace {
    /// `lin_rec709` (also `raw`, `none`, `Raw`, `linear`): taken as is.
    Linear,
    /// `srgb_texture`: the sRGB transfer function undone (IEC 61966-2-1).
    Srgb,
    /// `g22_rec709`: `max(c, 0)^2.2`.
    Gamma22,
    /// `g18_rec709`: `max(c, 0)^1.8`.
    Gamma18,
    /// `acescg` (`lin_ap1`): the AP1 → Rec.709 matrix of MaterialX's cmlib.
    AcesCg,
}

/// cmlib's `NG_acescg_to_lin_rec709` matrix (a row vector times this matrix).
pub const ACESCG_TO_LIN_REC709: [[f64; 3]; 3] = [
    [1.705050992658, -0.130256417507, -0.024003356805],
    [-0.621792120657, 1.140804736575, -0.128968976065],
    [-0.083258872001, -0.010548319068, 1.15297233287],
];

impl ColorSpace {
    /// The colour space a MaterialX `colorspace` (or USD `colorSpace`) name states; `None`
    /// for an empty name or one lux does not know.
    pub fn named(name: &str) -> Option<ColorSpace> {
        Some(match name {
            "lin_rec709" | "raw" | "Raw" | "none" | "linear" | "scene-linear Rec.709-sRGB" => {
                ColorSpace::Linear
            }
            "srgb_texture" | "sRGB" | "srgb" => ColorSpace::Srgb,
            "g22_rec709" => ColorSpace::Gamma22,
            "g18_rec709" => ColorSpace::Gamma18,
            "acescg" | "lin_ap1" | "ACEScg" => ColorSpace::AcesCg,
            _ => return None,
        })
    }

    /// The colour space of a texture file's texels: `named(name)`, and for an empty name sRGB
    /// for integer (8/16-bit) formats and linear for EXR and HDR files, as MaterialX assumes.
    pub fn of(name: &str, path: &Path) -> Option<ColorSpace> {
        if name.is_empty() {
            return Some(if is_float_format(path) {
                ColorSpace::Linear
            } else {
                ColorSpace::Srgb
            });
        }
        ColorSpace::named(name)
    }

    /// `lin_rec709` from a value `c` in this colour space (alpha is never converted).
    pub fn decode(self, c: [f64; 3]) -> [f64; 3] {
        match self {
            ColorSpace::Linear => c,
            ColorSpace::Srgb => c.map(srgb_to_linear),
            ColorSpace::Gamma22 => c.map(|x| x.max(0.0).powf(2.2)),
            ColorSpace::Gamma18 => c.map(|x| x.max(0.0).powf(1.8)),
            ColorSpace::AcesCg => {
                let m = ACESCG_TO_LIN_REC709;
                let mut out = [0.0; 3];
                for (j, o) in out.iter_mut().enumerate() {
                    *o = c[0] * m[0][j] + c[1] * m[1][j] + c[2] * m[2][j];
                }
                out
            }
        }
    }
}

/// The sRGB EOTF (IEC 61966-2-1): `c ≤ 0.04045 → c/12.92`, otherwise
/// `((c + 0.055)/1.055)^2.4`.
pub fn srgb_to_linear(c: f64) -> f64 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// Whether a texture file holds float data (EXR, Radiance HDR), whose texels are linear
/// unless stated otherwise; other formats are integer, sRGB unless stated otherwise.
pub fn is_float_format(path: &Path) -> bool {
    let name = path.to_string_lossy().to_ascii_lowercase();
    let name = name.trim_end_matches(']');
    name.ends_with(".exr") || name.ends_with(".hdr")
}

/// Converts a colour value (the first three of `c`, alpha untouched) from the colour space
/// `name` to `lin_rec709`; false, with the value unchanged, for a name lux does not know.
pub fn to_lin_rec709(name: &str, c: &mut [f64]) -> bool {
    let Some(space) = ColorSpace::named(name) else {
        return false;
    };
    if c.len() >= 3 && space != ColorSpace::Linear {
        let rgb = space.decode([c[0], c[1], c[2]]);
        c[..3].copy_from_slice(&rgb);
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn acescg_white_stays_white_and_primaries_map_by_cmlib() {
        // AP1 and Rec.709 share the D60/D65-adapted white: (1, 1, 1) stays (1, 1, 1) to the
        // matrix's 12 digits.
        for x in ColorSpace::AcesCg.decode([1.0; 3]) {
            assert!((x - 1.0).abs() < 1e-11, "{x}");
        }
        assert_eq!(
            ColorSpace::AcesCg.decode([1.0, 0.0, 0.0]),
            ACESCG_TO_LIN_REC709[0]
        );
    }

    #[test]
    fn srgb_decode_matches_the_standard_at_its_knee_and_ends() {
        assert_eq!(srgb_to_linear(0.0), 0.0);
        assert!((srgb_to_linear(1.0) - 1.0).abs() < 1e-15);
        assert!((srgb_to_linear(0.04045) - 0.04045 / 12.92).abs() < 1e-18);
        assert!((srgb_to_linear(0.5) - 0.214_041_140_482_232_5).abs() < 1e-15);
    }

    #[test]
    fn unknown_names_leave_values_unchanged() {
        let mut c = [0.5, 0.25, 0.125, 0.9];
        assert!(!to_lin_rec709("adobergb", &mut c));
        assert_eq!(c, [0.5, 0.25, 0.125, 0.9]);
        assert!(to_lin_rec709("g22_rec709", &mut c));
        assert!((c[0] - 0.5f64.powf(2.2)).abs() < 1e-15);
        assert_eq!(c[3], 0.9);
    }
}
