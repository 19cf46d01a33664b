//! `inputs:colorTemperature`: the colour of a blackbody at a temperature, three ways.
//!
//! - [`usdlux_blackbody_rgb`]: OpenUSD's `UsdLuxBlackbodyTemperatureAsRgb`, the function the
//!   26.11 text names (a Catmull-Rom spline through a 1000–10000 K table, normalised to Rec.709
//!   luminance 1, clamped at 0). Not white at 6500 K: (1.0433, 0.9836, 1.0346).
//! - [`spec_blackbody_rgb`]: that function divided by its own 6500 K value, so that 6500 K is
//!   exactly white as the text says (the `Spec` profile's colour).
//! - [`hdembree_blackbody_rgb`]: what the hdEmbree reference renders use (the `HdEmbree`
//!   profile's colour): Krystek's 1985 rational fit of the Planckian locus in CIE 1960 (u, v) →
//!   xy → XYZ (Y = 1) → linear Rec.709 → absolute values → ÷ max component → ÷ Rec.709 luminance.

use crate::Profile;
use glam::DVec3;

/// The knot table of `UsdLuxBlackbodyTemperatureAsRgb`: 1000–10000 K every 500 K, with the first
/// knot repeated once in front and the last twice at the end (22 knots, 18 segments of 500 K).
const KNOTS: [[f64; 3]; 22] = [
    [1.000000, 0.027490, 0.000000],
    [1.000000, 0.027490, 0.000000],
    [1.000000, 0.149664, 0.000000],
    [1.000000, 0.256644, 0.008095],
    [1.000000, 0.372033, 0.067450],
    [1.000000, 0.476725, 0.153601],
    [1.000000, 0.570376, 0.259196],
    [1.000000, 0.653480, 0.377155],
    [1.000000, 0.726878, 0.501606],
    [1.000000, 0.791543, 0.628050],
    [1.000000, 0.848462, 0.753228],
    [1.000000, 0.898581, 0.874905],
    [1.000000, 0.942771, 0.991642],
    [0.906947, 0.890456, 1.000000],
    [0.828247, 0.841838, 1.000000],
    [0.765791, 0.801896, 1.000000],
    [0.715255, 0.768579, 1.000000],
    [0.673683, 0.740423, 1.000000],
    [0.638992, 0.716359, 1.000000],
    [0.609681, 0.695588, 1.000000],
    [0.609681, 0.695588, 1.000000],
    [0.609681, 0.695588, 1.000000],
];

/// Rec.709 luma weights used by `UsdLuxBlackbodyTemperatureAsRgb` to normalise its result.
const REC709_LUMA: [f64; 3] = [0.2126, 0.7152, 0.0722];

/// `UsdLuxBlackbodyTemperatureAsRgb(T)` (OpenUSD 26.11), computed in double precision.
///
/// `u = clamp((T − 1000)/9000, 0, 1)`; segment `s = ⌊18u⌋`, local `t = 18u − s`; uniform
/// Catmull-Rom through knots `k[s..s+4]`:
/// `rgb = ((a t + b) t + c) t + k₁` with `a = (−k₀ + 3k₁ − 3k₂ + k₃)/2`,
/// `b = k₀ − 5k₁/2 + 2k₂ − k₃/2`, `c = (k₂ − k₀)/2`; then `rgb /= 0.2126 r + 0.7152 g + 0.0722 b`
/// and each component is clamped at 0. Temperatures outside 1000–10000 K clamp to the ends; NaN
/// is treated as the schema default 6500 K.
pub fn usdlux_blackbody_rgb(kelvin: f64) -> DVec3 {
    let t_k = if kelvin.is_nan() { 6500.0 } else { kelvin };
    let u = ((t_k - 1000.0) / 9000.0).clamp(0.0, 1.0);
    let x = u * 18.0;
    let seg = (x.floor() as usize).min(18);
    let t = x - seg as f64;
    let mut rgb = [0.0; 3];
    for (i, out) in rgb.iter_mut().enumerate() {
        let (k0, k1, k2, k3) = (
            KNOTS[seg][i],
            KNOTS[seg + 1][i],
            KNOTS[seg + 2][i],
            KNOTS[seg + 3][i],
        );
        let a = -0.5 * k0 + 1.5 * k1 - 1.5 * k2 + 0.5 * k3;
        let b = k0 - 2.5 * k1 + 2.0 * k2 - 0.5 * k3;
        let c = -0.5 * k0 + 0.5 * k2;
        *out = ((a * t + b) * t + c) * t + k1;
    }
    let luma = REC709_LUMA[0] * rgb[0] + REC709_LUMA[1] * rgb[1] + REC709_LUMA[2] * rgb[2];
    DVec3::new(
        (rgb[0] / luma).max(0.0),
        (rgb[1] / luma).max(0.0),
        (rgb[2] / luma).max(0.0),
    )
}

/// `UsdLuxBlackbodyTemperatureAsRgb(6500)`, the divisor of [`spec_blackbody_rgb`].
fn usdlux_6500() -> DVec3 {
    // Segment 11, t = 0: the spline passes through knot 12 exactly, luma-normalised.
    let k = KNOTS[12];
    let luma = REC709_LUMA[0] * k[0] + REC709_LUMA[1] * k[1] + REC709_LUMA[2] * k[2];
    DVec3::new(k[0] / luma, k[1] / luma, k[2] / luma)
}

/// The `Spec` profile's colorTemperature colour: `usdlux_blackbody_rgb(T) /
/// usdlux_blackbody_rgb(6500)` component-wise, so 6500 K is exactly (1, 1, 1) as the 26.11 text
/// requires.
pub fn spec_blackbody_rgb(kelvin: f64) -> DVec3 {
    usdlux_blackbody_rgb(kelvin) / usdlux_6500()
}

/// XYZ → linear Rec.709 (D65), derived exactly from the Rec.709 primaries and the D65 white
/// point (x, y) = (0.3127, 0.3290).
const XYZ_TO_REC709: [[f64; 3]; 3] = [
    [
        3.240_969_941_904_521_3,
        -1.537_383_177_570_093_5,
        -0.498_610_760_293_003_3,
    ],
    [
        -0.969_243_636_280_879_8,
        1.875_967_501_507_720_6,
        0.041_555_057_407_175_61,
    ],
    [
        0.055_630_079_696_993_61,
        -0.203_976_958_888_976_57,
        1.056_971_514_242_878_6,
    ],
];

/// Rec.709 relative luminance, the Y row of linear Rec.709 → XYZ (D65), exact from the primaries.
pub const REC709_LUMINANCE: [f64; 3] = [
    0.212_639_005_871_510_36,
    0.715_168_678_767_755_9,
    0.072_192_315_360_733_71,
];

/// Krystek (1985) rational fit of the Planckian locus: CIE 1960 (u, v) at `T` kelvin
/// (stated for 1000–15000 K).
pub fn krystek_planckian_uv(kelvin: f64) -> (f64, f64) {
    let t = kelvin;
    let t2 = t * t;
    let u = (0.860_117_757 + 1.541_182_54e-4 * t + 1.286_412_12e-7 * t2)
        / (1.0 + 8.424_202_35e-4 * t + 7.081_451_63e-7 * t2);
    let v = (0.317_398_726 + 4.228_062_45e-5 * t + 4.204_816_91e-8 * t2)
        / (1.0 - 2.897_418_16e-5 * t + 1.614_560_53e-7 * t2);
    (u, v)
}

/// The `HdEmbree` profile's colorTemperature colour: [`krystek_planckian_uv`] → xy
/// (`x = 3u/(2u − 8v + 4)`, `y = 2v/(2u − 8v + 4)`) → XYZ with Y = 1 → linear Rec.709 →
/// component-wise absolute value → ÷ max component → ÷ Rec.709 luminance.
/// 6500 K → (1.0442, 0.9833, 1.0357); 2000 K → (2.5199, 0.6470, 0.0204).
///
/// Non-finite or negative temperatures are treated as 6500 K.
pub fn hdembree_blackbody_rgb(kelvin: f64) -> DVec3 {
    let t = if kelvin.is_finite() && kelvin >= 0.0 {
        kelvin
    } else {
        6500.0
    };
    let (u, v) = krystek_planckian_uv(t);
    let d = 2.0 * u - 8.0 * v + 4.0;
    let (x, y) = (3.0 * u / d, 2.0 * v / d);
    let xyz = [x / y, 1.0, (1.0 - x - y) / y];
    let mut rgb = [0.0f64; 3];
    for (i, out) in rgb.iter_mut().enumerate() {
        let m = XYZ_TO_REC709[i];
        *out = (m[0] * xyz[0] + m[1] * xyz[1] + m[2] * xyz[2]).abs();
    }
    let max = rgb[0].max(rgb[1]).max(rgb[2]);
    let c = DVec3::new(rgb[0] / max, rgb[1] / max, rgb[2] / max);
    let lum = REC709_LUMINANCE[0] * c.x + REC709_LUMINANCE[1] * c.y + REC709_LUMINANCE[2] * c.z;
    let out = c / lum;
    if out.is_finite() { out } else { DVec3::ONE }
}

/// The colour multiplier of `inputs:colorTemperature` for a profile: [`spec_blackbody_rgb`] for
/// [`Profile::Spec`], [`hdembree_blackbody_rgb`] for [`Profile::HdEmbree`].
pub fn color_temperature_rgb(kelvin: f64, profile: Profile) -> DVec3 {
    match profile {
        Profile::Spec => spec_blackbody_rgb(kelvin),
        Profile::HdEmbree => hdembree_blackbody_rgb(kelvin),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spec_is_white_at_6500() {
        assert_eq!(spec_blackbody_rgb(6500.0), DVec3::ONE);
        let u = usdlux_blackbody_rgb(6500.0);
        assert!(
            (u - DVec3::new(1.043_333, 0.983_624, 1.034_613))
                .abs()
                .max_element()
                < 1e-6
        );
    }

    #[test]
    fn hdembree_documented_values() {
        let c = hdembree_blackbody_rgb(6500.0);
        assert!((c - DVec3::new(1.0442, 0.9833, 1.0357)).abs().max_element() < 1e-4);
        let c = hdembree_blackbody_rgb(2000.0);
        assert!((c - DVec3::new(2.5199, 0.6470, 0.0204)).abs().max_element() < 1e-4);
        // Luminance 1 by construction.
        let l = REC709_LUMINANCE[0] * c.x + REC709_LUMINANCE[1] * c.y + REC709_LUMINANCE[2] * c.z;
        assert!((l - 1.0).abs() < 1e-14);
    }
}
