//! `subsurface_bsdf`, approximated for a renderer without volumes.
//!
//! The spec defines it as a unit Lambertian transmission over an `anisotropic_vdf` whose
//! coefficients come from `color` and `radius` ("Subsurface Scattering Model"): light leaves
//! at another point, with total diffuse reflectance `ρ = color` in the semi-infinite limit.
//! Here it is the local limit of that: **Lambertian reflection of `color`**, `f = ρ/π`, at the
//! same point. `radius` and `anisotropy` are unused (no spatial spread, no phase function).

use glam::DVec3;
use std::f64::consts::FRAC_1_PI;

/// `f cosθi` in the local frame.
pub fn eval(wi: DVec3, rho: DVec3) -> DVec3 {
    if wi.z <= 0.0 {
        DVec3::ZERO
    } else {
        rho * (wi.z * FRAC_1_PI)
    }
}
