//! `sheen_bsdf` (spec: "Conty-Kulla Sheen Equations"): the "Charlie" fibre distribution
//! `D(θh) = (2 + 1/r)(sin θh)^{1/r}/(2π)` with Neubelt & Pettineo's visibility,
//! `f = c D / (4(cosθi + cosθo − cosθi cosθo))`, albedo tabulated (`albedo.rs`), sampled
//! cosine-weighted. Reciprocal.
//!
//! `mode = zeltner` is the Zeltner 2022 LTC lobe of the spec's "Zeltner Sheen Model"
//! appendix ([`Zeltner`]): closed-form albedo `c·Ê(μo, r)`, sampled exactly by transforming a
//! cosine lobe; not reciprocal (the lobe's shape follows `ωo`).
//!
//! Conty–Kulla's roughness is clamped to `[0.02, 1]`, Zeltner's to `[0.01, 1]` (the spec's).

use crate::albedo::SHEEN_MIN_ROUGHNESS;
use glam::DVec3;
use std::f64::consts::PI;

/// The clamped roughness.
pub fn roughness(r: f64) -> f64 {
    if r.is_nan() {
        1.0
    } else {
        r.clamp(SHEEN_MIN_ROUGHNESS, 1.0)
    }
}

/// `f` per unit colour in the local frame (zero below the horizon).
pub fn conty_kulla(wo: DVec3, wi: DVec3, r: f64) -> f64 {
    if wi.z <= 0.0 || wo.z <= 0.0 {
        return 0.0;
    }
    let h = (wo + wi).normalize_or_zero();
    let sin2 = (1.0 - h.z * h.z).max(0.0);
    let inv = 1.0 / r;
    let d = (2.0 + inv) * sin2.powf(0.5 * inv) / (2.0 * PI);
    d / (4.0 * (wi.z + wo.z - wi.z * wo.z))
}

/// `f cosθi`.
pub fn eval(wo: DVec3, wi: DVec3, color: DVec3, r: f64) -> DVec3 {
    color * (conty_kulla(wo, wi, r) * wi.z.max(0.0))
}

/// Directional albedo.
pub fn albedo(mu: f64, color: DVec3, r: f64) -> DVec3 {
    color * crate::albedo::sheen(mu, r)
}

/// The Zeltner 2022 sheen lobe for one `ωo`, in a frame whose `x` axis is `ωo`'s projection
/// on the tangent plane (spec: "LTC Inverse Matrix", "Fitted Coefficients").
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Zeltner {
    /// `a(μo, r)`.
    pub a: f64,
    /// `b(μo, r)`.
    pub b: f64,
    /// `Ê(μo, r)`, the directional albedo (clamped to `[0, 1]`).
    pub albedo: f64,
}

impl Zeltner {
    /// The fitted `M⁻¹ = [[a, 0, b], [0, a, 0], [0, 0, 1]]` and albedo for `x = cosθo`,
    /// `y = r` (clamped to `[0.01, 1]`):
    /// `a = (2.58126x + 0.813703y)y / (1 + 0.310327x² + 2.60994xy)`,
    /// `b = √(1 − x)(y − 1)y³ / (0.0000254053 + 1.71228x − 1.71506xy + 1.34174y²)`,
    /// `Ê = exp(−½((x − m)/s)²)/(s√(2π)) + o` with the spec's rational `s`, `m`, `o`.
    pub fn new(mu: f64, r: f64) -> Zeltner {
        let x = mu.clamp(0.0, 1.0);
        let y = if r.is_nan() { 1.0 } else { r.clamp(0.01, 1.0) };
        let a = (2.58126 * x + 0.813703 * y) * y / (1.0 + 0.310327 * x * x + 2.60994 * x * y);
        let b = (1.0 - x).sqrt() * (y - 1.0) * y * y * y
            / (0.0000254053 + 1.71228 * x - 1.71506 * x * y + 1.34174 * y * y);
        let s = y * (0.0206607 + 1.58491 * y) / (0.0379424 + y * (1.32227 + y));
        let m = y * (-0.193854 + y * (-1.14885 + y * (1.7932 - 0.95943 * y * y))) / (0.046391 + y);
        let o =
            y * (0.000654023 + (-0.0207818 + 0.119681 * y) * y) / (1.26264 + y * (-1.92021 + y));
        let z = (x - m) / s;
        let e = (-0.5 * z * z).exp() / (s * (2.0 * PI).sqrt()) + o;
        Zeltner {
            a: a.max(1e-6),
            b,
            albedo: if e.is_finite() {
                e.clamp(0.0, 1.0)
            } else {
                0.0
            },
        }
    }

    /// The LTC density `D_o(M⁻¹ω/‖M⁻¹ω‖) a² / ‖M⁻¹ω‖³`, `D_o = max(cosθ, 0)/π`, for a
    /// direction in the lobe's frame; it integrates to 1, so `f cosθi = c Ê · pdf`.
    pub fn pdf(&self, w: DVec3) -> f64 {
        let v = DVec3::new(self.a * w.x + self.b * w.z, self.a * w.y, w.z);
        let l2 = v.length_squared();
        if !(v.z > 0.0) || !(l2 > 0.0) {
            return 0.0;
        }
        let l = l2.sqrt();
        (v.z / l) / PI * self.a * self.a / (l2 * l)
    }

    /// Maps a cosine-distributed direction `v` through `M = (M⁻¹)⁻¹`.
    pub fn warp(&self, v: DVec3) -> DVec3 {
        DVec3::new((v.x - self.b * v.z) / self.a, v.y / self.a, v.z).normalize()
    }
}

/// The lobe frame's axes: `x` along `wo`'s tangential part (any axis at normal incidence).
pub fn zeltner_axes(wo: DVec3) -> (DVec3, DVec3) {
    let t = DVec3::new(wo.x, wo.y, 0.0);
    let x = if t.length_squared() > 1e-20 {
        t.normalize()
    } else {
        DVec3::X
    };
    (x, DVec3::new(-x.y, x.x, 0.0))
}

/// `ω` (local shading frame) in the Zeltner lobe frame.
pub fn to_lobe(wo: DVec3, w: DVec3) -> DVec3 {
    let (x, y) = zeltner_axes(wo);
    DVec3::new(w.dot(x), w.dot(y), w.z)
}

/// `ω` from the Zeltner lobe frame back to the local shading frame.
pub fn from_lobe(wo: DVec3, v: DVec3) -> DVec3 {
    let (x, y) = zeltner_axes(wo);
    x * v.x + y * v.y + DVec3::Z * v.z
}
