//! The latlong (equirectangular) texture convention of `DomeLight.inputs:texture:file`, defined
//! once for every lux crate (lux-sample's dome sampling, lux-spectral's dome illuminance, the
//! renderer's lookup).
//!
//! Convention (spec §2 for DomeLight, the OpenEXR latlong layout), in the dome's texture frame:
//! row 0 (v = 0) is +Y and the last row −Y; the centre column (u = 0.5) looks along +Z, u = 0.25
//! along +X, u = 0.75 along −X. With the colatitude θ = π·v from +Y and the longitude
//! λ = π·(1 − 2u) (from +π at u = 0 to −π at u = 1, measured from +Z towards +X),
//!
//! **d = (sin θ sin λ, cos θ, sin θ cos λ).**
//!
//! The texture's own frame is the dome's light-to-world transform, turned by `poleAxis`; that
//! turn is the caller's.

use core::f64::consts::{FRAC_1_PI, PI};
use glam::DVec3;

/// The unit direction of colatitude `theta` (from +Y) and longitude `longitude` (from +Z towards
/// +X) in the latlong frame: d = (sin θ sin λ, cos θ, sin θ cos λ) (see the module docs).
#[inline]
pub fn latlong_direction_from_angles(theta: f64, longitude: f64) -> DVec3 {
    let (st, ct) = theta.sin_cos();
    let (sl, cl) = longitude.sin_cos();
    DVec3::new(st * sl, ct, st * cl)
}

/// Latlong (u, v) ∈ \[0, 1\]² → unit direction in the texture's frame: θ = πv from +Y,
/// longitude λ = π(1 − 2u), d = (sin θ sin λ, cos θ, sin θ cos λ) (the spec §2 convention, see
/// the module docs).
#[inline]
pub fn latlong_direction(uv: [f64; 2]) -> DVec3 {
    latlong_direction_from_angles(PI * uv[1], PI * (1.0 - 2.0 * uv[0]))
}

/// The inverse of [`latlong_direction`] for a unit direction: v = acos(d_y)/π,
/// u = ½(1 − atan2(d_x, d_z)/π), the seam (λ = −π, u = 1) wrapped to u = 0; d_y is clamped to
/// \[−1, 1\] and u to \[0, 1\] against rounding. A NaN direction gives NaN.
#[inline]
pub fn latlong_uv(d: DVec3) -> [f64; 2] {
    let v = d.y.clamp(-1.0, 1.0).acos() * FRAC_1_PI;
    let lambda = d.x.atan2(d.z);
    let mut u = 0.5 * (1.0 - lambda * FRAC_1_PI);
    if u >= 1.0 {
        u -= 1.0;
    }
    [u.clamp(0.0, 1.0), v]
}

/// The colatitude θ = π·row/height of the edge above texel row `row` of a `height`-row latlong
/// texture (row 0's top edge is θ = 0, +Y; `row = height` the bottom edge, θ = π).
#[inline]
pub fn latlong_row_edge(row: usize, height: usize) -> f64 {
    PI * row as f64 / height as f64
}

/// The longitude λ = π − 2π·col/width of the left edge of texel column `col` of a
/// `width`-column latlong texture (column 0's left edge is λ = π; λ decreases with u): the
/// λ = π(1 − 2u) of [`latlong_direction`] at u = col/width, evaluated as π − 2π·col/width.
#[inline]
pub fn latlong_column_edge(col: usize, width: usize) -> f64 {
    PI - 2.0 * PI * col as f64 / width as f64
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spec_convention() {
        // Spec §2: top row +Y, centre column +Z, u = 0.25 is +X.
        assert!((latlong_direction([0.5, 0.0]) - DVec3::Y).length() < 1e-12);
        assert!((latlong_direction([0.5, 1.0]) + DVec3::Y).length() < 1e-12);
        assert!((latlong_direction([0.5, 0.5]) - DVec3::Z).length() < 1e-12);
        assert!((latlong_direction([0.25, 0.5]) - DVec3::X).length() < 1e-12);
        assert!((latlong_direction([0.75, 0.5]) + DVec3::X).length() < 1e-12);
        assert!((latlong_direction([0.0, 0.5]) + DVec3::Z).length() < 1e-12);
        let d = DVec3::new(0.3, -0.5, -0.8).normalize();
        assert!((latlong_direction(latlong_uv(d)) - d).length() < 1e-12);
        for (u, v) in [(0.1, 0.2), (0.5, 0.5), (0.9, 0.7), (0.25, 0.99)] {
            let [u2, v2] = latlong_uv(latlong_direction([u, v]));
            assert!(
                (u2 - u).abs() < 1e-12 && (v2 - v).abs() < 1e-12,
                "({u}, {v})"
            );
        }
    }

    #[test]
    fn texel_edges_follow_the_same_map() {
        // the edges are the (u, v) map at u = col/width, v = row/height
        assert_eq!(latlong_row_edge(0, 8), 0.0);
        assert_eq!(latlong_row_edge(8, 8), PI);
        assert_eq!(latlong_column_edge(0, 16), PI);
        assert_eq!(latlong_column_edge(16, 16), -PI);
        for (col, row) in [(3, 1), (8, 4), (13, 7)] {
            let (theta, lambda) = (latlong_row_edge(row, 8), latlong_column_edge(col, 16));
            let from_uv = latlong_direction([col as f64 / 16.0, row as f64 / 8.0]);
            let from_angles = latlong_direction_from_angles(theta, lambda);
            assert!((from_uv - from_angles).length() < 1e-15, "({col}, {row})");
        }
        // the equator's edge at u = 1/4 looks along +X
        let d = latlong_direction_from_angles(latlong_row_edge(4, 8), latlong_column_edge(4, 16));
        assert!((d - DVec3::X).length() < 1e-15, "{d}");
    }

    #[test]
    fn bad_directions_do_not_panic() {
        for d in [
            DVec3::ZERO,
            DVec3::NAN,
            DVec3::INFINITY,
            DVec3::new(0.0, 2.0, 0.0),
        ] {
            let [u, _] = latlong_uv(d);
            assert!(u.is_nan() || (0.0..=1.0).contains(&u));
        }
    }
}
