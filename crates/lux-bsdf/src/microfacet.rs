//! The anisotropic GGX microfacet model of the spec's "Reflectance Models → Microfacet Model":
//! the normal distribution `D`, Smith's height-correlated masking-shadowing `G2` (and its
//! one-direction form `G1`), sampling of the distribution of visible normals, and the
//! Jacobians that turn a density of microfacet normals into a density of directions for
//! reflection and refraction (Walter et al. 2007).
//!
//! All vectors here are in the closure's local shading frame: `x` along the tangent, `y`
//! along the bitangent, `z` along the normal.

use glam::{DVec2, DVec3};
use std::f64::consts::PI;

/// Smallest roughness a rough lobe is evaluated with (below it `D` overflows to nonsense).
pub const MIN_ALPHA: f64 = 1.0e-4;

/// Anisotropic GGX (Trowbridge–Reitz) with roughness `ax` along the tangent, `ay` along the
/// bitangent (spec: "GGX Normal Distribution Function").
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ggx {
    /// α along the tangent.
    pub ax: f64,
    /// α along the bitangent.
    pub ay: f64,
}

impl Ggx {
    /// The distribution for the `roughness` input (α per axis, no remapping), each clamped
    /// to `[MIN_ALPHA, 1]` (the spec's accepted range; NaN becomes `MIN_ALPHA`).
    pub fn new(alpha: DVec2) -> Ggx {
        let c = |a: f64| {
            if a.is_nan() {
                MIN_ALPHA
            } else {
                a.clamp(MIN_ALPHA, 1.0)
            }
        };
        Ggx {
            ax: c(alpha.x),
            ay: c(alpha.y),
        }
    }

    /// `D(m) = 1 / (π αx αy ((mx/αx)² + (my/αy)² + mz²)²)` for `mz > 0`, else 0.
    pub fn d(&self, m: DVec3) -> f64 {
        if m.z <= 0.0 {
            return 0.0;
        }
        let x = m.x / self.ax;
        let y = m.y / self.ay;
        let s = x * x + y * y + m.z * m.z;
        1.0 / (PI * self.ax * self.ay * s * s)
    }

    /// Smith's `Λ(ω) = (−1 + √(1 + (αx² ωx² + αy² ωy²)/ωz²)) / 2` (Heitz 2014, eq. 86).
    ///
    /// For `αx = αy = α` it makes `G2` below exactly the spec's
    /// `2 cosθi cosθo / (λo cosθi + λi cosθo)` with `λ(c) = √(α² + (1 − α²)c²)`; for
    /// anisotropic roughness it is the exact anisotropic Smith term, where the spec
    /// approximates with `α = √(αx αy)`.
    pub fn lambda(&self, w: DVec3) -> f64 {
        let z2 = w.z * w.z;
        if z2 <= 0.0 {
            return f64::INFINITY;
        }
        let t = (self.ax * self.ax * w.x * w.x + self.ay * self.ay * w.y * w.y) / z2;
        0.5 * (-1.0 + (1.0 + t).sqrt())
    }

    /// `G1(ω) = 1 / (1 + Λ(ω))`.
    pub fn g1(&self, w: DVec3) -> f64 {
        1.0 / (1.0 + self.lambda(w))
    }

    /// Height-correlated `G2(ωo, ωi) = 1 / (1 + Λ(ωo) + Λ(ωi))` (spec: "Height-Correlated
    /// Smith Masking-Shadowing"; Heitz 2014 eq. 99). Uses `|cos|`, so it serves reflection and
    /// transmission alike.
    pub fn g2(&self, wo: DVec3, wi: DVec3) -> f64 {
        1.0 / (1.0 + self.lambda(wo) + self.lambda(wi))
    }

    /// The roughness seen along `w`'s azimuth, `√(αx² cos²φ + αy² sin²φ)`: the isotropic α
    /// with the same `Λ(ω)`; the albedo tables are indexed with it (an approximation for
    /// anisotropic lobes, exact for isotropic ones).
    pub fn projected_alpha(&self, w: DVec3) -> f64 {
        let s2 = w.x * w.x + w.y * w.y;
        if s2 <= 1e-24 {
            return (self.ax * self.ay).sqrt();
        }
        ((self.ax * self.ax * w.x * w.x + self.ay * self.ay * w.y * w.y) / s2).sqrt()
    }

    /// The isotropic roughness the albedo tables are read with: the RMS
    /// `√((αx² + αy²)/2)` (equal to α when isotropic). An approximation for anisotropic lobes
    /// (whose albedo depends on the azimuth of `ωo`): measured within ~2 % for `θo ≤ 60°` at
    /// `α = (0.1, 0.6)`, worse towards grazing along the smooth axis.
    pub fn albedo_alpha(&self) -> f64 {
        (0.5 * (self.ax * self.ax + self.ay * self.ay)).sqrt()
    }

    /// Samples a normal from the distribution of normals visible from `wo` (`wo.z > 0`),
    /// `D_wo(m) = G1(wo) max(0, wo·m) D(m) / wo.z`, by Dupuy & Benyoub 2023's spherical-cap
    /// construction: stretch `wo` to the α = 1 configuration, sample the visible hemisphere
    /// there as a uniform spherical cap, and unstretch.
    pub fn sample_visible(&self, wo: DVec3, u: [f64; 2]) -> DVec3 {
        let wh = DVec3::new(self.ax * wo.x, self.ay * wo.y, wo.z).normalize();
        let phi = 2.0 * PI * u[0];
        let z = (1.0 - u[1]) * (1.0 + wh.z) - wh.z;
        let s = (1.0 - z * z).max(0.0).sqrt();
        let c = DVec3::new(s * phi.cos(), s * phi.sin(), z);
        let h = c + wh;
        DVec3::new(self.ax * h.x, self.ay * h.y, h.z.max(1e-12)).normalize()
    }

    /// Density of [`Ggx::sample_visible`] per unit solid angle of `m`.
    pub fn pdf_visible(&self, wo: DVec3, m: DVec3) -> f64 {
        if wo.z <= 0.0 {
            return 0.0;
        }
        self.g1(wo) * wo.dot(m).max(0.0) * self.d(m) / wo.z
    }
}

/// Mirror direction of `w` about `m`: `2(w·m)m − w`.
pub fn reflect(w: DVec3, m: DVec3) -> DVec3 {
    2.0 * w.dot(m) * m - w
}

/// Refracts `wo` (on `m`'s side, `wo·m > 0`) through a facet `m` into a medium of relative
/// index `eta` (transmitted over incident): `wi = −wo/η + (c/η − cosθt) m`, with
/// `cos²θt = 1 − (1 − c²)/η²`. `None` on total internal reflection.
pub fn refract(wo: DVec3, m: DVec3, eta: f64) -> Option<DVec3> {
    let c = wo.dot(m);
    let s2 = (1.0 - c * c).max(0.0) / (eta * eta);
    if s2 >= 1.0 {
        return None;
    }
    let ct = (1.0 - s2).sqrt();
    Some((-wo / eta + (c / eta - ct) * m).normalize())
}

/// The generalized half vector of a refraction, `m ∝ wo + η wi`, turned to `m.z > 0`
/// (spec: "Microfacet BTDF", `ω_ht`). `None` when degenerate.
pub fn half_vector_t(wo: DVec3, wi: DVec3, eta: f64) -> Option<DVec3> {
    let h = wo + eta * wi;
    let l = h.length();
    if !(l > 1e-12) {
        return None;
    }
    let m = h / l;
    Some(if m.z < 0.0 { -m } else { m })
}

/// `dω_m/dω_i` of reflection, `1 / (4 |wo·m|)` (Walter 2007 eq. 14).
pub fn jacobian_reflect(wo_dot_m: f64) -> f64 {
    1.0 / (4.0 * wo_dot_m.abs())
}

/// `dω_m/dω_i` of refraction, `η² |wi·m| / (wo·m + η wi·m)²` (Walter 2007 eq. 17).
pub fn jacobian_refract(wo_dot_m: f64, wi_dot_m: f64, eta: f64) -> f64 {
    let den = wo_dot_m + eta * wi_dot_m;
    eta * eta * wi_dot_m.abs() / (den * den)
}
