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

/// The Rec.709 luma weights rounded to four digits, as `UsdLuxBlackbodyTemperatureAsRgb`
/// normalises its result with them. Deliberately not [`luminance`]: the spec's colour depends on
/// these rounded values (and they enter a `const` table).
const REC709_LUMA: [f64; 3] = [0.2126, 0.7152, 0.0722];

/// The Catmull-Rom segment polynomials of [`KNOTS`], per segment: for each of r, g, b and
/// their Rec.709 luma `0.2126 r + 0.7152 g + 0.0722 b` (a cubic too), the coefficients
/// `[a, b, c, k₁]` of `((a t + b) t + c) t + k₁` (see [`usdlux_blackbody_rgb`]), computed at
/// compile time.
const SEGMENTS: [[[f64; 4]; 4]; 19] = segment_table();

const fn segment_table() -> [[[f64; 4]; 4]; 19] {
    let mut out = [[[0.0; 4]; 4]; 19];
    let mut seg = 0;
    while seg < 19 {
        let mut i = 0;
        while i < 3 {
            let (k0, k1, k2, k3) = (
                KNOTS[seg][i],
                KNOTS[seg + 1][i],
                KNOTS[seg + 2][i],
                KNOTS[seg + 3][i],
            );
            out[seg][i] = [
                -0.5 * k0 + 1.5 * k1 - 1.5 * k2 + 0.5 * k3,
                k0 - 2.5 * k1 + 2.0 * k2 - 0.5 * k3,
                -0.5 * k0 + 0.5 * k2,
                k1,
            ];
            i += 1;
        }
        let mut j = 0;
        while j < 4 {
            out[seg][3][j] = REC709_LUMA[0] * out[seg][0][j]
                + REC709_LUMA[1] * out[seg][1][j]
                + REC709_LUMA[2] * out[seg][2][j];
            j += 1;
        }
        seg += 1;
    }
    out
}

/// `UsdLuxBlackbodyTemperatureAsRgb(T)` (OpenUSD 26.11), computed in double precision.
///
/// `u = clamp((T − 1000)/9000, 0, 1)`; segment `s = ⌊18u⌋`, local `t = 18u − s`; uniform
/// Catmull-Rom through knots `k[s..s+4]`:
/// `rgb = ((a t + b) t + c) t + k₁` with `a = (−k₀ + 3k₁ − 3k₂ + k₃)/2`,
/// `b = k₀ − 5k₁/2 + 2k₂ − k₃/2`, `c = (k₂ − k₀)/2`; then `rgb /= 0.2126 r + 0.7152 g + 0.0722 b`
/// and each component is clamped at 0. Temperatures outside 1000–10000 K clamp to the ends; NaN
/// is treated as the schema default 6500 K.
///
/// Evaluation: `18u` as `(T − 1000)/500` (exact at every knot, so 6500 K lands on knot 12
/// with t = 0), the segment by truncation (no `floor` call), the per-segment coefficients of
/// r, g, b and of their luma from a table built at compile time (the luma cubic is evaluated
/// beside the colour ones rather than after them), each as `(a t + b)·t² + (c t + k₁)`, and
/// one division. Within a few ulp of the nested form.
#[inline]
pub fn usdlux_blackbody_rgb(kelvin: f64) -> DVec3 {
    let (rgb, l) = usdlux_unnormalized(kelvin);
    (rgb * (1.0 / l)).max(DVec3::ZERO)
}

/// The spline before its luma normalisation, and that luma.
#[inline(always)]
fn usdlux_unnormalized(kelvin: f64) -> (DVec3, f64) {
    let t_k = if kelvin.is_nan() { 6500.0 } else { kelvin };
    // clamp((T − 1000)/9000, 0, 1)·18 without the intermediate u
    let x = ((t_k - 1000.0) * (1.0 / 500.0)).clamp(0.0, 18.0);
    let seg = (x as u32).min(18); // x ≥ 0: truncation is ⌊x⌋
    let t = x - f64::from(seg);
    let t2 = t * t;
    let c = &SEGMENTS[seg as usize];
    let poly = |k: &[f64; 4]| (k[0] * t + k[1]) * t2 + (k[2] * t + k[3]);
    (
        DVec3::new(poly(&c[0]), poly(&c[1]), poly(&c[2])),
        poly(&c[3]),
    )
}

/// 1 / `UsdLuxBlackbodyTemperatureAsRgb(6500)` per component: the spline passes through knot
/// 12, so this is `luma(k₁₂)/k₁₂`.
const INV_USDLUX_6500: [f64; 3] = {
    let k = KNOTS[12];
    let l = REC709_LUMA[0] * k[0] + REC709_LUMA[1] * k[1] + REC709_LUMA[2] * k[2];
    [l / k[0], l / k[1], l / k[2]]
};

/// The `Spec` profile's colorTemperature colour: `usdlux_blackbody_rgb(T) /
/// usdlux_blackbody_rgb(6500)` component-wise, so 6500 K is exactly (1, 1, 1) as the 26.11 text
/// requires.
///
/// Evaluated as `max(rgb_c · luma(k₁₂)/k₁₂,c, 0) / luma(rgb)` with one division; at 6500 K the
/// spline is exactly `k₁₂` (t = 0), whose white is returned exactly (a rounding of the
/// product there would otherwise leave it an ulp off white).
#[inline]
pub fn spec_blackbody_rgb(kelvin: f64) -> DVec3 {
    let (rgb, l) = usdlux_unnormalized(kelvin);
    let k = KNOTS[12];
    if rgb == DVec3::new(k[0], k[1], k[2]) {
        return DVec3::ONE;
    }
    (rgb * DVec3::from(INV_USDLUX_6500) * (1.0 / l)).max(DVec3::ZERO)
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
pub const REC709_LUMINANCE: DVec3 = DVec3::new(
    0.212_639_005_871_510_36,
    0.715_168_678_767_755_9,
    0.072_192_315_360_733_71,
);

/// The Rec.709 relative luminance of a linear Rec.709 colour, **Y = c · REC709_LUMINANCE**
/// (`0.2126 r + 0.7152 g + 0.0722 b` to four digits; [`REC709_LUMINANCE`] has the exact
/// weights). The one luminance of lux: light power for selection, the importance of dome texels,
/// the colour of one nit, test probes. Evaluated as `c.x·Y_r + c.y·Y_g + c.z·Y_b` left to right
/// (glam's `dot`), so any caller writing that sum gets the same bits.
#[inline]
pub fn luminance(c: DVec3) -> f64 {
    c.dot(REC709_LUMINANCE)
}

/// Krystek (1985) rational fit of the Planckian locus: CIE 1960 (u, v) at `T` kelvin
/// (stated for 1000–15000 K).
pub fn krystek_planckian_uv(kelvin: f64) -> (f64, f64) {
    let [nu, du, nv, dv] = krystek_terms(kelvin);
    (nu / du, nv / dv)
}

/// Numerators and denominators of Krystek's fit, `[n_u, d_u, n_v, d_v]` with `u = n_u/d_u`,
/// `v = n_v/d_v` (quadratics in T).
#[inline(always)]
fn krystek_terms(t: f64) -> [f64; 4] {
    let t2 = t * t;
    [
        0.860_117_757 + 1.541_182_54e-4 * t + 1.286_412_12e-7 * t2,
        1.0 + 8.424_202_35e-4 * t + 7.081_451_63e-7 * t2,
        0.317_398_726 + 4.228_062_45e-5 * t + 4.204_816_91e-8 * t2,
        1.0 - 2.897_418_16e-5 * t + 1.614_560_53e-7 * t2,
    ]
}

/// The `HdEmbree` profile's colorTemperature colour: [`krystek_planckian_uv`] → xy
/// (`x = 3u/(2u − 8v + 4)`, `y = 2v/(2u − 8v + 4)`) → XYZ with Y = 1 → linear Rec.709 →
/// component-wise absolute value → ÷ max component → ÷ Rec.709 luminance.
/// 6500 K → (1.0442, 0.9833, 1.0357); 2000 K → (2.5199, 0.6470, 0.0204).
///
/// Evaluated with two divisions: with Krystek's `u = n_u/d_u`, `v = n_v/d_v`, the XYZ of
/// luminance 1 is `X = x/y = 3 n_u d_v·q`, `Z = (1 − x − y)/y = (4 d_u d_v − n_u d_v −
/// 10 n_v d_u)·q` with `q = 1/(2 d_u n_v)`; the ÷ max cancels in the ÷ luminance, so the
/// result is `|rgb| / (Y·|rgb|)`.
///
/// Non-finite or negative temperatures are treated as 6500 K.
#[inline]
pub fn hdembree_blackbody_rgb(kelvin: f64) -> DVec3 {
    let t = if kelvin.is_finite() && kelvin >= 0.0 {
        kelvin
    } else {
        6500.0
    };
    let [nu, du, nv, dv] = krystek_terms(t);
    let q = 1.0 / (2.0 * du * nv);
    let x = 3.0 * nu * dv * q;
    let z = (4.0 * du * dv - nu * dv - 10.0 * nv * du) * q;
    let m = &XYZ_TO_REC709;
    let rgb = DVec3::new(
        m[0][0] * x + m[0][1] + m[0][2] * z,
        m[1][0] * x + m[1][1] + m[1][2] * z,
        m[2][0] * x + m[2][1] + m[2][2] * z,
    )
    .abs();
    let out = rgb * (1.0 / luminance(rgb));
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
        assert!((luminance(c) - 1.0).abs() < 1e-14);
    }
}
