//! # lux-irradiance
//!
//! The exact irradiance of UsdLux area lights on a Lambertian receiver, in closed form: lighting
//! maths a renderer can use in place of samples and shadow rays where it applies.
//!
//! - [`projected`]: the **projected solid angle** `Π = ∫ max(0, n·ω) dω` of a polygon (rect,
//!   mesh face), a disk or a sphere seen from a receiver `(p, n)`, clipped to its horizon — the
//!   unshadowed irradiance `E = L·Π` of a uniform emitter of radiance `L`.
//! - [`hidden`]: what an opaque triangle or planar convex polygon between the receiver and the
//!   light hides of a sphere's cap, a convex polygon or a disk, and whether two blockers'
//!   projections overlap — the exact shadowed irradiance `L·(Π − Σ H)` behind a few blockers.
//! - [`overlap`]: what blockers whose projections overlap hide together — their union, by
//!   inclusion–exclusion over the convex intersections of their spherical polygons.
//!
//! Geometry is `f64` (`glam::DVec3`), points in world space; nothing here samples or traces
//! rays (lux-sample samples the same lights).

#![warn(missing_docs)]

pub mod hidden;
pub mod overlap;
pub mod projected;

/// True for NaN, zero and negative values: the "no usable positive quantity" test that turns
/// degenerate or non-finite geometry into `None`/0 instead of panicking.
#[inline]
pub(crate) fn not_positive(x: f64) -> bool {
    x.is_nan() || x <= 0.0
}

/// The README's example, compiled and run as a doctest.
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;
