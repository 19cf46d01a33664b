//! `generalized_schlick_bsdf` (spec: "generalized_schlick_bsdf", "Generalized Schlick
//! Equations"): the microfacet lobe of `dielectric_bsdf` with Hoffman 2023's F82 Schlick curve
//! (colour `F`, transmission `1 − F` per channel), refracting with the index of the
//! Schlick-to-IOR inversion of `mean(color0)`.
//!
//! Energy and albedo:
//! * `R`: `f_ss (1 + F̄ (1 − E_ss)/E_ss)` per channel, `F̄` in closed form, the albedo exact
//!   up to table accuracy (the curve is linear in three tabulated integrals).
//! * `T`, `RT` (approximation): the lobes are divided by the dielectric `E_R + E_T` at the
//!   inverted index, the reflection albedo is the exact Schlick one times that factor, the
//!   transmission albedo is the dielectric `E_T` scaled by `(1 − F̄_schlick)/(1 − F̄_dielectric)`.
//!   Exact when the curve is the dielectric one; otherwise off by the curves' difference.
//! * Thin-walled `T`/`RT` (approximation): divided by `E_ss`; reflection albedo
//!   `E_ss · slab(E_schlick/E_ss)`.
//!
//! Thin film (entering or thin-walled): the Airy reflectance over the Schlick substrate
//! (`thinfilm.rs`, effective index from `color0`); the reflection albedo then comes from the
//! Fresnel-angle histogram and `F̄` from quadrature.

use crate::albedo;
use crate::dielectric::{fresnel_average, snap_eta};
use crate::fresnel;
use crate::lobe::{Fresnel, Lobe, film};
use crate::{ScatterMode, ThinFilm};
use glam::{DVec2, DVec3};

/// The closure's inputs.
pub(crate) struct Inputs {
    pub weight: f64,
    pub r0: DVec3,
    pub t: DVec3,
    pub r90: DVec3,
    pub q: f64,
    pub alpha: DVec2,
    pub retro: bool,
    pub mode: ScatterMode,
    pub thinfilm: ThinFilm,
}

/// The lobe for `wo` (local, `wo.z > 0`) and its directional albedo.
pub(crate) fn lobe(i: &Inputs, wo: DVec3, entering: bool, thin_walled: bool) -> (Lobe, DVec3) {
    let (ggx, delta) = Lobe::distribution(i.alpha);
    let q = if i.q.is_finite() && i.q > 0.0 {
        i.q
    } else {
        5.0
    };
    let eta0 = fresnel::ior_from_f0((i.r0.x + i.r0.y + i.r0.z) / 3.0);
    let thin = thin_walled && i.mode != ScatterMode::R;
    let eta = if thin || entering {
        snap_eta(eta0)
    } else {
        snap_eta(1.0 / eta0)
    };
    let w = DVec3::splat(i.weight);
    let mut l = Lobe {
        ggx,
        delta,
        tint: w,
        fresnel: Fresnel::Schlick {
            r0: i.r0,
            t: i.t,
            r90: i.r90,
            q,
            dip: fresnel::schlick_dip(i.r0, i.t, i.r90, q),
        },
        eta,
        mode: i.mode,
        thin,
        retro: i.retro,
        k_r: DVec3::ONE,
        k_t: DVec3::ONE,
        film: if entering || thin_walled {
            film(i.thinfilm)
        } else {
            None
        },
    };
    if delta {
        let f = l.f(wo.z);
        let a = match i.mode {
            ScatterMode::R => f,
            ScatterMode::T => DVec3::ONE - f,
            ScatterMode::Rt => DVec3::ONE,
        };
        return (l, a * w);
    }
    let mu = wo.z;
    let a = ggx.albedo_alpha();
    let ess = albedo::ggx(mu, a).max(1e-6);
    let (es, fbar) = if l.film.is_some() {
        (albedo::ggx_fresnel(mu, a, |c| l.f(c)), l.fresnel_average())
    } else {
        (
            albedo::ggx_schlick(mu, a, i.r0, i.t, i.r90, q),
            fresnel::schlick_average(i.r0, i.t, i.r90, q),
        )
    };
    // Reflection and transmission albedos and the normalisation of `T`/`RT` (unused by `R`,
    // whose compensation needs neither: skipping them spares the dielectric lookups).
    let split = || {
        if thin {
            let er = ess * fresnel::slab((es / ess).min(DVec3::ONE));
            (er, DVec3::splat(ess) - er, 1.0 / ess)
        } else {
            let (dr, dt) = albedo::dielectric(mu, a, eta);
            let fd = fresnel_average(eta, false);
            let scale = if fd < 1.0 {
                (DVec3::ONE - fbar) / (1.0 - fd)
            } else {
                DVec3::ZERO
            };
            (es, dt * scale, 1.0 / (dr + dt).max(1e-6))
        }
    };
    let alb = match i.mode {
        ScatterMode::R => {
            l.k_r = DVec3::ONE + fbar * ((1.0 - ess) / ess);
            es * l.k_r
        }
        ScatterMode::T => {
            let (_, et, k) = split();
            l.k_t = DVec3::splat(k);
            et * k
        }
        ScatterMode::Rt => {
            let (er, et, k) = split();
            l.k_r = DVec3::splat(k);
            l.k_t = DVec3::splat(k);
            (er + et) * k
        }
    };
    (l, alb * w)
}
