//! Thin-film iridescence (spec: "Thin-Film Iridescence" and the "Thin-Film Iridescence Model"
//! appendix, Belcour & Barla 2017): the Airy reflectance of outer medium (η₁ = 1) / film
//! (`thinfilm_ior` η₂, `thinfilm_thickness` d nm) / substrate, summed per polarization with
//! the spectral interference terms integrated against Gaussian fits of the CIE matching
//! functions, and converted to linear Rec.709.
//!
//! Per the appendix:
//! * interface 1: dielectric Fresnel `R₁₂` at `cos θ`, `T₁₂ = 1 − R₁₂`, film angle
//!   `cos θt = √(1 − sin²θ/η₂²)`; phase `φ₂₁ˢ = π`, `φ₂₁ᵖ = π` below Brewster's angle
//!   `atan(η₂)`, else 0;
//! * interface 2 at `θt`: the substrate's polarized reflectances relative to the film
//!   (dielectric `η₃/η₂`; conductor `(η₃/η₂, κ₃/η₂)`; Schlick: its curve at `cos θt` for both
//!   polarizations) and phases (the complex-index `atan2` formulas; Schlick: the 0/π step);
//! * optical path difference `Δ = 2η₂ cos θt d·10⁻⁹`;
//! * `I = R₁₂ + R_dc + Σ_{m=1..M} C_m·2𝒮(mΔ, m(φ₂₃ + φ₂₁))` with
//!   `R_dc = T₁₂² R₂₃/(1 − R₁₂R₂₃)`, `C₀ = R_dc − T₁₂`, `C_m = C_{m−1}√(R₁₂R₂₃)`, `M = 2`
//!   orders (the spec leaves `M` open; Belcour's reference uses 2);
//! * `F = ½(Iᵖ + Iˢ)`, clamped to `[0, 1]`.
//!
//! Colour: the sensitivity terms `𝒮` are XYZ and go through the XYZ → linear Rec.709 matrix;
//! the incoherent part `R₁₂ + R_dc` is a flat spectrum and is added per RGB channel directly
//! (as the glTF iridescence reference does), so that an index-matched film (`η₂ = 1`) or a
//! thick one leaves the substrate's colour unchanged — applying the matrix to it would tint
//! white by illuminant E's Rec.709 coordinates (1.20, 0.95, 0.91). Conductor and Schlick
//! substrates are evaluated per channel with that channel's substrate values (channel `c` of
//! the result uses the substrate's channel `c`).

use crate::fresnel;
use glam::DVec3;
use std::f64::consts::PI;

/// XYZ → linear Rec.709 (the spec's `M_XYZ→lin_rec709`).
const XYZ_TO_REC709: [[f64; 3]; 3] = [
    [3.2404542, -1.5371385, -0.4985314],
    [-0.9692660, 1.8760108, 0.0415560],
    [0.0556434, -0.2040259, 1.0572252],
];

/// The film's substrate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Substrate {
    /// A dielectric of index `η₃` (relative to the outer medium).
    Dielectric(f64),
    /// A conductor `η₃ + iκ₃` per channel.
    Conductor(DVec3, DVec3),
    /// The generalized Schlick curve `(r0, t, r90, q)` with effective index `η₃`.
    Schlick {
        /// `color0`.
        r0: DVec3,
        /// `color82`.
        t: DVec3,
        /// `color90`.
        r90: DVec3,
        /// `exponent`.
        q: f64,
        /// Schlick-to-IOR inversion of `color0`.
        eta3: f64,
    },
}

/// The spectral sensitivity `𝒮(Δ, φ)` in XYZ (normalised by `1.0685·10⁻⁷`):
/// `Σ v √(2πσ²) cos(μ·2πΔ + φ) exp(−σ²(2πΔ)²)` with the spec's fitted `(v, μ, σ²)` per
/// channel and the second X lobe.
pub fn sensitivity(opd: f64, shift: f64) -> DVec3 {
    let ph = 2.0 * PI * opd;
    let g = |v: f64, mu: f64, s2: f64| {
        v * (2.0 * PI * s2).sqrt() * (mu * ph + shift).cos() * (-s2 * ph * ph).exp()
    };
    let x = g(5.4856e-13, 1.6810e6, 4.3278e9) + g(9.7470e-14, 2.2399e6, 4.5282e9);
    let y = g(4.4201e-13, 1.7953e6, 9.3046e9);
    let z = g(5.2481e-13, 2.2084e6, 6.6121e9);
    DVec3::new(x, y, z) / 1.0685e-7
}

fn to_rec709(xyz: DVec3) -> DVec3 {
    let m = XYZ_TO_REC709;
    DVec3::new(
        m[0][0] * xyz.x + m[0][1] * xyz.y + m[0][2] * xyz.z,
        m[1][0] * xyz.x + m[1][1] * xyz.y + m[1][2] * xyz.z,
        m[2][0] * xyz.x + m[2][1] * xyz.y + m[2][2] * xyz.z,
    )
}

/// Phases `(φ₂₃ᵖ, φ₂₃ˢ)` at the film–substrate interface for a substrate `η₃ + iκ₃` (the
/// spec's `k̄`, `A`, `B`, `U`, `V` and `atan2` formulas).
fn substrate_phases(eta2: f64, eta3: f64, k3: f64, ct: f64) -> (f64, f64) {
    let eta3 = eta3.max(1e-6);
    let kb = k3 / eta3;
    let st2 = 1.0 - ct * ct;
    let a = eta3 * eta3 * (1.0 - kb * kb) - eta2 * eta2 * st2;
    let b = (a * a + (2.0 * eta3 * eta3 * kb).powi(2)).sqrt();
    let u = ((a + b) / 2.0).max(0.0).sqrt();
    let v = ((b - a) / 2.0).max(0.0).sqrt();
    let phi_s = (2.0 * eta2 * v * ct).atan2(u * u + v * v - (eta2 * ct).powi(2));
    let phi_p = (2.0 * eta2 * eta3 * eta3 * ct * (2.0 * kb * u - (1.0 - kb * kb) * v))
        .atan2((eta3 * eta3 * (1.0 + kb * kb) * ct).powi(2) - eta2 * eta2 * (u * u + v * v));
    (phi_p, phi_s)
}

/// One polarization's Airy sum in RGB.
fn airy_pol(r12: f64, r23: f64, phase: f64, opd: f64) -> DVec3 {
    let t12 = 1.0 - r12;
    let den = 1.0 - r12 * r23;
    let rdc = if den > 1e-12 {
        t12 * t12 * r23 / den
    } else {
        0.0
    };
    let mut i = DVec3::splat(r12 + rdc);
    let r123 = (r12 * r23).max(0.0).sqrt();
    let mut cm = rdc - t12;
    for m in 1..=2 {
        cm *= r123;
        i += cm * to_rec709(2.0 * sensitivity(m as f64 * opd, m as f64 * phase));
    }
    i
}

/// The Airy reflectance `F_airy` at `cos = |cos θ|` for a film of `thickness` nm and index
/// `eta2` over `substrate`, per RGB channel in `[0, 1]`.
pub fn airy(cos: f64, thickness: f64, eta2: f64, substrate: Substrate) -> DVec3 {
    let c = cos.abs().min(1.0);
    let s2 = 1.0 - c * c;
    let st2 = s2 / (eta2 * eta2);
    if !(st2 < 1.0) {
        return DVec3::ONE;
    }
    let ct = (1.0 - st2).sqrt();
    let (r12s, r12p) = fresnel::dielectric_polarized(c, eta2);
    let phi21p = if s2.sqrt() < eta2 * c { PI } else { 0.0 };
    let phi21s = PI;
    let opd = 2.0 * eta2 * ct * thickness * 1e-9;
    let one = |r23p: f64, r23s: f64, phi23p: f64, phi23s: f64| {
        0.5 * (airy_pol(r12p, r23p, phi23p + phi21p, opd)
            + airy_pol(r12s, r23s, phi23s + phi21s, opd))
    };
    let mut out = DVec3::ZERO;
    match substrate {
        Substrate::Dielectric(eta3) => {
            let (rs, rp) = fresnel::dielectric_polarized(ct, eta3 / eta2);
            let (pp, ps) = substrate_phases(eta2, eta3, 0.0, ct);
            out = one(rp, rs, pp, ps);
        }
        Substrate::Conductor(eta, k) => {
            for ch in 0..3 {
                let (rs, rp) = fresnel::conductor_polarized(ct, eta[ch] / eta2, k[ch] / eta2);
                let (pp, ps) = substrate_phases(eta2, eta[ch], k[ch], ct);
                out[ch] = one(rp, rs, pp, ps)[ch];
            }
        }
        Substrate::Schlick {
            r0,
            t,
            r90,
            q,
            eta3,
        } => {
            let f = fresnel::schlick(ct, r0, t, r90, q);
            let p = if eta3 < eta2 { PI } else { 0.0 };
            for ch in 0..3 {
                out[ch] = one(f[ch], f[ch], p, p)[ch];
            }
        }
    }
    let fix = |v: f64| {
        if v.is_finite() {
            v.clamp(0.0, 1.0)
        } else {
            0.0
        }
    };
    DVec3::new(fix(out.x), fix(out.y), fix(out.z))
}
