//! `translucent_bsdf` (spec: "Lambertian Transmittance Equation"): `f_t = ρ/π` on the
//! hemisphere opposite `ωo`; its albedo is `ρ`.

use glam::DVec3;
use std::f64::consts::FRAC_1_PI;

/// `f cosθi` in the local frame (`wo.z > 0`; nonzero only for `wi.z < 0`).
pub fn eval(wi: DVec3, rho: DVec3) -> DVec3 {
    if wi.z >= 0.0 {
        DVec3::ZERO
    } else {
        rho * (-wi.z * FRAC_1_PI)
    }
}
