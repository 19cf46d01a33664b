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
//! * Thin film (entering or thin-walled; ignored seen from inside): the Airy reflectance
//!   over the dielectric (`thinfilm.rs`); `E_R` then comes from the Fresnel-angle histogram
//!   and `E_T` is approximated as the film-less `E_R + E_T` minus it.

use crate::albedo;
use crate::lobe::{Fresnel, Lobe, film};
use crate::{ScatterMode, ThinFilm};
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
    thinfilm: ThinFilm,
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
        // The film sits on the outside: seen from inside it is ignored.
        film: if entering || thin_walled {
            film(thinfilm)
        } else {
            None
        },
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
    // Single-scattering E_R (per channel with a film) and E_R + E_T.
    let (er, sum) = if thin {
        let er = if l.film.is_some() {
            albedo::ggx_fresnel(mu, a, |c| l.f(c))
        } else {
            DVec3::splat(albedo::dielectric_thin(mu, a, eta))
        };
        (er, ess)
    } else {
        let (er, et) = albedo::dielectric(mu, a, eta);
        let er_film = l.film.map(|_| albedo::ggx_fresnel(mu, a, |c| l.f(c)));
        (er_film.unwrap_or(DVec3::splat(er)), er + et)
    };
    let et = (DVec3::splat(sum) - er).max(DVec3::ZERO);
    let k = 1.0 / sum.max(1e-6);
    let alb = match mode {
        ScatterMode::R => {
            let fbar = if l.film.is_some() {
                l.fresnel_average()
            } else {
                DVec3::splat(fresnel_average(eta, false))
            };
            l.k_r = DVec3::ONE + fbar * ((1.0 - ess) / ess);
            tint * er * l.k_r
        }
        ScatterMode::T => {
            l.k_t = DVec3::splat(k);
            tint * et * k
        }
        ScatterMode::Rt => {
            l.k_r = DVec3::splat(k);
            l.k_t = DVec3::splat(k);
            tint * (er + et) * k
        }
    };
    (l, alb)
}
