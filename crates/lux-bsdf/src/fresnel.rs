//! Fresnel reflectances of the spec's microfacet nodes: the dielectric curve in Lagarde's
//! form ("Dielectric Fresnel Equations"), the conductor curve with a complex index per
//! channel ("Conductor Fresnel Equations"), and Hoffman 2023's generalized Schlick curve with
//! its 82° tint ("Generalized Schlick Equations"); plus the incoherent thin-slab sum used for
//! thin-walled transmission.
//!
//! Thin-film iridescence (Belcour 2017) replaces these curves by the Airy reflectance of
//! `thinfilm.rs` when a film is present.

use glam::DVec3;

/// Dielectric Fresnel reflectance for `cos = |cos θ|` and relative index `eta` (transmitted
/// over incident), Lagarde's form of the unpolarized Fresnel equations:
/// `g = √(η² + c² − 1)`,
/// `F = ½ (g − c)²/(g + c)² · (1 + (c(g + c) − 1)²/(c(g − c) + 1)²)`;
/// total internal reflection (`η² + c² < 1`) gives 1.
pub fn dielectric(cos: f64, eta: f64) -> f64 {
    let c = cos.abs().min(1.0);
    let g2 = eta * eta + c * c - 1.0;
    if !(g2 > 0.0) {
        return 1.0;
    }
    let g = g2.sqrt();
    let a = (g - c) / (g + c);
    let b = (c * (g + c) - 1.0) / (c * (g - c) + 1.0);
    (0.5 * a * a * (1.0 + b * b)).clamp(0.0, 1.0)
}

/// One channel of the conductor Fresnel reflectance for `cos = |cos θ|` and complex index
/// `eta + i·k` (spec: "Conductor Fresnel Equations", Lagarde 2013):
/// `a² + b² = √((η² − κ² − sin²θ)² + 4η²κ²)`, `a = √(max(0, ½(a² + b² + η² − κ² − sin²θ)))`,
/// `Rs = (a² + b² − 2a cosθ + cos²θ)/(a² + b² + 2a cosθ + cos²θ)`,
/// `Rp = Rs (cos²θ(a² + b²) − 2a cosθ sin²θ + sin⁴θ)/(cos²θ(a² + b²) + 2a cosθ sin²θ + sin⁴θ)`,
/// `F = ½(Rs + Rp)`.
pub fn conductor_channel(cos: f64, eta: f64, k: f64) -> f64 {
    let (rs, rp) = conductor_polarized(cos, eta, k);
    let f = 0.5 * (rs + rp);
    if f.is_finite() {
        f.clamp(0.0, 1.0)
    } else {
        0.0
    }
}

/// The s- and p-polarized reflectances `(Rs, Rp)` of [`conductor_channel`].
pub fn conductor_polarized(cos: f64, eta: f64, k: f64) -> (f64, f64) {
    let c = cos.abs().min(1.0);
    let c2 = c * c;
    let s2 = 1.0 - c2;
    let t = eta * eta - k * k - s2;
    let a2b2 = (t * t + 4.0 * eta * eta * k * k).sqrt();
    let a = (0.5 * (a2b2 + t)).max(0.0).sqrt();
    let rs_num = a2b2 - 2.0 * a * c + c2;
    let rs_den = a2b2 + 2.0 * a * c + c2;
    let rs = if rs_den > 0.0 { rs_num / rs_den } else { 1.0 };
    let rp_num = c2 * a2b2 - 2.0 * a * c * s2 + s2 * s2;
    let rp_den = c2 * a2b2 + 2.0 * a * c * s2 + s2 * s2;
    let rp = if rp_den > 0.0 {
        rs * rp_num / rp_den
    } else {
        rs
    };
    (rs.clamp(0.0, 1.0), rp.clamp(0.0, 1.0))
}

/// The s- and p-polarized reflectances `(Rs, Rp)` of a dielectric interface of relative index
/// `eta` at `cos = |cos θ|`: `rs = (c − η c_t)/(c + η c_t)`, `rp = (η c − c_t)/(η c + c_t)`,
/// squared; `(1, 1)` on total internal reflection. Their mean is [`dielectric`].
pub fn dielectric_polarized(cos: f64, eta: f64) -> (f64, f64) {
    let c = cos.abs().min(1.0);
    let st2 = (1.0 - c * c) / (eta * eta);
    if !(st2 < 1.0) {
        return (1.0, 1.0);
    }
    let ct = (1.0 - st2).sqrt();
    let rs = (c - eta * ct) / (c + eta * ct);
    let rp = (eta * c - ct) / (eta * c + ct);
    ((rs * rs).min(1.0), (rp * rp).min(1.0))
}

/// [`conductor_channel`] per colour channel.
pub fn conductor(cos: f64, eta: DVec3, k: DVec3) -> DVec3 {
    DVec3::new(
        conductor_channel(cos, eta.x, k.x),
        conductor_channel(cos, eta.y, k.y),
        conductor_channel(cos, eta.z, k.z),
    )
}

/// `cos θmax = 1/7` of Hoffman's 82° dip.
const COS_MAX: f64 = 1.0 / 7.0;

/// The dip coefficient of the generalized Schlick curve,
/// `a = [r0 + (r90 − r0)(1 − cosθmax)^q](1 − t) / (cosθmax (1 − cosθmax)⁶)`.
pub fn schlick_dip(r0: DVec3, t: DVec3, r90: DVec3, q: f64) -> DVec3 {
    let base = r0 + (r90 - r0) * pow_q(1.0 - COS_MAX, q);
    base * (DVec3::ONE - t) / (COS_MAX * (1.0 - COS_MAX).powi(6))
}

/// Hoffman 2023's generalized Schlick reflectance (spec: "Generalized Schlick Equations"):
/// `F = r0 + (r90 − r0)(1 − c)^q − a c (1 − c)⁶` with `a` from [`schlick_dip`], clamped to
/// `[0, 1]` per channel so that `1 − F` stays a transmittance.
pub fn schlick(cos: f64, r0: DVec3, t: DVec3, r90: DVec3, q: f64) -> DVec3 {
    schlick_with_dip(cos, r0, r90, q, schlick_dip(r0, t, r90, q))
}

/// [`schlick`] with its dip coefficient `a` ([`schlick_dip`]) computed beforehand.
pub(crate) fn schlick_with_dip(cos: f64, r0: DVec3, r90: DVec3, q: f64, a: DVec3) -> DVec3 {
    let c = cos.abs().min(1.0);
    let m = 1.0 - c;
    let m2 = m * m;
    let f = r0 + (r90 - r0) * pow_q(m, q) - a * (c * (m2 * m2 * m2));
    f.clamp(DVec3::ZERO, DVec3::ONE)
}

/// `x^q` by multiplications for Schlick's usual exponent 5, else `powf`.
#[inline]
pub(crate) fn pow_q(x: f64, q: f64) -> f64 {
    if q == 5.0 {
        let x2 = x * x;
        x2 * x2 * x
    } else {
        x.powf(q)
    }
}

/// Cosine-weighted hemispherical average `2∫₀¹ F(μ) μ dμ` of the generalized Schlick curve, in
/// closed form (before clamping): `r0 + 2(r90 − r0)/((q + 1)(q + 2)) − a/126`
/// (`2∫μ²(1 − μ)⁶dμ = 2·B(3, 7) = 1/126`).
pub fn schlick_average(r0: DVec3, t: DVec3, r90: DVec3, q: f64) -> DVec3 {
    let a = schlick_dip(r0, t, r90, q);
    (r0 + (r90 - r0) * (2.0 / ((q + 1.0) * (q + 2.0))) - a / 126.0).clamp(DVec3::ZERO, DVec3::ONE)
}

/// Normal-incidence reflectance of a dielectric, `((η − 1)/(η + 1))²`.
pub fn f0_from_ior(eta: f64) -> f64 {
    let r = (eta - 1.0) / (eta + 1.0);
    r * r
}

/// The Schlick-to-IOR inversion `η = (1 + √F0)/(1 − √F0)` (F0 clamped to `[0, 0.99]`).
pub fn ior_from_f0(f0: f64) -> f64 {
    let s = f0.clamp(0.0, 0.99).sqrt();
    (1.0 + s) / (1.0 - s)
}

/// Reflectance of a non-absorbing thin slab whose two faces each reflect `F`, summing the
/// incoherent inter-reflections: `F + (1 − F)² F / (1 − F²) = 2F / (1 + F)`; its
/// transmittance is `(1 − F)/(1 + F)`.
pub fn slab(f: DVec3) -> DVec3 {
    2.0 * f / (DVec3::ONE + f)
}

/// The generalized Schlick parameters `(r0, t)` (with `r90 = 1`, `q = 5`) that match a
/// conductor at normal incidence and at `cos θ = 1/7` (Hoffman 2023's F82 fit).
pub fn conductor_as_schlick(eta: DVec3, k: DVec3) -> (DVec3, DVec3) {
    let r0 = conductor(1.0, eta, k);
    let f82 = conductor(COS_MAX, eta, k);
    let base = r0 + (DVec3::ONE - r0) * (1.0 - COS_MAX).powi(5);
    let t = DVec3::new(
        if base.x > 0.0 { f82.x / base.x } else { 1.0 },
        if base.y > 0.0 { f82.y / base.y } else { 1.0 },
        if base.z > 0.0 { f82.z / base.z } else { 1.0 },
    );
    (r0, t)
}
