//! # lux-math
//!
//! The arithmetic of UsdLux light emission, as specified by the OpenUSD 26.11 UsdLux schema:
//! size factors for `inputs:normalize`, the base emission
//! `L = intensity · 2^exposure · color · blackbody(colorTemperature) / sizeFactor`,
//! colour temperature, and the conformance [`Profile`] that every lux crate takes.
//!
//! Conventions: USD matrices are **row-vector** (`p' = p · M`, translation in the last row); a
//! `glam::DMat4` built from a USD matrix's rows therefore holds `M` transposed, and
//! `DMat4::transform_point3` applies it correctly (see [`usd_matrix`]). Lights emit along local −Z.

mod polar;
mod profile;
mod scalar;

pub use polar::{Frame, azimuth_from_xy, light_direction, light_polar};
pub use profile::{Profile, UnknownProfile};
pub use scalar::{lerp, lerp_f32, smooth_step, smooth_step_f32};
