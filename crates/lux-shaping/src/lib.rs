//! # lux-shaping
//!
//! The UsdLux `ShapingAPI` (OpenUSD 26.11): the RGB multiplier that `inputs:shaping:focus`,
//! `inputs:shaping:focusTint`, `inputs:shaping:cone:angle`, `inputs:shaping:cone:softness` and an
//! IES profile (`inputs:shaping:ies:file` with `ies:angleScale` and `ies:normalize`) apply to a
//! light's emission in a given direction; conservative bounds of it for light selection, and its
//! integrals over the sphere for power and normalization.
//!
//! Conventions (spec §2–3): directions are in the light's local space and point from the light
//! towards the receiver; the light's axis is its local −Z; θ is the angle off −Z and φ the IES
//! azimuth of [`lux_math::light_polar`]. A world direction goes through
//! [`Shaping::factor_world`], which maps it by `L⁻¹` ([`lux_math::LightTransform::local_direction`]).
//! Values are `f64` and `DVec3` (glam 0.34, re-exported as `lux_math::glam`). The factor is, in
//! this order,
//!
//! ```text
//! focusColor = lerp(|cos θ|^focus, focusTint, white)               (focus > 0 only)
//! cone       = θ > θcut ? 0 : 1 − smoothStep(θ, lerp(softness, θcut, 0), θcut)
//! ies        = I(applyAngleScale(θ), φ) [/ mean intensity if ies:normalize]
//! factor     = focusColor · cone · ies
//! ```
//!
//! A light **without** `ShapingAPI` has no cone ([`Shaping::identity`]); with the API applied and
//! nothing authored the cone is 90° ([`ShapingParams::default`]).
//!
//! ```
//! use glam::DVec3;
//! use lux_shaping::{Shaping, ShapingOptions, ShapingParams};
//!
//! // A 45° spotlight with a soft edge that also pulls light towards its axis.
//! let params = ShapingParams {
//!     cone_angle_deg: 45.0,
//!     cone_softness: 0.2,
//!     focus: 2.0,
//!     ..ShapingParams::default()
//! };
//! let spot = Shaping::new(&params, None, ShapingOptions::default())?;
//! // straight along the light's −Z axis: unchanged
//! assert_eq!(spot.factor(DVec3::NEG_Z), DVec3::ONE);
//! // 60° off the axis: outside the cone
//! let t = 60f64.to_radians();
//! assert_eq!(spot.factor(DVec3::new(t.sin(), 0.0, -t.cos())), DVec3::ZERO);
//! // a flat light radiates π (cos-weighted hemisphere) unshaped; this one much less
//! let ratio = spot.integral_cos_hemisphere()[0] / std::f64::consts::PI;
//! assert!(ratio > 0.2 && ratio < 0.5);
//! assert_eq!(spot.max_factor(), 1.0);
//! # Ok::<(), lux_shaping::ShapingError>(())
//! ```
//!
//! The two conformance profiles ([`lux_math::Profile`]) differ here in the clamping of
//! `cone:softness` (see [`Shaping::new`]) and in the flux that `ies:normalize` divides by (see
//! [`lux_ies::PhotometricWeb::mean_intensity`]).

#![warn(missing_docs)]
// `!(x >= a)` is used on purpose: it is true for NaN, which must take the "outside" branch.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

mod angle;
mod cone;
mod error;
mod grid;
mod ies;
mod params;
mod quad;
mod shaping;

pub use angle::apply_angle_scale;
pub use error::ShapingError;
pub use params::{AngleScaleFormula, ShapingOptions, ShapingParams};
pub use shaping::Shaping;

#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;
