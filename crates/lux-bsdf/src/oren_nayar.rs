//! `oren_nayar_diffuse_bsdf` (spec: "Qualitative Oren-Nayar Reflectance Equations" and the
//! "EON Reflectance Model" appendix), in the local frame (`z` the normal, `wo.z > 0`).
//!
//! Both forms are reciprocal; `σ = 0` is exactly Lambertian `ρ/π`.

use glam::DVec3;
use std::f64::consts::{FRAC_1_PI, PI};

/// `c₁ = ½ − 2/(3π)` of EON.
const C1: f64 = 0.5 - 2.0 / (3.0 * PI);
/// `c₂ = ⅔ − 28/(15π)` of EON.
const C2: f64 = 2.0 / 3.0 - 28.0 / (15.0 * PI);

/// `s = ωi·ωo − cosθi cosθo` (`= sinθi sinθo cos(φi − φo)`).
fn s_term(wo: DVec3, wi: DVec3) -> f64 {
    wi.dot(wo) - wi.z * wo.z
}

/// Qualitative Oren–Nayar `f/ρ`: `(A + B·g)/π`, `A = 1 − 0.5 σ²/(σ² + 0.33)`,
/// `B = 0.45 σ²/(σ² + 0.09)`, `g = max(0, cos(φi − φo)) sinα tanβ`, which is
/// `max(0, s)/max(cosθi, cosθo)` since `sinα sinβ = sinθi sinθo` and `tanβ` takes the larger
/// cosine.
pub fn qualitative(wo: DVec3, wi: DVec3, sigma: f64) -> f64 {
    let s2 = sigma * sigma;
    let a = 1.0 - 0.5 * s2 / (s2 + 0.33);
    let b = 0.45 * s2 / (s2 + 0.09);
    let g = s_term(wo, wi).max(0.0) / wi.z.max(wo.z).max(1e-12);
    (a + b * g) * FRAC_1_PI
}

/// Directional albedo of the qualitative model per unit `ρ`, in closed form: integrating `g`
/// over azimuth gives `2 sinα tanβ`, and over `θi` split at `θo`
/// `E = A + (2B/π)[sinθo (θo − sinθo cosθo)/2 + tanθo (1 − sin³θo)/3]`.
pub fn qualitative_albedo(mu: f64, sigma: f64) -> f64 {
    let s2 = sigma * sigma;
    let a = 1.0 - 0.5 * s2 / (s2 + 0.33);
    let b = 0.45 * s2 / (s2 + 0.09);
    let mu = mu.clamp(0.0, 1.0);
    let th = mu.acos();
    let s = (1.0 - mu * mu).sqrt();
    let tail = if mu > 1e-9 {
        s / mu * (1.0 - s * s * s) / 3.0
    } else {
        0.0
    };
    a + 2.0 * b / PI * (s * (th - s * mu) / 2.0 + tail)
}

/// EON's `A = 1/(1 + c₁σ)`.
fn eon_a(sigma: f64) -> f64 {
    1.0 / (1.0 + C1 * sigma)
}

/// Fujii's `G(θ) = sinθ(θ − sinθ cosθ) + ⅔(sinθ(1 − sin³θ)/cosθ − sinθ)`.
fn fujii_g(mu: f64) -> f64 {
    let mu = mu.clamp(0.0, 1.0);
    let s = (1.0 - mu * mu).sqrt();
    let th = mu.acos();
    let q = if mu > 1e-9 {
        s * (1.0 - s * s * s) / mu
    } else {
        0.0
    };
    s * (th - s * mu) + 2.0 / 3.0 * (q - s)
}

/// EON's single-scatter directional albedo `Ê(θ, σ) = A + σA G(θ)/π` per unit `ρ`.
pub fn eon_e_hat(mu: f64, sigma: f64) -> f64 {
    let a = eon_a(sigma);
    a + sigma * a * fujii_g(mu) / PI
}

/// EON's average albedo `Ē(σ) = (1 + c₂σ)/(1 + c₁σ)`.
pub fn eon_e_bar(sigma: f64) -> f64 {
    (1.0 + C2 * sigma) / (1.0 + C1 * sigma)
}

/// EON `f` (per channel of `ρ`): `f_ss + f_ms`, `f_ss = ρA(1 + σ s/t)/π` with `s/t = s/max(cosθi,
/// cosθo)` for `s > 0`, else `s`; `f_ms = ρ_ms (1 − Ê(θo))(1 − Ê(θi)) / (π(1 − Ē))` with
/// `ρ_ms = ρ²Ē/(1 − ρ(1 − Ē))`.
pub fn eon(wo: DVec3, wi: DVec3, rho: DVec3, sigma: f64) -> DVec3 {
    if sigma <= 0.0 {
        return rho * FRAC_1_PI;
    }
    let s = s_term(wo, wi);
    let st = if s > 0.0 {
        s / wi.z.max(wo.z).max(1e-12)
    } else {
        s
    };
    let fss = rho * (eon_a(sigma) * (1.0 + sigma * st) * FRAC_1_PI);
    let eb = eon_e_bar(sigma);
    let rho_ms = rho * rho * eb / (DVec3::ONE - rho * (1.0 - eb));
    let fms = rho_ms
        * ((1.0 - eon_e_hat(wo.z, sigma)) * (1.0 - eon_e_hat(wi.z, sigma)) / (PI * (1.0 - eb)));
    (fss + fms).max(DVec3::ZERO)
}

/// EON albedo: `ρ Ê(θo) + ρ_ms (1 − Ê(θo))` (the multi-scatter lobe integrates
/// `(1 − Ê(θi))cosθi/π` to `1 − Ē`).
pub fn eon_albedo(mu: f64, rho: DVec3, sigma: f64) -> DVec3 {
    if sigma <= 0.0 {
        return rho;
    }
    let eb = eon_e_bar(sigma);
    let rho_ms = rho * rho * eb / (DVec3::ONE - rho * (1.0 - eb));
    let e = eon_e_hat(mu, sigma);
    rho * e + rho_ms * (1.0 - e)
}

/// `f cosθi` of the closure (`ρ` already times `weight`; colour clamped to `[0, 1]` for EON,
/// whose multi-scatter colour diverges at `ρ = 1/(1 − Ē)`).
pub fn eval(wo: DVec3, wi: DVec3, rho: DVec3, sigma: f64, eon_mode: bool) -> DVec3 {
    if wi.z <= 0.0 || wo.z <= 0.0 {
        return DVec3::ZERO;
    }
    if eon_mode {
        eon(wo, wi, rho, sigma) * wi.z
    } else {
        rho * (qualitative(wo, wi, sigma) * wi.z)
    }
}

/// Directional albedo of the closure.
pub fn albedo(mu: f64, rho: DVec3, sigma: f64, eon_mode: bool) -> DVec3 {
    if eon_mode {
        eon_albedo(mu, rho, sigma)
    } else {
        rho * qualitative_albedo(mu, sigma)
    }
}
