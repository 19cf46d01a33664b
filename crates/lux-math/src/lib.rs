//! # lux-math
//!
//! The arithmetic of UsdLux light emission, as specified by the OpenUSD 26.11 UsdLux schema:
//! size factors for `inputs:normalize`, the base emission
//! `L = intensity · 2^exposure · color · blackbody(colorTemperature) / sizeFactor`,
//! colour temperature, and the conformance [`Profile`] that every lux crate takes.
//!
//! Conventions: USD matrices are **row-vector** (`p' = p · M`, translation in the last row); a
//! `glam::DMat4` whose columns are the USD rows applies the same map to column vectors
//! ([`usd_matrix`]). Lights emit along local −Z; polar angles are measured from −Z
//! ([`light_polar`]).
//!
//! ```
//! use glam::{DMat4, DVec3};
//! use lux_math::{LightKind, LightParams, LightShape, Profile, emitted_radiance, size_factor};
//!
//! // A 2 × 1 RectLight scaled by 3 in X, normalize on: its world area is 6.
//! let shape = LightShape::Rect { width: 2.0, height: 1.0 };
//! let xf = DMat4::from_scale(DVec3::new(3.0, 1.0, 1.0));
//! assert_eq!(size_factor(&shape, &xf, Profile::Spec), 6.0);
//! let params = LightParams { intensity: 12.0, normalize: true, ..LightParams::defaults_for(LightKind::Rect) };
//! assert_eq!(emitted_radiance(&params, &shape, &xf, Profile::Spec), DVec3::splat(2.0));
//! ```

#![warn(missing_docs)]

mod blackbody;
mod elliptic;
mod emission;
mod latlong;
mod light_transform;
mod polar;
mod profile;
mod scalar;
mod shadow;
mod shape;
mod size;
mod tables;
mod transform;

pub use blackbody::{
    REC709_LUMINANCE, color_temperature_rgb, hdembree_blackbody_rgb, krystek_planckian_uv,
    luminance, spec_blackbody_rgb, usdlux_blackbody_rgb,
};
pub use elliptic::{
    THOMSEN_P, carlson_rf_rd, carlson_rg, ellipse_perimeter, ellipse_perimeter_ramanujan,
    ellipsoid_area, ellipsoid_area_thomsen,
};
pub use emission::{LightParams, emission, emitted_radiance};
/// glam, the vector and matrix types of every public signature (`DVec3`, `DMat4`, …), at the
/// version lux is built with (0.34): depend on it through this re-export to never pin another.
pub use glam;
pub use latlong::{
    latlong_column_edge, latlong_direction, latlong_direction_from_angles, latlong_row_edge,
    latlong_uv,
};
pub use light_transform::{LightTransform, TransformError};
pub use polar::{Frame, azimuth_from_xy, light_direction, light_polar, polar_angle, polar_angles};
pub use profile::{Profile, UnknownProfile};
pub use scalar::{lerp, smooth_step, smooth_step_fraction};
pub use shadow::{shadow_strength, shadowed};
pub use shape::{LightKind, LightShape};
pub use size::{
    cylinder_area, cylinder_area_reference, disk_area, disk_area_reference, distant_size_factor,
    gram_eigenvalues, mesh_area, rect_area, size_factor, sphere_area, sphere_area_reference,
    world_area,
};
pub use transform::{
    AFFINE_TOLERANCE, affine_deviation, is_finite_matrix, linear_part, transform_vector,
    usd_matrix, usd_rows,
};

/// The README's example, compiled and run as a doctest.
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;
