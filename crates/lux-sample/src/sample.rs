//! The result of sampling a light, and the shading point it is sampled from.

use glam::DVec3;

/// The point being lit (the shading point): world position and (optionally) the receiver's unit
/// normal, from which lights are sampled and their projected solid angle `∫ max(0, n·ω) dω` is
/// taken.
///
/// A zero `n` means "no normal" (a point in a medium, or a caller that does not want the
/// cosine-aware techniques); samplers then ignore receiver orientation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Reference {
    /// Position of the receiving point (world space).
    pub p: DVec3,
    /// Unit surface normal at `p`, or zero.
    pub n: DVec3,
}

impl Reference {
    /// A reference point without a normal.
    #[inline]
    pub fn point(p: DVec3) -> Self {
        Self { p, n: DVec3::ZERO }
    }

    /// A reference point on a surface with unit normal `n`.
    #[inline]
    pub fn surface(p: DVec3, n: DVec3) -> Self {
        Self { p, n }
    }
}

/// One light sample, pbrt-v4 style: a point on the light seen from the reference point.
///
/// `pdf` is a density with respect to **solid angle** at the reference point (for a delta light
/// it is the discrete probability 1 and `delta` is set). For lights at infinity (distant, dome)
/// `distance` is `f64::INFINITY`, `point` holds the unit direction `wi` (the point on the sphere
/// at infinity) and `normal` is `−wi`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightSample {
    /// Sampled point on the light's surface (world space).
    pub point: DVec3,
    /// Unit geometric normal of the light at `point`, on the emitting side.
    pub normal: DVec3,
    /// Unit direction from the reference point towards `point`.
    pub wi: DVec3,
    /// Distance from the reference point to `point`.
    pub distance: f64,
    /// Density of `wi` per unit solid angle (1 for delta lights).
    pub pdf: f64,
    /// True for delta lights (DistantLight with `angle` = 0), whose `pdf` is a probability.
    pub delta: bool,
}

/// A point on a light's surface for emission sampling (pbrt-v4's `SampleLe` position): each
/// shape's `sample_area`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AreaSample {
    /// The point (world space).
    pub point: DVec3,
    /// Unit world normal of the side that emits (a two-sided mesh's front side).
    pub normal: DVec3,
    /// Density per unit world area.
    pub pdf: f64,
}
