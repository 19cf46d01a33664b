//! `sheen_bsdf` (spec: "Conty-Kulla Sheen Equations"): the "Charlie" fibre distribution
//! `D(θh) = (2 + 1/r)(sin θh)^{1/r}/(2π)` with Neubelt & Pettineo's visibility,
//! `f = c D / (4(cosθi + cosθo − cosθi cosθo))`, albedo tabulated (`albedo.rs`), sampled
//! cosine-weighted. Reciprocal.
//!
//! `mode = zeltner` falls back to this Conty–Kulla lobe (the Zeltner 2022 LTC lobe is not
//! implemented).
//!
//! The roughness is clamped to `[0.02, 1]`.

use crate::albedo::SHEEN_MIN_ROUGHNESS;
use glam::DVec3;
use std::f64::consts::PI;

/// The clamped roughness.
pub fn roughness(r: f64) -> f64 {
    if r.is_nan() {
        1.0
    } else {
        r.clamp(SHEEN_MIN_ROUGHNESS, 1.0)
    }
}

/// `f` per unit colour in the local frame (zero below the horizon).
pub fn conty_kulla(wo: DVec3, wi: DVec3, r: f64) -> f64 {
    if wi.z <= 0.0 || wo.z <= 0.0 {
        return 0.0;
    }
    let h = (wo + wi).normalize_or_zero();
    let sin2 = (1.0 - h.z * h.z).max(0.0);
    let inv = 1.0 / r;
    let d = (2.0 + inv) * sin2.powf(0.5 * inv) / (2.0 * PI);
    d / (4.0 * (wi.z + wo.z - wi.z * wo.z))
}

/// `f cosθi`.
pub fn eval(wo: DVec3, wi: DVec3, color: DVec3, r: f64) -> DVec3 {
    color * (conty_kulla(wo, wi, r) * wi.z.max(0.0))
}

/// Directional albedo.
pub fn albedo(mu: f64, color: DVec3, r: f64) -> DVec3 {
    color * crate::albedo::sheen(mu, r)
}
