//! Luminous flux of a photometric web: the exact integral of the bilinear interpolant, and the
//! midpoint rule of the reference renderer.
//!
//! Flux Φ = ∫ I dω. With the polar angle from the pole of the goniometer system the solid-angle
//! element is `sin θ dθ dφ` (type C, θ = vertical angle) or `cos V dV dH` (types A/B, V =
//! elevation from the equator).

use crate::file::PhotometricType;
use crate::web::PhotometricWeb;

/// The two weights `(A, B)` with `∫_{v0}^{v1} (c0 + (c1 − c0)(v − v0)/Δ) w(v) dv = A·c0 + B·c1`,
/// for `w = sin` (`polar = true`) or `w = cos`. Closed forms:
/// sin: `∫ sin = cos v0 − cos v1`, `∫ (v − v0) sin v = sin v1 − sin v0 − Δ cos v1`;
/// cos: `∫ cos = sin v1 − sin v0`, `∫ (v − v0) cos v = Δ sin v1 + cos v1 − cos v0`.
pub fn linear_segment_weights(v0: f64, v1: f64, polar: bool) -> (f64, f64) {
    let d = v1 - v0;
    let (s0, c0) = v0.sin_cos();
    let (s1, c1) = v1.sin_cos();
    let (whole, moment) = if polar {
        (c0 - c1, s1 - s0 - d * c1)
    } else {
        (s1 - s0, d * s1 + c1 - c0)
    };
    let b = moment / d;
    (whole - b, b)
}

/// Exact ∫ I dω of the bilinear interpolant over the web's angular domain.
///
/// Bilinear in (v, h) means that for each horizontal interval the h-integral is the trapezoid
/// `Δh·(L_j(v) + L_{j+1}(v))/2` exactly, where `L_j` is the piecewise-linear column j; each column
/// is then integrated against sin v (or cos V) in closed form ([`linear_segment_weights`]).
pub fn exact(web: &PhotometricWeb) -> f64 {
    let v = web.vertical_angles();
    let h = web.horizontal_angles();
    let nv = v.len();
    let polar = web.photometric_type() == PhotometricType::C;
    let weights: Vec<(f64, f64)> = v
        .windows(2)
        .map(|w| linear_segment_weights(w[0], w[1], polar))
        .collect();
    let column = |j: usize| {
        let r = &web.values()[j * nv..(j + 1) * nv];
        weights
            .iter()
            .enumerate()
            .map(|(i, (a, b))| a * r[i] + b * r[i + 1])
            .sum::<f64>()
    };
    let cols: Vec<f64> = (0..h.len()).map(column).collect();
    h.windows(2)
        .enumerate()
        .map(|(j, w)| 0.5 * (w[1] - w[0]) * (cols[j] + cols[j + 1]))
        .sum()
}

/// Midpoint rule as in the reference (hdEmbree's `PxrIESFile`): for every cell,
/// `Δh · Δv · sin(v + Δv/2) · (mean of the four corner values)` (cos for types A/B), summed.
pub fn midpoint(web: &PhotometricWeb) -> f64 {
    let v = web.vertical_angles();
    let h = web.horizontal_angles();
    let nv = v.len();
    let polar = web.photometric_type() == PhotometricType::C;
    let vals = web.values();
    let mut sum = 0.0;
    for j in 0..h.len() - 1 {
        let dh = h[j + 1] - h[j];
        let r0 = &vals[j * nv..(j + 1) * nv];
        let r1 = &vals[(j + 1) * nv..(j + 2) * nv];
        for i in 0..nv - 1 {
            let dv = v[i + 1] - v[i];
            let m = v[i] + 0.5 * dv;
            let w = if polar { m.sin() } else { m.cos() };
            let c = 0.25 * (r0[i] + r0[i + 1] + r1[i] + r1[i + 1]);
            sum += dh * dv * w * c;
        }
    }
    sum
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn segment_weights_integrate_constants_and_lines() {
        // constant 1 over [0, π]: ∫ sin = 2
        let (a, b) = linear_segment_weights(0.0, core::f64::consts::PI, true);
        assert!((a + b - 2.0).abs() < 1e-14);
        // I = 1 - v/π over [0, π]: ∫ (1 - v/π) sin v dv = 1 (so 2π after φ)
        assert!((a - 1.0).abs() < 1e-14, "{a}");
        // cos weight over [-π/2, π/2]: ∫ cos = 2, ∫ (v + π/2)/π cos v dv = 1
        let (a, b) = linear_segment_weights(
            -core::f64::consts::FRAC_PI_2,
            core::f64::consts::FRAC_PI_2,
            false,
        );
        assert!((a + b - 2.0).abs() < 1e-14);
        assert!((b - 1.0).abs() < 1e-14, "{b}");
    }
}
