//! A light's base radiance (RGB nits, before shaping and texture) from its USD inputs: the
//! LightAPI pipeline of lux-math, or — when the physical-light-unit or spectral APIs are
//! applied — the conversions of lux-spectral. lux-render only gathers the inputs here; every
//! formula lives in lux-math, lux-shaping and lux-spectral.
//!
//! Precedence, per light:
//! 1. A Photometric/Radiometric {Area, Dome, Distant} LightAPI (`photometric:power` lm,
//!    `radiometric:power` W, `photometric:illuminance` lux, `radiometric:irradiance` W/m²) fixes
//!    the absolute output: `lux_spectral::emitted` with the light's world area
//!    (`lux_math::size_factor`) and its shaping integral (lux-shaping), or the dome texture's
//!    cosine-weighted mean, or the distant angle. `intensity`, `exposure`, `color` and
//!    `normalize` do not enter (the proposal's `calculateRgbLuminance`).
//! 2. Else `PhysicalLightIlluminantAPI` alone: the LightAPI luminance
//!    `intensity · 2^exposure · color / sizeFactor` coloured by the illuminant's colour of one
//!    nit (white, blackbody at `colorTemperature`, or the custom table); `enableColorTemperature`
//!    is not applied a second time.
//! 3. Else LTESpectralAPI `wavelength:emission` (or its `illuminantPreset`): the same LightAPI
//!    luminance coloured by the SPD's colour of one nit (explicit values win over the preset).
//! 4. Else the plain LightAPI emission (`lux_math::emitted_radiance`).

use crate::RenderError;
use crate::image_io::Texture;
use glam::DVec3;
use lux_math::{LightKind, LightShape, Profile};
use lux_shaping::Shaping;
use lux_spectral::{
    ColorSpace, EmitterShape, IlluminantKind, Interpolation, LightGeometry, PhysicalLightInputs,
    PhysicalQuantity, ShapingIntegral, SpectralAttribute, SpectralInputs, WavelengthUnit,
};
use lux_usd::{Light, RawValue, SpectralAttributes};

/// The API schemas that carry a physical quantity, with the quantity they author.
const QUANTITY_APIS: [&str; 6] = [
    "PhotometricAreaLightAPI",
    "RadiometricAreaLightAPI",
    "PhotometricDomeLightAPI",
    "RadiometricDomeLightAPI",
    "PhotometricDistantLightAPI",
    "RadiometricDistantLightAPI",
];

/// A raw attribute, with or without the `inputs:` prefix.
fn raw<'a>(a: &'a SpectralAttributes, name: &str) -> Option<&'a RawValue> {
    a.values
        .get(name)
        .or_else(|| a.values.get(&format!("inputs:{name}")))
}

/// Metadata `key` of attribute `name` (with or without `inputs:`).
fn meta<'a>(a: &'a SpectralAttributes, name: &str, key: &str) -> Option<&'a str> {
    a.metadata
        .get(name)
        .or_else(|| a.metadata.get(&format!("inputs:{name}")))
        .and_then(|m| m.get(key))
        .map(String::as_str)
}

fn number(a: &SpectralAttributes, name: &str, default: f64) -> Result<f64, String> {
    match raw(a, name) {
        None => Ok(default),
        Some(RawValue::Number(x)) => Ok(*x),
        Some(other) => Err(format!("{name}: expected a number, found {other:?}")),
    }
}

fn pairs(a: &SpectralAttributes, name: &str) -> Result<Option<Vec<[f32; 2]>>, String> {
    match raw(a, name) {
        None => Ok(None),
        Some(RawValue::Numbers(v)) if v.len() % 2 == 0 => Ok(Some(
            v.chunks_exact(2)
                .map(|c| [c[0] as f32, c[1] as f32])
                .collect(),
        )),
        Some(other) => Err(format!(
            "{name}: expected float2[] (wavelength, value) pairs, found {other:?}"
        )),
    }
}

fn light_error(l: &Light, message: impl Into<String>) -> RenderError {
    RenderError::Light {
        light: l.path.clone(),
        message: message.into(),
    }
}

fn spectral_error(l: &Light, e: impl std::fmt::Display) -> RenderError {
    light_error(l, e.to_string())
}

fn has_api(l: &Light, name: &str) -> bool {
    l.api_schemas.iter().any(|a| a == name)
}

/// The physical quantity the light's applied API authors (with the schema default when the
/// API is applied but the value is not authored).
fn quantity(l: &Light) -> Result<Option<PhysicalQuantity>, RenderError> {
    let Some(api) = QUANTITY_APIS.iter().find(|a| has_api(l, a)) else {
        return Ok(None);
    };
    let a = &l.physical;
    let e = |m: String| light_error(l, m);
    let q = match *api {
        "PhotometricAreaLightAPI" => PhysicalQuantity::PhotometricPower(
            number(
                a,
                "photometric:power",
                PhysicalQuantity::DEFAULT_PHOTOMETRIC_POWER,
            )
            .map_err(e)?,
        ),
        "RadiometricAreaLightAPI" => PhysicalQuantity::RadiometricPower(
            number(
                a,
                "radiometric:power",
                PhysicalQuantity::DEFAULT_RADIOMETRIC_POWER,
            )
            .map_err(e)?,
        ),
        "PhotometricDomeLightAPI" | "PhotometricDistantLightAPI" => {
            PhysicalQuantity::PhotometricIlluminance(
                number(
                    a,
                    "photometric:illuminance",
                    PhysicalQuantity::DEFAULT_PHOTOMETRIC_ILLUMINANCE,
                )
                .map_err(e)?,
            )
        }
        _ => PhysicalQuantity::RadiometricIrradiance(
            number(
                a,
                "radiometric:irradiance",
                PhysicalQuantity::DEFAULT_RADIOMETRIC_IRRADIANCE,
            )
            .map_err(e)?,
        ),
    };
    Ok(Some(q))
}

/// `PhysicalLightInputs` of the light for `quantity` (illuminant token, custom table,
/// colour temperature).
pub fn physical_inputs(
    l: &Light,
    quantity: PhysicalQuantity,
) -> Result<PhysicalLightInputs, RenderError> {
    let mut inputs = PhysicalLightInputs::new(quantity);
    inputs.color_temperature = l.params.color_temperature;
    if let Some(v) = raw(&l.physical, "physical:illuminant") {
        let RawValue::Text(t) = v else {
            return Err(light_error(
                l,
                format!("physical:illuminant: expected a token, found {v:?}"),
            ));
        };
        inputs.illuminant = IlluminantKind::parse(t).map_err(|e| spectral_error(l, e))?;
    }
    if let Some(p) =
        pairs(&l.physical, "physical:customIlluminant").map_err(|m| light_error(l, m))?
    {
        inputs.custom_illuminant = p;
    }
    Ok(inputs)
}

/// A `float2[] wavelength:*` attribute with its metadata, `None` when neither values nor an
/// `illuminantPreset` are authored.
fn spectral_attribute(
    a: &SpectralAttributes,
    attr: &str,
    interpolation_key: Option<&str>,
) -> Result<Option<SpectralAttribute>, String> {
    let values = pairs(a, attr)?;
    let preset = meta(a, attr, "illuminantPreset");
    if values.is_none() && preset.is_none() {
        return Ok(None);
    }
    let unit = meta(a, attr, "unitForWavelength")
        .map(WavelengthUnit::parse)
        .transpose()
        .map_err(|e| e.to_string())?;
    let interpolation = interpolation_key
        .and_then(|k| meta(a, attr, k))
        .map(|t| Interpolation::parse(t, attr))
        .transpose()
        .map_err(|e| e.to_string())?
        .unwrap_or_default();
    let illuminant_preset = preset
        .map(lux_spectral::Illuminant::parse)
        .transpose()
        .map_err(|e| e.to_string())?;
    Ok(Some(SpectralAttribute {
        values: values.unwrap_or_default(),
        unit_for_wavelength: unit,
        interpolation,
        illuminant_preset,
    }))
}

/// The LTESpectralAPI inputs of a light (emission only), or `None` without
/// `wavelength:emission`.
pub fn spectral_inputs(
    l: &Light,
    stage_unit: WavelengthUnit,
) -> Result<Option<SpectralInputs>, RenderError> {
    let emission = spectral_attribute(
        &l.physical,
        "wavelength:emission",
        Some("emissionInterpolation"),
    )
    .map_err(|m| light_error(l, m))?;
    Ok(emission.map(|e| SpectralInputs {
        unit_for_wavelength: stage_unit,
        emission: Some(e),
        ..SpectralInputs::default()
    }))
}

/// The LTESpectralAPI inputs of a surface: `wavelength:reflectance`, `wavelength:ior` (with
/// `iorInterpolation`, including `"sellmeier"`) and the scalar `ior`. Errors are messages for
/// the caller to attach to the prim.
pub fn surface_spectral_inputs(
    a: &SpectralAttributes,
    stage_unit: WavelengthUnit,
) -> Result<SpectralInputs, String> {
    let reflectance = spectral_attribute(a, "wavelength:reflectance", None)?;
    let ior = match pairs(a, "wavelength:ior")? {
        None => None,
        Some(values) => Some(lux_spectral::IorAttribute {
            values,
            unit_for_wavelength: meta(a, "wavelength:ior", "unitForWavelength")
                .map(WavelengthUnit::parse)
                .transpose()
                .map_err(|e| e.to_string())?,
            interpolation: meta(a, "wavelength:ior", "iorInterpolation")
                .map(lux_spectral::IorInterpolation::parse)
                .transpose()
                .map_err(|e| e.to_string())?
                .unwrap_or_default(),
        }),
    };
    let scalar_ior = match raw(a, "ior") {
        Some(RawValue::Number(x)) => Some(*x),
        _ => None,
    };
    Ok(SpectralInputs {
        unit_for_wavelength: stage_unit,
        emission: None,
        reflectance,
        ior,
        scalar_ior,
    })
}

/// The stage's `unitForWavelength` (nanometres when unauthored).
pub fn stage_wavelength_unit(unit: Option<&str>) -> Result<WavelengthUnit, String> {
    match unit {
        None => Ok(WavelengthUnit::default()),
        Some(t) => WavelengthUnit::parse(t).map_err(|e| format!("stage unitForWavelength: {e}")),
    }
}

/// The base radiance of `l` (see the module docs for the precedence of the APIs).
///
/// `texture` is the light's `inputs:texture:file`: a RectLight's texture enters the power
/// conversion through its texel mean (`ShapingIntegral::from_shaping_textured`: the texture
/// multiplies the emission, so a texture of mean luminance ½ needs twice the luminance for the
/// same lumens; exact for the nearest-texel lookup, and for the bilinear one up to the
/// half-texel border), a DomeLight's latlong texture through its cosine-weighted mean about
/// `dome_up`, the stage's up axis expressed in the texture's frame (the dome's transform and
/// `poleAxis` undone).
pub fn base_radiance(
    l: &Light,
    shaping: &Shaping,
    texture: Option<&Texture>,
    dome_up: DVec3,
    profile: Profile,
    stage_unit: WavelengthUnit,
) -> Result<DVec3, RenderError> {
    let space = ColorSpace::Rec709;
    if let Some(q) = quantity(l)? {
        let inputs = physical_inputs(l, q)?;
        let ill =
            lux_spectral::resolve_illuminant(&inputs, space).map_err(|e| spectral_error(l, e))?;
        let geometry = match &l.shape {
            LightShape::Rect { .. }
            | LightShape::Disk { .. }
            | LightShape::Sphere { .. }
            | LightShape::Cylinder { .. } => {
                let shape = match l.kind {
                    LightKind::Sphere => EmitterShape::Sphere,
                    LightKind::Cylinder => EmitterShape::Cylinder,
                    _ => EmitterShape::Flat,
                };
                let texture_mean = match (texture, l.kind) {
                    (Some(t), LightKind::Rect) => {
                        let [r, g, b, _] = t.average();
                        DVec3::new(r, g, b)
                    }
                    _ => DVec3::ONE,
                };
                LightGeometry::Area {
                    world_area: lux_math::size_factor(&l.shape, &l.light_to_world, profile),
                    shaping: ShapingIntegral::from_shaping_textured(
                        shape,
                        shaping,
                        ill.rgb_per_nit,
                        texture_mean,
                    )
                    .map_err(|e| spectral_error(l, e))?,
                }
            }
            LightShape::Dome => LightGeometry::Dome {
                cosine_weighted_mean: match texture {
                    None => 1.0,
                    Some(t) => {
                        let lum: Vec<f32> = t
                            .texels()
                            .iter()
                            .map(|p| {
                                (lux_math::REC709_LUMINANCE[0] * p[0] as f64
                                    + lux_math::REC709_LUMINANCE[1] * p[1] as f64
                                    + lux_math::REC709_LUMINANCE[2] * p[2] as f64)
                                    as f32
                            })
                            .collect();
                        lux_spectral::latlong_cosine_weighted_mean(
                            t.width(),
                            t.height(),
                            &lum,
                            dome_up,
                        )
                        .map_err(|e| spectral_error(l, e))?
                    }
                },
            },
            LightShape::Distant { angle_deg } => LightGeometry::Distant {
                angle_deg: *angle_deg,
            },
            _ => {
                return Err(light_error(
                    l,
                    format!("{} cannot be applied to a {}", q.attribute(), l.type_name),
                ));
            }
        };
        let e =
            lux_spectral::emitted(&inputs, &geometry, space).map_err(|e| spectral_error(l, e))?;
        return Ok(finite(e.rgb));
    }
    if has_api(l, "PhysicalLightIlluminantAPI") {
        let inputs = physical_inputs(l, PhysicalQuantity::PhotometricPower(0.0))?;
        let ill =
            lux_spectral::resolve_illuminant(&inputs, space).map_err(|e| spectral_error(l, e))?;
        let mut params = l.params;
        params.enable_color_temperature = false;
        let base = lux_math::emitted_radiance(&params, &l.shape, &l.light_to_world, profile);
        return Ok(finite(base * ill.rgb_per_nit));
    }
    if let Some(s) = spectral_inputs(l, stage_unit)? {
        let rgb = s
            .emission_rgb_per_nit(space)
            .map_err(|e| spectral_error(l, e))?
            .unwrap_or(DVec3::ONE);
        let mut params = l.params;
        params.enable_color_temperature = false;
        let base = lux_math::emitted_radiance(&params, &l.shape, &l.light_to_world, profile);
        return Ok(finite(base * rgb));
    }
    Ok(finite(lux_math::emitted_radiance(
        &l.params,
        &l.shape,
        &l.light_to_world,
        profile,
    )))
}

fn finite(c: DVec3) -> DVec3 {
    if c.is_finite() {
        c.max(DVec3::ZERO)
    } else {
        DVec3::ZERO
    }
}
