//! A light's base radiance (RGB nits, before shaping and texture) from its USD inputs: the
//! LightAPI pipeline of lux-math, or — when the physical-light-unit or spectral APIs are
//! applied — the conversions of lux-spectral. lux-render only gathers the inputs here; every
//! formula lives in lux-math, lux-shaping and lux-spectral.
//!
//! Precedence, per light:
//! 1. A Photometric/Radiometric {Area, Dome, Distant} LightAPI (`photometric:power` lm,
//!    `radiometric:power` W, `photometric:illuminance` lux, `radiometric:irradiance` W/m²) fixes
//!    the absolute output: `lux_spectral::emitted` with the light's world area
//!    (`lux_math::size_factor`) and its shaping integral (the factor's integrals by lux-shaping, `Shaping::emitter_integral`), or the dome texture's
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
    ColorSpace, LightGeometry, PhysicalLightInputs, PhysicalQuantity, ShapingIntegral,
    SpectralInputs, WavelengthUnit,
};
use lux_usd::Light;

fn spectral_error(l: &Light, e: impl std::fmt::Display) -> RenderError {
    RenderError::Light {
        light: l.path.clone(),
        message: e.to_string(),
    }
}

/// `PhysicalLightInputs` of the light for `quantity` (illuminant, custom table, colour
/// temperature).
pub fn physical_inputs(l: &Light, quantity: PhysicalQuantity) -> PhysicalLightInputs {
    let mut inputs = PhysicalLightInputs::new(quantity);
    inputs.color_temperature = l.params.color_temperature;
    if let Some(p) = &l.physical {
        inputs.illuminant = p.illuminant;
        inputs.custom_illuminant = p
            .custom_illuminant
            .iter()
            .map(|&[nm, v]| [f64::from(nm), f64::from(v)])
            .collect();
    }
    inputs
}

/// The LTESpectralAPI inputs of a light (emission only), or `None` without
/// `wavelength:emission`.
pub fn spectral_inputs(l: &Light, stage_unit: WavelengthUnit) -> Option<SpectralInputs> {
    l.emission_spectrum.as_ref().map(|e| SpectralInputs {
        unit_for_wavelength: stage_unit,
        emission: Some(e.clone()),
        ..SpectralInputs::default()
    })
}

/// The LTESpectralAPI inputs of a surface for lux-spectral.
pub fn surface_spectral_inputs(
    a: &lux_usd::SurfaceSpectral,
    stage_unit: WavelengthUnit,
) -> SpectralInputs {
    SpectralInputs {
        unit_for_wavelength: stage_unit,
        emission: None,
        reflectance: a.reflectance.clone(),
        ior: a.ior.clone(),
        scalar_ior: a.scalar_ior,
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
    if let Some(q) = l.physical.as_ref().and_then(|p| p.quantity) {
        let inputs = physical_inputs(l, q);
        let ill =
            lux_spectral::resolve_illuminant(&inputs, space).map_err(|e| spectral_error(l, e))?;
        let geometry = match &l.shape {
            LightShape::Rect { .. }
            | LightShape::Disk { .. }
            | LightShape::Sphere { .. }
            | LightShape::Cylinder { .. } => {
                let kind = l.shape.kind();
                let texture_mean = match (texture, l.kind) {
                    (Some(t), LightKind::Rect) => {
                        let [r, g, b, _] = t.average();
                        DVec3::new(r, g, b)
                    }
                    _ => DVec3::ONE,
                };
                LightGeometry::Area {
                    world_area: lux_math::size_factor(&l.shape, &l.light_to_world, profile),
                    shaping: ShapingIntegral::from_integrals_textured(
                        kind,
                        shaping.emitter_integral(kind),
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
                            .texels_iter()
                            .map(|p| {
                                lux_math::luminance(DVec3::new(
                                    p[0] as f64,
                                    p[1] as f64,
                                    p[2] as f64,
                                )) as f32
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
                return Err(spectral_error(
                    l,
                    format!("{} cannot be applied to a {}", q.attribute(), l.type_name),
                ));
            }
        };
        let e =
            lux_spectral::emitted(&inputs, &geometry, space).map_err(|e| spectral_error(l, e))?;
        return Ok(finite(e.rgb));
    }
    if l.physical.is_some() {
        let inputs = physical_inputs(l, PhysicalQuantity::PhotometricPower(0.0));
        let ill =
            lux_spectral::resolve_illuminant(&inputs, space).map_err(|e| spectral_error(l, e))?;
        let mut params = l.params;
        params.enable_color_temperature = false;
        let base = lux_math::emitted_radiance(&params, &l.shape, &l.light_to_world, profile);
        return Ok(finite(base * ill.rgb_per_nit));
    }
    if let Some(s) = spectral_inputs(l, stage_unit) {
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
