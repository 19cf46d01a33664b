//! Base emission of a light: the LightAPI inputs turned into RGB radiance (nits).
//!
//! UsdLux 26.11, `LightAPI`:
//! `L = intensity · 2^exposure · color · blackbody(colorTemperature) / sizeFactor`, where the
//! blackbody factor applies only when `inputs:enableColorTemperature` is on and `sizeFactor` only
//! when `inputs:normalize` is on. Shaping (focus, cone, IES) multiplies this afterwards
//! (lux-shaping).

use crate::{LightKind, LightShape, Profile, color_temperature_rgb, size_factor};
use glam::{DMat4, DVec3};

/// The `UsdLuxLightAPI` inputs that set a light's base emission.
///
/// `Default` gives the LightAPI schema defaults (intensity 1, exposure 0, colour white,
/// colour temperature 6500 K but disabled, normalize off); [`LightParams::defaults_for`] adds the
/// per-light overrides (DistantLight `inputs:intensity` = 50000).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightParams {
    /// `inputs:intensity` (nits; lux for a delta DistantLight).
    pub intensity: f64,
    /// `inputs:exposure`, in stops: multiplies by `2^exposure`.
    pub exposure: f64,
    /// `inputs:color`, linear RGB in the rendering colour space.
    pub color: DVec3,
    /// `inputs:enableColorTemperature`.
    pub enable_color_temperature: bool,
    /// `inputs:colorTemperature`, kelvin.
    pub color_temperature: f64,
    /// `inputs:normalize`: divide by the light's `sizeFactor`.
    pub normalize: bool,
}

impl Default for LightParams {
    fn default() -> Self {
        LightParams {
            intensity: 1.0,
            exposure: 0.0,
            color: DVec3::ONE,
            enable_color_temperature: false,
            color_temperature: 6500.0,
            normalize: false,
        }
    }
}

impl LightParams {
    /// The schema defaults for a light of `kind` (DistantLight overrides `inputs:intensity` to
    /// 50000; every other kind uses the LightAPI defaults).
    pub fn defaults_for(kind: LightKind) -> LightParams {
        match kind {
            LightKind::Distant => LightParams {
                intensity: 50000.0,
                ..LightParams::default()
            },
            _ => LightParams::default(),
        }
    }

    /// The RGB multiplier `intensity · 2^exposure · color · blackbody` without any size factor.
    ///
    /// Non-finite intensity, exposure or colour give 0 (a light that emits nothing, never NaN);
    /// negative intensity or colour components are clamped to 0 (no negative light).
    pub fn scale(&self, profile: Profile) -> DVec3 {
        if !(self.intensity.is_finite() && self.exposure.is_finite() && self.color.is_finite()) {
            return DVec3::ZERO;
        }
        let mut rgb =
            self.color.max(DVec3::ZERO) * (self.intensity.max(0.0) * self.exposure.exp2());
        if self.enable_color_temperature {
            rgb *= color_temperature_rgb(self.color_temperature, profile);
        }
        if rgb.is_finite() { rgb } else { DVec3::ZERO }
    }
}

/// Base emitted radiance (RGB nits) of a light of `kind` given its already computed
/// `size_factor` ([`crate::size_factor`]):
/// `intensity · 2^exposure · color · blackbody / (normalize ? sizeFactor : 1)`.
///
/// Profiles: for a DomeLight, [`Profile::HdEmbree`] ignores intensity, exposure, colour and
/// colour temperature (returns white), as the reference renders do; [`Profile::Spec`] applies them.
/// Dome and portal lights ignore `normalize` (sizeFactor 1).
///
/// A light whose size factor is needed but is not a positive finite number (zero-area or invalid
/// geometry) emits 0. The result is always finite and ≥ 0.
pub fn emission(
    params: &LightParams,
    kind: LightKind,
    size_factor: f64,
    profile: Profile,
) -> DVec3 {
    if kind == LightKind::Dome && profile == Profile::HdEmbree {
        return DVec3::ONE;
    }
    let rgb = params.scale(profile);
    let uses_size = params.normalize && !matches!(kind, LightKind::Dome | LightKind::Portal);
    if !uses_size {
        return rgb;
    }
    if !(size_factor.is_finite() && size_factor > 0.0) {
        return DVec3::ZERO;
    }
    let out = rgb / size_factor;
    if out.is_finite() { out } else { DVec3::ZERO }
}

/// [`emission`] with the size factor computed from the light's shape and light-to-world
/// transform (only when `normalize` is on).
pub fn emitted_radiance(
    params: &LightParams,
    shape: &LightShape,
    light_to_world: &DMat4,
    profile: Profile,
) -> DVec3 {
    let sf = if params.normalize {
        size_factor(shape, light_to_world, profile)
    } else {
        1.0
    };
    emission(params, shape.kind(), sf, profile)
}

#[cfg(test)]
mod tests {
    use super::*;
    use core::f64::consts::PI;

    #[test]
    fn defaults() {
        assert_eq!(
            LightParams::defaults_for(LightKind::Distant).intensity,
            50000.0
        );
        assert_eq!(
            LightParams::defaults_for(LightKind::Rect),
            LightParams::default()
        );
        let p = LightParams::default();
        assert_eq!(
            emission(&p, LightKind::Rect, 4.0, Profile::Spec),
            DVec3::ONE
        );
    }

    #[test]
    fn full_formula() {
        let p = LightParams {
            intensity: 3.0,
            exposure: 2.0,
            color: DVec3::new(0.5, 1.0, 0.25),
            enable_color_temperature: true,
            color_temperature: 6500.0,
            normalize: true,
        };
        // Spec colour is white at 6500 K; rect 2x1 area 2: 3*4*c/2.
        let shape = LightShape::Rect {
            width: 2.0,
            height: 1.0,
        };
        let l = emitted_radiance(&p, &shape, &DMat4::IDENTITY, Profile::Spec);
        assert!((l - DVec3::new(3.0, 6.0, 1.5)).abs().max_element() < 1e-12);
        // hdembree colour at 6500 K is not white
        let l = emitted_radiance(&p, &shape, &DMat4::IDENTITY, Profile::HdEmbree);
        assert!((l.x / 3.0 - 1.044_155).abs() < 1e-5);
    }

    #[test]
    fn dome_profiles() {
        let p = LightParams {
            intensity: 5.0,
            normalize: true,
            ..LightParams::default()
        };
        assert_eq!(
            emission(&p, LightKind::Dome, 0.0, Profile::Spec),
            DVec3::splat(5.0)
        );
        assert_eq!(
            emission(&p, LightKind::Dome, 0.0, Profile::HdEmbree),
            DVec3::ONE
        );
    }

    #[test]
    fn distant_normalized_is_illuminance() {
        // E on a facing patch = L·π sin²θmax = intensity when normalized.
        let p = LightParams {
            intensity: 0.3,
            normalize: true,
            ..LightParams::default()
        };
        let shape = LightShape::Distant { angle_deg: 80.0 };
        let l = emitted_radiance(&p, &shape, &DMat4::IDENTITY, Profile::Spec);
        let s = 40f64.to_radians().sin();
        assert!((l.x * PI * s * s - 0.3).abs() < 1e-15);
        // Normalize off: floor E/π = intensity·sin²(40°) = 0.12395 (the reference's frame).
        let p = LightParams {
            normalize: false,
            ..p
        };
        let l = emitted_radiance(&p, &shape, &DMat4::IDENTITY, Profile::Spec);
        assert!((l.x * s * s - 0.123_953).abs() < 1e-6);
    }

    #[test]
    fn bad_inputs_emit_zero() {
        let shape = LightShape::Sphere { radius: 0.0 };
        let p = LightParams {
            normalize: true,
            ..LightParams::default()
        };
        assert_eq!(
            emitted_radiance(&p, &shape, &DMat4::IDENTITY, Profile::Spec),
            DVec3::ZERO
        );
        for p in [
            LightParams {
                intensity: f64::NAN,
                ..LightParams::default()
            },
            LightParams {
                exposure: f64::INFINITY,
                ..LightParams::default()
            },
            LightParams {
                exposure: 5000.0,
                ..LightParams::default()
            },
            LightParams {
                color: DVec3::new(f64::NAN, 1.0, 1.0),
                ..LightParams::default()
            },
        ] {
            assert_eq!(
                emission(&p, LightKind::Rect, 1.0, Profile::Spec),
                DVec3::ZERO,
                "{p:?}"
            );
        }
        let neg = LightParams {
            intensity: -2.0,
            ..LightParams::default()
        };
        assert_eq!(
            emission(&neg, LightKind::Rect, 1.0, Profile::Spec),
            DVec3::ZERO
        );
    }
}
