//! Cosine-weighted hemisphere sampling (Malley's method over Shirley–Chiu's concentric disk),
//! the sampling of every diffuse-like lobe.

use glam::DVec3;
use std::f64::consts::{FRAC_1_PI, FRAC_PI_4, PI};

/// A direction on the upper hemisphere with density `cos θ / π`.
pub fn cosine_hemisphere(u: [f64; 2]) -> DVec3 {
    let (a, b) = (2.0 * u[0] - 1.0, 2.0 * u[1] - 1.0);
    let (r, phi) = if a == 0.0 && b == 0.0 {
        (0.0, 0.0)
    } else if a.abs() > b.abs() {
        (a, FRAC_PI_4 * (b / a))
    } else {
        (b, 0.5 * PI - FRAC_PI_4 * (a / b))
    };
    let (x, y) = (r * phi.cos(), r * phi.sin());
    DVec3::new(x, y, (1.0 - x * x - y * y).max(0.0).sqrt().max(1e-12))
}

/// Density of [`cosine_hemisphere`] (upper hemisphere only).
pub fn cosine_pdf(w: DVec3) -> f64 {
    w.z.max(0.0) * FRAC_1_PI
}
