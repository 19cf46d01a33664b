//! Directional albedos `E(μo, …) = ∫ f cos θi dωi` of the lobes without a closed form, the
//! quantity the spec's `layer` ("Layer Equation") and Turquin 2019's energy compensation
//! ("Directional Albedo and Energy Conservation") need.
//!
//! Every table is computed deterministically on first use (a [`OnceLock`], no threads) by
//! quadrature and interpolated bilinearly (trilinearly with the index axis):
//!
//! * microfacet lobes integrate over the distribution of visible normals: with `m` drawn from
//!   `D_wo`, `E = E_m[F · G2(ωo, ωi)/G1(ωo)]` for reflection and for refraction alike (the
//!   BTDF as written in `lobe.rs` makes the refraction Jacobian cancel), evaluated on a
//!   midpoint grid of the sampler's unit square;
//! * the diffuse-like lobes (Burley, sheen) integrate over the hemisphere with Gauss–Legendre
//!   in `cos θi` and the midpoint rule in azimuth.
//!
//! Axes: `√μo` and `√α` (denser near grazing and near smooth, where the albedos bend most),
//! `r = (η − 1)/(η + 1) ∈ [0, ½]` for the dielectric index (η ∈ [1, 3], clamped), the
//! Schlick exponent `q ∈ [1, 10]` (clamped), the sheen roughness `r ∈ [0.02, 1]`.

use crate::fresnel;
use crate::microfacet::{Ggx, reflect, refract};
use glam::{DVec2, DVec3};
use std::f64::consts::PI;
use std::sync::OnceLock;

const N_MU: usize = 32;
const N_ALPHA: usize = 32;
const N_MU_D: usize = 32;
const N_ALPHA_D: usize = 20;
const N_ETA: usize = 24;
const N_Q: usize = 10;
const N_ROUGH: usize = 32;
/// Sampler grid per axis for the microfacet integrals.
const GRID: usize = 64;
const GRID_D: usize = 40;

fn mu_of(x: f64) -> f64 {
    (x * x).max(1e-4)
}
fn alpha_of(x: f64) -> f64 {
    (x * x).max(1e-4)
}
fn wo_of(mu: f64) -> DVec3 {
    DVec3::new((1.0 - mu * mu).max(0.0).sqrt(), 0.0, mu)
}

/// Position of `x ∈ [0, 1]` on an axis of `n` nodes: lower node and fraction.
fn locate(x: f64, n: usize) -> (usize, f64) {
    let x = if x.is_nan() { 0.0 } else { x.clamp(0.0, 1.0) };
    let p = x * (n - 1) as f64;
    let i = (p.floor() as usize).min(n - 2);
    (i, p - i as f64)
}

/// Bilinear lookup of a row-major `n0 × n1` table (plus a stride for interleaved values).
fn lerp2(t: &[f64], n1: usize, stride: usize, off: usize, a: (usize, f64), b: (usize, f64)) -> f64 {
    let at = |i: usize, j: usize| t[(i * n1 + j) * stride + off];
    let (i, fi) = a;
    let (j, fj) = b;
    let v0 = at(i, j) * (1.0 - fj) + at(i, j + 1) * fj;
    let v1 = at(i + 1, j) * (1.0 - fj) + at(i + 1, j + 1) * fj;
    v0 * (1.0 - fi) + v1 * fi
}

/// Gauss–Legendre nodes and weights on `[0, 1]` (Newton on the Legendre recurrence).
pub(crate) fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
    let mut out = Vec::with_capacity(n);
    for i in 0..n {
        let mut x = (PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
        let mut dp = 1.0;
        for _ in 0..100 {
            let (mut p0, mut p1) = (1.0, x);
            for k in 2..=n {
                let p2 = ((2 * k - 1) as f64 * x * p1 - (k - 1) as f64 * p0) / k as f64;
                p0 = p1;
                p1 = p2;
            }
            dp = n as f64 * (x * p1 - p0) / (x * x - 1.0);
            let dx = p1 / dp;
            x -= dx;
            if dx.abs() < 1e-15 {
                break;
            }
        }
        let w = 2.0 / ((1.0 - x * x) * dp * dp);
        out.push((0.5 * (x + 1.0), 0.5 * w));
    }
    out
}

/// `∫ g(ωi) dωi` over the upper hemisphere for `wo` in the xz-plane: Gauss–Legendre in
/// `cos θi` (`n` nodes), midpoint in `φ ∈ [0, π]` doubled by the mirror symmetry `y → −y`.
fn hemisphere(gl: &[(f64, f64)], n_phi: usize, mut g: impl FnMut(DVec3) -> f64) -> f64 {
    let mut sum = 0.0;
    for &(mu, w) in gl {
        let s = (1.0 - mu * mu).max(0.0).sqrt();
        let mut row = 0.0;
        for k in 0..n_phi {
            let phi = PI * (k as f64 + 0.5) / n_phi as f64;
            row += g(DVec3::new(s * phi.cos(), s * phi.sin(), mu));
        }
        sum += w * row * (2.0 * PI / n_phi as f64);
    }
    sum
}

/// Mean over the `n × n` midpoint grid of the visible-normal sampler of `h(m)`.
fn visible_mean(ggx: &Ggx, wo: DVec3, n: usize, mut h: impl FnMut(DVec3)) {
    for i in 0..n {
        for j in 0..n {
            let u = [(i as f64 + 0.5) / n as f64, (j as f64 + 0.5) / n as f64];
            h(ggx.sample_visible(wo, u));
        }
    }
}

struct Tables {
    /// Per (μ, α): `[E_ss, T2, T1(q_0..q_9), (W_b, W_b c̄_b) × N_C]` — the F = 1 albedo, the
    /// Schlick bases, and the albedo's histogram over the Fresnel angle's offset `ωo·m − μo`.
    ggx: Vec<f64>,
    /// Per (r, μ, α): `[E_R, E_T]` entering (η ≥ 1), `[E_R, E_T]` leaving (1/η).
    diel: Vec<f64>,
    /// Per r: hemispherical average of `F` and of the slab's `2F/(1 + F)`.
    favg: Vec<f64>,
}

/// Bins of `c = ωo·m` in the Fresnel-angle histogram.
pub const N_C: usize = 32;
const GGX_STRIDE: usize = 2 + N_Q + 2 * N_C;
const DIEL_STRIDE: usize = 4;

fn q_of(k: usize) -> f64 {
    1.0 + 9.0 * k as f64 / (N_Q - 1) as f64
}
fn eta_of(k: usize) -> f64 {
    let r = 0.5 * k as f64 / (N_ETA - 1) as f64;
    (1.0 + r) / (1.0 - r)
}

fn ggx_tables() -> &'static Tables {
    static T: OnceLock<Tables> = OnceLock::new();
    T.get_or_init(build)
}

fn build() -> Tables {
    let mut ggx = vec![0.0; N_MU * N_ALPHA * GGX_STRIDE];
    for i in 0..N_MU {
        let wo = wo_of(mu_of(i as f64 / (N_MU - 1) as f64));
        for j in 0..N_ALPHA {
            let a = alpha_of(j as f64 / (N_ALPHA - 1) as f64);
            let d = Ggx::new(DVec2::splat(a));
            let g1 = d.g1(wo);
            let mut acc = [0.0; GGX_STRIDE];
            visible_mean(&d, wo, GRID, |m| {
                let wi = reflect(wo, m);
                if wi.z <= 0.0 {
                    return;
                }
                let w = d.g2(wo, wi) / g1;
                let c = wo.dot(m).clamp(0.0, 1.0);
                acc[0] += w;
                acc[1] += w * c * (1.0 - c).powi(6);
                for k in 0..N_Q {
                    acc[2 + k] += w * (1.0 - c).powf(q_of(k));
                }
                let dc = c - wo.z;
                let b = (((dc + 1.0) * 0.5 * N_C as f64) as usize).min(N_C - 1);
                acc[2 + N_Q + 2 * b] += w;
                acc[3 + N_Q + 2 * b] += w * dc;
            });
            let o = (i * N_ALPHA + j) * GGX_STRIDE;
            for k in 0..GGX_STRIDE {
                ggx[o + k] = acc[k] / (GRID * GRID) as f64;
            }
        }
    }
    let mut diel = vec![0.0; N_ETA * N_MU_D * N_ALPHA_D * DIEL_STRIDE];
    for e in 0..N_ETA {
        let eta = eta_of(e);
        for i in 0..N_MU_D {
            let wo = wo_of(mu_of(i as f64 / (N_MU_D - 1) as f64));
            for j in 0..N_ALPHA_D {
                let a = alpha_of(j as f64 / (N_ALPHA_D - 1) as f64);
                let d = Ggx::new(DVec2::splat(a));
                let g1 = d.g1(wo);
                let mut acc = [0.0; DIEL_STRIDE];
                visible_mean(&d, wo, GRID_D, |m| {
                    let c = wo.dot(m);
                    let wr = reflect(wo, m);
                    for (side, et) in [(0usize, eta), (2, 1.0 / eta)] {
                        let f = fresnel::dielectric(c, et);
                        if wr.z > 0.0 {
                            acc[side] += f * d.g2(wo, wr) / g1;
                        }
                        if f < 1.0
                            && let Some(wt) = refract(wo, m, et)
                            && wt.z < 0.0
                        {
                            acc[side + 1] += (1.0 - f) * d.g2(wo, wt) / g1;
                        }
                    }
                });
                let o = ((e * N_MU_D + i) * N_ALPHA_D + j) * DIEL_STRIDE;
                for k in 0..DIEL_STRIDE {
                    diel[o + k] = acc[k] / (GRID_D * GRID_D) as f64;
                }
            }
        }
    }
    let gl = gauss_legendre(64);
    let mut favg = vec![0.0; N_ETA * 2];
    for e in 0..N_ETA {
        let eta = eta_of(e);
        for &(mu, w) in &gl {
            let f = fresnel::dielectric(mu, eta);
            favg[2 * e] += 2.0 * w * mu * f;
            favg[2 * e + 1] += 2.0 * w * mu * 2.0 * f / (1.0 + f);
        }
    }
    Tables { ggx, diel, favg }
}

/// `E_ss(μo, α)`: directional albedo of the single-scattering GGX BRDF with `F = 1`
/// (the `E_ss` of the spec's "Energy Compensation").
pub fn ggx(mu: f64, alpha: f64) -> f64 {
    let t = ggx_tables();
    let a = locate(mu.max(0.0).sqrt(), N_MU);
    let b = locate(alpha.max(0.0).sqrt(), N_ALPHA);
    lerp2(&t.ggx, N_ALPHA, GGX_STRIDE, 0, a, b)
}

/// Albedo of the single-scattering GGX BRDF with the generalized Schlick Fresnel:
/// linear in the curve, `r0·E_ss + (r90 − r0)·∫f(1 − c)^q − a·∫f c(1 − c)⁶` with the three
/// integrals tabulated (`q` clamped to `[1, 10]`).
pub fn ggx_schlick(mu: f64, alpha: f64, r0: DVec3, t: DVec3, r90: DVec3, q: f64) -> DVec3 {
    let tb = ggx_tables();
    let a = locate(mu.max(0.0).sqrt(), N_MU);
    let b = locate(alpha.max(0.0).sqrt(), N_ALPHA);
    let e0 = lerp2(&tb.ggx, N_ALPHA, GGX_STRIDE, 0, a, b);
    let e2 = lerp2(&tb.ggx, N_ALPHA, GGX_STRIDE, 1, a, b);
    let (k, fk) = locate((q - 1.0) / 9.0, N_Q);
    let e1 = lerp2(&tb.ggx, N_ALPHA, GGX_STRIDE, 2 + k, a, b) * (1.0 - fk)
        + lerp2(&tb.ggx, N_ALPHA, GGX_STRIDE, 3 + k, a, b) * fk;
    let dip = fresnel::schlick_dip(r0, t, r90, q);
    (r0 * e0 + (r90 - r0) * e1 - dip * e2).max(DVec3::ZERO)
}

/// Albedo of the single-scattering GGX BRDF with an arbitrary smooth Fresnel curve `f(c)`:
/// `Σ_b W_b f(μo + δ̄_b)` over the tabulated histogram of the F = 1 albedo in the offset
/// `δ = ωo·m − μo` of the Fresnel angle from the macro angle (`N_C` bins over `[−1, 1]`,
/// each at its weighted mean; second-order accurate in the bin width for a smooth curve such
/// as a conductor's, and exact in the smooth limit where `ωo·m → μo`: storing offsets rather
/// than angles keeps interpolation in `μo` from smearing the curve).
pub fn ggx_fresnel(mu: f64, alpha: f64, f: impl Fn(f64) -> DVec3) -> DVec3 {
    let tb = ggx_tables();
    let a = locate(mu.max(0.0).sqrt(), N_MU);
    let b = locate(alpha.max(0.0).sqrt(), N_ALPHA);
    let mut e = DVec3::ZERO;
    for k in 0..N_C {
        let w = lerp2(&tb.ggx, N_ALPHA, GGX_STRIDE, 2 + N_Q + 2 * k, a, b);
        if w > 0.0 {
            let wdc = lerp2(&tb.ggx, N_ALPHA, GGX_STRIDE, 3 + N_Q + 2 * k, a, b);
            e += w * f((mu + wdc / w).clamp(0.0, 1.0));
        }
    }
    e
}

fn eta_axis(eta: f64) -> (usize, f64, bool) {
    let leaving = eta < 1.0;
    let e = if leaving { 1.0 / eta } else { eta };
    let r = (e - 1.0) / (e + 1.0);
    let (k, f) = locate(r / 0.5, N_ETA);
    (k, f, leaving)
}

fn diel_lookup(mu: f64, alpha: f64, eta: f64, off: usize) -> f64 {
    let tb = ggx_tables();
    let a = locate(mu.max(0.0).sqrt(), N_MU_D);
    let b = locate(alpha.max(0.0).sqrt(), N_ALPHA_D);
    let (k, fk, _) = eta_axis(eta);
    let n = N_MU_D * N_ALPHA_D * DIEL_STRIDE;
    let v0 = lerp2(
        &tb.diel[k * n..(k + 1) * n],
        N_ALPHA_D,
        DIEL_STRIDE,
        off,
        a,
        b,
    );
    let v1 = lerp2(
        &tb.diel[(k + 1) * n..(k + 2) * n],
        N_ALPHA_D,
        DIEL_STRIDE,
        off,
        a,
        b,
    );
    v0 * (1.0 - fk) + v1 * fk
}

/// Single-scattering albedos `(E_R, E_T)` of a rough dielectric interface of relative index
/// `eta` (`< 1` when leaving the denser medium; `η` or `1/η` clamped to `[1, 3]`).
///
/// Near the critical angle (leaving) `E_R` rises steeply with `μo`, too steeply for the
/// `(μo, α, η)` table when the lobe is narrow. So `E_R` is the table's for `α ≥ 0.3`, the
/// Fresnel-angle histogram's ([`ggx_fresnel`], exact in the smooth limit) for `α ≤ 0.1`,
/// blended linearly in between; `E_T` is the tabulated `E_R + E_T` (smooth: the Fresnel
/// split only moves energy between the two lobes) minus that `E_R`.
pub fn dielectric(mu: f64, alpha: f64, eta: f64) -> (f64, f64) {
    let off = if eta < 1.0 { 2 } else { 0 };
    let tr = diel_lookup(mu, alpha, eta, off);
    let sum = tr + diel_lookup(mu, alpha, eta, off + 1);
    let s = ((alpha - 0.1) / 0.2).clamp(0.0, 1.0);
    let er = if s >= 1.0 {
        tr
    } else {
        let h = ggx_fresnel(mu, alpha, |c| DVec3::splat(fresnel::dielectric(c, eta))).x;
        h + (tr - h) * s
    };
    (er, (sum - er).max(0.0))
}

/// Single-scattering reflection albedo of the thin-walled slab (`F_slab = 2F/(1 + F)`), from
/// the Fresnel-angle histogram; its transmission albedo is `E_ss(μo, α)` minus this.
pub fn dielectric_thin(mu: f64, alpha: f64, eta: f64) -> f64 {
    let e = if eta < 1.0 { 1.0 / eta } else { eta };
    ggx_fresnel(mu, alpha, |c| {
        fresnel::slab(DVec3::splat(fresnel::dielectric(c, e)))
    })
    .x
}

/// Cosine-weighted hemispherical average of the dielectric Fresnel curve from the outside,
/// `F̄(η) = 2∫₀¹ F(μ, η) μ dμ` (`slab`: of `2F/(1 + F)`), tabulated in `η`.
pub fn dielectric_average(eta: f64, slab: bool) -> f64 {
    let tb = ggx_tables();
    let e = if eta < 1.0 { 1.0 / eta } else { eta };
    let (k, fk, _) = eta_axis(e);
    let o = slab as usize;
    tb.favg[2 * k + o] * (1.0 - fk) + tb.favg[2 * k + 2 + o] * fk
}

/// A 2-D table over `(√μo, r)` of a hemispherical integral, built on first use.
struct Table2 {
    v: Vec<f64>,
}

impl Table2 {
    fn build(r_of: impl Fn(f64) -> f64, f: impl Fn(DVec3, DVec3, f64) -> f64) -> Table2 {
        let gl = gauss_legendre(48);
        let mut v = vec![0.0; N_MU * N_ROUGH];
        for i in 0..N_MU {
            let wo = wo_of(mu_of(i as f64 / (N_MU - 1) as f64));
            for j in 0..N_ROUGH {
                let r = r_of(j as f64 / (N_ROUGH - 1) as f64);
                v[i * N_ROUGH + j] = hemisphere(&gl, 96, |wi| f(wo, wi, r) * wi.z);
            }
        }
        Table2 { v }
    }
    fn get(&self, mu: f64, x: f64) -> f64 {
        lerp2(
            &self.v,
            N_ROUGH,
            1,
            0,
            locate(mu.max(0.0).sqrt(), N_MU),
            locate(x, N_ROUGH),
        )
    }
}

/// Sheen roughness range the table covers.
pub const SHEEN_MIN_ROUGHNESS: f64 = 0.02;

/// Directional albedo of the Conty–Kulla sheen lobe with unit colour, `E(μo, r)`
/// (`r` clamped to `[0.02, 1]`).
pub fn sheen(mu: f64, r: f64) -> f64 {
    static T: OnceLock<Table2> = OnceLock::new();
    let t = T.get_or_init(|| {
        Table2::build(
            |x| SHEEN_MIN_ROUGHNESS + (1.0 - SHEEN_MIN_ROUGHNESS) * x,
            crate::sheen::conty_kulla,
        )
    });
    t.get(mu, (r - SHEEN_MIN_ROUGHNESS) / (1.0 - SHEEN_MIN_ROUGHNESS))
}

/// Directional albedo of the Burley diffuse lobe with unit colour, `E(μo, σ)`.
pub fn burley(mu: f64, sigma: f64) -> f64 {
    static T: OnceLock<Table2> = OnceLock::new();
    let t = T.get_or_init(|| Table2::build(|x| x, crate::burley::brdf));
    t.get(mu, sigma)
}
