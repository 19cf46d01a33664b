//! The Lambertian BRDF `f = albedo/π`, sampled by the cosine (Malley's method).

use super::BsdfSample;
use glam::DVec3;
use lux_math::Frame;
use lux_sample::warp::sample_cosine_hemisphere;
use std::f64::consts::FRAC_1_PI;

/// Lambertian reflection about the shading normal `ns`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DiffuseBsdf {
    /// Albedo ρ (linear RGB in \[0, 1\]): `f = ρ/π`.
    pub albedo: DVec3,
    /// Unit shading normal, on the viewer's side.
    pub ns: DVec3,
}

impl DiffuseBsdf {
    /// `ρ/π` above the shading horizon, 0 below.
    #[inline]
    pub fn f(&self, wi: DVec3) -> DVec3 {
        if self.ns.dot(wi) > 0.0 {
            self.albedo * FRAC_1_PI
        } else {
            DVec3::ZERO
        }
    }

    /// `cos θ/π` above the horizon, 0 below.
    #[inline]
    pub fn pdf(&self, wi: DVec3) -> f64 {
        let cos = self.ns.dot(wi);
        if cos > 0.0 { cos * FRAC_1_PI } else { 0.0 }
    }

    /// A cosine-distributed direction about `ns`: density `cos θ/π`, weight `ρ` exactly.
    #[inline]
    pub fn sample(&self, u: [f64; 2]) -> Option<BsdfSample> {
        let wi = Frame::from_normal(self.ns).to_world(sample_cosine_hemisphere(u));
        let cos = self.ns.dot(wi);
        if cos <= 0.0 {
            return None;
        }
        Some(BsdfSample {
            wi,
            pdf: cos * FRAC_1_PI,
            weight: self.albedo,
            delta: false,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use lux_sample::SplitMix64;

    fn bsdf() -> DiffuseBsdf {
        DiffuseBsdf {
            albedo: DVec3::new(0.8, 0.5, 0.2),
            ns: DVec3::new(0.3, -0.4, 0.8).normalize(),
        }
    }

    /// Reciprocity, energy (∫ f cos = ρ ≤ 1 by quadrature) and the sample's density and weight
    /// against `pdf` and `f·cos/pdf`.
    #[test]
    fn lambertian_values() {
        let b = bsdf();
        let frame = Frame::from_normal(b.ns);
        // ∫ f cos dω over the hemisphere by a midpoint rule in (cos θ, φ): f·cos integrates to ρ.
        let (nt, np) = (200, 200);
        let mut e = DVec3::ZERO;
        let mut p = 0.0;
        for i in 0..nt {
            for j in 0..np {
                let c = (i as f64 + 0.5) / nt as f64;
                let phi = (j as f64 + 0.5) / np as f64 * std::f64::consts::TAU;
                let s = (1.0 - c * c).sqrt();
                let w = frame.to_world(DVec3::new(s * phi.cos(), s * phi.sin(), c));
                let dw = std::f64::consts::TAU / (nt * np) as f64;
                e += b.f(w) * c * dw;
                p += b.pdf(w) * dw;
            }
        }
        assert!((e - b.albedo).abs().max_element() < 1e-9, "{e}");
        assert!((p - 1.0).abs() < 1e-9, "{p}");
        let mut rng = SplitMix64::new(5);
        for _ in 0..1000 {
            let s = b.sample(rng.next_2d()).unwrap();
            let cos = b.ns.dot(s.wi);
            assert!(cos > 0.0 && (s.wi.length() - 1.0).abs() < 1e-12);
            assert_eq!(s.pdf, b.pdf(s.wi));
            let w = b.f(s.wi) * cos / s.pdf;
            assert!(
                (w - s.weight).abs().max_element() < 1e-12,
                "{w} vs {}",
                s.weight
            );
            // Reciprocity: f(wo, wi) = f(wi, wo) — a Lambertian f does not depend on either.
            assert_eq!(b.f(s.wi), b.f(b.ns));
        }
        assert_eq!(b.f(-b.ns), DVec3::ZERO);
        assert_eq!(b.pdf(-b.ns), 0.0);
    }
}
