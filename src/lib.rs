//! # lux
//!
//! UsdLux lighting as precisely specified: light units, `normalize`, shaping, IES profiles,
//! physical light units and spectra, and the exact irradiance of area lights, as a set of small
//! crates re-exported here.

pub use lux_bsdf as bsdf;
pub use lux_ies as ies;
pub use lux_irradiance as irradiance;
pub use lux_math as math;
pub use lux_render as render;
pub use lux_sample as sample;
pub use lux_shaping as shaping;
pub use lux_spectral as spectral;
pub use lux_usd as usd;
