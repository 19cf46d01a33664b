//! `conductor_bsdf` (spec: "conductor_bsdf", "Conductor Fresnel Equations"): GGX reflection
//! with the complex-index Fresnel curve per channel, a mirror below [`crate::DELTA_ALPHA`].
//!
//! Energy (Turquin 2019, spec "Energy Compensation"): `f = f_ss (1 + F̄ (1 − E_ss)/E_ss)`
//! per channel, `F̄` from the generalized-Schlick (F82) fit of the conductor curve
//! (`r0 = F(0°)`, tint matching `F` at `cos θ = 1/7`, `r90 = 1`, `q = 5`, Hoffman 2023) in
//! closed form. The directional albedo `k · Σ_b W_b F(c̄_b)` uses the tabulated histogram of
//! the GGX albedo over the Fresnel angle ([`crate::albedo::ggx_fresnel`]): exact for a white
//! conductor (`F ≡ 1`, e.g. `ior = extinction = 0`). With a thin film the curve is the Airy
//! reflectance over the conductor (`thinfilm.rs`), `F̄` its quadrature average.

use crate::albedo;
use crate::fresnel;
use crate::lobe::{Fresnel, Lobe, film};
use crate::{ScatterMode, ThinFilm};
use glam::{DVec2, DVec3};

/// The lobe for `wo` (local, `wo.z > 0`) and its directional albedo.
#[allow(clippy::too_many_arguments)]
pub(crate) fn lobe(
    weight: f64,
    eta: DVec3,
    k: DVec3,
    alpha: DVec2,
    retro: bool,
    thinfilm: ThinFilm,
    wo: DVec3,
) -> (Lobe, DVec3) {
    let (ggx, delta) = Lobe::distribution(alpha);
    let mut l = Lobe {
        ggx,
        delta,
        tint: DVec3::splat(weight),
        fresnel: Fresnel::Conductor { eta, k },
        eta: 1.0,
        mode: ScatterMode::R,
        thin: false,
        retro,
        k_r: DVec3::ONE,
        k_t: DVec3::ONE,
        film: film(thinfilm),
    };
    if delta {
        let a = l.f(wo.z) * weight;
        return (l, a);
    }
    let a = ggx.albedo_alpha();
    let ess = albedo::ggx(wo.z, a).max(1e-6);
    let fbar = if l.film.is_some() {
        l.fresnel_average()
    } else {
        let (r0, t) = fresnel::conductor_as_schlick(eta, k);
        fresnel::schlick_average(r0, t, DVec3::ONE, 5.0)
    };
    l.k_r = DVec3::ONE + fbar * ((1.0 - ess) / ess);
    let e = albedo::ggx_fresnel(wo.z, a, |c| l.f(c));
    (l, e * l.k_r * weight)
}
