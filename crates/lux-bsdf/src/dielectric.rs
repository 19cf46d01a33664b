//! `dielectric_bsdf` (spec: "dielectric_bsdf", "Dielectric Fresnel Equations", "Microfacet
//! Model"): GGX reflection and/or refraction (`R`, `T`, `RT`) weighted by the dielectric
//! Fresnel curve and `tint`, smooth (a delta lobe) below [`crate::DELTA_ALPHA`].
//!
//! * Relative index: `ior` entering, `1/ior` leaving (`|η − 1| ≥ 10⁻³`: an index-matched
//!   rough refraction is a delta, which this lobe does not represent). `ior = 0` (or negative,
//!   NaN) disables the Fresnel curve: the lobe reflects with `F = 1` and transmits nothing.
//! * Thin-walled (`T`, `RT`): the slab model of `lobe.rs` (transmission straight through,
//!   mirrored reflection lobe, `R = 2F/(1 + F)`); `R` mode is the plain interface.
//! * Energy (Turquin 2019): in `RT` and `T` the lobes are divided by the single-scattering
//!   `E_R + E_T` of the interface (tabulated, with the real Fresnel curve), so that the
//!   white `RT` furnace is 1 at every roughness (thin-walled: by `E_ss`); in `R` mode the
//!   reflection is multiplied by `1 + F̄ (1 − E_ss)/E_ss` (spec: "Energy Compensation", `F̄`
//!   the hemispherical average of `F`).
//! * Thin film: ignored.

use crate::ScatterMode;
use crate::albedo;
use crate::lobe::{Fresnel, Lobe};
use glam::{DVec2, DVec3};

/// Keeps a relative index away from 1 by at least `10⁻³`.
pub fn snap_eta(eta: f64) -> f64 {
    if eta >= 1.0 {
        eta.max(1.001)
    } else {
        eta.min(0.999)
    }
}

/// Hemispherical average of `F` seen from `wo`'s side: `F̄(η)` outside, and
/// `1 − (1 − F̄(1/η))·η²` from inside (`η < 1`, reciprocity of the transmittance).
pub fn fresnel_average(eta: f64, slab: bool) -> f64 {
    let f = albedo::dielectric_average(eta, slab);
    if eta < 1.0 && !slab {
        1.0 - (1.0 - f) * eta * eta
    } else {
        f
    }
}

/// The lobe of the closure for `wo` (local, `wo.z > 0`) and its directional albedo.
#[allow(clippy::too_many_arguments)]
pub(crate) fn lobe(
    tint: DVec3,
    ior: f64,
    alpha: DVec2,
    retro: bool,
    mode: ScatterMode,
    wo: DVec3,
    entering: bool,
    thin_walled: bool,
) -> (Lobe, DVec3) {
    let (ggx, delta) = Lobe::distribution(alpha);
    let no_fresnel = !(ior > 0.0) || !ior.is_finite();
    let mode = if no_fresnel { ScatterMode::R } else { mode };
    let thin = thin_walled && mode != ScatterMode::R;
    let eta = if no_fresnel {
        1.0
    } else if thin || entering {
        snap_eta(ior)
    } else {
        snap_eta(1.0 / ior)
    };
    let mut l = Lobe {
        ggx,
        delta,
        tint,
        fresnel: if no_fresnel {
            Fresnel::One
        } else {
            Fresnel::Dielectric
        },
        eta,
        mode,
        thin,
        retro,
        k_r: DVec3::ONE,
        k_t: DVec3::ONE,
    };
    if delta {
        let f = l.f(wo.z);
        let a = match mode {
            ScatterMode::R => tint * f,
            ScatterMode::T => tint * (DVec3::ONE - f),
            ScatterMode::Rt => tint,
        };
        return (l, a);
    }
    let mu = wo.z;
    let a = ggx.albedo_alpha();
    let ess = albedo::ggx(mu, a).max(1e-6);
    if no_fresnel {
        l.k_r = DVec3::splat(1.0 / ess);
        return (l, tint);
    }
    let (er, et, k) = if thin {
        let er = albedo::dielectric_thin(mu, a, eta);
        (er, (ess - er).max(0.0), 1.0 / ess)
    } else {
        let (er, et) = albedo::dielectric(mu, a, eta);
        (er, et, 1.0 / (er + et).max(1e-6))
    };
    let alb = match mode {
        ScatterMode::R => {
            let fbar = fresnel_average(eta, false);
            let kr = 1.0 + fbar * (1.0 - ess) / ess;
            l.k_r = DVec3::splat(kr);
            tint * (er * kr)
        }
        ScatterMode::T => {
            l.k_t = DVec3::splat(k);
            tint * (et * k)
        }
        ScatterMode::Rt => {
            l.k_r = DVec3::splat(k);
            l.k_t = DVec3::splat(k);
            tint * ((er + et) * k)
        }
    };
    (l, alb)
}
