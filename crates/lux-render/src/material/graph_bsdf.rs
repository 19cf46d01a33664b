//! A MaterialX closure tree (`lux_bsdf::Bsdf`, what a shading graph evaluates to at a hit)
//! behind the renderer's BSDF interface: `f` without the cosine (lux-bsdf's `eval` is
//! `f·|cos θi|` with each closure's cosine about its own normal; here divided by the
//! `|ns·wi|` the integrators multiply back), its density, and samples with their lobe kind.

use super::BsdfSample;
use glam::DVec3;
use lux_bsdf::LobeKind;

/// Below this `|ns·wi|` a direction grazes the shading surface and `f` is taken as 0 (the
/// integrators multiply it by that cosine).
const GRAZING: f64 = 1.0e-9;

/// A closure tree at a hit, with the shading normal the integrators take cosines about.
#[derive(Clone, Debug)]
pub struct GraphBsdf {
    /// The closure tree, resolved for the viewer's direction once per hit.
    pub bsdf: lux_bsdf::PreparedBsdf,
    /// The shading normal `ns` of the [`super::SurfacePoint`].
    pub ns: DVec3,
    /// Whether some closure of the tree transmits.
    pub transmits: bool,
}

impl GraphBsdf {
    /// `f(wi)`: the tree's `f·|cos θi|` over `|ns·wi|`.
    #[inline]
    pub fn f(&self, wi: DVec3) -> DVec3 {
        let (d, s) = self.f_lobes(wi);
        d + s
    }

    /// `f(wi)` as its diffuse and glossy parts.
    #[inline]
    pub fn f_lobes(&self, wi: DVec3) -> (DVec3, DVec3) {
        let c = self.ns.dot(wi).abs();
        if c < GRAZING {
            return (DVec3::ZERO, DVec3::ZERO);
        }
        let e = self.bsdf.eval(wi);
        (e.diffuse / c, e.specular / c)
    }

    /// Density of [`GraphBsdf::sample`] producing `wi`.
    #[inline]
    pub fn pdf(&self, wi: DVec3) -> f64 {
        self.bsdf.pdf(wi)
    }

    /// A sampled direction: `u_lobe` chooses the closure, `u` the direction.
    #[inline]
    // `!(pdf > 0.0)` on purpose: it also rejects NaN.
    #[allow(clippy::neg_cmp_op_on_partial_ord)]
    pub fn sample(&self, u: [f64; 2], u_lobe: f64) -> Option<BsdfSample> {
        let s = self.bsdf.sample(u_lobe, u)?;
        if !(s.pdf > 0.0) || !s.weight.is_finite() {
            return None;
        }
        Some(BsdfSample {
            wi: s.wi,
            pdf: s.pdf,
            weight: s.weight.max(DVec3::ZERO),
            delta: s.kind == LobeKind::Specular,
        })
    }
}
