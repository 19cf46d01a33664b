//! The cosine-weighted mean of a dome light's latlong texture (for `photometric:illuminance`).

use glam::DVec3;
use std::f64::consts::PI;

use crate::error::SpectralError;

/// Largest latlong texture accepted, in texels (2¹⁸ × 2¹⁷).
pub const MAX_LATLONG_TEXELS: usize = 1 << 35;

/// m = (1/π) ∫_{ω·up > 0} Y(ω) (ω·up) dω for a latlong luminance texture, the factor in
/// [`crate::dome_light_luminance`] (1 for a uniform texture of luminance 1).
///
/// Texture convention (OpenEXR latlong, as the spec's §2 states for DomeLight): row 0 is +Y,
/// the centre column is +Z, u = 0.25 is +X, longitude runs from +π at u = 0 to −π at u = 1. A
/// texel's direction is its centre, ω = (sin θ sin φ, cos θ, sin θ cos φ) with θ = π·v,
/// φ = π − 2π·u; its solid angle is exact, (2π/width)(cos θ_top − cos θ_bottom). `up` is the
/// stage's up axis in the texture's frame (+Y, or +Z after `poleAxis = "Z"`), normalised here.
/// `luminance` is row-major, `width × height` values (cd/m² relative units).
pub fn latlong_cosine_weighted_mean(
    width: usize,
    height: usize,
    luminance: &[f32],
    up: DVec3,
) -> Result<f64, SpectralError> {
    let invalid =
        |attribute: &str, value: f64, expected: &'static str| SpectralError::InvalidValue {
            attribute: attribute.to_owned(),
            value,
            expected,
        };
    if width == 0 || height == 0 || width.saturating_mul(height) > MAX_LATLONG_TEXELS {
        return Err(invalid(
            "dome texture size",
            width.saturating_mul(height) as f64,
            "1 to 2^35 texels",
        ));
    }
    if luminance.len() != width * height {
        return Err(invalid(
            "dome texture texel count",
            luminance.len() as f64,
            "width × height values",
        ));
    }
    let up = up.normalize_or_zero();
    if up == DVec3::ZERO || !up.is_finite() {
        return Err(invalid(
            "dome up axis",
            up.length(),
            "a finite non-zero vector",
        ));
    }
    let dphi = 2.0 * PI / width as f64;
    let mut sum = 0.0;
    for row in 0..height {
        let t0 = PI * row as f64 / height as f64;
        let t1 = PI * (row + 1) as f64 / height as f64;
        let dw = dphi * (t0.cos() - t1.cos());
        let theta = 0.5 * (t0 + t1);
        let (st, ct) = theta.sin_cos();
        for col in 0..width {
            let y = f64::from(luminance[row * width + col]);
            if !y.is_finite() {
                return Err(invalid("dome texture texel", y, "finite luminance"));
            }
            let phi = PI - 2.0 * PI * (col as f64 + 0.5) / width as f64;
            let (sp, cp) = phi.sin_cos();
            let c = DVec3::new(st * sp, ct, st * cp).dot(up);
            if c > 0.0 {
                sum += y * c * dw;
            }
        }
    }
    Ok(sum / PI)
}
