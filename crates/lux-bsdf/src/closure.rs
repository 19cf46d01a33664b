//! One closure prepared for one `ωo`: its local frame (turned so that `ωo` is above it: every
//! closure is two-sided), its inputs sanitised, its albedo, and evaluation, density and
//! sampling in local coordinates.
//!
//! Sanitising: `weight` is clamped to `[0, 1]` (NaN → 0); colours have NaN, infinite and
//! negative channels set to 0; roughnesses are clamped to the spec's `[0, 1]` (NaN → 0).

use crate::lobe::Lobe;
use crate::schlick;
use crate::warp::{cosine_hemisphere, cosine_pdf};
use crate::{Closure, Frame, LobeKind, SheenMode};
use crate::{burley, conductor, dielectric, oren_nayar, sheen, subsurface, translucent};
use glam::DVec3;

fn w(x: f64) -> f64 {
    if x.is_nan() { 0.0 } else { x.clamp(0.0, 1.0) }
}
fn c(v: DVec3) -> DVec3 {
    let f = |x: f64| if x.is_finite() && x > 0.0 { x } else { 0.0 };
    DVec3::new(f(v.x), f(v.y), f(v.z))
}
fn r(x: f64) -> f64 {
    w(x)
}

#[derive(Clone, Copy, Debug)]
pub(crate) enum Kind {
    OrenNayar { rho: DVec3, sigma: f64, eon: bool },
    Burley { rho: DVec3, sigma: f64 },
    Translucent { rho: DVec3 },
    Subsurface { rho: DVec3 },
    Sheen { color: DVec3, r: f64 },
    Zeltner { color: DVec3, lobe: sheen::Zeltner },
    Microfacet(Lobe),
}

/// A closure at one shading point for one `ωo`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Leaf {
    pub frame: Frame,
    pub wo: DVec3,
    pub kind: Kind,
}

fn frame_of(c: &Closure) -> Frame {
    match *c {
        Closure::OrenNayar { frame, .. }
        | Closure::Burley { frame, .. }
        | Closure::Translucent { frame, .. }
        | Closure::Dielectric { frame, .. }
        | Closure::Conductor { frame, .. }
        | Closure::GeneralizedSchlick { frame, .. }
        | Closure::Sheen { frame, .. }
        | Closure::Subsurface { frame, .. } => frame,
    }
}

impl Leaf {
    /// Prepares `cl` for the world direction `wo`, with its directional albedo; `None` when
    /// `ωo` grazes its frame or the frame is broken.
    pub fn new(
        cl: &Closure,
        wo_world: DVec3,
        entering: bool,
        thin_walled: bool,
    ) -> Option<(Leaf, DVec3)> {
        let mut f = frame_of(cl);
        if !(f.n.is_finite() && f.t.is_finite() && f.b.is_finite()) {
            return None;
        }
        if f.n.dot(wo_world) < 0.0 {
            f = Frame {
                n: -f.n,
                t: f.t,
                b: -f.b,
            };
        }
        let wo = DVec3::new(f.t.dot(wo_world), f.b.dot(wo_world), f.n.dot(wo_world));
        if !(wo.z > 1e-9) {
            return None;
        }
        let wo = wo.normalize();
        let (kind, albedo) = match *cl {
            Closure::OrenNayar {
                weight,
                color,
                roughness,
                energy_compensation,
                ..
            } => {
                let mut rho = c(color) * w(weight);
                if energy_compensation {
                    rho = rho.min(DVec3::ONE);
                }
                let sigma = r(roughness);
                let a = oren_nayar::albedo(wo.z, rho, sigma, energy_compensation);
                (
                    Kind::OrenNayar {
                        rho,
                        sigma,
                        eon: energy_compensation,
                    },
                    a,
                )
            }
            Closure::Burley {
                weight,
                color,
                roughness,
                ..
            } => {
                let rho = c(color) * w(weight);
                let sigma = r(roughness);
                (
                    Kind::Burley { rho, sigma },
                    burley::albedo(wo.z, rho, sigma),
                )
            }
            Closure::Translucent { weight, color, .. } => {
                let rho = c(color) * w(weight);
                (Kind::Translucent { rho }, rho)
            }
            Closure::Subsurface { weight, color, .. } => {
                let rho = c(color) * w(weight);
                (Kind::Subsurface { rho }, rho)
            }
            Closure::Sheen {
                weight,
                color,
                roughness,
                mode,
                ..
            } => {
                let color = c(color) * w(weight);
                if mode == SheenMode::Zeltner {
                    let lobe = sheen::Zeltner::new(wo.z, roughness);
                    (Kind::Zeltner { color, lobe }, color * lobe.albedo)
                } else {
                    let r = sheen::roughness(roughness);
                    (Kind::Sheen { color, r }, sheen::albedo(wo.z, color, r))
                }
            }
            Closure::Dielectric {
                weight,
                tint,
                ior,
                alpha,
                retroreflective,
                mode,
                thinfilm,
                ..
            } => {
                let (l, a) = dielectric::lobe(
                    c(tint) * w(weight),
                    ior,
                    alpha,
                    retroreflective,
                    thinfilm,
                    mode,
                    wo,
                    entering,
                    thin_walled,
                );
                (Kind::Microfacet(l), a)
            }
            Closure::Conductor {
                weight,
                ior,
                extinction,
                alpha,
                retroreflective,
                thinfilm,
                ..
            } => {
                let (l, a) = conductor::lobe(
                    w(weight),
                    c(ior),
                    c(extinction),
                    alpha,
                    retroreflective,
                    thinfilm,
                    wo,
                );
                (Kind::Microfacet(l), a)
            }
            Closure::GeneralizedSchlick {
                weight,
                color0,
                color82,
                color90,
                exponent,
                alpha,
                retroreflective,
                mode,
                thinfilm,
                ..
            } => {
                let i = schlick::Inputs {
                    weight: w(weight),
                    r0: c(color0),
                    t: c(color82),
                    r90: c(color90),
                    q: exponent,
                    alpha,
                    retro: retroreflective,
                    mode,
                    thinfilm,
                };
                let (l, a) = schlick::lobe(&i, wo, entering, thin_walled);
                (Kind::Microfacet(l), a)
            }
        };
        Some((Leaf { frame: f, wo, kind }, c(albedo)))
    }

    pub fn local(&self, v: DVec3) -> DVec3 {
        DVec3::new(
            self.frame.t.dot(v),
            self.frame.b.dot(v),
            self.frame.n.dot(v),
        )
    }
    pub fn world(&self, v: DVec3) -> DVec3 {
        self.frame.t * v.x + self.frame.b * v.y + self.frame.n * v.z
    }

    pub fn lobe_kind(&self) -> LobeKind {
        match self.kind {
            Kind::Microfacet(l) if l.delta => LobeKind::Specular,
            Kind::Microfacet(_) => LobeKind::Glossy,
            _ => LobeKind::Diffuse,
        }
    }

    pub fn is_delta(&self) -> bool {
        matches!(self.kind, Kind::Microfacet(l) if l.delta)
    }

    /// `f cosθi` for a local `wi`.
    pub fn eval(&self, wi: DVec3) -> DVec3 {
        let wo = self.wo;
        match self.kind {
            Kind::OrenNayar { rho, sigma, eon } => oren_nayar::eval(wo, wi, rho, sigma, eon),
            Kind::Burley { rho, sigma } => burley::eval(wo, wi, rho, sigma),
            Kind::Translucent { rho } => translucent::eval(wi, rho),
            Kind::Subsurface { rho } => subsurface::eval(wi, rho),
            Kind::Sheen { color, r } => sheen::eval(wo, wi, color, r),
            Kind::Zeltner { color, lobe } => {
                color * (lobe.albedo * lobe.pdf(sheen::to_lobe(wo, wi)))
            }
            Kind::Microfacet(l) => l.eval(wo, wi),
        }
    }

    /// Density of [`Leaf::sample`] for a local `wi`.
    pub fn pdf(&self, wi: DVec3) -> f64 {
        match self.kind {
            Kind::Translucent { .. } => cosine_pdf(-wi),
            Kind::Zeltner { lobe, .. } => lobe.pdf(sheen::to_lobe(self.wo, wi)),
            Kind::Microfacet(l) => l.pdf(self.wo, wi),
            _ => cosine_pdf(wi),
        }
    }

    /// A local direction, and for a delta lobe its `(weight, probability)`.
    pub fn sample(&self, u_sel: f64, u: [f64; 2]) -> Option<(DVec3, Option<(DVec3, f64)>)> {
        match self.kind {
            Kind::Translucent { .. } => Some((-cosine_hemisphere(u), None)),
            Kind::Zeltner { lobe, .. } => {
                let v = lobe.warp(cosine_hemisphere(u));
                Some((sheen::from_lobe(self.wo, v), None))
            }
            Kind::Microfacet(l) => l.sample(self.wo, u_sel, u).map(|s| (s.wi, s.delta)),
            _ => Some((cosine_hemisphere(u), None)),
        }
    }
}
