//! The microfacet reflection/transmission lobe shared by `dielectric_bsdf`,
//! `conductor_bsdf` and `generalized_schlick_bsdf` (spec: "Microfacet BRDF", "Microfacet
//! BTDF"), in the closure's local frame with `wo.z > 0`.
//!
//! * Reflection: `f_r cosθi = tint · k_r · F(ωo·h) D(h) G2 / (4 cosθo)`.
//! * Refraction (solid, relative index `η` = inside over outside when entering, its inverse
//!   when leaving): `f_t |cosθi| = tint · k_t · (1 − F) D(m) G2 |ωo·m||ωi·m| η² /
//!   (cosθo (ωo·m + η ωi·m)²)`, `m ∝ ωo + η ωi`. This is Walter's BTDF with the `η²` radiance
//!   factor taken out (the form in which it integrates to the Fresnel transmittance; the
//!   spec's formula up to which side's index is squared): radiance's `1/η²` compression on
//!   entering and `η²` on leaving cancel along a closed path, and a renderer that tracks it
//!   applies it at the interface, as Mitsuba and pbrt do.
//! * Thin-walled transmission: the slab model (Fresnel reflectance `2F/(1 + F)`,
//!   transmittance `(1 − F)/(1 + F)` summing the incoherent inter-reflections between two
//!   parallel faces of the same microstructure), the transmitted lobe being the reflected one
//!   mirrored through the surface plane (`ωi = (x, y, −z)` of the reflection): transmission
//!   without refraction, reciprocal, and with `R + T` of the slab equal to 1 per microfacet.
//! * Retroreflection: the reflection lobe of `ωo` mirrored about the normal (`(−x, −y, z)`),
//!   so that it is centred on `ωo`.
//! * `k_r`, `k_t`: Turquin 2019 energy compensation factors, set by each closure.
//! * Total internal reflection makes `F = 1` for every Fresnel curve.
//! * A thin film replaces the curve by the Airy reflectance (`thinfilm.rs`), transmission
//!   by `1 − F_airy`.
//!
//! Sampling draws a visible normal (Dupuy–Benyoub 2023), then reflection with probability
//! `P_R = mean(F(ωo·m))` (1 in `R` mode, 0 in `T` mode) or refraction; with retroreflection in
//! `RT` mode the choice is made first with the fixed `P_R = mean(F(cosθo))`, since the two
//! lobes then see different visible-normal distributions.

use crate::fresnel;
use crate::microfacet::{Ggx, half_vector_t, jacobian_reflect, jacobian_refract, reflect, refract};
use crate::thinfilm::{Substrate, airy};
use crate::{DELTA_ALPHA, ScatterMode, ThinFilm};
use glam::{DVec2, DVec3};
use std::sync::OnceLock;

/// The Fresnel curve of a lobe.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Fresnel {
    /// Dielectric with relative index (the same `η` as the refraction).
    Dielectric,
    /// Conductor with complex index.
    Conductor { eta: DVec3, k: DVec3 },
    /// Generalized Schlick.
    Schlick {
        r0: DVec3,
        t: DVec3,
        r90: DVec3,
        q: f64,
        /// [`fresnel::schlick_dip`] of the four.
        dip: DVec3,
    },
    /// No Fresnel curve (`ior = 0`): reflect everything.
    One,
}

/// A microfacet lobe ready to evaluate.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Lobe {
    pub ggx: Ggx,
    pub delta: bool,
    pub tint: DVec3,
    pub fresnel: Fresnel,
    pub eta: f64,
    pub mode: ScatterMode,
    pub thin: bool,
    pub retro: bool,
    pub k_r: DVec3,
    pub k_t: DVec3,
    /// Thin film `(thickness nm, ior)` over the substrate, if any.
    pub film: Option<(f64, f64)>,
}

/// The film of a closure's `thinfilm` inputs: `None` for thickness 0 (or invalid numbers).
pub(crate) fn film(tf: ThinFilm) -> Option<(f64, f64)> {
    (tf.thickness > 0.0 && tf.thickness.is_finite() && tf.ior > 0.0 && tf.ior.is_finite())
        .then_some((tf.thickness, tf.ior))
}

/// What a lobe's sampling produced: a direction of the rough lobe, or a delta direction with
/// its weight (`value / choice probability`) and choice probability.
pub(crate) struct LobeSample {
    pub wi: DVec3,
    pub delta: Option<(DVec3, f64)>,
}

fn mean(v: DVec3) -> f64 {
    (v.x + v.y + v.z) / 3.0
}

impl Lobe {
    /// The GGX distribution for `roughness` (NaN → 0) and whether it is a delta lobe.
    pub fn distribution(alpha: DVec2) -> (Ggx, bool) {
        let a = DVec2::new(
            if alpha.x.is_nan() { 0.0 } else { alpha.x },
            if alpha.y.is_nan() { 0.0 } else { alpha.y },
        );
        (Ggx::new(a), a.x.max(a.y) < DELTA_ALPHA)
    }

    /// The Fresnel reflectance at `cos` (`ωo·m`); 1 on total internal reflection; the slab's
    /// `2F/(1 + F)` when thin-walled.
    pub fn f(&self, cos: f64) -> DVec3 {
        let tir = !self.thin && 1.0 - (1.0 - cos * cos) / (self.eta * self.eta) <= 0.0;
        let f = match self.fresnel {
            Fresnel::One => return DVec3::ONE,
            _ if tir && self.mode != ScatterMode::R => return DVec3::ONE,
            Fresnel::Dielectric => match self.film {
                Some((d, n)) => airy(cos, d, n, Substrate::Dielectric(self.eta)),
                None => DVec3::splat(fresnel::dielectric(cos, self.eta)),
            },
            Fresnel::Conductor { eta, k } => match self.film {
                Some((d, n)) => airy(cos, d, n, Substrate::Conductor(eta, k)),
                None => fresnel::conductor(cos, eta, k),
            },
            Fresnel::Schlick { r0, t, r90, q, dip } => match self.film {
                Some((d, n)) => {
                    let s = Substrate::Schlick {
                        r0,
                        t,
                        r90,
                        q,
                        eta3: self.eta,
                    };
                    airy(cos, d, n, s)
                }
                None => fresnel::schlick_with_dip(cos, r0, r90, q, dip),
            },
        };
        if self.thin { fresnel::slab(f) } else { f }
    }

    /// Cosine-weighted hemispherical average `2∫₀¹ F(μ) μ dμ` of [`Lobe::f`] (8-point
    /// Gauss–Legendre), the `F̄` of Turquin's compensation when no closed form applies.
    pub fn fresnel_average(&self) -> DVec3 {
        static GL: OnceLock<Vec<(f64, f64)>> = OnceLock::new();
        let gl = GL.get_or_init(|| crate::albedo::gauss_legendre(8));
        gl.iter().map(|&(mu, w)| self.f(mu) * (2.0 * w * mu)).sum()
    }

    fn p_reflect(&self, f: DVec3) -> f64 {
        match self.mode {
            ScatterMode::R => 1.0,
            ScatterMode::T => 0.0,
            ScatterMode::Rt => mean(f).clamp(0.0, 1.0),
        }
    }

    fn retro_rt(&self) -> bool {
        self.retro && self.mode == ScatterMode::Rt
    }

    fn wo_r(&self, wo: DVec3) -> DVec3 {
        if self.retro {
            DVec3::new(-wo.x, -wo.y, wo.z)
        } else {
            wo
        }
    }

    fn p_reflect_at(&self, wo: DVec3, m_cos: f64) -> f64 {
        if self.retro_rt() {
            self.p_reflect(self.f(wo.z))
        } else {
            self.p_reflect(self.f(m_cos))
        }
    }

    /// `f cosθi` for `wo.z > 0` (zero for delta lobes).
    pub fn eval(&self, wo: DVec3, wi: DVec3) -> DVec3 {
        if self.delta || wo.z <= 0.0 {
            return DVec3::ZERO;
        }
        if wi.z > 0.0 {
            if self.mode == ScatterMode::T {
                return DVec3::ZERO;
            }
            let wo = self.wo_r(wo);
            let h = (wo + wi).normalize();
            let c = wo.dot(h);
            if !(c > 0.0) {
                return DVec3::ZERO;
            }
            let v = self.ggx.d(h) * self.ggx.g2(wo, wi) / (4.0 * wo.z);
            self.tint * self.k_r * self.f(c) * v
        } else if wi.z < 0.0 {
            if self.mode == ScatterMode::R {
                return DVec3::ZERO;
            }
            if self.thin {
                let wm = DVec3::new(wi.x, wi.y, -wi.z);
                let h = (wo + wm).normalize();
                let c = wo.dot(h);
                if !(c > 0.0) {
                    return DVec3::ZERO;
                }
                let v = self.ggx.d(h) * self.ggx.g2(wo, wm) / (4.0 * wo.z);
                return self.tint * self.k_t * (DVec3::ONE - self.f(c)) * v;
            }
            let Some(m) = half_vector_t(wo, wi, self.eta) else {
                return DVec3::ZERO;
            };
            let (co, ci) = (wo.dot(m), wi.dot(m));
            if !(co > 0.0 && ci < 0.0) {
                return DVec3::ZERO;
            }
            let den = co + self.eta * ci;
            let v = self.ggx.d(m) * self.ggx.g2(wo, wi) * co * ci.abs() * self.eta * self.eta
                / (wo.z * den * den);
            self.tint * self.k_t * (DVec3::ONE - self.f(co)) * v
        } else {
            DVec3::ZERO
        }
    }

    /// Density of [`Lobe::sample`] for a rough lobe.
    pub fn pdf(&self, wo: DVec3, wi: DVec3) -> f64 {
        if self.delta || wo.z <= 0.0 {
            return 0.0;
        }
        if wi.z > 0.0 {
            if self.mode == ScatterMode::T {
                return 0.0;
            }
            let wr = self.wo_r(wo);
            let h = (wr + wi).normalize();
            let c = wr.dot(h);
            if !(c > 0.0) {
                return 0.0;
            }
            self.p_reflect_at(wo, c) * self.ggx.pdf_visible(wr, h) * jacobian_reflect(c)
        } else if wi.z < 0.0 {
            if self.mode == ScatterMode::R {
                return 0.0;
            }
            if self.thin {
                let wm = DVec3::new(wi.x, wi.y, -wi.z);
                let h = (wo + wm).normalize();
                let c = wo.dot(h);
                if !(c > 0.0) {
                    return 0.0;
                }
                return (1.0 - self.p_reflect_at(wo, c))
                    * self.ggx.pdf_visible(wo, h)
                    * jacobian_reflect(c);
            }
            let Some(m) = half_vector_t(wo, wi, self.eta) else {
                return 0.0;
            };
            let (co, ci) = (wo.dot(m), wi.dot(m));
            if !(co > 0.0 && ci < 0.0) {
                return 0.0;
            }
            (1.0 - self.p_reflect_at(wo, co))
                * self.ggx.pdf_visible(wo, m)
                * jacobian_refract(co, ci, self.eta)
        } else {
            0.0
        }
    }

    /// Samples the lobe; `u_sel ∈ [0, 1)` picks reflection or transmission.
    pub fn sample(&self, wo: DVec3, u_sel: f64, u: [f64; 2]) -> Option<LobeSample> {
        if wo.z <= 0.0 {
            return None;
        }
        if self.delta {
            let f = self.f(wo.z);
            let p = self.p_reflect(f);
            if u_sel < p {
                let wr = self.wo_r(wo);
                let wi = DVec3::new(-wr.x, -wr.y, wr.z);
                return Some(LobeSample {
                    wi,
                    delta: Some((self.tint * f / p, p)),
                });
            }
            let wi = if self.thin {
                -wo
            } else {
                refract(wo, DVec3::Z, self.eta)?
            };
            let q = 1.0 - p;
            return Some(LobeSample {
                wi,
                delta: Some((self.tint * (DVec3::ONE - f) / q, q)),
            });
        }
        let reflect_lobe = if self.retro_rt() {
            u_sel < self.p_reflect(self.f(wo.z))
        } else {
            self.mode == ScatterMode::R
        };
        let (wi, up) = if reflect_lobe {
            let wr = self.wo_r(wo);
            let m = self.ggx.sample_visible(wr, u);
            (reflect(wr, m), true)
        } else {
            let m = self.ggx.sample_visible(wo, u);
            let choose_r = !self.retro_rt()
                && self.mode == ScatterMode::Rt
                && u_sel < self.p_reflect(self.f(wo.dot(m)));
            if choose_r {
                (reflect(wo, m), true)
            } else if self.thin {
                let w = reflect(wo, m);
                if w.z <= 0.0 {
                    return None;
                }
                (DVec3::new(w.x, w.y, -w.z), false)
            } else {
                (refract(wo, m, self.eta)?, false)
            }
        };
        // A reflection must leave above the surface, a refraction below it; otherwise the
        // sample falls where the lobe is zero.
        if !wi.is_finite() || (wi.z > 0.0) != up || wi.z == 0.0 {
            return None;
        }
        Some(LobeSample { wi, delta: None })
    }
}
