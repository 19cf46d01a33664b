//! # lux-sample
//!
//! Importance sampling for every UsdLux light: per-shape samplers (rect, disk, sphere, cylinder,
//! mesh, distant, dome), transformed lights with exact densities, light selection (uniform,
//! power, light BVH), and the primitive warps and distributions they are built from.
//!
//! Interface (pbrt-v4 style): each light has `sample(&Reference, u: [f64; 2]) ->
//! Option<LightSample>` giving the point, normal, unit direction `wi` (reference → light),
//! distance and the density **per unit solid angle**, and `pdf(&Reference, wi)` returning the
//! same density for MIS. Samples are deterministic functions of `u`. All geometry is `f64`
//! (`glam::DVec3`); the cost over `f32` is small (see the benches) and it keeps the spherical
//! rectangle and tiny-cone formulas accurate.
//!
//! Light-space conventions follow the spec §2: lights emit along local −Z; rect and disk lie in
//! local XY and emit from the −Z side only; the cylinder's axis is local X; the dome texture is
//! latlong with +Y up and +Z at the centre column (`lux_math::latlong_direction`).

#![warn(missing_docs)]

mod alias;
mod bounds;
mod bvh;
mod cylinder;
mod disk;
mod distant;
mod distribution;
mod dome;
mod error;
mod light;
mod mesh;
mod rect;
mod rng;
mod sample;
mod select;
mod sphere;
pub mod spherical;
pub mod stats;
mod strategy;
mod transform;
pub mod warp;

pub use alias::AliasTable;
pub use bounds::{EmissionCone, LightBounds};
pub use bvh::LightBvh;
pub use cylinder::{CylinderFrom, CylinderLight, CylinderTechnique};
pub use disk::{DiskFrom, DiskLight, DiskTechnique};
pub use distant::DistantLight;
pub use distribution::{Distribution1D, Distribution2D};
pub use dome::{DomeLight, DomeTechnique, LatLongMap};
pub use error::{MAX_ENTRIES, SampleError};
pub use light::Light;
/// The latlong convention of the dome texture (spec §2), defined in lux-math and re-exported
/// here for the samplers' callers.
pub use lux_math::{latlong_direction, latlong_uv};
pub use mesh::{MeshLight, MeshTechnique};
pub use rect::{RectFrom, RectLight, RectTechnique};
pub use rng::SplitMix64;
pub use sample::{AreaSample, LightSample, Reference};
pub use select::LightSelector;
pub use sphere::{SphereFrom, SphereLight, SphereTechnique};
pub use strategy::Strategy;
pub use transform::LightTransform;

pub(crate) use lux_math::lerp;

/// Solid angle (sr) below which the solid-angle techniques (spherical rectangle, spherical
/// triangle) switch to area sampling: below it their trigonometry loses digits to cancellation
/// (S = Σγ − 2π), while area sampling is already near-uniform in solid angle.
pub const MIN_SOLID_ANGLE: f64 = 1e-4;

/// True for NaN, zero and negative values: the "no usable positive quantity" test used to turn
/// degenerate or non-finite geometry into `None`/0 instead of panicking.
#[inline]
pub(crate) fn not_positive(x: f64) -> bool {
    x.is_nan() || x <= 0.0
}

/// The README's example, compiled and run as a doctest.
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;
