//! The cosine-weighted mean of a dome light's latlong texture (for `photometric:illuminance`).

use glam::DVec3;
use lux_math::{latlong_column_edge, latlong_direction_from_angles, latlong_row_edge};
use std::f64::consts::{FRAC_PI_2, PI};

use crate::error::SpectralError;

/// Largest latlong texture accepted, in texels (2¹⁸ × 2¹⁷).
pub const MAX_LATLONG_TEXELS: usize = 1 << 35;

/// m = (1/π) ∫_{ω·up > 0} Y(ω) (ω·up) dω for a latlong luminance texture, the factor in
/// [`crate::dome_light_luminance`] (1 for a uniform texture of luminance 1).
///
/// Texture convention: lux-math's latlong (spec §2 for DomeLight, OpenEXR latlong; see
/// [`lux_math::latlong_direction`]): row 0 is +Y, the centre column is +Z, u = 0.25 is +X, so
/// ω = (sin θ sin φ, cos θ, sin θ cos φ) with θ = π·v and the longitude φ = π − 2π·u, texel
/// edges by [`lux_math::latlong_row_edge`] and [`lux_math::latlong_column_edge`]. `up` is the
/// stage's up axis in the texture's frame (+Y, or +Z after `poleAxis = "Z"`), normalised here.
/// `luminance` is row-major, `width × height` values (cd/m² relative units).
///
/// The texture is taken as constant over each texel and the integral is **exact** for that
/// reconstruction: over a texel [θ₀, θ₁] × [φ₀, φ₁] with up = (a, c, b) in (x, y, z),
///
/// ∫∫ (ω·up) sin θ dθ dφ = S₂·(a·(cos φ₀ − cos φ₁) + b·(sin φ₁ − sin φ₀)) + c·S_c·(φ₁ − φ₀),
///
/// S₂ = ∫ sin²θ dθ, S_c = ∫ sin θ cos θ dθ. A texel the horizon (ω·up = 0) crosses — found
/// from the exact range of ω·up over the texel — is split in four, recursively, down to cells
/// of about 2π/4096 rad, which count by the sign of ω·up at their centre (an error of the
/// order of that side squared: ω·up vanishes on the horizon). A uniform
/// texture gives m = 1 for any size and any `up` (to rounding when `up` is an axis). The
/// renderer's bilinear lookup differs from this only within half a texel of a luminance step.
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
    for &y in luminance {
        if !y.is_finite() {
            return Err(invalid(
                "dome texture texel",
                f64::from(y),
                "finite luminance",
            ));
        }
    }
    let theta = |row: usize| latlong_row_edge(row, height);
    // Per column: φ₀ < φ₁ (φ decreases with u), a·∫sin φ + b·∫cos φ, and the range of
    // g(φ) = a sin φ + b cos φ.
    let cols: Vec<[f64; 5]> = (0..width)
        .map(|col| {
            let p0 = latlong_column_edge(col + 1, width);
            let p1 = latlong_column_edge(col, width);
            let (sp0, cp0) = p0.sin_cos();
            let (sp1, cp1) = p1.sin_cos();
            let (gmin, gmax) = sinusoid_range(up.x, up.z, p0, p1);
            [p0, p1, up.x * (cp0 - cp1) + up.z * (sp1 - sp0), gmin, gmax]
        })
        .collect();
    let dphi = 2.0 * PI / width as f64;
    // horizon cells are split down to a side of about 2π/4096 (error ∝ side², since ω·up
    // vanishes on the horizon), however coarse the texture
    let side = dphi.max(PI / height as f64);
    let depth = (side * 4096.0 / (2.0 * PI)).log2().ceil().clamp(0.0, 12.0) as u32;
    let mut sum = 0.0;
    for row in 0..height {
        let (t0, t1) = (theta(row), theta(row + 1));
        let (s2, sc) = theta_integrals(t0, t1);
        // sin θ over the row (it peaks at π/2), cos θ decreasing
        let (st0, st1) = (t0.sin(), t1.sin());
        let smax = if t0 < FRAC_PI_2 && t1 > FRAC_PI_2 {
            1.0
        } else {
            st0.max(st1)
        };
        let smin = st0.min(st1);
        let (c_lo, c_hi) = {
            let (a, b) = (up.y * t0.cos(), up.y * t1.cos());
            (a.min(b), a.max(b))
        };
        let mut row_sum = 0.0;
        for (col, &[p0, p1, phi_int, gmin, gmax]) in cols.iter().enumerate() {
            let y = f64::from(luminance[row * width + col]);
            if y == 0.0 {
                continue;
            }
            // interval bounds of ω·up = sin θ·g + c cos θ over the texel (conservative: a
            // texel near the horizon may take the exact test below without crossing it)
            let lo = (smin * gmin).min(smax * gmin) + c_lo;
            let hi = (smin * gmax).max(smax * gmax) + c_hi;
            let v = if hi <= 0.0 {
                0.0
            } else if lo >= 0.0 {
                s2 * phi_int + up.y * sc * dphi
            } else {
                clipped_cosine_integral(up, t0, t1, p0, p1, depth)
            };
            row_sum += y * v;
        }
        sum += row_sum;
    }
    Ok(sum / PI)
}

/// ∫∫ max(ω·up, 0) dω over the latlong cell [t0, t1] × [p0, p1] (see
/// [`latlong_cosine_weighted_mean`]), `depth` more quadrisections allowed where the horizon
/// crosses the cell.
fn clipped_cosine_integral(up: DVec3, t0: f64, t1: f64, p0: f64, p1: f64, depth: u32) -> f64 {
    let (lo, hi) = cosine_range(up, t0, t1, p0, p1);
    if hi <= 0.0 {
        return 0.0;
    }
    if lo >= 0.0 {
        return cosine_integral(up, t0, t1, p0, p1);
    }
    let (tm, pm) = (0.5 * (t0 + t1), 0.5 * (p0 + p1));
    if depth == 0 {
        let centre = latlong_direction_from_angles(tm, pm).dot(up);
        return if centre > 0.0 {
            cosine_integral(up, t0, t1, p0, p1)
        } else {
            0.0
        };
    }
    let d = depth - 1;
    clipped_cosine_integral(up, t0, tm, p0, pm, d)
        + clipped_cosine_integral(up, t0, tm, pm, p1, d)
        + clipped_cosine_integral(up, tm, t1, p0, pm, d)
        + clipped_cosine_integral(up, tm, t1, pm, p1, d)
}

/// S₂ = ∫ sin²θ dθ and S_c = ∫ sin θ cos θ dθ over [t0, t1].
fn theta_integrals(t0: f64, t1: f64) -> (f64, f64) {
    let s2 = 0.5 * (t1 - t0) - 0.25 * ((2.0 * t1).sin() - (2.0 * t0).sin());
    let sc = 0.5 * (t1.sin().powi(2) - t0.sin().powi(2));
    (s2, sc)
}

/// ∫∫ (ω·up) sin θ dθ dφ over [t0, t1] × [p0, p1], in closed form.
fn cosine_integral(up: DVec3, t0: f64, t1: f64, p0: f64, p1: f64) -> f64 {
    let (s2, sc) = theta_integrals(t0, t1);
    let (sp0, cp0) = p0.sin_cos();
    let (sp1, cp1) = p1.sin_cos();
    s2 * (up.x * (cp0 - cp1) + up.z * (sp1 - sp0)) + up.y * sc * (p1 - p0)
}

/// The exact range of ω·up = sin θ·(a sin φ + b cos φ) + c cos θ over [t0, t1] × [p0, p1]
/// (θ ∈ [0, π], so sin θ ≥ 0: the extremes over φ come first, then those over θ).
fn cosine_range(up: DVec3, t0: f64, t1: f64, p0: f64, p1: f64) -> (f64, f64) {
    let (gmin, gmax) = sinusoid_range(up.x, up.z, p0, p1);
    let lo = sinusoid_range(gmin, up.y, t0, t1).0;
    let hi = sinusoid_range(gmax, up.y, t0, t1).1;
    (lo, hi)
}

/// The range of p·sin t + q·cos t = R·cos(t − t*) over [t0, t1] (R = |(p, q)|, t* = atan2(p, q)):
/// the end values, and ±R where t* or t* + π falls inside.
fn sinusoid_range(p: f64, q: f64, t0: f64, t1: f64) -> (f64, f64) {
    let f = |t: f64| {
        let (s, c) = t.sin_cos();
        p * s + q * c
    };
    let (a, b) = (f(t0), f(t1));
    let (mut lo, mut hi) = (a.min(b), a.max(b));
    let r = p.hypot(q);
    let star = p.atan2(q);
    let inside = |t: f64| {
        // some t + 2kπ in [t0, t1]
        let k = ((t0 - t) / (2.0 * PI)).ceil();
        t + 2.0 * PI * k <= t1
    };
    if inside(star) {
        hi = r;
    }
    if inside(star + PI) {
        lo = -r;
    }
    (lo, hi)
}
