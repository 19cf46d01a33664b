//! Physical quantities → emitted luminance: one entry point per light type.

use glam::DVec3;
use std::f64::consts::PI;

use crate::colorspace::ColorSpace;
use crate::error::SpectralError;
use crate::physical::{PhysicalLightInputs, PhysicalQuantity, resolve_illuminant};
use crate::shaping_integral::ShapingIntegral;

/// The geometry facts a conversion needs, computed by the caller (world areas come from
/// `lux_math::size_factor`, the integrals of the shaping factor from the caller's shaping model).
///
/// This is the photometric category of the proposal's Photometric/Radiometric {Area, Dome,
/// Distant} LightAPIs, not a light kind: which quantity applies (power for `Area`, illuminance
/// for `Dome` and `Distant`) and the numbers its conversion needs. The four area light kinds
/// (`lux_math::LightKind::{Rect, Disk, Sphere, Cylinder}`) share `Area`, their differences
/// being folded into the world area and [`ShapingIntegral`] (built from the kind); a kind's
/// shape is never matched on here.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum LightGeometry {
    /// Rect, disk, sphere or cylinder light: world-space emitting area (scene units², the
    /// `normalize` size factor) and its [`ShapingIntegral`].
    Area {
        /// World-space surface area A.
        world_area: f64,
        /// G, π when unshaped.
        shaping: ShapingIntegral,
    },
    /// Dome light: m = (1/π) ∫_{upper hemisphere} Y_tex(ω) cos θ dω, the cosine-weighted mean
    /// luminance of its texture around the stage's up axis (1 without a texture).
    Dome {
        /// m, the cosine-weighted mean of the texture.
        cosine_weighted_mean: f64,
    },
    /// Distant light with its `inputs:angle` in degrees (clipped to [0, 360)).
    Distant {
        /// `inputs:angle`, degrees.
        angle_deg: f64,
    },
}

impl LightGeometry {
    /// The geometry of the light described by its UsdLux shape (lux-math's
    /// [`lux_math::LightShape`], the same value lux-sample's `Light::from_shape` and
    /// lux-math's `size_factor` take) under its light-to-world transform:
    ///
    /// | shape | geometry |
    /// |---|---|
    /// | rect, disk, sphere, cylinder, mesh | [`LightGeometry::Area`]: the **exact** world area under any affine map ([`lux_math::world_area`] under `profile`, the `inputs:normalize` size factor) and `shaping` |
    /// | dome | [`LightGeometry::Dome`] with mean 1 (an untextured dome; for a texture use [`crate::latlong_cosine_weighted_mean`]) |
    /// | distant | [`LightGeometry::Distant`] with `inputs:angle` |
    /// | portal | [`SpectralError::NotAnAreaEmitter`]: a PortalLight emits nothing itself |
    ///
    /// `shaping` is the light's shaping integral G ([`ShapingIntegral::UNSHAPED`] without
    /// ShapingAPI; from lux-shaping's `Shaping::emitter_integral` with
    /// [`ShapingIntegral::from_integrals`] otherwise); only area lights use it.
    pub fn from_shape(
        shape: &lux_math::LightShape,
        light_to_world: &lux_math::LightTransform,
        profile: lux_math::Profile,
        shaping: ShapingIntegral,
    ) -> Result<LightGeometry, SpectralError> {
        use lux_math::LightShape;
        Ok(match shape {
            LightShape::Rect { .. }
            | LightShape::Disk { .. }
            | LightShape::Sphere { .. }
            | LightShape::Cylinder { .. }
            | LightShape::Mesh { .. } => LightGeometry::Area {
                world_area: lux_math::world_area(shape, &light_to_world.matrix(), profile),
                shaping,
            },
            LightShape::Dome => LightGeometry::Dome {
                cosine_weighted_mean: 1.0,
            },
            LightShape::Distant { angle_deg } => LightGeometry::Distant {
                angle_deg: *angle_deg,
            },
            LightShape::Portal { .. } => {
                return Err(SpectralError::NotAnAreaEmitter {
                    light: "PortalLight",
                });
            }
        })
    }

    fn name(&self) -> &'static str {
        match self {
            LightGeometry::Area { .. } => "area light",
            LightGeometry::Dome { .. } => "dome light",
            LightGeometry::Distant { .. } => "distant light",
        }
    }
}

/// What a light emits under a physical-unit API (PhotometricAreaLightAPI and friends): the
/// luminance `L = Φ / (A·G)` of an area light given its power Φ (lm; W converted by the
/// illuminant's efficacy), `L = E / (π·m)` of a dome given its illuminance, `L = E / Ω⊥` of a
/// distant light, and its RGB `L · rgb_per_nit`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Emission {
    /// Luminance in nits: the value to use in place of `intensity·2^exposure/sizeFactor`
    /// (per direction, before the shaping factor). For a delta distant light (angle 0): the
    /// illuminance in lux on a patch facing it.
    pub luminance: f64,
    /// `luminance · rgb_per_nit`: the RGB the renderer emits (before shaping).
    pub rgb: DVec3,
    /// True for a distant light of angle 0 (a delta light).
    pub delta: bool,
}

fn check(
    attribute: &str,
    value: f64,
    positive: bool,
    expected: &'static str,
) -> Result<f64, SpectralError> {
    let ok = value.is_finite() && if positive { value > 0.0 } else { value >= 0.0 };
    if ok {
        Ok(value)
    } else {
        Err(SpectralError::InvalidValue {
            attribute: attribute.to_owned(),
            value,
            expected,
        })
    }
}

/// Area light: **L = Φ / (A · G)** nits for a luminous flux Φ (lm), world area A and shaping
/// integral G (Φ = ∫_A ∫ L f(ω) cos θ dω dA = L·A·G).
pub fn area_light_luminance(
    flux_lm: f64,
    world_area: f64,
    shaping: ShapingIntegral,
) -> Result<f64, SpectralError> {
    let flux = check("photometric:power", flux_lm, false, "a finite flux ≥ 0 lm")?;
    let area = check("world area", world_area, true, "a finite area > 0")?;
    Ok(flux / (area * shaping.value()))
}

/// Area light, the inverse: flux Φ = L · A · G (lm for nits).
pub fn area_light_flux(luminance: f64, world_area: f64, shaping: ShapingIntegral) -> f64 {
    luminance * world_area * shaping.value()
}

/// Dome light: **L = E / (π · m)** for an illuminance E (lux) on an upward-facing patch and the
/// texture's cosine-weighted mean m (E = ∫_{H⁺} L·Y_tex(ω) cos θ dω = L·π·m).
pub fn dome_light_luminance(
    illuminance_lux: f64,
    cosine_weighted_mean: f64,
) -> Result<f64, SpectralError> {
    let e = check(
        "photometric:illuminance",
        illuminance_lux,
        false,
        "a finite illuminance ≥ 0 lux",
    )?;
    let m = check(
        "dome texture cosine-weighted mean",
        cosine_weighted_mean,
        true,
        "a finite mean > 0",
    )?;
    Ok(e / (PI * m))
}

/// Distant light: the projected solid angle Ω⊥ seen by a one-sided patch facing the light,
/// θmax = clamp(radians(angle)/2, 0, π): π·sin²θmax for θmax ≤ π/2, π beyond (the part of the
/// cone behind the patch does not reach it); 0 for angle 0 (delta light).
pub fn distant_projected_solid_angle(angle_deg: f64) -> f64 {
    let angle = if angle_deg.is_nan() {
        0.0
    } else {
        angle_deg.clamp(0.0, 360.0)
    };
    let tmax = (angle.to_radians() / 2.0).clamp(0.0, PI);
    if tmax <= PI / 2.0 {
        let s = tmax.sin();
        PI * s * s
    } else {
        PI
    }
}

/// Distant light: **L = E / Ω⊥** for an illuminance E on a perpendicular patch; for angle 0
/// returns (E, delta = true): a delta light whose `intensity` is that illuminance.
pub fn distant_light_luminance(
    illuminance_lux: f64,
    angle_deg: f64,
) -> Result<(f64, bool), SpectralError> {
    let e = check(
        "photometric:illuminance",
        illuminance_lux,
        false,
        "a finite illuminance ≥ 0 lux",
    )?;
    let angle = check(
        "inputs:angle",
        angle_deg,
        false,
        "a finite angle ≥ 0 degrees",
    )?;
    let omega = distant_projected_solid_angle(angle);
    if omega == 0.0 {
        Ok((e, true))
    } else {
        Ok((e / omega, false))
    }
}

/// The entry point the proposal asks for (`calculateRgbLuminance`): the luminance and RGB a
/// light emits given its PhysicalLightIlluminantAPI / Photometric / Radiometric inputs.
///
/// Radiometric quantities are first converted to photometric ones with the illuminant's
/// luminous efficacy K (Φ_v = K·Φ_e, E_v = K·E_e). `intensity`, `exposure` and `normalize` do not
/// enter: the physical quantity fixes the absolute output. `color` is not applied either; a
/// renderer that tints must keep the tint's luminance at 1 to preserve the stated power.
pub fn emitted(
    inputs: &PhysicalLightInputs,
    geometry: &LightGeometry,
    space: ColorSpace,
) -> Result<Emission, SpectralError> {
    let ill = resolve_illuminant(inputs, space)?;
    let q = inputs.quantity;
    let photometric = match q {
        PhysicalQuantity::RadiometricPower(w) | PhysicalQuantity::RadiometricIrradiance(w) => {
            check(q.attribute(), w, false, "a finite value ≥ 0")? * ill.efficacy
        }
        PhysicalQuantity::PhotometricPower(v) | PhysicalQuantity::PhotometricIlluminance(v) => v,
    };
    let mismatch = || SpectralError::QuantityMismatch {
        quantity: q.attribute(),
        geometry: geometry.name(),
    };
    let (luminance, delta) = match (q, geometry) {
        (
            PhysicalQuantity::PhotometricPower(_) | PhysicalQuantity::RadiometricPower(_),
            LightGeometry::Area {
                world_area,
                shaping,
            },
        ) => (
            area_light_luminance(photometric, *world_area, *shaping)?,
            false,
        ),
        (
            PhysicalQuantity::PhotometricIlluminance(_)
            | PhysicalQuantity::RadiometricIrradiance(_),
            LightGeometry::Dome {
                cosine_weighted_mean,
            },
        ) => (
            dome_light_luminance(photometric, *cosine_weighted_mean)?,
            false,
        ),
        (
            PhysicalQuantity::PhotometricIlluminance(_)
            | PhysicalQuantity::RadiometricIrradiance(_),
            LightGeometry::Distant { angle_deg },
        ) => distant_light_luminance(photometric, *angle_deg)?,
        _ => return Err(mismatch()),
    };
    Ok(Emission {
        luminance,
        rgb: luminance * ill.rgb_per_nit,
        delta,
    })
}
