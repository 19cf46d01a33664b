//! The UsdPreviewSurface BRDF (reflection only): a diffuse lobe under a GGX specular lobe,
//! under an optional white GGX clearcoat.
//!
//! With `c = cos θ` about the shading normal, `h = normalize(wo + wi)`, `T(c) = (1 − c/2)⁵` and
//! Schlick's `F(F0, x) = F0 + (1 − F0)(1 − x)⁵` (F90 = 1 for every lobe):
//!
//! ```text
//! f = clearcoat·f_c + a(cₒ)·a(cᵢ)·(f_s + f_d)
//! f_s = F(F0, wo·h)·D(h)·G₂ / (4 cₒ cᵢ)                     GGX, alpha = max(roughness², 1e-3)
//! f_c = F(F0c, wo·h)·D_c(h)·G₂c / (4 cₒ cᵢ)                 GGX, alpha = max(clearcoatRoughness², 1e-3)
//! f_d = 28/(23π)·ρ_d·(1 − F0)·(1 − T(cᵢ))·(1 − T(cₒ))      Ashikhmin–Shirley coupled diffuse
//! a(c) = 1 − clearcoat·Ê_c(c),  Ê_c(c) = F0c + (1 − F0c)·T(c)
//! ```
//!
//! Choices, against the UsdPreviewSurface specification:
//! - **Specular colour.** Metallic workflow (`useSpecularWorkflow` 0): `F0 = mix(R, diffuseColor,
//!   metallic)` with `R = ((1 − ior)/(1 + ior))²`, and the diffuse albedo
//!   `ρ_d = (1 − metallic)·diffuseColor`. Specular workflow: `F0 = specularColor`,
//!   `ρ_d = diffuseColor`. F90 is white for both workflows (the specification's metallic edge
//!   colour `F90 = diffuseColor` is not used).
//! - **Microfacets.** GGX (Trowbridge–Reitz), `alpha = roughness²`, clamped to at least
//!   `ALPHA_MIN` = 1e-3 so the BSDF is never a delta; Smith **height-correlated**
//!   masking–shadowing `G₂ = 1/(1 + Λ(wo) + Λ(wi))`; sampled by visible normals with Dupuy &
//!   Benyoub's spherical caps (2023), the density `G₁(wo)·D(h)/(4 cₒ)` per solid angle of `wi`
//!   (a reflected direction below the horizon is a failed sample).
//! - **Clearcoat.** White, weight `clearcoat`, roughness `clearcoatRoughness`, `F0c` from the
//!   same `ior` (the specification names the clearcoat among the users of `ior`).
//! - **Energy and reciprocity.** Every factor is symmetric in (wo, wi), so `f` is reciprocal.
//!   The one-sided bound `Ê(F0, c) = F0 + (1 − F0)·T(c)` is at least the directional albedo of
//!   a GGX lobe with Schlick's Fresnel for every `alpha ≤ 1` (it holds for a mirror since
//!   `(1 − c)⁵ ≤ T(c)`; for rough lobes it is checked numerically by the test
//!   `schlick_tail_albedo_below_bound`, worst ratio ≈ 0.97 at grazing mirrors), and the coupled diffuse has directional albedo exactly
//!   `ρ_d·(1 − F0)·(1 − T(cₒ))` (28/23 normalises `∫(1 − T(c))·c dω/π = 23/28`). So the base
//!   reflects at most `Ê(F0, cₒ) + (1 − F0)(1 − T(cₒ)) = 1` per channel, and with the coat at most
//!   `clearcoat·Ê_c(cₒ) + a(cₒ)·1 = 1`.
//! - **The diffuse-only case** (specular workflow, `specularColor` 0, no clearcoat) is not
//!   Lambertian: `f = f_d + f_s` with `F0 = 0`, a Schlick grazing sheen `(1 − wo·h)⁵` whose
//!   energy the diffuse gives up; at normal incidence and exitance `f = 28/(23π)·(31/32)²·ρ`
//!   (about 1.1425·ρ/π: brighter than Lambertian head-on), at grazing angles the diffuse vanishes.
//! - **Sanitised inputs** (so nothing panics or yields NaN): a non-finite colour channel or
//!   scalar takes its schema default; colours, `metallic`, `roughness`, `clearcoat` and
//!   `clearcoatRoughness` are clamped to \[0, 1\]; an `ior` that is not finite and > 0 becomes
//!   1.5 (the Fresnel term is the same for `ior` and `1/ior`; `ior` 1 gives `R = 0`).
//! - **Lobe selection.** `u[0]` picks diffuse, specular or clearcoat with probabilities in
//!   proportion to their albedo bounds at `wo` (the luminance of `a(cₒ)·ρ_d(1 − F0)(1 − T(cₒ))`,
//!   of `a(cₒ)·Ê(F0, cₒ)`, and `clearcoat·Ê_c(cₒ)`), and is stretched back to \[0, 1) for that
//!   lobe; the diffuse lobe is sampled by the cosine. [`PreviewBsdf::pdf`] is the mixture
//!   `Σ pₖ·pdfₖ`, the density of [`PreviewBsdf::sample`] exactly (one-sample MIS over lobes).

use super::BsdfSample;
use glam::DVec3;
use lux_math::Frame;
use lux_sample::warp::sample_cosine_hemisphere;
use std::f64::consts::{FRAC_1_PI, TAU};

/// Smallest GGX alpha (`roughness²` is raised to it): a roughness below √1e-3 ≈ 0.032 is as
/// glossy as 0.032, and the BSDF never becomes a delta.
const ALPHA_MIN: f64 = 1e-3;

/// 28/(23π), the normalisation of the Ashikhmin–Shirley coupled diffuse.
const DIFFUSE_NORM: f64 = 28.0 / (23.0 * std::f64::consts::PI);

/// Largest f64 below 1.
const ONE_MINUS_EPSILON: f64 = 1.0 - f64::EPSILON / 2.0;

/// UsdPreviewSurface inputs at one shading point, resolved to values (textures already looked up).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PreviewParams {
    /// `inputs:diffuseColor` (default 0.18 grey): the diffuse albedo, and the metal's `F0` in
    /// the metallic workflow.
    pub diffuse_color: DVec3,
    /// `inputs:useSpecularWorkflow` (0/1, default false): `F0 = specularColor` instead of
    /// `mix(((1 − ior)/(1 + ior))², diffuseColor, metallic)`.
    pub use_specular_workflow: bool,
    /// `inputs:specularColor` (default black): `F0` in the specular workflow.
    pub specular_color: DVec3,
    /// `inputs:metallic` (default 0): metallic workflow `F0` mix and diffuse scale `1 − metallic`.
    pub metallic: f64,
    /// `inputs:roughness` (default 0.5): specular GGX `alpha = max(roughness², 1e-3)`.
    pub roughness: f64,
    /// `inputs:clearcoat` (default 0): weight of the white clearcoat lobe.
    pub clearcoat: f64,
    /// `inputs:clearcoatRoughness` (default 0.01): clearcoat GGX `alpha = max(r², 1e-3)`.
    pub clearcoat_roughness: f64,
    /// `inputs:ior` (default 1.5): dielectric `F0 = ((1 − ior)/(1 + ior))²` of base and coat.
    pub ior: f64,
}

impl Default for PreviewParams {
    /// The UsdPreviewSurface schema defaults.
    fn default() -> PreviewParams {
        PreviewParams {
            diffuse_color: DVec3::splat(0.18),
            use_specular_workflow: false,
            specular_color: DVec3::ZERO,
            metallic: 0.0,
            roughness: 0.5,
            clearcoat: 0.0,
            clearcoat_roughness: 0.01,
            ior: 1.5,
        }
    }
}

impl PreviewParams {
    /// The inputs made safe: non-finite → schema default, colours and weights into \[0, 1\],
    /// `ior` not finite or ≤ 0 → 1.5.
    fn sanitised(&self) -> PreviewParams {
        let d = PreviewParams::default();
        let scalar = |v: f64, def: f64| {
            if v.is_finite() {
                v.clamp(0.0, 1.0)
            } else {
                def
            }
        };
        let colour = |c: DVec3, def: DVec3| {
            let ch = |v: f64, def: f64| {
                if v.is_finite() {
                    v.clamp(0.0, 1.0)
                } else {
                    def
                }
            };
            DVec3::new(ch(c.x, def.x), ch(c.y, def.y), ch(c.z, def.z))
        };
        PreviewParams {
            diffuse_color: colour(self.diffuse_color, d.diffuse_color),
            use_specular_workflow: self.use_specular_workflow,
            specular_color: colour(self.specular_color, d.specular_color),
            metallic: scalar(self.metallic, d.metallic),
            roughness: scalar(self.roughness, d.roughness),
            clearcoat: scalar(self.clearcoat, d.clearcoat),
            clearcoat_roughness: scalar(self.clearcoat_roughness, d.clearcoat_roughness),
            ior: if self.ior.is_finite() && self.ior > 0.0 {
                self.ior
            } else {
                d.ior
            },
        }
    }
}

/// The UsdPreviewSurface BSDF at one point, for one outgoing (viewer) direction.
#[derive(Clone, Copy, Debug)]
pub struct PreviewBsdf {
    /// Frame about the shading normal.
    frame: Frame,
    /// Unit direction to the viewer, local (z along the shading normal).
    wo: DVec3,
    /// False when `wo` (or the normal) is unusable or below the horizon: then `f = pdf = 0`.
    valid: bool,
    /// Specular lobe: GGX alpha, `F0`, and `cₒ·Λ(wo)`.
    alpha: f64,
    f0: DVec3,
    lambda_o: f64,
    /// Clearcoat lobe: weight, GGX alpha, `F0c`, and `cₒ·Λc(wo)`.
    coat: f64,
    alpha_c: f64,
    f0_c: f64,
    lambda_o_c: f64,
    /// `28/(23π)·ρ_d·(1 − F0)·(1 − T(cₒ))`: the diffuse `f` without the `wi` factor.
    diffuse_o: DVec3,
    /// Base attenuation by the coat towards the viewer, `a(cₒ)`.
    atten_o: f64,
    /// Lobe selection probabilities: diffuse, specular, clearcoat (sum 1 when valid).
    prob: [f64; 3],
}

/// `T(c) = (1 − c/2)⁵`, the Ashikhmin–Shirley transmission shape.
#[inline]
fn tail(c: f64) -> f64 {
    let t = 1.0 - 0.5 * c;
    let t2 = t * t;
    t2 * t2 * t
}

/// Schlick's `(1 − x)⁵` for `x ∈ [0, 1]`.
#[inline]
fn schlick_weight(x: f64) -> f64 {
    let t = (1.0 - x).clamp(0.0, 1.0);
    let t2 = t * t;
    t2 * t2 * t
}

/// `c·Λ(w)` for the GGX Smith Λ, `c = w.z > 0`: `α²s²/(2(√(c² + α²s²) + c))` with
/// `s² = w.x² + w.y²` (no cancellation, no division by `c`).
#[inline]
fn c_lambda(w: DVec3, alpha: f64) -> f64 {
    let a2s2 = alpha * alpha * (w.x * w.x + w.y * w.y);
    a2s2 / (2.0 * ((w.z * w.z + a2s2).sqrt() + w.z))
}

/// GGX `D(h) = α²/(π(s² + α²z²)²)` for a unit half vector `h` with `h.z > 0`.
#[inline]
fn ggx_d(h: DVec3, alpha: f64) -> f64 {
    let a2 = alpha * alpha;
    let q = h.x * h.x + h.y * h.y + a2 * h.z * h.z;
    a2 * FRAC_1_PI / (q * q)
}

/// Visible-normal sample (Dupuy & Benyoub 2023, spherical caps) for unit local `wo`, `wo.z > 0`:
/// the reflected direction `wi` (possibly below the horizon), or `None` for a degenerate `h`.
#[inline]
fn sample_vndf_reflect(wo: DVec3, alpha: f64, u: [f64; 2]) -> Option<DVec3> {
    let v = DVec3::new(alpha * wo.x, alpha * wo.y, wo.z).normalize();
    let phi = TAU * u[1];
    let z = (1.0 - u[0]) * (1.0 + v.z) - v.z;
    let s = (1.0 - z * z).max(0.0).sqrt();
    let hs = DVec3::new(s * phi.cos(), s * phi.sin(), z) + v;
    let h = DVec3::new(alpha * hs.x, alpha * hs.y, hs.z.max(0.0)).normalize_or_zero();
    if h == DVec3::ZERO || !h.is_finite() {
        return None;
    }
    Some(2.0 * wo.dot(h) * h - wo)
}

/// Rec. 709 luminance.
#[inline]
fn luminance(c: DVec3) -> f64 {
    c.dot(DVec3::new(0.2126, 0.7152, 0.0722))
}

impl PreviewBsdf {
    /// `ns`: unit shading normal on the viewer's side; `wo`: unit direction towards the viewer.
    pub fn new(p: &PreviewParams, ns: DVec3, wo: DVec3) -> PreviewBsdf {
        let p = p.sanitised();
        let n = ns.normalize_or_zero();
        let n_ok = n != DVec3::ZERO && n.is_finite();
        let frame = Frame::from_normal(if n_ok { n } else { DVec3::Z });
        let wo_w = wo.normalize_or_zero();
        let wo_l = if wo_w.is_finite() {
            frame.to_local(wo_w)
        } else {
            DVec3::ZERO
        };
        let valid = n_ok && wo_l.z > 0.0 && wo_l.is_finite();
        let c_o = wo_l.z.clamp(0.0, 1.0);

        let r = ((1.0 - p.ior) / (1.0 + p.ior)).powi(2);
        let (f0, rho_d) = if p.use_specular_workflow {
            (p.specular_color, p.diffuse_color)
        } else {
            (
                DVec3::splat(r).lerp(p.diffuse_color, p.metallic),
                p.diffuse_color * (1.0 - p.metallic),
            )
        };
        let alpha = (p.roughness * p.roughness).max(ALPHA_MIN);
        let alpha_c = (p.clearcoat_roughness * p.clearcoat_roughness).max(ALPHA_MIN);
        let t_o = tail(c_o);
        let coat = p.clearcoat;
        let atten_o = 1.0 - coat * (r + (1.0 - r) * t_o);
        let diffuse_o = DIFFUSE_NORM * rho_d * (DVec3::ONE - f0) * (1.0 - t_o);

        let w_d = atten_o * luminance(rho_d * (DVec3::ONE - f0)) * (1.0 - t_o);
        let w_s = atten_o * luminance(f0 + (DVec3::ONE - f0) * t_o);
        let w_c = coat * (r + (1.0 - r) * t_o);
        let sum = w_d + w_s + w_c;
        let prob = if valid && sum > 0.0 && sum.is_finite() {
            [w_d / sum, w_s / sum, w_c / sum]
        } else {
            [0.0; 3]
        };
        PreviewBsdf {
            frame,
            wo: wo_l,
            valid,
            alpha,
            f0,
            lambda_o: c_lambda(wo_l, alpha),
            coat,
            alpha_c,
            f0_c: r,
            lambda_o_c: c_lambda(wo_l, alpha_c),
            diffuse_o,
            atten_o,
            prob,
        }
    }

    /// `f(wo, wi)` = `clearcoat·f_c + a(cₒ)a(cᵢ)(f_s + f_d)` for the unit world direction `wi`
    /// (towards the light); 0 when `wi` or `wo` is below the shading horizon.
    pub fn f(&self, wi: DVec3) -> DVec3 {
        match self.local(wi) {
            Some(wi) => self.f_local(wi),
            None => DVec3::ZERO,
        }
    }

    /// Density with which [`PreviewBsdf::sample`] produces `wi`, per unit solid angle:
    /// `p_d·cᵢ/π + p_s·G₁(wo)D(h)/(4cₒ) + p_c·G₁c(wo)D_c(h)/(4cₒ)`; 0 below the horizon.
    pub fn pdf(&self, wi: DVec3) -> f64 {
        match self.local(wi) {
            Some(wi) => self.pdf_local(wi),
            None => 0.0,
        }
    }

    /// Picks a lobe with `u[0]` (stretched back to \[0, 1) within the lobe's interval), then
    /// samples it (cosine for diffuse, visible normals for the GGX lobes); `None` when the
    /// direction falls below the shading horizon (or `wo` does). Weight `f·cos θᵢ/pdf`.
    pub fn sample(&self, u: [f64; 2]) -> Option<BsdfSample> {
        if !self.valid {
            return None;
        }
        // Lobe k owns [ends[k−1], ends[k]); the last lobe present ends at 1 exactly.
        let [p_d, p_s, p_c] = self.prob;
        let last = if p_c > 0.0 {
            2
        } else if p_s > 0.0 {
            1
        } else {
            0
        };
        let mut ends = [p_d, p_d + p_s, 1.0];
        ends[last] = 1.0;
        let u0 = u[0].clamp(0.0, ONE_MINUS_EPSILON);
        let k = (0..last).find(|&k| u0 < ends[k]).unwrap_or(last);
        let start = if k == 0 { 0.0 } else { ends[k - 1] };
        let v = [
            ((u0 - start) / (ends[k] - start)).clamp(0.0, ONE_MINUS_EPSILON),
            u[1],
        ];
        let local = match k {
            0 => sample_cosine_hemisphere(v),
            1 => sample_vndf_reflect(self.wo, self.alpha, v)?,
            _ => sample_vndf_reflect(self.wo, self.alpha_c, v)?,
        };
        let wi = self.frame.to_world(local).normalize_or_zero();
        // Evaluate through the same path as `f`/`pdf`, so the sample agrees with them exactly.
        let l = self.local(wi)?;
        let pdf = self.pdf_local(l);
        if !(pdf > 0.0 && pdf.is_finite()) {
            return None;
        }
        let weight = self.f_local(l) * l.z / pdf;
        if !weight.is_finite() {
            return None;
        }
        Some(BsdfSample {
            wi,
            pdf,
            weight,
            delta: false,
        })
    }

    /// True when nothing is reflected towards this viewer (`wo` below the shading horizon, or an
    /// unusable normal or direction); the Schlick edge (F90 = 1) reflects otherwise.
    pub fn is_black(&self) -> bool {
        !self.valid
    }

    /// Never: GGX alpha is at least 1e-3, so every lobe has a density.
    pub fn is_delta(&self) -> bool {
        false
    }

    /// `wi` in local coordinates when both it and `wo` are above the horizon.
    #[inline]
    fn local(&self, wi: DVec3) -> Option<DVec3> {
        if !self.valid || !wi.is_finite() {
            return None;
        }
        let l = self.frame.to_local(wi);
        (l.z > 0.0).then_some(l)
    }

    /// `f` for local `wi` above the horizon.
    fn f_local(&self, wi: DVec3) -> DVec3 {
        let (d, s) = self.f_lobes_local(wi);
        d + s
    }

    /// `f(wi)` split into its diffuse and specular (GGX and clearcoat) parts, which sum to
    /// [`PreviewBsdf::f`]: the light's `inputs:diffuse` and `inputs:specular` scale them.
    pub fn f_lobes(&self, wi: DVec3) -> (DVec3, DVec3) {
        match self.local(wi) {
            Some(wi) => self.f_lobes_local(wi),
            None => (DVec3::ZERO, DVec3::ZERO),
        }
    }

    /// The diffuse and specular parts of `f` for local `wi` above the horizon.
    fn f_lobes_local(&self, wi: DVec3) -> (DVec3, DVec3) {
        let (wo, c_o, c_i) = (self.wo, self.wo.z, wi.z);
        let t_i = tail(c_i);
        let diffuse = self.diffuse_o * (1.0 - t_i);
        let mut base = DVec3::ZERO;
        let h = (wo + wi).normalize_or_zero();
        let mut coat = 0.0;
        if h.z > 0.0 && h.is_finite() {
            let fw = schlick_weight(wo.dot(h));
            // 4cₒcᵢ(1 + Λ(wo) + Λ(wi)) = 4(cₒcᵢ + cᵢ·cₒΛ(wo) + cₒ·cᵢΛ(wi)): symmetric.
            let den = 4.0 * (c_o * c_i + c_i * self.lambda_o + c_o * c_lambda(wi, self.alpha));
            if den > 0.0 {
                let f = self.f0 + (DVec3::ONE - self.f0) * fw;
                base += f * (ggx_d(h, self.alpha) / den);
            }
            if self.coat > 0.0 {
                let den_c =
                    4.0 * (c_o * c_i + c_i * self.lambda_o_c + c_o * c_lambda(wi, self.alpha_c));
                if den_c > 0.0 {
                    let f = self.f0_c + (1.0 - self.f0_c) * fw;
                    coat = self.coat * f * ggx_d(h, self.alpha_c) / den_c;
                }
            }
        }
        let atten_i = 1.0 - self.coat * (self.f0_c + (1.0 - self.f0_c) * t_i);
        let atten = self.atten_o * atten_i;
        (diffuse * atten, base * atten + DVec3::splat(coat))
    }

    /// The mixture density for local `wi` above the horizon.
    fn pdf_local(&self, wi: DVec3) -> f64 {
        let [p_d, p_s, p_c] = self.prob;
        let mut pdf = p_d * wi.z * FRAC_1_PI;
        let h = (self.wo + wi).normalize_or_zero();
        if h.z > 0.0 && h.is_finite() {
            let c_o = self.wo.z;
            if p_s > 0.0 {
                pdf += p_s * ggx_d(h, self.alpha) / (4.0 * (c_o + self.lambda_o));
            }
            if p_c > 0.0 {
                pdf += p_c * ggx_d(h, self.alpha_c) / (4.0 * (c_o + self.lambda_o_c));
            }
        }
        pdf
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use lux_sample::SplitMix64;
    use proptest::prelude::*;

    /// Unit direction from (cos θ, φ) in `frame`.
    fn dir(frame: &Frame, cos: f64, phi: f64) -> DVec3 {
        let s = (1.0 - cos * cos).max(0.0).sqrt();
        frame.to_world(DVec3::new(s * phi.cos(), s * phi.sin(), cos))
    }

    /// A normal that is not an axis, and its frame.
    fn normal() -> (DVec3, Frame) {
        let n = DVec3::new(0.3, -0.4, 0.8).normalize();
        (n, Frame::from_normal(n))
    }

    /// Directional albedo `∫ f cos dωᵢ` at the BSDF's `wo`: the mean sample weight (failed samples
    /// count 0) over `k×k` jittered strata of `u`, with the standard error of the mean.
    fn albedo(b: &PreviewBsdf, k: usize, seed: u64) -> (DVec3, DVec3) {
        let mut rng = SplitMix64::new(seed);
        let (mut s1, mut s2) = (DVec3::ZERO, DVec3::ZERO);
        for i in 0..k {
            for j in 0..k {
                let u = [
                    (i as f64 + rng.next_f64()) / k as f64,
                    (j as f64 + rng.next_f64()) / k as f64,
                ];
                let w = b.sample(u).map_or(DVec3::ZERO, |s| s.weight);
                s1 += w;
                s2 += w * w;
            }
        }
        let n = (k * k) as f64;
        let mean = s1 / n;
        let var = (s2 / n - mean * mean).max(DVec3::ZERO) * (n / (n - 1.0));
        (mean, (var / n).powf(0.5))
    }

    /// [`albedo`] over `reps` independent stratified runs: the mean of their means, and its
    /// standard error from their spread (the per-sample σ overstates a stratified estimate's).
    fn albedo_replicated(b: &PreviewBsdf, k: usize, reps: usize) -> (DVec3, DVec3) {
        let means: Vec<DVec3> = (0..reps).map(|r| albedo(b, k, 100 + r as u64).0).collect();
        let n = reps as f64;
        let mean = means.iter().sum::<DVec3>() / n;
        let var = means
            .iter()
            .map(|m| (*m - mean) * (*m - mean))
            .sum::<DVec3>()
            / (n - 1.0);
        (mean, (var / n).powf(0.5))
    }

    /// Random parameters spanning the valid ranges.
    fn params() -> impl Strategy<Value = PreviewParams> {
        (
            (0.0..=1.0f64, 0.0..=1.0f64, 0.0..=1.0f64),
            any::<bool>(),
            (0.0..=1.0f64, 0.0..=1.0f64, 0.0..=1.0f64),
            (0.0..=1.0f64, 0.0..=1.0f64, 0.0..=1.0f64, 0.0..=1.0f64),
            0.2..4.0f64,
        )
            .prop_map(|(d, ws, s, (m, r, c, cr), ior)| PreviewParams {
                diffuse_color: DVec3::new(d.0, d.1, d.2),
                use_specular_workflow: ws,
                specular_color: DVec3::new(s.0, s.1, s.2),
                metallic: m,
                roughness: r,
                clearcoat: c,
                clearcoat_roughness: cr,
                ior,
            })
    }

    /// Relative difference, 0 when both vanish.
    fn rel(a: f64, b: f64) -> f64 {
        let m = a.abs().max(b.abs());
        if m == 0.0 { 0.0 } else { (a - b).abs() / m }
    }

    proptest! {
        /// Reciprocity f(wo, wi) = f(wi, wo) to 1e-9 relative; f, pdf finite and ≥ 0; the sample
        /// finite, above the horizon, with a consistent density.
        #[test]
        fn reciprocal_nonnegative_finite(
            p in params(),
            (nt, np) in (0.0..=1.0f64, 0.0..TAU),
            (co, po) in (-0.2..=1.0f64, 0.0..TAU),
            (ci, pi) in (-0.2..=1.0f64, 0.0..TAU),
            u in (0.0..1.0f64, 0.0..1.0f64),
        ) {
            let n = dir(&Frame::from_normal(DVec3::Z), 2.0 * nt - 1.0, np);
            let frame = Frame::from_normal(n);
            let (wo, wi) = (dir(&frame, co, po), dir(&frame, ci, pi));
            let a = PreviewBsdf::new(&p, n, wo);
            let b = PreviewBsdf::new(&p, n, wi);
            let (fa, fb) = (a.f(wi), b.f(wo));
            prop_assert!(fa.is_finite() && fa.min_element() >= 0.0, "{fa}");
            for k in 0..3 {
                prop_assert!(rel(fa[k], fb[k]) < 1e-9, "{fa} vs {fb}");
            }
            if co <= 0.0 || ci <= 0.0 {
                prop_assert_eq!(fa, DVec3::ZERO);
                prop_assert_eq!(a.pdf(wi), 0.0);
            } else {
                prop_assert!(fa.max_element() > 0.0, "{fa}");
            }
            let pdf = a.pdf(wi);
            prop_assert!(pdf.is_finite() && pdf >= 0.0, "{pdf}");
            prop_assert!(!a.is_delta());
            prop_assert_eq!(a.is_black(), co <= 0.0);
            if let Some(s) = a.sample([u.0, u.1]) {
                prop_assert!(s.weight.is_finite() && s.weight.min_element() >= 0.0);
                prop_assert!(s.pdf.is_finite() && s.pdf > 0.0 && s.wi.dot(n) > 0.0);
                prop_assert!((s.wi.length() - 1.0).abs() < 1e-12);
            }
        }
    }

    /// Out-of-range and non-finite inputs (and directions) give finite, non-negative values.
    #[test]
    fn sanitised_inputs() {
        let bad = PreviewParams {
            diffuse_color: DVec3::new(f64::NAN, 2.0, -1.0),
            use_specular_workflow: false,
            specular_color: DVec3::INFINITY,
            metallic: f64::NAN,
            roughness: -3.0,
            clearcoat: 7.0,
            clearcoat_roughness: f64::INFINITY,
            ior: -1.0,
        };
        let s = bad.sanitised();
        assert_eq!(s.diffuse_color, DVec3::new(0.18, 1.0, 0.0));
        assert_eq!(s.specular_color, DVec3::ZERO);
        assert_eq!((s.metallic, s.roughness, s.clearcoat), (0.0, 0.0, 1.0));
        assert_eq!((s.clearcoat_roughness, s.ior), (0.01, 1.5));
        assert_eq!(
            PreviewParams {
                ior: f64::NAN,
                ..PreviewParams::default()
            }
            .sanitised()
            .ior,
            1.5
        );
        let (n, frame) = normal();
        let wo = dir(&frame, 0.6, 1.0);
        let mut rng = SplitMix64::new(3);
        for b in [
            PreviewBsdf::new(&bad, n, wo),
            PreviewBsdf::new(&PreviewParams::default(), DVec3::ZERO, wo),
            PreviewBsdf::new(&PreviewParams::default(), n, DVec3::NAN),
            PreviewBsdf::new(&PreviewParams::default(), n, n),
            PreviewBsdf::new(&PreviewParams::default(), n, frame.t),
        ] {
            for _ in 0..200 {
                let wi = dir(&frame, 2.0 * rng.next_f64() - 1.0, TAU * rng.next_f64());
                let f = b.f(wi);
                assert!(f.is_finite() && f.min_element() >= 0.0, "{f}");
                let p = b.pdf(wi);
                assert!(p.is_finite() && p >= 0.0);
                if let Some(s) = b.sample(rng.next_2d()) {
                    assert!(s.weight.is_finite() && s.pdf > 0.0);
                }
            }
            assert!(b.f(DVec3::NAN) == DVec3::ZERO && b.pdf(DVec3::INFINITY) == 0.0);
        }
        // An unusable normal or viewer, or a viewer on the horizon: black.
        assert!(PreviewBsdf::new(&PreviewParams::default(), DVec3::ZERO, wo).is_black());
        assert!(PreviewBsdf::new(&PreviewParams::default(), n, DVec3::NAN).is_black());
        assert!(PreviewBsdf::new(&PreviewParams::default(), n, frame.t).is_black());
        assert!(!PreviewBsdf::new(&bad, n, wo).is_black());
    }

    /// The sample's weight is `f·cos/pdf` and its density `pdf(wi)`, to 1e-9 relative.
    #[test]
    fn sample_weight_and_pdf_consistent() {
        let (n, frame) = normal();
        let mut rng = SplitMix64::new(11);
        let mut some = 0;
        for case in 0..200 {
            let p = PreviewParams {
                diffuse_color: DVec3::new(rng.next_f64(), rng.next_f64(), rng.next_f64()),
                use_specular_workflow: case % 3 == 0,
                specular_color: DVec3::new(rng.next_f64(), rng.next_f64(), rng.next_f64()),
                metallic: rng.next_f64(),
                roughness: rng.next_f64(),
                clearcoat: if case % 2 == 0 { rng.next_f64() } else { 0.0 },
                clearcoat_roughness: rng.next_f64(),
                ior: 1.0 + 2.0 * rng.next_f64(),
            };
            let wo = dir(&frame, rng.next_f64(), TAU * rng.next_f64());
            let b = PreviewBsdf::new(&p, n, wo);
            for _ in 0..20 {
                let Some(s) = b.sample(rng.next_2d()) else {
                    continue;
                };
                some += 1;
                assert!(
                    rel(s.pdf, b.pdf(s.wi)) < 1e-9,
                    "{} vs {}",
                    s.pdf,
                    b.pdf(s.wi)
                );
                let w = b.f(s.wi) * n.dot(s.wi) / s.pdf;
                for k in 0..3 {
                    assert!(rel(w[k], s.weight[k]) < 1e-9, "{w} vs {}", s.weight);
                }
            }
        }
        assert!(some > 3000, "{some}");
    }

    /// The lemma behind the energy bound: a GGX lobe with Schlick's tail `(1 − wo·h)⁵` alone
    /// (F0 = 0) reflects at most `T(cₒ) = (1 − cₒ/2)⁵`, for every alpha ≤ 1; with F0 = 1 at most 1.
    #[test]
    fn schlick_tail_albedo_below_bound() {
        let (n, frame) = normal();
        let mut worst: f64 = 0.0;
        for r in [0.0, 0.2, 0.4, 0.6, 0.8, 0.9, 1.0] {
            for c in [1.0, 0.9, 0.7, 0.5, 0.3, 0.15, 0.05, 0.01] {
                let p = PreviewParams {
                    diffuse_color: DVec3::ZERO,
                    use_specular_workflow: true,
                    specular_color: DVec3::ZERO,
                    roughness: r,
                    ..PreviewParams::default()
                };
                let b = PreviewBsdf::new(&p, n, dir(&frame, c, 0.3));
                let (e, sigma) = albedo(&b, 48, 7);
                assert!(
                    e.x <= tail(c) + 3.0 * sigma.x,
                    "r {r} c {c}: {e} > {}",
                    tail(c)
                );
                worst = worst.max(e.x / tail(c));
            }
        }
        // The bound is not loose everywhere: at grazing angles a mirror nearly attains it.
        assert!(worst > 0.5 && worst < 1.0, "{worst}");
    }

    /// ∫ f cos dωᵢ ≤ 1 (+ 3σ, σ from 8 independent 32×32-stratified runs) over a grid of
    /// parameters and views.
    #[test]
    fn energy_at_most_one() {
        let (n, frame) = normal();
        let mut max: f64 = 0.0;
        let bases = [
            // (workflow, diffuse, specular, metallic)
            (false, 1.0, 0.0, 0.0),
            (false, 1.0, 0.0, 1.0),
            (true, 1.0, 1.0, 0.0),
            (true, 1.0, 0.0, 0.0),
        ];
        for r in [0.01, 0.3, 1.0] {
            for &(ws, d, s, m) in &bases {
                for (cc, ccr) in [(0.0, 0.01), (1.0, 0.01), (1.0, 1.0)] {
                    for ior in [1.2, 3.0] {
                        for c in [1.0, 0.5, 0.1] {
                            let p = PreviewParams {
                                diffuse_color: DVec3::splat(d),
                                use_specular_workflow: ws,
                                specular_color: DVec3::splat(s),
                                metallic: m,
                                roughness: r,
                                clearcoat: cc,
                                clearcoat_roughness: ccr,
                                ior,
                            };
                            let b = PreviewBsdf::new(&p, n, dir(&frame, c, 2.0));
                            let (e, sigma) = albedo_replicated(&b, 32, 8);
                            let e = e.max_element();
                            assert!(
                                e <= 1.0 + 3.0 * sigma.max_element(),
                                "{p:?} cos {c}: {e} ± {sigma}"
                            );
                            max = max.max(e);
                        }
                    }
                }
            }
        }
        assert!(max > 0.97, "{max}");
    }

    /// Metal furnace (F0 = 1): albedo ≤ 1 for every roughness (each weight is G₂/G₁ ≤ 1), and
    /// close to 1 for a smooth metal seen head-on.
    #[test]
    fn metal_furnace() {
        let (n, frame) = normal();
        let metal = |r: f64| PreviewParams {
            diffuse_color: DVec3::ONE,
            metallic: 1.0,
            roughness: r,
            ..PreviewParams::default()
        };
        for r in [0.0, 0.05, 0.2, 0.5, 0.8, 1.0] {
            for c in [1.0, 0.6, 0.2, 0.02] {
                let b = PreviewBsdf::new(&metal(r), n, dir(&frame, c, 0.7));
                let (e, _) = albedo(&b, 32, 9);
                assert!(e.max_element() <= 1.0 + 1e-12, "r {r} c {c}: {e}");
                assert!(e.min_element() > 0.3, "r {r} c {c}: {e}");
            }
        }
        let (e, _) = albedo(&PreviewBsdf::new(&metal(0.05), n, n), 32, 9);
        assert!(e.min_element() > 0.99, "{e}");
        let (e, _) = albedo(&PreviewBsdf::new(&metal(1.0), n, n), 32, 9);
        assert!(e.max_element() < 0.95, "{e}");
    }

    /// A smooth metal with F0 = c seen head-on reflects ≈ c (Schlick at wo·h ≈ 1), within 2 %.
    #[test]
    fn smooth_metal_albedo_is_f0() {
        let (n, _) = normal();
        let c = DVec3::new(0.9, 0.6, 0.3);
        for p in [
            PreviewParams {
                diffuse_color: c,
                metallic: 1.0,
                roughness: 0.05,
                ..PreviewParams::default()
            },
            PreviewParams {
                diffuse_color: DVec3::ZERO,
                use_specular_workflow: true,
                specular_color: c,
                roughness: 0.05,
                ..PreviewParams::default()
            },
        ] {
            let (e, _) = albedo(&PreviewBsdf::new(&p, n, n), 32, 13);
            assert!(((e - c) / c).abs().max_element() < 0.02, "{e} vs {c}");
        }
    }

    /// The density integrates (over the sphere, by quadrature in (cos θ, φ) about the mirror
    /// direction, cos θ clustered near it) to the fraction of `sample` calls that succeed.
    #[test]
    fn pdf_integrates_to_success_fraction() {
        let (n, frame) = normal();
        let cases = [
            // (roughness, metallic, clearcoat, clearcoat roughness, cos θₒ)
            (0.05, 1.0, 0.0, 0.01, 0.9),
            (0.2, 0.0, 1.0, 0.1, 0.5),
            (0.5, 0.5, 0.5, 0.3, 0.2),
            (1.0, 0.0, 0.0, 0.01, 1.0),
            (0.7, 1.0, 1.0, 0.05, 0.3),
        ];
        for (r, m, cc, ccr, c) in cases {
            let p = PreviewParams {
                diffuse_color: DVec3::new(0.8, 0.5, 0.3),
                metallic: m,
                roughness: r,
                clearcoat: cc,
                clearcoat_roughness: ccr,
                ..PreviewParams::default()
            };
            let wo = dir(&frame, c, 1.1);
            let b = PreviewBsdf::new(&p, n, wo);
            let axis = Frame::from_normal(2.0 * n.dot(wo) * n - wo);
            // 1 − cos θ = 2t⁴, t ∈ (0, 1): d(cos θ) = 8t³ dt.
            let (nt, np) = (500, 192);
            let mut total = 0.0;
            for i in 0..nt {
                let t = (i as f64 + 0.5) / nt as f64;
                let cos = 1.0 - 2.0 * t.powi(4);
                let dcos = 8.0 * t.powi(3) / nt as f64;
                for j in 0..np {
                    let phi = (j as f64 + 0.5) / np as f64 * TAU;
                    total += b.pdf(dir(&axis, cos, phi)) * dcos * TAU / np as f64;
                }
            }
            let k = 256;
            let mut ok = 0;
            for i in 0..k {
                for j in 0..k {
                    let u = [(i as f64 + 0.5) / k as f64, (j as f64 + 0.5) / k as f64];
                    ok += b.sample(u).is_some() as usize;
                }
            }
            let frac = ok as f64 / (k * k) as f64;
            assert!(frac > 0.5 && frac <= 1.0);
            assert!(
                (total - frac).abs() < 3e-3,
                "r {r} c {c}: ∫pdf {total} vs {frac}"
            );
        }
    }

    /// χ² test of `sample` against `pdf`: bins in (cos θ, φ) about the normal plus one bin for
    /// failed samples, expected counts by integrating `pdf` over each bin, bins expecting fewer
    /// than 5 pooled; p-value > 1e-3.
    #[test]
    fn chi_square_sample_matches_pdf() {
        let (n, frame) = normal();
        let cases = [
            // (roughness, metallic, clearcoat, clearcoat roughness, cos θₒ, specular workflow)
            (0.2, 0.0, 0.0, 0.01, 0.7, false),
            (0.2, 1.0, 0.0, 0.01, 0.4, false),
            (0.6, 0.5, 1.0, 0.2, 0.8, false),
            (1.0, 0.0, 0.5, 0.4, 0.3, true),
            (0.35, 0.0, 0.0, 0.01, 0.15, true),
        ];
        let (nt, np, sub) = (16, 32, 12);
        let samples = 100_000;
        let mut rng = SplitMix64::new(17);
        for (r, m, cc, ccr, c, ws) in cases {
            let p = PreviewParams {
                diffuse_color: DVec3::new(0.7, 0.4, 0.2),
                use_specular_workflow: ws,
                specular_color: DVec3::new(0.3, 0.2, 0.1),
                metallic: m,
                roughness: r,
                clearcoat: cc,
                clearcoat_roughness: ccr,
                ior: 1.6,
            };
            let b = PreviewBsdf::new(&p, n, dir(&frame, c, 0.4));
            let mut observed = vec![0.0; nt * np + 1];
            for _ in 0..samples {
                let bin = match b.sample(rng.next_2d()) {
                    Some(s) => {
                        let l = frame.to_local(s.wi);
                        let ti = (((1.0 - l.z) * nt as f64) as usize).min(nt - 1);
                        let ph = l.y.atan2(l.x).rem_euclid(TAU) / TAU;
                        ti * np + ((ph * np as f64) as usize).min(np - 1)
                    }
                    None => nt * np,
                };
                observed[bin] += 1.0;
            }
            let mut expected = vec![0.0; nt * np + 1];
            let (dc, dp) = (1.0 / (nt * sub) as f64, TAU / (np * sub) as f64);
            for ti in 0..nt {
                for pi in 0..np {
                    let mut e = 0.0;
                    for a in 0..sub {
                        let cos = 1.0 - (ti * sub + a) as f64 * dc - 0.5 * dc;
                        for q in 0..sub {
                            let phi = ((pi * sub + q) as f64 + 0.5) * dp;
                            e += b.pdf(dir(&frame, cos, phi));
                        }
                    }
                    expected[ti * np + pi] = e * dc * dp * samples as f64;
                }
            }
            let inside: f64 = expected.iter().sum();
            expected[nt * np] = (samples as f64 - inside).max(0.0);
            let (mut chi2, mut dof, mut po, mut pe) = (0.0, 0usize, 0.0, 0.0);
            for (o, e) in observed.iter().zip(&expected) {
                if *e < 5.0 {
                    po += o;
                    pe += e;
                } else {
                    chi2 += (o - e) * (o - e) / e;
                    dof += 1;
                }
            }
            if pe > 0.0 {
                chi2 += (po - pe) * (po - pe) / pe;
                dof += 1;
            }
            let pv = lux_sample::stats::chi2_p_value(chi2, dof - 1);
            assert!(dof > 20, "r {r}: {dof} bins");
            assert!(
                pv > 1e-3,
                "r {r} m {m} cc {cc} c {c}: χ² {chi2}, {dof} bins, p {pv}"
            );
        }
    }

    /// The diffuse-only inputs (specular workflow, specularColor 0, no clearcoat): the coupled
    /// diffuse plus a Schlick sheen; head-on `f = 28/(23π)·(31/32)²·ρ` exactly (F(1) = 0).
    #[test]
    fn diffuse_only_case() {
        let (n, frame) = normal();
        let rho = DVec3::new(0.8, 0.5, 0.2);
        let p = PreviewParams {
            diffuse_color: rho,
            use_specular_workflow: true,
            specular_color: DVec3::ZERO,
            ..PreviewParams::default()
        };
        let head_on = PreviewBsdf::new(&p, n, n).f(n);
        let want = DIFFUSE_NORM * (31.0f64 / 32.0).powi(2) * rho;
        assert!(
            (head_on - want).abs().max_element() < 1e-12,
            "{head_on} vs {want}"
        );
        assert!((want.x / (rho.x * FRAC_1_PI) - 1.1425).abs() < 1e-4);
        // Off the mirror direction the sheen adds a grey (channel-independent) term.
        let b = PreviewBsdf::new(&p, n, dir(&frame, 0.2, 0.0));
        let wi = dir(&frame, 0.9, 2.5);
        let diffuse = DIFFUSE_NORM * rho * (1.0 - tail(0.2)) * (1.0 - tail(0.9));
        let sheen = b.f(wi) - diffuse;
        assert!(
            sheen.x > 0.0 && (sheen.x - sheen.z).abs() < 1e-12,
            "{sheen}"
        );
        // Albedo head-on: exactly (31/32)·ρ from the diffuse, plus a sheen of under 1 %.
        let (e, sigma) = albedo(&PreviewBsdf::new(&p, n, n), 48, 21);
        let d = rho * (31.0 / 32.0);
        assert!(
            (e - d + 3.0 * sigma).min_element() > 0.0 && (e - d).max_element() < 0.01,
            "{e} ± {sigma} vs {d}"
        );
    }

    /// The schema defaults.
    #[test]
    fn defaults() {
        let d = PreviewParams::default();
        assert_eq!(d.diffuse_color, DVec3::splat(0.18));
        assert!(!d.use_specular_workflow);
        assert_eq!(d.specular_color, DVec3::ZERO);
        assert_eq!(
            (
                d.metallic,
                d.roughness,
                d.clearcoat,
                d.clearcoat_roughness,
                d.ior
            ),
            (0.0, 0.5, 0.0, 0.01, 1.5)
        );
        assert_eq!(d.sanitised(), d);
    }
}
