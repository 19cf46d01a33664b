//! `burley_diffuse_bsdf` (spec: "Burley Diffuse Reflectance Equations"): `f = ρ/π F_D(θi)
//! F_D(θo)` with `F_D(θ) = 1 + (F_D90 − 1)(1 − cosθ)⁵`, `F_D90 = ½ + 2σ(ωi·ωh)²`. Reciprocal;
//! not energy conserving (its albedo, tabulated in `albedo.rs`, exceeds 1 for rough
//! surfaces, as Burley's model does).

use glam::DVec3;
use std::f64::consts::FRAC_1_PI;

/// `f/ρ` in the local frame (zero below the horizon).
pub fn brdf(wo: DVec3, wi: DVec3, sigma: f64) -> f64 {
    if wi.z <= 0.0 || wo.z <= 0.0 {
        return 0.0;
    }
    let h = wo + wi;
    let l2 = h.length_squared();
    // ωi·ωh = |ωi + ωo|/2; squared: (1 + ωi·ωo)/2.
    let cd2 = if l2 > 0.0 {
        0.5 * (1.0 + wi.dot(wo))
    } else {
        0.0
    };
    let fd90 = 0.5 + 2.0 * sigma * cd2;
    let fd = |c: f64| 1.0 + (fd90 - 1.0) * (1.0 - c).powi(5);
    FRAC_1_PI * fd(wi.z) * fd(wo.z)
}

/// `f cosθi`.
pub fn eval(wo: DVec3, wi: DVec3, rho: DVec3, sigma: f64) -> DVec3 {
    rho * (brdf(wo, wi, sigma) * wi.z.max(0.0))
}

/// Directional albedo (tabulated).
pub fn albedo(mu: f64, rho: DVec3, sigma: f64) -> DVec3 {
    rho * crate::albedo::burley(mu, sigma)
}
